#pragma once
// Private parts of the report (src/report): the figure builders (gnuplot
// script + data tables) and the page. The input is a value
// (bridgefit/report/report_input.hpp) that pipeline/report_file.hpp reads:
// nothing in src/report opens a fit, record, DIC, CSV or TOML file.
//
// Stages of WriteFitReport (report.cpp):
//   FlagFrames -> Add*Figure (figures_fit.cpp, figures_record.cpp,
//   figures_dic.cpp) -> RunGnuplot -> WritePage (page.cpp) -> Publish.

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bridgefit/core/records.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/report/report.hpp"
#include "bridgefit/report/report_input.hpp"

namespace bridgefit::report::detail {

namespace fs = std::filesystem;

// ---- input: the public view types (bridgefit/report/report_input.hpp) ----
using report::DicFrame;
using report::DicView;
using report::Estimate;
using report::FitView;
using report::Profile;
using report::ReferenceView;
using report::ReportInput;
using report::TruthView;

// ---- figures ----

struct Figure {
  std::string file;     // PNG next to index.html
  std::string section;  // "fit", "record", "dic"
  std::string caption;  // HTML
};

struct FigureSet {
  fs::path dir;     // where the tables and the script are written
  int max_flagged_frames = 6;
  std::string gp;   // the gnuplot script
  std::vector<Figure> figures;
  std::vector<std::string> notes;
  // Extra page content: DIC frame table rows, reference deviation rows (HTML).
  std::string dic_table_html, reference_html, profile_html;
  // The fitted law's break points and a fitted shape's parameters (HTML,
  // after the law figure; figures_fit.cpp).
  std::string law_shape_html;
  void Add(const std::string& file, const std::string& section, const std::string& caption) {
    figures.push_back({file, section, caption});
  }
};

void AddRCurveFigure(const ReportInput& in, FigureSet& set);
void AddLawFigure(const ReportInput& in, FigureSet& set);
void AddProfileFigure(const ReportInput& in, FigureSet& set);
void AddRecordFigures(const ReportInput& in, FigureSet& set);
void AddReferenceFigure(const ReportInput& in, FigureSet& set);
void AddDicFigures(const ReportInput& in, FigureSet& set);

// ---- page ----
std::string PageHtml(const ReportInput& in, const FigureSet& set, const std::string& title,
                     const fs::path& fit_h5);

// ---- shared helpers (report_util.cpp) ----
struct Display {
  std::string label;  // HTML
  double factor;      // from SI
  std::string unit;   // HTML
};
Display DisplayOf(const std::string& name);
std::string GnuplotUnit(const std::string& name);
std::string GnuplotSymbol(const std::string& name);
std::string Num(double v, double factor = 1.0);
std::string Escape(const std::string& text);
std::string GnuplotText(const std::string& text);  // single-quoted gnuplot string content
void WriteFile(const fs::path& path, const std::string& text);
// A sibling temporary folder, removed unless released.
struct StagingFolder {
  fs::path target, parent, path;
  std::string leaf;
  long long stamp = 0;
  explicit StagingFolder(const fs::path& out_dir) {
    target = fs::absolute(out_dir).lexically_normal();
    parent = target.has_filename() ? target.parent_path() : target.parent_path().parent_path();
    leaf = target.has_filename() ? target.filename().string() : target.parent_path().filename().string();
    fs::create_directories(parent);
    stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    path = parent / fmt::format(".{}.tmp-{}-{}", leaf, ::getpid(), stamp);
    fs::create_directories(path);
  }
  ~StagingFolder() {
    std::error_code ec;
    if (!path.empty()) fs::remove_all(path, ec);
  }
  // Replaces the target folder by the finished one.
  void Publish() {
    std::error_code ec;
    fs::path old;
    if (fs::exists(target)) {
      old = parent / fmt::format(".{}.old-{}-{}", leaf, ::getpid(), stamp);
      fs::rename(target, old);
    }
    fs::rename(path, target);
    path.clear();
    if (!old.empty()) fs::remove_all(old, ec);
  }
};

// Runs gnuplot on set.gp in set.dir; every figure must exist afterwards
// (throws Error naming the script and gnuplot's log otherwise).
void RunGnuplot(const FigureSet& set, const std::string& gnuplot);

// The page's browser self-check (page.cpp): the script for <head> and the
// #bf-check element it sets to "ok" when every image decoded.
extern const char* const kBrowserCheck;
extern const char* const kBrowserCheckElement;

// Each figure starts from the same state (multiplot leaves size/origin/margins set).
extern const char* const kTerminal;
// Two stacked panels (data above, residuals below) with explicit screen
// margins so tick labels of one never reach the other.
extern const char* const kUpperPanel;
extern const char* const kLowerPanel;

}  // namespace bridgefit::report::detail
