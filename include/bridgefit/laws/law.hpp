#pragma once
// Bridging (traction-separation) laws sigma(delta), PHYSICS.md section 2.
//
// Every law is a normalized shape s(d) on d = delta / delta_c in [0, 1],
// peaking at s = 1, scaled by the peak stress sigma_c and the critical
// opening delta_c:  sigma(delta) = sigma_c s(delta / delta_c).
// Hence J_B = k sigma_c delta_c with k = int_0^1 s(d) dd (the shape area),
// and any two of (sigma_c, delta_c, J_B) fix the third.
//
// LawT<T> is templated on the scalar so Ceres Jets differentiate it with
// respect to sigma_c and delta_c; the shape parameters stay double.

#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace bridgefit::laws {

enum class LawFamily { kLinear, kCubic, kTriangular, kTrilinear, kExponential, kTable };
// How a table law runs between its points: straight segments, or the
// monotone piecewise-cubic Hermite interpolant (PCHIP, Fritsch & Carlson
// 1980): C1, and on each segment between its two end values, so it stays
// >= 0 and its peak is the largest point; it reproduces a straight line
// exactly and a smooth law with an O(h^3) error instead of O(h^2).
enum class TableInterpolation { kLinear, kMonotoneCubic };

std::string_view LawFamilyName(LawFamily family);
// Parses "linear", "cubic", ... Throws Error naming the accepted values.
LawFamily ParseLawFamily(std::string_view name);

// The normalized shape s(d). Build it with the Make*Shape functions.
struct LawShape {
  LawFamily family = LawFamily::kLinear;
  double peak_ratio = 0.0;  // triangular: u_e / delta_c, in [0, 1)
  double alpha = 0.0;       // exponential: s = exp(-alpha d), alpha >= 0
  // Piecewise-linear families (trilinear, table): break points from
  // d = 0 to d = 1, with s(1) = 0 and max s = 1.
  std::vector<double> d_points;
  std::vector<double> s_points;
  TableInterpolation interpolation = TableInterpolation::kLinear;  // kTable only

  // Throws Error when the shape is impossible (e.g. peak_ratio >= 1).
  void Validate() const;
  // k = int_0^1 s(d) dd, so that J_B = k sigma_c delta_c.
  double Area() const;
};

LawShape MakeLinearShape();
LawShape MakeCubicShape();
// Elastic rise to the peak at u_e = peak_ratio delta_c, then linear to zero.
LawShape MakeTriangularShape(double peak_ratio);
// Exponential decay exp(-alpha d), cut at d = 1.
LawShape MakeExponentialShape(double alpha);
// The one home of the family -> shape rule: the default parameter of the
// one-parameter families (scene files, `bridgefit law` and `fit` use them).
constexpr double kDefaultPeakRatio = 0.1;        // triangular
constexpr double kDefaultExponentialAlpha = 3.0; // exponential
// A family's shape with its default parameter; nullopt for the families
// whose shape is data (trilinear, table: from a scene or the command line).
std::optional<LawShape> DefaultShape(LawFamily family);
// The families a fit compares by AICc, with their default shapes.
std::vector<LawShape> ComparedShapes();
// General three-segment law through (0, s0), (d1, s1), (d2, s2), (1, 0),
// with 0 < d1 < d2 < 1; s values are rescaled so the peak is 1.
LawShape MakeTrilinearShape(double s0, double d1, double s1, double d2, double s2);
// Tabulated law from absolute (delta [m], sigma [Pa]) points. Returns the
// normalized shape and sets sigma_c (peak) and delta_c (last point, where
// sigma must be 0).
LawShape MakeTableShape(const std::vector<double>& delta, const std::vector<double>& sigma,
                        double* sigma_c, double* delta_c);

// ---- Shape evaluation, templated on the scalar --------------------------

namespace detail {
template <class T>
T PiecewiseValue(const std::vector<double>& xs, const std::vector<double>& ys, const T& d) {
  for (size_t i = 1; i < xs.size(); ++i) {
    if (d <= T(xs[i])) {
      const double dx = xs[i] - xs[i - 1];
      if (dx <= 0.0) return T(ys[i]);
      return T(ys[i - 1]) + (d - T(xs[i - 1])) * ((ys[i] - ys[i - 1]) / dx);
    }
  }
  return T(0.0);
}
template <class T>
T PiecewiseIntegral(const std::vector<double>& xs, const std::vector<double>& ys, const T& d) {
  T total(0.0);
  for (size_t i = 1; i < xs.size(); ++i) {
    const double x0 = xs[i - 1];
    const double x1 = xs[i];
    if (d <= T(x0)) break;
    const double slope = x1 > x0 ? (ys[i] - ys[i - 1]) / (x1 - x0) : 0.0;
    if (d >= T(x1)) {
      total += T(0.5 * (ys[i - 1] + ys[i]) * (x1 - x0));
    } else {
      const T h = d - T(x0);
      total += T(ys[i - 1]) * h + T(0.5 * slope) * h * h;
      break;
    }
  }
  return total;
}
// PCHIP slope ds/dd at point k: the weighted harmonic mean of the two
// neighbouring secants, 0 where they differ in sign; at an end the
// three-point formula, 0 if it turns against the end secant and at most
// three times it (Moler's pchip).
inline double MonotoneSlope(const std::vector<double>& xs, const std::vector<double>& ys,
                            size_t k) {
  const size_t n = xs.size();
  auto h = [&](size_t i) { return xs[i + 1] - xs[i]; };
  auto secant = [&](size_t i) { return h(i) > 0.0 ? (ys[i + 1] - ys[i]) / h(i) : 0.0; };
  if (n < 3) return n == 2 ? secant(0) : 0.0;
  if (k == 0 || k == n - 1) {
    const size_t end = k == 0 ? 0 : n - 2, next = k == 0 ? 1 : n - 3;
    const double h0 = h(end), h1 = h(next), s0 = secant(end), s1 = secant(next);
    if (!(h0 + h1 > 0.0)) return 0.0;
    const double m = ((2.0 * h0 + h1) * s0 - h0 * s1) / (h0 + h1);
    if (m * s0 <= 0.0) return 0.0;
    if (s0 * s1 <= 0.0 && std::abs(m) > 3.0 * std::abs(s0)) return 3.0 * s0;
    return m;
  }
  const double s0 = secant(k - 1), s1 = secant(k);
  if (s0 * s1 <= 0.0) return 0.0;
  const double w0 = 2.0 * h(k) + h(k - 1), w1 = h(k) + 2.0 * h(k - 1);
  return (w0 + w1) / (w0 / s0 + w1 / s1);
}
// The cubic Hermite segment i (from point i-1 to i) in t = (d - x_(i-1)) / h:
// y(t) = c0 + c1 t + c2 t^2 + c3 t^3.
inline std::array<double, 4> HermiteSegment(const std::vector<double>& xs,
                                            const std::vector<double>& ys, size_t i) {
  const double h = xs[i] - xs[i - 1];
  const double m0 = h * MonotoneSlope(xs, ys, i - 1), m1 = h * MonotoneSlope(xs, ys, i);
  const double y0 = ys[i - 1], y1 = ys[i];
  return {y0, m0, 3.0 * (y1 - y0) - 2.0 * m0 - m1, 2.0 * (y0 - y1) + m0 + m1};
}
template <class T>
T MonotoneCubicValue(const std::vector<double>& xs, const std::vector<double>& ys, const T& d) {
  for (size_t i = 1; i < xs.size(); ++i) {
    if (d <= T(xs[i])) {
      const double h = xs[i] - xs[i - 1];
      if (h <= 0.0) return T(ys[i]);
      const std::array<double, 4> c = HermiteSegment(xs, ys, i);
      const T t = (d - T(xs[i - 1])) / h;
      return T(c[0]) + t * (T(c[1]) + t * (T(c[2]) + t * T(c[3])));
    }
  }
  return T(0.0);
}
// int_0^d of MonotoneCubicValue, exact: h (c0 t + c1 t^2/2 + c2 t^3/3 + c3 t^4/4) per segment.
template <class T>
T MonotoneCubicIntegral(const std::vector<double>& xs, const std::vector<double>& ys, const T& d) {
  T total(0.0);
  for (size_t i = 1; i < xs.size(); ++i) {
    const double h = xs[i] - xs[i - 1];
    if (d <= T(xs[i - 1])) break;
    if (h <= 0.0) continue;
    const std::array<double, 4> c = HermiteSegment(xs, ys, i);
    const T t = d >= T(xs[i]) ? T(1.0) : (d - T(xs[i - 1])) / h;
    total += T(h) * t * (T(c[0]) + t * (T(c[1] / 2.0) + t * (T(c[2] / 3.0) + t * T(c[3] / 4.0))));
  }
  return total;
}
}  // namespace detail

// s(d): 0 outside [0, 1).
template <class T>
T ShapeValue(const LawShape& shape, const T& d) {
  using std::exp;
  if (d < T(0.0) || d >= T(1.0)) return T(0.0);
  switch (shape.family) {
    case LawFamily::kLinear:
      return T(1.0) - d;
    case LawFamily::kCubic: {
      const T one_minus = T(1.0) - d;
      return T(27.0 / 4.0) * d * one_minus * one_minus;
    }
    case LawFamily::kTriangular:
      if (d < T(shape.peak_ratio)) return d / T(shape.peak_ratio);
      return (T(1.0) - d) / T(1.0 - shape.peak_ratio);
    case LawFamily::kExponential:
      return exp(T(-shape.alpha) * d);
    case LawFamily::kTable:
      if (shape.interpolation == TableInterpolation::kMonotoneCubic)
        return detail::MonotoneCubicValue(shape.d_points, shape.s_points, d);
      return detail::PiecewiseValue(shape.d_points, shape.s_points, d);
    case LawFamily::kTrilinear:
      return detail::PiecewiseValue(shape.d_points, shape.s_points, d);
  }
  return T(0.0);
}

// int_0^min(d,1) s(x) dx (0 for d <= 0).
template <class T>
T ShapeIntegral(const LawShape& shape, const T& d_in) {
  using std::exp;
  if (d_in <= T(0.0)) return T(0.0);
  const T d = d_in < T(1.0) ? d_in : T(1.0);
  switch (shape.family) {
    case LawFamily::kLinear:
      return d - T(0.5) * d * d;
    case LawFamily::kCubic: {
      const T d2 = d * d;
      return T(27.0 / 4.0) * (T(0.5) * d2 - T(2.0 / 3.0) * d2 * d + T(0.25) * d2 * d2);
    }
    case LawFamily::kTriangular: {
      const double p = shape.peak_ratio;
      if (d <= T(p)) return T(0.5) * d * d / T(p);
      const T rest = d - T(p);
      return T(0.5 * p) + (rest - T(0.5) * (d * d - T(p * p))) / T(1.0 - p);
    }
    case LawFamily::kExponential:
      if (shape.alpha == 0.0) return d;
      return (T(1.0) - exp(T(-shape.alpha) * d)) / T(shape.alpha);
    case LawFamily::kTable:
      if (shape.interpolation == TableInterpolation::kMonotoneCubic)
        return detail::MonotoneCubicIntegral(shape.d_points, shape.s_points, d);
      return detail::PiecewiseIntegral(shape.d_points, shape.s_points, d);
    case LawFamily::kTrilinear:
      return detail::PiecewiseIntegral(shape.d_points, shape.s_points, d);
  }
  return T(0.0);
}

// A law with its scale parameters. The shape must outlive the law.
template <class T>
struct LawT {
  const LawShape* shape = nullptr;
  T sigma_c = T(0.0);  // peak stress [Pa]
  T delta_c = T(0.0);  // critical opening [m]

  // sigma(delta) on the monotonic envelope [Pa].
  T Traction(const T& delta) const { return sigma_c * ShapeValue(*shape, delta / delta_c); }
  // W(delta) = int_0^delta sigma dd [J/m^2].
  T Work(const T& delta) const { return sigma_c * delta_c * ShapeIntegral(*shape, delta / delta_c); }
  // J_B = W(delta_c) [J/m^2].
  T BridgingToughness() const { return sigma_c * delta_c * T(shape->Area()); }
  // Energy given back on elastic unloading from delta_max: 1/2 sigma(delta_max) delta_max.
  T Recoverable(const T& delta_max) const { return T(0.5) * Traction(delta_max) * delta_max; }
  // Energy dissipated when loaded to delta_max: W(delta_max) - recoverable.
  T Dissipated(const T& delta_max) const { return Work(delta_max) - Recoverable(delta_max); }
  // Traction at opening delta for a point whose history maximum is
  // delta_max: the envelope when delta >= delta_max, else the elastic
  // unloading/reloading line toward the origin; zero once delta_max >= delta_c.
  T TractionWithHistory(const T& delta, const T& delta_max) const {
    if (delta >= delta_max) return Traction(delta);
    if (delta_max >= delta_c) return T(0.0);
    if (delta <= T(0.0) || delta_max <= T(0.0)) return T(0.0);
    return Traction(delta_max) * (delta / delta_max);
  }
};

using BridgingLaw = LawT<double>;

// Which pair of (sigma_c, delta_c, J_B) was given.
struct LawScales {
  double sigma_c = NAN;  // [Pa]
  double delta_c = NAN;  // [m]
  double J_B = NAN;      // [J/m^2]
};
// Completes a LawScales from any two of its three values for `shape`.
// Throws Error if fewer than two are given, if all three are given and
// disagree, or if any is not positive.
LawScales CompleteScales(const LawShape& shape, const LawScales& given);

// A law family with its shape options, as a scene file or the command line
// gives them (already parsed, SI).
struct ShapeSpec {
  LawFamily family = LawFamily::kLinear;
  double peak_ratio = kDefaultPeakRatio;         // triangular
  double alpha = kDefaultExponentialAlpha;       // exponential
  std::vector<double> trilinear;                 // s0, d1, s1, d2, s2
  std::vector<double> table_delta, table_sigma;  // table: [m], [Pa]
};
// The one home of the family -> shape rule (scene files and `bridgefit
// law`): the family's shape from its options. A table also sets the scales
// when none of the three is given (its peak and last opening). Throws Error
// (field "trilinear" or "table") when the family's data is missing, or as
// the Make*Shape functions do.
LawShape MakeShape(const ShapeSpec& spec, LawScales* given);

}  // namespace bridgefit::laws
