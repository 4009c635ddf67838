// HTML report of a campaign (include/bridgefit/report/campaign_report.hpp).
// Stages: the R-curve overlay (data tables + gnuplot script) -> RunGnuplot ->
// the page -> Publish (the fit report's staging, report_impl.hpp).

#include "bridgefit/report/campaign_report.hpp"

#include <sstream>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "report_impl.hpp"

namespace bridgefit::report {
namespace {

using detail::Escape;
using detail::Num;

// Every specimen's data (points) and fit (line), one colour each.
void AddOverlay(const CampaignView& view, detail::FigureSet& set) {
  std::string plots;
  int index = 0;
  for (const CampaignSpecimenView& s : view.specimens) {
    if (s.crack_length.empty()) continue;
    std::ostringstream data, fit;
    data << "# crack_length [mm], R [J/m^2]\n";
    for (std::size_t i = 0; i < s.crack_length.size(); ++i)
      data << fmt::format("{:.6g} {:.6g}\n", s.crack_length[i] * 1e3, s.R[i]);
    const std::string data_file = fmt::format("campaign_data_{}.dat", index);
    detail::WriteFile(set.dir / data_file, data.str());
    const std::string title = detail::GnuplotText(s.name);
    plots += fmt::format("{}'{}' using 1:2 with points pt 7 ps 0.7 lc {} title '{}'", plots.empty() ? "" : ", ",
                         data_file, index + 1, title);
    if (!s.fitted_crack_length.empty()) {
      fit << "# crack_length [mm], fitted R [J/m^2]\n";
      for (std::size_t i = 0; i < s.fitted_crack_length.size(); ++i)
        fit << fmt::format("{:.6g} {:.6g}\n", s.fitted_crack_length[i] * 1e3, s.fitted_R[i]);
      const std::string fit_file = fmt::format("campaign_fit_{}.dat", index);
      detail::WriteFile(set.dir / fit_file, fit.str());
      plots += fmt::format(", '{}' using 1:2 with lines lw 2 lc {} title '{} fit'", fit_file,
                           index + 1, title);
    }
    ++index;
  }
  if (plots.empty()) {
    set.notes.push_back("R-curve overlay left out: no specimen has an R curve");
    return;
  }
  set.gp += detail::kTerminal;
  set.gp += "set output 'rcurves.png'\nset key outside right\nset xlabel 'crack length a [mm]'\n"
            "set ylabel 'R [J/m^2]'\nset title 'R curves and fits, every specimen'\nplot " +
            plots + "\n";
  set.Add("rcurves.png", "campaign",
          "Every specimen's R curve (points) and its fitted model (line), one colour each.");
}

std::string Cell(const Estimate& e) {
  const detail::Display d = detail::DisplayOf(e.name);
  if (std::isfinite(e.value)) {
    std::string text = Num(e.value, d.factor) + " " + d.unit;
    if (std::isfinite(e.ci_low) || std::isfinite(e.ci_high))
      text += " [" + Num(e.ci_low, d.factor) + ", " + Num(e.ci_high, d.factor) + "]";
    return text;
  }
  if (std::isfinite(e.lower_bound)) return "&ge; " + Num(e.lower_bound, d.factor) + " " + d.unit + " (bound)";
  return "-";
}

std::string PageHtml(const CampaignView& view, const detail::FigureSet& set) {
  std::ostringstream out;
  out << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>"
      << Escape(view.name) << "</title>" << detail::kBrowserCheck << "<style>body{font-family:sans-serif;max-width:1100px;margin:auto}"
      << "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 6px}"
      << ".flag{background:#fde2c8}</style></head><body>\n";
  out << "<h1>Campaign: " << Escape(view.name) << "</h1>\n" << detail::kBrowserCheckElement;
  out << "<p>" << view.specimens.size() << " specimens. Intervals are the total 95% intervals "
      << "(statistical and model error); a bound is a PHYSICS 7 lower bound (the test did not "
      << "reach steady state). Flagged cells are outliers by the campaign's robust rule "
      << "(docs/CAMPAIGN.md), kept, not dropped.</p>\n";
  for (const detail::Figure& f : set.figures)
    out << "<figure id=\"" << Escape(f.file) << "\"><img src=\"" << Escape(f.file) << "\" alt=\""
        << Escape(f.file) << "\"><figcaption>" << f.caption << "</figcaption></figure>\n";
  out << "<h2 id=\"specimens\">Specimens</h2>\n<table><tr><th>specimen</th><th>status</th>";
  const char* names[] = {"sigma_c", "J_B", "delta_c", "J_tip_c"};
  for (const char* n : names) out << "<th>" << detail::DisplayOf(n).label << "</th>";
  out << "</tr>\n";
  for (const CampaignSpecimenView& s : view.specimens) {
    out << "<tr><td>" << Escape(s.name) << "</td><td>" << Escape(s.status)
        << (s.error.empty() ? "" : ": " + Escape(s.error)) << "</td>";
    for (std::size_t k = 0; k < 4; ++k) {
      bool flagged = false;
      for (const std::string& p : s.outlier_in) flagged = flagged || p == names[k];
      out << "<td" << (flagged ? " class=\"flag\"" : "") << ">"
          << (k < s.estimates.size() ? Cell(s.estimates[k]) : "-") << "</td>";
    }
    out << "</tr>\n";
  }
  out << "</table>\n<h2 id=\"statistics\">Statistics</h2>\n<table><tr><th>parameter</th><th>unit"
      << "</th><th>values</th><th>bounds</th><th>mean</th><th>SD</th><th>CV [%]</th><th>median"
      << "</th><th>campaign lower bound</th><th>outliers</th><th>note</th></tr>\n";
  for (const CampaignStatisticView& p : view.statistics)
    out << "<tr><td>" << Escape(p.parameter) << "</td><td>" << Escape(p.unit) << "</td><td>"
        << p.values << "</td><td>" << p.bounds << "</td><td>" << Num(p.mean) << "</td><td>"
        << Num(p.sd) << "</td><td>" << Num(p.cv_percent) << "</td><td>" << Num(p.median)
        << "</td><td>" << Num(p.lower_bound)
        << (p.bound_from.empty() ? "" : " (" + Escape(p.bound_from) + ")") << "</td><td>"
        << Escape(p.outliers) << "</td><td>" << Escape(p.note) << "</td></tr>\n";
  out << "</table>\n";
  if (!view.joint_text.empty())
    out << "<h2 id=\"joint\">Joint fit</h2>\n<pre>" << Escape(view.joint_text) << "</pre>\n";
  for (const std::string& note : set.notes) out << "<p class=\"note\">" << Escape(note) << "</p>\n";
  out << "</body></html>\n";
  return out.str();
}

}  // namespace

ReportSummary WriteCampaignReport(const CampaignView& view, const std::filesystem::path& out_dir,
                                  const ReportOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, why, {.field = "report options"});
  if (out_dir.empty()) throw Error(ErrorKind::kUsage, "the output folder is empty", {.field = "--out"});
  Stopwatch watch;
  detail::StagingFolder staging(out_dir);
  detail::FigureSet set;
  set.dir = staging.path;
  set.gp = "# gnuplot script of this report (run: gnuplot report.gp)\nset datafile missing 'nan'\nset grid\n";
  AddOverlay(view, set);
  if (!set.figures.empty()) detail::RunGnuplot(set, options.gnuplot);
  detail::WriteFile(staging.path / "index.html", PageHtml(view, set));
  staging.Publish();
  ReportSummary summary;
  summary.index_html = staging.target / "index.html";
  for (const detail::Figure& f : set.figures) summary.figures.push_back(f.file);
  summary.notes = set.notes;
  summary.wall_s = watch.Seconds();
  return summary;
}

}  // namespace bridgefit::report
