// `bridgefit simulate`: grows the crack of a scene with a forward model.
//   bridgefit simulate scene.toml --model reduced --resolution "0.5 mm" --json
//   bridgefit simulate scene.toml --model reduced --out run.h5 --csv run.csv
//   bridgefit simulate scene.toml --model reduced --cache-dir ~/.cache/bridgefit
//   bridgefit simulate scene.toml --model mpm --cell "2.5 mm"   (simulate_mpm.cpp)

#include <cmath>
#include <iostream>
#include <string>

#include <fmt/format.h>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/models/crack_plane_cache.hpp"
#include "bridgefit/models/reduced.hpp"
#include "command.hpp"
#include "simulate_mpm.hpp"

namespace bridgefit::cli {

std::string PointsCsv(const SimulationResult& result) {
  std::string text =
      "crack_length [m], R [J/m^2], R_energy [J/m^2], J_tip [J/m^2], J_ff [J/m^2], "
      "delta_root [m], root_position [m], bridging_zone_length [m], load [N], "
      "displacement [m], cmod [m]\n";
  for (const SimulationPoint& p : result.points)
    text += fmt::format("{:.10g}, {:.10g}, {:.10g}, {:.10g}, {:.10g}, {:.10g}, {:.10g}, {:.10g}, "
                        "{:.10g}, {:.10g}, {:.10g}\n",
                        p.crack_length, p.R, p.R_energy, p.J_tip, p.J_ff, p.delta_root,
                        p.root_position, p.bridging_zone_length, p.load, p.displacement, p.cmod);
  return text;
}

nlohmann::json ResultJson(const SimulationResult& result) {
  nlohmann::json out;
  out["model"] = result.model;
  out["status"] = RunStatusName(result.status);
  out["message"] = result.message;
  out["wall_s"] = result.wall_s;
  out["steady_state_reached"] = result.steady_state_reached;
  out["steady_state_crack_length_m"] = NumberOrNull(result.steady_state_crack_length);
  out["initiation_load_N"] = NumberOrNull(result.initiation_load);
  nlohmann::json figures = nlohmann::json::object();
  for (const auto& [key, value] : result.figures) figures[key] = NumberOrNull(value);
  out["figures"] = figures;
  nlohmann::json points = nlohmann::json::array();
  for (const SimulationPoint& p : result.points)
    points.push_back({{"crack_length_m", NumberOrNull(p.crack_length)},
                      {"R_J_per_m2", NumberOrNull(p.R)},
                      {"R_energy_J_per_m2", NumberOrNull(p.R_energy)},
                      {"J_tip_J_per_m2", NumberOrNull(p.J_tip)},
                      {"J_ff_J_per_m2", NumberOrNull(p.J_ff)},
                      {"delta_root_m", NumberOrNull(p.delta_root)},
                      {"root_position_m", NumberOrNull(p.root_position)},
                      {"bridging_zone_length_m", NumberOrNull(p.bridging_zone_length)},
                      {"load_N", NumberOrNull(p.load)},
                      {"displacement_m", NumberOrNull(p.displacement)},
                      {"cmod_m", NumberOrNull(p.cmod)}});
  out["points"] = std::move(points);
  return out;
}

void WriteSimulationH5(const std::string& path, const SimulationResult& result,
                       const Scene& scene) {
  io::H5Writer file(path);
  io::WriteRecordH5(file, result);
  file.WriteAttribute("/simulation", "scene", scene.source);
  file.Commit();
}

void PrintPointsTable(const SimulationResult& result) {
  std::cout << result.message << "\n";
  if (result.steady_state_reached)
    std::cout << fmt::format("steady state from a = {:.2f} mm\n",
                             result.steady_state_crack_length * 1e3);
  std::cout << fmt::format("{:>10} {:>10} {:>12} {:>10} {:>12} {:>10} {:>10}\n", "a [mm]",
                           "R [J/m^2]", "R_en [J/m^2]", "P [N]", "disp [mm]", "d_root[mm]",
                           "root [mm]");
  const size_t stride = std::max<size_t>(1, result.points.size() / 20);
  for (size_t i = 0; i < result.points.size(); ++i) {
    if (i % stride != 0 && i + 1 != result.points.size()) continue;
    const SimulationPoint& p = result.points[i];
    std::cout << fmt::format("{:10.3f} {:10.1f} {:12.1f} {:10.2f} {:12.4f} {:10.4f} {:10.2f}\n",
                             p.crack_length * 1e3, p.R, p.R_energy, p.load, p.displacement * 1e3,
                             p.delta_root * 1e3, p.root_position * 1e3);
  }
}

namespace {

class SimulateCommand final : public Command {
 public:
  const char* name() const override { return "simulate"; }
  const char* description() const override {
    return "Grow the crack of a scene with a forward model (reduced or mpm)";
  }
  void Register(CLI::App& sub) override {
    sub.add_option("scene", scene_file_, "Scene TOML file")->required();
    sub.add_option("--model", model_, "reduced | mpm")
        ->default_val("reduced")
        ->check(CLI::IsMember({"reduced", "mpm"}));
    sub.add_option("--resolution", resolution_,
                   "reduced: element size along the crack plane, e.g. '0.5 mm' "
                   "(default W/200 for CT, min(h/4, L/400) for DCB)");
    sub.add_option("--cache-dir", cache_dir_,
                   "reduced: directory caching the specimen's crack-plane model (HDF5)");
    sub.add_option("--out", out_h5_, "Write the result to this HDF5 file (/simulation)");
    sub.add_option("--csv", csv_, "Write the points to this CSV file");
    RegisterMpmOptions(sub, mpm_);
  }

  int Run(const CommonOptions& common) override {
    const Scene scene = io::ReadSceneFile(scene_file_);
    if (model_ == "mpm") return RunMpmSimulation(scene, mpm_, out_h5_, csv_, common);

    models::ReducedOptions options;
    if (!resolution_.empty()) {
      try {
        options.mesh.resolution = ParseQuantity(resolution_, Dimension::Length());
      } catch (const Error& e) {
        throw Error(ErrorKind::kUsage, e.message(), e.context())
            .WithContext({.field = "--resolution"});
      }
      if (!(options.mesh.resolution > 0.0))
        throw Error(ErrorKind::kUsage, "the resolution must be positive",
                    {.field = "--resolution", .value = resolution_});
    }
    options.progress = !common.quiet;
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
    const auto crack_plane =
        models::LoadOrBuildCrackPlaneModel(scene, options.mesh, cache_dir_, &cache);
    const double model_s = watch.Seconds();
    const models::ReducedModel model(crack_plane);
    std::optional<laws::BridgingLaw> law;
    if (scene.bridging) law = scene.bridging->Law();
    SimulationResult result =
        model.Run(law ? &*law : nullptr, scene.fracture->J_tip_c, options);
    result.figures["model_load_or_build_s"] = model_s;
    result.figures["model_cache_hit"] = cache.hit ? 1.0 : 0.0;
    result.figures["r_curve_s"] = result.wall_s;
    result.wall_s = watch.Seconds();

    if (!out_h5_.empty()) WriteSimulationH5(out_h5_, result, scene);
    if (!csv_.empty()) WriteTextFileAtomic(csv_, PointsCsv(result));

    if (common.json) {
      PrintJson(ResultJson(result));
    } else {
      std::cout << fmt::format(
          "model reduced ({}): {} elements, h = {:.4g} mm, {} crack lengths; model {:.3f} s "
          "({}), R curve {:.2f} ms\n",
          RunStatusName(result.status), crack_plane->elements, crack_plane->resolution * 1e3,
          result.points.size(), model_s, cache.hit ? "cached" : "built",
          result.figures["r_curve_s"] * 1e3);
      PrintPointsTable(result);
    }
    return result.status == RunStatus::kOk ? 0 : 1;
  }

 private:
  std::string scene_file_, model_ = "reduced", resolution_, cache_dir_, out_h5_, csv_;
  MpmCliOptions mpm_;
};

}  // namespace
std::unique_ptr<Command> MakeSimulateCommand() { return std::make_unique<SimulateCommand>(); }
}  // namespace bridgefit::cli
