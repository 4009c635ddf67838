#pragma once
// The report's input read from files: the fit file (/fit, pipeline/fit_file),
// its record (/experiment, of the fit file or `--record`), the DIC output
// (pipeline/dic_file), a reference column (CSV) and a truth scene (TOML).
// report::WriteFitReport takes the value; WriteFitReport here is
// `bridgefit report`: read, then render.
//   pipeline::WriteFitReport("fit.h5", "out/mdf_ct", {})

#include <filesystem>

#include "bridgefit/report/report.hpp"
#include "bridgefit/report/report_input.hpp"

namespace bridgefit::pipeline {

// Throws Error(kInput) naming the file (and field) that cannot be read.
report::ReportInput ReadReportInput(const std::filesystem::path& fit_h5,
                                    const report::ReportOptions& options);

// ReadReportInput, then report::WriteFitReport into `out_dir` (replaced).
report::ReportSummary WriteFitReport(const std::filesystem::path& fit_h5,
                                     const std::filesystem::path& out_dir,
                                     const report::ReportOptions& options = {});

}  // namespace bridgefit::pipeline
