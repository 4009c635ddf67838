#pragma once
// Private parts of the report (src/report): the input it presents
// (ReportInput, read in report_input.cpp: the only place that opens files),
// the figure builders (gnuplot script + data tables) and the page.
//
// Stages of WriteFitReport (report.cpp):
//   ReadReportInput -> Add*Figure (figures_fit.cpp, figures_record.cpp,
//   figures_dic.cpp) -> RunGnuplot -> WritePage (page.cpp) -> Publish.

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/report/report.hpp"

namespace bridgefit::report::detail {

namespace fs = std::filesystem;

// ---- input: a view of a fit (+ optional record, DIC, reference, truth) ----

struct Estimate {
  std::string name, units;
  double value = NAN, ci_low = NAN, ci_high = NAN, lower_bound = NAN;
  // Issue 17: ci_* are the total interval (statistical + model bias); the
  // profile's own crossings are the statistical ends (NaN in older files).
  double statistical_low = NAN, statistical_high = NAN, model_bias = NAN;
  double ProfileLow() const { return std::isfinite(model_bias) ? statistical_low : ci_low; }
  double ProfileHigh() const { return std::isfinite(model_bias) ? statistical_high : ci_high; }
  bool present = false, identified = false, fixed = false;
  std::string decided_by, note;
};

struct Profile {
  std::string name;
  std::vector<double> value, chi2;  // SI value, best chi^2 with the others re-optimized
  double threshold = NAN;           // Delta chi^2 of the 95% interval (3.84 s^2)
  bool flat = false;                // stays under the threshold to the box edge on a side
};

struct FitView {
  std::string source;  // file name, for the page
  std::string model, optimizer, law, verdict, r_kind, scene, stop_reason, fit_to;
  double converged = NAN, steady = NAN, bridging = NAN, rms = NAN, rms_load = NAN, wall_s = NAN;
  double evaluations = NAN, reduced_chi2 = NAN;
  std::vector<double> a, R, fit_a, fit_R, out_a, out_R;
  // A load-displacement fit: rows used, their load and the model's load.
  std::vector<double> fit_d, fit_P, data_P, out_d, out_P;
  std::vector<Estimate> estimates;  // sigma_c, J_B, delta_c, J_tip_c
  std::vector<Profile> profiles;
  const Estimate* Find(const std::string& name) const {
    for (const Estimate& e : estimates)
      if (e.name == name && e.present) return &e;
    return nullptr;
  }
};

// One DIC frame as `bridgefit dic` wrote it (CSV and/or HDF5).
struct DicFrame {
  std::string image;            // as recorded
  fs::path image_file;          // resolved on disk (empty when not found)
  double crack_length = NAN;    // [m]
  double tip_x = NAN, tip_y = NAN;  // [px], reference image
  std::string tip_method;       // "" or "none" when no tip
  double valid_fraction = NAN;
  bool methods_disagree = false;
  double tip_williams_s = NAN, tip_jump_s = NAN, tip_sqrt_s = NAN;  // [px] along the line, per method
  std::vector<double> cod_s, cod_opening;  // [px] along the crack line
  // A path found by DIC (optional, later versions): points in px.
  std::vector<double> path_x, path_y;
  std::string flag;             // why the frame is doubtful ("" = fine)
};

struct DicView {
  fs::path csv, h5;
  std::vector<DicFrame> frames;
  bool has_line = false;
  double line[4] = {NAN, NAN, NAN, NAN};  // x0,y0,x1,y1 [px]
  double scale_m_per_px = NAN, offset_m = NAN, fit_radius_px = NAN, subset_px = NAN;
  std::vector<double> path_x, path_y;     // a crack path for the whole sequence, if given
  bool has_geometry() const { return !h5.empty(); }
};

struct ReferenceView {
  std::string label, column, unit_text;  // e.g. G_I, N/mm
  fs::path file;
  std::vector<double> crack_length, value;  // [m], [J/m^2] (rows with both finite)
};

struct TruthView {
  bool present = false;
  std::optional<laws::LawShape> shape;  // the true law's shape (bridging in the scene)
  double sigma_c = NAN, delta_c = NAN, J_B = NAN, J_tip_c = NAN;
};

struct ReportInput {
  FitView fit;
  std::optional<ExperimentRecord> record;
  bool record_from_images = false;  // its crack length came from DIC (rcurve --crack-length-from)
  std::optional<DicView> dic;
  std::optional<ReferenceView> reference;
  TruthView truth;
  std::vector<std::string> notes;  // what could not be read, and why
};

// Reads everything the report shows; throws Error(kInput) naming the file.
ReportInput ReadReportInput(const fs::path& fit_h5, const ReportOptions& options);

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
// Each figure starts from the same state (multiplot leaves size/origin/margins set).
extern const char* const kTerminal;
// Two stacked panels (data above, residuals below) with explicit screen
// margins so tick labels of one never reach the other.
extern const char* const kUpperPanel;
extern const char* const kLowerPanel;

}  // namespace bridgefit::report::detail
