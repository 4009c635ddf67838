// R curves from test records: the stages every method shares (checks,
// cleaning, crack-length noise, validity window, initiation) and the one
// dispatch to the method (rcurve_energy.cpp, rcurve_pointwise.cpp).
#include "bridgefit/experiment/rcurve.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "rcurve_stages.hpp"

namespace bridgefit::experiment {
namespace detail {

LinearFit FitLine(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  LinearFit fit;
  if (n < 2) return fit;
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) mx += x[i], my += y[i];
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  if (!(sxx > 0)) return fit;
  fit.slope = sxy / sxx;
  fit.intercept = my - fit.slope * mx;
  return fit;
}

void AddDropped(RCurveResult& result, const std::string& reason, int count) {
  if (count <= 0) return;
  for (DroppedRows& d : result.dropped)
    if (d.reason == reason) {
      d.count += count;
      return;
    }
  result.dropped.push_back({reason, count});
}

std::string Mm(double metres) { return fmt::format("{:.4g} mm", metres * 1e3); }

void Rows::Truncate(std::size_t n) {
  row.resize(n);
  P.resize(n);
  d.resize(n);
  if (!a_raw.empty()) a_raw.resize(n);
  if (!a.empty()) a.resize(n);
}

void PushPoint(const Prepared& p, RCurveResult& result, int k, double a, double R, double U) {
  result.curve.crack_length.push_back(a);
  result.curve.R.push_back(R);
  result.curve.R_uncertainty.push_back(U);
  result.crack_growth.push_back(a - p.a0);
  result.load.push_back(p.w.P[k]);
  result.displacement.push_back(p.w.d[k]);
  result.rows.push_back(p.w.row[k]);
}

}  // namespace detail

namespace {
using namespace detail;

bool NeedsCrackLength(RMethod m, SpecimenType type) {
  return m == RMethod::kEnergy || m == RMethod::kMbt || m == RMethod::kComplianceCalibration ||
         (m == RMethod::kLefm && type == SpecimenType::kDCB);
}

// "R curve (mbt), initiation: " - every error of the reduction names its stage.
std::string Stage(const RCurveOptions& options, const char* stage) {
  return fmt::format("R curve ({} method), stage '{}': ", RMethodName(options.method), stage);
}

// Errors that no cleaning can fix: time running backwards, a load sign
// convention, crack lengths outside the specimen.
void CheckRecord(const ExperimentRecord& record, const RCurveOptions& options) {
  const std::string& src = record.source;
  const int n = static_cast<int>(record.size());
  BF_CHECK_INPUT(n >= 5, Stage(options, "checks") + "the record is too short for an R curve",
                 {.file = src, .field = "rows", .value = std::to_string(n), .expected = ">= 5 rows"});
  for (int i = 1; i < static_cast<int>(record.time.size()); ++i)
    if (record.time[i] < record.time[i - 1])
      throw Error(ErrorKind::kInput, Stage(options, "checks") + fmt::format("time decreases at row {}", i + 1),
                  {.file = src, .field = "time",
                   .value = fmt::format("{:g} s after {:g} s", record.time[i], record.time[i - 1]),
                   .expected = "non-decreasing time (one test, rows in order); way out: sort the "
                               "rows or split the file into its tests"});
  int negative = 0;
  for (double p : record.load) negative += p < 0.0;
  if (negative > n / 2)
    throw Error(ErrorKind::kInput, Stage(options, "checks") + "the load is negative in most rows",
                {.file = src, .field = "load", .value = fmt::format("{} of {} rows < 0", negative, n),
                 .expected = "tensile (positive) opening load; way out: flip the sign convention "
                             "(e.g. --units load=-N is not supported: negate the column)"});
  const SpecimenSpec& spec = options.specimen;
  const double specimen_end = spec.type == SpecimenType::kCT ? spec.width : spec.length;
  if (!record.has_crack_length()) return;
  for (int i = 0; i < n; ++i) {
    const double a = record.crack_length[i];
    if (std::isnan(a)) continue;  // no reading in this row: the cleaning counts it
    if (!(a > 0.0))
      throw Error(ErrorKind::kInput,
                  Stage(options, "checks") + fmt::format("crack length is not positive in row {}", i + 1),
                  {.file = src, .field = "crack_length", .value = fmt::format("{:g} m", a),
                   .expected = "a > 0, measured from the load line"});
    if (specimen_end > 0.0 && a >= specimen_end)
      throw Error(ErrorKind::kInput,
                  Stage(options, "checks") +
                      fmt::format("crack length in row {} reaches past the specimen", i + 1),
                  {.file = src, .field = "crack_length", .value = Mm(a),
                   .expected = fmt::format("a < {} ({}); check the crack-length unit (--units "
                                           "crack_length=mm)",
                                           Mm(specimen_end), spec.type == SpecimenType::kCT ? "W" : "L")});
  }
}

// Cleaning by named rules (cleaning.hpp) into the envelope rows.
void CleanStage(Prepared& p, RCurveResult& result) {
  const ExperimentRecord& record = *p.record;
  const RCurveOptions& options = *p.options;
  p.cleaned = CleanRecord(record, options.cleaning, p.has_a, options.load_noise,
                          options.displacement_noise);
  // Crack lengths come along where every kept row has one (methods that do
  // not need them still take a0 from the first).
  bool all_read = record.has_crack_length();
  for (int i : p.cleaned.rows) all_read = all_read && std::isfinite(record.crack_length[i]);
  for (int i : p.cleaned.rows) {
    p.w.row.push_back(i);
    p.w.P.push_back(record.load[i]);
    p.w.d.push_back(record.displacement[i]);
    if (all_read) p.w.a_raw.push_back(record.crack_length[i]);
  }
  // The load-fit rows: a missing crack reading does not take a row's load
  // and displacement out of a load-displacement fit.
  bool nan_crack = false;
  if (p.has_a)
    for (double a : record.crack_length) nan_crack |= std::isnan(a);
  result.clean_rows = nan_crack ? CleanRecord(record, options.cleaning, false, options.load_noise,
                                              options.displacement_noise)
                                      .rows
                                : p.cleaned.rows;
  for (const CleaningRule& rule : p.cleaned.rules) AddDropped(result, rule.reason, rule.count);
  result.notes.insert(result.notes.end(), p.cleaned.notes.begin(), p.cleaned.notes.end());
  result.warnings.insert(result.warnings.end(), p.cleaned.warnings.begin(), p.cleaned.warnings.end());
  result.figures["cleaning_unload_reload_cycles"] = static_cast<double>(p.cleaned.cycles.size());
  result.figures["cleaning_glitch_rows"] = static_cast<double>(p.cleaned.glitch_rows.size());
  result.figures["cleaning_jitter_rows"] = p.cleaned.jitter_rows;
  result.figures["cleaning_brief_reversal_rows"] = p.cleaned.brief_reversal_rows;
  result.figures["cleaning_repeated_time_rows"] = p.cleaned.repeated_time_rows;
  p.sigma_P = p.cleaned.load_noise;
  p.sigma_d = p.cleaned.displacement_noise;
  const int m = static_cast<int>(p.w.size());
  if (m >= 5) return;
  std::string counts;
  for (const CleaningRule& rule : p.cleaned.rules)
    counts += fmt::format("{}{} {} (option {})", counts.empty() ? "" : ", ", rule.count, rule.reason,
                          rule.option);
  throw Error(ErrorKind::kInput, Stage(options, "cleaning") + "too few rows left after cleaning",
              {.file = p.src, .field = "rows",
               .value = fmt::format("{} of {} rows", m, record.size()),
               .expected = fmt::format(">= 5 rows; taken out: {}; way out: the option named for "
                                       "the largest count",
                                       counts.empty() ? "none" : counts)});
}

// Crack lengths: isotonic fit, noise for the uncertainty (local scatter
// and reading step) and for the energy increments (scatter about a smooth
// monotone fit), validity window (edge effect).
void CrackLengthStage(Prepared& p, RCurveResult& result) {
  const RCurveOptions& options = *p.options;
  Rows& w = p.w;
  p.sigma_a = 0.0;
  if (!w.a_raw.empty()) {
    w.a = IsotonicIncreasing(w.a_raw);
    int shrinking = 0;
    double running = -INFINITY, worst = 0.0, rss = 0.0;
    for (std::size_t k = 0; k < w.size(); ++k) {
      if (w.a_raw[k] < running) ++shrinking, worst = std::max(worst, running - w.a_raw[k]);
      running = std::max(running, w.a_raw[k]);
      rss += (w.a_raw[k] - w.a[k]) * (w.a_raw[k] - w.a[k]);
    }
    if (shrinking > 0)
      result.notes.push_back(fmt::format(
          "crack length decreased in {} rows (largest drop {}): replaced by the isotonic "
          "(non-decreasing) least-squares fit",
          shrinking, Mm(worst)));
    result.figures["crack_rows_decreasing"] = shrinking;
    // Reading resolution: typical non-zero step of the smoothed crack length.
    std::vector<double> steps;
    for (std::size_t k = 1; k < w.size(); ++k)
      if (w.a[k] > w.a[k - 1]) steps.push_back(w.a[k] - w.a[k - 1]);
    double q = 0.0;
    if (!steps.empty()) {
      std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
      q = steps[steps.size() / 2];
    }
    // Scatter about an 11-row moving average catches tracking noise and
    // stick-slip jumps that the isotonic fit alone would absorb.
    const double scatter = ScatterAboutMovingAverage(w.a_raw, 5);
    const double estimate =
        std::sqrt(std::max(scatter * scatter, rss / std::max<std::size_t>(1, w.size())) + q * q / 12.0);
    result.figures["crack_scatter_m"] = scatter;
    p.sigma_a = std::isnan(options.crack_length_noise) ? estimate : options.crack_length_noise;
    p.sigma_a = std::max(p.sigma_a, 1e-9 * w.a.back());
  } else if (!std::isnan(options.crack_length_noise)) {
    p.sigma_a = options.crack_length_noise;
  }
  p.sigma_a_increment = p.sigma_a;
  if (p.sigma_a > 0.0) result.figures["crack_length_noise_m"] = p.sigma_a;

  double a_limit = options.max_crack_length;
  const SpecimenSpec& spec = options.specimen;
  if (std::isnan(a_limit)) {
    if (p.is_ct && spec.width > 0) a_limit = 0.9 * spec.width;
    if (!p.is_ct && spec.length > 0 && spec.height > 0) a_limit = spec.length - 4.0 * spec.height;
  }
  p.a_limit = a_limit;
  if (!w.a.empty() && std::isfinite(a_limit)) {
    std::size_t k = 0;
    while (k < w.size() && w.a[k] <= a_limit) ++k;
    if (k < w.size()) {
      const int past = static_cast<int>(w.size() - k);
      AddDropped(result, fmt::format("past the validity limit a > {} (edge effect)", Mm(a_limit)),
                 past);
      if (past > options.cleaning.warn_fraction * p.record->size())
        result.warnings.push_back(fmt::format(
            "{}: rule 'past the validity limit' took {} of {} rows ({:.1f}%) out of the R curve; "
            "its limit is set by --max-crack-length (now {})",
            p.src, past, p.record->size(), 100.0 * past / p.record->size(), Mm(a_limit)));
      w.Truncate(k);
    }
  }
  if (std::isfinite(a_limit)) result.figures["validity_max_crack_length_m"] = a_limit;
}

// Initiation: d = d0 + C0 P on the loading rows, NL, 5% offset / max, visual.
void InitiationStage(Prepared& p, RCurveResult& result) {
  const RCurveOptions& options = *p.options;
  const Rows& w = p.w;
  const int m = static_cast<int>(w.size());
  BF_CHECK_INPUT(m >= 5, Stage(options, "validity window") + "too few rows below the validity limit",
                 {.file = p.src, .field = "crack_length", .value = std::to_string(m) + " rows",
                  .expected = ">= 5 rows; way out: --max-crack-length"});
  int imax = 0;
  for (int k = 1; k < m; ++k)
    if (w.P[k] > w.P[imax]) imax = k;
  const double Pmax = w.P[imax];
  BF_CHECK_INPUT(Pmax > 0.0, Stage(options, "initiation") + "the load is never positive",
                 {.file = p.src, .field = "load"});
  std::vector<double> fit_P, fit_d;
  int last_fit = -1;
  for (int k = 0; k <= imax; ++k)
    if (w.P[k] >= options.linear_fit_low * Pmax && w.P[k] <= options.linear_fit_high * Pmax) {
      fit_P.push_back(w.P[k]);
      fit_d.push_back(w.d[k]);
      last_fit = k;
    }
  if (fit_P.size() < 3)
    throw Error(ErrorKind::kInput,
                Stage(options, "initiation") + "too few loading rows to fit the initial compliance",
                {.file = p.src, .field = "load",
                 .value = fmt::format("{} of {} rows kept after cleaning", fit_P.size(), m),
                 .expected = fmt::format(
                     ">= 3 rows with {:g}..{:g} x max load ({:.4g} N) before the maximum; way out: "
                     "a record that samples the loading, or --method equivalent|lefm with a "
                     "given --notch",
                     options.linear_fit_low, options.linear_fit_high, Pmax)});
  p.lin = FitLine(fit_P, fit_d);
  BF_CHECK_INPUT(p.lin.slope > 0, Stage(options, "initiation") + "the initial loading is not stiff and linear",
                 {.file = p.src, .field = "displacement",
                  .expected = "displacement growing with load on the loading rows"});
  Initiation& init = result.initiation;
  init.initial_compliance = p.lin.slope;
  init.displacement_offset = p.lin.intercept;
  init.max_load_row = w.row[imax];
  int nl = -1, off = -1;
  for (int k = last_fit + 1; k < m; ++k) {
    if (!(w.P[k] > 0)) continue;
    const double C = (w.d[k] - p.lin.intercept) / w.P[k];
    const double noise =
        3.0 * (p.sigma_d / std::max(w.d[k] - p.lin.intercept, 1e-300) + p.sigma_P / w.P[k]);
    if (nl < 0 && C > p.lin.slope * (1.0 + options.nonlinearity_tolerance + noise)) nl = k;
    if (off < 0 && C >= p.lin.slope * (1.0 + options.offset_fraction)) off = k;
  }
  if (off < 0 || off > imax) off = imax;
  if (nl < 0) nl = off;
  p.imax = imax, p.nl = nl, p.off = off;
  init.nonlinearity_row = w.row[nl];
  init.offset_row = w.row[off];

  const SpecimenSpec& spec = options.specimen;
  p.a0 = spec.notch;
  if (!w.a.empty()) {
    // a0: the median reading of the rows up to NL (no growth before it), so
    // neither a noisy first reading nor a trimmed preload row sets it.
    std::vector<double> before(w.a_raw.begin(), w.a_raw.begin() + nl + 1);
    std::nth_element(before.begin(), before.begin() + before.size() / 2, before.end());
    p.a0 = std::min(before[before.size() / 2], w.a[nl]);
    for (int k = 0; k < m; ++k)
      if (w.a[k] > p.a0 + p.sigma_a) {
        p.first_growth = k;
        break;
      }
    if (p.first_growth < 0)
      throw Error(ErrorKind::kInput,
                  Stage(options, "initiation") + "the crack length never grows beyond its noise",
                  {.file = p.src, .field = "crack_length",
                   .value = fmt::format("growth {} over {} rows kept, noise {}", Mm(w.a.back() - p.a0),
                                        m, Mm(p.sigma_a)),
                   .expected = fmt::format("growth > {}; way out: check the crack_length column "
                                           "and unit, give --crack-noise, or --method equivalent",
                                           Mm(p.sigma_a))});
    init.visual_row = w.row[p.first_growth];
    if (spec.notch > 0 && std::abs(p.a0 - spec.notch) > 0.1 * spec.notch)
      result.notes.push_back(fmt::format("first crack length {} differs from the notch {} by > 10%",
                                         Mm(p.a0), Mm(spec.notch)));
  }
  result.curve.initial_crack_length = p.a0;
  result.figures["initial_compliance_m_per_N"] = p.lin.slope;
  result.figures["displacement_offset_m"] = p.lin.intercept;
}

// Crack-length noise, continued. DCB: tracked crack lengths often lag and
// jump (errors correlated over many rows, invisible to the local scatter);
// their distance from the fitted compliance law C^(1/3) = s (a + Delta), in
// crack-length units, bounds that error from below and is used for the
// uncertainty when larger. The energy method's increment is set apart from
// that: by the readings' own scatter about a smooth monotone fit (isotonic,
// then an 11-row moving average), which the compliance law's own misfit
// does not inflate.
void CrackNoiseStage(Prepared& p, RCurveResult& result) {
  const RCurveOptions& options = *p.options;
  const Rows& w = p.w;
  const int m = static_cast<int>(w.size());
  if (p.first_growth < 0 || !std::isnan(options.crack_length_noise)) {
    result.crack_length_noise = p.sigma_a;
    return;
  }
  if (!p.is_ct) {
    std::vector<double> x, y;
    for (int k = p.first_growth; k < m; ++k)
      if (w.P[k] > 0 && w.d[k] > 0) {
        x.push_back(w.a_raw[k]);
        y.push_back(std::cbrt(w.d[k] / w.P[k]));
      }
    const LinearFit fit = x.size() >= 10 ? FitLine(x, y) : LinearFit{};
    if (fit.slope > 0) {
      double ss = 0.0;
      for (std::size_t k = 0; k < x.size(); ++k) {
        const double r = (y[k] - fit.intercept - fit.slope * x[k]) / fit.slope;
        ss += r * r;
      }
      const double residual = std::sqrt(ss / x.size());
      result.figures["crack_compliance_residual_m"] = residual;
      if (residual > p.sigma_a) {
        p.sigma_a = residual;
        result.notes.push_back(fmt::format(
            "crack-length noise for the uncertainty taken from the scatter about the compliance "
            "law C^(1/3) linear in a ({}), larger than the local scatter",
            Mm(residual)));
      }
    }
  }
  // Smooth monotone fit of the growth rows: isotonic, then a centred moving
  // average over 11 rows (a mean of a non-decreasing run stays non-decreasing).
  const int first = p.first_growth;
  const int count = m - first;
  if (count >= 11) {
    std::vector<double> iso(w.a.begin() + first, w.a.end());
    double ss = 0.0;
    for (int k = 0; k < count; ++k) {
      const int lo = std::max(0, k - 5), hi = std::min(count - 1, k + 5);
      double mean = 0.0;
      for (int q = lo; q <= hi; ++q) mean += iso[q];
      mean /= hi - lo + 1;
      const double r = w.a_raw[first + k] - mean;
      ss += r * r;
    }
    const double smooth_scatter = std::sqrt(ss / count);
    result.figures["crack_scatter_about_monotone_fit_m"] = smooth_scatter;
    p.sigma_a_increment = std::max(std::min(p.sigma_a, smooth_scatter), 1e-9 * w.a.back());
  }
  result.crack_length_noise = p.sigma_a;
}

}  // namespace

EnergyIncrementLimit EnergyIncrementLimitOf(const RCurveOptions& options, double floor) {
  if (options.min_crack_increment > 0 && options.min_crack_increment >= floor)
    return EnergyIncrementLimit::kAsked;
  return options.smoothing_half_window > 0 ? EnergyIncrementLimit::kSmoothed
                                           : EnergyIncrementLimit::kScatter;
}

const char* RMethodName(RMethod method) {
  switch (method) {
    case RMethod::kEnergy: return "energy";
    case RMethod::kMbt: return "mbt";
    case RMethod::kComplianceCalibration: return "cc";
    case RMethod::kLefm: return "lefm";
    case RMethod::kEquivalentCrack: return "equivalent";
  }
  return "?";
}

RMethod ParseRMethod(const std::string& name) {
  for (RMethod m : {RMethod::kEnergy, RMethod::kMbt, RMethod::kComplianceCalibration,
                    RMethod::kLefm, RMethod::kEquivalentCrack})
    if (name == RMethodName(m)) return m;
  throw Error(ErrorKind::kUsage, "unknown R-curve method",
              {.field = "--method", .value = name,
               .expected = "one of energy, mbt, cc, lefm, equivalent"});
}

bool RCurveOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!(coverage_factor > 0)) return fail("coverage_factor must be > 0");
  if (!cleaning.IsValid(why)) return false;
  if (!(increment_resolution >= 0) || !(min_crack_increment >= 0))
    return fail("increment settings must be >= 0");
  if (smoothing_half_window < 0) return fail("smoothing_half_window must be >= 0 (0: no smoothing)");
  if (smoothing_half_window > 0 && method != RMethod::kEnergy)
    return fail("smoothing_half_window applies to the energy method only");
  if (!(linear_fit_low >= 0 && linear_fit_low < linear_fit_high && linear_fit_high <= 1))
    return fail("need 0 <= linear_fit_low < linear_fit_high <= 1");
  if (!(nonlinearity_tolerance > 0 && offset_fraction > 0))
    return fail("nonlinearity_tolerance and offset_fraction must be > 0");
  for (double v : {load_noise, displacement_noise, crack_length_noise})
    if (!std::isnan(v) && !(v >= 0)) return fail("noise levels must be >= 0 (or NaN: estimate)");
  if (specimen.CrackFrontWidth() <= 0)
    return fail(specimen.type == SpecimenType::kCT
                    ? "CT needs the thickness B (specimen.thickness)"
                    : "DCB needs the width b (specimen.width)");
  if (specimen.type == SpecimenType::kCT && !(specimen.width > 0) &&
      (method == RMethod::kLefm || method == RMethod::kEquivalentCrack))
    return fail("CT lefm/equivalent need the width W (specimen.width)");
  if (specimen.type == SpecimenType::kDCB && !(specimen.height > 0) &&
      (method == RMethod::kLefm || method == RMethod::kEquivalentCrack))
    return fail("DCB lefm/equivalent need the arm thickness h (specimen.height)");
  if (std::isinf(given_mbt_delta) || !(std::isnan(given_cc_exponent) || given_cc_exponent > 0))
    return fail("a given compliance calibration needs a finite Delta and n > 0 (NaN: fitted)");
  if (!(load_block_offset >= 0) || !(load_block_half_length >= 0))
    return fail("load-block offset t and half length L' must be >= 0");
  if (large_displacement_correction &&
      (specimen.type != SpecimenType::kDCB ||
       (method != RMethod::kMbt && method != RMethod::kComplianceCalibration)))
    return fail("the large-displacement (F, N) corrections apply to DCB mbt and cc only");
  return true;
}

int RCurveResult::DroppedTotal() const {
  int total = 0;
  for (const DroppedRows& d : dropped) total += d.count;
  return total;
}

std::string RCurveResult::BriefReport() const {
  std::string text = fmt::format("R curve ({}, {}): {} points from {} rows; {} rows dropped",
                                 curve.method, curve.r_kind, curve.size(), points_used,
                                 DroppedTotal());
  for (const DroppedRows& d : dropped) text += fmt::format("\n  dropped {:5d}: {}", d.count, d.reason);
  text += fmt::format("\n  a0 = {}, initiation R = {:.5g} J/m^2", Mm(curve.initial_crack_length),
                      curve.initiation_R);
  text += fmt::format("\n  noise (1 sigma): load {:.3g} N, displacement {:.3g} mm, crack {:.3g} mm",
                      load_noise, displacement_noise * 1e3, crack_length_noise * 1e3);
  for (const auto& [key, value] : figures) text += fmt::format("\n  {} = {:.6g}", key, value);
  for (const std::string& n : notes) text += "\n  note: " + n;
  for (const std::string& n : warnings) text += "\n  warning: " + n;
  text += fmt::format("\n  {:.3f} s", wall_s);
  return text;
}
RCurveResult ComputeRCurve(const ExperimentRecord& record, const RCurveOptions& options) {
  Stopwatch watch;
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid R-curve options: " + why);
  record.Validate();
  const RMethod method = options.method;
  const SpecimenSpec& spec = options.specimen;
  if (NeedsCrackLength(method, spec.type) && !record.has_crack_length())
    throw Error(ErrorKind::kInput,
                Stage(options, "checks") +
                    fmt::format("the {} method needs a crack-length column", RMethodName(method)),
                {.file = record.source, .field = "crack_length",
                 .expected = "a crack_length column (--columns crack_length=NAME); way out: "
                             "--method equivalent, which takes the crack length from the compliance"});
  CheckRecord(record, options);

  RCurveResult result;
  result.curve.method = RMethodName(method);
  result.curve.r_kind = method == RMethod::kEnergy ? "energy" : "elastic-zone";
  result.curve.source = record.source;
  result.curve.uncertainty_coverage = options.coverage_factor;

  Prepared p;
  p.record = &record;
  p.options = &options;
  p.src = record.source;
  p.is_ct = spec.type == SpecimenType::kCT;
  p.B = spec.CrackFrontWidth();
  p.has_a = record.has_crack_length() && method != RMethod::kEquivalentCrack;
  CleanStage(p, result);
  CrackLengthStage(p, result);
  InitiationStage(p, result);
  CrackNoiseStage(p, result);
  result.load_noise = p.sigma_P;
  result.displacement_noise = p.sigma_d;
  result.crack_length_noise = p.sigma_a;

  switch (method) {
    case RMethod::kEnergy: EnergyMethod(p, result); break;
    case RMethod::kMbt:
    case RMethod::kComplianceCalibration: BeamMethod(p, result); break;
    case RMethod::kLefm: p.is_ct ? CtMethod(p, result) : DcbLefmMethod(p, result); break;
    case RMethod::kEquivalentCrack:
      p.is_ct ? CtMethod(p, result) : DcbEquivalentMethod(p, result);
      break;
  }
  result.wall_s = watch.Seconds();
  return result;
}

}  // namespace bridgefit::experiment
