#pragma once
// LEFM calibrations of the test specimens (handbook closed forms), SI units
// throughout (N, m, Pa, J/m^2). They serve as oracles for the models and as
// the usual cross-checks of experiments (PHYSICS.md section 8). Every
// function throws bridgefit::Error (kInput) for a value outside the range it
// is valid for, naming the field and the range.
//
// CT (ASTM E399 / E647 / E1820), crack length a from the load line, width W,
// thickness B, u = a/W:
//   K = P / (B sqrt(W)) f(u),
//   f(u) = (2 + u) / (1 - u)^1.5 (0.886 + 4.64u - 13.32u^2 + 14.72u^3 - 5.6u^4)
//   E' B C = ((1 + u)/(1 - u))^2 (2.1630 + 12.219u - 20.065u^2 - 0.9925u^3
//            + 20.609u^4 - 9.9314u^5)                     (Saxena & Hudak 1978)
// Ranges enforced: f(u) for 0.2 <= u <= 0.95 (E399 states the polynomial for
// u >= 0.2; a K_Ic is valid only for 0.45..0.55, which is not enforced here);
// the compliance for 0.2 <= u <= 0.975 (E647's stated range). Note: G from
// the compliance derivative and K^2/E' from f(u) agree within 1.5% for
// u >= 0.4 but differ by 9% at u = 0.3 and 27% at u = 0.2 (two fits).
//
// DCB (ASTM D5528), one arm of thickness h, width b, crack length a from the
// load line, modulus E1 along the arms:
//   simple beam    C = 8 a^3 / (E1 b h^3),           G = 12 P^2 a^2 / (E1 b^2 h^3)
//   corrected      a -> a + chi h (Williams' root rotation, chi from E11, E22, G13)
//   Timoshenko     C = 8 a^3 / (E1 b h^3) + 12 a / (5 b h G13)
//   foundation     C = 8/(E1 b h^3) (a^3 + 3a^2 l + 3a l^2 + 3 l^3 / 2),
//                  l = 1/lambda, lambda^4 = 6 E2 / (E1 h^4)   (Kanninen 1973)
// G = P^2 / (2b) dC/da in every case.

#include "bridgefit/scene/scene.hpp"

namespace bridgefit::specimen {

// ---- Moduli ---------------------------------------------------------------
// E' such that G = K_I^2 / E' for a mode I crack along material axis 1.
// Isotropic: E (plane stress) or E / (1 - nu^2) (plane strain).
// Orthotropic (angle 0): Sih-Paris-Irwin
//   1/E' = sqrt(b11 b22 / 2) sqrt(sqrt(b22/b11) + (2 b12 + b66) / (2 b11)),
// plane stress b = a: a11 = 1/E1, a22 = 1/E2, a12 = -nu12/E1, a66 = 1/G12;
// plane strain b_ij = a_ij - a_i3 a_j3 / a33 with the out-of-plane constants
// the scene does not carry taken as E3 = E2, nu13 = nu12, nu23 = nu12.
// A rotated material (angle != 0) throws.
double EffectiveModulus(const MaterialSpec& material, PlaneCondition plane);

// The in-plane compliances b11, b22, b12, b66 [1/Pa] of an orthotropic
// material (axis 1 along the crack) that EffectiveModulus uses: plane stress
// a_ij, plane strain reduced as above. Throws for an isotropic or rotated
// material.
struct InPlaneCompliance {
  double b11 = 0, b22 = 0, b12 = 0, b66 = 0;
};
InPlaneCompliance OrthotropicInPlaneCompliance(const MaterialSpec& material, PlaneCondition plane);

// Kolosov's constant of an isotropic material: 3 - 4 nu in plane strain,
// (3 - nu) / (1 + nu) in plane stress.
double KolosovConstant(const MaterialSpec& material, PlaneCondition plane);

// ---- Compact tension, ASTM E399 proportions -----------------------------
inline constexpr double kCtMinRelativeCrack = 0.2;
inline constexpr double kCtMaxRelativeCrack = 0.95;            // f(a/W)
inline constexpr double kCtMaxRelativeCrackCompliance = 0.975;  // Saxena-Hudak

// f(a/W) of ASTM E399 and df/du. Throws outside [0.2, 0.95].
double CtGeometryFactor(double relative_crack);
double CtGeometryFactorDerivative(double relative_crack);
// K [Pa m^0.5] for load P [N], thickness B, width W, crack a [m].
double CtStressIntensity(double load, double thickness, double width, double crack);
// G = K^2 / E' [J/m^2].
double CtEnergyReleaseRate(double load, double thickness, double width, double crack,
                           double effective_modulus);
// Saxena & Hudak (1978) load-line compliance, dimensionless E' B V / P, and
// its derivative d/du. Throws outside [0.2, 0.975].
double CtLoadLineComplianceFactor(double relative_crack);
double CtLoadLineComplianceFactorDerivative(double relative_crack);
// Load-line compliance V/P [m/N] with the effective modulus E' [Pa].
double CtLoadLineCompliance(double effective_modulus, double thickness, double width,
                            double crack);
// Inverse: a/W from E'BC. E1820's closed form in U = 1/(sqrt(E'BC) + 1) as
// the start, refined by Newton on the forward formula to |du| < 1e-13.
double CtRelativeCrackFromComplianceFactor(double compliance_factor);
// Crack length a [m] from a load-line compliance C [m/N].
double CtCrackFromLoadLineCompliance(double effective_modulus, double thickness, double width,
                                     double compliance);

// ---- Double cantilever beam ----------------------------------------------
enum class DcbTheory {
  kSimpleBeam,        // Euler-Bernoulli arms built in at the crack tip
  kCorrectedBeam,     // a + chi h, chi from Williams (E1, E2, G13)
  kTimoshenko,        // bending + shear (G13), no root rotation
  kElasticFoundation  // Kanninen: arms on a Winkler foundation of stiffness 2 E2 b / h
};
const char* DcbTheoryName(DcbTheory theory);

struct DcbBeam {
  double arm_thickness = 0.0;  // h [m], one arm
  double width = 0.0;          // b [m]
  double E1 = 0.0;             // axial (bending) modulus [Pa]
  double E2 = 0.0;             // transverse modulus [Pa]; 0: take E1
  double G13 = 0.0;            // transverse shear modulus [Pa]; 0: unknown
  // Throws Error naming the field when a value the theory needs is missing.
  void Validate(DcbTheory theory) const;
};
// The beam constants of a scene's DCB: b = specimen.width, h = specimen.height,
// E1 = AxialModulus; isotropic: E2 = E, G13 = E/(2(1+nu)); orthotropic:
// G13 (or G12 when G13 is 0).
DcbBeam DcbBeamFromScene(const SpecimenSpec& specimen, const MaterialSpec& material);

// Williams' root-rotation factor (ASTM D5528):
//   chi = sqrt(E1/(11 G13) (3 - 2 (Gamma/(1+Gamma))^2)), Gamma = 1.18 sqrt(E1 E2) / G13.
double WilliamsChi(double E1, double E2, double G13);
// Kanninen's foundation length 1/lambda = h (E1 / (6 E2))^(1/4).
double KanninenLength(const DcbBeam& beam);
// Length the theory adds to a in G: 0, chi h, 0 (shear is no length shift), 1/lambda.
double DcbCrackLengthCorrection(const DcbBeam& beam, DcbTheory theory);

// Load-point compliance (both arms) [m/N] and dC/da [1/N].
double DcbCompliance(const DcbBeam& beam, double crack, DcbTheory theory);
double DcbComplianceDerivative(const DcbBeam& beam, double crack, DcbTheory theory);
// G = P^2 / (2 b) dC/da [J/m^2].
double DcbEnergyReleaseRate(const DcbBeam& beam, double crack, double load, DcbTheory theory);
// Crack length [m] with DcbCompliance(a) = C (C increases monotonically in a;
// safeguarded Newton). Throws when C is not above the a = 0 compliance.
double DcbCrackFromCompliance(const DcbBeam& beam, double compliance, DcbTheory theory);

// Shorthands for the two theories used most.
// chi h of corrected beam theory [m].
double DcbCbtCorrection(const DcbBeam& beam);
double DcbCbtCompliance(const DcbBeam& beam, double crack);
double DcbCbtEnergyReleaseRate(const DcbBeam& beam, double crack, double load);
double DcbFoundationCompliance(const DcbBeam& beam, double crack);
double DcbFoundationEnergyReleaseRate(const DcbBeam& beam, double crack, double load);

// ---- Single edge crack in a long strip (Tada, Paris & Irwin) --------------
// F(a/b) for uniform remote tension or, equivalently, uniform pressure on the
// crack faces: K = sigma sqrt(pi a) F,
// F = 1.12 - 0.231 u + 10.55 u^2 - 21.72 u^3 + 30.39 u^4; 0.5% for u <= 0.6
// (enforced: 0 <= u <= 0.6).
double EdgeCrackFactor(double relative_crack);

}  // namespace bridgefit::specimen
