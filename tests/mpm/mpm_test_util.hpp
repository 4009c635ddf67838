#pragma once
// Shared scenes for the MPM tests.
#include <cmath>

#include "bridgefit/scene/scene.hpp"

namespace bridgefit::mpm::testing {

// The CT scene of the issues: W = 100 mm, a0 = 30 mm, B = 12.7 mm, E = 3 GPa.
inline Scene CtScene(double notch = 0.030) {
  Scene s;
  s.source = "test";
  s.specimen.type = SpecimenType::kCT;
  s.specimen.width = 0.100;
  s.specimen.height = 0.120;
  s.specimen.thickness = 0.0127;
  s.specimen.notch = notch;
  s.specimen.plane = PlaneCondition::kPlaneStress;
  s.material.E = 3e9;
  s.material.nu = 0.3;
  s.material.density = 609.0;
  return s;
}

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
