#pragma once
// HTML report of a fit: index.html plus PNG figures drawn by gnuplot (run as
// an external program on a script written next to the figures), built in a
// temporary folder and renamed onto the output folder when complete.
//   report::WriteFitReport(pipeline::ReadReportInput("fit.h5", {}), "out/mdf_ct", {})
// (pipeline::WriteFitReport("fit.h5", "out/mdf_ct") does both).
// Figures: data and fitted R curve with residuals, the bridging law with the
// region of laws allowed by the CIs / lower bounds, the profile likelihoods as
// Delta chi^2 with the threshold that defines the printed intervals and their
// ends marked; with a record (an rcurve.h5 with /experiment) load against
// displacement and crack length against frame; with DIC output the frames
// with the crack line, the tips and the field-fit window drawn on them and
// the opening along the crack; with a reference column (e.g. a DCB record's
// G_I) that column against R. docs/REPORT.md.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "bridgefit/report/report_input.hpp"

namespace bridgefit::report {

// A toughness column of a CSV record drawn against the R curve (e.g. the
// G_I the data's authors reduced), with its deviation from R in a table.
struct ReferenceColumn {
  std::filesystem::path csv;                 // the record CSV holding the column
  std::string column;                        // header name, e.g. "G_I"
  std::string crack_length_column = "crack_length";  // header of its crack length
  std::map<std::string, std::string> units;  // header -> unit, e.g. G_I -> N/mm
                                             // (else the header's brackets)
  bool enabled() const { return !csv.empty() || !column.empty(); }
};

// The files named here are read by pipeline::ReadReportInput.
struct ReportOptions {
  std::string title;                   // page title (default: the fit file name)
  std::filesystem::path record_h5;     // optional: HDF5 with /experiment (bridgefit rcurve --out);
                                       // default: the fit file's own /experiment, if any
  std::filesystem::path dic_csv;       // optional: bridgefit dic --csv (crack length per frame)
  std::filesystem::path dic_h5;        // optional: bridgefit dic --out (tips, crack line,
                                       // opening profiles): the DIC evidence figures
  std::filesystem::path images_dir;    // where the DIC images are when their recorded
                                       // paths do not resolve (default: next to dic_h5)
  ReferenceColumn reference;           // optional
  std::filesystem::path lawfree_h5;    // optional: bridgefit lawfree --out, drawn over the law
  std::filesystem::path truth_scene;   // optional: scene TOML with the true law (synthetic tests)
  std::string gnuplot = "gnuplot";     // executable
  int max_flagged_frames = 6;          // DIC frames flagged doubtful drawn at most
  bool IsValid(std::string* why) const;
};

struct ReportSummary {
  std::filesystem::path index_html;
  std::vector<std::string> figures;    // file names next to index.html
  std::vector<std::string> notes;      // figures left out and why
  double wall_s = 0.0;
  std::string BriefReport() const;
};

// Writes `out_dir`/index.html with its figures from `input` (a value: the
// report opens no fit, record, DIC or scene file; pipeline/report_file.hpp
// reads them). An existing `out_dir` is replaced. Throws bridgefit::Error:
// kUsage for bad options, kRuntime when gnuplot fails (its log is named in
// the message).
ReportSummary WriteFitReport(const ReportInput& input, const std::filesystem::path& out_dir,
                             const ReportOptions& options = {});

}  // namespace bridgefit::report
