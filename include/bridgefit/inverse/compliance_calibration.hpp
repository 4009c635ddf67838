#pragma once
// The model's compliance calibrated to a test record before a
// load-displacement fit (docs/FIT.md "Calibrating the compliance"): real
// records know E and the machine compliance to percents while the fit reads
// sigma_c from ~0.1% of the load.
//
//   initial slope:  f0 = C_model(a0) / C_record(a0), all moduli x f0 (all
//                   moduli by one factor scale an elastic model's compliance
//                   exactly);
//   refinement:     f = argmin chi^2_load(f) by golden section in
//                   [0.96 f0, 1.04 f0] (each chi^2 with the law re-fitted);
//   along crack:    (f, C_s) alternated with the law's fit so that
//                   C_i ~ s C_model(a_i) + C_s at the record's measured
//                   crack lengths (FitComplianceAlongCrack), Anderson-
//                   accelerated, until ln f and C_s / C_ref move < 1e-3.
//
// The caller owns the forward models: a factory rebuilds the model at a
// modulus factor and a series compliance. Throws Error when the model or the
// record cannot give a calibration (bad input), never for a fit that did not
// converge (that is reported).

#include <cmath>
#include <functional>
#include <optional>
#include <string>

#include "bridgefit/core/records.hpp"
#include "bridgefit/inverse/compliance.hpp"
#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/inverse/forward_model.hpp"
#include "bridgefit/laws/law.hpp"

namespace bridgefit::inverse {

enum class ComplianceCalibrationMode {
  kNone,          // the scene's moduli as given
  kInitialSlope,  // initial slope, refined on the whole record (reduced model)
  kAlongCrack,    // modulus scale and series compliance along the measured crack
};
const char* ComplianceCalibrationModeName(ComplianceCalibrationMode mode);  // "", "initial", "crack"
// "" (none), "initial" or "crack"; anything else is an Error (kUsage).
ComplianceCalibrationMode ParseComplianceCalibrationMode(const std::string& name);

struct ComplianceCalibrationOptions {
  ComplianceCalibrationMode mode = ComplianceCalibrationMode::kInitialSlope;
  // The record's initial compliance C0 [m/N] (slope of its loading line);
  // NaN: unknown (no initial-slope factor; along the crack starts at 1).
  double record_initial_compliance = NAN;
  // Golden-section refinement of the initial-slope factor on the whole
  // record (kInitialSlope): false for a model too slow for it (MPM).
  bool refine = true;
  double refine_low = 0.96, refine_high = 1.04;  // search interval [low f0, high f0]
  double refine_tolerance = 2e-4;    // on ln f (the factor to 0.01%)
  int max_rounds = 12;               // along the crack
  double round_tolerance = 1e-3;     // on ln f and C_s / C_ref
  bool IsValid(std::string* why) const;
};

// Rebuilds the forward model with every modulus x `modulus_factor` and
// `series_compliance` [m/N] in series; the pointer stays valid until the
// next call.
using ScaledModelFactory =
    std::function<const ForwardModel*(double modulus_factor, double series_compliance)>;

struct AlongCrackCalibration {
  ComplianceFit fit;  // the last round's compliance fit
  int rounds = 0;
};

struct ComplianceCalibrationResult {
  ComplianceCalibrationMode mode = ComplianceCalibrationMode::kNone;
  double modulus_factor = NAN;           // NaN: not calibrated
  double initial_slope_factor = NAN;     // f0
  double model_initial_compliance = NAN; // the unscaled model's C(a0) [m/N]
  double series_compliance = 0.0;        // [m/N]
  std::optional<AlongCrackCalibration> along_crack;
  int fits = 0, evaluations = 0;  // law fits run by the refinement / rounds
  double wall_s = 0.0;
  std::string note;  // a warning for the reader, or empty
  bool calibrated() const { return std::isfinite(modulus_factor); }
};

// The law a fit ended at: its best parameters, or J_tip,c alone when it
// found no bridging.
LawParameters FittedLaw(const FitSummary& summary);

// Stage 1: the initial-slope factor f0 = C_model(a0) / C0 of the model the
// factory builds at (1, 0). Leaves the result uncalibrated when C0 is unknown.
// `source` names the file in errors.
ComplianceCalibrationResult CalibrateInitialSlope(const ComplianceCalibrationOptions& options,
                                                  const ScaledModelFactory& factory,
                                                  const std::string& source);

// Stage 2 (after the start fit, whose parameters `fit_options.initial`
// holds): refinement on the whole record (kInitialSlope, options.refine) or
// the alternation along the crack (kAlongCrack: `record` with measured crack
// lengths, `notch` [m]). Updates `result`; the factory's last model is not
// necessarily the calibrated one (rebuild it at the result).
void RefineCalibration(const ComplianceCalibrationOptions& options,
                       const ScaledModelFactory& factory, const laws::LawShape& shape,
                       const FitData& load_data, const FitOptions& fit_options,
                       const ExperimentRecord& record, double notch,
                       ComplianceCalibrationResult& result);

}  // namespace bridgefit::inverse
