#pragma once
// Shared scenes for the MPM tests.
#include <cmath>

#include "bridgefit/scene/reference.hpp"

namespace bridgefit::mpm::testing {

// The CT scene of the issues (scene/reference.hpp) with notch a0.
inline Scene CtScene(double notch = 0.030) { return ReferenceCtScene(notch); }

// ASTM E399 geometry factor f(a/W): K = P/(B sqrt W) f.
inline double E399Factor(double u) {
  return (2.0 + u) / std::pow(1.0 - u, 1.5) *
         (0.886 + 4.64 * u - 13.32 * u * u + 14.72 * u * u * u - 5.6 * u * u * u * u);
}
// Saxena-Hudak load-line compliance E'BC.
inline double SaxenaHudak(double u) {
  const double r = (1.0 + u) / (1.0 - u);
  return r * r *
         (2.1630 + 12.219 * u - 20.065 * u * u - 0.9925 * std::pow(u, 3) + 20.609 * std::pow(u, 4) -
          9.9314 * std::pow(u, 5));
}

}  // namespace bridgefit::mpm::testing
