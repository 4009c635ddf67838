// The reduced model's crack-length solvers (reduced_impl.hpp; equations in reduced.hpp).

#include "reduced_impl.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/laws/rcurve_theory.hpp"

namespace bridgefit::models::reduced_internal {


// Forward-mode dual number: enough arithmetic for laws::ShapeValue.
struct Dual {
  double v = 0.0, d = 0.0;
  Dual() = default;
  explicit Dual(double value, double slope = 0.0) : v(value), d(slope) {}
  friend Dual operator+(Dual a, Dual b) { return Dual(a.v + b.v, a.d + b.d); }
  friend Dual operator-(Dual a, Dual b) { return Dual(a.v - b.v, a.d - b.d); }
  friend Dual operator*(Dual a, Dual b) { return Dual(a.v * b.v, a.d * b.v + a.v * b.d); }
  friend Dual operator/(Dual a, Dual b) {
    return Dual(a.v / b.v, (a.d * b.v - a.v * b.d) / (b.v * b.v));
  }
  friend Dual operator*(Dual a, double b) { return Dual(a.v * b, a.d * b); }
  friend Dual operator*(double a, Dual b) { return Dual(a * b.v, a * b.d); }
  friend Dual operator/(Dual a, double b) { return Dual(a.v / b, a.d / b); }
  friend Dual operator+(Dual a, double b) { return Dual(a.v + b, a.d); }
  friend Dual operator-(Dual a, double b) { return Dual(a.v - b, a.d); }
  Dual& operator+=(Dual b) { return *this = *this + b; }
  friend bool operator<(Dual a, Dual b) { return a.v < b.v; }
  friend bool operator<=(Dual a, Dual b) { return a.v <= b.v; }
  friend bool operator>(Dual a, Dual b) { return a.v > b.v; }
  friend bool operator>=(Dual a, Dual b) { return a.v >= b.v; }
  friend Dual exp(Dual a) {
    const double e = std::exp(a.v);
    return Dual(e, e * a.d);
  }
};

TractionSlope BridgingTraction(const laws::BridgingLaw& law, double delta, double delta_max) {
  if (delta >= delta_max) {
    const Dual s = laws::ShapeValue(*law.shape, Dual(delta / law.delta_c, 1.0 / law.delta_c));
    return {law.sigma_c * s.v, law.sigma_c * s.d};
  }
  if (delta_max >= law.delta_c || delta <= 0.0 || delta_max <= 0.0) return {0.0, 0.0};
  const double secant = law.Traction(delta_max) / delta_max;
  return {secant * delta, secant};
}

// Updates the opening history (breaking points for good) and appends the
// point of tip t with free openings u (nodes 0..t-1), load p and J_tip.
void RecordPoint(const CrackPlaneModel& m, const laws::BridgingLaw* law, double J_tip_c, int t,
                 const Eigen::VectorXd& u, double p, double J_tip, std::vector<double>& delta_max,
                 std::vector<char>& broken, SimulationResult& result) {
  const int n = m.size();
  const double h = m.resolution;
  const Eigen::Map<const Eigen::VectorXd> q(m.load_coupling.data(), n);
  const Eigen::Map<const Eigen::VectorXd> qm(m.mouth_coupling.data(), n);
  if (law) {
    for (int r = 1; r < t; ++r) {
      delta_max[r] = std::max(delta_max[r], 2.0 * u[r]);
      if (delta_max[r] >= law->delta_c) broken[r] = 1;
    }
  }
  SimulationPoint point;
  point.crack_length = m.CrackLength(t);
  point.J_tip = J_tip;
  point.load = p * m.thickness;
  point.displacement = 2.0 * (m.load_compliance * p + q.head(t).dot(u.head(t)));
  point.cmod = 2.0 * (m.mouth_compliance * p + qm.head(t).dot(u.head(t)));
  double delta_root = t >= 2 ? 2.0 * u[1] : 0.0;
  double root = m.notch;
  if (law && broken[1]) {
    int first = 1;
    while (first < t && broken[first]) ++first;
    const double d_broken = 2.0 * u[first - 1];
    const double d_next = first < t ? 2.0 * u[first] : 0.0;
    const double frac =
        d_broken > d_next ? std::clamp((d_broken - law->delta_c) / (d_broken - d_next), 0.0, 1.0)
                          : 0.0;
    root = m.node_x[first - 1] + frac * h;
    delta_root = law->delta_c;
    if (!result.steady_state_reached) {
      result.steady_state_reached = true;
      result.steady_state_crack_length = point.crack_length;
    }
  }
  point.delta_root = delta_root;
  point.root_position = root;
  point.bridging_zone_length = point.crack_length - root;
  if (law) {
    point.R = laws::ElasticZoneR(*law, delta_root, J_tip_c);
    point.J_ff = laws::FarFieldJ(*law, delta_root, J_tip);
  } else {
    point.R = J_tip_c;
    point.J_ff = J_tip;
  }
  result.points.push_back(point);
}

// Dense LDL^T factor of a symmetric matrix that grows by bordering (one new
// last row) and takes rank-one diagonal updates (Bennett's algorithm), both
// O(m^2). L is unit lower triangular, column-major.
class GrowingLdlt {
 public:
  explicit GrowingLdlt(int capacity) : L_(Eigen::MatrixXd::Zero(capacity, capacity)), d_(capacity) {}
  int size() const { return m_; }
  double pivot(int i) const { return d_[i]; }
  // Pivot the new row (column `col` of the matrix above the diagonal, and its
  // diagonal) would get; fills `l` with its L entries. Does not modify.
  double Preview(const Eigen::Ref<const Eigen::VectorXd>& col, double diagonal,
                 Eigen::VectorXd& l) const {
    l.head(m_) = col.head(m_);
    for (int k = 0; k < m_; ++k) {
      const double y = l[k];
      if (y != 0.0) l.segment(k + 1, m_ - k - 1).noalias() -= L_.col(k).segment(k + 1, m_ - k - 1) * y;
    }
    double pivot = diagonal;
    for (int k = 0; k < m_; ++k) {
      const double y = l[k];
      l[k] = y / d_[k];
      pivot -= y * l[k];
    }
    return pivot;
  }
  void Border(const Eigen::Ref<const Eigen::VectorXd>& col, double diagonal, Eigen::VectorXd& l) {
    const double pivot = Preview(col, diagonal, l);
    L_.row(m_).head(m_) = l.head(m_).transpose();
    L_(m_, m_) = 1.0;
    d_[m_] = pivot;
    ++m_;
  }
  // A + alpha e_j e_j^T.
  void AddToDiagonal(int j, double alpha, Eigen::VectorXd& w) {
    w.segment(j, m_ - j).setZero();
    w[j] = 1.0;
    for (int c = j; c < m_; ++c) {
      const double p = w[c];
      if (p == 0.0) continue;
      const double d_old = d_[c];
      d_[c] = d_old + alpha * p * p;
      const double beta = p * alpha / d_[c];
      alpha *= d_old / d_[c];
      for (int i = c + 1; i < m_; ++i) {
        w[i] -= p * L_(i, c);
        L_(i, c) += beta * w[i];
      }
    }
  }
  // x = A^-1 r (in place).
  void Solve(Eigen::Ref<Eigen::VectorXd> x) const {
    for (int k = 0; k < m_; ++k)
      if (x[k] != 0.0) x.segment(k + 1, m_ - k - 1).noalias() -= L_.col(k).segment(k + 1, m_ - k - 1) * x[k];
    x.head(m_).array() /= d_.head(m_).array();
    for (int k = m_ - 1; k >= 0; --k)
      x[k] -= L_.col(k).segment(k + 1, m_ - k - 1).dot(x.segment(k + 1, m_ - k - 1));
  }

 private:
  Eigen::MatrixXd L_;
  Eigen::VectorXd d_;
  int m_ = 0;
};


// Borders the flexibility of the free nodes 0..t-1 with node t once it is
// released (v = F s_t, phi its flexibility).
void BorderFlexibility(Eigen::MatrixXd& F, const Eigen::VectorXd& v, double phi, int t) {
  F.topLeftCorner(t, t).noalias() += phi * v.head(t) * v.head(t).transpose();
  F.col(t).head(t) = -phi * v.head(t);
  F.row(t).head(t) = -phi * v.head(t).transpose();
  F(t, t) = phi;
}

// One crack length in the flexibility form (1) restricted to the bridged
// nodes z0..t-1 (k of them): Newton on (u_zone, p) with a dense LU, O(k^3).
// F is the flexibility of nodes 0..t-1, Fg = F g, v = F s_t. On success `u`
// (nodes 0..t-1) and `p` hold the solution.
bool SolveZoneDense(const Eigen::MatrixXd& F, const Eigen::VectorXd& Fg, const Eigen::VectorXd& v,
                    double phi, double alpha, double psi, double tip_force, int z0, int t, double h,
                    const laws::BridgingLaw& law, const std::vector<double>& delta_max,
                    double J_tip_c, const ReducedOptions& options, Eigen::VectorXd& u, double& p,
                    int& newton_total) {
  const int k = t - z0;
  auto face_length = [&](int r) { return r == 1 ? 0.5 * h : h; };
  Eigen::VectorXd b(k), db(k);
  Eigen::VectorXd uz = u.segment(z0, k);
  auto evaluate = [&](const Eigen::VectorXd& x_u, double x_p, Eigen::VectorXd* residual,
                      Eigen::MatrixXd* jacobian) {
    for (int i = 0; i < k; ++i) {
      const int r = z0 + i;
      const TractionSlope ts = BridgingTraction(law, 2.0 * x_u[i], delta_max[r]);
      b[i] = face_length(r) * ts.sigma;
      db[i] = 2.0 * face_length(r) * ts.slope;
    }
    const auto F_zz = F.block(z0, z0, k, k);
    const auto F_back = F.row(t - 1).segment(z0, k);
    const double reaction = alpha * x_p + tip_force - v.segment(z0, k).dot(b);
    const double u_back = Fg[t - 1] * x_p - F_back.dot(b);
    const double G = CentredTipEnergy(reaction, phi, u_back, psi, h);
    residual->resize(k + 1);
    residual->head(k).noalias() = x_u - Fg.segment(z0, k) * x_p;
    residual->head(k).noalias() += F_zz * b;
    const double sqrtG = std::sqrt(std::max(G, 1e-300));
    (*residual)[k] = sqrtG / std::sqrt(J_tip_c) - 1.0;
    if (!jacobian) return;
    jacobian->resize(k + 1, k + 1);
    jacobian->topLeftCorner(k, k).noalias() = F_zz * db.asDiagonal();
    jacobian->topLeftCorner(k, k).diagonal().array() += 1.0;
    jacobian->col(k).head(k) = -Fg.segment(z0, k);
    const double scale = 1.0 / (2.0 * sqrtG * std::sqrt(J_tip_c) * h);
    jacobian->row(k).head(k) =
        -scale * (reaction * phi * v.segment(z0, k).transpose() + u_back / psi * F_back)
                     .cwiseProduct(db.transpose());
    (*jacobian)(k, k) = scale * (reaction * phi * alpha + u_back / psi * Fg[t - 1]);
  };
  auto norm = [&](const Eigen::VectorXd& r, const Eigen::VectorXd& x_u) {
    const double u_scale = std::max(x_u.cwiseAbs().maxCoeff(), 1e-12);
    return std::max(r.head(k).cwiseAbs().maxCoeff() / u_scale, std::abs(r[k]));
  };
  Eigen::VectorXd residual, trial_residual, trial_u;
  Eigen::MatrixXd jacobian;
  evaluate(uz, p, &residual, &jacobian);
  double current = norm(residual, uz);
  bool converged = false;
  for (int it = 0; it < options.max_newton_iterations; ++it) {
    ++newton_total;
    if (current < options.tolerance) {
      converged = true;
      break;
    }
    const Eigen::VectorXd step = jacobian.partialPivLu().solve(-residual);
    double lambda = 1.0, trial_p = p, trial = INFINITY;
    for (int ls = 0; ls < 30; ++ls, lambda *= 0.5) {
      trial_u = uz + lambda * step.head(k);
      trial_p = p + lambda * step[k];
      if (!(trial_p > 0.0)) continue;  // the physical root (see GrowBordered)
      evaluate(trial_u, trial_p, &trial_residual, nullptr);
      trial = norm(trial_residual, trial_u);
      if (trial < current * (1.0 - 1e-4 * lambda) || trial < options.tolerance) break;
    }
    uz = trial_u;
    p = trial_p;
    evaluate(uz, p, &residual, &jacobian);
    current = norm(residual, uz);
  }
  if (!converged && current < options.tolerance) converged = true;
  if (!converged) return false;
  evaluate(uz, p, &residual, nullptr);  // tractions b at the solution
  u.head(t).noalias() = Fg.head(t) * p - F.block(0, z0, t, k) * b;
  return true;
}

// Growth with the stiffness form of (1): S_ff u + b(u) = g p, solved by
// (chord) Newton on (u, p) with the LDL^T factor of S_ff + diag(b') kept
// across crack lengths (bordering, rank-one updates where a slope changed),
// O(t^2) per crack length instead of a dense O(k^3) factorization.
void GrowBordered(const CrackPlaneModel& m, const laws::BridgingLaw* law, double J_tip_c,
                  const ReducedOptions& options, SimulationResult& result, int& newton_total) {
  const int n = m.size();
  const double h = m.resolution;
  const Eigen::Map<const Eigen::MatrixXd> S(m.stiffness.data(), n, n);
  const Eigen::Map<const Eigen::VectorXd> g(m.load.data(), n);
  auto face_length = [&](int r) { return r == 1 ? 0.5 * h : h; };
  const double tip_traction = law ? law->Traction(0.0) : 0.0;
  std::vector<double> delta_max(n, 0.0);
  std::vector<char> broken(n, 0);
  GrowingLdlt elastic(n), tangent(n);
  Eigen::VectorXd slope = Eigen::VectorXd::Zero(n);  // b' held in `tangent`
  Eigen::VectorXd work(n), work2(n);
  elastic.Border(S.col(0), S(0, 0), work);
  tangent.Border(S.col(0), S(0, 0), work);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n), b(n), db(n), r_u(n), a(n), x1(n), x2(n);
  Eigen::VectorXd trial_u(n), trial_r(n), trial_a(n);
  double p = 0.0;
  const double force_scale = S.diagonal().cwiseAbs().maxCoeff();
  // The flexibility of the free nodes too (bordering, O(t^2) per crack length)
  // for crack lengths whose bridged zone is short: there the dense zone solve
  // (O(k^3)) is cheaper than O(t^2) iterations on all free nodes.
  Eigen::MatrixXd F = Eigen::MatrixXd::Zero(n, n);
  F(0, 0) = 1.0 / S(0, 0);
  Eigen::VectorXd v(n), Fg(n);
  Progress progress("reduced model", static_cast<size_t>(n - 1), options.progress);

  for (int t = 1; t < n; ++t) {
    const Eigen::Ref<const Eigen::VectorXd> s_t = S.col(t).head(t);
    const double phi = 1.0 / elastic.Preview(S.col(t), S(t, t), work);
    const double psi = 1.0 / elastic.pivot(t - 1);
    const double tip_force = law ? tip_traction * face_length(t) : 0.0;
    int z0 = 1;
    while (z0 < t && broken[z0]) ++z0;

    // Slopes b'_j at the current state; refresh the factor where they moved.
    auto slopes = [&](const Eigen::VectorXd& x_u) {
      b.head(t).setZero();
      db.head(t).setZero();
      if (!law) return;
      for (int r = z0; r < t; ++r) {
        const TractionSlope ts = BridgingTraction(*law, 2.0 * x_u[r], delta_max[r]);
        b[r] = face_length(r) * ts.sigma;
        db[r] = 2.0 * face_length(r) * ts.slope;
      }
    };
    auto refresh = [&](double tolerance) {
      bool changed = false;
      for (int r = 1; r < t; ++r) {
        const double target = (law && r >= z0) ? db[r] : 0.0;
        if (std::abs(target - slope[r]) > tolerance * S(r, r)) {
          tangent.AddToDiagonal(r, target - slope[r], work2);
          slope[r] = target;
          changed = true;
        }
      }
      return changed;
    };
    // Residuals: r_u = S u + b - g p (force), r_G = sqrt(J_tip / J_c) - 1, and
    // the gradient a = d r_G / d u, e = d r_G / d p.
    double reaction = 0.0, G = 0.0, e = 0.0, r_G = 0.0;
    auto evaluate = [&](const Eigen::VectorXd& x_u, double x_p, Eigen::VectorXd& ru,
                        Eigen::VectorXd& grad, double& rg, double& de) {
      slopes(x_u);
      ru.head(t).noalias() = S.topLeftCorner(t, t).selfadjointView<Eigen::Lower>() * x_u.head(t);
      ru.head(t) += b.head(t) - g.head(t) * x_p;
      reaction = s_t.dot(x_u.head(t)) - g[t] * x_p + tip_force;
      G = CentredTipEnergy(reaction, phi, x_u[t - 1], psi, h);
      const double sqrtG = std::sqrt(std::max(G, 1e-300));
      rg = sqrtG / std::sqrt(J_tip_c) - 1.0;
      const double scale = 1.0 / (2.0 * sqrtG * std::sqrt(J_tip_c) * h);
      grad.head(t) = (scale * reaction * phi) * s_t;
      grad[t - 1] += scale * x_u[t - 1] / psi;
      de = -scale * reaction * phi * g[t];
    };
    auto norm = [&](const Eigen::VectorXd& ru, const Eigen::VectorXd& x_u, double rg) {
      const double u_scale = std::max(x_u.head(t).cwiseAbs().maxCoeff(), 1e-12);
      return std::max(ru.head(t).cwiseAbs().maxCoeff() / (force_scale * u_scale), std::abs(rg));
    };

    v.head(t).noalias() = F.topLeftCorner(t, t) * s_t;
    const int zone_size = law ? t - z0 : 0;
    const bool dense_zone = options.solver == ReducedOptions::Solver::kHybrid && zone_size > 0 &&
                            p > 0.0 && std::pow(zone_size, 3) < 6.0 * t * t;
    bool converged = false;
    if (dense_zone) {
      Fg.head(t).noalias() = F.topLeftCorner(t, t) * g.head(t);
      const double alpha = v.head(t).dot(g.head(t)) - g[t];
      converged = SolveZoneDense(F, Fg, v, phi, alpha, F(t - 1, t - 1), tip_force, z0, t, h, *law,
                                 delta_max, J_tip_c, options, u, p, newton_total);
    } else if (!law) {
      // Linear in p: u = p S^-1 g, J_tip quadratic in p.
      x2.head(t) = g.head(t);
      tangent.Solve(x2.head(t));
      const double R1 = s_t.dot(x2.head(t)) - g[t];
      const double A = R1 * R1 * phi + x2[t - 1] * x2[t - 1] / psi;
      p = std::sqrt(2.0 * h * J_tip_c / A);
      u.head(t) = p * x2.head(t);
      converged = std::isfinite(p);
    } else {
      if (t == 1) p = 0.0;
      if (p <= 0.0) {
        // First step: the unbridged LEFM load.
        x2.head(t) = g.head(t);
        elastic.Solve(x2.head(t));
        const double R1 = s_t.dot(x2.head(t)) - g[t];
        p = std::sqrt(2.0 * h * J_tip_c / (R1 * R1 * phi + x2[t - 1] * x2[t - 1] / psi));
        // The openings of that load (issue 17): from u = 0 the residual is
        // all load, and on a coarse DCB mesh the first Newton step crossed
        // to the root with p < 0 (sqrt(J_tip) = sqrt(J_tip,c) at a negative
        // load), "Newton did not converge at crack length a0".
        u.head(t) = p * x2.head(t);
      }
      slopes(u);
      refresh(1e-9);
      x2.head(t) = g.head(t);
      tangent.Solve(x2.head(t));
      evaluate(u, p, r_u, a, r_G, e);
      double current = norm(r_u, u, r_G);
      double previous = INFINITY;
      for (int it = 0; it < options.max_newton_iterations; ++it) {
        ++newton_total;
        if (current < options.tolerance) {
          converged = true;
          break;
        }
        if (current > 0.25 * previous && refresh(1e-9)) {
          x2.head(t) = g.head(t);
          tangent.Solve(x2.head(t));
        }
        previous = current;
        // [K -g; a^T e] [du; dp] = -[r_u; r_G] by block elimination.
        x1.head(t) = r_u.head(t);
        tangent.Solve(x1.head(t));
        const double dp = (-r_G + a.head(t).dot(x1.head(t))) / (a.head(t).dot(x2.head(t)) + e);
        double lambda = 1.0, trial = INFINITY, trial_p = p, trial_rg = 0.0, trial_e = 0.0;
        for (int ls = 0; ls < 30; ++ls, lambda *= 0.5) {
          trial_u.head(t) = u.head(t) + lambda * (x2.head(t) * dp - x1.head(t));
          trial_p = p + lambda * dp;
          // The load stays positive: sqrt(J_tip) = sqrt(J_tip,c) has a root
          // at p < 0 too, which a full step can reach on a coarse mesh.
          if (!(trial_p > 0.0)) continue;
          evaluate(trial_u, trial_p, trial_r, trial_a, trial_rg, trial_e);
          trial = norm(trial_r, trial_u, trial_rg);
          if (trial < current * (1.0 - 1e-4 * lambda) || trial < options.tolerance) break;
        }
        u.head(t) = trial_u.head(t);
        p = trial_p;
        r_u.head(t) = trial_r.head(t);
        a.head(t) = trial_a.head(t);
        r_G = trial_rg;
        e = trial_e;
        current = trial;
      }
      if (!converged && current < options.tolerance) converged = true;
    }
    if (!converged || !(p > 0.0)) {
      result.status = RunStatus::kNotConverged;
      result.message = fmt::format("Newton did not converge at crack length {:.6g} mm",
                                   m.CrackLength(t) * 1e3);
      break;
    }
    slopes(u);
    const double R_t = s_t.dot(u.head(t)) - g[t] * p + tip_force;
    const double J_tip = CentredTipEnergy(R_t, phi, u[t - 1], psi, h);
    RecordPoint(m, law, J_tip_c, t, u, p, J_tip, delta_max, broken, result);
    progress.Update(static_cast<size_t>(t));

    if (t + 1 < n) {
      BorderFlexibility(F, v, phi, t);
      elastic.Border(S.col(t), S(t, t), work);
      // Node t joins shut; its slope is the envelope's at zero opening.
      double slope_t = 0.0;
      if (law) slope_t = 2.0 * face_length(t) * BridgingTraction(*law, 0.0, 0.0).slope;
      tangent.Border(S.col(t), S(t, t) + slope_t, work);
      slope[t] = slope_t;
      u[t] = 0.0;
    }
  }
  progress.Finish();
}

}  // namespace bridgefit::models::reduced_internal
