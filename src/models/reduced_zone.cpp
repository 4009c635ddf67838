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
  if (delta >= delta_max && law.shape->family == laws::LawFamily::kLinear) {
    // The dual-number path below for s(d) = 1 - d, the same operations
    // without the dual arithmetic (a fit's default law; called per node and
    // trial).
    const double d = delta / law.delta_c;
    if (d < 0.0 || d >= 1.0) return {0.0, 0.0};
    return {law.sigma_c * (1.0 - d), law.sigma_c * (0.0 - 1.0 / law.delta_c)};
  }
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

double GrowingLdlt::Preview(const Eigen::Ref<const Eigen::VectorXd>& col, double diagonal,
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

void GrowingLdlt::Border(const Eigen::Ref<const Eigen::VectorXd>& col, double diagonal,
                         Eigen::VectorXd& l) {
  const double pivot = Preview(col, diagonal, l);
  L_.row(m_).head(m_) = l.head(m_).transpose();
  L_(m_, m_) = 1.0;
  d_[m_] = pivot;
  ++m_;
}

void GrowingLdlt::AddToDiagonal(int j, double alpha, Eigen::VectorXd& w) {
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

void GrowingLdlt::SolveLeading(Eigen::Ref<Eigen::VectorXd> x, int m) const {
  ForwardLeading(x, m);
  ScaleBackLeading(x, m);
}

void GrowingLdlt::ForwardLeading(Eigen::Ref<Eigen::VectorXd> x, int m) const {
  for (int k = 0; k < m; ++k)
    if (x[k] != 0.0) x.segment(k + 1, m - k - 1).noalias() -= L_.col(k).segment(k + 1, m - k - 1) * x[k];
}

void GrowingLdlt::ScaleBackLeading(Eigen::Ref<Eigen::VectorXd> x, int m) const {
  x.head(m).array() /= d_.head(m).array();
  BackLeading(x, m);
}

void GrowingLdlt::BackLeading(Eigen::Ref<Eigen::VectorXd> x, int m) const {
  for (int k = m - 1; k >= 0; --k)
    x[k] -= L_.col(k).segment(k + 1, m - k - 1).dot(x.segment(k + 1, m - k - 1));
}

ElasticTables::ElasticTables(const CrackPlaneModel& m) : factor(m.size()) {
  const int n = m.size();
  const Eigen::Map<const Eigen::MatrixXd> S(m.stiffness.data(), n, n);
  const Eigen::Map<const Eigen::VectorXd> g(m.load.data(), n);
  Eigen::VectorXd work(n);
  for (int t = 0; t < n; ++t) factor.Border(S.col(t), S(t, t), work);
  Linv = factor.L().triangularView<Eigen::UnitLower>().solve(Eigen::MatrixXd::Identity(n, n));
  Linv.triangularView<Eigen::StrictlyUpper>().setZero();
  y = Linv * g;
}

void ZoneSystem::FromFlexibility(const Eigen::MatrixXd& F, const Eigen::VectorXd& Fg,
                                 const Eigen::VectorXd& v) {
  const int k = t - z0;
  F_zz = F.block(z0, z0, k, k);
  F_back = F.row(t - 1).segment(z0, k).transpose();
  Fg_z = Fg.segment(z0, k);
  Fg_back = Fg[t - 1];
  v_z = v.segment(z0, k);
}

void ZoneSystem::FromTables(const ElasticTables& tables) {
  const int k = t - z0;
  const auto W = tables.Linv.block(z0, z0, k, k);  // lower triangular
  Eigen::VectorXd d_inv(k);
  for (int i = 0; i < k; ++i) d_inv[i] = 1.0 / tables.factor.pivot(z0 + i);
  // F_zz = W^T D^-1 W (rows s < z0 of Linv vanish on the zone's columns).
  const Eigen::MatrixXd scaled = d_inv.asDiagonal() * W;
  F_zz.noalias() = W.transpose() * scaled;
  F_back = W.row(k - 1).transpose() * d_inv[k - 1];
  Fg_z.noalias() = W.transpose() * d_inv.cwiseProduct(tables.y.segment(z0, k));
  Fg_back = Fg_z[k - 1];
  v_z = -tables.Linv.row(t).segment(z0, k).transpose();
  phi = 1.0 / tables.factor.pivot(t);
  psi = 1.0 / tables.factor.pivot(t - 1);
  alpha = -tables.y[t];
}

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
bool SolveZoneDense(const ZoneSystem& zone, double h, const laws::BridgingLaw& law,
                    const std::vector<double>& delta_max, double J_tip_c,
                    const ReducedOptions& options, Eigen::VectorXd& uz, double& p,
                    Eigen::VectorXd& b, int& newton_total) {
  const int z0 = zone.z0;
  const int k = zone.t - z0;
  const double phi = zone.phi, psi = zone.psi, alpha = zone.alpha;
  auto face_length = [&](int r) { return r == 1 ? 0.5 * h : h; };
  b.resize(k);
  Eigen::VectorXd db(k);
  auto evaluate = [&](const Eigen::VectorXd& x_u, double x_p, Eigen::VectorXd* residual,
                      Eigen::MatrixXd* jacobian) {
    for (int i = 0; i < k; ++i) {
      const int r = z0 + i;
      const TractionSlope ts = BridgingTraction(law, 2.0 * x_u[i], delta_max[r]);
      b[i] = face_length(r) * ts.sigma;
      db[i] = 2.0 * face_length(r) * ts.slope;
    }
    const double reaction = alpha * x_p + zone.tip_force - zone.v_z.dot(b);
    const double u_back = zone.Fg_back * x_p - zone.F_back.dot(b);
    const double G = CentredTipEnergy(reaction, phi, u_back, psi, h);
    residual->resize(k + 1);
    residual->head(k).noalias() = x_u - zone.Fg_z * x_p;
    residual->head(k).noalias() += zone.F_zz * b;
    const double sqrtG = std::sqrt(std::max(G, 1e-300));
    (*residual)[k] = sqrtG / std::sqrt(J_tip_c) - 1.0;
    if (!jacobian) return;
    jacobian->resize(k + 1, k + 1);
    jacobian->topLeftCorner(k, k).noalias() = zone.F_zz * db.asDiagonal();
    jacobian->topLeftCorner(k, k).diagonal().array() += 1.0;
    jacobian->col(k).head(k) = -zone.Fg_z;
    const double scale = 1.0 / (2.0 * sqrtG * std::sqrt(J_tip_c) * h);
    jacobian->row(k).head(k) =
        -scale * (reaction * phi * zone.v_z.transpose() + u_back / psi * zone.F_back.transpose())
                     .cwiseProduct(db.transpose());
    (*jacobian)(k, k) = scale * (reaction * phi * alpha + u_back / psi * zone.Fg_back);
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
      if (!(trial_p > 0.0)) continue;  // the physical root (see SolveChordNewton)
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
  return true;
}

}  // namespace bridgefit::models::reduced_internal
