#include "bridgefit/inverse/forward_model.hpp"

#include <algorithm>
#include <cmath>

#include "bridgefit/core/error.hpp"
#include "bridgefit/laws/rcurve_theory.hpp"

namespace bridgefit::inverse {

const char* RKindName(RKind kind) {
  return kind == RKind::kEnergy ? "energy" : "elastic-zone";
}

RKind ParseRKind(const std::string& name) {
  if (name == "energy") return RKind::kEnergy;
  if (name == "elastic-zone") return RKind::kElasticZone;
  throw Error(ErrorKind::kUsage, "unknown R kind",
              {.field = "--r-kind", .value = name, .expected = "energy or elastic-zone"});
}

AnalyticForwardModel::AnalyticForwardModel(double effective_modulus, double initial_crack_length)
    : modulus_(effective_modulus), a0_(initial_crack_length) {
  BF_CHECK_INPUT(effective_modulus > 0.0, "the analytic model needs a positive modulus");
  BF_CHECK_INPUT(initial_crack_length > 0.0, "the analytic model needs a positive a0");
}

ForwardPrediction AnalyticForwardModel::Predict(const laws::LawShape& shape,
                                                const LawParameters& p,
                                                const std::vector<double>& crack_lengths,
                                                RKind /*kind: the same R here*/) const {
  ForwardPrediction out;
  if (!(p.J_tip_c > 0.0) || !(p.sigma_c > 0.0) || !(p.J_B >= 0.0)) {
    out.status = RunStatus::kInvalidInput;
    out.message = "parameters out of range";
    return out;
  }
  const bool bridged = p.J_B > 0.0;
  const double delta_c = bridged ? p.J_B / (shape.Area() * p.sigma_c) : 0.0;
  const laws::BridgingLaw law{&shape, p.sigma_c, bridged ? delta_c : 1.0};
  for (double a : crack_lengths) {
    const double growth = a - a0_;
    if (!bridged) {
      out.R.push_back(p.J_tip_c);
      out.delta_root.push_back(growth > 0 ? std::sqrt(32.0 * p.J_tip_c * growth / (M_PI * modulus_)) : 0.0);
      continue;
    }
    const double delta = AnalyticDeltaRoot(law, p.J_tip_c, growth, modulus_);
    out.delta_root.push_back(delta);
    out.R.push_back(laws::ElasticZoneR(law, delta, p.J_tip_c));
  }
  if (bridged) {
    // delta_root = delta_c when 32 (J_tip,c + J_B) growth / (pi E') = delta_c^2.
    const double growth_ss = M_PI * modulus_ * delta_c * delta_c / (32.0 * (p.J_tip_c + p.J_B));
    out.steady_state_crack_length = a0_ + growth_ss;
    out.steady_state_reached =
        !crack_lengths.empty() &&
        out.steady_state_crack_length <= *std::max_element(crack_lengths.begin(), crack_lengths.end());
  }
  return out;
}

SimulationForwardModel::SimulationForwardModel(std::string name, Simulator simulate)
    : name_(std::move(name)), simulate_(std::move(simulate)) {}

ForwardPrediction SimulationForwardModel::Predict(const laws::LawShape& shape,
                                                  const LawParameters& p,
                                                  const std::vector<double>& crack_lengths,
                                                  RKind kind) const {
  ForwardPrediction out;
  if (!(p.J_tip_c > 0.0) || !(p.sigma_c > 0.0) || !(p.J_B >= 0.0)) {
    out.status = RunStatus::kInvalidInput;
    out.message = "parameters out of range";
    return out;
  }
  SimulationResult result;
  try {
    if (p.J_B > 0.0) {
      const laws::BridgingLaw law{&shape, p.sigma_c, p.J_B / (shape.Area() * p.sigma_c)};
      result = simulate_(&law, p.J_tip_c);
    } else {
      result = simulate_(nullptr, p.J_tip_c);
    }
  } catch (const std::exception& e) {
    out.status = RunStatus::kFailed;
    out.message = e.what();
    return out;
  }
  if (result.status != RunStatus::kOk) {
    out.status = result.status;
    out.message = result.message;
    return out;
  }
  // Usable points: finite R of the requested kind.
  std::vector<double> a, r, d;
  for (const SimulationPoint& point : result.points) {
    const double value = kind == RKind::kEnergy ? point.R_energy : point.R;
    if (!std::isfinite(value) || !std::isfinite(point.crack_length)) continue;
    a.push_back(point.crack_length);
    r.push_back(value);
    d.push_back(point.delta_root);
  }
  if (a.size() < 2) {
    out.status = RunStatus::kFailed;
    out.message = "the simulation returned fewer than two usable points";
    return out;
  }
  for (double x : crack_lengths) {
    if (x < a.front() - 1e-9 || x > a.back() + 1e-9) {
      out.status = RunStatus::kFailed;
      out.message = "a data point lies outside the simulated crack lengths";
      out.R.clear();
      out.delta_root.clear();
      return out;
    }
    const size_t hi = std::min<size_t>(
        a.size() - 1, std::max<size_t>(1, std::lower_bound(a.begin(), a.end(), x) - a.begin()));
    const size_t lo = hi - 1;
    const double t = a[hi] > a[lo] ? (x - a[lo]) / (a[hi] - a[lo]) : 0.0;
    out.R.push_back(r[lo] + t * (r[hi] - r[lo]));
    out.delta_root.push_back(d[lo] + t * (d[hi] - d[lo]));
  }
  out.steady_state_reached = result.steady_state_reached;
  out.steady_state_crack_length = result.steady_state_crack_length;
  if (out.steady_state_reached && !crack_lengths.empty())
    out.steady_state_reached = result.steady_state_crack_length <=
                               *std::max_element(crack_lengths.begin(), crack_lengths.end());
  return out;
}

}  // namespace bridgefit::inverse
