#pragma once
// HTML report of a fit: index.html plus PNG figures drawn by gnuplot (run as
// an external program on a script written next to the figures), built in a
// temporary folder and renamed onto the output folder when complete.
//   report::WriteFitReport("fit.h5", "out/mdf_ct", {})
// Figures: data and fitted R curve with residuals, the bridging law with the
// region of laws allowed by the CIs / lower bounds, profile-likelihood curves,
// and, when a record is given (an rcurve.h5 with /experiment), load against
// displacement and crack length against frame (record and optional DIC CSV).

#include <filesystem>
#include <string>
#include <vector>

namespace bridgefit::report {

struct ReportOptions {
  std::string title;                   // page title (default: the fit file name)
  std::filesystem::path record_h5;     // optional: HDF5 with /experiment (bridgefit rcurve --out);
                                       // default: the fit file's own /experiment, if any
  std::filesystem::path dic_csv;       // optional: bridgefit dic --csv (crack length per frame)
  std::filesystem::path truth_scene;   // optional: scene TOML with the true law (synthetic tests)
  std::string gnuplot = "gnuplot";     // executable
  bool IsValid(std::string* why) const;
};

struct ReportSummary {
  std::filesystem::path index_html;
  std::vector<std::string> figures;    // file names next to index.html
  std::vector<std::string> notes;      // figures left out and why
  double wall_s = 0.0;
  std::string BriefReport() const;
};

// Reads the fit file (layout in docs/FORMATS.md: /rcurve, /fit) and writes
// `out_dir`/index.html with its figures. An existing `out_dir` is replaced.
// Throws bridgefit::Error: kInput for a missing or malformed fit file,
// kRuntime when gnuplot fails (its log is named in the message).
ReportSummary WriteFitReport(const std::filesystem::path& fit_h5,
                             const std::filesystem::path& out_dir,
                             const ReportOptions& options = {});

}  // namespace bridgefit::report
