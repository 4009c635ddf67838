// HTML report of a fit (include/bridgefit/report/report.hpp). Stages: the
// input is a value (read by pipeline/report_file) -> the figures (figures_*.cpp) -> RunGnuplot -> PageHtml (page.cpp) -> Publish.
#include "bridgefit/report/report.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "report_impl.hpp"

namespace bridgefit::report {
namespace fs = std::filesystem;

bool ReportOptions::IsValid(std::string* why) const {
  if (gnuplot.empty()) {
    if (why) *why = "the gnuplot executable name is empty";
    return false;
  }
  if (max_flagged_frames < 0) {
    if (why) *why = "max_flagged_frames is negative";
    return false;
  }
  if (reference.enabled() && (reference.csv.empty() || reference.column.empty())) {
    if (why) *why = "a reference column needs both the CSV (--reference-csv) and the column (--reference)";
    return false;
  }
  return true;
}

std::string ReportSummary::BriefReport() const {
  std::string text = fmt::format("report {} with {} figures in {:.2f} s", index_html.string(), figures.size(), wall_s);
  for (const std::string& note : notes) text += "\n  " + note;
  return text;
}

namespace {

std::string ShellQuote(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

detail::FigureSet BuildFigures(const detail::ReportInput& in, const fs::path& dir, const ReportOptions& options) {
  detail::FigureSet set;
  set.dir = dir;
  set.max_flagged_frames = options.max_flagged_frames;
  set.gp = "# gnuplot script of this report (run: gnuplot report.gp)\nset datafile missing 'nan'\nset grid\n";
  detail::AddRCurveFigure(in, set);
  detail::AddLawFigure(in, set);
  detail::AddProfileFigure(in, set);
  detail::AddRecordFigures(in, set);
  detail::AddReferenceFigure(in, set);
  detail::AddDicFigures(in, set);
  return set;
}

}  // namespace

namespace detail {

// Runs gnuplot on the script in `dir`; every figure must exist afterwards.
void RunGnuplot(const FigureSet& set, const std::string& gnuplot) {
  detail::WriteFile(set.dir / "report.gp", set.gp);
  const std::string command =
      "cd " + ShellQuote(set.dir.string()) + " && " + ShellQuote(gnuplot) + " report.gp > gnuplot.log 2>&1";
  const int rc = std::system(command.c_str());
  for (const detail::Figure& fig : set.figures) {
    if (rc != 0 || !fs::exists(set.dir / fig.file) || fs::file_size(set.dir / fig.file) == 0) {
      std::ifstream log(set.dir / "gnuplot.log");
      std::stringstream text;
      text << log.rdbuf();
      throw Error(ErrorKind::kRuntime, fmt::format("gnuplot failed (exit {}) drawing {}: {}", rc, fig.file, text.str()),
                  {.file = (set.dir / "report.gp").string(), .expected = "gnuplot with the pngcairo terminal"});
    }
  }
}

}  // namespace detail

ReportSummary WriteFitReport(const ReportInput& input, const fs::path& out_dir, const ReportOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, why, {.field = "report options"});
  if (out_dir.empty()) throw Error(ErrorKind::kUsage, "the output folder is empty", {.field = "--out"});
  Stopwatch watch;
  const fs::path& fit_h5 = input.fit_path;
  detail::StagingFolder staging(out_dir);
  const detail::FigureSet set = BuildFigures(input, staging.path, options);
  detail::RunGnuplot(set, options.gnuplot);
  const std::string title = options.title.empty() ? fit_h5.filename().string() : options.title;
  detail::WriteFile(staging.path / "index.html", detail::PageHtml(input, set, title, fit_h5));
  staging.Publish();

  ReportSummary summary;
  summary.index_html = staging.target / "index.html";
  for (const detail::Figure& fig : set.figures) summary.figures.push_back(fig.file);
  summary.notes = input.notes;
  summary.notes.insert(summary.notes.end(), set.notes.begin(), set.notes.end());
  summary.wall_s = watch.Seconds();
  return summary;
}

}  // namespace bridgefit::report
