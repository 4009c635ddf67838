#pragma once
// The report's input read from files: the fit file (/fit, pipeline/fit_file),
// its record (/experiment, of the fit file or `--record`), the DIC output
// (pipeline/dic_file), a reference column (CSV) and a truth scene (TOML).
// report::WriteFitReport takes the value; WriteFitReport here is
// `bridgefit report`: read, then render.
//   pipeline::WriteFitReport("fit.h5", "out/mdf_ct", {})

#include <filesystem>
#include <optional>
#include <string>

#include "bridgefit/pipeline/fit.hpp"
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

// A run's files (`bridgefit fit --out F --report DIR`): the fit file at
// `fit_h5` (atomic) and, with `report_dir`, its report, read back from the
// fit file (a temporary one, removed after, when `fit_h5` is empty).
// Returns the report's summary when one was written.
std::optional<report::ReportSummary> WriteFitOutputs(const FitRequest& request, const FitRun& run,
                                                     const std::string& fit_h5,
                                                     const std::filesystem::path& report_dir,
                                                     const report::ReportOptions& options);

}  // namespace bridgefit::pipeline
