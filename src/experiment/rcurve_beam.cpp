// DCB modified beam theory (mbt) and compliance calibration (cc), ASTM D5528,
// with the optional large-displacement (F) and load-block (N) corrections.
//   mbt: C^(1/3) = s (a + Delta) fitted, G = 3 P d / (2 b (a + |Delta|)) F/N
//   cc:  log C = log k + n log a fitted, G = n P d / (2 b a) F/N
// cc is always compared with mbt on the same rows: one power law misses the
// beam compliance over long crack ranges (a documented method limit,
// docs/RCURVE_METHODS.md), so its mean |difference| is reported and a
// difference above 3% anywhere is flagged.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "rcurve_stages.hpp"

namespace bridgefit::experiment::detail {
namespace {

constexpr double kCcMbtFlag = 0.03;  // flag when cc and mbt differ by more

// The unloading compliance of each unload-reload cycle (slope of d against P
// over its rows) at the cycle's crack length: one compliance point per cycle.
struct CycleCompliance {
  double a = NAN;
  double C = NAN;
  double d = NAN;  // largest displacement of the cycle (for F, N)
};

std::vector<CycleCompliance> CycleCompliances(const Prepared& p) {
  std::vector<CycleCompliance> out;
  const ExperimentRecord& record = *p.record;
  for (const std::vector<int>& cycle : p.cleaned.cycles) {
    std::vector<double> P, d, a;
    double Pmax = 0.0, Pmin = INFINITY, dmax = 0.0;
    for (int i : cycle) {
      if (!(record.load[i] > 0) || !std::isfinite(record.crack_length[i])) continue;
      P.push_back(record.load[i]);
      d.push_back(record.displacement[i]);
      a.push_back(record.crack_length[i]);
      Pmax = std::max(Pmax, record.load[i]);
      Pmin = std::min(Pmin, record.load[i]);
      dmax = std::max(dmax, record.displacement[i]);
    }
    // Needs 3 rows spanning a fifth of its top load: a cycle of jitter-size
    // says nothing about the slope.
    if (P.size() < 3 || Pmax - Pmin < 0.2 * Pmax) continue;
    const LinearFit line = FitLine(P, d);
    std::nth_element(a.begin(), a.begin() + a.size() / 2, a.end());
    const double a_mid = a[a.size() / 2];
    if (!(line.slope > 0) || !(a_mid > p.a0 + p.sigma_a)) continue;
    out.push_back({a_mid, line.slope, dmax});
  }
  return out;
}

}  // namespace

void BeamMethod(const Prepared& p, RCurveResult& result) {
  const RCurveOptions& options = *p.options;
  const RMethod method = options.method;
  const Rows& w = p.w;
  const int m = static_cast<int>(w.size());
  BF_CHECK_INPUT(!p.is_ct, "MBT and compliance calibration are DCB methods",
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
  // Compliance points: the propagation rows, then one per unload-reload cycle.
  std::vector<double> a_fit, C_fit;
  double F_min = 1.0, N_min = 1.0;
  for (int k = p.first_growth; k < m; ++k)
    if (w.P[k] > 0 && w.d[k] > 0) {
      const double N = N_of(w.d[k], w.a[k]);
      F_min = std::min(F_min, F_of(w.d[k], w.a[k]));
      N_min = std::min(N_min, N);
      a_fit.push_back(w.a[k]);
      C_fit.push_back(w.d[k] / w.P[k] / N);
    }
  const std::vector<CycleCompliance> cycles = CycleCompliances(p);
  for (const CycleCompliance& c : cycles) {
    a_fit.push_back(c.a);
    C_fit.push_back(c.C / N_of(c.d, c.a));
  }
  if (!cycles.empty()) {
    result.figures["compliance_fit_cycle_points"] = static_cast<double>(cycles.size());
    result.notes.push_back(fmt::format(
        "{} unload-reload cycle(s) enter the compliance fit with their unloading compliance "
        "(one point each, first at a = {}: {:.4g} mm/N)",
        cycles.size(), Mm(cycles.front().a), cycles.front().C * 1e3));
  }
  if (large) {
    BF_CHECK_INPUT(F_min > 0 && N_min > 0, "the large-displacement corrections are not positive",
                   {.file = p.src, .field = "load_block",
                    .value = fmt::format("F min {:.3g}, N min {:.3g}", F_min, N_min),
                    .expected = "d/a and the load-block sizes small enough for F, N > 0"});
    result.figures["d5528_F_min"] = F_min;
    result.figures["d5528_N_min"] = N_min;
    result.notes.push_back(fmt::format(
        "ASTM D5528 large-displacement and load-block corrections: fit on C/N, G x F/N "
        "(t = {}, L' = {}; over the fit rows F >= {:.4f}, N >= {:.4f})",
        Mm(t), Mm(half_block), F_min, N_min));
  }
  std::vector<double> x_mbt, y_mbt, x_cc, y_cc;
  for (std::size_t k = 0; k < a_fit.size(); ++k) {
    x_mbt.push_back(a_fit[k]);
    y_mbt.push_back(std::cbrt(C_fit[k]));
    x_cc.push_back(std::log(a_fit[k]));
    y_cc.push_back(std::log(C_fit[k]));
  }
  const LinearFit mbt_fit = FitLine(x_mbt, y_mbt);
  const LinearFit cc_fit = FitLine(x_cc, y_cc);
  const LinearFit& fit = method == RMethod::kMbt ? mbt_fit : cc_fit;
  const bool given = method == RMethod::kMbt ? std::isfinite(options.given_mbt_delta)
                                             : std::isfinite(options.given_cc_exponent);
  if (!given && !(fit.slope > 0))
    throw Error(ErrorKind::kInput,
                fmt::format("R curve ({} method), stage 'compliance fit': the compliance does not "
                            "grow with the crack length",
                            RMethodName(method)),
                {.file = p.src, .field = "crack_length",
                 .value = fmt::format("{} propagation rows", a_fit.size()),
                 .expected = "compliance increasing with crack length over the propagation rows; "
                             "way out: check the crack_length column, or --method energy"});
  const double b = options.specimen.width;
  // x-intercept at a = -Delta; both taken as given where the options say so
  const double mbt_delta = std::isfinite(options.given_mbt_delta)
                               ? options.given_mbt_delta
                               : mbt_fit.intercept / mbt_fit.slope;
  const double abs_delta = std::abs(mbt_delta);
  const double nexp =
      std::isfinite(options.given_cc_exponent) ? options.given_cc_exponent : cc_fit.slope;
  if (given)
    result.notes.push_back(fmt::format(
        "compliance calibration given, not fitted on this record: {}",
        method == RMethod::kMbt ? fmt::format("Delta = {}", Mm(mbt_delta))
                                : fmt::format("n = {:.4g}", nexp)));
  const Formula G_mbt = [=](double P, double d, double a) {
    return 3.0 * P * d / (2.0 * b * (a + abs_delta)) * F_of(d, a) / N_of(d, a);
  };
  const Formula G_cc = [=](double P, double d, double a) {
    return nexp * P * d / (2.0 * b * a) * F_of(d, a) / N_of(d, a);
  };
  if (method == RMethod::kMbt) {
    if (mbt_delta < 0)
      result.notes.push_back("the C^(1/3) fit crosses zero at a > 0; |Delta| used (ASTM D5528)");
    result.figures["mbt_delta_m"] = mbt_delta;
    result.figures["mbt_slope"] = mbt_fit.slope;
  } else {
    result.figures["cc_n"] = nexp;
    result.figures["cc_k"] = std::exp(cc_fit.intercept);
  }
  const Formula crack_of = [](double, double, double a) { return a; };
  PointwiseCurve(p, result, method == RMethod::kMbt ? G_mbt : G_cc, crack_of, p.first_growth);
  if (method != RMethod::kComplianceCalibration ||
      !(mbt_fit.slope > 0 || std::isfinite(options.given_mbt_delta)))
    return;

  // cc against mbt at every point (same rows, same crack lengths).
  double sum_abs = 0.0, worst = 0.0, worst_a = NAN;
  int over = 0;
  for (std::size_t i = 0; i < result.curve.size(); ++i) {
    const double ref = G_mbt(result.load[i], result.displacement[i], result.curve.crack_length[i]);
    const double e = result.curve.R[i] / ref - 1.0;
    sum_abs += std::abs(e);
    over += std::abs(e) > kCcMbtFlag;
    if (std::abs(e) > std::abs(worst)) worst = e, worst_a = result.curve.crack_length[i];
  }
  const double mean_abs = sum_abs / std::max<std::size_t>(1, result.curve.size());
  result.figures["cc_mean_abs_difference_to_mbt"] = mean_abs;
  result.figures["cc_max_abs_difference_to_mbt"] = std::abs(worst);
  result.figures["cc_points_over_3_percent_from_mbt"] = over;
  result.figures["cc_mbt_delta_m"] = mbt_delta;
  result.notes.push_back(fmt::format(
      "cc against mbt on the same rows: mean |difference| {:.2f}%, largest {:+.2f}% at a = {}",
      100 * mean_abs, 100 * worst, Mm(worst_a)));
  if (over > 0)
    result.warnings.push_back(fmt::format(
        "{}: cc and mbt differ by more than {:.0f}% at {} of {} points (largest {:+.2f}% at a = {}): "
        "one power law C = k a^n (ASTM D5528's compliance calibration) cannot follow the beam "
        "compliance over this crack range, a documented method limit "
        "(docs/RCURVE_METHODS.md); prefer --method mbt",
        p.src, 100 * kCcMbtFlag, over, result.curve.size(), 100 * worst, Mm(worst_a)));
}

}  // namespace bridgefit::experiment::detail
