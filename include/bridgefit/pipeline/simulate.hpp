#pragma once
// The forward runs of `bridgefit simulate` as calls (issue 16): a scene's
// crack grown by the reduced model or by MPM (quasi-static growth), or the
// stationary crack of an explicit MPM run, each returning a result value with
// the text the CLI prints. Their files: pipeline/simulation_file.hpp.
//
// A failed or stopped run is data (the result's status); bad input throws
// bridgefit::Error (kInput naming the scene field, kUsage for options).

#include <string>

#include "bridgefit/core/records.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/mpm/growth.hpp"
#include "bridgefit/mpm/solver.hpp"
#include "bridgefit/scene/scene.hpp"

namespace bridgefit::pipeline {

// The points as a table for a reader: the run's message, where steady state
// starts, and about 20 rows (the last always).
std::string SimulationTable(const SimulationResult& result);

// Reduced model (docs/REDUCED.md): crack-plane model loaded from
// `cache_dir` or built (and cached there when given), then grown.
struct ReducedSimulation {
  SimulationResult result;  // figures: model_load_or_build_s, model_cache_hit, r_curve_s
  int elements = 0;         // of the crack-plane model
  double resolution = 0.0;  // its element size h [m]
  double model_s = 0.0;     // loading or building it [s]
  bool cache_hit = false;
  // "model reduced (ok): N elements, h = ... mm, ..." and SimulationTable.
  std::string BriefReport() const;
};
// The scene needs [fracture] and [run] grow = true.
ReducedSimulation SimulateReduced(const Scene& scene, const models::ReducedOptions& options,
                                  const std::string& cache_dir);

// MPM crack growth (mpm/growth.hpp) with the scene's law and J_tip,c.
mpm::GrowthResult SimulateMpmGrowth(const Scene& scene, const mpm::GrowthOptions& options);
// "model mpm (ok), quasi-static half model: ..." and SimulationTable.
std::string MpmGrowthBriefReport(const mpm::GrowthResult& growth);

// The stationary crack with the explicit MPM solver (mpm/solver.hpp), its
// fields and history written to `out_h5` (+ .xdmf) when given.
struct MpmStationaryRun {
  mpm::Summary summary;
  std::string description;     // the model's
  std::vector<int> contour_cells;  // of the history's J columns
  std::string xdmf_path;       // written next to out_h5 (empty without)
};
// The stationary run; `cell` [m] and `ppc` build the specimen model.
MpmStationaryRun SimulateMpmStationary(const Scene& scene, double cell, int ppc,
                                       const mpm::SolverOptions& options,
                                       const std::string& out_h5);

}  // namespace bridgefit::pipeline
