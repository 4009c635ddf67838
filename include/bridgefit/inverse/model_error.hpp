#pragma once
// The forward model's own discretisation error inside every interval
// (issue 17, docs/FIT.md "Model error in every interval").
//
// At the fitted parameters the model is run again at two coarser element
// sizes, r h and r^2 h (r = 2), and the fit is re-run locally from its
// optimum with each: estimates p_h, p_2h, p_4h. The observed order of
// convergence q = ln(|p_4h - p_2h| / |p_2h - p_h|) / ln r (differences
// scaled by the statistical standard uncertainties), and Richardson's
// estimate of each parameter's discretisation bias (estimate minus the
// converged model's) is beta = (p_2h - p_h) / (r^p - 1), p = min(q, the
// model's asymptotic order 1). The same on the model's prediction at the
// data (R, or the load) gives its predicted bias, reported alongside.
// The total interval holds the statistical one and the statistical one
// shifted by -beta, widened by (F_s - 1)|beta| on both sides, with Roache's
// safety factor F_s = 1.25 for an observed order and 3 where it is not
// observed (the order 1 is assumed then). The statistical interval, beta
// and the total interval are all reported; the total is the default.

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "bridgefit/inverse/fit.hpp"

namespace bridgefit::inverse {

enum class ModelErrorStatus {
  kEstimated,         // observed order inside the accepted range (or no difference at all)
  kOrderNotObserved,  // the three solves do not converge cleanly: assumed order, F_s = 3
  kNotEstimated,      // no coarser solve (failed, or no error model): statistical interval only
};
// "estimated", "order_not_observed", "not_estimated"
const char* ModelErrorStatusName(ModelErrorStatus status);

struct ModelErrorOptions {
  // Coarse element size / fine (and coarser / coarse). Below 1 the one
  // "coarse" model is finer than the fit's (the fallback where a coarser
  // solve fails): Richardson's beta = (p_rh - p_h) / (r^p - 1) holds for
  // either side, with the order assumed (no third solve) and F_s = 3.
  double refinement_ratio = 2.0;
  double min_order = 0.5;         // an observed order outside [min, max] is not trusted
  double max_order = 3.0;
  // The model's asymptotic order: the reduced model converges with order
  // 0.9-1.2 (docs/REDUCED.md section 5). Assumed where the order is not
  // observed, and an upper limit on the order used: the interpolation of the
  // model's points between nodes adds an O(h^2) part that dominates the
  // coarse differences (observed 1.5-2.1 from 4, 2, 1 mm) while the O(h)
  // part dominates at h; a higher order would under-predict the bias
  // (docs/FIT.md "Model error in every interval").
  double assumed_order = 1.0;
  double safety_factor = 1.25;            // Roache's F_s, observed order
  double unverified_safety_factor = 3.0;  // Roache's F_s, assumed order
  bool IsValid(std::string* why) const;
};

// The rms predicted output bias, in noise standard deviations, above which
// the model is too coarse for the data (ModelErrorEstimate::warning).
inline constexpr double kOutputBiasNoiseLimit = 1.0;

struct ModelErrorEstimate {
  ModelErrorStatus status = ModelErrorStatus::kNotEstimated;
  std::string reason;            // why not estimated, or why the order is not trusted
  std::string model;             // the forward model's name
  std::string quantity;          // "R" [J/m^2] or "load" [N]
  double resolution = NAN;       // the fit's element size h [m]
  double coarse_resolution = NAN, coarser_resolution = NAN;  // [m]
  double observed_order = NAN;   // NaN when not observed
  double order_used = NAN;       // min(observed, assumed), or the assumed one
  double safety_factor = NAN;
  // Predicted bias of the model's prediction at each data point used (model
  // at h minus converged), in the quantity's unit; its rms and largest
  // magnitude, the latter also relative to the prediction there.
  std::vector<double> output_bias;
  double output_bias_rms = NAN;
  double output_bias_max = NAN;
  double output_bias_max_relative = NAN;
  // The same bias in units of the data's noise (the fit's standard
  // uncertainty of each point): rms and largest magnitude. Above
  // kOutputBiasNoiseLimit the model's own error is visible in the data: a
  // verdict (bridging detected, steady state) or an estimate can move by
  // more than the Richardson terms of the estimates say (`warning`).
  double output_bias_noise_rms = NAN;
  double output_bias_noise_max = NAN;
  std::string warning;  // set when the model is too coarse for the data; printed as a warning
  // Predicted bias of each estimate (estimate minus the converged model's),
  // SI; 0 for fixed parameters, NaN where not estimated.
  std::array<double, kParameterCount> parameter_bias = {NAN, NAN, NAN};
  // Statistical standard uncertainty of each free estimate from the fit's
  // Jacobian (s^2 (J^T J)^-1, s^2 as the fit's), NaN where not computed.
  std::array<double, kParameterCount> statistical_sd = {NAN, NAN, NAN};
  // The fit re-run with the coarse (r h) model from its optimum, SI; NaN
  // where not run or failed (the Richardson terms' p_rh).
  std::array<double, kParameterCount> coarse_estimate = {NAN, NAN, NAN};
  // The far field's share of parameter_bias (AddFarFieldError), SI; NaN
  // where not estimated (far_field_note says why).
  std::array<double, kParameterCount> far_field_bias = {NAN, NAN, NAN};
  std::string far_field_note;
  bool coarse_failed = false;  // not estimated because the r h solve or fit failed
  int runs = 0;        // forward runs spent (coarser solves and the Jacobian)
  double wall_s = 0.0;

  bool estimated() const { return status != ModelErrorStatus::kNotEstimated; }
  std::string Summary() const;  // one line for the report
};

// The model error of `fit` (made by `model` on `data` with `options`; its
// outliers are left out) from the coarser models `coarse` (r h) and
// `coarser` (r^2 h; may be null: then the order is assumed). Never throws
// for a failed run: the estimate says why it is missing.
ModelErrorEstimate EstimateModelError(const ForwardModel& model, const ForwardModel* coarse,
                                      const ForwardModel* coarser, double resolution,
                                      const laws::LawShape& shape, const FitData& data,
                                      const FitOptions& options, const FitSummary& fit,
                                      const ModelErrorOptions& error_options = {});

// The reduced model's far field (its largest element: CT W/40, DCB h) is
// not refined with the element size h, so its error is the same at every h
// and the Richardson terms of EstimateModelError cannot see it (docs/
// REDUCED.md section 5: a load-line compliance 0.7% low at every h). The
// fit is refitted locally from its optimum with `refined` (a model of some
// element size with half the largest element) and compared with
// `reference`, the estimate at that same size with the full far field
// (e.coarse_estimate where `refined` is e's coarse model at r h; null for
// the fit's own answer where `refined` is at the fit's h); its bias,
// order 1 in its element size, is twice the move, added to
// e.parameter_bias (and kept in e.far_field_bias). A failed refit leaves e
// as it was, far_field_note saying so.
void AddFarFieldError(const ForwardModel& refined, const laws::LawShape& shape,
                      const FitData& data, const FitOptions& options, const FitSummary& fit,
                      const std::array<double, kParameterCount>* reference,
                      ModelErrorEstimate& e);

// Where e's order is not observed (its coarse solves pre-asymptotic), the
// finer side's estimate `finer` (refinement_ratio < 1) may predict more:
// each parameter's bias becomes the larger in magnitude of the two (and the
// reason says which); the finer side's runs and time are added. A finer
// side not estimated is said in the reason and changes nothing else.
void TakeTheLargerBias(const ModelErrorEstimate& finer, ModelErrorEstimate& e);

// The predicted bias of the model's prediction at each data point into `e`:
// output_bias, its rms, its largest magnitude and that relative to the
// prediction there.
void SetOutputBias(std::vector<double> bias, const std::vector<double>& prediction,
                   ModelErrorEstimate& e);

// The total interval of one estimate from its statistical interval [low,
// high] (an open end stays open), the predicted bias and the safety factor.
std::array<double, 2> TotalInterval(double low, double high, double bias, double safety_factor);

// Moves the estimate's model error into `fit`: each estimate keeps its
// statistical interval (statistical_ci95_low/high), gets model_bias, and its
// ci95_low/high become the total interval; delta_c's interval is recomputed
// from the totals of J_B and sigma_c; a J_B lower bound is lowered where
// J_tip,c may be biased low. Nothing changes when the error is not estimated
// (the intervals stay the statistical ones, and the estimate says why).
void ApplyModelError(const ModelErrorEstimate& estimate, FitSummary& fit);

}  // namespace bridgefit::inverse
