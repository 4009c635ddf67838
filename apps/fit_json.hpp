#pragma once
// `bridgefit fit --json`: the fit run as one JSON object. Its keys are the
// CLI's interface (docs/FORMATS.md); `campaign` prints the same estimates.

#include <nlohmann/json.hpp>
#include <string>

#include "bridgefit/inverse/model_error.hpp"
#include "bridgefit/pipeline/fit.hpp"

namespace bridgefit::cli {

// The --json object of `bridgefit fit INPUT` (`input_path` as given).
nlohmann::json FitRunJson(const pipeline::FitRun& run, const std::string& input_path);

// The forward model's discretisation error estimate (the "model_error" key).
nlohmann::json ModelErrorJson(const inverse::ModelErrorEstimate& m);

}  // namespace bridgefit::cli
