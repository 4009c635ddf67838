#pragma once
// The --json objects of `rcurve`, `law`, `lawfree` and `simulate`: the library's result
// values as JSON (SI, units in the keys). The keys are the CLI's interface;
// the values come computed from the library (pipeline/rcurve.hpp,
// pipeline/law.hpp, pipeline/simulate.hpp). `fit` has its own (fit_json.hpp).

#include <nlohmann/json.hpp>

#include "bridgefit/core/records.hpp"
#include "bridgefit/mpm/growth.hpp"
#include "bridgefit/pipeline/law.hpp"
#include "bridgefit/pipeline/law_free.hpp"
#include "bridgefit/pipeline/rcurve.hpp"
#include "bridgefit/pipeline/simulate.hpp"

namespace bridgefit::cli {

// `bridgefit rcurve --json` (without the "out" and "csv" paths).
nlohmann::json RCurveRunJson(const pipeline::RCurveRun& run);

// `bridgefit law --json`.
nlohmann::json LawRunJson(const pipeline::LawRun& run);

// `bridgefit lawfree --json`: each route's sigma(delta) with its band,
// J_tip,c, J_B and delta_c (value or lower bound), notes.
nlohmann::json LawFreeRunJson(const pipeline::LawFreeRun& run);

// `bridgefit simulate --json`: a growth run (reduced, or MPM before its
// solver keys are added by MpmGrowthJson).
nlohmann::json SimulationJson(const SimulationResult& result);
nlohmann::json MpmGrowthJson(const mpm::GrowthResult& growth);
// The stationary explicit MPM run (`out`: the --out path, maybe empty).
nlohmann::json MpmStationaryJson(const pipeline::MpmStationaryRun& run, const std::string& out);

}  // namespace bridgefit::cli
