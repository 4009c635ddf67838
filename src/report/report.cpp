// HTML report of a fit (include/bridgefit/report/report.hpp).
#include "bridgefit/report/report.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/laws/law.hpp"

namespace bridgefit::report {
namespace fs = std::filesystem;

bool ReportOptions::IsValid(std::string* why) const {
  if (gnuplot.empty()) {
    if (why) *why = "the gnuplot executable name is empty";
    return false;
  }
  return true;
}

std::string ReportSummary::BriefReport() const {
  std::string text = fmt::format("report {} with {} figures in {:.2f} s", index_html.string(),
                                 figures.size(), wall_s);
  for (const std::string& note : notes) text += "\n  " + note;
  return text;
}

namespace {

struct Estimate {
  std::string name, units;
  double value = NAN, ci_low = NAN, ci_high = NAN, lower_bound = NAN;
  bool present = false, identified = false, fixed = false;
  std::string decided_by, note;
};

struct FitData {
  std::string model, optimizer, law, verdict, r_kind, scene, stop_reason, fit_to;
  double converged = NAN, steady = NAN, bridging = NAN, rms = NAN, rms_load = NAN, wall_s = NAN;
  double evaluations = NAN;
  std::vector<double> a, R, fit_a, fit_R, out_a, out_R;
  // A load-displacement fit: rows used, their load and the model's load.
  std::vector<double> fit_d, fit_P, data_P, out_d, out_P;
  std::vector<Estimate> estimates;  // sigma_c, J_B, delta_c, J_tip_c
  struct Profile {
    std::string name;
    std::vector<double> value, chi2;
    double threshold = NAN;
  };
  std::vector<Profile> profiles;
  const Estimate* Find(const std::string& name) const {
    for (const Estimate& e : estimates)
      if (e.name == name && e.present) return &e;
    return nullptr;
  }
};

std::string StringAttr(const io::H5Reader& r, const std::string& object, const std::string& key) {
  return r.HasAttribute(object, key) ? r.ReadStringAttribute(object, key) : std::string();
}
double NumberAttr(const io::H5Reader& r, const std::string& object, const std::string& key) {
  return r.HasAttribute(object, key) ? r.ReadNumberAttribute(object, key) : NAN;
}
std::vector<double> VectorOrEmpty(const io::H5Reader& r, const std::string& path) {
  return r.Exists(path) ? r.ReadVector(path) : std::vector<double>();
}

FitData ReadFit(const fs::path& path) {
  if (!fs::exists(path))
    throw Error(ErrorKind::kInput, "the fit file does not exist",
                {.file = path.string(), .expected = "an HDF5 file from 'bridgefit fit --out'"});
  const io::H5Reader r(path);
  if (!r.Exists("/fit"))
    throw Error(ErrorKind::kInput, "the file has no /fit group",
                {.file = path.string(), .field = "/fit",
                 .expected = "an HDF5 file from 'bridgefit fit --out'"});
  FitData f;
  const std::string g = "/fit";
  f.model = StringAttr(r, g, "model");
  f.optimizer = StringAttr(r, g, "optimizer");
  f.law = StringAttr(r, g, "law");
  f.verdict = StringAttr(r, g, "verdict");
  f.r_kind = StringAttr(r, g, "r_kind");
  f.scene = StringAttr(r, g, "scene");
  f.stop_reason = StringAttr(r, g, "stop_reason");
  f.converged = NumberAttr(r, g, "converged");
  f.steady = NumberAttr(r, g, "steady_state_reached");
  f.bridging = NumberAttr(r, g, "bridging_detected");
  f.rms = NumberAttr(r, g, "rms_residual_J_per_m2");
  f.fit_to = StringAttr(r, g, "fit_to");
  if (r.Exists(g + "/load_displacement")) {
    const std::string ld = g + "/load_displacement";
    f.rms_load = NumberAttr(r, g, "rms_residual_N");
    f.fit_d = VectorOrEmpty(r, ld + "/displacement");
    f.data_P = VectorOrEmpty(r, ld + "/load");
    f.fit_P = VectorOrEmpty(r, ld + "/fitted_load");
    f.out_d = VectorOrEmpty(r, ld + "/outlier_displacement");
    f.out_P = VectorOrEmpty(r, ld + "/outlier_load");
    if (f.fit_P.size() != f.fit_d.size() || f.data_P.size() != f.fit_d.size()) f.fit_P.clear();
  }
  f.wall_s = NumberAttr(r, g, "wall_s");
  f.evaluations = NumberAttr(r, g, "evaluations");
  f.a = VectorOrEmpty(r, g + "/crack_length");
  f.R = VectorOrEmpty(r, g + "/R");
  if (f.a.empty() && r.Exists("/rcurve/crack_length")) {
    f.a = r.ReadVector("/rcurve/crack_length");
    f.R = VectorOrEmpty(r, "/rcurve/R");
  }
  if (f.a.empty() || f.a.size() != f.R.size())
    throw Error(ErrorKind::kInput, "the fit file holds no R curve",
                {.file = path.string(), .field = "/fit/crack_length, /fit/R"});
  f.fit_a = VectorOrEmpty(r, g + "/fitted_crack_length");
  f.fit_R = VectorOrEmpty(r, g + "/fitted_R");
  if (f.fit_R.size() != f.fit_a.size()) f.fit_R.clear();
  f.out_a = VectorOrEmpty(r, g + "/outlier_crack_length");
  f.out_R = VectorOrEmpty(r, g + "/outlier_R");
  for (const char* name : {"sigma_c", "J_B", "delta_c", "J_tip_c"}) {
    Estimate e;
    e.name = name;
    const std::string pg = g + "/parameters/" + name;
    if (r.Exists(pg)) {
      e.present = true;
      e.units = StringAttr(r, pg, "units");
      e.value = NumberAttr(r, pg, "value");
      e.ci_low = NumberAttr(r, pg, "ci95_low");
      e.ci_high = NumberAttr(r, pg, "ci95_high");
      e.lower_bound = NumberAttr(r, pg, "lower_bound");
      e.identified = NumberAttr(r, pg, "identified") == 1.0;
      e.fixed = NumberAttr(r, pg, "fixed") == 1.0;
      e.decided_by = StringAttr(r, pg, "decided_by");
      e.note = StringAttr(r, pg, "note");
    }
    f.estimates.push_back(e);
    const std::string prof = g + "/profiles/" + name;
    if (r.Exists(prof + "/value") && r.Exists(prof + "/chi2")) {
      FitData::Profile p{name, r.ReadVector(prof + "/value"), r.ReadVector(prof + "/chi2"),
                         NumberAttr(r, prof, "chi2_threshold")};
      if (p.value.size() == p.chi2.size() && p.value.size() >= 2) f.profiles.push_back(p);
    }
  }
  return f;
}

// Display units of each parameter: (label, factor from SI, unit text).
struct Display {
  std::string label;
  double factor;
  std::string unit;
};
Display DisplayOf(const std::string& name) {
  if (name == "sigma_c") return {"&sigma;<sub>c</sub> (peak bridging stress)", 1e-6, "MPa"};
  if (name == "delta_c") return {"&delta;<sub>c</sub> (critical opening)", 1e3, "mm"};
  if (name == "J_B") return {"J<sub>B</sub> (bridging toughness)", 1.0, "J/m<sup>2</sup>"};
  return {"J<sub>tip,c</sub> (crack-tip toughness)", 1.0, "J/m<sup>2</sup>"};
}
std::string GnuplotUnit(const std::string& name) {
  if (name == "sigma_c") return "MPa";
  if (name == "delta_c") return "mm";
  return "J/m^2";
}

std::string Num(double v, double factor = 1.0) {
  if (!std::isfinite(v)) return "&ndash;";
  return fmt::format("{:.4g}", v * factor);
}

std::string Escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string ShellQuote(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

void WriteFile(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw Error(ErrorKind::kRuntime, "cannot write file", {.file = path.string()});
}

// Removed points as a gnuplot table: x [m] written in mm, then y; a final
// "nan nan" row keeps an empty table plottable.
std::string OutlierTable(const char* header, const std::vector<double>& x,
                         const std::vector<double>& y) {
  std::string out = std::string(header) + "\n";
  for (size_t i = 0; i < x.size() && i < y.size(); ++i)
    out += fmt::format("{:.8g} {:.8g}\n", x[i] * 1e3, y[i]);
  return out + "nan nan\n";
}

// Residual data - model at each fitted crack length (same points as the data).
std::vector<double> Residuals(const FitData& f) {
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

laws::LawShape ShapeOf(const std::string& law, std::vector<std::string>* notes) {
  if (law == "cubic") return laws::MakeCubicShape();
  if (law != "linear" && notes)
    notes->push_back("law '" + law + "': drawn with the linear shape (its shape parameter is not in the fit file)");
  return laws::MakeLinearShape();
}

// Each figure starts from the same state (multiplot leaves size/origin/margins set).
const char* kTerminal =
    "set terminal pngcairo size 860,520 enhanced font 'Sans,11'\n"
    "set size 1,1\nset origin 0,0\nunset tmargin\nunset bmargin\nunset lmargin\n"
    "set format x '%g'\nset format y '%g'\nunset logscale\nset autoscale\nunset title\n"
    "set xtics norotate font ''\nset ytics in\nunset x2tics\nset xtics mirror\nset key top left\n";

}  // namespace

ReportSummary WriteFitReport(const fs::path& fit_h5, const fs::path& out_dir,
                             const ReportOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, why, {.field = "gnuplot"});
  if (out_dir.empty()) throw Error(ErrorKind::kUsage, "the output folder is empty", {.field = "--out"});
  Stopwatch watch;
  const FitData f = ReadFit(fit_h5);
  ReportSummary summary;

  // Build in a sibling temporary folder, rename at the end.
  const fs::path target = fs::absolute(out_dir).lexically_normal();
  const fs::path parent = target.has_filename() ? target.parent_path() : target.parent_path().parent_path();
  const std::string leaf = target.has_filename() ? target.filename().string() : target.parent_path().filename().string();
  fs::create_directories(parent);
  const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
  const fs::path tmp = parent / fmt::format(".{}.tmp-{}-{}", leaf, ::getpid(), stamp);
  fs::create_directories(tmp);
  struct Cleanup {
    fs::path path;
    ~Cleanup() {
      std::error_code ec;
      if (!path.empty()) fs::remove_all(path, ec);
    }
  } cleanup{tmp};

  std::string gp = "# gnuplot script of this report (run: gnuplot report.gp)\n";
  gp += "set datafile missing 'nan'\nset grid\nset key top left\n";

  // 1. R curve data and fit, residuals below.
  {
    std::string dat = "# crack_length[mm] R_data[J/m^2]\n";
    for (size_t i = 0; i < f.a.size(); ++i) dat += fmt::format("{:.8g} {:.8g}\n", f.a[i] * 1e3, f.R[i]);
    WriteFile(tmp / "rcurve_data.dat", dat);
    std::string fit = "# crack_length[mm] R_model[J/m^2] residual[J/m^2]\n";
    const std::vector<double> res = f.fit_R.empty() ? std::vector<double>() : Residuals(f);
    for (size_t i = 0; i < f.fit_R.size(); ++i)
      fit += fmt::format("{:.8g} {:.8g} {:.8g}\n", f.fit_a[i] * 1e3, f.fit_R[i], res[i]);
    WriteFile(tmp / "rcurve_fit.dat", fit);
    WriteFile(tmp / "rcurve_outliers.dat",
              OutlierTable("# crack_length[mm] R[J/m^2]", f.out_a, f.out_R));
    gp += kTerminal;
    gp += "set output 'rcurve.png'\n";
    if (!f.fit_R.empty()) {
      gp += "set multiplot\nset title 'R curve: data and fitted model'\n";
      gp += "set size 1,0.68\nset origin 0,0.32\nset bmargin 0\nset lmargin 10\nset format x ''\n";
      gp += "set ylabel 'R [J/m^2]'\n";
      gp += "plot 'rcurve_data.dat' u 1:2 w p pt 7 ps 0.6 lc rgb '#1f77b4' t 'data', "
            "'rcurve_outliers.dat' u 1:2 w p pt 2 ps 1.2 lc rgb '#d62728' t 'outliers (removed)', "
            "'rcurve_fit.dat' u 1:2 w l lw 2 lc rgb '#ff7f0e' t 'fitted model'\n";
      gp += "set size 1,0.30\nset origin 0,0.02\nset bmargin 3\nset tmargin 0\nset format x '%g'\n";
      gp += "unset title\nset xlabel 'crack length a [mm]'\nset ylabel 'residual [J/m^2]'\nunset key\n"
            "set ytics out\nset ytics scale 0.5\nset lmargin 10\n";
      gp += "plot 'rcurve_fit.dat' u 1:3 w p pt 7 ps 0.5 lc rgb '#1f77b4', 0 w l lc rgb 'black'\n";
      gp += "unset multiplot\nset key top left\nunset tmargin\nunset bmargin\nunset lmargin\nunset xlabel\nset ytics in\n";
    } else {
      gp += "set title 'R curve (no model curve in the fit file)'\nset xlabel 'crack length a [mm]'\n"
            "set ylabel 'R [J/m^2]'\nplot 'rcurve_data.dat' u 1:2 w p pt 7 ps 0.6 t 'data'\nunset title\n";
      summary.notes.push_back("no fitted R curve in the fit file: data only");
    }
    summary.figures.push_back("rcurve.png");
  }

  // 2. Bridging law with the region of laws consistent with the CIs / bounds.
  const Estimate* sc = f.Find("sigma_c");
  const Estimate* dc = f.Find("delta_c");
  std::optional<laws::BridgingLaw> truth_law;
  laws::LawShape truth_shape;
  std::optional<double> truth_jtip;
  if (!options.truth_scene.empty()) {
    const Scene scene = io::ReadSceneFile(options.truth_scene);
    if (scene.fracture) truth_jtip = scene.fracture->J_tip_c;
    if (scene.bridging) {
      truth_shape = scene.bridging->shape;
      truth_law = laws::BridgingLaw{&truth_shape, scene.bridging->scales.sigma_c,
                                    scene.bridging->scales.delta_c};
    }
  }
  const bool bridging = !(f.bridging == 0.0) && sc && dc && std::isfinite(sc->value) &&
                        sc->value > 0 &&
                        (std::isfinite(dc->value) || std::isfinite(dc->lower_bound) ||
                         std::isfinite(dc->ci_low));
  if (bridging) {
    const laws::LawShape shape = ShapeOf(f.law, &summary.notes);
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
    const laws::BridgingLaw best{&shape, sc->value, d_best};
    const laws::BridgingLaw low{&shape, s_lo, d_lo};
    std::string dat = "# delta[mm] lower[MPa] upper[MPa] best[MPa] truth[MPa]\n";
    const int n = 300;
    for (int i = 0; i <= n; ++i) {
      const double d = x_max * i / n;
      const double upper = std::isfinite(d_hi) ? laws::BridgingLaw{&shape, s_hi, d_hi}.Traction(d)
                                               : s_hi * laws::ShapeValue(shape, 0.0);
      const double t = truth_law ? truth_law->Traction(d) : NAN;
      dat += fmt::format("{:.8g} {:.8g} {:.8g} {:.8g} {:.8g}\n", d * 1e3, low.Traction(d) * 1e-6,
                         upper * 1e-6, best.Traction(d) * 1e-6, t * 1e-6);
    }
    WriteFile(tmp / "law.dat", dat);
    const std::string region =
        std::isfinite(d_hi) ? "laws within the 95% CIs"
                            : "laws allowed by the bounds ({/Symbol d}_c, J_B only bounded below)";
    gp += kTerminal;
    gp += "set output 'law.png'\nset title 'Bridging law'\n";
    gp += "set xlabel 'crack opening {/Symbol d} [mm]'\nset ylabel 'bridging stress {/Symbol s} [MPa]'\n";
    gp += "set key top right\nset yrange [0:*]\n";
    gp += "plot 'law.dat' u 1:2:3 w filledcurves fc rgb '#cfe2f3' fs solid 0.8 t '" + region +
          "', '' u 1:4 w l lw 2 lc rgb '#ff7f0e' t '" +
          (at_bound ? "best {/Symbol s}_c with {/Symbol d}_c at its lower bound" : "best fit") + "'";
    if (truth_law) gp += ", '' u 1:5 w l lw 2 dt 2 lc rgb 'black' t 'true law (synthetic test)'";
    gp += "\nunset title\nset key top left\nset autoscale y\nunset xlabel\n";
    summary.figures.push_back("law.png");
  } else {
    summary.notes.push_back("no bridging detected: no bridging-law figure");
  }

  // 3. Profile likelihoods, one panel per parameter.
  if (!f.profiles.empty()) {
    gp += kTerminal;
    gp += "set output 'profiles.png'\n";
    gp += fmt::format("set multiplot layout 1,{} title 'Profile likelihood (others re-optimized)'\n",
                      f.profiles.size());
    for (const FitData::Profile& p : f.profiles) {
      const double factor = p.name == "sigma_c" ? 1e-6 : (p.name == "delta_c" ? 1e3 : 1.0);
      std::string dat = "# value chi2\n";
      std::vector<size_t> order(p.value.size());
      for (size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::sort(order.begin(), order.end(), [&](size_t x, size_t y) { return p.value[x] < p.value[y]; });
      for (size_t i : order) dat += fmt::format("{:.8g} {:.8g}\n", p.value[i] * factor, p.chi2[i]);
      const std::string file = "profile_" + p.name + ".dat";
      WriteFile(tmp / file, dat);
      gp += fmt::format("set xlabel '{} [{}]'\nset ylabel '{{/Symbol c}}^2'\nunset key\n",
                        p.name == "sigma_c" ? "{/Symbol s}_c" : (p.name == "J_B" ? "J_B" : "J_{tip,c}"),
                        GnuplotUnit(p.name));
      // A profile spanning decades (an unbounded J_B) reads better on a log axis.
      const auto [mn, mx] = std::minmax_element(p.value.begin(), p.value.end());
      const bool wide = *mn > 0 && *mx / *mn > 30;
      gp += wide ? "set logscale x\n" : "unset logscale x\n";
      gp += "set xtics rotate by 35 right font ',9'\nset xtics autofreq\n";
      gp += "plot '" + file + "' u 1:2 w lp pt 7 ps 0.5 lw 2 lc rgb '#1f77b4'";
      if (std::isfinite(p.threshold)) gp += fmt::format(", {:.8g} w l dt 2 lc rgb '#d62728'", p.threshold);
      gp += "\n";
    }
    gp += "unset multiplot\nunset xlabel\nunset logscale x\nset xtics norotate font ''\nset key top left\n";
    summary.figures.push_back("profiles.png");
  } else {
    summary.notes.push_back("no profile likelihood in the fit file (fit run with --no-profile?)");
  }

  // 4. Load-displacement and crack length against frame from the record.
  // The record: --record, else the fit file itself when it carries /experiment.
  fs::path record_h5 = options.record_h5;
  if (record_h5.empty() && io::H5Reader(fit_h5).Exists("/experiment/load")) record_h5 = fit_h5;
  if (!record_h5.empty()) {
    const io::H5Reader r(record_h5);
    const ExperimentRecord rec = io::ReadExperimentH5(r, "/experiment");
    std::string dat = "# frame displacement[mm] load[N] crack_length[mm]\n";
    for (size_t i = 0; i < rec.load.size(); ++i)
      dat += fmt::format("{} {:.8g} {:.8g} {:.8g}\n", i, rec.displacement[i] * 1e3, rec.load[i],
                         i < rec.crack_length.size() ? rec.crack_length[i] * 1e3 : NAN);
    WriteFile(tmp / "record.dat", dat);
    gp += kTerminal;
    gp += "set output 'load_displacement.png'\nset title 'Load against load-point displacement'\n";
    gp += "set xlabel 'displacement [mm]'\nset ylabel 'load P [N]'\n";
    if (!f.fit_P.empty()) {
      // A load-displacement fit: the model's load over the record, residuals below.
      std::string fit = "# displacement[mm] load_model[N] residual[N]\n";
      for (size_t i = 0; i < f.fit_d.size(); ++i)
        fit += fmt::format("{:.8g} {:.8g} {:.8g}\n", f.fit_d[i] * 1e3, f.fit_P[i],
                           f.data_P[i] - f.fit_P[i]);
      WriteFile(tmp / "load_fit.dat", fit);
      WriteFile(tmp / "load_outliers.dat",
                OutlierTable("# displacement[mm] load[N]", f.out_d, f.out_P));
      gp += "set multiplot\nset size 1,0.68\nset origin 0,0.32\nset bmargin 0\nset lmargin 10\n"
            "set format x ''\nunset xlabel\nset key top right\n";
      gp += "plot 'record.dat' u 2:3 w p pt 7 ps 0.4 lc rgb '#1f77b4' t 'record', "
            "'load_outliers.dat' u 1:2 w p pt 2 ps 1.2 lc rgb '#d62728' t 'outliers (removed)', "
            "'load_fit.dat' u 1:2 w l lw 2 lc rgb '#ff7f0e' t 'fitted model'\n";
      gp += "set size 1,0.30\nset origin 0,0.02\nset bmargin 3\nset tmargin 0\nset format x '%g'\n"
            "unset title\nset xlabel 'displacement [mm]'\nset ylabel 'residual [N]'\nunset key\n"
            "set ytics out\nset ytics scale 0.5\n";
      gp += "plot 'load_fit.dat' u 1:3 w p pt 7 ps 0.4 lc rgb '#1f77b4', 0 w l lc rgb 'black'\n";
      gp += "unset multiplot\nset key top left\nunset tmargin\nunset bmargin\nunset lmargin\n"
            "unset xlabel\nset ytics in\nunset title\n";
    } else {
      gp += "unset key\nplot 'record.dat' u 2:3 w lp pt 7 ps 0.4 lc rgb '#1f77b4'\nunset title\n"
            "set key top left\n";
    }
    summary.figures.push_back("load_displacement.png");
    bool have_crack = !rec.crack_length.empty();
    std::string dic_plot;
    bool dic_on_rows = false;  // DIC frames drawn at their record rows (image column)
    if (!options.dic_csv.empty()) {
      const io::CsvTable t = io::ReadCsvTable(options.dic_csv);
      int col = -1;
      for (size_t i = 0; i < t.names.size(); ++i)
        if (t.names[i].find("crack_length") != std::string::npos) { col = static_cast<int>(i); break; }
      if (col >= 0) {
        const std::vector<double> a = t.ColumnSi(t.names[col], Dimension::Length());
        // A record whose image column names the frames: each frame at its row.
        std::vector<double> row(a.size(), NAN);
        if (!rec.images.empty() && t.Find("image") >= 0) {
          const std::vector<std::string>& images = t.TextColumn("image");
          for (size_t k = 0; k < a.size(); ++k)
            for (size_t r = 0; r < rec.images.size(); ++r)
              if (!rec.images[r].empty() &&
                  fs::path(rec.images[r]).filename() == fs::path(images[k]).filename()) {
                row[k] = static_cast<double>(r);
                dic_on_rows = true;
                break;
              }
        }
        std::string d = dic_on_rows ? "# record_row crack_length[mm]\n" : "# frame crack_length[mm]\n";
        for (size_t i = 0; i < a.size(); ++i)
          d += fmt::format("{} {:.8g}\n", dic_on_rows ? row[i] : static_cast<double>(i), a[i] * 1e3);
        WriteFile(tmp / "dic.dat", d);
        dic_plot = dic_on_rows
                       ? ", 'dic.dat' u 1:2 w p pt 6 ps 1.5 lw 2 lc rgb '#2ca02c' t 'DIC (at the rows of its images)'"
                       : ", 'dic.dat' u 1:2 axes x2y1 w lp pt 6 ps 1 lw 2 lc rgb '#2ca02c' t 'DIC (image index, top axis)'";
        have_crack = true;
      } else {
        summary.notes.push_back("DIC CSV has no crack_length column: " + options.dic_csv.string());
      }
    }
    if (have_crack) {
      gp += kTerminal;
      gp += "set output 'crack_length.png'\nset title 'Crack length against frame'\n";
      gp += "set xlabel 'record row'\nset ylabel 'crack length a [mm]'\n";
      if (!dic_plot.empty() && !dic_on_rows)
        gp += "set xtics nomirror\nset x2tics\nset x2label 'image index (DIC)'\n";
      gp += "plot ";
      const bool from_images = rec.metadata.count("crack_length") > 0;  // rcurve --crack-length-from
      gp += rec.crack_length.empty()
                ? "1/0 notitle"
                : std::string("'record.dat' u 1:4 w p pt 7 ps 0.4 lc rgb '#1f77b4' t '") +
                      (from_images ? "record (from the images, linear between frames)" : "record") + "'";
      gp += dic_plot + "\nunset title\nunset x2label\n";
      summary.figures.push_back("crack_length.png");
    }
  } else {
    summary.notes.push_back("no record given: no load-displacement or crack-length figure");
  }
  // Issue 15: every row the R-curve reduction did not use, by reason, and
  // its warnings (written by `rcurve --out` and the fit of a record).
  {
    const io::H5Reader fit_file(fit_h5);
    if (fit_file.Exists("/rcurve/dropped_reasons") && fit_file.Exists("/rcurve/dropped_counts")) {
      const std::vector<std::string> reasons = fit_file.ReadStrings("/rcurve/dropped_reasons");
      const std::vector<double> counts = fit_file.ReadVector("/rcurve/dropped_counts");
      for (std::size_t i = 0; i < std::min(reasons.size(), counts.size()); ++i)
        summary.notes.push_back(fmt::format("R curve: {:.0f} record rows not used: {}", counts[i],
                                            reasons[i]));
    }
    if (fit_file.Exists("/rcurve/warnings"))
      for (const std::string& w : fit_file.ReadStrings("/rcurve/warnings"))
        if (w != "none") summary.notes.push_back("R curve warning: " + w);
  }

  WriteFile(tmp / "report.gp", gp);
  const std::string command = "cd " + ShellQuote(tmp.string()) + " && " + ShellQuote(options.gnuplot) +
                              " report.gp > gnuplot.log 2>&1";
  const int rc = std::system(command.c_str());
  for (const std::string& fig : summary.figures) {
    if (rc != 0 || !fs::exists(tmp / fig) || fs::file_size(tmp / fig) == 0) {
      std::ifstream log(tmp / "gnuplot.log");
      std::stringstream text;
      text << log.rdbuf();
      throw Error(ErrorKind::kRuntime,
                  fmt::format("gnuplot failed (exit {}) drawing {}: {}", rc, fig, text.str()),
                  {.file = (tmp / "report.gp").string(), .expected = "gnuplot with the pngcairo terminal"});
    }
  }

  // HTML page.
  const std::string title = options.title.empty() ? fit_h5.filename().string() : options.title;
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  h += "<title>bridgefit report: " + Escape(title) + "</title>\n";
  // Browser self-check: #bf-check ends as "ok" only when every image decoded
  // and no script error happened (read back by the headless-Chromium test).
  h += R"(<script>
window.addEventListener('error', function (e) {
  var m = document.getElementById('bf-check');
  if (m) { m.setAttribute('data-status', 'script-error'); m.textContent = 'script error: ' + e.message; }
});
window.addEventListener('load', function () {
  var m = document.getElementById('bf-check'), bad = [];
  for (var i = 0; i < document.images.length; i++) {
    var img = document.images[i];
    if (!img.complete || img.naturalWidth === 0) bad.push(img.getAttribute('src'));
  }
  if (m.getAttribute('data-status') !== 'pending') return;
  m.setAttribute('data-status', bad.length ? 'missing-images' : 'ok');
  m.textContent = bad.length ? 'missing images: ' + bad.join(', ')
                             : 'all ' + document.images.length + ' figures loaded';
});
</script>
<style>
body { font-family: sans-serif; max-width: 920px; margin: 1em auto; color: #222; }
table { border-collapse: collapse; margin: 0.5em 0 1em 0; }
th, td { border: 1px solid #bbb; padding: 3px 8px; text-align: left; }
th { background: #eee; }
.verdict { padding: 0.5em; background: #f4f8ff; border-left: 4px solid #1f77b4; }
img { max-width: 100%; }
#bf-check { color: #777; font-size: small; }
</style>
</head>
<body>
)";
  h += "<h1>Bridging-law fit: " + Escape(title) + "</h1>\n";
  h += "<p class=\"verdict\"><b>Identifiability verdict:</b> " + Escape(f.verdict) + "</p>\n";
  h += "<h2>Results</h2>\n<table id=\"results\">\n<tr><th>parameter</th><th>value</th><th>95% CI</th>"
       "<th>lower bound</th><th>units</th><th>status</th>";
  if (options.truth_scene.empty()) h += "<th>note</th></tr>\n";
  else h += "<th>true value</th><th>note</th></tr>\n";
  for (const Estimate& e : f.estimates) {
    if (!e.present) continue;
    const Display d = DisplayOf(e.name);
    std::string status = e.fixed ? "fixed" : e.identified ? "identified"
                         : std::isfinite(e.lower_bound) ? "lower bound only" : "not identified";
    if (e.name != "J_tip_c" && f.bridging == 0.0) status = "no bridging detected";
    h += "<tr><td>" + d.label + "</td><td>" + Num(e.value, d.factor) + "</td><td>";
    h += std::isfinite(e.ci_low) || std::isfinite(e.ci_high)
             ? "[" + Num(e.ci_low, d.factor) + ", " + Num(e.ci_high, d.factor) + "]" : "&ndash;";
    h += "</td><td>" + (std::isfinite(e.lower_bound) ? "&ge; " + Num(e.lower_bound, d.factor) : "&ndash;");
    h += "</td><td>" + d.unit + "</td><td>" + status + "</td>";
    if (!options.truth_scene.empty()) {
      double truth = NAN;
      if (truth_law) {
        if (e.name == "sigma_c") truth = truth_law->sigma_c;
        if (e.name == "delta_c") truth = truth_law->delta_c;
        if (e.name == "J_B") truth = truth_law->BridgingToughness();
      } else if (e.name != "J_tip_c") {
        truth = 0.0;
      }
      if (e.name == "J_tip_c" && truth_jtip) truth = *truth_jtip;
      h += "<td>" + Num(truth, d.factor) + "</td>";
    }
    std::string note = e.decided_by;
    if (!e.note.empty()) note += (note.empty() ? "" : ": ") + e.note;
    h += "<td>" + Escape(note) + "</td></tr>\n";
  }
  h += "</table>\n<table id=\"run\">\n";
  auto row = [&](const std::string& k, const std::string& v) {
    h += "<tr><th>" + k + "</th><td>" + v + "</td></tr>\n";
  };
  row("forward model", Escape(f.model));
  row("optimizer", Escape(f.optimizer));
  row("law family", Escape(f.law));
  if (!f.r_kind.empty()) row("R in the data", Escape(f.r_kind));
  row("converged", f.converged == 1.0 ? "yes" : "no" + (f.stop_reason.empty() ? "" : " (" + Escape(f.stop_reason) + ")"));
  row("bridging detected", f.bridging == 1.0 ? "yes" : "no");
  row("steady state reached in the data", f.steady == 1.0 ? "yes" : "no");
  if (!f.fit_to.empty()) row("fitted to", Escape(f.fit_to));
  if (std::isfinite(f.rms_load)) row("rms residual (load)", Num(f.rms_load) + " N");
  row(std::isfinite(f.rms_load) ? "rms residual (R at the fitted parameters)" : "rms residual",
      Num(f.rms) + " J/m<sup>2</sup>");
  row("data points", fmt::format("{} ({} used, {} outliers removed)", f.a.size(), f.fit_a.size(), f.out_a.size()));
  if (std::isfinite(f.evaluations)) row("model evaluations", Num(f.evaluations));
  row("fit time", Num(f.wall_s) + " s");
  if (!f.scene.empty()) row("scene", Escape(f.scene));
  row("fit file", Escape(fs::absolute(fit_h5).string()));
  h += "</table>\n<h2>Figures</h2>\n";
  const std::map<std::string, std::string> captions = {
      {"rcurve.png", "R curve: data (points) and the fitted model, residuals (data &minus; model) below."},
      {"law.png", "Bridging law: best fit and the shaded region of laws consistent with the 95% CIs; "
                  "where &delta;<sub>c</sub> and J<sub>B</sub> are only bounded below the region is open to the right."},
      {"profiles.png", "Profile likelihood &chi;<sup>2</sup> of each parameter with the others re-optimized; "
                       "the dashed line is the 95% threshold."},
      {"load_displacement.png", f.fit_P.empty()
                                    ? "Load against load-point displacement (the record)."
                                    : "Load against load-point displacement: the record, the model "
                                      "fitted to it, residuals (record &minus; model) below."},
      {"crack_length.png", "Crack length against frame: the record and, when given, DIC on the images."}};
  for (const std::string& fig : summary.figures) {
    const auto it = captions.find(fig);
    h += "<figure><img src=\"" + fig + "\" alt=\"" + fig + "\"><figcaption>" +
         (it != captions.end() ? it->second : fig) + "</figcaption></figure>\n";
  }
  if (!summary.notes.empty()) {
    h += "<h2>Notes</h2>\n<ul>\n";
    for (const std::string& n : summary.notes) h += "<li>" + Escape(n) + "</li>\n";
    h += "</ul>\n";
  }
  h += "<p>Figures drawn by gnuplot from <code>report.gp</code> and the <code>*.dat</code> files in this folder.</p>\n";
  h += "<p id=\"bf-check\" data-status=\"pending\">figures not checked (JavaScript off?)</p>\n";
  h += "</body>\n</html>\n";
  WriteFile(tmp / "index.html", h);

  // Replace the target folder by the finished one.
  std::error_code ec;
  fs::path old;
  if (fs::exists(target)) {
    old = parent / fmt::format(".{}.old-{}-{}", leaf, ::getpid(), stamp);
    fs::rename(target, old);
  }
  fs::rename(tmp, target);
  cleanup.path.clear();
  if (!old.empty()) fs::remove_all(old, ec);
  summary.index_html = target / "index.html";
  summary.wall_s = watch.Seconds();
  return summary;
}

}  // namespace bridgefit::report
