#pragma once
// The reduced forward model: a growing mode I crack with an elastic bridging
// zone on a specimen's crack-plane Green's function (specimen/crack_plane.hpp).
//
// For a tip at node t the openings u of the free crack-plane nodes solve
//   u = F_t (g p - b(u)),  b_j = w_j sigma(2 u_j; history)            (1)
// with F_t the flexibility of the free nodes (built by bordering as the tip
// advances), w_j the trapezoidal face lengths and sigma the bridging law with
// elastic unloading toward the origin. The load p = P/B is fixed by the tip
// criterion J_tip = J_tip,c, J_tip being the energy released per unit growth
// with the tractions frozen: the mean of the nodal-release energies of the
// step behind and the step ahead of the tip (centred on the tip):
//   J_tip = (R_t^2 phi_t + u_{t-1}^2 / psi_t) / (2 h)                   (2)
// (R_t: reaction that holds the tip node shut; phi_t: its flexibility once
// released; psi_t: flexibility of the node behind the tip). Both releases are
// energy differences under one set of loads in which the released node
// carries the traction of its full face length; that symmetric choice cancels
// the O(sqrt h) work of the near-tip tractions (face-pressure check: K within
// 0.7% at a/h = 20, against 4% with the node's half share). (1)-(2) is solved
// by Newton on (u, p), warm-started from the previous crack length, either in
// the stiffness form S u + b(u) = g p with factors kept across crack lengths
// (ReducedOptions::Solver::kBordered) or in the form (1) (kDense).

#include <memory>
#include <string>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/scene/scene.hpp"
#include "bridgefit/specimen/crack_plane.hpp"

namespace bridgefit::models {

namespace reduced_internal {
struct ElasticTables;  // src/models/reduced_impl.hpp
}

struct ReducedOptions {
  // kBordered: stiffness form with an LDL^T factor grown across crack lengths,
  // O(t^2) per crack length. kDense: flexibility form, dense LU of the zone
  // Jacobian, O(k^3). kHybrid: per crack length the cheaper of the two
  // (dense while the bridged zone is short, k^3 < 6 t^2). Same equations,
  // same answers (a test checks).
  enum class Solver { kHybrid, kBordered, kDense };
  Solver solver = Solver::kHybrid;
  specimen::CrackPlaneOptions mesh;  // resolution, largest crack length
  int max_newton_iterations = 60;
  double tolerance = 1e-10;          // relative residual
  bool progress = false;             // progress line on stderr

  bool IsValid(std::string* why) const;
};

// Linear state for a tip at retained node `tip` (1 .. n-1) under a load p
// [N/m] and closing nodal forces `closing` [N/m] on the free nodes 0..tip-1
// plus the tip node itself (size tip+1); the tip node's entry is the force it
// carries once released (its full face length, like the node behind it).
// Independent of the incremental solver; used by tests and K calibrations.
struct LinearTipState {
  double J_tip = 0.0;        // centred nodal-release energy per unit growth [J/m^2]
  double G_ahead = 0.0;      // release of the tip node [J/m^2]
  double G_behind = 0.0;     // release of the node behind the tip [J/m^2]
  double half_load_line_displacement = 0.0;  // Delta [m]
  double half_mouth_opening = 0.0;           // [m]
  double half_gauge_opening = 0.0;           // load-line face opening / 2 [m]
  std::vector<double> u;                     // u_y of free nodes [m]
};
LinearTipState SolveLinearTip(const specimen::CrackPlaneModel& model, int tip, double p,
                              const std::vector<double>& closing);

// The model of one specimen geometry, reusable for many laws (a fit). What
// depends on the geometry alone (the elastic crack plane's LDL^T factor and
// flexibility terms) is computed once here and shared read-only by Run,
// which may be called from several threads at once.
class ReducedModel {
 public:
  explicit ReducedModel(std::shared_ptr<const specimen::CrackPlaneModel> model);
  // Builds the crack-plane model of the scene's specimen.
  ReducedModel(const Scene& scene, const specimen::CrackPlaneOptions& mesh);

  const specimen::CrackPlaneModel& crack_plane() const { return *model_; }

  // Grows the crack from a0 to the model's last node. `law` may be null (no
  // bridging). A failed solve is reported in the result's status, never thrown;
  // bad inputs (J_tip,c <= 0, delta_c <= 0) throw Error.
  SimulationResult Run(const laws::BridgingLaw* law, double J_tip_c,
                       const ReducedOptions& options) const;

 private:
  std::shared_ptr<const specimen::CrackPlaneModel> model_;
  std::shared_ptr<const reduced_internal::ElasticTables> tables_;
};

// Builds the model for `scene` and runs it (scene.fracture is required).
SimulationResult SimulateReduced(const Scene& scene, const ReducedOptions& options);

// R_energy from the run's own load-displacement record (core/records.hpp).
using bridgefit::FillEnergyR;

}  // namespace bridgefit::models
