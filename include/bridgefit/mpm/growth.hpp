#pragma once
// Crack growth with bridging on the MPM discretisation (PHYSICS sections 3-5),
// solved quasi-statically (implicit MPM: one static equilibrium per crack
// length, particles at their reference positions, small strain).
//
// Discretisation: the explicit solver's background grid, particles and uGIMP
// (or linear) weights. Full model: an explicit straight crack on y = 0; nodes
// whose support it cuts carry a second field (the side a particle takes is
// decided by whether the particle-node line crosses the crack). Half model
// (mode I on a symmetry plane): the particles above y = 0, a node row on the
// plane held by u_y = 0 ahead of the tip and released as the tip advances.
//
// Per crack length a (tip at x = a from the load line):
//   K(a) U_d = F_d,  K(a) G_k = g_k              (one factorisation, n_b + 1 solves)
//   delta = d A - M (c o sigma(delta; delta_max)),  A_k = g_k.U_d, M_jk = g_j.G_k
// with d the load-point displacement, g_k the extraction vector of the COD at
// bridged point k (delta_k = g_k.u), c_k its face length (half of it in the
// half model, where delta = 2 u_y) and sigma the law with elastic unloading.
// d is found by secant iteration so that J_tip = J_tip,c, J_tip being the
// contour J minus the face term int sigma d(delta) between the contour's
// crossing and the tip (PHYSICS 4). Then the opening history is updated
// (a point whose opening reaches delta_c is broken for good), the point is
// recorded (R from the elastic-zone equation, J_ff, delta_root, root, load,
// displacement) and the tip advances by one increment.
// Pins: penalty on the normal displacement of the hole nodes the pin pushes on.

#include <string>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/mpm/solver.hpp"
#include "bridgefit/scene/scene.hpp"

namespace bridgefit::mpm {

enum class GrowthSymmetry {
  kAuto,  // half model when the scene is symmetric about the crack plane and
          // a0 is a multiple of the cell (the half model's tip is on a node)
  kHalf,  // half model (symmetry boundary on the ligament)
  kFull   // explicit crack through the whole specimen
};
const char* GrowthSymmetryName(GrowthSymmetry symmetry);

struct GrowthOptions {
  double cell = 2.5e-3;  // background cell [m]
  int ppc = 2;           // particles per cell per direction (even for the full model)
  ShapeFunction shape = ShapeFunction::kGimp;
  GrowthSymmetry symmetry = GrowthSymmetry::kAuto;
  // Tip increment [m]; 0: one cell. The half model's tip moves from node to
  // node (multiples of a cell). The full model takes any increment, but with
  // half a cell the discrete crack cuts alternately one and two particle-node
  // lines per step, so the energy released per step alternates by about
  // +-10 % (2 x 2 uGIMP, CT at 2.5 mm); a whole cell advances it evenly.
  double increment = 0.0;
  // J contour half sizes [cells]; the first decides growth, all are reported.
  std::vector<int> contour_cells = {3};
  // Largest crack length from the load line [m]; 0: the scene's
  // [run] max_crack_length, else as far as the contours fit in the specimen.
  double max_crack_length = 0.0;
  double tolerance = 1e-7;   // |J_tip / J_tip,c - 1| at each crack length
  int max_iterations = 60;   // secant iterations on the load per crack length
  int threads = 0;           // OpenMP threads for the assembly (0: default)
  bool progress = false;     // progress line on stderr

  bool IsValid(std::string* why) const;
};

struct GrowthResult {
  // Points as the reduced model reports them (model "mpm"); R_energy from
  // the run's own load-displacement record.
  SimulationResult result;
  bool half = false;                  // which model ran
  double cell = 0.0, increment = 0.0;  // [m]
  std::size_t particles = 0;
  std::size_t dofs = 0;                // equations of the static system
  std::vector<int> contour_cells;
  // Per point: J_tip on every contour in contour_cells [J/m^2], and the
  // contour J before the face term.
  std::vector<std::vector<double>> J_tip_contours;
  std::vector<std::vector<double>> J_contours;
  // Wall time by stage [s]: assembly, factorisation, solves, nonlinear.
  std::vector<std::pair<std::string, double>> stage_seconds;
};

// The growth model's validity against the cell (docs/MPM.md, "DCB growth"):
// about 8 cells through a DCB arm (at 4 the contour J is 25-33% low and
// R_energy 6-7% off). The reason the cell is too coarse for the
// specimen, empty when it is not. One home for the rule: `simulate --model
// mpm` warns with it, `fit --model auto` refines or warns with it.
inline constexpr double kMinGrowthCellsThroughArm = 8.0;
std::string GrowthCellTooCoarse(const SpecimenSpec& specimen, double cell);

// True when the scene is symmetric about the crack plane (mode I growth on
// a symmetry plane: isotropic, or orthotropic with axes along/across it).
bool SceneIsSymmetric(const Scene& scene);

// Grows the scene's crack from its notch with the law (null: no bridging)
// and crack-tip toughness J_tip_c [J/m^2]. A failed solve is reported in the
// result's status; bad inputs throw Error(kInput/kUsage).
GrowthResult SimulateGrowth(const Scene& scene, const laws::BridgingLaw* law, double J_tip_c,
                            const GrowthOptions& options);

}  // namespace bridgefit::mpm
