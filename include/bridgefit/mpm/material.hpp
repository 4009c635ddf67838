#pragma once
// Constitutive laws of the MPM solver. A law updates the stresses of a
// contiguous range of particles (structure-of-arrays) from their strain
// increments, so a law call costs one virtual dispatch per chunk, not per
// particle. Linear elasticity (isotropic, orthotropic) now; damage or
// plasticity laws implement the same interface later.

#include <array>
#include <cstddef>
#include <memory>

#include "bridgefit/scene/scene.hpp"

namespace bridgefit::mpm {

class ConstitutiveLaw {
 public:
  virtual ~ConstitutiveLaw() = default;
  virtual const char* Name() const = 0;
  // Largest in-plane elastic wave speed [m/s] (CFL condition).
  virtual double MaxWaveSpeed(double density) const = 0;
  // sigma += dsigma(d_eps) for particles [0, count); engineering shear
  // strain d_gxy = 2 d_eps_xy. Arrays are the chunk's own slices.
  virtual void UpdateStress(std::size_t count, const double* d_exx, const double* d_eyy,
                            const double* d_gxy, double* sxx, double* syy,
                            double* sxy) const = 0;
};

// sigma = Q eps in Voigt form [xx, yy, xy] with engineering shear strain.
class LinearElastic final : public ConstitutiveLaw {
 public:
  explicit LinearElastic(const std::array<double, 9>& stiffness);
  // Plane stress: Q11 = E/(1-nu^2); plane strain: Q11 = E(1-nu)/((1+nu)(1-2nu)).
  static LinearElastic Isotropic(double E, double nu, PlaneCondition plane);
  // Plane stress, material axis 1 at `angle` [rad] from x (lamination-theory
  // rotation Q-bar). Plane strain needs out-of-plane constants: throws.
  static LinearElastic Orthotropic(double E1, double E2, double G12, double nu12, double angle,
                                   PlaneCondition plane);
  static LinearElastic FromMaterial(const MaterialSpec& material, PlaneCondition plane);

  const char* Name() const override { return "linear-elastic"; }
  double MaxWaveSpeed(double density) const override;
  void UpdateStress(std::size_t count, const double* d_exx, const double* d_eyy,
                    const double* d_gxy, double* sxx, double* syy, double* sxy) const override;
  const std::array<double, 9>& Stiffness() const { return q_; }

 private:
  std::array<double, 9> q_;  // row-major 3x3
};

}  // namespace bridgefit::mpm
