// Specimen calibrations: ASTM E399 K, Saxena-Hudak compliance, DCB beam
// theories, Tada's edge crack. Equations: include/bridgefit/specimen/calibrations.hpp.
// Owner: engineer "experiment" (issue #6).
#include "bridgefit/specimen/calibrations.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"

namespace bridgefit::specimen {
namespace {

void RequirePositive(double value, const char* field, const char* unit_hint) {
  if (!(std::isfinite(value) && value > 0.0))
    throw Error(ErrorKind::kInput, "value must be positive and finite",
                {.field = field, .value = fmt::format("{:g}", value),
                 .expected = fmt::format("a value > 0 ({})", unit_hint)});
}

void RequireRange(double u, double lo, double hi, const char* field) {
  if (!(std::isfinite(u) && u >= lo && u <= hi))
    throw Error(ErrorKind::kInput, "relative crack length a/W outside the calibrated range",
                {.field = field, .value = fmt::format("{:.6g}", u),
                 .expected = fmt::format("{:g} <= a/W <= {:g}", lo, hi)});
}

// E399 polynomial in u and its derivative.
double E399Poly(double u) { return 0.886 + u * (4.64 + u * (-13.32 + u * (14.72 - 5.6 * u))); }
double E399PolyDerivative(double u) { return 4.64 + u * (-26.64 + u * (44.16 - 22.4 * u)); }

// Saxena-Hudak polynomial and derivative.
double ShPoly(double u) {
  return 2.1630 + u * (12.219 + u * (-20.065 + u * (-0.9925 + u * (20.609 - 9.9314 * u))));
}
double ShPolyDerivative(double u) {
  return 12.219 + u * (-40.13 + u * (-2.9775 + u * (82.436 - 49.657 * u)));
}

}  // namespace

// ---------------------------------------------------------------- moduli
double KolosovConstant(const MaterialSpec& m, PlaneCondition plane) {
  return plane == PlaneCondition::kPlaneStrain ? 3 - 4 * m.nu : (3 - m.nu) / (1 + m.nu);
}

InPlaneCompliance OrthotropicInPlaneCompliance(const MaterialSpec& m, PlaneCondition plane) {
  if (!m.orthotropic)
    throw Error(ErrorKind::kInternal, "in-plane orthotropic compliance of an isotropic material");
  RequirePositive(m.E1, "material.E1", "Pa");
  RequirePositive(m.E2, "material.E2", "Pa");
  RequirePositive(m.G12, "material.G12", "Pa");
  if (m.angle != 0.0)
    throw Error(ErrorKind::kInput,
                "effective modulus of a rotated orthotropic material is not implemented",
                {.field = "material.angle", .value = fmt::format("{:g} rad", m.angle),
                 .expected = "0 (axis 1 along the crack)"});
  double a11 = 1.0 / m.E1, a22 = 1.0 / m.E2, a12 = -m.nu12 / m.E1;
  const double a66 = 1.0 / m.G12;
  if (plane == PlaneCondition::kPlaneStrain) {
    // b_ij = a_ij - a_i3 a_j3 / a33 with E3 = E2, nu13 = nu23 = nu12.
    const double a33 = 1.0 / m.E2, a13 = -m.nu12 / m.E1, a23 = -m.nu12 / m.E2;
    const double b11 = a11 - a13 * a13 / a33, b22 = a22 - a23 * a23 / a33;
    const double b12 = a12 - a13 * a23 / a33;
    a11 = b11;
    a22 = b22;
    a12 = b12;
  }
  return {a11, a22, a12, a66};
}

double EffectiveModulus(const MaterialSpec& m, PlaneCondition plane) {
  if (!m.orthotropic) {
    RequirePositive(m.E, "material.E", "Pa");
    if (plane == PlaneCondition::kPlaneStress) return m.E;
    if (!(m.nu > -1.0 && m.nu < 0.5))
      throw Error(ErrorKind::kInput, "Poisson's ratio out of range",
                  {.field = "material.nu", .value = fmt::format("{:g}", m.nu),
                   .expected = "-1 < nu < 0.5"});
    return m.E / (1.0 - m.nu * m.nu);
  }
  const InPlaneCompliance c = OrthotropicInPlaneCompliance(m, plane);
  const double a11 = c.b11, a22 = c.b22, a12 = c.b12, a66 = c.b66;
  const double inner = std::sqrt(a22 / a11) + (2.0 * a12 + a66) / (2.0 * a11);
  if (!(inner > 0.0 && a11 > 0.0 && a22 > 0.0))
    throw Error(ErrorKind::kInput, "orthotropic constants give no positive effective modulus",
                {.field = "material.nu12", .value = fmt::format("{:g}", m.nu12)});
  // Sih, Paris & Irwin.
  return 1.0 / (std::sqrt(a11 * a22 / 2.0) * std::sqrt(inner));
}

// ---------------------------------------------------------------- CT
double CtGeometryFactor(double u) {
  RequireRange(u, kCtMinRelativeCrack, kCtMaxRelativeCrack, "a/W (E399 f)");
  return (2.0 + u) / std::pow(1.0 - u, 1.5) * E399Poly(u);
}

double CtGeometryFactorDerivative(double u) {
  RequireRange(u, kCtMinRelativeCrack, kCtMaxRelativeCrack, "a/W (E399 f)");
  const double g = (2.0 + u) / std::pow(1.0 - u, 1.5);
  // d/du (2+u)(1-u)^-1.5 = (1-u)^-1.5 + 1.5 (2+u)(1-u)^-2.5
  const double dg = 1.0 / std::pow(1.0 - u, 1.5) + 1.5 * (2.0 + u) / std::pow(1.0 - u, 2.5);
  return dg * E399Poly(u) + g * E399PolyDerivative(u);
}

double CtStressIntensity(double load, double B, double W, double a) {
  RequirePositive(W, "width W", "m");
  RequirePositive(B, "thickness B", "m");
  return load / (B * std::sqrt(W)) * CtGeometryFactor(a / W);
}

double CtEnergyReleaseRate(double load, double B, double W, double a, double E_eff) {
  RequirePositive(E_eff, "effective modulus E'", "Pa");
  const double K = CtStressIntensity(load, B, W, a);
  return K * K / E_eff;
}

double CtLoadLineComplianceFactor(double u) {
  RequireRange(u, kCtMinRelativeCrack, kCtMaxRelativeCrackCompliance, "a/W (Saxena-Hudak)");
  const double r = (1.0 + u) / (1.0 - u);
  return r * r * ShPoly(u);
}

double CtLoadLineComplianceFactorDerivative(double u) {
  RequireRange(u, kCtMinRelativeCrack, kCtMaxRelativeCrackCompliance, "a/W (Saxena-Hudak)");
  const double r = (1.0 + u) / (1.0 - u);
  const double dr = 2.0 / ((1.0 - u) * (1.0 - u));
  return 2.0 * r * dr * ShPoly(u) + r * r * ShPolyDerivative(u);
}

double CtLoadLineCompliance(double E_eff, double B, double W, double a) {
  RequirePositive(W, "width W", "m");
  RequirePositive(B, "thickness B", "m");
  RequirePositive(E_eff, "effective modulus E'", "Pa");
  return CtLoadLineComplianceFactor(a / W) / (E_eff * B);
}

double CtRelativeCrackFromComplianceFactor(double ebc) {
  const double lo = CtLoadLineComplianceFactor(kCtMinRelativeCrack);
  const double hi = CtLoadLineComplianceFactor(kCtMaxRelativeCrackCompliance);
  if (!(std::isfinite(ebc) && ebc >= lo && ebc <= hi))
    throw Error(ErrorKind::kInput, "normalised compliance E'BC outside the calibrated range",
                {.field = "E'BC", .value = fmt::format("{:.6g}", ebc),
                 .expected = fmt::format("{:.4g} <= E'BC <= {:.4g} (0.2 <= a/W <= 0.975)", lo,
                                         hi)});
  // E1820 A2 closed form (load-line C(T)).
  const double U = 1.0 / (std::sqrt(ebc) + 1.0);
  double u =
      1.000196 + U * (-4.06319 + U * (11.242 + U * (-106.043 + U * (464.335 - 650.677 * U))));
  u = std::clamp(u, kCtMinRelativeCrack, kCtMaxRelativeCrackCompliance);
  // Newton on the forward formula (monotone increasing), kept inside the range.
  for (int it = 0; it < 50; ++it) {
    const double r = CtLoadLineComplianceFactor(u) - ebc;
    const double du = r / CtLoadLineComplianceFactorDerivative(u);
    u = std::clamp(u - du, kCtMinRelativeCrack, kCtMaxRelativeCrackCompliance);
    if (std::abs(du) < 1e-13) break;
  }
  return u;
}

double CtCrackFromLoadLineCompliance(double E_eff, double B, double W, double C) {
  RequirePositive(C, "compliance C", "m/N");
  RequirePositive(W, "width W", "m");
  RequirePositive(B, "thickness B", "m");
  RequirePositive(E_eff, "effective modulus E'", "Pa");
  return W * CtRelativeCrackFromComplianceFactor(E_eff * B * C);
}

// ---------------------------------------------------------------- DCB
const char* DcbTheoryName(DcbTheory theory) {
  switch (theory) {
    case DcbTheory::kSimpleBeam: return "simple-beam";
    case DcbTheory::kCorrectedBeam: return "corrected-beam";
    case DcbTheory::kTimoshenko: return "timoshenko";
    case DcbTheory::kElasticFoundation: return "elastic-foundation";
  }
  return "?";
}

void DcbBeam::Validate(DcbTheory theory) const {
  RequirePositive(width, "specimen.width (b)", "m");
  RequirePositive(arm_thickness, "specimen.height (h, arm thickness)", "m");
  RequirePositive(E1, "material E1 (along the arms)", "Pa");
  if (E2 != 0.0) RequirePositive(E2, "material.E2", "Pa");
  if (theory == DcbTheory::kCorrectedBeam || theory == DcbTheory::kTimoshenko) {
    if (!(G13 > 0.0 && std::isfinite(G13)))
      throw Error(ErrorKind::kInput,
                  fmt::format("the {} DCB theory needs the transverse shear modulus",
                              DcbTheoryName(theory)),
                  {.field = "material.G13", .value = fmt::format("{:g}", G13),
                   .expected = "a value > 0 Pa"});
  }
}

DcbBeam DcbBeamFromScene(const SpecimenSpec& s, const MaterialSpec& m) {
  DcbBeam beam{.arm_thickness = s.height, .width = s.width};
  if (m.orthotropic) {
    beam.E1 = m.E1;
    beam.E2 = m.E2;
    beam.G13 = m.G13 > 0.0 ? m.G13 : m.G12;
  } else {
    beam.E1 = beam.E2 = m.E;
    if (m.E > 0.0 && m.nu > -1.0) beam.G13 = m.E / (2.0 * (1.0 + m.nu));
  }
  return beam;
}

double WilliamsChi(double E1, double E2, double G13) {
  RequirePositive(E1, "E1", "Pa");
  RequirePositive(E2, "E2", "Pa");
  RequirePositive(G13, "G13", "Pa");
  const double gamma = 1.18 * std::sqrt(E1 * E2) / G13;
  const double q = gamma / (1.0 + gamma);
  return std::sqrt(E1 / (11.0 * G13) * (3.0 - 2.0 * q * q));
}

double KanninenLength(const DcbBeam& beam) {
  const double E2 = beam.E2 > 0.0 ? beam.E2 : beam.E1;
  return beam.arm_thickness * std::pow(beam.E1 / (6.0 * E2), 0.25);
}

double DcbCrackLengthCorrection(const DcbBeam& beam, DcbTheory theory) {
  switch (theory) {
    case DcbTheory::kSimpleBeam:
    case DcbTheory::kTimoshenko: return 0.0;
    case DcbTheory::kCorrectedBeam:
      return WilliamsChi(beam.E1, beam.E2 > 0.0 ? beam.E2 : beam.E1, beam.G13) *
             beam.arm_thickness;
    case DcbTheory::kElasticFoundation: return KanninenLength(beam);
  }
  return 0.0;
}

double DcbCompliance(const DcbBeam& beam, double a, DcbTheory theory) {
  beam.Validate(theory);
  if (!(std::isfinite(a) && a >= 0.0))
    throw Error(ErrorKind::kInput, "crack length must be finite and >= 0",
                {.field = "crack_length", .value = fmt::format("{:g} m", a)});
  const double bend = 8.0 / (beam.E1 * beam.width * std::pow(beam.arm_thickness, 3));
  switch (theory) {
    case DcbTheory::kSimpleBeam: return bend * a * a * a;
    case DcbTheory::kCorrectedBeam: {
      const double ae = a + DcbCrackLengthCorrection(beam, theory);
      return bend * ae * ae * ae;
    }
    case DcbTheory::kTimoshenko:
      return bend * a * a * a + 12.0 * a / (5.0 * beam.width * beam.arm_thickness * beam.G13);
    case DcbTheory::kElasticFoundation: {
      const double l = KanninenLength(beam);  // 1/lambda
      return bend * (a * a * a + 3.0 * a * a * l + 3.0 * a * l * l + 1.5 * l * l * l);
    }
  }
  return NAN;
}

double DcbComplianceDerivative(const DcbBeam& beam, double a, DcbTheory theory) {
  beam.Validate(theory);
  const double bend = 8.0 / (beam.E1 * beam.width * std::pow(beam.arm_thickness, 3));
  switch (theory) {
    case DcbTheory::kSimpleBeam: return 3.0 * bend * a * a;
    case DcbTheory::kCorrectedBeam:
    case DcbTheory::kElasticFoundation: {
      const double ae = a + DcbCrackLengthCorrection(beam, theory);
      return 3.0 * bend * ae * ae;
    }
    case DcbTheory::kTimoshenko:
      return 3.0 * bend * a * a + 12.0 / (5.0 * beam.width * beam.arm_thickness * beam.G13);
  }
  return NAN;
}

double DcbEnergyReleaseRate(const DcbBeam& beam, double a, double load, DcbTheory theory) {
  return load * load / (2.0 * beam.width) * DcbComplianceDerivative(beam, a, theory);
}

double DcbCrackFromCompliance(const DcbBeam& beam, double C, DcbTheory theory) {
  beam.Validate(theory);
  const double c0 = DcbCompliance(beam, 0.0, theory);
  if (!(std::isfinite(C) && C > c0))
    throw Error(ErrorKind::kInput, "compliance not above the zero-crack-length compliance",
                {.field = "compliance", .value = fmt::format("{:.6g} m/N", C),
                 .expected = fmt::format("C > {:.6g} m/N", c0)});
  // Bracket [lo, hi], then Newton kept inside the bracket (C(a) increasing).
  double lo = 0.0, hi = std::max(beam.arm_thickness, 1e-6);
  while (DcbCompliance(beam, hi, theory) < C) {
    lo = hi;
    hi *= 2.0;
    if (hi > 1e6) throw Error(ErrorKind::kRuntime, "DCB compliance inversion did not bracket");
  }
  double a = 0.5 * (lo + hi);
  for (int it = 0; it < 200; ++it) {
    const double r = DcbCompliance(beam, a, theory) - C;
    if (r > 0) hi = a; else lo = a;
    const double d = DcbComplianceDerivative(beam, a, theory);
    double next = d > 0 ? a - r / d : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - a) < 1e-14 * std::max(1.0, a)) return next;
    a = next;
  }
  return a;
}

double DcbCbtCorrection(const DcbBeam& beam) {
  return DcbCrackLengthCorrection(beam, DcbTheory::kCorrectedBeam);
}
double DcbCbtCompliance(const DcbBeam& beam, double crack) {
  return DcbCompliance(beam, crack, DcbTheory::kCorrectedBeam);
}
double DcbCbtEnergyReleaseRate(const DcbBeam& beam, double crack, double load) {
  return DcbEnergyReleaseRate(beam, crack, load, DcbTheory::kCorrectedBeam);
}
double DcbFoundationCompliance(const DcbBeam& beam, double crack) {
  return DcbCompliance(beam, crack, DcbTheory::kElasticFoundation);
}
double DcbFoundationEnergyReleaseRate(const DcbBeam& beam, double crack, double load) {
  return DcbEnergyReleaseRate(beam, crack, load, DcbTheory::kElasticFoundation);
}

// ---------------------------------------------------------------- edge crack
double EdgeCrackFactor(double u) {
  if (!(std::isfinite(u) && u >= 0.0 && u <= 0.6))
    throw Error(ErrorKind::kInput, "relative edge-crack length outside the calibrated range",
                {.field = "a/b (edge crack)", .value = fmt::format("{:.6g}", u),
                 .expected = "0 <= a/b <= 0.6"});
  return 1.12 + u * (-0.231 + u * (10.55 + u * (-21.72 + 30.39 * u)));
}

}  // namespace bridgefit::specimen
