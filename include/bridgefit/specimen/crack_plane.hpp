#pragma once
// The linear-elastic Green's function of a specimen on its crack plane.
//
// A plane-stress or plane-strain finite-element model of the upper half of
// the specimen (mode I symmetry: the crack plane y = 0 is a symmetry plane,
// u_y = 0 on the ligament) is statically condensed onto the opening
// displacements u_y of the crack-plane nodes x_j = a0 + (j - 1) h, j = 0..n
// (j = 0 is one notch-face node behind a0). What the reduced model needs is
// then, per unit thickness and for a load p = P / B:
//
//   S u_R = g p + f_R                     (condensed stiffness, load vector)
//   Delta = c0 p + q . u_R                (load-line displacement, half model)
//   u_mouth = m0 p + qm . u_R             (crack-mouth face displacement)
//
// Delta is work-conjugate to the load (CT: the pin's push on the upper rim of
// its hole, cosine-distributed; DCB: a uniform shear on the arm's end face).
//
// with f_R the nodal forces on the retained nodes and nodes ahead of the crack
// tip held at u_R = 0. The full-specimen opening is 2 u_y, the load-point
// displacement 2 Delta. Elements: 4-node quadrilaterals with incompatible
// modes (Wilson-Taylor QM6), which bend without shear locking (DCB arms).
// Built once per geometry and resolution; cheap to copy.

#include <string>
#include <vector>

#include "bridgefit/scene/scene.hpp"

namespace bridgefit::specimen {

struct CrackPlaneOptions {
  // Element size along the crack plane h [m]; 0: a default from the geometry
  // (CT: W/200, DCB: min(h_arm/4, L/400)).
  double resolution = 0.0;
  // Last crack length the model can reach [m]; 0: the scene's
  // run.max_crack_length, else CT 0.8 W, DCB L - 10 h_arm.
  double max_crack_length = 0.0;
  // Growth ratio of element sizes away from the crack plane.
  double grading = 1.15;
  // Largest element as a multiple of the characteristic size (CT: W/40,
  // DCB: h_arm, strip: b/20).
  double coarse_factor = 1.0;

  bool IsValid(std::string* why) const;
};

// A single-edge-cracked strip, width b, height 2 H, loaded by a uniform
// pressure on its crack faces (used to check the traction part of the
// Green's function against the handbook).
struct EdgeCrackStrip {
  double width = 0.0;        // b [m]
  double half_height = 0.0;  // H [m]
  double notch = 0.0;        // a0 [m]
  double max_crack_length = 0.0;
};

struct CrackPlaneModel {
  std::string key;            // geometry + material + resolution, for caching
  std::string load_kind;      // "pin" (CT), "end" (DCB), "face-pressure" (strip)
  double resolution = 0.0;    // h [m]
  double notch = 0.0;         // a0 [m]
  double thickness = 0.0;     // crack-front width B (or b) [m]
  double effective_modulus = 0.0;  // E' [Pa] for K = sqrt(E' G)
  std::vector<double> node_x;      // n+1 retained node positions [m]
  std::vector<double> stiffness;   // S, (n+1)^2 column-major [N/m^2 per unit thickness]
  std::vector<double> load;        // g [1] (nodal force per unit load p)
  double load_compliance = 0.0;    // c0 [m^2/N]
  std::vector<double> load_coupling;   // q [1]
  double mouth_compliance = 0.0;       // m0 [m^2/N]
  std::vector<double> mouth_coupling;  // qm [1]
  // Face displacement on the load line x = 0 (CT: what a load-line clip
  // gauge reads, the displacement of Saxena-Hudak's compliance; DCB: the
  // mouth). u_gauge = gc p + qg . u_R.
  double gauge_x = 0.0;
  double gauge_compliance = 0.0;
  std::vector<double> gauge_coupling;
  // Size of the finite-element model (for summaries).
  int elements = 0;
  int dofs = 0;
  double build_s = 0.0;

  int size() const { return static_cast<int>(node_x.size()); }
  double S(int i, int j) const { return stiffness[static_cast<size_t>(j) * node_x.size() + i]; }
  // Crack length of tip index t (t >= 1: retained node t is the tip).
  double CrackLength(int tip) const { return node_x[tip]; }
};

// Builds the model of a scene's CT or DCB specimen. Throws Error for
// geometries outside the valid range (a/W, zero sizes, ...).
CrackPlaneModel BuildCrackPlaneModel(const Scene& scene, const CrackPlaneOptions& options);
// The edge-cracked strip (isotropic or orthotropic material from `material`).
CrackPlaneModel BuildEdgeCrackStripModel(const EdgeCrackStrip& strip, const MaterialSpec& material,
                                         PlaneCondition plane, const CrackPlaneOptions& options);

// Default element size for a scene (see CrackPlaneOptions::resolution).
double DefaultResolution(const SpecimenSpec& specimen);
// Largest crack length of a scene's run (see CrackPlaneOptions::max_crack_length).
double DefaultMaxCrackLength(const Scene& scene);

}  // namespace bridgefit::specimen
