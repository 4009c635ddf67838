#include "bridgefit/inverse/compliance.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"

namespace bridgefit::inverse {

double ComplianceCurve::At(double a) const {
  const std::size_t n = crack_length.size();
  if (n == 0 || !(a >= crack_length.front()) || !(a <= crack_length.back())) return NAN;
  if (n == 1) return compliance.front();
  const std::size_t k = std::min<std::size_t>(
      std::max<std::size_t>(
          std::upper_bound(crack_length.begin(), crack_length.end(), a) - crack_length.begin(), 1),
      n - 1);
  const double span = crack_length[k] - crack_length[k - 1];
  const double t = span > 0.0 ? (a - crack_length[k - 1]) / span : 0.0;
  return compliance[k - 1] + t * (compliance[k] - compliance[k - 1]);
}

bool ComplianceFitOptions::IsValid(std::string* why) const {
  if (std::isnan(min_series_compliance)) {
    if (why) *why = "min_series_compliance must be a number (m/N)";
    return false;
  }
  if (min_rows < 2 + (fit_series ? 1 : 0)) {
    if (why) *why = "min_rows must exceed the number of fitted constants";
    return false;
  }
  return true;
}

std::string ComplianceFit::Summary() const {
  std::string text = fmt::format(
      "compliance along the crack: scale {:.4f}, series {:.4g} mm/N, rms {:.2f}% over {} rows "
      "(a = {:.1f}..{:.1f} mm)",
      scale, series_compliance * 1e3, 100.0 * rms_relative, rows, crack_min * 1e3, crack_max * 1e3);
  if (series_at_bound)
    text += fmt::format("; the free fit asked for a negative series compliance ({:.3g} mm/N), held "
                        "at {:.3g} mm/N: the model is too compliant at long cracks for a spring to "
                        "explain (check the scene's moduli)",
                        series_unconstrained * 1e3, series_compliance * 1e3);
  return text;
}

ComplianceFit FitComplianceAlongCrack(const ComplianceCurve& model,
                                      const std::vector<double>& crack_length,
                                      const std::vector<double>& compliance,
                                      const ComplianceFitOptions& options,
                                      const std::string& source) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid compliance fit options: " + why);
  BF_CHECK_INPUT(crack_length.size() == compliance.size(),
                 "crack lengths and compliances differ in number", {.file = source});
  // Relative residual r_i = s x_i + C_s y_i - 1 with x_i = C_m(a_i) / C_i,
  // y_i = 1 / C_i: normal equations of two unknowns.
  double xx = 0, xy = 0, yy = 0, x1 = 0, y1 = 0;
  ComplianceFit fit;
  std::vector<double> x, y;
  for (std::size_t i = 0; i < crack_length.size(); ++i) {
    const double cm = model.At(crack_length[i]);
    if (!std::isfinite(cm) || !(compliance[i] > 0.0) || !std::isfinite(compliance[i])) continue;
    x.push_back(cm / compliance[i]);
    y.push_back(1.0 / compliance[i]);
    xx += x.back() * x.back(), xy += x.back() * y.back(), yy += y.back() * y.back();
    x1 += x.back(), y1 += y.back();
    fit.crack_min = std::isnan(fit.crack_min) ? crack_length[i] : std::min(fit.crack_min, crack_length[i]);
    fit.crack_max = std::isnan(fit.crack_max) ? crack_length[i] : std::max(fit.crack_max, crack_length[i]);
  }
  fit.rows = static_cast<int>(x.size());
  BF_CHECK_INPUT(fit.rows >= options.min_rows,
                 fmt::format("{} rows with a measured crack length inside the model's range "
                             "({:.1f}..{:.1f} mm); the compliance fit needs {}",
                             fit.rows, model.crack_length.empty() ? NAN : model.crack_length.front() * 1e3,
                             model.crack_length.empty() ? NAN : model.crack_length.back() * 1e3,
                             options.min_rows),
                 {.file = source, .field = "crack_length",
                  .expected = "crack lengths beyond the notch on the loading path"});
  if (options.fit_series) {
    const double det = xx * yy - xy * xy;
    BF_CHECK_INPUT(det > 1e-12 * xx * yy,
                   "the record's compliance does not separate a scale from a series compliance "
                   "(its crack lengths span too little)",
                   {.file = source, .field = "crack_length"});
    fit.scale = (x1 * yy - y1 * xy) / det;
    fit.series_compliance = (y1 * xx - x1 * xy) / det;
    fit.series_unconstrained = fit.series_compliance;
    if (fit.series_compliance < options.min_series_compliance) {
      // C_s held at its bound: the scale alone minimises sum (s x + C_s y - 1)^2.
      fit.series_compliance = options.min_series_compliance;
      fit.scale = (x1 - fit.series_compliance * xy) / xx;
      fit.series_at_bound = true;
    }
  } else {
    fit.scale = x1 / xx;
    fit.series_compliance = 0.0;
  }
  BF_CHECK_INPUT(fit.scale > 0.0,
                 fmt::format("the compliance fit gives a non-physical scale {:.4g}", fit.scale),
                 {.file = source, .field = "crack_length",
                  .expected = "a record whose compliance rises with its crack length"});
  double sum = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double r = fit.scale * x[i] + fit.series_compliance * y[i] - 1.0;
    sum += r * r;
  }
  fit.rms_relative = std::sqrt(sum / static_cast<double>(x.size()));
  return fit;
}

}  // namespace bridgefit::inverse
