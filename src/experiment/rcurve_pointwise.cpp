// Point-wise R-curve methods: one G(P, d, a) per row (mbt and cc in
// rcurve_beam.cpp). DCB: beam-theory LEFM, the equivalent crack; CT: E399 LEFM with measured or compliance crack lengths.
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/specimen/calibrations.hpp"
#include "rcurve_stages.hpp"

namespace bridgefit::experiment::detail {

void PointwiseCurve(const Prepared& p, RCurveResult& result, const Formula& G,
                    const Formula& crack_of, int first_point) {
  const Rows& w = p.w;
  const int m = static_cast<int>(w.size());
  const double sigma_P = p.sigma_P, sigma_d = p.sigma_d, sigma_a = p.sigma_a, a0 = p.a0;
  const double a_limit = p.a_limit, k_cov = p.options->coverage_factor;
  const bool has_a = p.has_a;
  const int nl = p.nl, off = p.off;
  Initiation& init = result.initiation;
  if (first_point < 0) first_point = nl;
  AddDropped(result, "before initiation", first_point);
  int zero_load = 0, out_of_range = 0;
  for (int k = first_point; k < m; ++k) {
    const double P = w.P[k], d = w.d[k], a = w.a.empty() ? NAN : w.a[k];
    if (!(P > 0) || !(d > 0)) {
      ++zero_load;
      continue;
    }
    try {
      const double R = G(P, d, a);
      const double gp = (G(P + sigma_P, d, a) - G(P - sigma_P, d, a)) / 2.0;
      const double gd = (G(P, d + sigma_d, a) - G(P, d - sigma_d, a)) / 2.0;
      const double ga = has_a ? (G(P, d, a + sigma_a) - G(P, d, a - sigma_a)) / 2.0 : 0.0;
      const double ar = crack_of(P, d, a);
      if (std::isfinite(a_limit) && ar > a_limit) {
        AddDropped(result, fmt::format("past the validity limit a > {} (edge effect)", Mm(a_limit)), 1);
        continue;
      }
      PushPoint(p, result, k, ar, R, k_cov * std::sqrt(gp * gp + gd * gd + ga * ga));
    } catch (const Error&) {
      ++out_of_range;  // outside a calibration's range (e.g. a/W < 0.2)
    }
  }
  AddDropped(result, "zero load or displacement", zero_load);
  AddDropped(result, "outside the calibrated range of the specimen formula", out_of_range);
  result.points_used = static_cast<int>(result.curve.size());
  if (result.curve.size() == 0)
    throw Error(ErrorKind::kInput,
                fmt::format("R curve ({} method), stage 'R points': no row gives an R point",
                            RMethodName(p.options->method)),
                {.file = p.src, .field = "load",
                 .expected = "rows with positive load and displacement inside the formula's "
                             "range after initiation; way out: another --method"});
  // Initiation values with a = a0 (crack lengths) or from the compliance.
  auto at = [&](int k) -> double {
    try {
      return G(w.P[k], w.d[k], w.a.empty() ? a0 : w.a[k]);
    } catch (const Error&) {
      return NAN;
    }
  };
  init.R_nonlinearity = at(nl);
  init.R_offset = at(off);
  result.curve.initiation_R =
      std::isfinite(init.R_nonlinearity) ? init.R_nonlinearity : result.curve.R.front();
}

void CtMethod(const Prepared& p, RCurveResult& result) {
  const RCurveOptions& options = *p.options;
  const SpecimenSpec& spec = options.specimen;
  const double a0 = p.a0, B = p.B;
  const LinearFit& lin = p.lin;
  const bool has_a = p.has_a;
  Formula G, crack_of;
  // CT lefm / equivalent: E399 K with a measured or from the compliance.
  const double W = spec.width;
  double E_eff = NAN;
  try {
    E_eff = specimen::EffectiveModulus(options.material, spec.plane);
  } catch (const Error&) {
    if (!options.calibrate_modulus) throw;
  }
  if (options.calibrate_modulus) {
    BF_CHECK_INPUT(a0 > 0, "the initial crack length is needed to calibrate the modulus",
                   {.field = "specimen.notch", .expected = "a0 > 0 (notch or first crack length)"});
    const double E_cal = specimen::CtLoadLineComplianceFactor(a0 / W) / (B * lin.slope);
    if (std::isfinite(E_eff)) result.figures["modulus_ratio_calibrated_to_material"] = E_cal / E_eff;
    E_eff = E_cal;
    result.figures["calibrated_effective_modulus_Pa"] = E_cal;
  }
  const double d0 = lin.intercept;
  const bool from_compliance = !has_a;
  result.figures["effective_modulus_Pa"] = E_eff;
  crack_of = [=](double P, double d, double a) {
    return from_compliance ? specimen::CtCrackFromLoadLineCompliance(E_eff, B, W, (d - d0) / P) : a;
  };
  G = [=](double P, double d, double a) {
    return specimen::CtEnergyReleaseRate(P, B, W, crack_of(P, d, a), E_eff);
  };
  if (from_compliance) result.notes.push_back("crack length from the Saxena-Hudak compliance inverse");
  PointwiseCurve(p, result, G, crack_of, has_a ? p.first_growth : p.nl);
}

void DcbLefmMethod(const Prepared& p, RCurveResult& result) {
  const RCurveOptions& options = *p.options;
  const specimen::DcbBeam beam = specimen::DcbBeamFromScene(options.specimen, options.material);
  Formula G, crack_of;
  const specimen::DcbTheory theory = options.beam_shear && beam.G13 > 0
                                         ? specimen::DcbTheory::kCorrectedBeam
                                         : specimen::DcbTheory::kElasticFoundation;
  result.notes.push_back(std::string("DCB beam theory: ") + specimen::DcbTheoryName(theory));
  result.figures["beam_crack_length_correction_m"] = specimen::DcbCrackLengthCorrection(beam, theory);
  G = [=](double P, double, double a) { return specimen::DcbEnergyReleaseRate(beam, a, P, theory); };
  crack_of = [](double, double, double a) { return a; };
  PointwiseCurve(p, result, G, crack_of, p.first_growth);
}

void DcbEquivalentMethod(const Prepared& p, RCurveResult& result) {
  const RCurveOptions& options = *p.options;
  const SpecimenSpec& spec = options.specimen;
  const double a0 = p.a0, B = p.B;
  const LinearFit& lin = p.lin;
  const ExperimentRecord& record = *p.record;
  const specimen::DcbBeam beam = specimen::DcbBeamFromScene(spec, options.material);
  Formula G, crack_of;
  // DCB equivalent crack: flexural modulus from C0 at a0 + |Delta|, then
  // a_e from every compliance (de Moura et al. 2008 with Timoshenko arms
  // when G13 is known).
  BF_CHECK_INPUT(a0 > 0, "the equivalent-crack method needs the initial crack length",
                 {.field = "specimen.notch", .expected = "a0 > 0 (notch or first crack length)"});
  double delta = options.crack_length_correction;
  std::string delta_source = "given";
  if (std::isnan(delta) && record.has_crack_length()) {
    RCurveOptions mbt_options = options;
    mbt_options.method = RMethod::kMbt;
    const RCurveResult mbt = ComputeRCurve(record, mbt_options);
    delta = std::abs(mbt.figures.at("mbt_delta_m"));
    delta_source = "MBT fit of the record's crack lengths";
  }
  if (std::isnan(delta) && options.beam_shear && beam.G13 > 0 && beam.E1 > 0) {
    delta = specimen::DcbCrackLengthCorrection(beam, specimen::DcbTheory::kCorrectedBeam);
    delta_source = "Williams chi h";
  }
  if (std::isnan(delta)) {
    delta = 0.0;
    delta_source = "none (no crack lengths, no G13): R biased high by about (a0+Delta)/a0";
  }
  const specimen::DcbTheory theory = options.beam_shear && beam.G13 > 0
                                         ? specimen::DcbTheory::kTimoshenko
                                         : specimen::DcbTheory::kSimpleBeam;
  specimen::DcbBeam cal = beam;
  cal.E1 = 1.0;
  const double ae0 = a0 + delta;
  // C0 = 8 ae0^3/(Ef b h^3) (+ 12 ae0/(5 b h G13)): solve for Ef.
  const double shear = theory == specimen::DcbTheory::kTimoshenko
                           ? 12.0 * ae0 / (5.0 * beam.width * beam.arm_thickness * beam.G13)
                           : 0.0;
  BF_CHECK_INPUT(lin.slope > shear, "initial compliance below the shear compliance",
                 {.field = "material.G13"});
  cal.E1 = 8.0 * ae0 * ae0 * ae0 /
           (beam.width * std::pow(beam.arm_thickness, 3) * (lin.slope - shear));
  result.figures["flexural_modulus_Pa"] = cal.E1;
  result.figures["equivalent_delta_m"] = delta;
  result.notes.push_back("equivalent crack: Delta from " + delta_source + "; arms: " +
                         specimen::DcbTheoryName(theory));
  const double d0 = lin.intercept;
  crack_of = [=](double P, double d, double) {
    return specimen::DcbCrackFromCompliance(cal, (d - d0) / P, theory) - delta;
  };
  G = [=](double P, double d, double a) {
    return specimen::DcbEnergyReleaseRate(cal, crack_of(P, d, a) + delta, P, theory);
  };

  PointwiseCurve(p, result, G, crack_of, p.nl);
}

}  // namespace bridgefit::experiment::detail
