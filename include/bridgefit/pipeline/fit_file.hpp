#pragma once
// The fit file (`bridgefit fit --out fit.h5`), its one owner: the input's
// groups (/experiment and /rcurve, pipeline/rcurve_file.hpp) and /fit (the
// summary, the data and the model's fit to it, the parameters, the model
// check, the profiles). Every dataset and attribute carries its units.

#include <string>

#include "bridgefit/pipeline/fit.hpp"

namespace bridgefit::pipeline {

// Writes `run` to `path` atomically (the file appears complete or not at all).
void WriteFitFile(const std::string& path, const FitRequest& request, const FitRun& run);

}  // namespace bridgefit::pipeline
