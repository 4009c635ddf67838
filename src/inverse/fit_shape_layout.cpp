// Which break points and knot values each fitted-shape family frees
// (fit_shape.hpp): box coordinates, the shape they make, its roughness and
// the projection of a fixed shape onto the family (a start).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "fit_shape_impl.hpp"

namespace bridgefit::inverse::shape_internal {

namespace {
constexpr double kMinGap = 0.02;  // least spacing of free break points [delta_c]
}  // namespace

int ShapeLayout::positions() const {
  return family == ShapeFamily::kBilinear ? 1 : family == ShapeFamily::kTrilinear ? 2 : 0;
}
int ShapeLayout::values() const {
  return family == ShapeFamily::kBilinear ? 1 : family == ShapeFamily::kTrilinear ? 3 : knots;
}
bool ShapeLayout::normalised() const { return family != ShapeFamily::kBilinear; }

std::vector<std::string> ShapeLayout::Names() const {
  switch (family) {
    case ShapeFamily::kBilinear:
      return {"d1", "s1"};
    case ShapeFamily::kTrilinear:
      return {"d1", "d2", "s0", "s1", "s2"};
    case ShapeFamily::kTable:
      break;
  }
  std::vector<std::string> names;
  for (int k = 0; k < knots; ++k) names.push_back(fmt::format("s({:.3g})", double(k) / knots));
  return names;
}

// bilinear: d1 in [g, 1 - g]; trilinear: d1 in [g, 1 - 2g], d2 in [d1 + g, 1 - g].
std::vector<double> ShapeLayout::PositionsFromBox(const double* x) const {
  if (family == ShapeFamily::kBilinear) return {kMinGap + (1.0 - 2 * kMinGap) * x[0]};
  if (family == ShapeFamily::kTrilinear) {
    const double d1 = kMinGap + (1.0 - 3 * kMinGap) * x[0];
    return {d1, d1 + kMinGap + (1.0 - 2 * kMinGap - d1) * x[1]};
  }
  return {};
}

std::vector<double> ShapeLayout::PositionsToBox(const std::vector<double>& d) const {
  auto unit = [](double v) { return std::clamp(v, 0.0, 1.0); };
  if (family == ShapeFamily::kBilinear) return {unit((d[0] - kMinGap) / (1.0 - 2 * kMinGap))};
  if (family == ShapeFamily::kTrilinear) {
    const double x0 = unit((d[0] - kMinGap) / (1.0 - 3 * kMinGap));
    const double d1 = kMinGap + (1.0 - 3 * kMinGap) * x0;
    return {x0, unit((d[1] - d1 - kMinGap) / (1.0 - 2 * kMinGap - d1))};
  }
  return {};
}

bool ShapeLayout::Build(const std::vector<double>& d, const std::vector<double>& v,
                        laws::LawShape* out) const {
  if (static_cast<int>(d.size()) != positions() || static_cast<int>(v.size()) != values())
    return false;
  for (double value : v)
    if (!std::isfinite(value) || value < 0.0) return false;
  for (size_t k = 0; k < d.size(); ++k) {
    const double before = k == 0 ? 0.0 : d[k - 1];
    if (!(d[k] > before) || !(d[k] < 1.0)) return false;
  }
  laws::LawShape shape;
  if (family == ShapeFamily::kBilinear) {
    if (v[0] > 1.0) return false;  // softening: the peak is sigma_c at delta = 0
    shape.family = laws::LawFamily::kTable;
    shape.d_points = {0.0, d[0], 1.0};
    shape.s_points = {1.0, v[0], 0.0};
  } else {
    const double peak = *std::max_element(v.begin(), v.end());
    if (!(peak > 0.0)) return false;
    shape.family =
        family == ShapeFamily::kTrilinear ? laws::LawFamily::kTrilinear : laws::LawFamily::kTable;
    shape.d_points.push_back(0.0);
    if (family == ShapeFamily::kTrilinear)
      shape.d_points.insert(shape.d_points.end(), d.begin(), d.end());
    else
      for (int k = 1; k < knots; ++k) shape.d_points.push_back(double(k) / knots);
    shape.d_points.push_back(1.0);
    for (double value : v) shape.s_points.push_back(value / peak);
    shape.s_points.push_back(0.0);
    if (family == ShapeFamily::kTable) shape.interpolation = interpolation;
  }
  *out = std::move(shape);
  return true;
}

double ShapeLayout::Roughness(const laws::LawShape& shape) const {
  if (family != ShapeFamily::kTable) return 0.0;
  const std::vector<double>& s = shape.s_points;  // N knots and the final 0
  double sum = 0.0;
  for (size_t c = 1; c + 1 < s.size(); ++c) sum += std::pow(s[c - 1] - 2 * s[c] + s[c + 1], 2);
  return sum;
}

std::vector<double> ShapeLayout::Project(const laws::LawShape& seed) const {
  auto value = [&](double d) { return std::clamp(laws::ShapeValue(seed, d), 0.0, 1.0); };
  std::vector<double> x;
  if (family == ShapeFamily::kBilinear) {
    // The kink on the seed's curve that follows it best (least squares on 41 points).
    double best = INFINITY, best_d = 0.5;
    for (double d1 = 0.1; d1 < 0.95; d1 += 0.05) {
      laws::LawShape trial;
      if (!Build({d1}, {value(d1)}, &trial)) continue;
      double sum = 0.0;
      for (int i = 0; i <= 40; ++i)
        sum += std::pow(laws::ShapeValue(trial, i / 40.0) - laws::ShapeValue(seed, i / 40.0), 2);
      if (sum < best) best = sum, best_d = d1;
    }
    x = PositionsToBox({best_d});
    x.push_back(value(best_d));
  } else if (family == ShapeFamily::kTrilinear) {
    x = PositionsToBox({1.0 / 3.0, 2.0 / 3.0});
    for (double d : {0.0, 1.0 / 3.0, 2.0 / 3.0}) x.push_back(value(d));
  } else {
    for (int k = 0; k < knots; ++k) x.push_back(value(double(k) / knots));
  }
  return x;
}

}  // namespace bridgefit::inverse::shape_internal
