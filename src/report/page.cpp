// The report's HTML page: verdict, results and run tables, the figures by
// section with their tables (profiles, reference deviation, DIC frames).
#include <cmath>

#include <fmt/format.h>

#include "report_impl.hpp"

namespace bridgefit::report::detail {
namespace {

}  // namespace

// Browser self-check: #bf-check ends as "ok" only when every image decoded
// and no script error happened (read back by the headless-Chromium tests).
const char* const kBrowserCheck = R"(<script>
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
)";
const char* const kBrowserCheckElement =
    "<p id=\"bf-check\" data-status=\"pending\">figures not checked (JavaScript off?)</p>\n";

namespace {

const char* const kStyle = R"(<style>
body { font-family: sans-serif; max-width: 1000px; margin: 1em auto; color: #222; }
table { border-collapse: collapse; margin: 0.5em 0 1em 0; }
th, td { border: 1px solid #bbb; padding: 3px 8px; text-align: left; }
th { background: #eee; }
tr.flagged td { background: #fff3e0; }
.verdict { padding: 0.5em; background: #f4f8ff; border-left: 4px solid #1f77b4; }
img { max-width: 100%; }
figure { margin: 1em 0; }
#bf-check { color: #777; font-size: small; }
</style>
</head>
<body>
)";

std::string ResultsTable(const ReportInput& in) {
  const FitView& f = in.fit;
  std::string h = "<h2>Results</h2>\n<table id=\"results\">\n<tr><th>parameter</th><th>value</th><th>95% CI</th>"
                  "<th>lower bound</th><th>units</th><th>status</th>";
  h += in.truth.present ? "<th>true value</th><th>note</th></tr>\n" : "<th>note</th></tr>\n";
  for (const Estimate& e : f.estimates) {
    if (!e.present) continue;
    const Display d = DisplayOf(e.name);
    std::string status = e.fixed ? "fixed" : e.identified ? "identified"
                         : std::isfinite(e.lower_bound) ? "lower bound only" : "not identified";
    if (e.name != "J_tip_c" && f.bridging == 0.0) status = "no bridging detected";
    h += "<tr><td>" + d.label + "</td><td>" + Num(e.value, d.factor) + "</td><td>";
    h += std::isfinite(e.ci_low) || std::isfinite(e.ci_high)
             ? "[" + Num(e.ci_low, d.factor) + ", " + Num(e.ci_high, d.factor) + "]" : "&ndash;";
    // Issue 17: the printed interval is the total; its parts.
    if (std::isfinite(e.model_bias))
      h += " (statistical [" + Num(e.statistical_low, d.factor) + ", " +
           Num(e.statistical_high, d.factor) + "], model bias " + Num(e.model_bias, d.factor) + ")";
    h += "</td><td>" + (std::isfinite(e.lower_bound) ? "&ge; " + Num(e.lower_bound, d.factor) : "&ndash;");
    h += "</td><td>" + d.unit + "</td><td>" + status + "</td>";
    if (in.truth.present) {
      const double truth = e.name == "sigma_c" ? in.truth.sigma_c
                           : e.name == "delta_c" ? in.truth.delta_c
                           : e.name == "J_B"     ? in.truth.J_B
                                                 : in.truth.J_tip_c;
      h += "<td>" + Num(truth, d.factor) + "</td>";
    }
    std::string note = e.decided_by;
    if (!e.note.empty()) note += (note.empty() ? "" : ": ") + e.note;
    h += "<td>" + Escape(note) + "</td></tr>\n";
  }
  return h + "</table>\n";
}

std::string RunTable(const FitView& f, const fs::path& fit_h5) {
  std::string h = "<table id=\"run\">\n";
  auto row = [&](const std::string& k, const std::string& v) { h += "<tr><th>" + k + "</th><td>" + v + "</td></tr>\n"; };
  row("forward model", Escape(f.model));
  row("optimizer", Escape(f.optimizer));
  row("law family", Escape(f.law));
  if (!f.r_kind.empty()) row("R in the data", Escape(f.r_kind));
  row("converged", f.converged == 1.0 ? "yes" : "no" + (f.stop_reason.empty() ? "" : " (" + Escape(f.stop_reason) + ")"));
  row("bridging detected", f.bridging == 1.0 ? "yes" : "no");
  row("steady state reached in the data", f.steady == 1.0 ? "yes" : "no");
  if (!f.fit_to.empty()) row("fitted to", Escape(f.fit_to));
  if (std::isfinite(f.reduced_chi2)) row("reduced &chi;<sup>2</sup>", Num(f.reduced_chi2));
  if (std::isfinite(f.rms_load)) row("rms residual (load)", Num(f.rms_load) + " N");
  row(std::isfinite(f.rms_load) ? "rms residual (R at the fitted parameters)" : "rms residual",
      Num(f.rms) + " J/m<sup>2</sup>");
  if (!f.fit_d.empty()) {
    // A load-displacement fit: its data are the record's rows; the R curve only started it.
    row("record rows fitted", fmt::format("{} ({} outliers removed)", f.fit_d.size(), f.out_d.size()));
    row("R-curve points (start, figures)", fmt::format("{}", f.a.size()));
  } else {
    row("data points", fmt::format("{} ({} used, {} outliers removed)", f.a.size(), f.fit_a.size(), f.out_a.size()));
  }
  if (std::isfinite(f.evaluations)) row("model evaluations", Num(f.evaluations));
  row("fit time", Num(f.wall_s) + " s");
  if (!f.scene.empty()) row("scene", Escape(f.scene));
  row("fit file", Escape(fs::absolute(fit_h5).string()));
  return h + "</table>\n";
}

std::string Figures(const FigureSet& set, const std::string& section) {
  std::string h;
  for (const Figure& fig : set.figures) {
    if (fig.section != section) continue;
    const std::string id = fs::path(fig.file).stem().string();
    h += "<figure id=\"" + id + "\"><img src=\"" + fig.file + "\" alt=\"" + fig.file + "\"><figcaption>" +
         fig.caption + "</figcaption></figure>\n";
  }
  return h;
}

}  // namespace

std::string PageHtml(const ReportInput& in, const FigureSet& set, const std::string& title, const fs::path& fit_h5) {
  std::string h = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  h += "<title>bridgefit report: " + Escape(title) + "</title>\n";
  h += kBrowserCheck;
  h += kStyle;
  h += "<h1>Bridging-law fit: " + Escape(title) + "</h1>\n";
  h += "<p class=\"verdict\"><b>Identifiability verdict:</b> " + Escape(in.fit.verdict) + "</p>\n";
  h += ResultsTable(in);
  h += RunTable(in.fit, fit_h5);
  h += "<h2>Fit</h2>\n" + Figures(set, "fit") + set.law_shape_html;
  if (!set.profile_html.empty()) h += "<h3>Profiles</h3>\n" + set.profile_html;
  const std::string record = Figures(set, "record");
  if (!record.empty()) h += "<h2>Record</h2>\n" + record + set.reference_html;
  if (!set.dic_table_html.empty()) {
    h += "<h2>DIC evidence</h2>\n<p>Frames as <code>bridgefit dic</code> measured them; flagged rows are "
         "doubtful (no tip, tip methods disagreeing, few correlated points). The linked figures show the "
         "frame with the crack line, the tips and the field-fit window.</p>\n";
    h += set.dic_table_html + Figures(set, "dic");
  }
  std::vector<std::string> notes = in.notes;
  notes.insert(notes.end(), set.notes.begin(), set.notes.end());
  if (!notes.empty()) {
    h += "<h2>Notes</h2>\n<ul>\n";
    for (const std::string& n : notes) h += "<li>" + Escape(n) + "</li>\n";
    h += "</ul>\n";
  }
  h += "<p>Figures drawn by gnuplot from <code>report.gp</code> and the <code>*.dat</code> files in this folder.</p>\n";
  h += kBrowserCheckElement;
  h += "</body>\n</html>\n";
  return h;
}

}  // namespace bridgefit::report::detail
