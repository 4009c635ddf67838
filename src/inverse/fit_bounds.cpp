// The uncertainty of the PHYSICS 7 truncation bounds (fit_impl.hpp).
#include <cmath>

#include "fit_impl.hpp"

namespace bridgefit::inverse::fit_internal {

double BridgingRise(const Objective& objective, const std::vector<double>& p,
                    const ForwardPrediction& prediction, std::size_t last) {
  if (prediction.R_physical.empty() && objective.data().kind == RKind::kEnergy) {
    if (last >= prediction.delta_root.size() || !(p[kSigmaC] > 0.0) || !(p[kJB] > 0.0)) return 0.0;
    const laws::LawShape& shape = objective.shape();
    const laws::BridgingLaw law{&shape, p[kSigmaC], p[kJB] / (shape.Area() * p[kSigmaC])};
    return law.Work(std::min(prediction.delta_root[last], law.delta_c));
  }
  const std::vector<double>& R = prediction.R_physical.empty() ? prediction.R : prediction.R_physical;
  return last < R.size() ? R[last] - p[kJTipC] : NAN;
}

namespace {

// g_J = PHYSICS 7's R_max - J_tip,c (BridgingRise) and g_d =
// delta_root(a_last) at parameters p; false when the run fails.
bool BoundQuantities(const Objective& objective, const std::vector<double>& p, std::size_t last,
                     double* g_J, double* g_d) {
  std::vector<double> r(objective.data().size());
  ForwardPrediction prediction;
  if (!objective.Residuals(p, r.data(), &prediction)) return false;
  if (last >= prediction.delta_root.size()) return false;
  *g_J = BridgingRise(objective, p, prediction, last);
  *g_d = prediction.delta_root[last];
  return std::isfinite(*g_J);
}

}  // namespace

void ProfileBoundMinimum(const Objective& objective, const std::vector<Profile>& profiles,
                         double best_chi2, double threshold, std::size_t last,
                         BoundUncertainty* out) {
  for (const Profile& profile : profiles)
    for (const ProfilePoint& point : profile.points) {
      if (!point.ok || point.chi2 - best_chi2 > threshold) continue;
      double g_J, g_d;
      const std::vector<double> p(point.parameters.begin(), point.parameters.end());
      if (!BoundQuantities(objective, p, last, &g_J, &g_d)) continue;
      out->J_B_profile_min = std::fmin(out->J_B_profile_min, g_J);
      out->delta_c_profile_min = std::fmin(out->delta_c_profile_min, g_d);
    }
}

BoundUncertainty TruncationBoundUncertainty(const Objective& objective,
                                            const std::vector<double>& full,
                                            const Eigen::MatrixXd& covariance, std::size_t last) {
  BoundUncertainty out;
  const std::vector<int>& free = objective.free();
  const int n = static_cast<int>(free.size());
  if (n == 0 || covariance.rows() != n || !covariance.allFinite()) return out;
  auto at = [&](const std::vector<double>& p, double* g_J, double* g_d) {
    return BoundQuantities(objective, p, last, g_J, g_d);
  };
  Eigen::VectorXd grad_J(n), grad_d(n);
  for (int k = 0; k < n; ++k) {
    const int j = free[k];
    const double h = 1e-4 * std::max(std::abs(full[j]), 1e-12);
    std::vector<double> plus = full, minus = full;
    plus[j] += h;
    minus[j] -= h;
    double J_plus, d_plus, J_minus, d_minus;
    if (!at(plus, &J_plus, &d_plus) || !at(minus, &J_minus, &d_minus)) return out;
    grad_J(k) = (J_plus - J_minus) / (2 * h);
    grad_d(k) = (d_plus - d_minus) / (2 * h);
  }
  out.J_B_sd = std::sqrt(std::max(0.0, grad_J.dot(covariance * grad_J)));
  out.delta_c_sd = std::sqrt(std::max(0.0, grad_d.dot(covariance * grad_d)));
  return out;
}

}  // namespace bridgefit::inverse::fit_internal
