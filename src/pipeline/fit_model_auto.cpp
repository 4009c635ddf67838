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
#include "fit_models.hpp"

namespace bridgefit::pipeline {
namespace {

constexpr double kMinCellsThroughArm = 8.0;    // DCB (docs/MPM.md, growth)
constexpr double kMinCellsOverGrowth = 10.0;   // any specimen
constexpr double kConvergenceShare = 0.5;      // of the correction

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

// The cell against the scene: the reasons it is too coarse (empty: none).
std::string CellTooCoarse(const FitRequest& request, const FitModels& models, double cell) {
  const SpecimenSpec& s = request.scene.specimen;
  std::string why;
  if (s.type == SpecimenType::kDCB && s.height / cell < kMinCellsThroughArm)
    why = fmt::format("{:.3g} cells through the DCB arm (h {:.3g} mm; growth needs about {:g}: at "
                      "4 the contour J is 25-33% low, docs/MPM.md)",
                      s.height / cell, s.height * 1e3, kMinCellsThroughArm);
  const double growth = models.data_end() - s.notch;
  if (growth > 0.0 && growth / cell < kMinCellsOverGrowth)
    why += fmt::format("{}{:.3g} cells over the data's {:.3g} mm of crack growth (fewer than {:g})",
                       why.empty() ? "" : "; ", growth / cell, growth * 1e3, kMinCellsOverGrowth);
  return why;
}

// A correction to MPM: MPM at the cell and at half of it, at the final
// parameters. False (with `why`) when the correction is not to be trusted.
bool CorrectionConverged(const FitModels& models, FitRun& run,
                         std::string* why) {
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
    return false;
  }
  if (!at_cell.ok() || !at_half.ok()) {
    *why = fmt::format("MPM at the corrected parameters failed at {:.3g} mm ({})",
                       (at_cell.ok() ? 0.5 : 1.0) * cell * 1e3,
                       at_cell.ok() ? at_half.message : at_cell.message);
    return false;
  }
  run.mpm_convergence = MaxRelativeDifference(at_cell.R, at_half.R);
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
  if (const std::string coarse = CellTooCoarse(request, models, run.mpm_cell); !coarse.empty())
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

}  // namespace bridgefit::pipeline
