// Reduced forward model (see reduced.hpp for the equations).

#include "bridgefit/models/reduced.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/laws/rcurve_theory.hpp"
#include "reduced_impl.hpp"

namespace bridgefit::models {

using namespace reduced_internal;

bool ReducedOptions::IsValid(std::string* why) const {
  if (!mesh.IsValid(why)) return false;
  if (max_newton_iterations < 1) {
    if (why) *why = "max_newton_iterations must be >= 1";
    return false;
  }
  if (!(tolerance > 0.0 && tolerance < 1e-2)) {
    if (why) *why = "tolerance must lie in (0, 1e-2)";
    return false;
  }
  return true;
}

LinearTipState SolveLinearTip(const CrackPlaneModel& model, int tip, double p,
                              const std::vector<double>& closing) {
  const int n = model.size();
  BF_CHECK_INPUT(tip >= 1 && tip < n, "tip index outside the crack-plane model",
                 {.field = "tip", .value = std::to_string(tip)});
  BF_CHECK_INPUT(static_cast<int>(closing.size()) == tip + 1, "closing forces: one per node",
                 {.field = "closing", .expected = std::to_string(tip + 1) + " values"});
  const Eigen::Map<const Eigen::MatrixXd> S(model.stiffness.data(), n, n);
  const Eigen::Map<const Eigen::VectorXd> g(model.load.data(), n);
  const Eigen::Map<const Eigen::VectorXd> c(closing.data(), tip + 1);
  const Eigen::MatrixXd S_ff = S.topLeftCorner(tip, tip);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(S_ff);
  const Eigen::VectorXd u = ldlt.solve(g.head(tip) * p - c.head(tip));
  const Eigen::VectorXd s = S.col(tip).head(tip);
  const double reaction = s.dot(u) - g[tip] * p + c[tip];
  const double phi = 1.0 / (S(tip, tip) - s.dot(ldlt.solve(s)));
  Eigen::VectorXd e = Eigen::VectorXd::Zero(tip);
  e[tip - 1] = 1.0;
  const double psi = ldlt.solve(e)[tip - 1];
  const double h = model.resolution;
  LinearTipState state;
  state.G_ahead = reaction * reaction * phi / h;
  state.G_behind = u[tip - 1] * u[tip - 1] / psi / h;
  state.J_tip = 0.5 * (state.G_ahead + state.G_behind);
  const Eigen::Map<const Eigen::VectorXd> q(model.load_coupling.data(), n);
  const Eigen::Map<const Eigen::VectorXd> qm(model.mouth_coupling.data(), n);
  state.half_load_line_displacement = model.load_compliance * p + q.head(tip).dot(u);
  state.half_mouth_opening = model.mouth_compliance * p + qm.head(tip).dot(u);
  const Eigen::Map<const Eigen::VectorXd> qg(model.gauge_coupling.data(), n);
  state.half_gauge_opening = model.gauge_compliance * p + qg.head(tip).dot(u);
  state.u.assign(u.data(), u.data() + tip);
  return state;
}

ReducedModel::ReducedModel(std::shared_ptr<const CrackPlaneModel> model) : model_(std::move(model)) {
  BF_CHECK_INPUT(model_ && model_->size() >= 3, "the crack-plane model is empty",
                 {.field = "model"});
  tables_ = std::make_shared<const ElasticTables>(*model_);
}

ReducedModel::ReducedModel(const Scene& scene, const specimen::CrackPlaneOptions& mesh)
    : ReducedModel(std::make_shared<const CrackPlaneModel>(
          specimen::BuildCrackPlaneModel(scene, mesh))) {}

SimulationResult ReducedModel::Run(const laws::BridgingLaw* law, double J_tip_c,
                                   const ReducedOptions& options) const {
  Stopwatch watch;
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid reduced-model options: " + why);
  BF_CHECK_INPUT(std::isfinite(J_tip_c) && J_tip_c > 0.0, "J_tip,c must be positive",
                 {.field = "fracture.J_tip_c", .value = fmt::format("{:g} J/m^2", J_tip_c)});
  if (law) {
    BF_CHECK_INPUT(law->shape != nullptr, "the bridging law has no shape", {.field = "bridging"});
    BF_CHECK_INPUT(std::isfinite(law->delta_c) && law->delta_c > 0.0,
                   "the bridging law needs delta_c > 0",
                   {.field = "bridging.delta_c", .value = fmt::format("{:g} m", law->delta_c),
                    .expected = "a value > 0"});
    BF_CHECK_INPUT(std::isfinite(law->sigma_c) && law->sigma_c > 0.0,
                   "the bridging law needs sigma_c > 0",
                   {.field = "bridging.sigma_c", .value = fmt::format("{:g} Pa", law->sigma_c),
                    .expected = "a value > 0"});
  }
  const CrackPlaneModel& m = *model_;
  const int n = m.size();
  const double h = m.resolution;
  const Eigen::Map<const Eigen::MatrixXd> S(m.stiffness.data(), n, n);
  const Eigen::Map<const Eigen::VectorXd> g(m.load.data(), n);

  SimulationResult result;
  result.model = "reduced";
  result.figures["resolution_m"] = h;
  result.figures["elements"] = m.elements;
  result.figures["dofs"] = m.dofs;
  result.figures["crack_plane_nodes"] = n;
  result.figures["model_build_s"] = m.build_s;

  if (options.solver != ReducedOptions::Solver::kDense) {
    int newton_total = 0;
    GrowBordered(m, *tables_, law, J_tip_c, options, result, newton_total);
    FillEnergyR(result.points, m.thickness);
    if (!result.points.empty()) result.initiation_load = result.points.front().load;
    result.figures["newton_iterations"] = newton_total;
    if (result.status == RunStatus::kOk)
      result.message = fmt::format("crack grown to {:.6g} mm", m.CrackLength(n - 1) * 1e3);
    result.wall_s = watch.Seconds();
    return result;
  }

  // Face length carried by node r (r = 1 is a0: half a segment, the notch is
  // behind it).
  auto face_length = [&](int r) { return r == 1 ? 0.5 * h : h; };
  const double tip_traction = law ? law->Traction(0.0) : 0.0;

  // Flexibility of the free set {0 .. t-1}, grown by bordering.
  Eigen::MatrixXd F = Eigen::MatrixXd::Zero(n, n);
  F(0, 0) = 1.0 / S(0, 0);
  std::vector<double> delta_max(n, 0.0);  // history of the full opening
  std::vector<char> broken(n, 0);
  std::vector<double> u_prev(n, 0.0);
  double p_prev = 0.0;
  int newton_total = 0;
  Progress progress("reduced model", static_cast<size_t>(n - 1), options.progress);

  Eigen::VectorXd Fg(n), v(n);
  for (int t = 1; t < n; ++t) {
    // Bordering data of the tip node t.
    v.head(t).noalias() = F.topLeftCorner(t, t) * S.col(t).head(t);
    const double phi = 1.0 / (S(t, t) - S.col(t).head(t).dot(v.head(t)));
    Fg.head(t).noalias() = F.topLeftCorner(t, t) * g.head(t);
    const double alpha = v.head(t).dot(g.head(t)) - g[t];
    const double psi = F(t - 1, t - 1);
    // The tip node carries its full face length once released (reduced.hpp).
    const double tip_force = law ? tip_traction * face_length(t) : 0.0;

    // Zone unknowns: the crack-face nodes z0 .. t-1 from the first unbroken
    // one (the notch root) to the node behind the tip, a contiguous block
    // (a broken node inside it would simply carry zero traction).
    int z0 = 1;
    while (z0 < t && broken[z0]) ++z0;
    const int k = law ? t - z0 : 0;
    double p = 0.0;
    // Openings of the free nodes; the zone part is warm-started from the
    // previous crack length (the new node starts shut).
    Eigen::VectorXd u = Eigen::Map<const Eigen::VectorXd>(u_prev.data(), n);
    bool converged = false;
    if (k == 0) {
      // No bridging unknowns: J_tip is quadratic in p (tip force only shifts R).
      // Solve (alpha p + tip_force)^2 phi + (Fg p)^2/psi = 2 h J_c for p > 0.
      const double A = alpha * alpha * phi + Fg[t - 1] * Fg[t - 1] / psi;
      const double B = 2.0 * alpha * tip_force * phi;
      const double C = tip_force * tip_force * phi - 2.0 * h * J_tip_c;
      const double disc = B * B - 4.0 * A * C;
      p = (-B + std::sqrt(std::max(disc, 0.0))) / (2.0 * A);  // A > 0
      converged = std::isfinite(p);
      u.head(t) = Fg.head(t) * p;
    } else {
      p = p_prev;
      ZoneSystem zone;
      zone.z0 = z0;
      zone.t = t;
      zone.phi = phi;
      zone.alpha = alpha;
      zone.psi = psi;
      zone.tip_force = tip_force;
      zone.FromFlexibility(F, Fg, v);
      Eigen::VectorXd uz = u.segment(z0, k), b;
      converged = SolveZoneDense(zone, h, *law, delta_max, J_tip_c, options, uz, p, b,
                                 newton_total);
      if (converged) u.head(t).noalias() = Fg.head(t) * p - F.block(0, z0, t, k) * b;
    }
    if (!converged || !(p > 0.0)) {
      result.status = RunStatus::kNotConverged;
      result.message = fmt::format("Newton did not converge at crack length {:.6g} mm",
                                   m.CrackLength(t) * 1e3);
      break;
    }
    for (int i = 0; i < t; ++i) u_prev[i] = u[i];
    u_prev[t] = 0.0;
    p_prev = p;

    // Tip energy as evaluated (a check of the solve), history, root.
    double reaction = alpha * p + tip_force;
    for (int r = z0; r < z0 + k; ++r)
      reaction -= v[r] * face_length(r) * BridgingTraction(*law, 2.0 * u[r], delta_max[r]).sigma;
    const double J_tip = CentredTipEnergy(reaction, phi, u[t - 1], psi, h);
    RecordPoint(m, law, J_tip_c, t, u, p, J_tip, delta_max, broken, result);
    progress.Update(static_cast<size_t>(t));

    // Border F with node t for the next tip position.
    if (t + 1 < n) BorderFlexibility(F, v, phi, t);
  }
  progress.Finish();
  FillEnergyR(result.points, m.thickness);
  if (!result.points.empty()) result.initiation_load = result.points.front().load;
  result.figures["newton_iterations"] = newton_total;
  if (result.status == RunStatus::kOk)
    result.message = fmt::format("crack grown to {:.6g} mm", m.CrackLength(n - 1) * 1e3);
  result.wall_s = watch.Seconds();
  return result;
}

SimulationResult SimulateReduced(const Scene& scene, const ReducedOptions& options) {
  Stopwatch watch;
  scene.Validate();
  BF_CHECK_INPUT(scene.fracture.has_value(), "the reduced model needs a [fracture] table",
                 {.file = scene.source, .field = "fracture.J_tip_c",
                  .expected = "a crack-tip toughness, e.g. '2210 J/m^2'"});
  BF_CHECK_INPUT(scene.run.grow, "the reduced model only runs crack growth (run.grow = true)",
                 {.file = scene.source, .field = "run.grow"});
  const ReducedModel model(scene, options.mesh);
  std::optional<laws::BridgingLaw> law;
  if (scene.bridging) law = scene.bridging->Law();
  SimulationResult result = model.Run(law ? &*law : nullptr, scene.fracture->J_tip_c, options);
  result.wall_s = watch.Seconds();
  return result;
}

}  // namespace bridgefit::models
