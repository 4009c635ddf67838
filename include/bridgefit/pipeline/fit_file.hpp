#pragma once
// The fit file (`bridgefit fit --out fit.h5`), its one owner (writer and
// reader): the input's groups (/experiment and /rcurve,
// pipeline/rcurve_file.hpp) and /fit (the summary, the data and the model's
// fit to it, the parameters, the model check, the profiles). Every dataset
// and attribute carries its units.

#include <filesystem>
#include <string>

#include "bridgefit/pipeline/fit.hpp"
#include "bridgefit/report/report_input.hpp"

namespace bridgefit::pipeline {

// Writes `run` to `path` atomically (the file appears complete or not at all).
void WriteFitFile(const std::string& path, const FitRequest& request, const FitRun& run);

// Reads /fit back as the report's view of it (its R curve from /rcurve when
// /fit holds none). Throws Error(kInput) naming the file and field for a
// missing file, no /fit group or no R curve.
report::FitView ReadFitView(const std::filesystem::path& path);

}  // namespace bridgefit::pipeline
