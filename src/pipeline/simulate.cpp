// The forward runs of `bridgefit simulate` (pipeline/simulate.hpp).
#include "bridgefit/pipeline/simulate.hpp"

#include <algorithm>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/models/crack_plane_cache.hpp"
#include "bridgefit/mpm/model.hpp"
#include "bridgefit/mpm/output.hpp"

namespace bridgefit::pipeline {

std::string SimulationTable(const SimulationResult& result) {
  std::string text = result.message + "\n";
  for (const std::string& w : result.warnings) text += "warning: " + w + "\n";
  if (result.steady_state_reached)
    text += fmt::format("steady state from a = {:.2f} mm\n", result.steady_state_crack_length * 1e3);
  text += fmt::format("{:>10} {:>10} {:>12} {:>10} {:>12} {:>10} {:>10}\n", "a [mm]", "R [J/m^2]",
                      "R_en [J/m^2]", "P [N]", "disp [mm]", "d_root[mm]", "root [mm]");
  const size_t stride = std::max<size_t>(1, result.points.size() / 20);
  for (size_t i = 0; i < result.points.size(); ++i) {
    if (i % stride != 0 && i + 1 != result.points.size()) continue;
    const SimulationPoint& p = result.points[i];
    text += fmt::format("{:10.3f} {:10.1f} {:12.1f} {:10.2f} {:12.4f} {:10.4f} {:10.2f}\n",
                        p.crack_length * 1e3, p.R, p.R_energy, p.load, p.displacement * 1e3,
                        p.delta_root * 1e3, p.root_position * 1e3);
  }
  return text;
}

std::string ReducedSimulation::BriefReport() const {
  const auto r_curve_s = result.figures.find("r_curve_s");
  return fmt::format(
             "model reduced ({}): {} elements, h = {:.4g} mm, {} crack lengths; model {:.3f} s "
             "({}), R curve {:.2f} ms\n",
             RunStatusName(result.status), elements, resolution * 1e3, result.points.size(),
             model_s, cache_hit ? "cached" : "built",
             (r_curve_s != result.figures.end() ? r_curve_s->second : 0.0) * 1e3) +
         SimulationTable(result);
}

ReducedSimulation SimulateReduced(const Scene& scene, const models::ReducedOptions& options,
                                  const std::string& cache_dir) {
  scene.Validate();
  if (!scene.fracture)
    throw Error(ErrorKind::kInput, "the reduced model needs a [fracture] table",
                {.file = scene.source, .field = "fracture.J_tip_c",
                 .expected = "a crack-tip toughness, e.g. '2210 J/m^2'"});
  if (!scene.run.grow)
    throw Error(ErrorKind::kInput, "the reduced model only runs crack growth",
                {.file = scene.source, .field = "run.grow", .expected = "true"});

  Stopwatch watch;
  models::CacheOutcome cache;
  const auto crack_plane = models::LoadOrBuildCrackPlaneModel(scene, options.mesh, cache_dir, &cache);
  ReducedSimulation run;
  run.model_s = watch.Seconds();
  run.elements = crack_plane->elements;
  run.resolution = crack_plane->resolution;
  run.cache_hit = cache.hit;
  const models::ReducedModel model(crack_plane);
  std::optional<laws::BridgingLaw> law;
  if (scene.bridging) law = scene.bridging->Law();
  run.result = model.Run(law ? &*law : nullptr, scene.fracture->J_tip_c, options);
  run.result.figures["model_load_or_build_s"] = run.model_s;
  run.result.figures["model_cache_hit"] = cache.hit ? 1.0 : 0.0;
  run.result.figures["r_curve_s"] = run.result.wall_s;
  run.result.wall_s = watch.Seconds();
  return run;
}

mpm::GrowthResult SimulateMpmGrowth(const Scene& scene, const mpm::GrowthOptions& options) {
  if (!scene.fracture)
    throw Error(ErrorKind::kInput, "MPM crack growth needs a [fracture] table",
                {.file = scene.source, .field = "fracture.J_tip_c",
                 .expected = "a crack-tip toughness, e.g. '2210 J/m^2'"});
  std::optional<laws::BridgingLaw> law;
  if (scene.bridging) law = scene.bridging->Law();
  return mpm::SimulateGrowth(scene, law ? &*law : nullptr, scene.fracture->J_tip_c, options);
}

std::string MpmGrowthBriefReport(const mpm::GrowthResult& g) {
  const SimulationResult& result = g.result;
  return fmt::format(
             "model mpm ({}), quasi-static {} model: cell {:.4g} mm, {} particles, {} equations, "
             "increment {:.4g} mm, {:.3f} s\n",
             RunStatusName(result.status), g.half ? "half" : "full", g.cell * 1e3, g.particles,
             g.dofs, g.increment * 1e3, result.wall_s) +
         SimulationTable(result);
}

MpmStationaryRun SimulateMpmStationary(const Scene& scene, double cell, int ppc,
                                       const mpm::SolverOptions& options,
                                       const std::string& out_h5) {
  mpm::Model model = mpm::BuildSpecimenModel(scene, cell, ppc);
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid MPM options: " + why);
  mpm::Solver solver(model, options);
  std::unique_ptr<mpm::RunWriter> writer;
  if (!out_h5.empty()) {
    writer = std::make_unique<mpm::RunWriter>(out_h5);
    if (options.fields_every > 0)
      solver.SetFieldsCallback([&](long step, double time, const mpm::ParticleFields& f) {
        writer->AddFields(step, time, f);
      });
  }
  MpmStationaryRun run;
  run.summary = solver.Run();
  if (writer) {
    writer->Finish(run.summary, solver.model(), options);
    run.xdmf_path = writer->xdmf_path().string();
  }
  run.description = solver.model().description;
  run.contour_cells = options.contour_cells;
  return run;
}

}  // namespace bridgefit::pipeline
