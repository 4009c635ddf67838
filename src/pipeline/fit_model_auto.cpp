// --model auto never passes silently (issue 17): the checks after the
// reduced fit was checked (and perhaps corrected) by MPM (fit_models.hpp).
//
//   coverage  - the MPM run did not reach the data's crack lengths, or
//               failed: the check did not complete; said, with the way out
//   cell      - too few MPM cells through a DCB arm (docs/MPM.md: about 8
//               needed; at 4 the contour J is 25-33% low) or over the
//               data's crack growth: the check's own error is large
//   converged - a correction is accepted only when MPM at half the cell,
//               at the corrected parameters, differs from MPM at the cell
//               by less than half the correction (MPM's own error must not
//               be what it corrects); otherwise the reduced fit is
//               reported, warned

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/inverse/model_check.hpp"
#include "bridgefit/inverse/model_error.hpp"
#include "bridgefit/mpm/growth.hpp"
#include "fit_models.hpp"

namespace bridgefit::pipeline {
namespace {

constexpr double kMinCellsOverGrowth = 10.0;   // any specimen
constexpr double kConvergenceShare = 0.5;      // of the correction (or of the tolerance)
constexpr double kMaxAutoCell = 2.5e-3;        // [m], --mpm-cell auto's coarsest

// Max |b / a - 1| over points where both are finite; NaN when none is.
double MaxRelativeDifference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = NAN;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    if (!std::isfinite(a[i]) || !std::isfinite(b[i]) || a[i] == 0.0) continue;
    const double d = std::abs(b[i] / a[i] - 1.0);
    if (!(d <= worst)) worst = d;
  }
  return worst;
}

// max |R(cell / 2) / R(cell) - 1| of MPM at the final parameters over the
// check's crack lengths; NaN with `why` when either run fails. `step` (may
// be null) gets R(cell / 2) - R(cell) there [J/m^2].
double MpmHalvingStep(const FitModels& models, const FitRun& run, std::string* why,
                      std::vector<double>* step = nullptr) {
  const inverse::ModelCheckResult& c = run.model_check;
  const inverse::LawParameters p = inverse::FittedLaw(run.summary);
  const double cell = run.mpm_cell;
  const inverse::RKind kind = run.data.kind;
  inverse::ForwardPrediction at_cell, at_half;
  try {
    at_cell = models.accurate()->Predict(run.shape, p, c.crack_length, kind);
    at_half = models.MpmAt(0.5 * cell)->Predict(run.shape, p, c.crack_length, kind);
  } catch (const Error& e) {
    *why = fmt::format("MPM at {:.3g} mm could not run ({})", 0.5 * cell * 1e3, e.what());
    return NAN;
  }
  if (!at_cell.ok() || !at_half.ok()) {
    *why = fmt::format("MPM at the final parameters failed at {:.3g} mm ({})",
                       (at_cell.ok() ? 0.5 : 1.0) * cell * 1e3,
                       at_cell.ok() ? at_half.message : at_cell.message);
    return NAN;
  }
  if (step) {
    step->resize(at_cell.R.size());
    for (std::size_t i = 0; i < at_cell.R.size() && i < at_half.R.size(); ++i)
      (*step)[i] = at_half.R[i] - at_cell.R[i];
  }
  return MaxRelativeDifference(at_cell.R, at_half.R);
}

// MPM's own error at its cell h (R(h) minus the converged R), order 1: from
// a step to h / 2, R(h) - R(h / 2) = C h / 2 gives 2 (R(h) - R(h / 2)); from
// the step that led to h, R(2 h) - R(h) = C h gives it once.
std::vector<double> MpmErrorFromStep(const std::vector<double>& step, bool to_half_cell) {
  std::vector<double> error(step.size());
  for (std::size_t i = 0; i < step.size(); ++i) error[i] = (to_half_cell ? -2.0 : -1.0) * step[i];
  return error;
}

}  // namespace

std::string MpmCellTooCoarse(const FitRequest& request, const FitModels& models, double cell) {
  const SpecimenSpec& s = request.scene.specimen;
  std::string why = mpm::GrowthCellTooCoarse(s, cell);
  const double growth = models.data_end() - s.notch;
  if (growth > 0.0 && growth / cell < kMinCellsOverGrowth)
    why += fmt::format("{}{:.3g} cells over the data's {:.3g} mm of crack growth (fewer than {:g})",
                       why.empty() ? "" : "; ", growth / cell, growth * 1e3, kMinCellsOverGrowth);
  return why;
}

namespace {

// A correction to MPM: MPM at the cell and at half of it, at the final
// parameters (computed once: FitCheckedByMpm may have). False (with `why`)
// when the correction is not to be trusted.
bool CorrectionConverged(const FitModels& models, FitRun& run, std::string* why) {
  const inverse::ModelCheckResult& c = run.model_check;
  const double cell = run.mpm_cell;
  // --mpm-cell auto computed the step at this cell already (NaN: it failed, said there).
  if (std::isnan(run.mpm_convergence) && run.mpm_cell_choice.empty()) {
    std::vector<double> step;
    run.mpm_convergence = MpmHalvingStep(models, run, why, &step);
    run.mpm_error_R = MpmErrorFromStep(step, true);
    run.mpm_error_from_cell = 0.5 * cell;
  }
  if (std::isnan(run.mpm_convergence)) {
    if (why->empty()) *why = fmt::format("MPM at {:.3g} mm failed", 0.5 * cell * 1e3);
    return false;
  }
  const double correction = c.discrepancy_at_cheap_optimum;
  const double limit = kConvergenceShare * correction;
  if (run.mpm_convergence <= limit) return true;
  *why = fmt::format(
      "MPM at {:.3g} mm is not converged enough for its correction: its R moves by {:.2f}% at "
      "{:.3g} mm, the correction was {:.2f}% (accepted when below {:.2f}%)",
      cell * 1e3, 100 * run.mpm_convergence, 0.5 * cell * 1e3, 100 * correction, 100 * limit);
  return false;
}

}  // namespace

double CoarsestMpmCell(const SpecimenSpec& s, double data_end) {
  double cell = kMaxAutoCell;
  if (s.type == SpecimenType::kDCB) cell = std::min(cell, s.height / mpm::kMinGrowthCellsThroughArm);
  const double growth = data_end - s.notch;
  if (growth > 0.0) cell = std::min(cell, growth / kMinCellsOverGrowth);
  return cell;
}

void FitCheckedByMpm(const FitRequest& request, FitModels& models, const inverse::FitData& data,
                     const inverse::FitOptions& options, FitRun& run) {
  const bool auto_cell = !std::isfinite(request.mpm_cell);
  const double finest = models.mpm_cell() / std::pow(2.0, request.mpm_cell_halvings);
  const double limit = kConvergenceShare * request.model_tolerance;
  std::string tried, verdict;
  double step_to_here = NAN;  // MPM's R step from the coarser cell to this one (none at first)
  std::vector<double> step_vector;  // the same at each data crack length [J/m^2]
  for (;;) {
    run.summary = inverse::FitWithModelCheck(models.model(), *models.accurate(), run.shape, data,
                                             options, run.check, &run.model_check);
    run.model_note = "auto: " + run.model_check.outcome;
    run.mpm_cell = models.mpm_cell();
    run.mpm_convergence = NAN;
    run.mpm_error_R.clear();
    if (!auto_cell) return;
    if (!run.model_check.accurate_ok) {
      verdict = "not verified: the check did not complete";
      break;
    }
    // MPM's own error at a halved cell is, to order 1, the step that led to
    // it (R(h) - R(h/2) = C h/2): accepted without a finer run when small.
    if (step_to_here <= limit) {
      run.mpm_convergence = 0.5 * step_to_here;  // its step to half the cell, order 1
      run.mpm_error_R = MpmErrorFromStep(step_vector, false);
      run.mpm_error_from_cell = 2.0 * run.mpm_cell;
      tried += fmt::format(", {:.3g} mm {:.2f}% (the step from the coarser cell)",
                           run.mpm_cell * 1e3, 100 * step_to_here);
      verdict = "accepted";
      break;
    }
    // Otherwise: twice its step to half the cell (order 1).
    std::string why;
    run.mpm_convergence = MpmHalvingStep(models, run, &why, &step_vector);
    run.mpm_error_R = MpmErrorFromStep(step_vector, true);
    run.mpm_error_from_cell = 0.5 * run.mpm_cell;
    const double error = 2.0 * run.mpm_convergence;
    tried += fmt::format("{}{:.3g} mm {}", tried.empty() ? "" : ", ", run.mpm_cell * 1e3,
                         std::isnan(error) ? "unknown" : fmt::format("{:.2f}%", 100 * error));
    if (error <= limit) {
      verdict = "accepted";
      break;
    }
    if (std::isnan(error)) {
      verdict = "not verified";
      run.model_check_warning = fmt::format(
          "--mpm-cell auto: MPM's own error at {:.3g} mm is unknown ({}): the check is "
          "unverified; pass --mpm-cell, or --model reduced",
          run.mpm_cell * 1e3, why);
      break;
    }
    if (0.5 * run.mpm_cell < finest * (1.0 - 1e-9)) {
      verdict = "not converged enough";
      run.model_check_warning = fmt::format(
          "--mpm-cell auto: MPM's own error at the finest cell tried, {:.3g} mm, is {:.2f}%, "
          "above half the tolerance ({:.2f}%): the check cannot resolve R differences that "
          "small; pass a finer --mpm-cell or a larger --model-tolerance",
          run.mpm_cell * 1e3, 100 * error, 100 * limit);
      break;
    }
    models.UseMpmCell(0.5 * run.mpm_cell);
    step_to_here = run.mpm_convergence;
  }
  run.mpm_cell_choice = fmt::format(
      "--mpm-cell auto: {:.3g} mm, {} (MPM's own error, twice its R step to half the cell, "
      "accepted below half the tolerance, {:.2f}%; tried: {})",
      run.mpm_cell * 1e3, verdict, 100 * limit, tried.empty() ? "none" : tried);
}

void CheckModelAuto(const FitRequest& request, const FitModels& models,
                    const inverse::FitData& data, const inverse::FitOptions& options, FitRun& run) {
  if (!run.model_checked || !models.accurate()) return;
  std::vector<std::string> warnings;
  const inverse::ModelCheckResult& c = run.model_check;
  if (!c.accurate_ok)
    warnings.push_back(fmt::format(
        "the MPM check did not complete ({}); the reduced fit is unchecked: a finer --mpm-cell "
        "(now {:.3g} mm) or --model reduced",
        c.outcome, run.mpm_cell * 1e3));
  if (const std::string coarse = MpmCellTooCoarse(request, models, run.mpm_cell); !coarse.empty())
    warnings.push_back(fmt::format("the MPM cell {:.3g} mm is too coarse for this scene: {}; "
                                   "refine --mpm-cell",
                                   run.mpm_cell * 1e3, coarse));
  if (c.corrected) {
    std::string why;
    if (!CorrectionConverged(models, run, &why)) {
      // The reduced fit, as it was before the check.
      run.summary = inverse::FitBridgingLaw(models.model(), run.shape, data, options);
      run.model_note = "auto: correction not accepted (" + why + "); the reduced fit is reported";
      warnings.push_back("--model auto did not accept the correction to MPM: " + why +
                         "; the reduced fit is reported (refine --mpm-cell to check it)");
    } else {
      run.model_note += fmt::format("; MPM converged for it: {:.2f}% between {:.3g} and {:.3g} mm",
                                    100 * run.mpm_convergence, run.mpm_cell * 1e3,
                                    0.5 * run.mpm_cell * 1e3);
    }
  }
  for (const std::string& w : warnings)
    run.model_check_warning += (run.model_check_warning.empty() ? "" : "; ") + w;
}

inverse::ModelErrorEstimate MpmCorrectionError(const FitModels& models,
                                               const inverse::FitData& data,
                                               const inverse::FitOptions& options,
                                               const FitRun& run) {
  inverse::ModelErrorEstimate e;
  e.model = "mpm";
  e.quantity = "R";
  e.resolution = run.mpm_cell;
  const inverse::ModelCheckResult& c = run.model_check;
  if (run.mpm_error_R.empty() || run.mpm_error_R.size() != c.crack_length.size()) {
    e.reason = fmt::format(
        "the fit is the reduced model corrected to MPM at {:.3g} mm, whose own error at the "
        "data is not known (no MPM run at another cell at these parameters)",
        run.mpm_cell * 1e3);
    return e;
  }
  Stopwatch clock;
  e.status = inverse::ModelErrorStatus::kOrderNotObserved;
  e.reason = "MPM at two cells only; order 1 from its cell-size study, docs/MPM.md";
  e.coarse_resolution = run.mpm_error_from_cell;
  e.order_used = 1.0;
  e.safety_factor = inverse::ModelErrorOptions{}.unverified_safety_factor;
  inverse::SetOutputBias(run.mpm_error_R, c.R_accurate, e);
  e.parameter_bias = inverse::CorrectedFitBias(models.model(), c, run.shape, data, options,
                                               run.summary, run.mpm_error_R, &e.runs);
  if (!std::isfinite(e.parameter_bias[inverse::kJTipC])) {
    e.status = inverse::ModelErrorStatus::kNotEstimated;
    e.reason = "the refit of the corrected model without MPM's own error failed";
  }
  e.wall_s = clock.Seconds();
  return e;
}

}  // namespace bridgefit::pipeline
