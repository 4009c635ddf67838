// `bridgefit simulate`: grows the crack of a scene with a forward model.
//   bridgefit simulate scene.toml --model reduced --resolution "0.5 mm" --json
//   bridgefit simulate scene.toml --model reduced --out run.h5 --csv run.csv
//   bridgefit simulate scene.toml --model reduced --cache-dir ~/.cache/bridgefit
//   bridgefit simulate scene.toml --model mpm --cell "2.5 mm"   (simulate_mpm.cpp)
// Flags -> options -> pipeline::SimulateReduced (pipeline/simulate.hpp) ->
// printing; the files are written by pipeline/simulation_file.hpp.

#include <iostream>
#include <string>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/pipeline/simulate.hpp"
#include "bridgefit/pipeline/simulation_file.hpp"
#include "command.hpp"
#include "json_output.hpp"
#include "simulate_mpm.hpp"

namespace bridgefit::cli {

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
    const pipeline::ReducedSimulation run = pipeline::SimulateReduced(scene, options, cache_dir_);
    if (!out_h5_.empty()) pipeline::WriteSimulationH5(out_h5_, run.result, scene);
    if (!csv_.empty()) pipeline::WriteSimulationCsv(csv_, run.result);
    if (common.json) {
      PrintJson(SimulationJson(run.result));
    } else {
      std::cout << run.BriefReport();
    }
    return run.result.status == RunStatus::kOk ? 0 : 1;
  }

 private:
  std::string scene_file_, model_ = "reduced", resolution_, cache_dir_, out_h5_, csv_;
  MpmCliOptions mpm_;
};

}  // namespace
std::unique_ptr<Command> MakeSimulateCommand() { return std::make_unique<SimulateCommand>(); }
}  // namespace bridgefit::cli
