#pragma once
// What the MPM solver simulates: a background grid, the material points, a
// constitutive law, velocity constraints (pins, arm ends, supports) and an
// explicit crack. Builders make a Model from a Scene (CT, DCB); tests can
// assemble their own (bars, plates).

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bridgefit/mpm/material.hpp"
#include "bridgefit/scene/scene.hpp"

namespace bridgefit::mpm {

// Nodes (i, j) at (x0 + i h, y0 + j h), i < nx, j < ny; node index j nx + i.
struct GridSpec {
  double x0 = 0.0, y0 = 0.0;
  double cell = 0.0;  // h [m]
  int nx = 0, ny = 0;
  std::size_t NodeCount() const { return static_cast<std::size_t>(nx) * ny; }
  double NodeX(int i) const { return x0 + i * cell; }
  double NodeY(int j) const { return y0 + j * cell; }
};

// Initial material points (SoA). Volumes per unit thickness [m^2].
struct ParticleSeed {
  std::vector<double> x, y, volume, vx, vy;
  std::size_t size() const { return x.size(); }
};

// Fills the sub-cells of `grid` (ppc x ppc per cell) whose centres satisfy
// `inside(x, y)` with one particle each.
ParticleSeed FillParticles(const GridSpec& grid, int ppc,
                           const std::function<bool(double, double)>& inside);

// Nodes whose velocity is prescribed: v = share * rate(t) along the
// constrained directions, rate(t) being the load-point displacement rate of
// the loading profile (share 0: a fixed support).
struct NodeConstraint {
  std::string name;
  std::vector<int> nodes;
  bool constrain_x = false;
  bool constrain_y = false;
  double share_x = 0.0;
  double share_y = 0.0;
  // Rigid pin (frictionless): only the component along n = (node - centre)/|.|
  // is prescribed, so the pin transmits no moment and the specimen turns
  // about it freely; unilateral: the pin only pushes.
  bool radial = false;
  bool unilateral = false;
  double center_x = 0.0, center_y = 0.0;
};

struct Model {
  std::string description;
  GridSpec grid;
  int ppc = 2;
  ParticleSeed particles;
  std::shared_ptr<const ConstitutiveLaw> law;
  double density = 0.0;  // [kg/m^3]
  PlaneCondition plane = PlaneCondition::kPlaneStress;
  double thickness = 1.0;  // out of plane [m]; loads and energies are scaled by it
  double effective_modulus = 0.0;  // E' with G = K^2/E' (for reports)
  std::vector<NodeConstraint> constraints;
  // The load is the y reaction on this constraint times thickness [N].
  int load_constraint = -1;
  // Explicit crack: polyline from the mouth to the tip (empty: none).
  std::vector<std::array<double, 2>> crack;
  // Half model of a specimen symmetric about the crack plane y = 0: the
  // particles above it only, node row y = 0 on the plane (the growth model
  // holds it as a symmetry boundary ahead of the tip), no explicit crack.
  bool half = false;
  // Lowest natural angular frequency estimate [rad/s] (sets auto damping).
  double lowest_frequency = 0.0;

  // Throws Error when inconsistent (particles off the grid, bad law, ...).
  void Validate() const;
};

enum class PinModel {
  kHoles,    // CT: E399 pin holes with a rigid frictionless pin in each
  kPatches   // CT: no holes, one driven node at each pin centre (a hinge)
};

// CT: origin on the load line at the crack plane, x towards the back edge;
// total width 1.25 W (front face at -0.25 W), height 1.2 W unless the scene
// sets it, pin holes of diameter 0.25 W centred at (0, +-0.275 W) (E399).
// Crack points every half cell from the front face to a0.
// DCB: arms of thickness h from x = 0 (load line, driven ends) to L.
Model BuildSpecimenModel(const Scene& scene, double cell, int ppc,
                         PinModel pins = PinModel::kHoles);
// The upper half (y > 0) of the same specimen with its top pin or arm end,
// on a grid with a node row on y = 0 (for the quasi-static growth model).
Model BuildHalfSpecimenModel(const Scene& scene, double cell, int ppc);

}  // namespace bridgefit::mpm
