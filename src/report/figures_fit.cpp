// Figures of the fit itself: the R curve with residuals, the bridging law
// with the region the intervals allow, the profile likelihoods.
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "report_impl.hpp"

namespace bridgefit::report::detail {
namespace {

// Removed points as a gnuplot table: x [m] written in mm, then y; a final
// "nan nan" row keeps an empty table plottable.
std::string OutlierTable(const char* header, const std::vector<double>& x, const std::vector<double>& y) {
  std::string out = std::string(header) + "\n";
  for (size_t i = 0; i < x.size() && i < y.size(); ++i)
    out += fmt::format("{:.8g} {:.8g}\n", x[i] * 1e3, y[i]);
  return out + "nan nan\n";
}

// Residual data - model at each fitted crack length (same points as the data).
std::vector<double> Residuals(const FitView& f) {
  std::vector<double> res;
  for (size_t i = 0; i < f.fit_a.size(); ++i) {
    size_t best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < f.a.size(); ++j) {
      const double d = std::abs(f.a[j] - f.fit_a[i]);
      if (d < best_d) best_d = d, best = j;
    }
    res.push_back(best_d <= 1e-9 ? f.R[best] - f.fit_R[i] : NAN);
  }
  return res;
}

// The law's shape as the fit file holds it; without one (a family whose
// shape is data, in a file that predates /fit/law_shape) the linear law, said.
laws::LawShape ShapeOf(const FitView& f, std::vector<std::string>* notes) {
  if (f.shape) {
    if (!f.shape_note.empty()) notes->push_back("law shape: " + f.shape_note);
    return *f.shape;
  }
  notes->push_back("law '" + f.law + "': drawn with the linear shape (its shape is not in the fit file" +
                   (f.shape_note.empty() ? std::string(")") : ": " + f.shape_note + ")"));
  return laws::MakeLinearShape();
}

// A shape given as points (bilinear, trilinear, table): its break points at
// the drawn scales as law_points.dat (d, s, delta [mm], sigma [MPa]) and as
// the page's table, with a fitted shape's parameters and their Wald
// intervals; "" for a shape without points. Returns the plot clause.
std::string LawPoints(const FitView& f, const laws::BridgingLaw& drawn, bool at_bound,
                      FigureSet& set) {
  const laws::LawShape& shape = *drawn.shape;
  if (shape.d_points.empty()) return "";
  std::string dat = "# d[1] s[1] delta[mm] sigma[MPa]\n";
  std::string h = fmt::format(
      "<table id=\"law_shape\">\n<caption>Law shape: {}{}, {} between the points; at {}&sigma;<sub>c</sub> "
      "and {}&delta;<sub>c</sub></caption>\n"
      "<tr><th>d = &delta;/&delta;<sub>c</sub></th><th>s = &sigma;/&sigma;<sub>c</sub></th>"
      "<th>&delta; [mm]</th><th>&sigma; [MPa]</th></tr>\n",
      f.fitted_shape.empty() ? std::string(laws::LawFamilyName(shape.family)) : f.fitted_shape,
      f.shape_knots > 0 ? fmt::format(", N = {} knots", f.shape_knots) : "",
      shape.family == laws::LawFamily::kTable &&
              shape.interpolation == laws::TableInterpolation::kMonotoneCubic
          ? "monotone cubic (PCHIP)"
          : "straight segments",
      "the best ", at_bound ? "the lower bound of " : "the best ");
  for (size_t k = 0; k < shape.d_points.size(); ++k) {
    const double delta = shape.d_points[k] * drawn.delta_c;
    const double sigma = drawn.Traction(delta);
    dat += fmt::format("{:.8g} {:.8g} {:.8g} {:.8g}\n", shape.d_points[k], shape.s_points[k],
                       delta * 1e3, sigma * 1e-6);
    h += "<tr><td>" + Num(shape.d_points[k]) + "</td><td>" + Num(shape.s_points[k]) + "</td><td>" +
         Num(delta, 1e3) + "</td><td>" + Num(sigma, 1e-6) + "</td></tr>\n";
  }
  h += "</table>\n";
  WriteFile(set.dir / "law_points.dat", dat);
  if (!f.shape_parameters.empty()) {
    h += "<table id=\"shape_parameters\">\n<caption>Shape parameters fitted with "
         "&sigma;<sub>c</sub>, J<sub>B</sub>, J<sub>tip,c</sub>: 95% intervals are Wald "
         "(1.96 standard errors, the scale parameters free), not profiles</caption>\n"
         "<tr><th>parameter</th><th>value</th><th>95% Wald interval</th><th>at the best fit</th></tr>\n";
    for (const FitView::ShapeParameter& p : f.shape_parameters) {
      const bool position = p.name.rfind('d', 0) == 0;
      const double scale = position ? drawn.delta_c * 1e3 : drawn.sigma_c * 1e-6;
      const std::string interval =
          p.pinned ? "the peak: &sigma;<sub>c</sub> by definition"
          : std::isfinite(p.standard_error)
              ? "[" + Num(p.value - 1.96 * p.standard_error) + ", " +
                    Num(p.value + 1.96 * p.standard_error) + "]"
              : "&ndash; (singular)";
      h += "<tr><td>" + Escape(p.name) + "</td><td>" + Num(p.value) + "</td><td>" + interval +
           "</td><td>" + Num(p.value * scale) + (position ? " mm" : " MPa") + "</td></tr>\n";
    }
    h += "</table>\n";
    if (!f.fitted_shape_note.empty()) h += "<p>" + Escape(f.fitted_shape_note) + "</p>\n";
  }
  set.law_shape_html = h;
  return ", 'law_points.dat' u 3:4 w p pt 7 ps 1.0 lc rgb '#ff7f0e' t 'break points'";
}

// Which printed interval ends come from the profile likelihood, read from
// the estimate's note as the fitter writes it (src/inverse/fit.cpp).
struct ProfileEnds {
  bool low = false, high = false;
};
ProfileEnds EndsFromProfile(const Estimate* e) {
  ProfileEnds ends;
  if (!e || e->note.find("profile likelihood") == std::string::npos) return ends;
  ends.high = std::isfinite(e->ProfileHigh());
  ends.low = std::isfinite(e->ProfileLow()) && e->note.find("Jacobian below") == std::string::npos;
  return ends;
}

// chi^2_min of a profile: its point at the estimate (the fitter adds the
// optimum to each profile), else its smallest value.
double ProfileMinimum(const Profile& p, const Estimate* e) {
  double lowest = *std::min_element(p.chi2.begin(), p.chi2.end());
  if (e && std::isfinite(e->value))
    for (size_t i = 0; i < p.value.size(); ++i)
      if (std::abs(p.value[i] - e->value) <= 1e-12 * std::abs(e->value) && p.chi2[i] <= lowest + 1e-9 * std::abs(lowest))
        return p.chi2[i];
  return lowest;
}

}  // namespace

void AddRCurveFigure(const ReportInput& in, FigureSet& set) {
  const FitView& f = in.fit;
  std::string dat = "# crack_length[mm] R_data[J/m^2]\n";
  for (size_t i = 0; i < f.a.size(); ++i) dat += fmt::format("{:.8g} {:.8g}\n", f.a[i] * 1e3, f.R[i]);
  WriteFile(set.dir / "rcurve_data.dat", dat);
  std::string fit = "# crack_length[mm] R_model[J/m^2] residual[J/m^2]\n";
  const std::vector<double> res = f.fit_R.empty() ? std::vector<double>() : Residuals(f);
  for (size_t i = 0; i < f.fit_R.size(); ++i)
    fit += fmt::format("{:.8g} {:.8g} {:.8g}\n", f.fit_a[i] * 1e3, f.fit_R[i], res[i]);
  WriteFile(set.dir / "rcurve_fit.dat", fit);
  WriteFile(set.dir / "rcurve_outliers.dat", OutlierTable("# crack_length[mm] R[J/m^2]", f.out_a, f.out_R));
  std::string& gp = set.gp;
  gp += kTerminal;
  gp += "set output 'rcurve.png'\n";
  if (!f.fit_R.empty()) {
    gp += "set multiplot\nset title 'R curve: data and fitted model'\n";
    gp += kUpperPanel;
    gp += "set ylabel 'R [J/m^2]'\n";
    gp += "plot 'rcurve_data.dat' u 1:2 w p pt 7 ps 0.6 lc rgb '#1f77b4' t 'data', "
          "'rcurve_outliers.dat' u 1:2 w p pt 2 ps 1.2 lc rgb '#d62728' t 'outliers (removed)', "
          "'rcurve_fit.dat' u 1:2 w l lw 2 lc rgb '#ff7f0e' t 'fitted model'\n";
    gp += kLowerPanel;
    gp += "set xlabel 'crack length a [mm]'\nset ylabel 'residual [J/m^2]'\n";
    gp += "plot 'rcurve_fit.dat' u 1:3 w p pt 7 ps 0.5 lc rgb '#1f77b4', 0 w l lc rgb 'black'\n";
    gp += "unset multiplot\n";
    set.Add("rcurve.png", "fit", "R curve: data (points) and the fitted model, residuals (data &minus; model) below.");
  } else {
    gp += "set title 'R curve (no model curve in the fit file)'\nset xlabel 'crack length a [mm]'\n"
          "set ylabel 'R [J/m^2]'\nplot 'rcurve_data.dat' u 1:2 w p pt 7 ps 0.6 t 'data'\n";
    set.notes.push_back("no fitted R curve in the fit file: data only");
    set.Add("rcurve.png", "fit", "R curve: data (the fit file holds no model curve).");
  }
}

// The law-free curves (bridgefit lawfree): one file per route, its band
// and line appended to the law plot; widens x_max to their openings.
std::string LawFreeCurves(const ReportInput& in, FigureSet& set, double* x_max) {
  if (!in.law_free) return "";
  std::string plot;
  const char* colours[] = {"#2ca02c", "#9467bd"};
  for (size_t c = 0; c < in.law_free->curves.size() && c < 2; ++c) {
    const LawFreeView::Curve& k = in.law_free->curves[c];
    const std::string file = fmt::format("lawfree_{}.dat", c);
    // Column 5: sigma where the band is within +-resolved_fraction of the
    // peak (the data pin it), NaN elsewhere (gnuplot leaves a gap).
    std::string dat = "# delta[mm] sigma[MPa] lower[MPa] upper[MPa] resolved_sigma[MPa]\n";
    int resolved = 0;
    for (size_t j = 0; j < k.delta.size() && j < k.sigma.size(); ++j) {
      const double lo = j < k.lower.size() ? k.lower[j] : NAN;
      const double hi = j < k.upper.size() ? k.upper[j] : NAN;
      const bool pinned = j < k.resolved.size() && k.resolved[j];
      resolved += pinned;
      dat += fmt::format("{:.8g} {:.8g} {:.8g} {:.8g} {}\n", k.delta[j] * 1e3, k.sigma[j] * 1e-6,
                         std::max(lo, 0.0) * 1e-6, hi * 1e-6,
                         pinned ? fmt::format("{:.8g}", k.sigma[j] * 1e-6) : std::string("NaN"));
    }
    WriteFile(set.dir / file, dat);
    if (!k.delta.empty()) *x_max = std::max(*x_max, k.delta.back());
    // gnuplot's enhanced text: J_{ff}, {/Symbol d}.
    const std::string route = k.route == "J_ff(delta*)"    ? "J_{ff}({/Symbol d}*)"
                              : k.route == "R(delta_root)" ? "R({/Symbol d}_{root})"
                                                           : k.route;
    const std::string what =
        fmt::format("law-free {}{}", route, k.identified ? "" : " (bounds only)");
    plot += fmt::format(", '{}' u 1:3:4 w filledcurves fc rgb '{}' fs transparent solid 0.25 t '{} 95% band'",
                        file, colours[c], what);
    plot += fmt::format(", '{}' u 1:2 w l lw 2 lc rgb '{}' t '{}'", file, colours[c], what);
    if (resolved > 0)
      plot += fmt::format(
          ", '{}' u 1:5 w l lw 5 lc rgb '{}' t 'resolved: band within +-{:.0f}% of the peak'", file,
          colours[c], 100 * k.resolved_fraction);
  }
  if (!in.law_free->curves.empty())
    set.notes.push_back(
        "law figure: the law-free sigma(delta) from " + in.law_free->file.string() +
        " drawn over the fit (where they disagree beyond the band, the family is wrong; " +
        fmt::format("thick where the data pin sigma to +-{:.0f} % of its peak, thin "
                    "where the curve is the smoothing penalty's shape inside its band)",
                    100 * in.law_free->curves.front().resolved_fraction));
  return plot;
}

void AddLawFigure(const ReportInput& in, FigureSet& set) {
  const FitView& f = in.fit;
  const Estimate* sc = f.Find("sigma_c");
  const Estimate* dc = f.Find("delta_c");
  const bool bridging = !(f.bridging == 0.0) && sc && dc && std::isfinite(sc->value) && sc->value > 0 &&
                        (std::isfinite(dc->value) || std::isfinite(dc->lower_bound) || std::isfinite(dc->ci_low));
  if (!bridging) {
    set.notes.push_back("no bridging detected: no bridging-law figure");
    return;
  }
  const laws::LawShape shape = ShapeOf(f, &set.notes);
  std::optional<laws::BridgingLaw> truth_law;
  if (in.truth.shape) truth_law = laws::BridgingLaw{&*in.truth.shape, in.truth.sigma_c, in.truth.delta_c};
  auto pick = [](double a, double b) { return std::isfinite(a) ? a : b; };
  const double s_lo = pick(sc->ci_low, sc->value), s_hi = pick(sc->ci_high, sc->value);
  const double d_lo = pick(dc->ci_low, pick(dc->lower_bound, dc->value));
  const double d_hi = dc->identified ? pick(dc->ci_high, dc->value) : INFINITY;
  // Without a delta_c estimate (only a bound) the law drawn is the one at the bound.
  const bool at_bound = !std::isfinite(dc->value);
  const double d_best = at_bound ? d_lo : dc->value;
  double x_max = 1.5 * std::max(d_best, d_lo);
  if (!std::isfinite(d_hi)) x_max = std::max(x_max, 2.5 * d_lo);
  if (truth_law) x_max = std::max(x_max, 1.2 * truth_law->delta_c);
  const std::string law_free_plot = LawFreeCurves(in, set, &x_max);
  const laws::BridgingLaw best{&shape, sc->value, d_best};
  const laws::BridgingLaw low{&shape, s_lo, d_lo};
  const std::string points_plot = LawPoints(f, best, at_bound, set);
  // 300 even steps and the break points (the curve passes through each kink).
  std::vector<double> openings;
  const int n = 300;
  for (int i = 0; i <= n; ++i) openings.push_back(x_max * i / n);
  for (double d : shape.d_points)
    if (d * d_best <= x_max) openings.push_back(d * d_best);
  std::sort(openings.begin(), openings.end());
  openings.erase(std::unique(openings.begin(), openings.end()), openings.end());
  std::string dat = "# delta[mm] lower[MPa] upper[MPa] best[MPa] truth[MPa]\n";
  for (double d : openings) {
    const double upper = std::isfinite(d_hi) ? laws::BridgingLaw{&shape, s_hi, d_hi}.Traction(d)
                                             : s_hi * laws::ShapeValue(shape, 0.0);
    const double t = truth_law ? truth_law->Traction(d) : NAN;
    dat += fmt::format("{:.8g} {:.8g} {:.8g} {:.8g} {:.8g}\n", d * 1e3, low.Traction(d) * 1e-6,
                       upper * 1e-6, best.Traction(d) * 1e-6, t * 1e-6);
  }
  WriteFile(set.dir / "law.dat", dat);
  const std::string region = std::isfinite(d_hi)
                                 ? "laws within the 95% CIs"
                                 : "laws allowed by the bounds ({/Symbol d}_c, J_B only bounded below)";
  std::string& gp = set.gp;
  gp += kTerminal;
  gp += "set output 'law.png'\nset title 'Bridging law'\n";
  gp += "set xlabel 'crack opening {/Symbol d} [mm]'\nset ylabel 'bridging stress {/Symbol s} [MPa]'\n";
  gp += "set key top right\nset yrange [0:*]\n";
  gp += "plot 'law.dat' u 1:2:3 w filledcurves fc rgb '#cfe2f3' fs solid 0.8 t '" + region +
        "', '' u 1:4 w l lw 2 lc rgb '#ff7f0e' t '" +
        (at_bound ? "best {/Symbol s}_c with {/Symbol d}_c at its lower bound" : "best fit") + "'";
  if (truth_law) gp += ", '' u 1:5 w l lw 2 dt 2 lc rgb 'black' t 'true law (synthetic test)'";
  gp += points_plot + law_free_plot + "\n";
  set.Add("law.png", "fit",
          "Bridging law: best fit and the shaded region of laws consistent with the 95% CIs; "
          "where &delta;<sub>c</sub> and J<sub>B</sub> are only bounded below the region is open to the right.");
}

// One panel per profile: Delta chi^2 = chi^2 - chi^2_min against the
// parameter, the threshold 3.84 s^2 that defines the printed 95% intervals
// (s^2 = the fit's scaling: max(1, reduced chi^2) with stated uncertainties),
// the printed ends from the profile marked at the threshold, an open side
// (the profile stays under the threshold to the box edge) labelled open.
void AddProfileFigure(const ReportInput& in, FigureSet& set) {
  const FitView& f = in.fit;
  if (f.profiles.empty()) {
    set.notes.push_back("no profile likelihood in the fit file (fit run with --no-profile?)");
    return;
  }
  const size_t n = f.profiles.size();
  const int width = std::max(860, static_cast<int>(330 * n));
  std::string& gp = set.gp;
  gp += kTerminal;
  gp += fmt::format("set terminal pngcairo size {},500 enhanced font 'Sans,11'\n", width);
  gp += "set output 'profiles.png'\n";
  const double threshold0 = f.profiles.front().threshold;
  const double s2 = threshold0 / 3.84;
  const std::string scaling =
      std::abs(s2 - 1.0) < 1e-9 ? "s^2 = 1: the stated uncertainties"
                                : fmt::format("s^2 = {:.4g}, the reduced {{/Symbol c}}^2 (Birge ratio)", s2);
  gp += fmt::format(
      "set multiplot title \"Profile likelihood (others re-optimized): {{/Symbol D}}{{/Symbol c}}^2 = "
      "{{/Symbol c}}^2 - {{/Symbol c}}^2_{{min}}; 95% threshold 3.84 s^2 = {:.4g} ({})\"\n",
      threshold0, scaling);
  std::string html = "<table id=\"profiles\">\n<tr><th>parameter</th><th>&chi;<sup>2</sup><sub>min</sub></th>"
                     "<th>threshold &Delta;&chi;<sup>2</sup></th><th>points</th><th>explored</th>"
                     "<th>printed 95% interval from this profile</th></tr>\n";
  for (size_t k = 0; k < n; ++k) {
    const Profile& p = f.profiles[k];
    const Estimate* e = f.Find(p.name);
    const Display d = DisplayOf(p.name);
    const double threshold = std::isfinite(p.threshold) && p.threshold > 0 ? p.threshold : 3.84;
    const double chi2_min = ProfileMinimum(p, e);
    std::vector<size_t> order(p.value.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t x, size_t y) { return p.value[x] < p.value[y]; });
    std::string dat = fmt::format(
        "# profile of {}: value [{}], Delta chi^2 = chi^2 - chi^2_min, chi^2\n"
        "# chi^2_min = {:.10g}; 95% threshold Delta chi^2 = {:.10g} (3.84 s^2, s^2 = {:.6g})\n",
        p.name, GnuplotUnit(p.name), chi2_min, threshold, threshold / 3.84);
    double y_max = 0.0;
    for (size_t i : order) {
      dat += fmt::format("{:.10g} {:.10g} {:.10g}\n", p.value[i] * d.factor, p.chi2[i] - chi2_min, p.chi2[i]);
      y_max = std::max(y_max, p.chi2[i] - chi2_min);
    }
    const std::string file = "profile_" + p.name + ".dat";
    WriteFile(set.dir / file, dat);
    // The printed ends that come from this profile, at the threshold.
    const ProfileEnds ends = EndsFromProfile(e);
    std::string ends_dat = "# printed 95% interval ends from the profile: value delta_chi2 (= threshold)\n";
    if (ends.low) ends_dat += fmt::format("{:.10g} {:.10g}\n", e->ProfileLow() * d.factor, threshold);
    if (ends.high) ends_dat += fmt::format("{:.10g} {:.10g}\n", e->ProfileHigh() * d.factor, threshold);
    ends_dat += "nan nan\n";
    const std::string ends_file = "profile_" + p.name + "_ends.dat";
    WriteFile(set.dir / ends_file, ends_dat);
    const double lo = p.value[order.front()] * d.factor, hi = p.value[order.back()] * d.factor;
    // Open sides as the fitter reported them ("profile likelihood flat ...").
    const bool flat_note = e && e->note.find("profile likelihood flat") != std::string::npos;
    const bool open_low = p.flat && flat_note && !std::isfinite(e->ci_low);
    const bool open_high = p.flat && flat_note && !std::isfinite(e->ci_high);
    // Panel k of n, margins in screen coordinates so panels never share space.
    const double w = 1.0 / n, x0 = k * w;
    gp += fmt::format("set lmargin at screen {:.4f}\nset rmargin at screen {:.4f}\n", x0 + 0.23 * w,
                      x0 + 0.96 * w);
    gp += "set tmargin at screen 0.80\nset bmargin at screen 0.20\nunset key\nunset label\nunset arrow\n";
    gp += fmt::format("set xlabel '{} [{}]'\nset ylabel '{{/Symbol D}}{{/Symbol c}}^2'\n",
                      GnuplotSymbol(p.name), GnuplotUnit(p.name));
    // Up to 4 thresholds high: the interval region fills the panel. The x
    // range: the points under the top, and one sample beyond on each side.
    const double top = std::clamp(1.1 * y_max, 1.5 * threshold, 4.0 * threshold);
    gp += fmt::format("set yrange [{:.6g}:{:.6g}]\n", -0.05 * top, top);
    size_t first = order.size(), last = 0;
    for (size_t i = 0; i < order.size(); ++i)
      if (p.chi2[order[i]] - chi2_min <= top) first = std::min(first, i), last = i;
    if (first > last) first = 0, last = order.size() - 1;
    first = first > 0 ? first - 1 : 0;
    last = std::min(last + 1, order.size() - 1);
    double x_lo = p.value[order[first]] * d.factor, x_hi = p.value[order[last]] * d.factor;
    const bool wide = x_lo > 0 && x_hi / x_lo > 30;  // an unbounded J_B spans decades
    if (wide) {
      x_lo /= 1.1, x_hi *= 1.1;
    } else {
      const double pad = 0.04 * (x_hi - x_lo);
      x_lo -= pad, x_hi += pad;
    }
    gp += wide ? "set logscale x\n" : "unset logscale x\n";
    gp += fmt::format("set xrange [{:.10g}:{:.10g}]\n", x_lo, x_hi);
    gp += "set xtics rotate by 35 right font ',9'\nset xtics autofreq\n";
    std::string panel_title;
    if (ends.low || ends.high)
      panel_title =
          std::isfinite(e->model_bias)
              ? fmt::format("statistical 95% CI [{}, {}]; printed with model error [{}, {}]",
                            ends.low ? Num(e->ProfileLow(), d.factor) : "-",
                            ends.high ? Num(e->ProfileHigh(), d.factor) : "-",
                            Num(e->ci_low, d.factor), Num(e->ci_high, d.factor))
              : fmt::format("printed 95% CI [{}, {}]", ends.low ? Num(e->ci_low, d.factor) : "-",
                            ends.high ? Num(e->ci_high, d.factor) : "-");
    else if (e && std::isfinite(e->lower_bound))
      panel_title = fmt::format("printed: >= {} (a bound, not this profile)", Num(e->lower_bound, d.factor));
    else if (open_low || open_high)
      panel_title = open_low && open_high ? "flat: no interval (open on both sides)" : "no printed interval: open";
    else
      panel_title = "printed value not from this profile";  // why: the profile table (decided by)
    gp += "set title '" + GnuplotText(panel_title) + "' font ',10'\n";
    if (open_high)
      gp += "set label 'open: under the threshold\\nto the box edge {/Symbol \\256}' at graph 0.97, graph 0.55 "
            "right font ',9' tc rgb '#555555'\n";
    if (open_low)
      gp += "set label '{/Symbol \\254} open: under the threshold\\nto the box edge' at graph 0.03, graph 0.55 "
            "left font ',9' tc rgb '#555555'\n";
    if (e && std::isfinite(e->lower_bound) && !(ends.low || ends.high) && e->lower_bound * d.factor > x_lo &&
        e->lower_bound * d.factor < x_hi)  // arrows are not clipped to the panel
      gp += fmt::format("set arrow from {:.10g}, graph 0 to {:.10g}, graph 1 nohead dt 3 lc rgb '#555555'\n",
                        e->lower_bound * d.factor, e->lower_bound * d.factor);
    // The test (tests/report/figure_check.hpp) reads this line: column 2 and the threshold.
    gp += fmt::format("plot '{}' u 1:2 w lp pt 7 ps 0.5 lw 2 lc rgb '#1f77b4', {:.10g} w l dt 2 lw 2 lc rgb "
                      "'#d62728', '{}' u 1:2 w impulses lw 2 lc rgb '#2ca02c', '' u 1:2 w p pt 9 ps 1.6 lc "
                      "rgb '#2ca02c'\n",
                      file, threshold, ends_file);
    html += fmt::format("<tr><td>{}</td><td>{:.6g}</td><td>{:.4g}</td><td>{}</td><td>{} .. {} {}</td><td>{}</td></tr>\n",
                        d.label, chi2_min, threshold, p.value.size(), Num(lo), Num(hi), d.unit,
                        ends.low || ends.high
                            ? fmt::format("[{}, {}]{}", ends.low ? Num(e->ProfileLow(), d.factor) : "&ndash;",
                                          ends.high ? Num(e->ProfileHigh(), d.factor) : "&ndash;",
                                          open_high ? " (open above)" : open_low ? " (open below)" : "")
                            : (open_low || open_high ? "none: flat (open)"
                                                     : "none (" + Escape(e ? e->decided_by : "") + ")"));
  }
  gp += "unset multiplot\n";
  set.profile_html = html + "</table>\n";
  set.Add("profiles.png", "fit",
          "Profile likelihood of each parameter (the others re-optimized), drawn as &Delta;&chi;<sup>2</sup> = "
          "&chi;<sup>2</sup> &minus; &chi;<sup>2</sup><sub>min</sub> (blue). The red dashed line is the "
          "threshold that defines the printed 95% intervals, 3.84&nbsp;s<sup>2</sup> with s<sup>2</sup> the fit's "
          "scaling (the reduced &chi;<sup>2</sup> when it exceeds 1); green marks are the printed interval "
          "ends, where the profile crosses it. A side that stays under the threshold to the end of the "
          "explored range is labelled open. The table below the figures lists each profile.");
}

}  // namespace bridgefit::report::detail
