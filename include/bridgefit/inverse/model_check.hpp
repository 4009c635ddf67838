#pragma once
// "Model no more than a scene needs" (--model auto): fit with a cheap forward
// model, check the optimum with an accurate one and, when they disagree by
// more than a tolerance, correct the cheap model by output space mapping:
//   s_k(p) = c(p) + [f(p_k) - c(p_k)]   (the accurate-minus-cheap residual at
// the last iterate, interpolated in crack length), refit s_k -> p_{k+1},
// until the parameters stop moving. Each accurate run is one forward
// simulation at the current parameters, so a correction costs a few accurate
// runs instead of a fit's hundreds.

#include <string>
#include <vector>

#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/inverse/forward_model.hpp"

namespace bridgefit::inverse {

struct ModelCheckOptions {
  // Largest |R_accurate / R_cheap - 1| over the data's crack lengths at the
  // cheap optimum accepted without correction.
  double tolerance = 0.03;
  int max_corrections = 4;          // space-mapping iterations
  // Relative change of every free parameter that ends the iterations.
  double parameter_tolerance = 0.005;
  bool IsValid(std::string* why) const;
};

struct ModelCheckResult {
  std::string cheap_model, accurate_model;
  std::string outcome;        // one sentence: accepted / corrected / failed
  bool accurate_ok = false;   // the accurate model ran at the final parameters
  bool corrected = false;
  int corrections = 0;        // space-mapping iterations done
  int accurate_runs = 0;
  double cheap_fit_s = 0.0;   // the first (cheap) fit
  double accurate_s = 0.0;    // all accurate runs
  double correction_fit_s = 0.0;  // refits of the corrected model
  double discrepancy_at_cheap_optimum = NAN;  // max |R_acc / R_cheap - 1|
  double discrepancy_final = NAN;  // max |R_acc / R_used - 1| at the final parameters
  std::array<double, kParameterCount> cheap_optimum = {NAN, NAN, NAN};
  std::array<double, kParameterCount> final_parameters = {NAN, NAN, NAN};
  // At the final parameters, at the data's crack lengths [m], [J/m^2].
  std::vector<double> crack_length, R_cheap, R_accurate;
};

// Fits with `cheap`, checks with `accurate`, corrects when needed. The
// returned summary is the cheap fit (accepted) or the fit of the corrected
// model (its intervals and profiles from that model); every estimate's
// decided_by says which. A failed accurate run leaves the cheap fit with the
// failure in `result->outcome`, never throws.
FitSummary FitWithModelCheck(const ForwardModel& cheap, const ForwardModel& accurate,
                             const laws::LawShape& shape, const FitData& data,
                             const FitOptions& options, const ModelCheckOptions& check,
                             ModelCheckResult* result);

// The bias of a corrected fit's parameters from the accurate model's own
// discretisation error (issue 17: model error in every interval).
// `accurate_error` is that error of the accurate R at result.crack_length
// (the accurate R minus its converged R [J/m^2]; for MPM, from a halved
// cell at order 1). The corrected model is rebuilt with the converged
// accurate R (its offset less the error) and refitted without profiles from
// the fit's optimum; each free parameter's bias is the fit's value minus the
// refit's (0 for fixed ones, NaN for all when the refit fails or the
// sizes differ). `runs` (may be null) gets the forward runs spent.
std::array<double, kParameterCount> CorrectedFitBias(const ForwardModel& cheap,
                                                     const ModelCheckResult& result,
                                                     const laws::LawShape& shape,
                                                     const FitData& data, const FitOptions& options,
                                                     const FitSummary& fit,
                                                     const std::vector<double>& accurate_error,
                                                     int* runs = nullptr);

}  // namespace bridgefit::inverse
