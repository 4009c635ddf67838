#pragma once
// Test fields shared by j_integral_test.cpp and frame_j_test.cpp: the
// Westergaard/Williams mode I field sampled on a grid in px (10 um a px,
// E 3 GPa, nu 0.3, plane stress), its J = K^2 / E, Gaussian noise.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>

#include "bridgefit/dic/correlation.hpp"
#include "bridgefit/dic/j_integral.hpp"
#include "bridgefit/dic/speckle.hpp"

namespace bridgefit::dic::test_fields {

constexpr double kPx = 1e-5;  // metres per px (10 um)
constexpr double kE = 3e9, kNu = 0.3;
constexpr double kMu = kE / (2 * (1 + kNu));
constexpr double kKappa = (3 - kNu) / (1 + kNu);  // plane stress

// J = K^2 / E (plane stress) with K = 2 mu A, A = k_over_2mu in px^0.5.
inline double JFromKOver2mu(double k_over_2mu_px) {
  const double k = 2 * kMu * k_over_2mu_px * std::sqrt(kPx);
  return k * k / kE;
}

using Displacement = std::function<void(double, double, double*, double*)>;

// A regular grid in px (rows at odd y so a crack along y = 0 runs between
// rows); points with |n| < band_px behind the tip are kCrackBand.
inline DisplacementField SampleGrid(const Displacement& disp, const CrackGeometry& crack, double half_x,
                             double half_y, double spacing, double band_px = 2.0) {
  DisplacementField f;
  f.nx = static_cast<int>(std::floor(2 * half_x / spacing)) + 1;
  f.ny = static_cast<int>(std::floor(2 * half_y / spacing)) + 1;
  const double len = std::hypot(crack.direction_x, crack.direction_y);
  const double c = crack.direction_x / len, s = crack.direction_y / len;
  for (int iy = 0; iy < f.ny; ++iy) {
    for (int ix = 0; ix < f.nx; ++ix) {
      const double x = -half_x + ix * spacing, y = -half_y + 0.5 * spacing + iy * spacing;
      double u = 0, v = 0;
      disp(x, y, &u, &v);
      const double along = c * (x - crack.tip_x) + s * (y - crack.tip_y);
      const double normal = -s * (x - crack.tip_x) + c * (y - crack.tip_y);
      f.x.push_back(x);
      f.y.push_back(y);
      f.u.push_back(u);
      f.v.push_back(v);
      f.status.push_back(along < 0 && std::abs(normal) < band_px ? PointStatus::kCrackBand
                                                                 : PointStatus::kOk);
    }
  }
  return f;
}

// Gaussian noise of `fraction` of the largest displacement magnitude, on u and v.
inline void AddNoise(DisplacementField* f, double fraction, std::uint64_t seed) {
  double umax = 0;
  for (std::size_t i = 0; i < f->size(); ++i) umax = std::max(umax, std::hypot(f->u[i], f->v[i]));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, fraction * umax);
  for (std::size_t i = 0; i < f->size(); ++i) {
    f->u[i] += noise(rng);
    f->v[i] += noise(rng);
  }
}

inline ModeICrackField LefmField() {
  ModeICrackField m;
  m.tip_x = 0.5;
  m.tip_y = 0.0;
  m.k_over_2mu = 0.05;
  m.kappa = kKappa;
  return m;
}

inline CrackGeometry CrackOf(double tip_x, double tip_y, double dx, double dy, double root = 0) {
  return CrackGeometry{tip_x, tip_y, dx, dy, root};
}

}  // namespace bridgefit::dic::test_fields
