#pragma once
// Private: the plane-stress stiffness of dic::ElasticConstants (axis 1 along
// the crack), one home for the domain J integral (j_integral.cpp) and the
// field-wide J fit (j_fit.cpp).

#include <Eigen/Dense>

#include "bridgefit/dic/j_integral.hpp"

namespace bridgefit::dic::detail {

// (sigma11, sigma22, sigma12) = C (e11, e22, g12) (Voigt, engineering shear), C = S^-1.
inline Eigen::Matrix3d PlaneStressStiffness(const ElasticConstants& e) {
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  if (e.kind == ElasticConstants::Kind::kIsotropic) {
    S << 1 / e.E, -e.nu / e.E, 0, -e.nu / e.E, 1 / e.E, 0, 0, 0, 2 * (1 + e.nu) / e.E;
  } else {
    S << 1 / e.E1, -e.nu12 / e.E1, 0, -e.nu12 / e.E1, 1 / e.E2, 0, 0, 0, 1 / e.G12;
  }
  return S.inverse();
}

}  // namespace bridgefit::dic::detail
