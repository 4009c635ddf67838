// The validation campaign's statistics and outputs (validation.hpp).

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "validation.hpp"

namespace bridgefit::validate {
namespace {

constexpr const char* kNames[3] = {"sigma_c", "J_B", "J_tip_c"};
// Display units: MPa for sigma_c, J/m^2 for the energies.
constexpr double kScale[3] = {1e-6, 1.0, 1.0};
constexpr const char* kUnit[3] = {"MPa", "J_per_m2", "J_per_m2"};

double Median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Wilson score interval (95%) for k successes in n.
void Wilson(int k, int n, double* low, double* high) {
  if (n == 0) {
    *low = *high = NAN;
    return;
  }
  const double z = 1.96, p = double(k) / n, z2n = z * z / n;
  const double centre = (p + z2n / 2) / (1 + z2n);
  const double half = z * std::sqrt(p * (1 - p) / n + z2n / (4 * n)) / (1 + z2n);
  *low = centre - half;
  *high = centre + half;
}

ParameterStats ParameterSummary(const std::vector<CaseResult>& results, int p) {
  ParameterStats st;
  std::vector<double> rel_errors, abs_errors, widths, z, cr;
  for (const CaseResult& r : results) {
    if (!r.ran) continue;
    const ParameterCheck& c = r.parameters[p];
    if (std::isfinite(c.value)) ++st.estimates;
    if (std::isfinite(c.lower_bound)) ++st.bounds;
    st.bounds_above_truth += c.bound_above_truth;
    st.failures += c.failure;
    st.silent_failures += c.silent_failure;
    if (!c.has_interval) continue;
    ++st.identified;
    st.covered += c.covered;
    rel_errors.push_back(c.value / c.truth - 1.0);
    abs_errors.push_back(std::abs(c.value / c.truth - 1.0));
    if (std::isfinite(c.width_ratio)) widths.push_back(c.width_ratio);
    // The Wald width is the Cramer-Rao width only where the Fisher
    // information is regular: every parameter of the case identified (a
    // bound-only J_B leaves J^T J nearly singular and inflates the others').
    const bool all_identified = std::all_of(r.parameters.begin(), r.parameters.end(),
                                            [](const ParameterCheck& q) { return q.has_interval; });
    if (all_identified && c.model_error_small && std::isfinite(c.cr_width_ratio))
      cr.push_back(c.cr_width_ratio);
    const double stat_half = c.truth >= c.value ? c.stat_high - c.value : c.value - c.stat_low;
    if (std::isfinite(stat_half) && stat_half > 0.0)
      z.push_back((c.value - c.truth) / (stat_half / 1.96));
  }
  st.coverage = st.identified ? double(st.covered) / st.identified : NAN;
  Wilson(st.covered, st.identified, &st.coverage_low, &st.coverage_high);
  double mean = 0.0;
  for (double e : rel_errors) mean += e / rel_errors.size();
  st.bias_percent = rel_errors.empty() ? NAN : 100.0 * mean;
  st.median_abs_error_percent = 100.0 * Median(abs_errors);
  st.width_ratio_median = Median(widths);
  st.cr_cases = static_cast<int>(cr.size());
  st.cr_ratio_median = Median(cr);
  st.cr_ratio_mean = NAN;
  if (!cr.empty()) {
    st.cr_ratio_mean = 0.0;
    for (double v : cr) st.cr_ratio_mean += v / cr.size();
  }
  double zz = 0.0;
  for (double v : z) zz += v * v;
  st.z_sd = z.empty() ? NAN : std::sqrt(zz / z.size());
  return st;
}

std::string Num(double v, int digits = 5) {
  return std::isfinite(v) ? fmt::format("{:.{}g}", v, digits) : std::string("nan");
}

// CSV cells must not hold commas or quotes: warnings are joined with " | ".
std::string CsvText(std::string text) {
  for (char& ch : text)
    if (ch == ',' || ch == '"' || ch == '\n') ch = ';';
  return text;
}

}  // namespace

CampaignStats Summarise(const std::vector<CaseResult>& results) {
  CampaignStats s;
  s.cases = static_cast<int>(results.size());
  for (const CaseResult& r : results) {
    s.generate_s += r.generate_s;
    s.fit_s += r.fit_s;
    if (!r.ran) {
      ++(r.generation_failed ? s.generation_failures : s.errors);
      continue;
    }
    ++s.ran;
    s.bridging_missed_large += !r.bridging_detected && r.truth_R_rise >= 0.1;
    s.truth_steady += r.truth_steady_state;
    s.fit_steady += r.fit_steady_state;
    s.steady_agree += r.truth_steady_state == r.fit_steady_state;
    s.bridging_detected += r.bridging_detected;
    s.converged += r.converged;
    s.warned_cases += !r.warnings.empty();
  }
  for (int p = 0; p < 3; ++p) {
    s.parameters[p] = ParameterSummary(results, p);
    s.silent_failures += s.parameters[p].silent_failures;
  }
  return s;
}

std::string CaseCsvHeader() {
  std::string h =
      "case, seed, label, specimen, size_mm, material, law, route, load_noise_rel, "
      "displacement_noise_um, crack_noise_mm, notch_mm, max_crack_length_mm, "
      "generation_resolution_mm, fit_resolution_mm, truth_R_rise_rel, ran, error, truth_steady_state, "
      "fit_steady_state, bridging_detected, converged, data_points, generate_s, fit_s";
  for (int p = 0; p < 3; ++p) {
    const std::string n = kNames[p], u = kUnit[p];
    h += fmt::format(
        ", {0}_truth_{1}, {0}_value_{1}, {0}_ci95_low_{1}, {0}_ci95_high_{1}, "
        "{0}_stat_ci95_low_{1}, {0}_stat_ci95_high_{1}, {0}_lower_bound_{1}, {0}_identified, "
        "{0}_interval_status, {0}_covered, {0}_error_over_halfwidth, {0}_width_ratio, "
        "{0}_warned, {0}_failure, {0}_silent_failure",
        n, u);
  }
  for (int p = 0; p < 3; ++p)
    h += fmt::format(", {0}_width_over_cramer_rao, {0}_model_error_small", kNames[p]);
  return h + ", dic_frames, dic_flagged, dic_mean_error_mm, dic_max_abs_error_mm, dic_s, warnings\n";
}

std::string CaseCsvRow(const CaseResult& r) {
  const ValidationCase& c = r.spec;
  const SpecimenSpec& sp = c.scene.specimen;
  const bool ct = sp.type == SpecimenType::kCT;
  std::string row = fmt::format(
      "{}, {}, {}, {}, {:.2f}, {}, {}, {}, {:.4g}, {:.3g}, {:.3g}, {:.2f}, {:.2f}, {:.4g}, {}, {:.4g}, "
      "{}, {}, {}, {}, {}, {}, {}, {:.2f}, {:.2f}",
      c.index, c.seed, CsvText(c.Label()), ct ? "CT" : "DCB", (ct ? sp.width : sp.height) * 1e3,
      c.scene.material.orthotropic ? "orthotropic" : "isotropic",
      laws::LawFamilyName(c.scene.bridging->shape.family), RouteName(c.route), c.load_noise,
      c.displacement_noise * 1e6, c.crack_noise * 1e3, sp.notch * 1e3, r.max_crack_length * 1e3,
      c.generation_resolution * 1e3, Num(r.fit_resolution * 1e3), r.truth_R_rise, r.ran, CsvText(r.error),
      r.truth_steady_state, r.fit_steady_state, r.bridging_detected, r.converged, r.data_points,
      r.generate_s, r.fit_s);
  for (int p = 0; p < 3; ++p) {
    if (!r.ran) {  // no fit: every cell of the parameter is nan
      for (int cell = 0; cell < 15; ++cell) row += ", nan";
      continue;
    }
    const ParameterCheck& k = r.parameters[p];
    const double f = kScale[p];
    row += fmt::format(", {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}", Num(k.truth * f),
                       Num(k.value * f), Num(k.low * f), Num(k.high * f), Num(k.stat_low * f),
                       Num(k.stat_high * f), Num(k.lower_bound * f), k.identified,
                       k.interval_status, k.covered, Num(k.error_ratio, 4), Num(k.width_ratio, 4),
                       k.warned, k.failure, k.silent_failure);
  }
  for (int p = 0; p < 3; ++p)
    row += r.ran ? fmt::format(", {}, {}", Num(r.parameters[p].cr_width_ratio, 4),
                               r.parameters[p].model_error_small)
                 : std::string(", nan, nan");
  std::string warnings;
  for (const std::string& w : r.warnings) warnings += (warnings.empty() ? "" : " | ") + w;
  row += fmt::format(", {}, {}, {}, {}, {:.2f}", r.dic_frames, r.dic_flagged, Num(r.dic_mean_error * 1e3),
                     Num(r.dic_max_abs_error * 1e3), r.dic_s);
  return row + ", " + CsvText(warnings) + "\n";
}

std::string SummaryTable(const CampaignStats& s) {
  std::string t = fmt::format(
      "cases {} (ran {}, fit threw {}, generation threw {}), converged {}, cases with a warning {}, bridging detected {} "
      "(missed with the true R rise >= 0.1 J_tip,c: {})\n"
      "steady state: truth {} / fit {} / agree {}; generation {:.0f} s, fits {:.0f} s (summed)\n",
      s.cases, s.ran, s.errors, s.generation_failures, s.converged, s.warned_cases, s.bridging_detected,
      s.bridging_missed_large, s.truth_steady,
      s.fit_steady, s.steady_agree, s.generate_s, s.fit_s);
  t += fmt::format("{:<8} {:>5} {:>5} {:>8} {:>15} {:>8} {:>9} {:>7} {:>6} {:>7} {:>9} {:>7}\n",
                   "param", "est", "ident", "cover", "Wilson95", "bias%", "med|e|%", "Wtot/st",
                   "z_sd", "bounds", "bnd>true", "fail/sil");
  for (int p = 0; p < 3; ++p) {
    const ParameterStats& q = s.parameters[p];
    t += fmt::format(
        "{:<8} {:>5} {:>5} {:>7.1f}% {:>6.1f}-{:>5.1f}% {:>+8.2f} {:>9.2f} {:>7.2f} {:>6.2f} {:>7} "
        "{:>9} {:>3}/{:<3}\n",
        kNames[p], q.estimates, q.identified, 100 * q.coverage, 100 * q.coverage_low,
        100 * q.coverage_high, q.bias_percent, q.median_abs_error_percent, q.width_ratio_median,
        q.z_sd, q.bounds, q.bounds_above_truth, q.failures, q.silent_failures);
  }
  t += "total width / Cramer-Rao width (2 x 1.96 x the Jacobian's sd at the estimate), where the "
       "model's predicted bias is <= 0.3 sd and every parameter of the case is identified:\n";
  for (int p = 0; p < 3; ++p) {
    const ParameterStats& q = s.parameters[p];
    t += fmt::format("  {:<8} {} estimates, mean {}, median {}\n", kNames[p], q.cr_cases,
                     Num(q.cr_ratio_mean, 3), Num(q.cr_ratio_median, 3));
  }
  t += fmt::format("silent failures: {}\n", s.silent_failures);
  return t;
}

std::string FailureList(const std::vector<CaseResult>& results, bool silent_only) {
  std::string out;
  for (const CaseResult& r : results) {
    if (!r.ran) {
      if (!silent_only)
        out += fmt::format("{}: {} threw: {}\n", r.spec.Label(),
                           r.generation_failed ? "generation" : "fit", r.error);
      continue;
    }
    for (int p = 0; p < 3; ++p) {
      const ParameterCheck& k = r.parameters[p];
      if (!k.failure || (silent_only && !k.silent_failure)) continue;
      const double f = kScale[p];
      out += fmt::format(
          "{} (seed {}): {} truth {} {}, estimate {} [{}, {}] (statistical [{}, {}]), lower "
          "bound {}, |error|/half-width {}, interval {}, {}{}\n",
          r.spec.Label(), r.spec.seed, kNames[p], Num(k.truth * f), kUnit[p], Num(k.value * f),
          Num(k.low * f), Num(k.high * f), Num(k.stat_low * f), Num(k.stat_high * f),
          Num(k.lower_bound * f), Num(k.error_ratio, 3), k.interval_status,
          k.silent_failure ? "SILENT" : "warned",
          r.warnings.empty() ? "" : " (" + r.warnings.front() + ")");
    }
  }
  return out;
}

std::string MissedBridgingList(const std::vector<CaseResult>& results) {
  std::string out;
  for (const CaseResult& r : results) {
    if (!r.ran || r.bridging_detected || r.truth_R_rise < 0.1) continue;
    const laws::LawScales& t = r.spec.scene.bridging->scales;
    const ParameterCheck& tip = r.parameters[2];
    out += fmt::format(
        "{} (seed {}): truth sigma_c {} MPa, J_B {} J/m^2, J_tip_c {} J/m^2, R rise {:.0f}% over "
        "{:.1f} mm of growth ({} R points); fitted J_tip_c {} [{}, {}]\n",
        r.spec.Label(), r.spec.seed, Num(t.sigma_c * 1e-6), Num(t.J_B), Num(tip.truth),
        100 * r.truth_R_rise, (r.max_crack_length - r.spec.scene.specimen.notch) * 1e3,
        r.data_points, Num(tip.value), Num(tip.low), Num(tip.high));
  }
  return out;
}

std::string ReproductionToml(const ValidationCase& c) {
  const SpecimenSpec& sp = c.scene.specimen;
  const MaterialSpec& m = c.scene.material;
  const bool ct = sp.type == SpecimenType::kCT;
  const char* route = c.route == Route::kMbt    ? " --rcurve-method mbt"
                      : c.route == Route::kLoad ? " --fit-to load-displacement --calibrate-compliance=crack"
                                                : "";
  std::string t = fmt::format(
      "# Validation case {} (seed {}): {}\n"
      "#   bridgefit synth case.toml --out case --seed {} --resolution '{:.17g} mm' --frames 0 "
      "--far-field {:.17g} --load-noise {:.17g} --displacement-noise '{:.17g} um' --crack-noise "
      "'{:.17g} mm'\n"
      "#   bridgefit fit case/record.csv --scene case.toml --law {}{}\n"
      "# (the fit reads only [specimen] and [material] from the scene; the CLI's synth\n"
      "# draws its noise as the library does, seeded by --seed)\n",
      c.index, c.seed, c.Label(), c.seed, c.generation_resolution * 1e3, c.generation_far_field,
      c.load_noise,
      c.displacement_noise * 1e6, c.crack_noise * 1e3,
      laws::LawFamilyName(c.scene.bridging->shape.family), route);
  t += fmt::format("[specimen]\ntype = \"{}\"\nwidth = \"{:.17g} mm\"\nheight = \"{:.17g} mm\"\n",
                   ct ? "ct" : "dcb", sp.width * 1e3, sp.height * 1e3);
  if (ct) t += fmt::format("thickness = \"{:.17g} mm\"\n", sp.thickness * 1e3);
  else t += fmt::format("length = \"{:.17g} mm\"\n", sp.length * 1e3);
  t += fmt::format("notch = \"{:.17g} mm\"\nplane = \"stress\"\n\n[material]\n", sp.notch * 1e3);
  if (m.orthotropic)
    t += fmt::format("E1 = \"{:.17g} GPa\"\nE2 = \"{:.17g} GPa\"\nG12 = \"{:.17g} GPa\"\nnu12 = {:.17g}\n",
                     m.E1 * 1e-9, m.E2 * 1e-9, m.G12 * 1e-9, m.nu12);
  else
    t += fmt::format("E = \"{:.17g} GPa\"\nnu = {:.17g}\n", m.E * 1e-9, m.nu);
  t += fmt::format("density = \"{:.17g} kg/m^3\"\n\n[fracture]\nJ_tip_c = \"{:.17g} J/m^2\"\n\n",
                   m.density, c.scene.fracture->J_tip_c);
  const BridgingSpec& b = *c.scene.bridging;
  t += fmt::format("[bridging]\nlaw = \"{}\"\nsigma_c = \"{:.17g} MPa\"\nJ_B = \"{:.17g} J/m^2\"\n",
                   laws::LawFamilyName(b.shape.family), b.scales.sigma_c * 1e-6, b.scales.J_B);
  if (b.shape.family == laws::LawFamily::kTriangular)
    t += fmt::format("peak_ratio = {:.17g}\n", b.shape.peak_ratio);
  if (b.shape.family == laws::LawFamily::kExponential)
    t += fmt::format("alpha = {:.17g}\n", b.shape.alpha);
  t += fmt::format("\n[run]\nmax_crack_length = \"{:.17g} mm\"\n", *c.scene.run.max_crack_length * 1e3);
  return t;
}

std::string CoverageData(const CampaignStats& s) {
  std::string d = "# parameter index, name, coverage_percent, wilson_low_percent, wilson_high_percent, identified\n";
  for (int p = 0; p < 3; ++p) {
    const ParameterStats& q = s.parameters[p];
    d += fmt::format("{} {} {:.3f} {:.3f} {:.3f} {}\n", p, kNames[p], 100 * q.coverage,
                     100 * q.coverage_low, 100 * q.coverage_high, q.identified);
  }
  return d;
}

std::string GnuplotScript(const std::string& base) {
  // Columns of the case CSV: error_over_halfwidth of sigma_c, J_B, J_tip_c.
  const int first = 26, stride = 15, ratio = 10;  // 1-based: parameter block start + offset
  std::string gp = "set terminal pngcairo size 1100,440 enhanced font 'Sans,10'\n";
  gp += "set output '" + base + ".png'\nset multiplot layout 1,2\n";
  gp += "set title 'Coverage of the 95% total intervals (identified estimates)'\n";
  gp += "set ylabel 'coverage [%]'\nset yrange [40:100]\nset xrange [-0.5:2.5]\nset grid y\n";
  gp += "set xtics ('sigma_c' 0, 'J_B' 1, 'J_{tip,c}' 2)\nset key bottom right\n";
  gp += "set object 1 rect from -0.5,90 to 2.5,98 fc rgb '#ddeedd' fs solid 0.5 behind\n";
  gp += "plot '" + base + "_coverage.dat' u 1:3:4:5 w yerrorbars pt 7 ps 1.5 lw 2 "
        "t 'coverage, Wilson 95%', 95 w l dt 2 lc rgb 'gray' t 'nominal 95%'\n";
  gp += "unset object 1\nset title 'Cumulative fraction of |error| / interval half-width'\n";
  gp += "set xlabel '|estimate - truth| / half-width of the 95% total interval (truth side)'\n";
  gp += "set ylabel 'fraction of identified estimates'\nset xrange [0:4]\nset yrange [0:1]\n";
  gp += "set xtics auto\nset ytics 0.1\nset datafile separator ','\nset datafile missing 'nan'\n";
  gp += "set arrow 1 from 1, graph 0 to 1, graph 1 nohead dt 2\n";
  gp += "set arrow 2 from 2, graph 0 to 2, graph 1 nohead lc rgb 'red'\n";
  gp += "set arrow 3 from graph 0, first 0.95 to graph 1, first 0.95 nohead dt 3 lc rgb 'gray'\n";
  gp += "clip(x) = x > 4 ? 4 : x\nplot ";
  const char* titles[3] = {"sigma_c", "J_B", "J_{tip,c}"};
  for (int p = 0; p < 3; ++p) {
    const int col = first + p * stride + ratio;
    gp += fmt::format("{}'{}.csv' skip 1 u (clip(${})):(1.0) smooth cnormal w steps lw 2 t '{}'",
                      p ? ", " : "", base, col, titles[p]);
  }
  gp += "\nunset multiplot\n";
  return gp;
}

}  // namespace bridgefit::validate
