#include "bridgefit/inverse/compliance_calibration.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"

namespace bridgefit::inverse {

const char* ComplianceCalibrationModeName(ComplianceCalibrationMode mode) {
  switch (mode) {
    case ComplianceCalibrationMode::kInitialSlope: return "initial";
    case ComplianceCalibrationMode::kAlongCrack: return "crack";
    default: return "";
  }
}

ComplianceCalibrationMode ParseComplianceCalibrationMode(const std::string& name) {
  if (name.empty()) return ComplianceCalibrationMode::kNone;
  if (name == "initial") return ComplianceCalibrationMode::kInitialSlope;
  if (name == "crack") return ComplianceCalibrationMode::kAlongCrack;
  throw Error(ErrorKind::kUsage, "unknown compliance calibration",
              {.field = "--calibrate-compliance", .value = name, .expected = "initial or crack"});
}

bool ComplianceCalibrationOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!(record_initial_compliance > 0.0) && !std::isnan(record_initial_compliance))
    return fail("the record's initial compliance must be positive (or NaN: unknown)");
  if (!(refine_low > 0.0 && refine_low < 1.0 && refine_high > 1.0))
    return fail("the refinement interval must hold 1 (0 < refine_low < 1 < refine_high)");
  if (!(refine_tolerance > 0.0)) return fail("refine_tolerance must be positive");
  if (max_rounds < 1) return fail("max_rounds must be 1 or more");
  if (!(round_tolerance > 0.0)) return fail("round_tolerance must be positive");
  return true;
}

LawParameters FittedLaw(const FitSummary& s) {
  return {.sigma_c = s.best_parameters[kSigmaC],
          .J_B = s.bridging_detected ? s.best_parameters[kJB] : 0.0,
          .J_tip_c = s.bridging_detected ? s.best_parameters[kJTipC] : s.J_tip_c.value};
}

ComplianceCalibrationResult CalibrateInitialSlope(const ComplianceCalibrationOptions& options,
                                                  const ScaledModelFactory& factory,
                                                  const std::string& source) {
  ComplianceCalibrationResult result;
  result.mode = options.mode;
  if (options.mode == ComplianceCalibrationMode::kNone ||
      !std::isfinite(options.record_initial_compliance))
    return result;
  // A probe on the linear branch: a displacement far below initiation.
  const double d_probe = 1e-3 * options.record_initial_compliance;
  const ForwardPrediction probe = factory(1.0, 0.0)->PredictLoad(
      laws::MakeLinearShape(), {.sigma_c = 1e6, .J_B = 0.0, .J_tip_c = 1000.0}, {d_probe});
  if (!probe.ok() || probe.load.empty() || !(probe.load[0] > 0.0))
    throw Error(ErrorKind::kRuntime,
                "the model's initial compliance could not be computed: " + probe.message,
                {.file = source});
  result.model_initial_compliance = d_probe / probe.load[0];
  result.modulus_factor = result.model_initial_compliance / options.record_initial_compliance;
  result.initial_slope_factor = result.modulus_factor;
  return result;
}

namespace {

FitOptions QuickFitOptions(FitOptions options) {
  options.profile_likelihood = false;
  options.starts = 1;
  options.progress = false;
  return options;
}

// The initial slope of a record gives its compliance to about 1% (a few
// noisy loading rows); the whole record holds it to about 0.1%: the modulus
// factor minimising the load-displacement chi^2 (each with the law
// re-fitted, no profiles) by golden section within +-4% of f0.
void RefineOnRecord(const ComplianceCalibrationOptions& options, const ScaledModelFactory& factory,
                    const laws::LawShape& shape, const FitData& load_data,
                    const FitOptions& fit_options, ComplianceCalibrationResult& result) {
  const FitOptions quick = QuickFitOptions(fit_options);
  auto chi2_at = [&](double factor) {
    const ForwardModel* model = factory(factor, 0.0);
    ++result.fits;
    const FitSummary q = FitBridgingLaw(*model, shape, load_data, quick);
    result.wall_s += q.wall_s;
    result.evaluations += q.evaluations;
    return q.converged ? q.chi2 : INFINITY;
  };
  constexpr double kGolden = 0.6180339887498949;
  const double f0 = result.initial_slope_factor;
  double lo = std::log(options.refine_low * f0), hi = std::log(options.refine_high * f0);
  double x1 = hi - kGolden * (hi - lo), x2 = lo + kGolden * (hi - lo);
  double f1 = chi2_at(std::exp(x1)), f2 = chi2_at(std::exp(x2));
  while (hi - lo > options.refine_tolerance) {
    if (f1 <= f2) {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - kGolden * (hi - lo);
      f1 = chi2_at(std::exp(x1));
    } else {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + kGolden * (hi - lo);
      f2 = chi2_at(std::exp(x2));
    }
  }
  result.modulus_factor = std::exp(0.5 * (lo + hi));
  // Within 0.1% of an end of +-4%: the minimum may lie outside the interval.
  if (std::abs(std::log(result.modulus_factor / f0)) > 0.039)
    result.note = "compliance: the refined modulus factor is at the edge of +-4% of the "
                  "initial slope's: check the record's first rows";
}

// The record's rows on its loading path (up to the largest displacement)
// with a crack measured beyond the notch and a load above a fifth of the
// peak: displacement, crack length and compliance d / P.
struct CompliancePoints {
  std::vector<double> displacement, crack_length, compliance;
};

CompliancePoints LoadingPathPoints(const ExperimentRecord& record, double notch) {
  CompliancePoints out;
  const std::size_t last =
      std::max_element(record.displacement.begin(), record.displacement.end()) -
      record.displacement.begin();
  const double peak = *std::max_element(record.load.begin(), record.load.end());
  for (std::size_t i = 0; i <= last; ++i)
    if (std::isfinite(record.crack_length[i]) && record.crack_length[i] > notch &&
        record.load[i] >= 0.2 * peak && record.displacement[i] > 0.0) {
      out.displacement.push_back(record.displacement[i]);
      out.crack_length.push_back(record.crack_length[i]);
      out.compliance.push_back(record.displacement[i] / record.load[i]);
    }
  BF_CHECK_INPUT(out.compliance.size() >= 5,
                 fmt::format("{} rows with a crack beyond the notch on the loading path; the "
                             "compliance along the crack needs 5 or more",
                             out.compliance.size()),
                 {.file = record.source, .field = "crack_length"});
  return out;
}

// The fitted model's specimen compliance (d - C_s P) / P against its crack
// length along the fitted path, ascending and unique in crack length.
ComplianceCurve ModelComplianceAlongPath(const ForwardPrediction& p,
                                         const std::vector<double>& displacement,
                                         double series_compliance, double notch) {
  std::vector<std::pair<double, double>> curve;
  for (std::size_t j = 0; j < displacement.size(); ++j)
    if (p.load[j] > 0.0 && p.crack_length_physical[j] > notch)
      curve.emplace_back(p.crack_length_physical[j],
                         (displacement[j] - series_compliance * p.load[j]) / p.load[j]);
  std::sort(curve.begin(), curve.end());
  ComplianceCurve model_curve;
  for (const auto& [crack, compliance] : curve)
    if (model_curve.crack_length.empty() || crack > model_curve.crack_length.back()) {
      model_curve.crack_length.push_back(crack);
      model_curve.compliance.push_back(compliance);
    }
  return model_curve;
}

// A negative series compliance smaller than this fraction of the median
// compliance is within the calibration's scatter.
constexpr double kResolvedSeriesFraction = 2e-3;

// --calibrate-compliance=crack: quick load fit at (f, C_s) -> the model's
// specimen compliance along its fitted path -> a scale s and C_s from the
// record's rows -> f / s and the new C_s (Anderson-accelerated), until ln f
// and C_s / C_ref move by less than the tolerance (C_ref: the median
// compliance of the rows used).
void CalibrateAlongCrack(const ComplianceCalibrationOptions& options,
                         const ScaledModelFactory& factory, const laws::LawShape& shape,
                         const FitData& load_data, const FitOptions& fit_options,
                         const ExperimentRecord& record, double notch,
                         ComplianceCalibrationResult& out) {
  const CompliancePoints rows = LoadingPathPoints(record, notch);
  std::vector<double> sorted = rows.compliance;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double reference = sorted[sorted.size() / 2];
  FitOptions quick = QuickFitOptions(fit_options);
  AlongCrackCalibration& along = out.along_crack.emplace();
  out.modulus_factor = std::isfinite(out.modulus_factor) ? out.modulus_factor : 1.0;
  out.series_compliance = 0.0;
  std::array<double, 2> previous_F{}, previous_g{};
  for (int round = 0; round < options.max_rounds; ++round) {
    const ForwardModel* model = factory(out.modulus_factor, out.series_compliance);
    const FitSummary q = FitBridgingLaw(*model, shape, load_data, quick);
    ++out.fits;
    out.evaluations += q.evaluations;
    out.wall_s += q.wall_s;
    const LawParameters at = FittedLaw(q);
    // A round's fit need not converge to move (f, C_s) on: the final fit
    // reports its own convergence.
    if (!std::isfinite(at.J_tip_c) || !std::isfinite(at.sigma_c))
      throw Error(ErrorKind::kRuntime,
                  "calibrating the compliance along the crack: the law's fit gave no parameters (" +
                      q.stop_reason + ")",
                  {.file = record.source, .field = "--calibrate-compliance", .value = "crack"});
    for (int i = 0; i < kParameterCount; ++i)
      if (std::isfinite(q.best_parameters[i])) quick.initial[i] = q.best_parameters[i];
    if (!q.bridging_detected) quick.initial[kJTipC] = q.J_tip_c.value;
    const ForwardPrediction p = model->PredictLoad(shape, at, rows.displacement);
    if (!p.ok())
      throw Error(ErrorKind::kRuntime,
                  "calibrating the compliance along the crack: the fitted model failed: " +
                      p.message,
                  {.file = record.source, .field = "--calibrate-compliance"});
    const ComplianceCurve model_curve =
        ModelComplianceAlongPath(p, rows.displacement, out.series_compliance, notch);
    // A fit whose law never grows the crack on the record's loading path
    // has no compliance along the crack to compare (the rows' own crack
    // lengths say it grew): said as such, not as rows outside a NaN range.
    if (model_curve.crack_length.size() < 2)
      throw Error(ErrorKind::kRuntime,
                  fmt::format("calibrating the compliance along the crack: round {}'s fit (sigma_c "
                              "{:.4g} MPa, J_B {:.4g} J/m^2, J_tip,c {:.4g} J/m^2) grows the crack "
                              "beyond the notch at {} of the record's {} loading rows (up to {:.4g} "
                              "mm), which measure {:.4g}..{:.4g} mm",
                              round + 1, at.sigma_c * 1e-6, at.J_B, at.J_tip_c,
                              model_curve.crack_length.size(), rows.displacement.size(),
                              rows.displacement.empty() ? NAN : rows.displacement.back() * 1e3,
                              *std::min_element(rows.crack_length.begin(), rows.crack_length.end()) * 1e3,
                              *std::max_element(rows.crack_length.begin(), rows.crack_length.end()) * 1e3) +
                      "; way out: rerun with more --starts, or calibrate on the initial slope "
                      "alone (--calibrate-compliance without =crack)",
                  {.file = record.source, .field = "--calibrate-compliance", .value = "crack",
                   .expected = "a law fit whose crack grows over the record"});
    along.fit = FitComplianceAlongCrack(model_curve, rows.crack_length, rows.compliance, {},
                                        record.source);
    // The fixed point x = (ln f, C_s / C_ref) -> g(x), the values this
    // round's compliance fit asks for. The law's refit moves the bridged
    // compliance against them (on the MDF record plain updates overshoot by
    // 0.65-0.75 of their step and oscillate), so the update is Anderson-
    // accelerated (depth one): x+ = g - theta (g - g_prev),
    // theta = F.(F - F_prev) / |F - F_prev|^2 with F = g - x.
    const std::array<double, 2> x = {std::log(out.modulus_factor),
                                     out.series_compliance / reference};
    const std::array<double, 2> g = {x[0] - std::log(along.fit.scale),
                                     along.fit.series_compliance / reference};
    const std::array<double, 2> F = {g[0] - x[0], g[1] - x[1]};
    std::array<double, 2> next = g;
    if (round > 0) {
      const double d0 = F[0] - previous_F[0], d1 = F[1] - previous_F[1];
      const double norm = d0 * d0 + d1 * d1;
      if (norm > 0.0) {
        const double theta = (F[0] * d0 + F[1] * d1) / norm;
        for (int k = 0; k < 2; ++k) next[k] = g[k] - theta * (g[k] - previous_g[k]);
      }
    }
    previous_F = F, previous_g = g;
    out.modulus_factor = std::exp(x[0] + std::clamp(next[0] - x[0], -0.2, 0.2));
    // A compliance in series is >= 0 (issue 15): FitComplianceAlongCrack
    // holds it there, and so does the accelerated step.
    out.series_compliance = std::max(0.0, next[1] * reference);
    along.rounds = round + 1;
    const bool settled =
        std::abs(F[0]) < options.round_tolerance && std::abs(F[1]) < options.round_tolerance;
    if (settled || (along.fit.series_at_bound && out.series_compliance == 0.0 &&
                    std::abs(F[0]) < options.round_tolerance)) {
      // Only a negative compliance the record resolves says something about
      // the moduli: below 0.2% of the rows' median compliance it is the
      // calibration's own scatter (the whole record holds f to ~0.1%), as on
      // a synthetic record made with none (-3e-8 mm/N against 4.5e-4).
      if (along.fit.series_at_bound &&
          -along.fit.series_unconstrained > kResolvedSeriesFraction * reference)
        out.note = fmt::format(
            "compliance along the crack: the record asks for a negative series compliance "
            "({:.3g} mm/N), held at 0: the model is too compliant at long cracks for a spring to "
            "explain; check the scene's moduli (E, G13) before trusting sigma_c",
            1e3 * along.fit.series_unconstrained);
      return;
    }
  }
  out.note = fmt::format(
      "compliance along the crack: not settled after {} rounds (last scale {:.4f})",
      options.max_rounds, along.fit.scale);
}

}  // namespace

void RefineCalibration(const ComplianceCalibrationOptions& options,
                       const ScaledModelFactory& factory, const laws::LawShape& shape,
                       const FitData& load_data, const FitOptions& fit_options,
                       const ExperimentRecord& record, double notch,
                       ComplianceCalibrationResult& result) {
  if (std::string why; !options.IsValid(&why))
    throw Error(ErrorKind::kUsage, "invalid compliance calibration options: " + why,
                {.field = "--calibrate-compliance"});
  if (options.mode == ComplianceCalibrationMode::kAlongCrack) {
    CalibrateAlongCrack(options, factory, shape, load_data, fit_options, record, notch, result);
  } else if (options.mode == ComplianceCalibrationMode::kInitialSlope && options.refine &&
             std::isfinite(result.initial_slope_factor)) {
    RefineOnRecord(options, factory, shape, load_data, fit_options, result);
  }
}

}  // namespace bridgefit::inverse
