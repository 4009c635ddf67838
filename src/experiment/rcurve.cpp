// R curves from test records: cleaning, initiation, validity window and the
// five reductions of include/bridgefit/experiment/rcurve.hpp.
#include "bridgefit/experiment/rcurve.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/specimen/calibrations.hpp"

namespace bridgefit::experiment {
namespace {

struct LinearFit {
  double slope = NAN;
  double intercept = NAN;
};

LinearFit FitLine(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) mx += x[i], my += y[i];
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  LinearFit fit;
  if (n < 2 || !(sxx > 0)) return fit;
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

// The rows kept after cleaning, in record order.
struct Rows {
  std::vector<int> row;
  std::vector<double> P, d, a_raw, a;
  std::size_t size() const { return row.size(); }
  void Truncate(std::size_t n) {
    row.resize(n);
    P.resize(n);
    d.resize(n);
    if (!a_raw.empty()) a_raw.resize(n);
    if (!a.empty()) a.resize(n);
  }
};

bool NeedsCrackLength(RMethod m, SpecimenType type) {
  return m == RMethod::kEnergy || m == RMethod::kMbt || m == RMethod::kComplianceCalibration ||
         (m == RMethod::kLefm && type == SpecimenType::kDCB);
}

}  // namespace

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
  text += fmt::format("\n  {:.3f} s", wall_s);
  return text;
}

RCurveResult ComputeRCurve(const ExperimentRecord& record, const RCurveOptions& options) {
  Stopwatch watch;
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid R-curve options: " + why);
  record.Validate();
  const std::string& src = record.source;
  const int n = static_cast<int>(record.size());
  BF_CHECK_INPUT(n >= 5, "the record is too short for an R curve",
                 {.file = src, .field = "rows", .value = std::to_string(n),
                  .expected = ">= 5 rows"});
  const SpecimenSpec& spec = options.specimen;
  const bool is_ct = spec.type == SpecimenType::kCT;
  const double B = spec.CrackFrontWidth();
  const RMethod method = options.method;
  const bool has_a = record.has_crack_length() && method != RMethod::kEquivalentCrack;
  if (NeedsCrackLength(method, spec.type) && !record.has_crack_length())
    throw Error(ErrorKind::kInput,
                fmt::format("the {} method needs a crack-length column", RMethodName(method)),
                {.file = src, .field = "crack_length",
                 .expected = "a crack_length column (or --method equivalent)"});

  RCurveResult result;
  result.curve.method = RMethodName(method);
  result.curve.r_kind = method == RMethod::kEnergy ? "energy" : "elastic-zone";
  result.curve.source = src;

  // ---- time must increase
  for (int i = 1; i < static_cast<int>(record.time.size()); ++i)
    if (record.time[i] < record.time[i - 1])
      throw Error(ErrorKind::kInput, fmt::format("time decreases at row {}", i + 1),
                  {.file = src, .field = "time",
                   .value = fmt::format("{:g} s after {:g} s", record.time[i], record.time[i - 1]),
                   .expected = "non-decreasing time (one test, rows in order)"});

  // ---- negative load: a few are dropped and counted; mostly negative is an error
  int negative = 0;
  for (double p : record.load) negative += p < 0.0;
  if (negative > n / 2)
    throw Error(ErrorKind::kInput, "the load is negative in most rows",
                {.file = src, .field = "load", .value = fmt::format("{} of {} rows < 0", negative, n),
                 .expected = "tensile (positive) opening load; check the sign convention"});

  // ---- crack lengths must be positive and inside the specimen
  const double specimen_end = is_ct ? spec.width : spec.length;
  if (record.has_crack_length()) {
    for (int i = 0; i < n; ++i) {
      const double a = record.crack_length[i];
      if (!(a > 0.0))
        throw Error(ErrorKind::kInput, fmt::format("crack length is not positive in row {}", i + 1),
                    {.file = src, .field = "crack_length", .value = fmt::format("{:g} m", a),
                     .expected = "a > 0, measured from the load line"});
      if (specimen_end > 0.0 && a >= specimen_end)
        throw Error(ErrorKind::kInput,
                    fmt::format("crack length in row {} reaches past the specimen", i + 1),
                    {.file = src, .field = "crack_length", .value = Mm(a),
                     .expected = fmt::format("a < {} ({}); check the crack-length unit",
                                             Mm(specimen_end), is_ct ? "W" : "L")});
    }
  }

  Rows w;
  for (int i = 0; i < n; ++i) {
    if (record.load[i] < 0.0) continue;
    w.row.push_back(i);
    w.P.push_back(record.load[i]);
    w.d.push_back(record.displacement[i]);
    if (record.has_crack_length()) w.a_raw.push_back(record.crack_length[i]);
  }
  AddDropped(result, "negative load", negative);

  // ---- noise of load and displacement
  double maxP = 0, maxd = 0;
  for (std::size_t k = 0; k < w.size(); ++k) maxP = std::max(maxP, w.P[k]), maxd = std::max(maxd, std::abs(w.d[k]));
  BF_CHECK_INPUT(maxP > 0.0, "the load is never positive", {.file = src, .field = "load"});
  const double sigma_P = std::max(
      std::isnan(options.load_noise) ? RobustNoiseSigma(w.P) : options.load_noise, 1e-9 * maxP);
  const double sigma_d =
      std::max(std::isnan(options.displacement_noise) ? RobustNoiseSigma(w.d)
                                                      : options.displacement_noise,
               1e-9 * maxd);

  // ---- validity: stop at the first unloading
  if (options.stop_at_unloading) {
    double dmax = -INFINITY;
    const double tol = std::max(3.0 * sigma_d, 1e-6 * maxd);
    // A decrease counts when it lasts 3 rows: on a long record a single row
    // 3 sigmas below the (noisy) running maximum is chance, not unloading.
    auto below = [&](std::size_t k, double level) {
      for (std::size_t q = k; q < std::min(w.size(), k + 3); ++q)
        if (!(w.d[q] < level)) return false;
      return true;
    };
    for (std::size_t k = 0; k < w.size(); ++k) {
      dmax = std::max(dmax, w.d[k]);
      if (w.d[k] < dmax - tol && below(k, dmax - tol)) {
        AddDropped(result, "after unloading (load-point displacement decreased)",
                   static_cast<int>(w.size() - k));
        result.notes.push_back(fmt::format("displacement decreased at row {}: rows from there on dropped",
                                           w.row[k] + 1));
        w.Truncate(k);
        break;
      }
    }
  }

  // ---- crack length: isotonic (non-decreasing) fit, counted
  double sigma_a = 0.0;
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
    const double estimate = std::sqrt(std::max(scatter * scatter, rss / std::max<std::size_t>(1, w.size())) +
                                      q * q / 12.0);
    result.figures["crack_scatter_m"] = scatter;
    sigma_a = std::isnan(options.crack_length_noise) ? estimate : options.crack_length_noise;
    sigma_a = std::max(sigma_a, 1e-9 * w.a.back());
  } else if (!std::isnan(options.crack_length_noise)) {
    sigma_a = options.crack_length_noise;
  }
  result.load_noise = sigma_P;
  result.displacement_noise = sigma_d;
  result.crack_length_noise = sigma_a;

  // ---- validity: edge effect
  double a_limit = options.max_crack_length;
  if (std::isnan(a_limit)) {
    if (is_ct && spec.width > 0) a_limit = 0.9 * spec.width;
    if (!is_ct && spec.length > 0 && spec.height > 0) a_limit = spec.length - 4.0 * spec.height;
  }
  if (!w.a.empty() && std::isfinite(a_limit)) {
    std::size_t k = 0;
    while (k < w.size() && w.a[k] <= a_limit) ++k;
    if (k < w.size()) {
      AddDropped(result, fmt::format("past the validity limit a > {} (edge effect)", Mm(a_limit)),
                 static_cast<int>(w.size() - k));
      w.Truncate(k);
    }
  }
  if (std::isfinite(a_limit)) result.figures["validity_max_crack_length_m"] = a_limit;

  // ---- initial compliance and initiation
  const int m = static_cast<int>(w.size());
  BF_CHECK_INPUT(m >= 5, "too few rows left after cleaning", {.file = src, .field = "rows",
                 .value = std::to_string(m), .expected = ">= 5 valid rows"});
  int imax = 0;
  for (int k = 1; k < m; ++k)
    if (w.P[k] > w.P[imax]) imax = k;
  const double Pmax = w.P[imax];
  std::vector<double> fit_P, fit_d;
  int last_fit = -1;
  for (int k = 0; k <= imax; ++k)
    if (w.P[k] >= options.linear_fit_low * Pmax && w.P[k] <= options.linear_fit_high * Pmax) {
      fit_P.push_back(w.P[k]);
      fit_d.push_back(w.d[k]);
      last_fit = k;
    }
  if (fit_P.size() < 3)
    throw Error(ErrorKind::kInput, "too few loading rows to fit the initial compliance",
                {.file = src, .field = "load", .value = fmt::format("{} rows", fit_P.size()),
                 .expected = fmt::format(">= 3 rows with {:g}..{:g} x max load before the maximum",
                                         options.linear_fit_low, options.linear_fit_high)});
  const LinearFit lin = FitLine(fit_P, fit_d);  // d = d0 + C0 P
  BF_CHECK_INPUT(lin.slope > 0, "the initial loading is not stiff and linear",
                 {.file = src, .field = "displacement"});
  Initiation& init = result.initiation;
  init.initial_compliance = lin.slope;
  init.displacement_offset = lin.intercept;
  init.max_load_row = w.row[imax];
  std::vector<double> C(m, NAN);  // compliance from the linear part's origin
  for (int k = 0; k < m; ++k)
    if (w.P[k] > 0) C[k] = (w.d[k] - lin.intercept) / w.P[k];
  int nl = -1, off = -1;
  for (int k = last_fit + 1; k < m; ++k) {
    if (!(w.P[k] > 0)) continue;
    const double noise = 3.0 * (sigma_d / std::max(w.d[k] - lin.intercept, 1e-300) + sigma_P / w.P[k]);
    if (nl < 0 && C[k] > lin.slope * (1.0 + options.nonlinearity_tolerance + noise)) nl = k;
    if (off < 0 && C[k] >= lin.slope * (1.0 + options.offset_fraction)) off = k;
  }
  if (off < 0 || off > imax) off = imax;
  if (nl < 0) nl = off;
  init.nonlinearity_row = w.row[nl];
  init.offset_row = w.row[off];

  // a0 and the first row of growth.
  double a0 = spec.notch;
  int first_growth = -1;
  if (!w.a.empty()) {
    a0 = w.a[0];
    for (int k = 0; k < m; ++k)
      if (w.a[k] > a0 + sigma_a) {
        first_growth = k;
        break;
      }
    if (first_growth < 0)
      throw Error(ErrorKind::kInput, "the crack length never grows beyond its noise",
                  {.file = src, .field = "crack_length", .value = Mm(w.a.back() - a0),
                   .expected = fmt::format("growth > {}", Mm(sigma_a))});
    init.visual_row = w.row[first_growth];
    if (spec.notch > 0 && std::abs(a0 - spec.notch) > 0.1 * spec.notch)
      result.notes.push_back(fmt::format("first crack length {} differs from the notch {} by > 10%",
                                         Mm(a0), Mm(spec.notch)));
  }
  result.curve.initial_crack_length = a0;
  // DCB: tracked crack lengths often lag and jump (errors correlated over many
  // rows, invisible to the local scatter). Their distance from the fitted
  // compliance law C^(1/3) = s (a + Delta), in crack-length units, bounds that
  // error from below; the larger estimate is used.
  if (!is_ct && first_growth >= 0 && std::isnan(options.crack_length_noise)) {
    std::vector<double> x, y;
    for (int k = first_growth; k < m; ++k)
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
      if (residual > sigma_a) {
        sigma_a = residual;
        result.crack_length_noise = sigma_a;
        result.notes.push_back(fmt::format(
            "crack-length noise taken from the scatter about the compliance law C^(1/3) "
            "linear in a ({}), larger than the local scatter",
            Mm(residual)));
      }
    }
  }
  result.figures["initial_compliance_m_per_N"] = lin.slope;
  result.figures["displacement_offset_m"] = lin.intercept;
  const double k_cov = options.coverage_factor;
  result.curve.uncertainty_coverage = k_cov;

  auto push = [&](int k, double a, double R, double U) {
    result.curve.crack_length.push_back(a);
    result.curve.R.push_back(R);
    result.curve.R_uncertainty.push_back(U);
    result.crack_growth.push_back(a - a0);
    result.load.push_back(w.P[k]);
    result.displacement.push_back(w.d[k]);
    result.rows.push_back(w.row[k]);
  };

  // ================================================================ energy
  if (method == RMethod::kEnergy) {
    const int h = options.smoothing_half_window;
    const double da_min =
        std::max(options.min_crack_increment, options.increment_resolution * std::sqrt(2.0) * sigma_a);
    std::vector<double> ds(m);
    for (int k = 0; k < m; ++k) ds[k] = w.d[k] - lin.intercept;  // elastic unloading to d0
    const int start = std::max(0, first_growth - 1);
    AddDropped(result, "before initiation (no crack growth yet)", start);
    // Values entering the balance: the rows as measured, or (h > 0) local
    // quadratic fits against time over the growth rows [start, m - 1] only,
    // so no window straddles the initiation kink.
    std::vector<double> P_e = w.P, d_e = ds, a_e = w.a;
    std::vector<LocalWeights> fit_weights;  // per row from start (h > 0)
    if (h > 0) {
      std::vector<double> x(m);
      bool time_increases = !record.time.empty();
      for (int k = 0; k < m; ++k) {
        x[k] = time_increases ? record.time[w.row[k]] : k;
        if (k > start && !(x[k] > x[k - 1])) time_increases = false;
      }
      if (!time_increases)
        for (int k = 0; k < m; ++k) x[k] = k;
      double hat_sum = 0.0;
      for (int k = start; k < m; ++k) {
        LocalWeights lw = LocalQuadraticWeights(x, start, m - 1, k, h);
        double p = 0.0, d = 0.0, a = 0.0, hat = 0.0;
        for (std::size_t q = 0; q < lw.weights.size(); ++q) {
          const int r = lw.first_row + static_cast<int>(q);
          p += lw.weights[q] * w.P[r];
          d += lw.weights[q] * ds[r];
          a += lw.weights[q] * w.a_raw[r];
          hat += lw.weights[q] * lw.weights[q];
        }
        P_e[k] = p, d_e[k] = d, a_e[k] = a;
        hat_sum += std::sqrt(hat);
        fit_weights.push_back(std::move(lw));
      }
      const double noise_factor = hat_sum / (m - start);  // mean sqrt(sum w^2)
      result.figures["energy_smoothing_half_window_rows"] = h;
      result.figures["energy_smoothed_crack_noise_m"] = noise_factor * sigma_a;
      result.notes.push_back(fmt::format(
          "energy method on local quadratic fits of load, displacement and crack length against {} "
          "over {} rows (ASTM E647 incremental polynomial); crack-length noise {} per row, {} "
          "after the fits; every increment spans at least one window",
          time_increases ? "time" : "row number", 2 * h + 1, Mm(sigma_a), Mm(noise_factor * sigma_a)));
    }
    // Standard deviation of a_e[j] - a_e[i] over sigma_a: sqrt 2 for raw rows,
    // the norm of the difference of the two fits' weights when smoothed.
    std::vector<double> dense(h > 0 ? m : 0, 0.0);
    auto da_noise_factor = [&](int i, int j) {
      if (h <= 0) return std::sqrt(2.0);
      const LocalWeights& wi = fit_weights[i - start];
      const LocalWeights& wj = fit_weights[j - start];
      for (std::size_t q = 0; q < wj.weights.size(); ++q) dense[wj.first_row + q] += wj.weights[q];
      for (std::size_t q = 0; q < wi.weights.size(); ++q) dense[wi.first_row + q] -= wi.weights[q];
      double ss = 0.0;
      const int lo = std::min(wi.first_row, wj.first_row);
      const int hi = std::max(wi.first_row + static_cast<int>(wi.weights.size()),
                              wj.first_row + static_cast<int>(wj.weights.size()));
      for (int r = lo; r < hi; ++r) ss += dense[r] * dense[r], dense[r] = 0.0;
      return std::sqrt(ss);
    };
    // Increments [i, j]: each the shortest run with da >= da_min (smoothed:
    // da >= max(min_crack_increment, increment_resolution x its own noise)
    // and at least one window of rows); rows left over at the end join the
    // last increment.
    auto resolvable = [&](int i, int j) {
      const double da = a_e[j] - a_e[i];
      if (h <= 0) return da >= da_min;
      return j - i >= 2 * h + 1 && da >= options.min_crack_increment &&
             da >= options.increment_resolution * sigma_a * da_noise_factor(i, j);
    };
    result.figures["energy_min_increment_m"] = h > 0 ? options.min_crack_increment : da_min;
    std::vector<std::pair<int, int>> increments;
    for (int i = start;;) {
      int j = i + 1;
      while (j < m && !resolvable(i, j)) ++j;
      if (j >= m) break;
      increments.emplace_back(i, j);
      i = j;
    }
    if (!increments.empty() && increments.back().second < m - 1 &&
        a_e[m - 1] > a_e[increments.back().second]) {
      result.notes.push_back(fmt::format("the last {} rows (growth {}) joined the last increment",
                                         m - 1 - increments.back().second,
                                         Mm(a_e[m - 1] - a_e[increments.back().second])));
      increments.back().second = m - 1;
    }
    std::vector<double> gP(h > 0 ? m : 0, 0.0), gd(h > 0 ? m : 0, 0.0);
    int last_end = start;
    for (const auto& [i, j] : increments) {
      const double da = a_e[j] - a_e[i];
      const double dU = EnergyReleased(P_e, d_e, i, j);
      const double R = dU / (B * da);
      // Linear sensitivities of dU to every P_k and d_k of the increment
      // (smoothed: carried back to the measured rows through the fits' weights).
      double var = 0.0;
      for (int k = i; k <= j; ++k) {
        const double dprev = k > i ? d_e[k] - d_e[k - 1] : 0.0;
        const double dnext = k < j ? d_e[k + 1] - d_e[k] : 0.0;
        double sP = 0.5 * (dprev + dnext);
        const double Pprev = k > i ? P_e[k - 1] : P_e[k];
        const double Pnext = k < j ? P_e[k + 1] : P_e[k];
        double sd = (k > i ? 0.5 * (Pprev + P_e[k]) : 0.0) - (k < j ? 0.5 * (P_e[k] + Pnext) : 0.0);
        if (k == j) sP -= 0.5 * d_e[k], sd -= 0.5 * P_e[k];
        if (k == i) sP += 0.5 * d_e[k], sd += 0.5 * P_e[k];
        if (h <= 0) {
          var += sP * sP * sigma_P * sigma_P + sd * sd * sigma_d * sigma_d;
          continue;
        }
        const LocalWeights& lw = fit_weights[k - start];
        for (std::size_t q = 0; q < lw.weights.size(); ++q) {
          gP[lw.first_row + q] += sP * lw.weights[q];
          gd[lw.first_row + q] += sd * lw.weights[q];
        }
      }
      if (h > 0)
        for (int r = start; r < m; ++r) {
          var += gP[r] * gP[r] * sigma_P * sigma_P + gd[r] * gd[r] * sigma_d * sigma_d;
          gP[r] = gd[r] = 0.0;
        }
      const double rel_da = da_noise_factor(i, j) * sigma_a / da;
      const double u = std::sqrt(var / (B * da * B * da) + R * R * rel_da * rel_da);
      result.curve.crack_length.push_back(0.5 * (a_e[i] + a_e[j]));
      result.curve.R.push_back(R);
      result.curve.R_uncertainty.push_back(k_cov * u);
      result.crack_growth.push_back(0.5 * (a_e[i] + a_e[j]) - a0);
      result.load.push_back(w.P[j]);
      result.displacement.push_back(w.d[j]);
      result.rows.push_back(w.row[j]);
      last_end = j;
    }
    result.points_used = result.curve.size() > 0 ? last_end - start + 1 : 0;
    AddDropped(result, "tail without crack growth after the last increment",
               result.curve.size() > 0 ? m - 1 - last_end : m - start);
    if (result.curve.size() == 0)
      throw Error(ErrorKind::kInput, "no crack increment is resolvable against the crack-length noise",
                  {.file = src, .field = "crack_length", .value = Mm(w.a.back() - a0),
                   .expected = fmt::format("growth >= {}", Mm(da_min))});
    result.curve.initiation_R = result.curve.R.front();
    result.wall_s = watch.Seconds();
    return result;
  }

  // ================================================================ point-wise methods
  // G(P, d, a) for one row; uncertainty by central differences of +-1 sigma.
  std::function<double(double, double, double)> G;
  std::function<double(double, double, double)> crack_of;  // reported a for (P, d, a_meas)
  int first_point = has_a ? first_growth : nl;
  const specimen::DcbBeam beam = specimen::DcbBeamFromScene(spec, options.material);

  if (method == RMethod::kMbt || method == RMethod::kComplianceCalibration) {
    BF_CHECK_INPUT(!is_ct, "MBT and compliance calibration are DCB methods",
                   {.field = "--method", .value = RMethodName(method),
                    .expected = "energy, lefm or equivalent for a CT specimen"});
    // ASTM D5528 large-displacement (F) and load-block (N) corrections; 1 when off.
    const bool large = options.large_displacement_correction;
    const double t = options.load_block_offset, half_block = options.load_block_half_length;
    auto F_of = [=](double d, double a) {
      return large ? 1.0 - 0.3 * (d / a) * (d / a) - 1.5 * d * t / (a * a) : 1.0;
    };
    auto N_of = [=](double d, double a) {
      const double l = half_block / a;
      return large ? 1.0 - l * l * l - 9.0 / 8.0 * (1.0 - l * l) * d * t / (a * a) -
                         9.0 / 35.0 * (d / a) * (d / a)
                   : 1.0;
    };
    std::vector<double> x, y;
    double F_min = 1.0, N_min = 1.0;
    for (int k = first_growth; k < m; ++k)
      if (w.P[k] > 0 && w.d[k] > 0) {
        const double N = N_of(w.d[k], w.a[k]);
        F_min = std::min(F_min, F_of(w.d[k], w.a[k]));
        N_min = std::min(N_min, N);
        if (method == RMethod::kMbt) {
          x.push_back(w.a[k]);
          y.push_back(std::cbrt(w.d[k] / w.P[k] / N));
        } else {
          x.push_back(std::log(w.a[k]));
          y.push_back(std::log(w.d[k] / w.P[k] / N));
        }
      }
    if (large) {
      BF_CHECK_INPUT(F_min > 0 && N_min > 0, "the large-displacement corrections are not positive",
                     {.file = src, .field = "load_block",
                      .value = fmt::format("F min {:.3g}, N min {:.3g}", F_min, N_min),
                      .expected = "d/a and the load-block sizes small enough for F, N > 0"});
      result.figures["d5528_F_min"] = F_min;
      result.figures["d5528_N_min"] = N_min;
      result.notes.push_back(fmt::format(
          "ASTM D5528 large-displacement and load-block corrections: fit on C/N, G x F/N "
          "(t = {}, L' = {}; over the fit rows F >= {:.4f}, N >= {:.4f})",
          Mm(t), Mm(half_block), F_min, N_min));
    }
    const LinearFit fit = FitLine(x, y);
    if (!(fit.slope > 0))
      throw Error(ErrorKind::kInput, "the compliance does not grow with the crack length",
                  {.file = src, .field = "crack_length",
                   .expected = "compliance increasing with crack length over the propagation rows"});
    const double b = spec.width;
    if (method == RMethod::kMbt) {
      const double delta = fit.intercept / fit.slope;  // x-intercept at a = -delta
      if (delta < 0)
        result.notes.push_back("the C^(1/3) fit crosses zero at a > 0; |Delta| used (ASTM D5528)");
      const double abs_delta = std::abs(delta);
      result.figures["mbt_delta_m"] = delta;
      result.figures["mbt_slope"] = fit.slope;
      G = [=](double P, double d, double a) {
        return 3.0 * P * d / (2.0 * b * (a + abs_delta)) * F_of(d, a) / N_of(d, a);
      };
    } else {
      const double nexp = fit.slope;
      result.figures["cc_n"] = nexp;
      result.figures["cc_k"] = std::exp(fit.intercept);
      G = [=](double P, double d, double a) {
        return nexp * P * d / (2.0 * b * a) * F_of(d, a) / N_of(d, a);
      };
    }
    crack_of = [](double, double, double a) { return a; };
  } else if (is_ct) {
    // CT lefm / equivalent: E399 K with a measured or from the compliance.
    const double W = spec.width;
    double E_eff = NAN;
    try {
      E_eff = specimen::EffectiveModulus(options.material, spec.plane);
    } catch (const Error&) {
      if (!options.calibrate_modulus) throw;
    }
    if (options.calibrate_modulus) {
      BF_CHECK_INPUT(a0 > 0, "the initial crack length is needed to calibrate the modulus",
                     {.field = "specimen.notch", .expected = "a0 > 0 (notch or first crack length)"});
      const double E_cal = specimen::CtLoadLineComplianceFactor(a0 / W) / (B * lin.slope);
      if (std::isfinite(E_eff)) result.figures["modulus_ratio_calibrated_to_material"] = E_cal / E_eff;
      E_eff = E_cal;
      result.figures["calibrated_effective_modulus_Pa"] = E_cal;
    }
    const double d0 = lin.intercept;
    const bool from_compliance = !has_a;
    result.figures["effective_modulus_Pa"] = E_eff;
    crack_of = [=](double P, double d, double a) {
      return from_compliance ? specimen::CtCrackFromLoadLineCompliance(E_eff, B, W, (d - d0) / P) : a;
    };
    G = [=](double P, double d, double a) {
      return specimen::CtEnergyReleaseRate(P, B, W, crack_of(P, d, a), E_eff);
    };
    if (from_compliance) result.notes.push_back("crack length from the Saxena-Hudak compliance inverse");
  } else if (method == RMethod::kLefm) {
    const specimen::DcbTheory theory = options.beam_shear && beam.G13 > 0
                                           ? specimen::DcbTheory::kCorrectedBeam
                                           : specimen::DcbTheory::kElasticFoundation;
    result.notes.push_back(std::string("DCB beam theory: ") + specimen::DcbTheoryName(theory));
    result.figures["beam_crack_length_correction_m"] = specimen::DcbCrackLengthCorrection(beam, theory);
    G = [=](double P, double, double a) { return specimen::DcbEnergyReleaseRate(beam, a, P, theory); };
    crack_of = [](double, double, double a) { return a; };
  } else {
    // DCB equivalent crack: flexural modulus from C0 at a0 + |Delta|, then
    // a_e from every compliance (de Moura et al. 2008 with Timoshenko arms
    // when G13 is known).
    BF_CHECK_INPUT(a0 > 0, "the equivalent-crack method needs the initial crack length",
                   {.field = "specimen.notch", .expected = "a0 > 0 (notch or first crack length)"});
    double delta = options.crack_length_correction;
    std::string delta_source = "given";
    if (std::isnan(delta) && record.has_crack_length()) {
      RCurveOptions mbt_options = options;
      mbt_options.method = RMethod::kMbt;
      const RCurveResult mbt = ComputeRCurve(record, mbt_options);
      delta = std::abs(mbt.figures.at("mbt_delta_m"));
      delta_source = "MBT fit of the record's crack lengths";
    }
    if (std::isnan(delta) && options.beam_shear && beam.G13 > 0 && beam.E1 > 0) {
      delta = specimen::DcbCrackLengthCorrection(beam, specimen::DcbTheory::kCorrectedBeam);
      delta_source = "Williams chi h";
    }
    if (std::isnan(delta)) {
      delta = 0.0;
      delta_source = "none (no crack lengths, no G13): R biased high by about (a0+Delta)/a0";
    }
    const specimen::DcbTheory theory = options.beam_shear && beam.G13 > 0
                                           ? specimen::DcbTheory::kTimoshenko
                                           : specimen::DcbTheory::kSimpleBeam;
    specimen::DcbBeam cal = beam;
    cal.E1 = 1.0;
    const double ae0 = a0 + delta;
    // C0 = 8 ae0^3/(Ef b h^3) (+ 12 ae0/(5 b h G13)): solve for Ef.
    const double shear = theory == specimen::DcbTheory::kTimoshenko
                             ? 12.0 * ae0 / (5.0 * beam.width * beam.arm_thickness * beam.G13)
                             : 0.0;
    BF_CHECK_INPUT(lin.slope > shear, "initial compliance below the shear compliance",
                   {.field = "material.G13"});
    cal.E1 = 8.0 * ae0 * ae0 * ae0 /
             (beam.width * std::pow(beam.arm_thickness, 3) * (lin.slope - shear));
    result.figures["flexural_modulus_Pa"] = cal.E1;
    result.figures["equivalent_delta_m"] = delta;
    result.notes.push_back("equivalent crack: Delta from " + delta_source + "; arms: " +
                           specimen::DcbTheoryName(theory));
    const double d0 = lin.intercept;
    crack_of = [=](double P, double d, double) {
      return specimen::DcbCrackFromCompliance(cal, (d - d0) / P, theory) - delta;
    };
    G = [=](double P, double d, double a) {
      return specimen::DcbEnergyReleaseRate(cal, crack_of(P, d, a) + delta, P, theory);
    };
    first_point = nl;
  }

  if (first_point < 0) first_point = nl;
  AddDropped(result, "before initiation", first_point);
  int zero_load = 0, out_of_range = 0;
  for (int k = first_point; k < m; ++k) {
    const double P = w.P[k], d = w.d[k], a = w.a.empty() ? NAN : w.a[k];
    if (!(P > 0) || !(d > 0)) {
      ++zero_load;
      continue;
    }
    try {
      const double R = G(P, d, a);
      const double gp = (G(P + sigma_P, d, a) - G(P - sigma_P, d, a)) / 2.0;
      const double gd = (G(P, d + sigma_d, a) - G(P, d - sigma_d, a)) / 2.0;
      const double ga = has_a ? (G(P, d, a + sigma_a) - G(P, d, a - sigma_a)) / 2.0 : 0.0;
      const double ar = crack_of(P, d, a);
      if (std::isfinite(a_limit) && ar > a_limit) {
        AddDropped(result, fmt::format("past the validity limit a > {} (edge effect)", Mm(a_limit)), 1);
        continue;
      }
      push(k, ar, R, k_cov * std::sqrt(gp * gp + gd * gd + ga * ga));
    } catch (const Error&) {
      ++out_of_range;  // outside a calibration's range (e.g. a/W < 0.2)
    }
  }
  AddDropped(result, "zero load or displacement", zero_load);
  AddDropped(result, "outside the calibrated range of the specimen formula", out_of_range);
  result.points_used = static_cast<int>(result.curve.size());
  if (result.curve.size() == 0)
    throw Error(ErrorKind::kInput, "no row gives an R point", {.file = src});
  // Initiation values with a = a0 (crack lengths) or from the compliance.
  auto at = [&](int k) -> double {
    try {
      return G(w.P[k], w.d[k], w.a.empty() ? a0 : w.a[k]);
    } catch (const Error&) {
      return NAN;
    }
  };
  init.R_nonlinearity = at(nl);
  init.R_offset = at(off);
  result.curve.initiation_R =
      std::isfinite(init.R_nonlinearity) ? init.R_nonlinearity : result.curve.R.front();
  result.wall_s = watch.Seconds();
  return result;
}

ExperimentRecord CrackLengthFromFrames(const ExperimentRecord& record,
                                       const std::vector<std::string>& frame_images,
                                       const std::vector<double>& frame_crack_lengths,
                                       const std::string& source, std::vector<std::string>* notes) {
  BF_CHECK_INPUT(frame_images.size() == frame_crack_lengths.size(),
                 "image names and crack lengths differ in length", {.file = source});
  BF_CHECK_INPUT(!record.images.empty(), "the record names no images, so frames cannot be matched",
                 {.file = record.source, .field = "image",
                  .expected = "a column 'image' with the file of the frame taken at that row"});
  auto name_of = [](const std::string& path) {
    return std::filesystem::path(path).filename().string();
  };
  std::map<std::string, double> measured;
  for (std::size_t f = 0; f < frame_images.size(); ++f)
    if (std::isfinite(frame_crack_lengths[f])) measured[name_of(frame_images[f])] = frame_crack_lengths[f];
  // The matched rows in record order, with the axis they are interpolated on.
  const bool timed = !record.time.empty();
  std::vector<std::size_t> rows;
  std::vector<double> values;
  for (std::size_t r = 0; r < record.size(); ++r) {
    if (record.images[r].empty()) continue;
    const auto it = measured.find(name_of(record.images[r]));
    if (it == measured.end()) continue;
    rows.push_back(r);
    values.push_back(it->second);
  }
  BF_CHECK_INPUT(rows.size() >= 2, "fewer than two frames with a crack length match the record's images",
                 {.file = source, .field = "image",
                  .value = std::to_string(rows.size()) + " matched",
                  .expected = "the record's image names (file names, folders ignored)"});
  auto axis = [&](std::size_t r) { return timed ? record.time[r] : static_cast<double>(r); };
  ExperimentRecord out = record;
  const std::size_t last = rows.back();
  out.load.resize(last + 1);
  out.displacement.resize(last + 1);
  if (timed) out.time.resize(last + 1);
  out.images.resize(last + 1);
  out.crack_length.assign(last + 1, values.front());
  std::size_t k = 0;
  for (std::size_t r = rows.front(); r <= last; ++r) {
    while (k + 1 < rows.size() && rows[k + 1] < r) ++k;
    if (r == rows[k] || k + 1 >= rows.size()) {
      out.crack_length[r] = values[k];
      continue;
    }
    const double t0 = axis(rows[k]), t1 = axis(rows[k + 1]);
    const double w = t1 > t0 ? (axis(r) - t0) / (t1 - t0) : 0.0;
    out.crack_length[r] = values[k] + w * (values[k + 1] - values[k]);
  }
  out.metadata["crack_length"] = "from images: " + source;
  if (notes) {
    notes->push_back(fmt::format(
        "crack length from {} frames of {} (rows {}-{}), linear in {} between them; {} rows "
        "before the first take its {:.4g} mm",
        rows.size(), source, rows.front() + 1, last + 1, timed ? "time" : "row",
        rows.front(), values.front() * 1e3));
    if (last + 1 < record.size())
      notes->push_back(fmt::format("{} rows after the last frame (row {}) removed: no crack length",
                                   record.size() - last - 1, last + 1));
  }
  out.Validate();
  return out;
}

}  // namespace bridgefit::experiment
