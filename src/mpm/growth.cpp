#include "bridgefit/mpm/growth.hpp"

#include <omp.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/laws/rcurve_theory.hpp"
#include "bridgefit/mpm/material.hpp"
#include "bridgefit/mpm/model.hpp"
#include "shape.hpp"
#include "growth_impl.hpp"

namespace bridgefit::mpm {

const char* GrowthSymmetryName(GrowthSymmetry symmetry) {
  switch (symmetry) {
    case GrowthSymmetry::kAuto: return "auto";
    case GrowthSymmetry::kHalf: return "half";
    case GrowthSymmetry::kFull: return "full";
  }
  return "?";
}

bool GrowthOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!(cell > 0.0)) return fail("cell must be positive");
  if (ppc < 1 || ppc > 8) return fail("ppc must be 1..8");
  if (!(increment >= 0.0)) return fail("increment must be >= 0");
  if (contour_cells.empty()) return fail("at least one J contour is needed");
  for (int k : contour_cells)
    if (k < 1) return fail("contour half sizes must be >= 1 cell");
  if (!(max_crack_length >= 0.0)) return fail("max_crack_length must be >= 0");
  if (!(tolerance > 0.0 && tolerance < 0.1)) return fail("tolerance must be in (0, 0.1)");
  if (max_iterations < 2) return fail("max_iterations must be >= 2");
  if (threads < 0) return fail("threads must be >= 0");
  return true;
}

bool SceneIsSymmetric(const Scene& scene) {
  const MaterialSpec& m = scene.material;
  if (!m.orthotropic) return true;
  const double a = std::fmod(std::abs(m.angle), M_PI);
  return a < 1e-9 || std::abs(a - 0.5 * M_PI) < 1e-9 || std::abs(a - M_PI) < 1e-9;
}
namespace growth_internal {

// StaticGrowth::Run: quasi-static growth, one crack length at a time, each at
// the load-point displacement where J_tip = J_tip,c (PHYSICS 4):
// FactorizeAt -> UnitFields -> ReduceToBridgedPoints -> SolveLoadForJtipc ->
// RecordCrackLength -> AddBridgedPoints.
GrowthResult StaticGrowth::Run(const laws::BridgingLaw* law, double J_tip_c) {
  Stopwatch watch;
  BF_CHECK_INPUT(std::isfinite(J_tip_c) && J_tip_c > 0.0, "J_tip,c must be positive",
                 {.field = "fracture.J_tip_c", .value = fmt::format("{:g} J/m^2", J_tip_c)});
  if (law)
    BF_CHECK_INPUT(law->shape && law->delta_c > 0.0 && law->sigma_c > 0.0,
                   "the bridging law needs sigma_c > 0 and delta_c > 0", {.field = "bridging"});
  GrowthResult out;
  out.half = half_;
  out.cell = h_;
  out.increment = increment_;
  out.particles = P_;
  out.dofs = static_cast<std::size_t>(ndof_);
  out.contour_cells = opt_.contour_cells;
  SimulationResult& res = out.result;
  res.model = "mpm";
  res.figures["cell_m"] = h_;
  res.figures["increment_m"] = increment_;
  res.figures["particles"] = static_cast<double>(P_);
  res.figures["dofs"] = ndof_;
  res.figures["half_model"] = half_ ? 1.0 : 0.0;

  double x_tip = a0_;
  {
    Stopwatch s;
    AssembleInitial(x_tip);
    t_assembly_ += s.Seconds();
  }
  // Bridged points: crack points from a0 to the tip (full model, the tip
  // point included), released symmetry-plane nodes behind the tip (half).
  std::vector<BridgedPoint> pts;
  if (law && !half_) pts.push_back({.x = a0_});
  const int steps_total = static_cast<int>(std::floor((x_end_ - a0_) / increment_ + 1e-9)) + 1;
  Progress progress("MPM growth", static_cast<std::size_t>(steps_total), opt_.progress);
  double d_prev = NAN;
  const Functional mouth = CodFunctional(x_front_ + (half_ ? 0.0 : 0.25 * h_));
  int step = 0;
  for (;; ++step) {
    // ---- system for this crack length
    if (!FactorizeAt(x_tip)) {
      res.status = RunStatus::kFailed;
      res.message = fmt::format("the static system is singular at a = {:.4g} mm", x_tip * 1e3);
      break;
    }
    LengthSystem sys = UnitFields(pts, x_tip);
    Stopwatch nonlinear;
    ReduceToBridgedPoints(pts, sys);
    // ---- load-point displacement with J_tip = J_tip,c (secant on sqrt J).
    const LoadSolution load = SolveLoadForJtipc(law, J_tip_c, pts, d_prev, sys);
    t_nonlinear_ += nonlinear.Seconds();
    if (std::abs(load.f2) > 0.5 * opt_.tolerance || !load.ok) {
      res.status = RunStatus::kNotConverged;
      res.message = fmt::format(
          "the load for J_tip = J_tip,c did not converge at a = {:.4g} mm ({} iterations, "
          "|sqrt(J_tip/J_tip,c) - 1| = {:.3g}{})",
          x_tip * 1e3, load.iterations, std::abs(load.f2),
          load.ok ? "" : ", bridging openings unconverged");
      break;
    }
    const double d = load.d2;
    d_prev = d;
    const Vec u = Field(sys, d);
    // ---- record this crack length
    res.points.push_back(RecordCrackLength(law, J_tip_c, mouth, u, d, sys, pts, res));
    out.J_contours.push_back(sys.J_all);
    out.J_tip_contours.push_back(sys.Jtip_all);
    progress.Update(static_cast<std::size_t>(step + 1));
    // ---- advance the tip
    const double next = x_tip + increment_;
    if (next > x_end_ + 1e-9 * h_) break;
    AddBridgedPoints(law, x_tip, next, pts);
    x_tip = next;
  }
  progress.Finish();
  FillEnergyR(res.points, model_.thickness);
  if (!res.points.empty()) res.initiation_load = res.points.front().load;
  if (res.status == RunStatus::kOk)
    res.message = fmt::format("crack grown from {:.6g} to {:.6g} mm ({} model, {} points)",
                              a0_ * 1e3, res.points.empty() ? a0_ * 1e3
                                                            : res.points.back().crack_length * 1e3,
                              half_ ? "half" : "full", res.points.size());
  res.wall_s = watch.Seconds();
  out.stage_seconds = {{"assembly", t_assembly_},
                       {"factorization", t_factor_},
                       {"solves", t_solve_},
                       {"nonlinear_and_J", t_nonlinear_}};
  return out;
}

// Masks of the particles cut by the crack at x_tip and K = LDL^T of the
// constrained stiffness; false when K is singular.
bool StaticGrowth::FactorizeAt(double x_tip) {
  {
    Stopwatch s;
    UpdateMasks(x_tip);
    t_assembly_ += s.Seconds();
  }
  Stopwatch s;
  const bool ok = Factorize(x_tip);
  t_factor_ += s.Seconds();
  return ok;
}

// Unit fields: U_d = K^-1 F_d (unit load-point displacement) and
// G_q = K^-1 g_q (unit closing pair on active bridged point q).
StaticGrowth::LengthSystem StaticGrowth::UnitFields(const std::vector<BridgedPoint>& pts,
                                                    double x_tip) {
  LengthSystem sys;
  sys.x_tip = x_tip;
  std::vector<int>& act = sys.act;
  std::vector<double>& c = sys.c;
  // Active (unbroken) bridged points and their face lengths.
  for (std::size_t k = 0; k < pts.size(); ++k) {
    if (pts[k].broken) continue;
    const double prev = k == 0 ? a0_ : pts[k - 1].x;
    const double next = k + 1 < pts.size() ? pts[k + 1].x : (half_ ? x_tip : pts[k].x);
    const double w = 0.5 * (std::max(next, a0_) - std::max(prev, a0_));
    if (w <= 0.0) continue;
    act.push_back(static_cast<int>(k));
    c.push_back(half_ ? 0.5 * w : w);
  }
  const int nb = sys.nb = static_cast<int>(act.size());
  // Opening functionals of every crack point, once per crack length.
  std::vector<Functional>& cod = sys.cod;
  cod.resize(pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k) cod[k] = CodFunctional(pts[k].x);
  sys.tip_cod = CodFunctional(x_tip);
  std::vector<Functional>& g = sys.g;
  g.resize(nb);
  Vec& U_d = sys.U_d;
  Eigen::MatrixXd& G = sys.G;
  G.resize(ndof_, nb);
  {
    Stopwatch s;
    U_d = ldlt_.solve(F_d_);
    for (int q = 0; q < nb; ++q) {
      g[q] = cod[act[q]];
      Vec rhs = Vec::Zero(ndof_);
      for (std::size_t e = 0; e < g[q].dof.size(); ++e) rhs[g[q].dof[e]] += g[q].coef[e];
      G.col(q) = ldlt_.solve(rhs);
    }
    t_solve_ += s.Seconds();
  }
  return sys;
}

// Reduced bridged system: delta = d A - M sigma, A_q = g_q . U_d,
// M_qr = g_q . G_r; openings start from the last crack length's.
void StaticGrowth::ReduceToBridgedPoints(const std::vector<BridgedPoint>& pts,
                                         LengthSystem& sys) const {
  const int nb = sys.nb;
  sys.A = Vec(nb);
  sys.M = Eigen::MatrixXd(nb, nb);
  for (int q = 0; q < nb; ++q) {
    sys.A[q] = sys.g[q].Apply(sys.U_d);
    for (int r = 0; r < nb; ++r) sys.M(q, r) = sys.g[q].Apply(sys.G.col(r));
  }
  sys.delta = Vec::Zero(nb);
  sys.sig = Vec::Zero(nb);
  for (int q = 0; q < nb; ++q) sys.delta[q] = pts[sys.act[q]].delta;
  sys.J_all.assign(opt_.contour_cells.size(), 0.0);
  sys.Jtip_all.assign(opt_.contour_cells.size(), 0.0);
}

// Openings at load-point displacement d: delta - d A + M (c sigma(delta)) = 0
// by damped Newton; false when it does not converge in 100 iterations.
bool StaticGrowth::SolveOpenings(const laws::BridgingLaw* law,
                                 const std::vector<BridgedPoint>& pts, LengthSystem& sys,
                                 double d) const {
  const int nb = sys.nb;
  const std::vector<int>& act = sys.act;
  const std::vector<double>& c = sys.c;
  const Vec& A = sys.A;
  const Eigen::MatrixXd& M = sys.M;
  Vec& delta = sys.delta;
  Vec& sig = sys.sig;
  // Traction and slope at opening x of active point q.
  auto traction = [&](int q, double x, double* slope) {
    const BridgedPoint& b = pts[act[q]];
    const double s0 = law->TractionWithHistory(x, b.delta_max);
    if (slope) {
      const double e = 1e-7 * law->delta_c;
      *slope = (law->TractionWithHistory(x + e, b.delta_max) -
                law->TractionWithHistory(x - e, b.delta_max)) / (2.0 * e);
    }
    return s0;
  };
  if (nb == 0) return true;
  Vec r(nb), slope(nb);
  for (int it = 0; it < 100; ++it) {
    for (int q = 0; q < nb; ++q) sig[q] = c[q] * traction(q, delta[q], &slope[q]);
    r = delta - d * A + M * sig;
    const double norm = r.cwiseAbs().maxCoeff();
    if (norm < 1e-13 * law->delta_c + 1e-15) return true;
    const Vec cs = Eigen::Map<const Vec>(c.data(), nb).cwiseProduct(slope);
    Eigen::MatrixXd Jm = M * cs.asDiagonal();
    Jm.diagonal().array() += 1.0;
    Vec step_v = Jm.partialPivLu().solve(r);
    double lambda = 1.0;
    for (int ls = 0; ls < 30; ++ls) {
      Vec trial = delta - lambda * step_v;
      Vec st(nb);
      for (int q = 0; q < nb; ++q) st[q] = c[q] * traction(q, trial[q], nullptr);
      const double tn = (trial - d * A + M * st).cwiseAbs().maxCoeff();
      if (tn < norm || ls == 29) {
        delta = trial;
        break;
      }
      lambda *= 0.5;
    }
  }
  return false;
}

// Displacement field u = d U_d - G sigma.
Vec StaticGrowth::Field(const LengthSystem& sys, double d) {
  Vec u = d * sys.U_d;
  if (sys.nb > 0) u.noalias() -= sys.G * sys.sig;
  return u;
}

// J_tip on each contour: contour J minus int sigma d(delta) between the
// contour's crossing of the crack and the tip (PHYSICS 4).
double StaticGrowth::TipJ(const laws::BridgingLaw* law, const std::vector<BridgedPoint>& pts,
                          LengthSystem& sys, const Vec& u) const {
  const double x_tip = sys.x_tip;
  const std::vector<Functional>& cod = sys.cod;
  // Openings and tractions of every crack point behind the tip, tip last.
  std::vector<double> xs, ds, ss;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    if (half_ || pts[k].x < x_tip - 1e-9 * h_) {
      xs.push_back(pts[k].x);
      ds.push_back(cod[k].Apply(u));
      ss.push_back(law ? law->TractionWithHistory(ds.back(), pts[k].delta_max) : 0.0);
      if (pts[k].broken) ss.back() = 0.0;
    }
  }
  xs.push_back(x_tip);
  ds.push_back(half_ ? 0.0 : sys.tip_cod.Apply(u));
  ss.push_back(law && !half_ ? law->TractionWithHistory(ds.back(), pts.back().delta_max)
                             : 0.0);
  for (std::size_t q = 0; q < opt_.contour_cells.size(); ++q) {
    const int k = opt_.contour_cells[q];
    const double J = ContourJ(u, x_tip, k);
    const int it = static_cast<int>(std::lround((x_tip - x0_) * inv_h_));
    const double face = detail::FaceWork(
        xs, [&](std::size_t e) { return ds[e]; }, [&](std::size_t e) { return ss[e]; },
        x0_ + (it - k) * h_);
    sys.J_all[q] = J;
    sys.Jtip_all[q] = J - face;
  }
  return sys.Jtip_all[0];
}

// Load-point displacement d with sqrt(J_tip(d) / J_tip,c) - 1 = 0, by secant
// from the last crack length's d (or a linear estimate at the first).
StaticGrowth::LoadSolution StaticGrowth::SolveLoadForJtipc(const laws::BridgingLaw* law,
                                                           double J_tip_c,
                                                           const std::vector<BridgedPoint>& pts,
                                                           double d_prev,
                                                           LengthSystem& sys) const {
  const int nb = sys.nb;
  Vec& sig = sys.sig;
  auto residual = [&](double d, bool* ok) {
    *ok = SolveOpenings(law, pts, sys, d);
    const double Jt = TipJ(law, pts, sys, Field(sys, d));
    return std::sqrt(std::max(Jt, 0.0) / J_tip_c) - 1.0;
  };
  bool ok = true;
  double d1;
  if (!std::isfinite(d_prev)) {
    // Linear estimate with the openings frozen at zero.
    for (int q = 0; q < nb; ++q) sig[q] = 0.0;
    const double j1 = TipJ(law, pts, sys, Field(sys, 1.0));
    d1 = j1 > 0.0 ? std::sqrt(J_tip_c / j1) : 1e-3;
  } else {
    d1 = d_prev;
  }
  double f1 = residual(d1, &ok);
  double d2 = d1 / (1.0 + f1), f2 = residual(d2, &ok);
  int iterations = 2;
  while (std::abs(f2) > 0.5 * opt_.tolerance && iterations < opt_.max_iterations) {
    const double slope = (f2 - f1) / (d2 - d1);
    double d3 = std::abs(slope) > 0.0 && std::isfinite(slope) ? d2 - f2 / slope : d2 / (1.0 + f2);
    if (!(d3 > 0.0)) d3 = 0.5 * d2;
    d1 = d2;
    f1 = f2;
    d2 = d3;
    f2 = residual(d2, &ok);
    ++iterations;
  }
  return {.d2 = d2, .f2 = f2, .iterations = iterations, .ok = ok};
}

// The converged state of this crack length: load, CMOD, bridged openings
// (delta_max history, breaking at delta_c), zone root and R (PHYSICS 3).
SimulationPoint StaticGrowth::RecordCrackLength(const laws::BridgingLaw* law, double J_tip_c,
                                                const Functional& mouth, const Vec& u, double d,
                                                const LengthSystem& sys,
                                                std::vector<BridgedPoint>& pts,
                                                SimulationResult& res) const {
  const double x_tip = sys.x_tip;
  const std::vector<Functional>& cod = sys.cod;
  SimulationPoint point;
  point.crack_length = x_tip;
  point.J_tip = sys.Jtip_all[0];
  point.load = ReactionLoad(u, d);
  point.displacement = d;
  point.cmod = mouth.Apply(u);
  double delta_root = 0.0, root = a0_;
  if (law && !pts.empty()) {
    for (std::size_t k = 0; k < pts.size(); ++k) {
      BridgedPoint& b = pts[k];
      if (b.broken) continue;
      const double now = cod[k].Apply(u);
      b.delta = now;
      b.delta_max = std::max(b.delta_max, now);
      if (b.delta_max >= law->delta_c) b.broken = true;
    }
    // The notch root opening (zero while the root is still the tip).
    delta_root = pts.front().x < x_tip - 1e-9 * h_ ? pts.front().delta : 0.0;
    if (pts.front().broken) {
      std::size_t first = 0;
      while (first < pts.size() && pts[first].broken) ++first;
      const double d_broken = pts[first - 1].delta;
      const double d_next = first < pts.size() ? pts[first].delta : 0.0;
      const double x_next = first < pts.size() ? pts[first].x : x_tip;
      const double frac = d_broken > d_next ? std::clamp((d_broken - law->delta_c) /
                                                             (d_broken - d_next), 0.0, 1.0)
                                            : 0.0;
      root = pts[first - 1].x + frac * (x_next - pts[first - 1].x);
      delta_root = law->delta_c;
      if (!res.steady_state_reached) {
        res.steady_state_reached = true;
        res.steady_state_crack_length = x_tip;
      }
    }
  }
  point.delta_root = delta_root;
  point.root_position = root;
  point.bridging_zone_length = x_tip - root;
  point.R = law ? laws::ElasticZoneR(*law, delta_root, J_tip_c) : J_tip_c;
  point.J_ff = law ? laws::FarFieldJ(*law, delta_root, point.J_tip) : point.J_tip;
  return point;
}

// New bridged points on the crack advanced from x_tip to next: every released
// symmetry-plane node (half model) or the new tip crack point (full model).
void StaticGrowth::AddBridgedPoints(const laws::BridgingLaw* law, double x_tip, double next,
                                    std::vector<BridgedPoint>& pts) const {
  if (law) {
    if (half_) {
      for (double x = x_tip; x < next - 1e-9 * h_; x += h_) pts.push_back({.x = x});
    } else {
      pts.push_back({.x = next});
    }
  }
}
}  // namespace growth_internal

using growth_internal::StaticGrowth;

std::string GrowthCellTooCoarse(const SpecimenSpec& s, double cell) {
  if (s.type != SpecimenType::kDCB || !(cell > 0.0) || s.height / cell >= kMinGrowthCellsThroughArm)
    return "";
  return fmt::format(
      "{:.3g} cells through the DCB arm (h {:.3g} mm; growth needs about {:g}: at 4 the contour J "
      "is 25-33% low and R_energy 6-7% off, docs/MPM.md)",
      s.height / cell, s.height * 1e3, kMinGrowthCellsThroughArm);
}

GrowthResult SimulateGrowth(const Scene& scene, const laws::BridgingLaw* law, double J_tip_c,
                            const GrowthOptions& options) {
  StaticGrowth growth(scene, options);
  GrowthResult g = growth.Run(law, J_tip_c);
  if (std::string why = GrowthCellTooCoarse(scene.specimen, g.cell); !why.empty())
    g.result.warnings.push_back(
        fmt::format("MPM cell {:.3g} mm too coarse: {}; refine the cell to {:.3g} mm or less",
                    g.cell * 1e3, why, scene.specimen.height / kMinGrowthCellsThroughArm * 1e3));
  return g;
}

}  // namespace bridgefit::mpm
