#include "bridgefit/mpm/material.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"

namespace bridgefit::mpm {

LinearElastic::LinearElastic(const std::array<double, 9>& stiffness) : q_(stiffness) {
  for (double v : q_)
    BF_CHECK_INPUT(std::isfinite(v), "stiffness entries must be finite");
  BF_CHECK_INPUT(q_[0] > 0.0 && q_[4] > 0.0 && q_[8] > 0.0,
                 "stiffness must be positive definite");
}

LinearElastic LinearElastic::Isotropic(double E, double nu, PlaneCondition plane) {
  BF_CHECK_INPUT(E > 0.0 && nu > -1.0 && nu < 0.5, "isotropic constants out of range",
                 {.field = "E, nu", .value = fmt::format("{:g} Pa, {:g}", E, nu),
                  .expected = "E > 0, -1 < nu < 0.5"});
  const double g = E / (2.0 * (1.0 + nu));
  double q11 = 0.0, q12 = 0.0;
  if (plane == PlaneCondition::kPlaneStress) {
    q11 = E / (1.0 - nu * nu);
    q12 = nu * q11;
  } else {
    const double lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    q11 = lambda + 2.0 * g;
    q12 = lambda;
  }
  return LinearElastic({q11, q12, 0.0, q12, q11, 0.0, 0.0, 0.0, g});
}

LinearElastic LinearElastic::Orthotropic(double E1, double E2, double G12, double nu12,
                                         double angle, PlaneCondition plane) {
  BF_CHECK_INPUT(E1 > 0.0 && E2 > 0.0 && G12 > 0.0 && nu12 * nu12 < E1 / E2,
                 "orthotropic constants out of range");
  if (plane == PlaneCondition::kPlaneStrain)
    throw Error(ErrorKind::kInput,
                "orthotropic plane strain needs out-of-plane constants the scene does not carry",
                {.field = "specimen.plane", .value = "plane strain", .expected = "plane stress"});
  // Reduced stiffness in material axes, then Q-bar (Jones, Mechanics of
  // Composite Materials, eq. 2.85).
  const double nu21 = nu12 * E2 / E1;
  const double den = 1.0 - nu12 * nu21;
  const double Q11 = E1 / den, Q22 = E2 / den, Q12 = nu12 * E2 / den, Q66 = G12;
  const double c = std::cos(angle), s = std::sin(angle);
  const double c2 = c * c, s2 = s * s, c4 = c2 * c2, s4 = s2 * s2;
  const double q11 = Q11 * c4 + 2.0 * (Q12 + 2.0 * Q66) * s2 * c2 + Q22 * s4;
  const double q12 = (Q11 + Q22 - 4.0 * Q66) * s2 * c2 + Q12 * (s4 + c4);
  const double q22 = Q11 * s4 + 2.0 * (Q12 + 2.0 * Q66) * s2 * c2 + Q22 * c4;
  const double q16 = (Q11 - Q12 - 2.0 * Q66) * s * c2 * c + (Q12 - Q22 + 2.0 * Q66) * s2 * s * c;
  const double q26 = (Q11 - Q12 - 2.0 * Q66) * s2 * s * c + (Q12 - Q22 + 2.0 * Q66) * s * c2 * c;
  const double q66 = (Q11 + Q22 - 2.0 * Q12 - 2.0 * Q66) * s2 * c2 + Q66 * (s4 + c4);
  return LinearElastic({q11, q12, q16, q12, q22, q26, q16, q26, q66});
}

LinearElastic LinearElastic::FromMaterial(const MaterialSpec& m, PlaneCondition plane) {
  if (m.orthotropic) return Orthotropic(m.E1, m.E2, m.G12, m.nu12, m.angle, plane);
  return Isotropic(m.E, m.nu, plane);
}

double LinearElastic::MaxWaveSpeed(double density) const {
  // Largest eigenvalue of the acoustic tensor Gamma_ik = C_ijkl n_j n_l over
  // in-plane directions n (sampled every degree; exact for isotropy).
  const auto& q = q_;
  double best = 0.0;
  for (int k = 0; k < 180; ++k) {
    const double t = M_PI * k / 180.0, n1 = std::cos(t), n2 = std::sin(t);
    // Voigt: sigma_xx row 0, sigma_yy row 1, sigma_xy row 2; eps index xy engineering.
    const double g11 = q[0] * n1 * n1 + 2.0 * q[2] * n1 * n2 + q[8] * n2 * n2;
    const double g22 = q[8] * n1 * n1 + 2.0 * q[5] * n1 * n2 + q[4] * n2 * n2;
    const double g12 = q[2] * n1 * n1 + (q[1] + q[8]) * n1 * n2 + q[5] * n2 * n2;
    const double mean = 0.5 * (g11 + g22);
    const double rad = std::sqrt(0.25 * (g11 - g22) * (g11 - g22) + g12 * g12);
    best = std::max(best, mean + rad);
  }
  return std::sqrt(best / density);
}

void LinearElastic::UpdateStress(std::size_t count, const double* d_exx, const double* d_eyy,
                                 const double* d_gxy, double* sxx, double* syy,
                                 double* sxy) const {
  const double q0 = q_[0], q1 = q_[1], q2 = q_[2], q4 = q_[4], q5 = q_[5], q8 = q_[8];
#pragma omp simd
  for (std::size_t p = 0; p < count; ++p) {
    const double a = d_exx[p], b = d_eyy[p], g = d_gxy[p];
    sxx[p] += q0 * a + q1 * b + q2 * g;
    syy[p] += q1 * a + q4 * b + q5 * g;
    sxy[p] += q2 * a + q5 * b + q8 * g;
  }
}

}  // namespace bridgefit::mpm
