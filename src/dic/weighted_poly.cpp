// Weighted polynomial fit with a sandwich covariance (weighted_poly_impl.hpp).
#include "weighted_poly_impl.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace bridgefit::dic::detail {

WeightedPoly FitWeightedPoly(const std::vector<double>& x, const std::vector<double>& y,
                             const std::vector<double>& w, int degree, double inflation) {
  WeightedPoly out;
  const int p = degree + 1;
  double sw = 0, swx = 0;
  for (size_t i = 0; i < x.size(); ++i)
    if (w[i] > 0) {
      sw += w[i];
      swx += w[i] * x[i];
      ++out.points;
    }
  // Points correlated in blocks of `inflation` carry points / inflation
  // independent ones: no more unknowns than that can be resolved.
  const double infl = std::max(1.0, inflation);
  const double n_eff = out.points / infl;
  if (n_eff <= p || !(sw > 0)) return out;
  out.x_ref = swx / sw;
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(p, p);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(p);
  auto row = [&](double xi) {
    Eigen::VectorXd r(p);
    double t = 1;
    for (int j = 0; j < p; ++j, t *= xi - out.x_ref) r(j) = t;
    return r;
  };
  for (size_t i = 0; i < x.size(); ++i) {
    if (!(w[i] > 0)) continue;
    const Eigen::VectorXd r = row(x[i]);
    B += w[i] * r * r.transpose();
    rhs += w[i] * y[i] * r;
  }
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(B);
  if (!lu.isInvertible()) return out;
  const Eigen::VectorXd c = lu.solve(rhs);
  const Eigen::MatrixXd Binv = lu.inverse();
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(p, p);
  for (size_t i = 0; i < x.size(); ++i) {
    if (!(w[i] > 0)) continue;
    const Eigen::VectorXd r = row(x[i]);
    // HC3: a residual understates its point's error by 1 - leverage.
    const double leverage = w[i] * r.dot(Binv * r);
    if (!(leverage < 1.0 - 1e-9)) return out;  // the point alone decides the fit
    const double e = w[i] * (y[i] - r.dot(c)) / (1.0 - leverage);
    M += e * e * r * r.transpose();
  }
  const Eigen::MatrixXd cov = infl * Binv * M * Binv;
  out.c.assign(c.data(), c.data() + p);
  out.cov.resize(static_cast<size_t>(p * p));
  for (int i = 0; i < p; ++i)
    for (int j = 0; j < p; ++j) out.cov[static_cast<size_t>(i * p + j)] = cov(i, j);
  out.ok = std::all_of(out.c.begin(), out.c.end(), [](double v) { return std::isfinite(v); });
  return out;
}

double WeightedPoly::Value(double x) const {
  double v = 0, t = 1;
  for (double cj : c) {
    v += cj * t;
    t *= x - x_ref;
  }
  return v;
}

double WeightedPoly::Se(double x) const {
  const size_t p = c.size();
  std::vector<double> r(p);
  double t = 1;
  for (size_t j = 0; j < p; ++j, t *= x - x_ref) r[j] = t;
  double var = 0;
  for (size_t i = 0; i < p; ++i)
    for (size_t j = 0; j < p; ++j) var += r[i] * cov[i * p + j] * r[j];
  return std::sqrt(std::max(var, 0.0));
}

double WeightedPoly::CoefSe(int j) const {
  const size_t p = c.size();
  return std::sqrt(std::max(cov[static_cast<size_t>(j) * p + static_cast<size_t>(j)], 0.0));
}

}  // namespace bridgefit::dic::detail
