#include "bridgefit/inverse/joint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "bridgefit/core/error.hpp"
#include "brent.hpp"

namespace bridgefit::inverse {

JointForwardModel::JointForwardModel(std::vector<const ForwardModel*> models,
                                     std::vector<std::size_t> counts, std::vector<double> offsets)
    : models_(std::move(models)), counts_(std::move(counts)), offsets_(std::move(offsets)) {
  BF_CHECK_INPUT(!models_.empty() && models_.size() == counts_.size() &&
                     offsets_.size() == counts_.size(),
                 fmt::format("{} models for {} data blocks", models_.size(), counts_.size()),
                 {.field = "joint fit"});
  for (const ForwardModel* m : models_)
    BF_CHECK_INPUT(m != nullptr, "a joint fit needs a model per specimen", {.field = "joint fit"});
}

std::string JointForwardModel::Name() const {
  return fmt::format("joint ({} x {})", models_.size(), models_.front()->Name());
}

ForwardPrediction JointForwardModel::Predict(const laws::LawShape& shape, const LawParameters& p,
                                             const std::vector<double>& crack_lengths,
                                             RKind kind) const {
  return Joined(shape, p, crack_lengths, kind, false);
}

ForwardPrediction JointForwardModel::PredictLoad(const laws::LawShape& shape,
                                                 const LawParameters& p,
                                                 const std::vector<double>& displacements) const {
  return Joined(shape, p, displacements, RKind::kEnergy, true);
}

ForwardPrediction JointForwardModel::Joined(const laws::LawShape& shape, const LawParameters& p,
                                            const std::vector<double>& axis, RKind kind,
                                            bool load) const {
  ForwardPrediction out;
  const std::size_t total = std::accumulate(counts_.begin(), counts_.end(), std::size_t{0});
  if (axis.size() != total) {
    out.status = RunStatus::kFailed;
    out.message = fmt::format("joint model: {} {} for blocks of {} in all", axis.size(),
                              load ? "displacements" : "crack lengths", total);
    return out;
  }
  std::size_t at = 0;
  for (std::size_t k = 0; k < models_.size(); ++k) {
    std::vector<double> block(axis.begin() + at, axis.begin() + at + counts_[k]);
    at += counts_[k];
    if (!load)
      for (double& a : block) a -= offsets_[k];
    const ForwardPrediction part =
        load ? models_[k]->PredictLoad(shape, p, block) : models_[k]->Predict(shape, p, block, kind);
    const std::size_t got = load ? part.load.size() : part.R.size();
    if (!part.ok() || got != block.size()) {
      out.status = part.ok() ? RunStatus::kFailed : part.status;
      out.message = fmt::format("specimen {}: {}", k + 1, part.message);
      return out;
    }
    // A load prediction always carries the physical crack length and R.
    const std::vector<double>& physical =
        part.crack_length_physical.empty() ? block : part.crack_length_physical;
    const std::vector<double>& R_physical = part.R_physical.empty() ? part.R : part.R_physical;
    out.R.insert(out.R.end(), part.R.begin(), part.R.end());
    out.load.insert(out.load.end(), part.load.begin(), part.load.end());
    out.delta_root.insert(out.delta_root.end(), part.delta_root.begin(), part.delta_root.end());
    out.crack_length_physical.insert(out.crack_length_physical.end(), physical.begin(), physical.end());
    out.R_physical.insert(out.R_physical.end(), R_physical.begin(), R_physical.end());
    for (double a : physical)
      out.past_steady_state.push_back(part.steady_state_reached && a >= part.steady_state_crack_length);
    out.steady_state_reached = out.steady_state_reached || part.steady_state_reached;
  }
  return out;
}

ModulusProfiledLoadModel::ModulusProfiledLoadModel(const SimulationForwardModel& base,
                                                   double series_compliance, FitData rows,
                                                   double span)
    : base_(base), series_compliance_(series_compliance), rows_(std::move(rows)), span_(span) {
  BF_CHECK_INPUT(rows_.target == FitTarget::kLoad && !rows_.load.empty(),
                 "a profiled modulus scale needs the specimen's load-displacement rows",
                 {.field = "joint fit"});
  BF_CHECK_INPUT(span_ > 0.0 && span_ < 0.5, "the modulus scale's span must lie in (0, 0.5)",
                 {.field = "joint fit", .value = fmt::format("{}", span_)});
}

ForwardPrediction ModulusProfiledLoadModel::Predict(const laws::LawShape&, const LawParameters&,
                                                    const std::vector<double>&, RKind) const {
  ForwardPrediction out;
  out.status = RunStatus::kInvalidInput;
  out.message = "a model with a profiled modulus scale predicts its load-displacement record only";
  return out;
}

ForwardPrediction ModulusProfiledLoadModel::PredictLoadAtScale(
    const laws::LawShape& shape, const LawParameters& p, const std::vector<double>& displacements,
    double g) const {
  std::vector<double> scaled = displacements;
  for (double& d : scaled) d *= g;
  ForwardPrediction out = base_.PredictLoadInSeries(
      shape, {p.sigma_c, g * p.J_B, g * p.J_tip_c}, scaled, g * series_compliance_);
  for (double& r : out.R_physical) r /= g;
  for (double& r : out.R) r /= g;
  for (double& d : out.delta_root) d /= g;
  return out;
}

double ModulusProfiledLoadModel::ProfiledScale(const laws::LawShape& shape,
                                               const LawParameters& p) const {
  const bool weighted = rows_.weighted();
  const auto chi2 = [&](double log_g) {
    const ForwardPrediction q = PredictLoadAtScale(shape, p, rows_.displacement, std::exp(log_g));
    if (!q.ok() || q.load.size() != rows_.load.size()) return static_cast<double>(INFINITY);
    double sum = 0.0;
    for (std::size_t i = 0; i < q.load.size(); ++i)
      sum += std::pow((q.load[i] - rows_.load[i]) / (weighted ? rows_.load_uncertainty[i] : 1.0), 2);
    return sum;
  };
  // Brent's minimiser on ln g in [-span, span] (chi^2 is near-quadratic in
  // ln g, so ~8-12 runs where golden section alone took 21), from g = 1 (the
  // specimen's own calibrated factor), to 1e-5 in ln g.
  const detail::BrentMinimum best = detail::BrentMinimize(chi2, -span_, span_, 0.0, 2.5e-6);
  if (!std::isfinite(best.f)) return NAN;
  return std::exp(best.x);
}

ForwardPrediction ModulusProfiledLoadModel::PredictLoad(
    const laws::LawShape& shape, const LawParameters& p,
    const std::vector<double>& displacements) const {
  ForwardPrediction out;
  if (displacements != rows_.displacement) {
    out.status = RunStatus::kInvalidInput;
    out.message = "a profiled modulus scale is fitted to the specimen's own rows only";
    return out;
  }
  const double g = ProfiledScale(shape, p);
  if (!std::isfinite(g)) {
    out.status = RunStatus::kFailed;
    out.message = fmt::format("no modulus scale within +-{:g}% gave a valid run", span_ * 100);
    return out;
  }
  return PredictLoadAtScale(shape, p, displacements, g);
}

FitData JoinFitData(const std::vector<FitData>& parts, std::vector<double>* offsets) {
  BF_CHECK_INPUT(!parts.empty(), "a joint fit needs at least one specimen", {.field = "joint fit"});
  FitData joined;
  joined.kind = parts.front().kind;
  joined.target = parts.front().target;
  const bool load = joined.target == FitTarget::kLoad;
  bool all_weighted = true;
  for (const FitData& d : parts) {
    BF_CHECK_INPUT(d.target == joined.target,
                   "the specimens were fitted to different data (a joint fit compares like with "
                   "like: every specimen's R curve, or every specimen's load-displacement record)",
                   {.field = "fit_to", .value = FitTargetName(d.target),
                    .expected = FitTargetName(joined.target)});
    if (!load)
      BF_CHECK_INPUT(d.kind == joined.kind, "the specimens' R curves are of different kinds",
                     {.field = "r_kind", .value = RKindName(d.kind),
                      .expected = RKindName(joined.kind)});
    all_weighted = all_weighted && d.weighted() && d.size() > 0;
  }
  offsets->clear();
  for (const FitData& d : parts) {
    if (load) {
      offsets->push_back(0.0);
      joined.displacement.insert(joined.displacement.end(), d.displacement.begin(),
                                 d.displacement.end());
      joined.load.insert(joined.load.end(), d.load.begin(), d.load.end());
      if (all_weighted)
        joined.load_uncertainty.insert(joined.load_uncertainty.end(), d.load_uncertainty.begin(),
                                       d.load_uncertainty.end());
      continue;
    }
    const double offset =
        joined.crack_length.empty() || d.crack_length.empty()
            ? 0.0
            : std::max(0.0, joined.crack_length.back() + 1e-3 - d.crack_length.front());
    offsets->push_back(offset);
    for (double a : d.crack_length) joined.crack_length.push_back(a + offset);
    joined.R.insert(joined.R.end(), d.R.begin(), d.R.end());
    if (all_weighted)
      joined.R_uncertainty.insert(joined.R_uncertainty.end(), d.R_uncertainty.begin(),
                                  d.R_uncertainty.end());
  }
  return joined;
}

namespace {

// ln Gamma-regularized pieces (Numerical-analysis textbook forms, written
// here): P(a, x) by its series for x < a + 1, Q(a, x) by Lentz's continued
// fraction otherwise.
double LowerSeries(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < 1000; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::abs(term) < std::abs(sum) * 1e-15) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

double UpperFraction(double a, double x) {
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double step = d * c;
    h *= step;
    if (std::abs(step - 1.0) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

}  // namespace

double ChiSquareSurvival(double x, int degrees_of_freedom) {
  if (degrees_of_freedom <= 0 || !std::isfinite(x)) return NAN;
  if (x <= 0.0) return 1.0;
  const double a = 0.5 * degrees_of_freedom, y = 0.5 * x;
  return y < a + 1.0 ? 1.0 - LowerSeries(a, y) : UpperFraction(a, y);
}

ConsistencyTest TestConsistency(double joint_chi2, const std::vector<double>& separate_chi2,
                                const std::vector<int>& separate_dof, int free_parameters,
                                bool weighted, double alpha) {
  ConsistencyTest t;
  t.alpha = alpha;
  const double chi2_sum = std::accumulate(separate_chi2.begin(), separate_chi2.end(), 0.0);
  const int dof_sum = std::accumulate(separate_dof.begin(), separate_dof.end(), 0);
  if (separate_chi2.size() < 2 || dof_sum <= 0 || !std::isfinite(joint_chi2)) return t;
  const double pooled = chi2_sum / dof_sum;
  t.noise_scale2 = weighted ? std::max(1.0, pooled) : pooled;
  t.degrees_of_freedom = free_parameters * static_cast<int>(separate_chi2.size() - 1);
  // The joint optimum cannot beat the separate ones; a slightly negative
  // difference is the optimizers' tolerance.
  t.statistic = std::max(0.0, joint_chi2 - chi2_sum) / std::max(t.noise_scale2, 1e-300);
  t.p_value = ChiSquareSurvival(t.statistic, t.degrees_of_freedom);
  return t;
}

std::string ConsistencyTest::Summary() const {
  if (!std::isfinite(p_value)) return "consistency not tested (fewer than two specimens fitted)";
  return fmt::format(
      "likelihood ratio {:.3g} on {} degrees of freedom (noise scale s^2 {:.3g}): p = {:.3g}; {}",
      statistic, degrees_of_freedom, noise_scale2, p_value,
      consistent() ? fmt::format("one law describes every specimen (p >= {:g})", alpha)
                   : fmt::format("the specimens are NOT described by one law (p < {:g}): the "
                                 "joint estimate fits none of them well; report them separately "
                                 "and look for what differs (material batch, size, test)",
                                 alpha));
}

}  // namespace bridgefit::inverse
