#include "bridgefit/laws/law.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "bridgefit/core/error.hpp"
#include "bridgefit/laws/rcurve_theory.hpp"

namespace bridgefit::laws {
namespace {

constexpr std::array<std::pair<std::string_view, LawFamily>, 6> kFamilies = {{
    {"linear", LawFamily::kLinear},
    {"cubic", LawFamily::kCubic},
    {"triangular", LawFamily::kTriangular},
    {"trilinear", LawFamily::kTrilinear},
    {"exponential", LawFamily::kExponential},
    {"table", LawFamily::kTable},
}};

void ValidatePiecewise(const LawShape& shape) {
  const auto& d = shape.d_points;
  const auto& s = shape.s_points;
  BF_CHECK_INPUT(d.size() == s.size() && d.size() >= 2,
                 "a piecewise-linear law needs at least two (delta, sigma) points");
  BF_CHECK_INPUT(d.front() == 0.0 && d.back() == 1.0,
                 "a piecewise-linear law must span openings from 0 to delta_c");
  for (size_t i = 1; i < d.size(); ++i)
    BF_CHECK_INPUT(d[i] >= d[i - 1], "law openings must not decrease",
                   {.value = std::to_string(d[i]), .expected = "openings in increasing order"});
  for (double v : s)
    BF_CHECK_INPUT(std::isfinite(v) && v >= 0.0, "law tractions must be finite and >= 0",
                   {.value = std::to_string(v)});
  BF_CHECK_INPUT(s.back() == 0.0, "a law must reach zero traction at delta_c",
                 {.value = std::to_string(s.back()), .expected = "sigma = 0 at the last point"});
}

// Rescales s so its maximum is 1.
void NormalizePeak(std::vector<double>& s) {
  const double peak = *std::max_element(s.begin(), s.end());
  BF_CHECK_INPUT(peak > 0.0, "a law must carry some traction",
                 {.expected = "a positive peak traction"});
  for (double& v : s) v /= peak;
}

}  // namespace

std::string_view LawFamilyName(LawFamily family) {
  for (const auto& [name, f] : kFamilies)
    if (f == family) return name;
  return "unknown";
}

LawFamily ParseLawFamily(std::string_view name) {
  for (const auto& [n, f] : kFamilies)
    if (n == name) return f;
  throw Error(ErrorKind::kInput, "unknown bridging law",
              {.field = "law", .value = std::string(name),
               .expected = "one of linear, cubic, triangular, trilinear, exponential, table"});
}

std::string_view TableInterpolationName(TableInterpolation interpolation) {
  return interpolation == TableInterpolation::kMonotoneCubic ? "monotone-cubic" : "linear";
}

TableInterpolation ParseTableInterpolation(std::string_view name) {
  for (TableInterpolation i : {TableInterpolation::kLinear, TableInterpolation::kMonotoneCubic})
    if (TableInterpolationName(i) == name) return i;
  throw Error(ErrorKind::kInput, "unknown table interpolation",
              {.field = "interpolation", .value = std::string(name),
               .expected = "linear or monotone-cubic"});
}

void LawShape::Validate() const {
  switch (family) {
    case LawFamily::kLinear:
    case LawFamily::kCubic:
      return;
    case LawFamily::kTriangular:
      BF_CHECK_INPUT(peak_ratio >= 0.0 && peak_ratio < 1.0,
                     "the triangular law's peak opening must lie in [0, delta_c)",
                     {.field = "peak_ratio", .value = std::to_string(peak_ratio),
                      .expected = "0 <= u_e / delta_c < 1"});
      return;
    case LawFamily::kExponential:
      BF_CHECK_INPUT(std::isfinite(alpha) && alpha >= 0.0,
                     "the exponential law's decay constant must be >= 0",
                     {.field = "alpha", .value = std::to_string(alpha), .expected = "alpha >= 0"});
      return;
    case LawFamily::kTrilinear:
    case LawFamily::kTable:
      ValidatePiecewise(*this);
      return;
  }
}

double LawShape::Area() const { return ShapeIntegral(*this, 1.0); }

LawShape MakeLinearShape() { return LawShape{.family = LawFamily::kLinear}; }
LawShape MakeCubicShape() { return LawShape{.family = LawFamily::kCubic}; }

LawShape MakeTriangularShape(double peak_ratio) {
  LawShape shape{.family = LawFamily::kTriangular, .peak_ratio = peak_ratio};
  shape.Validate();
  return shape;
}

LawShape MakeExponentialShape(double alpha) {
  LawShape shape{.family = LawFamily::kExponential, .alpha = alpha};
  shape.Validate();
  return shape;
}

std::optional<LawShape> DefaultShape(LawFamily family) {
  switch (family) {
    case LawFamily::kLinear: return MakeLinearShape();
    case LawFamily::kCubic: return MakeCubicShape();
    case LawFamily::kTriangular: return MakeTriangularShape(kDefaultPeakRatio);
    case LawFamily::kExponential: return MakeExponentialShape(kDefaultExponentialAlpha);
    default: return std::nullopt;
  }
}

LawShape MakeShape(const ShapeSpec& spec, LawScales* given) {
  switch (spec.family) {
    case LawFamily::kLinear: return MakeLinearShape();
    case LawFamily::kCubic: return MakeCubicShape();
    case LawFamily::kTriangular: return MakeTriangularShape(spec.peak_ratio);
    case LawFamily::kExponential: return MakeExponentialShape(spec.alpha);
    case LawFamily::kTrilinear: {
      const std::vector<double>& v = spec.trilinear;
      BF_CHECK_INPUT(v.size() == 5, "the trilinear law needs its five break-point values",
                     {.field = "trilinear", .value = std::to_string(v.size()) + " values",
                      .expected = "s0, d1, s1, d2, s2"});
      return MakeTrilinearShape(v[0], v[1], v[2], v[3], v[4]);
    }
    case LawFamily::kTable: {
      BF_CHECK_INPUT(!spec.table_delta.empty(), "the table law needs its (delta, sigma) points",
                     {.field = "table", .expected = "a CSV with columns delta and sigma"});
      double sigma_c = 0, delta_c = 0;
      LawShape shape = MakeTableShape(spec.table_delta, spec.table_sigma, &sigma_c, &delta_c);
      if (given && !std::isfinite(given->sigma_c) && !std::isfinite(given->delta_c) &&
          !std::isfinite(given->J_B)) {
        given->sigma_c = sigma_c;
        given->delta_c = delta_c;
      }
      return shape;
    }
  }
  return MakeLinearShape();
}

std::vector<LawShape> ComparedShapes() {
  return {MakeLinearShape(), MakeCubicShape(), MakeTriangularShape(kDefaultPeakRatio),
          MakeExponentialShape(kDefaultExponentialAlpha)};
}

LawShape MakeTrilinearShape(double s0, double d1, double s1, double d2, double s2) {
  BF_CHECK_INPUT(0.0 < d1 && d1 < d2 && d2 < 1.0,
                 "trilinear break points must satisfy 0 < d1 < d2 < 1 (fractions of delta_c)",
                 {.value = std::to_string(d1) + ", " + std::to_string(d2)});
  LawShape shape{.family = LawFamily::kTrilinear};
  shape.d_points = {0.0, d1, d2, 1.0};
  shape.s_points = {s0, s1, s2, 0.0};
  for (double s : shape.s_points)
    BF_CHECK_INPUT(std::isfinite(s) && s >= 0.0, "trilinear tractions must be >= 0",
                   {.value = std::to_string(s)});
  NormalizePeak(shape.s_points);
  shape.Validate();
  return shape;
}

LawShape MakeTableShape(const std::vector<double>& delta, const std::vector<double>& sigma,
                        double* sigma_c, double* delta_c) {
  BF_CHECK_INPUT(delta.size() == sigma.size() && delta.size() >= 2,
                 "a tabulated law needs at least two (delta, sigma) rows",
                 {.value = std::to_string(delta.size()) + " rows"});
  BF_CHECK_INPUT(delta.front() == 0.0, "a tabulated law must start at delta = 0",
                 {.field = "delta", .value = std::to_string(delta.front()), .expected = "0"});
  const double last = delta.back();
  BF_CHECK_INPUT(last > 0.0, "a tabulated law must end at a positive delta_c",
                 {.field = "delta", .value = std::to_string(last)});
  LawShape shape{.family = LawFamily::kTable};
  const double peak = *std::max_element(sigma.begin(), sigma.end());
  BF_CHECK_INPUT(peak > 0.0, "a tabulated law must carry some traction",
                 {.field = "sigma", .expected = "a positive peak"});
  for (size_t i = 0; i < delta.size(); ++i) {
    shape.d_points.push_back(delta[i] / last);
    shape.s_points.push_back(sigma[i] / peak);
  }
  shape.d_points.back() = 1.0;
  shape.Validate();
  if (sigma_c) *sigma_c = peak;
  if (delta_c) *delta_c = last;
  return shape;
}

LawScales CompleteScales(const LawShape& shape, const LawScales& given) {
  const double k = shape.Area();
  const int count = std::isfinite(given.sigma_c) + std::isfinite(given.delta_c) +
                    std::isfinite(given.J_B);
  BF_CHECK_INPUT(count >= 2, "a bridging law needs two of sigma_c, delta_c and J_B",
                 {.expected = "two of sigma_c, delta_c, J_B"});
  auto check_positive = [](double v, const char* name, const char* unit) {
    if (std::isfinite(v))
      BF_CHECK_INPUT(v > 0.0, std::string(name) + " must be positive",
                     {.field = name, .value = std::to_string(v) + " " + unit,
                      .expected = std::string("a value > 0 ") + unit});
  };
  check_positive(given.sigma_c, "sigma_c", "Pa");
  check_positive(given.delta_c, "delta_c", "m");
  check_positive(given.J_B, "J_B", "J/m^2");
  LawScales out = given;
  if (!std::isfinite(out.J_B)) {
    out.J_B = k * out.sigma_c * out.delta_c;
  } else if (!std::isfinite(out.delta_c)) {
    out.delta_c = out.J_B / (k * out.sigma_c);
  } else if (!std::isfinite(out.sigma_c)) {
    out.sigma_c = out.J_B / (k * out.delta_c);
  } else {
    const double implied = k * out.sigma_c * out.delta_c;
    BF_CHECK_INPUT(std::abs(implied - out.J_B) <= 1e-6 * out.J_B,
                   "sigma_c, delta_c and J_B disagree for this law",
                   {.field = "J_B", .value = std::to_string(out.J_B) + " J/m^2",
                    .expected = std::to_string(implied) + " J/m^2 (= k sigma_c delta_c, k = " +
                                std::to_string(k) + "), or give only two of the three"});
  }
  return out;
}

TruncationBounds BoundsFromTruncatedCurve(double R_max, double J_tip_c, double delta_root_max,
                                          double crack_length_max) {
  BF_CHECK_INPUT(std::isfinite(R_max) && std::isfinite(J_tip_c) && J_tip_c > 0.0,
                 "bounds need a finite R_max and a positive J_tip,c");
  BF_CHECK_INPUT(std::isfinite(delta_root_max) && delta_root_max >= 0.0,
                 "bounds need a finite notch-root opening >= 0");
  TruncationBounds b;
  b.J_B_lower = std::max(0.0, R_max - J_tip_c);
  b.delta_c_lower = delta_root_max;
  b.R_max = R_max;
  b.J_tip_c = J_tip_c;
  b.crack_length_max = crack_length_max;
  return b;
}

}  // namespace bridgefit::laws
