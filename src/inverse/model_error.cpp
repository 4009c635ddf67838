// The forward model's discretisation error in the intervals
// (include/bridgefit/inverse/model_error.hpp).

#include "bridgefit/inverse/model_error.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/progress.hpp"
#include "fit_impl.hpp"

namespace bridgefit::inverse {

using namespace fit_internal;

const char* ModelErrorStatusName(ModelErrorStatus status) {
  switch (status) {
    case ModelErrorStatus::kEstimated: return "estimated";
    case ModelErrorStatus::kOrderNotObserved: return "order_not_observed";
    default: return "not_estimated";
  }
}

bool ModelErrorOptions::IsValid(std::string* why) const {
  auto fail = [why](const char* text) {
    if (why) *why = text;
    return false;
  };
  // Below 1: one finer solve (the fallback when a coarser one fails); the
  // order is then assumed.
  if (!(refinement_ratio > 0.0 && refinement_ratio != 1.0))
    return fail("refinement_ratio must be positive and not 1");
  if (!(min_order > 0.0 && max_order > min_order)) return fail("need 0 < min_order < max_order");
  if (!(assumed_order > 0.0)) return fail("assumed_order must be positive");
  if (!(safety_factor >= 1.0 && unverified_safety_factor >= safety_factor))
    return fail("need 1 <= safety_factor <= unverified_safety_factor");
  return true;
}

std::string ModelErrorEstimate::Summary() const {
  if (status == ModelErrorStatus::kNotEstimated)
    return "model error not estimated: " + reason + "; the intervals are the noise's alone";
  const bool load = quantity == "load";
  std::string text =
      coarse_resolution < resolution
          ? fmt::format("model error ({} model at {:.3g} mm, from one finer solve at {:.3g} mm): ",
                        model, resolution * 1e3, coarse_resolution * 1e3)
      : !std::isfinite(coarser_resolution)
          ? fmt::format("model error ({} model at {:.3g} mm, from one coarser solve at {:.3g} mm): ",
                        model, resolution * 1e3, coarse_resolution * 1e3)
          : fmt::format("model error ({} model at {:.3g} mm, from {:.3g} and {:.3g} mm): ", model,
                        resolution * 1e3, coarse_resolution * 1e3, coarser_resolution * 1e3);
  if (status == ModelErrorStatus::kEstimated)
    text += std::isfinite(observed_order)
                ? fmt::format("observed order {:.2f}, order {:.2f} used", observed_order, order_used)
                : std::string("the coarser solves agree with it");
  else
    text += fmt::format("order not observed ({}), order {:.2f} assumed", reason, order_used);
  text += fmt::format(
      ", safety factor {:.3g}; predicted bias of {} up to {:.3g} {} ({:.2g}%), rms {:.3g} {}",
      safety_factor, quantity, output_bias_max, load ? "N" : "J/m^2",
      100 * output_bias_max_relative, output_bias_rms, load ? "N" : "J/m^2");
  if (std::isfinite(output_bias_noise_rms))
    text += fmt::format(" ({:.2g} noise sd rms)", output_bias_noise_rms);
  if (!far_field_note.empty()) text += "; " + far_field_note;
  return text;
}

namespace fit_internal {

OrderChoice ChooseOrder(const std::vector<double>& fine, const std::vector<double>& coarse,
                        const std::string& problem, const ModelErrorOptions& o) {
  OrderChoice c;
  double fine_norm = 0.0, coarse_norm = 0.0, dot = 0.0;
  for (std::size_t i = 0; i < fine.size(); ++i) {
    fine_norm += fine[i] * fine[i];
    if (coarse.size() == fine.size()) {
      coarse_norm += coarse[i] * coarse[i];
      dot += coarse[i] * fine[i];
    }
  }
  c.order = o.assumed_order;
  c.problem = problem;
  if (fine_norm == 0.0) {
    c.no_difference = true;
  } else if (problem.empty() && coarse.size() == fine.size()) {
    const double q = 0.5 * std::log(coarse_norm / fine_norm) / std::log(o.refinement_ratio);
    if (!(dot > 0.0)) {
      c.problem = "the differences between successive solves change direction";
    } else if (!(q >= o.min_order && q <= o.max_order)) {
      c.problem = fmt::format("observed order {:.2f} outside [{:g}, {:g}]", q, o.min_order,
                              o.max_order);
    } else {
      c.observed = true;
      c.observed_order = q;
      c.order = std::min(q, o.assumed_order);
    }
  } else if (c.problem.empty()) {
    c.problem = "no third solve";
  }
  c.denominator = std::pow(o.refinement_ratio, c.order) - 1.0;
  return c;
}


}  // namespace fit_internal

namespace fit_internal {

// The rows the fit kept: its outliers (listed by crack length or
// displacement and value) are left out.
FitData RowsUsed(const FitData& data, const FitSummary& fit) {
  if (fit.outlier_crack_lengths.empty()) return data;
  const bool load = data.target == FitTarget::kLoad;
  const std::vector<double>& x = load ? data.displacement : data.crack_length;
  const std::vector<double>& y = load ? data.load : data.R;
  std::vector<int> keep;
  for (std::size_t i = 0; i < x.size(); ++i) {
    bool removed = false;
    for (std::size_t k = 0; k < fit.outlier_crack_lengths.size(); ++k)
      removed |= x[i] == fit.outlier_crack_lengths[k] && y[i] == fit.outlier_R[k];
    if (!removed) keep.push_back(static_cast<int>(i));
  }
  return data.Subset(keep);
}

// The model's prediction at the data (R or load); empty when the run failed
// (the message in `why`).
std::vector<double> PredictAt(const ForwardModel& model, const laws::LawShape& shape,
                              const LawParameters& p, const FitData& data, std::string* why) {
  const bool load = data.target == FitTarget::kLoad;
  const ForwardPrediction prediction = load ? model.PredictLoad(shape, p, data.displacement)
                                            : model.Predict(shape, p, data.crack_length, data.kind);
  const std::vector<double>& y = load ? prediction.load : prediction.R;
  if (!prediction.ok() || y.size() != data.size()) {
    *why = prediction.message.empty() ? "no prediction at every data point" : prediction.message;
    return {};
  }
  return y;
}

// Weighted norm of (a - b) / u.
double WeightedNorm(const std::vector<double>& a, const std::vector<double>& b,
                    const std::vector<double>& u) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    sum += std::pow((a[i] - b[i]) / (u.empty() ? 1.0 : u[i]), 2);
  return std::sqrt(sum);
}

// The parameters the answer rests on and which of them the data decided:
// every free one with bridging; without bridging only J_tip,c, and only
// where a model gave it (a load-displacement fit; an R curve's flat J_tip,c
// is the data's weighted mean, free of model error).
FitOptions AnswerParameters(const FitOptions& options, const FitSummary& fit,
                            std::array<double, kParameterCount>* at) {
  FitOptions answer = options;
  *at = fit.best_parameters;
  if (!fit.bridging_detected) {
    (*at)[kJB] = 0.0;
    (*at)[kJTipC] = fit.J_tip_c.value;
    answer.fixed[kSigmaC] = answer.fixed[kJB] = true;
    answer.fixed[kJTipC] = options.fixed[kJTipC] || fit.target != FitTarget::kLoad;
  }
  for (int i = 0; i < kParameterCount; ++i)
    if (answer.fixed[i]) answer.fixed_value[i] = (*at)[i];
  return answer;
}

// The predicted output bias against the data's noise (the fit's standard
// uncertainty of each point: u_i s with s^2 the fit's noise scale), and the
// warning when it is larger than the noise.
std::array<double, 2> NoiseRelative(const std::vector<double>& bias, const FitData& data,
                                    double scale2) {
  const std::vector<double>& u =
      data.target == FitTarget::kLoad ? data.load_uncertainty : data.R_uncertainty;
  if (!(scale2 > 0.0) || bias.empty()) return {NAN, NAN};
  double sum2 = 0.0, largest = 0.0;
  for (std::size_t i = 0; i < bias.size(); ++i) {
    const double sd = (u.size() == bias.size() ? u[i] : 1.0) * std::sqrt(scale2);
    const double z = std::abs(bias[i]) / sd;
    sum2 += z * z;
    largest = std::max(largest, z);
  }
  return {std::sqrt(sum2 / bias.size()), largest};
}

void NoiseRelativeBias(const FitData& used, const FitSummary& fit, ModelErrorEstimate& e) {
  const bool load = used.target == FitTarget::kLoad;
  // Against the data's own uncertainties where it has them: a fit's noise
  // scale grows with the misfit the model's error makes, and would hide it.
  const double scale2 = used.weighted() ? 1.0
                        : std::isfinite(fit.noise_scale2) ? fit.noise_scale2
                                                          : fit.reduced_chi2;
  const std::array<double, 2> z = NoiseRelative(e.output_bias, used, scale2);
  e.output_bias_noise_rms = z[0];
  e.output_bias_noise_max = z[1];
  const double largest = z[1];
  if (e.output_bias_noise_rms > kOutputBiasNoiseLimit)
    e.warning = fmt::format(
        "the {} model at {:.3g} mm is too coarse for this record: its predicted error of {} "
        "is {:.2g} noise standard deviations rms (up to {:.2g}), more than the noise itself, so "
        "an estimate or a verdict (bridging detected, steady state) may be off by more than its "
        "interval; refit with a finer --resolution (e.g. '{:.3g} mm')",
        e.model, e.resolution * 1e3, load ? "the load" : "R", e.output_bias_noise_rms, largest,
        e.resolution * 1e3 / 2);
}

}  // namespace fit_internal

namespace {

// The fit re-run locally (BOBYQA) from x0 (the answer's free parameters, in
// the box) with `model`: the full parameters (SI), or empty when the search
// found no valid run. Adds the forward runs spent to *runs.
std::vector<double> RefitLocally(const ForwardModel& model, const laws::LawShape& shape,
                                 const FitData& used, const FitOptions& answer,
                                 const std::vector<double>& x0, int max_evaluations, int* runs) {
  const Objective objective(model, shape, used, answer);
  const LocalResult result = MinimizeLocal(objective, Optimizer::kBobyqa, x0, max_evaluations);
  *runs += objective.evaluations();
  if (result.chi2 >= kFailedCost) return {};
  return objective.Expand(result.x.data());
}

}  // namespace

ModelErrorEstimate EstimateModelError(const ForwardModel& model, const ForwardModel* coarse,
                                      const ForwardModel* coarser, double resolution,
                                      const laws::LawShape& shape, const FitData& data,
                                      const FitOptions& options, const FitSummary& fit,
                                      const ModelErrorOptions& error_options) {
  const Stopwatch clock;
  ModelErrorEstimate e;
  e.model = model.Name();
  e.quantity = data.target == FitTarget::kLoad ? "load" : "R";
  e.resolution = resolution;
  e.coarse_resolution = error_options.refinement_ratio * resolution;
  e.coarser_resolution = error_options.refinement_ratio * e.coarse_resolution;
  auto give_up = [&](std::string why) {
    e.status = ModelErrorStatus::kNotEstimated;
    e.reason = std::move(why);
    e.wall_s = clock.Seconds();
    return e;
  };
  if (std::string why; !error_options.IsValid(&why)) return give_up("invalid options: " + why);
  if (!coarse) return give_up("no coarser solve of the " + e.model + " model");
  // A finer solve has no third one: its order is assumed.
  if (error_options.refinement_ratio < 1.0) coarser = nullptr;
  if (!std::isfinite(fit.best_parameters[kJTipC]) || fit.chi2 >= kFailedCost)
    return give_up("the fit failed");

  std::array<double, kParameterCount> at{};
  const FitOptions answer = AnswerParameters(options, fit, &at);
  const FitData used = RowsUsed(data, fit);
  const LawParameters p{at[kSigmaC], at[kJB], at[kJTipC]};
  const std::vector<double>& u = used.target == FitTarget::kLoad ? used.load_uncertainty
                                                                 : used.R_uncertainty;
  std::string why;
  const std::vector<double> y_h = PredictAt(model, shape, p, used, &why);
  ++e.runs;
  if (y_h.empty()) return give_up("the fitted model's run failed: " + why);
  const std::vector<double> y_2h = PredictAt(*coarse, shape, p, used, &why);
  ++e.runs;
  e.coarse_failed = y_2h.empty();
  if (y_2h.empty())
    return give_up(fmt::format("the coarser solve at {:.3g} mm failed: {}",
                               e.coarse_resolution * 1e3, why));
  std::vector<double> y_4h;
  std::string prediction_problem = "no third solve";
  if (coarser) {
    y_4h = PredictAt(*coarser, shape, p, used, &why);
    ++e.runs;
    if (y_4h.empty())
      prediction_problem =
          fmt::format("the solve at {:.3g} mm failed: {}", e.coarser_resolution * 1e3, why);
  }

  // The prediction's bias (R or load at the data), for the report:
  // Richardson with the order of the prediction's differences.
  std::string order_problem = y_4h.empty() ? prediction_problem : std::string();
  std::vector<double> step_fine(y_h.size()), step_coarse(y_4h.size());
  for (std::size_t i = 0; i < y_h.size(); ++i) {
    const double w = u.empty() ? 1.0 : u[i];
    step_fine[i] = (y_2h[i] - y_h[i]) / w;
    if (!y_4h.empty()) step_coarse[i] = (y_4h[i] - y_2h[i]) / w;
  }
  const OrderChoice output_order = ChooseOrder(step_fine, step_coarse, order_problem, error_options);
  std::vector<double> bias(y_h.size());
  for (std::size_t i = 0; i < y_h.size(); ++i)
    bias[i] = (y_2h[i] - y_h[i]) / output_order.denominator;
  SetOutputBias(std::move(bias), y_h, e);
  NoiseRelativeBias(used, fit, e);

  // The parameters: the fit re-run locally from its optimum with each
  // coarser model (Richardson on the estimates themselves; mapping the
  // prediction's bias through the Jacobian missed the sign of the actual
  // error near a0, where the coarse R curves are poorly resolved: docs/FIT.md).
  for (int i = 0; i < kParameterCount; ++i) e.parameter_bias[i] = answer.fixed[i] ? 0.0 : NAN;
  const Objective objective(model, shape, used, answer);
  const std::vector<int>& free = objective.free();
  const std::vector<double> full(at.begin(), at.end());
  if (free.empty()) {
    e.status = ModelErrorStatus::kEstimated;
    e.safety_factor = error_options.safety_factor;
    e.wall_s = clock.Seconds();
    return e;
  }
  // Statistical standard uncertainties from the Jacobian (the scale of the
  // differences, and what --resolution auto compares the bias with).
  Eigen::MatrixXd jacobian;
  const bool jacobian_ok = PhysicalJacobian(objective, full, &jacobian);
  e.runs += objective.evaluations();
  std::vector<double> sd(free.size(), NAN);
  if (jacobian_ok) {
    const double scale2 = std::isfinite(fit.noise_scale2)
                              ? fit.noise_scale2
                              : (used.weighted() ? std::max(1.0, fit.reduced_chi2) : fit.reduced_chi2);
    const Eigen::MatrixXd jtj = jacobian.transpose() * jacobian;
    const Eigen::MatrixXd covariance = scale2 * jtj.completeOrthogonalDecomposition().pseudoInverse();
    for (std::size_t k = 0; k < free.size(); ++k) {
      sd[k] = std::sqrt(covariance(k, k));
      e.statistical_sd[free[k]] = sd[k];
    }
  }
  std::vector<double> x0;
  for (int index : free) x0.push_back(ToBox(index, at[index], answer));
  auto refit = [&](const ForwardModel& coarse_model, std::vector<double>* estimate) {
    const std::vector<double> p_full =
        RefitLocally(coarse_model, shape, used, answer, x0, options.max_evaluations, &e.runs);
    if (p_full.empty()) return false;
    for (int index : free) estimate->push_back(p_full[index]);
    if (&coarse_model == coarse) std::copy(p_full.begin(), p_full.end(), e.coarse_estimate.begin());
    return true;
  };
  std::vector<double> p_2h, p_4h;
  if (!refit(*coarse, &p_2h)) {
    e.coarse_failed = true;
    e.status = ModelErrorStatus::kNotEstimated;
    e.reason = fmt::format("the fit with the {:.3g} mm model failed", e.coarse_resolution * 1e3);
    e.wall_s = clock.Seconds();
    return e;
  }
  std::string parameter_problem = order_problem;
  if (coarser && parameter_problem.empty() && !refit(*coarser, &p_4h))
    parameter_problem = fmt::format("the fit with the {:.3g} mm model failed",
                                    e.coarser_resolution * 1e3);
  std::vector<double> move_fine(free.size()), move_coarse;
  for (std::size_t k = 0; k < free.size(); ++k) {
    const double scale = std::isfinite(sd[k]) && sd[k] > 0.0 ? sd[k] : std::abs(at[free[k]]);
    move_fine[k] = (p_2h[k] - at[free[k]]) / scale;
    if (p_4h.size() == free.size()) move_coarse.push_back((p_4h[k] - p_2h[k]) / scale);
  }
  const OrderChoice order = ChooseOrder(move_fine, move_coarse, parameter_problem, error_options);
  e.status = order.observed || order.no_difference ? ModelErrorStatus::kEstimated
                                                   : ModelErrorStatus::kOrderNotObserved;
  e.reason = order.problem;
  e.observed_order = order.observed_order;
  e.order_used = order.order;
  e.safety_factor = e.status == ModelErrorStatus::kEstimated
                        ? error_options.safety_factor
                        : error_options.unverified_safety_factor;
  for (std::size_t k = 0; k < free.size(); ++k)
    e.parameter_bias[free[k]] = (p_2h[k] - at[free[k]]) / order.denominator;
  e.wall_s = clock.Seconds();
  return e;
}

void AddFarFieldError(const ForwardModel& refined, const laws::LawShape& shape,
                      const FitData& data, const FitOptions& options, const FitSummary& fit,
                      const std::array<double, kParameterCount>* reference_or_answer,
                      ModelErrorEstimate& e) {
  const Stopwatch clock;
  std::array<double, kParameterCount> at{};
  const FitOptions answer = AnswerParameters(options, fit, &at);
  const std::array<double, kParameterCount>& reference =
      reference_or_answer ? *reference_or_answer : at;
  std::vector<int> free;
  std::vector<double> x0;
  for (int index = 0; index < kParameterCount; ++index)
    if (!answer.fixed[index]) {
      free.push_back(index);
      x0.push_back(ToBox(index, at[index], answer));
    }
  const bool have_reference = std::all_of(free.begin(), free.end(), [&](int index) {
    return std::isfinite(reference[index]);
  });
  const std::vector<double> p_refined =
      free.empty() || !have_reference
          ? std::vector<double>{}
          : RefitLocally(refined, shape, RowsUsed(data, fit), answer, x0, options.max_evaluations,
                         &e.runs);
  if (p_refined.empty()) {
    e.far_field_note = "the far field's share not estimated: a refit failed";
    e.wall_s += clock.Seconds();
    return;
  }
  std::string shares;
  for (int index : free) {
    const double bias = 2.0 * (reference[index] - p_refined[index]);
    e.far_field_bias[index] = bias;
    if (std::isfinite(e.parameter_bias[index])) e.parameter_bias[index] += bias;
    shares += fmt::format("{}{} {:+.2g}%", shares.empty() ? "" : ", ", ParameterName(index),
                          100.0 * bias / std::abs(at[index]));
  }
  e.far_field_note = "far field's share (half its largest element): " + shares;
  e.wall_s += clock.Seconds();
}

void TakeTheLargerBias(const ModelErrorEstimate& finer, ModelErrorEstimate& e) {
  e.runs += finer.runs;
  e.wall_s += finer.wall_s;
  const std::string at = fmt::format("the finer side ({:.3g} mm)", finer.coarse_resolution * 1e3);
  if (!finer.estimated()) {
    e.reason += fmt::format("; {} not estimated: {}", at, finer.reason);
    return;
  }
  std::string taken;
  for (int i = 0; i < kParameterCount; ++i) {
    const double mine = e.parameter_bias[i], theirs = finer.parameter_bias[i];
    if (!std::isfinite(theirs) || (std::isfinite(mine) && std::abs(mine) >= std::abs(theirs)))
      continue;
    e.parameter_bias[i] = theirs;
    taken += fmt::format("{}{}", taken.empty() ? "" : ", ", ParameterName(i));
  }
  e.safety_factor = std::max(e.safety_factor, finer.safety_factor);
  e.reason += taken.empty() ? fmt::format("; {} predicts no larger bias", at)
                            : fmt::format("; {} predicts a larger bias of {}: taken", at, taken);
}

std::array<double, 2> TotalInterval(double low, double high, double bias, double safety_factor) {
  if (!std::isfinite(bias)) return {low, high};
  const double margin = (safety_factor - 1.0) * std::abs(bias);
  // An open end stays open; every parameter is positive: a total interval
  // never reaches below 0.
  const double total_low =
      std::isfinite(low) ? std::max(0.0, std::min(low, low - bias) - margin) : low;
  const double total_high = std::isfinite(high) ? std::max(high, high - bias) + margin : high;
  return {total_low, total_high};
}

void SetOutputBias(std::vector<double> bias, const std::vector<double>& prediction,
                   ModelErrorEstimate& e) {
  e.output_bias = std::move(bias);
  double sum2 = 0.0;
  e.output_bias_max = e.output_bias_max_relative = 0.0;
  for (std::size_t i = 0; i < e.output_bias.size(); ++i) {
    sum2 += e.output_bias[i] * e.output_bias[i];
    const double magnitude = std::abs(e.output_bias[i]);
    if (magnitude > e.output_bias_max) {
      e.output_bias_max = magnitude;
      const double there = i < prediction.size() ? std::abs(prediction[i]) : 0.0;
      e.output_bias_max_relative = magnitude / std::max(there, 1e-300);
    }
  }
  e.output_bias_rms = std::sqrt(sum2 / std::max<std::size_t>(1, e.output_bias.size()));
}

void ApplyModelError(const ModelErrorEstimate& estimate, FitSummary& fit) {
  if (!estimate.estimated()) return;
  const double fs = estimate.safety_factor;
  ParameterEstimate* estimates[] = {&fit.sigma_c, &fit.J_B, &fit.J_tip_c};
  for (int i = 0; i < kParameterCount; ++i) {
    ParameterEstimate& e = *estimates[i];
    // Fixed, or no interval (a bound, J_B = 0 without bridging): unchanged.
    if (e.fixed || (!std::isfinite(e.ci95_low) && !std::isfinite(e.ci95_high))) continue;
    e.statistical_ci95_low = e.ci95_low;
    e.statistical_ci95_high = e.ci95_high;
    e.model_bias = estimate.parameter_bias[i];
    if (!std::isfinite(e.model_bias)) continue;
    const std::array<double, 2> total = TotalInterval(e.ci95_low, e.ci95_high, e.model_bias, fs);
    e.ci95_low = total[0];
    e.ci95_high = total[1];
  }
  // J_B >= R_max - J_tip,c: a J_tip,c biased low (bias < 0) raises the
  // bound above what the converged model would give.
  const double tip_bias = estimate.parameter_bias[kJTipC];
  if (std::isfinite(fit.J_B.lower_bound) && std::isfinite(tip_bias) && tip_bias < 0.0)
    fit.J_B.lower_bound = std::max(0.0, fit.J_B.lower_bound + fs * tip_bias);
  // delta_c = J_B / (k sigma_c): its interval from the totals' extremes.
  ParameterEstimate& dc = fit.delta_c;
  const ParameterEstimate& sc = fit.sigma_c;
  const ParameterEstimate& jb = fit.J_B;
  if (std::isfinite(dc.value) && std::isfinite(sc.value) && std::isfinite(jb.value) &&
      dc.value > 0.0) {
    const double k = jb.value / (sc.value * dc.value);
    dc.statistical_ci95_low = dc.ci95_low;
    dc.statistical_ci95_high = dc.ci95_high;
    if (std::isfinite(jb.model_bias) && std::isfinite(sc.model_bias))
      dc.model_bias = dc.value - (jb.value - jb.model_bias) / (k * (sc.value - sc.model_bias));
    if (std::isfinite(dc.ci95_low) && std::isfinite(dc.ci95_high)) {
      dc.ci95_low = jb.ci95_low / (k * sc.ci95_high);
      dc.ci95_high = sc.ci95_low > 0.0 ? jb.ci95_high / (k * sc.ci95_low) : NAN;
    }
  }
}

}  // namespace bridgefit::inverse
