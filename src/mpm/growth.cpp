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
    {
      Stopwatch s;
      UpdateMasks(x_tip);
      t_assembly_ += s.Seconds();
    }
    {
      Stopwatch s;
      const bool ok = Factorize(x_tip);
      t_factor_ += s.Seconds();
      if (!ok) {
        res.status = RunStatus::kFailed;
        res.message = fmt::format("the static system is singular at a = {:.4g} mm", x_tip * 1e3);
        break;
      }
    }
    // Active (unbroken) bridged points and their face lengths.
    std::vector<int> act;
    std::vector<double> c;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      if (pts[k].broken) continue;
      const double prev = k == 0 ? a0_ : pts[k - 1].x;
      const double next = k + 1 < pts.size() ? pts[k + 1].x : (half_ ? x_tip : pts[k].x);
      const double w = 0.5 * (std::max(next, a0_) - std::max(prev, a0_));
      if (w <= 0.0) continue;
      act.push_back(static_cast<int>(k));
      c.push_back(half_ ? 0.5 * w : w);
    }
    const int nb = static_cast<int>(act.size());
    // Opening functionals of every crack point, once per crack length.
    std::vector<Functional> cod(pts.size());
    for (std::size_t k = 0; k < pts.size(); ++k) cod[k] = CodFunctional(pts[k].x);
    const Functional tip_cod = CodFunctional(x_tip);
    std::vector<Functional> g(nb);
    Vec U_d;
    Eigen::MatrixXd G(ndof_, nb);
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
    Stopwatch nonlinear;
    Vec A(nb);
    Eigen::MatrixXd M(nb, nb);
    for (int q = 0; q < nb; ++q) {
      A[q] = g[q].Apply(U_d);
      for (int r = 0; r < nb; ++r) M(q, r) = g[q].Apply(G.col(r));
    }
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
    Vec delta = Vec::Zero(nb), sig = Vec::Zero(nb);
    for (int q = 0; q < nb; ++q) delta[q] = pts[act[q]].delta;
    // Openings at load-point displacement d (Newton on delta, damped).
    auto solve_openings = [&](double d) {
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
    };
    auto field = [&](double d) {
      Vec u = d * U_d;
      if (nb > 0) u.noalias() -= G * sig;
      return u;
    };
    // J_tip on each contour: contour J minus int sigma d(delta) between the
    // contour's crossing of the crack and the tip (PHYSICS 4).
    std::vector<double> J_all(opt_.contour_cells.size()), Jtip_all(opt_.contour_cells.size());
    auto tip_J = [&](const Vec& u) {
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
      ds.push_back(half_ ? 0.0 : tip_cod.Apply(u));
      ss.push_back(law && !half_ ? law->TractionWithHistory(ds.back(), pts.back().delta_max)
                                 : 0.0);
      for (std::size_t q = 0; q < opt_.contour_cells.size(); ++q) {
        const int k = opt_.contour_cells[q];
        const double J = ContourJ(u, x_tip, k);
        const int it = static_cast<int>(std::lround((x_tip - x0_) * inv_h_));
        const double face = detail::FaceWork(
            xs, [&](std::size_t e) { return ds[e]; }, [&](std::size_t e) { return ss[e]; },
            x0_ + (it - k) * h_);
        J_all[q] = J;
        Jtip_all[q] = J - face;
      }
      return Jtip_all[0];
    };
    // ---- load-point displacement with J_tip = J_tip,c (secant on sqrt J).
    auto residual = [&](double d, bool* ok) {
      *ok = solve_openings(d);
      const double Jt = tip_J(field(d));
      return std::sqrt(std::max(Jt, 0.0) / J_tip_c) - 1.0;
    };
    bool ok = true;
    double d1;
    if (!std::isfinite(d_prev)) {
      // Linear estimate with the openings frozen at zero.
      for (int q = 0; q < nb; ++q) sig[q] = 0.0;
      const double j1 = tip_J(field(1.0));
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
    t_nonlinear_ += nonlinear.Seconds();
    if (std::abs(f2) > 0.5 * opt_.tolerance || !ok) {
      res.status = RunStatus::kNotConverged;
      res.message = fmt::format(
          "the load for J_tip = J_tip,c did not converge at a = {:.4g} mm ({} iterations, "
          "|sqrt(J_tip/J_tip,c) - 1| = {:.3g}{})",
          x_tip * 1e3, iterations, std::abs(f2), ok ? "" : ", bridging openings unconverged");
      break;
    }
    const double d = d2;
    d_prev = d;
    const Vec u = field(d);
    // ---- record this crack length
    SimulationPoint point;
    point.crack_length = x_tip;
    point.J_tip = Jtip_all[0];
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
    res.points.push_back(point);
    out.J_contours.push_back(J_all);
    out.J_tip_contours.push_back(Jtip_all);
    progress.Update(static_cast<std::size_t>(step + 1));
    // ---- advance the tip
    const double next = x_tip + increment_;
    if (next > x_end_ + 1e-9 * h_) break;
    if (law) {
      if (half_) {
        for (double x = x_tip; x < next - 1e-9 * h_; x += h_) pts.push_back({.x = x});
      } else {
        pts.push_back({.x = next});
      }
    }
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
}  // namespace growth_internal

using growth_internal::StaticGrowth;

GrowthResult SimulateGrowth(const Scene& scene, const laws::BridgingLaw* law, double J_tip_c,
                            const GrowthOptions& options) {
  StaticGrowth growth(scene, options);
  return growth.Run(law, J_tip_c);
}

}  // namespace bridgefit::mpm
