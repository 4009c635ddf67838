#include "bridgefit/inverse/model_check.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"

namespace bridgefit::inverse {

bool ModelCheckOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!(tolerance > 0.0 && tolerance < 1.0)) return fail("the model tolerance must be in (0, 1)");
  if (max_corrections < 0) return fail("max_corrections must be >= 0");
  if (!(parameter_tolerance > 0.0)) return fail("parameter_tolerance must be > 0");
  return true;
}

namespace {

// The cheap model plus an additive R correction known at `knots` (linear
// between them, constant beyond).
class CorrectedModel final : public ForwardModel {
 public:
  CorrectedModel(const ForwardModel& base, std::string accurate, std::vector<double> knots,
                 std::vector<double> offset)
      : base_(base), accurate_(std::move(accurate)), knots_(std::move(knots)),
        offset_(std::move(offset)) {}
  std::string Name() const override { return base_.Name() + " mapped to " + accurate_; }
  ForwardPrediction Predict(const laws::LawShape& shape, const LawParameters& p,
                            const std::vector<double>& crack_lengths, RKind kind) const override {
    ForwardPrediction out = base_.Predict(shape, p, crack_lengths, kind);
    if (!out.ok()) return out;
    for (std::size_t i = 0; i < crack_lengths.size() && i < out.R.size(); ++i)
      out.R[i] += Offset(crack_lengths[i]);
    return out;
  }

 private:
  double Offset(double a) const {
    if (knots_.empty()) return 0.0;
    if (a <= knots_.front()) return offset_.front();
    if (a >= knots_.back()) return offset_.back();
    const auto it = std::upper_bound(knots_.begin(), knots_.end(), a);
    const std::size_t j = static_cast<std::size_t>(it - knots_.begin());
    const double f = (a - knots_[j - 1]) / (knots_[j] - knots_[j - 1]);
    return (1.0 - f) * offset_[j - 1] + f * offset_[j];
  }
  const ForwardModel& base_;
  std::string accurate_;
  std::vector<double> knots_, offset_;
};

LawParameters ToLaw(const std::array<double, kParameterCount>& x) {
  return {.sigma_c = x[kSigmaC], .J_B = x[kJB], .J_tip_c = x[kJTipC]};
}

// Data crack lengths in ascending order (the correction's knots).
std::vector<double> SortedKnots(const FitData& data) {
  std::vector<std::size_t> order(data.crack_length.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return data.crack_length[a] < data.crack_length[b]; });
  std::vector<double> knots;
  for (std::size_t i : order) knots.push_back(data.crack_length[i]);
  return knots;
}

// Largest |R_used / R_accurate - 1| over the knots.
double Discrepancy(const std::vector<double>& used, const std::vector<double>& ra) {
  double worst = 0.0;
  for (std::size_t i = 0; i < ra.size(); ++i)
    if (std::isfinite(ra[i]) && std::isfinite(used[i]) && ra[i] != 0.0)
      worst = std::max(worst, std::abs(used[i] / ra[i] - 1.0));
  return worst;
}

// R of both models at the knots for parameters x (the accurate runs timed
// and counted in the result); false, with the failing model's message, when
// either fails.
class TwoModels {
 public:
  TwoModels(const ForwardModel& cheap, const ForwardModel& accurate, const laws::LawShape& shape,
            const std::vector<double>& knots, RKind kind, ModelCheckResult& r)
      : cheap_(cheap), accurate_(accurate), shape_(shape), knots_(knots), kind_(kind), r_(r) {}
  bool Evaluate(const std::array<double, kParameterCount>& x, std::vector<double>& rc,
                std::vector<double>& ra, std::string* failure) const {
    const ForwardPrediction c = cheap_.Predict(shape_, ToLaw(x), knots_, kind_);
    Stopwatch watch;
    const ForwardPrediction a = accurate_.Predict(shape_, ToLaw(x), knots_, kind_);
    r_.accurate_s += watch.Seconds();
    ++r_.accurate_runs;
    if (!c.ok() || !a.ok()) {
      *failure = !a.ok() ? r_.accurate_model + ": " + a.message : r_.cheap_model + ": " + c.message;
      return false;
    }
    rc = c.R;
    ra = a.R;
    return true;
  }

 private:
  const ForwardModel& cheap_;
  const ForwardModel& accurate_;
  const laws::LawShape& shape_;
  const std::vector<double>& knots_;
  RKind kind_;
  ModelCheckResult& r_;
};

// The cheap fit stands: the models agree within the tolerance, or no
// correction is allowed; each free parameter says so.
FitSummary AcceptCheapFit(FitSummary fit, const ModelCheckOptions& check, ModelCheckResult& r) {
  const bool agree = r.discrepancy_at_cheap_optimum <= check.tolerance;
  const std::string checked = fmt::format("checked by {} (largest R difference {:.2f}% <= {:.2g}%)",
                                          r.accurate_model, 100 * r.discrepancy_at_cheap_optimum,
                                          100 * check.tolerance);
  r.outcome = agree ? "accepted: " + checked
                    : fmt::format("not corrected (no iterations allowed): the {} R differs by "
                                  "{:.2f}%",
                                  r.accurate_model, 100 * r.discrepancy_at_cheap_optimum);
  for (ParameterEstimate* e : {&fit.sigma_c, &fit.J_B, &fit.delta_c, &fit.J_tip_c})
    if (!e->fixed) e->decided_by += "; " + (agree ? checked : r.outcome);
  fit.wall_s += r.accurate_s;
  return fit;
}

// The space mapping's iterate: parameters, both models' R there, the last
// model failure, and whether the last refit moved the parameters little.
struct MappingState {
  std::array<double, kParameterCount> x;
  std::vector<double> rc, ra;
  std::string failure;
  bool moved_little = false;
};

// Output space mapping (R_corrected = R_cheap + R_accurate(x_k) - R_cheap(x_k)):
// refit until the parameters move less than parameter_tolerance or after
// max_corrections refits; an accurate-model failure clears r.accurate_ok.
void SpaceMappingIterations(const ForwardModel& cheap, const TwoModels& models,
                            const laws::LawShape& shape, const FitData& data,
                            const FitOptions& options, const ModelCheckOptions& check,
                            const std::vector<double>& knots, MappingState& state,
                            ModelCheckResult& r) {
  std::vector<double> offset(knots.size());
  FitOptions quick = options;
  quick.profile_likelihood = false;
  FitSummary mapped;
  for (int k = 0; k < check.max_corrections; ++k) {
    for (std::size_t i = 0; i < knots.size(); ++i) offset[i] = state.ra[i] - state.rc[i];
    const CorrectedModel surrogate(cheap, r.accurate_model, knots, offset);
    mapped = FitBridgingLaw(surrogate, shape, data, quick);
    r.correction_fit_s += mapped.wall_s;
    ++r.corrections;
    if (!std::isfinite(mapped.best_parameters[kJTipC])) break;
    const std::array<double, kParameterCount> next = mapped.best_parameters;
    double change = 0.0;
    for (int i = 0; i < kParameterCount; ++i)
      if (!options.fixed[i] && std::abs(state.x[i]) > 0.0)
        change = std::max(change, std::abs(next[i] / state.x[i] - 1.0));
    state.x = next;
    std::vector<double> rc_next, ra_next;
    if (!models.Evaluate(state.x, rc_next, ra_next, &state.failure)) {
      r.accurate_ok = false;
      break;
    }
    // How well the surrogate used in this refit matched the accurate model.
    std::vector<double> used(knots.size());
    for (std::size_t i = 0; i < knots.size(); ++i) used[i] = rc_next[i] + offset[i];
    r.discrepancy_final = Discrepancy(used, ra_next);
    state.rc = rc_next;
    state.ra = ra_next;
    state.moved_little = change < check.parameter_tolerance;
    if (state.moved_little) break;
  }
}

// Final fit of the corrected model with the full options (intervals,
// profiles, bounds), from the mapped optimum; the outcome and each free
// parameter's provenance say how it was corrected.
FitSummary FinalCorrectedFit(const ForwardModel& cheap, const laws::LawShape& shape,
                             const FitData& data, const FitOptions& options,
                             const ModelCheckOptions& check, const std::vector<double>& knots,
                             const MappingState& state, ModelCheckResult& r) {
  std::vector<double> offset(knots.size());
  for (std::size_t i = 0; i < knots.size(); ++i) offset[i] = state.ra[i] - state.rc[i];
  const CorrectedModel final_model(cheap, r.accurate_model, knots, offset);
  FitOptions last = options;
  for (int i = 0; i < kParameterCount; ++i)
    if (!options.fixed[i]) last.initial[i] = state.x[i];
  FitSummary out = FitBridgingLaw(final_model, shape, data, last);
  r.correction_fit_s += out.wall_s;
  r.corrected = true;
  r.final_parameters = out.best_parameters;
  r.crack_length = knots;
  r.R_cheap = state.rc;
  r.R_accurate = state.ra;
  r.outcome = fmt::format(
      "corrected: the {} R differed by {:.2f}% (> {:.2g}%) at the {} optimum; output space "
      "mapping, {} iteration(s), {} {} run(s){}; the corrected model matches {} within {:.2f}% "
      "at the last iterate",
      r.accurate_model, 100 * r.discrepancy_at_cheap_optimum, 100 * check.tolerance,
      r.cheap_model, r.corrections, r.accurate_runs, r.accurate_model,
      state.moved_little ? "" : " (iteration limit)", r.accurate_model, 100 * r.discrepancy_final);
  const std::string decided = fmt::format("{} + {} corrected to {} ({} run(s))", out.optimizer,
                                          r.cheap_model, r.accurate_model, r.accurate_runs);
  for (ParameterEstimate* e : {&out.sigma_c, &out.J_B, &out.delta_c, &out.J_tip_c})
    if (!e->fixed && e->decided_by.find(out.model) != std::string::npos)
      e->decided_by = decided;
    else if (!e->fixed)
      e->decided_by += " (model: " + decided + ")";
  out.wall_s += r.cheap_fit_s + r.accurate_s + (r.correction_fit_s - out.wall_s);
  return out;
}

}  // namespace

// Stages: cheap fit -> both models at its optimum -> accept, or output space
// mapping iterations -> final fit of the corrected model.
FitSummary FitWithModelCheck(const ForwardModel& cheap, const ForwardModel& accurate,
                             const laws::LawShape& shape, const FitData& data,
                             const FitOptions& options, const ModelCheckOptions& check,
                             ModelCheckResult* result) {
  std::string why;
  if (!check.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid model check: " + why);
  if (data.target != FitTarget::kRCurve)
    throw Error(ErrorKind::kUsage,
                "the model check corrects R curves; a load-displacement fit runs with one model",
                {.field = "--model", .value = "auto", .expected = "reduced or mpm"});
  ModelCheckResult local;
  ModelCheckResult& r = result ? *result : local;
  r = ModelCheckResult{};
  r.cheap_model = cheap.Name();
  r.accurate_model = accurate.Name();

  FitSummary fit = FitBridgingLaw(cheap, shape, data, options);
  r.cheap_fit_s = fit.wall_s;
  r.cheap_optimum = fit.best_parameters;
  r.final_parameters = fit.best_parameters;
  if (!std::isfinite(fit.best_parameters[kJTipC])) {
    r.outcome = "not checked: the " + r.cheap_model + " fit failed";
    return fit;
  }
  const std::vector<double> knots = SortedKnots(data);
  const TwoModels models(cheap, accurate, shape, knots, data.kind, r);
  MappingState state;
  state.x = fit.best_parameters;
  if (!models.Evaluate(fit.best_parameters, state.rc, state.ra, &state.failure)) {
    r.outcome = "not checked: the accurate model failed at the " + r.cheap_model +
                " optimum (" + state.failure + "); the " + r.cheap_model + " fit stands";
    return fit;
  }
  r.accurate_ok = true;
  r.discrepancy_at_cheap_optimum = Discrepancy(state.rc, state.ra);
  r.crack_length = knots;
  r.R_cheap = state.rc;
  r.R_accurate = state.ra;
  r.discrepancy_final = r.discrepancy_at_cheap_optimum;
  if (r.discrepancy_at_cheap_optimum <= check.tolerance || check.max_corrections == 0)
    return AcceptCheapFit(std::move(fit), check, r);

  SpaceMappingIterations(cheap, models, shape, data, options, check, knots, state, r);
  if (!r.accurate_ok) {
    r.outcome = "correction stopped: the accurate model failed (" + state.failure + "); the " +
                r.cheap_model + " fit stands";
    return fit;
  }
  return FinalCorrectedFit(cheap, shape, data, options, check, knots, state, r);
}

std::array<double, kParameterCount> CorrectedFitBias(const ForwardModel& cheap,
                                                     const ModelCheckResult& result,
                                                     const laws::LawShape& shape,
                                                     const FitData& data, const FitOptions& options,
                                                     const FitSummary& fit,
                                                     const std::vector<double>& accurate_error,
                                                     int* runs) {
  std::array<double, kParameterCount> bias = {NAN, NAN, NAN};
  const std::size_t n = result.crack_length.size();
  if (!result.corrected || n == 0 || accurate_error.size() != n || result.R_cheap.size() != n ||
      result.R_accurate.size() != n)
    return bias;
  std::vector<double> offset(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(accurate_error[i])) return bias;
    offset[i] = result.R_accurate[i] - accurate_error[i] - result.R_cheap[i];
  }
  const CorrectedModel converged(cheap, result.accurate_model + " converged", result.crack_length,
                                 offset);
  FitOptions quick = options;
  quick.profile_likelihood = false;
  for (int i = 0; i < kParameterCount; ++i)
    if (!options.fixed[i] && std::isfinite(fit.best_parameters[i]))
      quick.initial[i] = fit.best_parameters[i];
  const FitSummary refit = FitBridgingLaw(converged, shape, data, quick);
  if (runs) *runs = refit.evaluations;
  if (!refit.converged) return bias;
  for (int i = 0; i < kParameterCount; ++i)
    bias[i] = options.fixed[i] ? 0.0 : fit.best_parameters[i] - refit.best_parameters[i];
  return bias;
}

}  // namespace bridgefit::inverse
