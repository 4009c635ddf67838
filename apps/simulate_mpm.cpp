// The MPM branch of `bridgefit simulate`: crack growth with bridging when the
// scene has [fracture] (quasi-static, half or full model), else a stationary
// crack with the explicit solver.
//   bridgefit simulate ct.toml --model mpm --cell "2.5 mm" --json          (growth)
//   bridgefit simulate ct.toml --model mpm --full --contours 3,5 --csv r.csv
//   bridgefit simulate stationary.toml --model mpm --out run.h5 --fields-every 500
#include "simulate_mpm.hpp"

#include <iostream>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/mpm/growth.hpp"
#include "bridgefit/mpm/solver.hpp"
#include "bridgefit/pipeline/simulate.hpp"
#include "bridgefit/pipeline/simulation_file.hpp"
#include "json_output.hpp"

namespace bridgefit::cli {

void RegisterMpmOptions(CLI::App& sub, MpmCliOptions& options) {
  sub.add_option("--cell", options.cell, "MPM background cell size, e.g. '2.5 mm'")
      ->capture_default_str();
  sub.add_option("--ppc", options.ppc, "MPM particles per cell per direction")
      ->capture_default_str();
  sub.add_option("--threads", options.threads, "MPM OpenMP threads (0: default)");
  sub.add_option("--fields-every", options.fields_every,
                 "MPM: write particle fields to --out every N steps (0: never)");
  sub.add_option("--shape", options.shape, "MPM shape functions: gimp | linear")
      ->check(CLI::IsMember({"gimp", "linear"}))
      ->capture_default_str();
  sub.add_option("--scheme", options.scheme, "MPM update scheme: usf | usl | usavg")
      ->check(CLI::IsMember({"usf", "usl", "usavg"}))
      ->capture_default_str();
  sub.add_option("--cfl", options.cfl, "MPM CFL factor (time step = cfl h / c)")
      ->capture_default_str();
  sub.add_flag("--half", options.half,
               "MPM growth: half-specimen model (symmetry plane; default for symmetric scenes)");
  sub.add_flag("--full", options.full, "MPM growth: full explicit-crack model");
  sub.add_option("--increment", options.increment,
                 "MPM growth: tip increment, e.g. '2.5 mm' (default one cell)");
  sub.add_option("--contours", options.contours,
                 "MPM growth: J contour half sizes in cells (the first decides growth)")
      ->delimiter(',');
}

namespace {

// Crack growth on the MPM discretisation (mpm/growth.hpp).
int RunMpmGrowth(const Scene& scene, const MpmCliOptions& options, const std::string& out_h5,
                 const std::string& csv, const CommonOptions& common) {
  if (options.fields_every > 0)
    throw Error(ErrorKind::kUsage,
                "--fields-every is for the explicit stationary run; crack growth is solved "
                "quasi-statically and writes its points (--out, --csv)",
                {.field = "--fields-every", .expected = "no --fields-every, or [run] grow = false"});
  if (options.half && options.full)
    throw Error(ErrorKind::kUsage, "--half and --full exclude each other", {.field = "--half"});
  mpm::GrowthOptions opt;
  opt.cell = ParseQuantity(options.cell, Dimension::Length());
  opt.ppc = options.ppc;
  opt.shape = options.shape == "linear" ? mpm::ShapeFunction::kLinear : mpm::ShapeFunction::kGimp;
  opt.symmetry = options.half   ? mpm::GrowthSymmetry::kHalf
                 : options.full ? mpm::GrowthSymmetry::kFull
                                : mpm::GrowthSymmetry::kAuto;
  if (!options.increment.empty())
    opt.increment = ParseQuantity(options.increment, Dimension::Length());
  opt.contour_cells = options.contours;
  opt.threads = options.threads;
  opt.progress = !common.quiet;
  std::string why;
  if (!opt.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid MPM growth options: " + why);
  const mpm::GrowthResult g = pipeline::SimulateMpmGrowth(scene, opt);
  const SimulationResult& result = g.result;
  for (const std::string& w : result.warnings) std::cerr << "warning: simulate: " << w << "\n";
  if (!out_h5.empty()) pipeline::WriteSimulationH5(out_h5, result, scene);
  if (!csv.empty()) pipeline::WriteSimulationCsv(csv, result);
  if (common.json) {
    PrintJson(MpmGrowthJson(g));
  } else {
    std::cout << pipeline::MpmGrowthBriefReport(g);
  }
  return result.status == RunStatus::kOk ? 0 : 1;
}

}  // namespace

int RunMpmSimulation(const Scene& scene, const MpmCliOptions& options, const std::string& out_h5,
                     const std::string& csv, const CommonOptions& common) {
  const bool grows = scene.fracture.has_value() && scene.run.grow;
  if (grows) return RunMpmGrowth(scene, options, out_h5, csv, common);
  if (options.half)
    throw Error(ErrorKind::kUsage, "the half-specimen model is for crack growth",
                {.file = scene.source, .field = "--half",
                 .expected = "a scene with [fracture] and [run] grow = true"});
  if (scene.bridging)
    throw Error(ErrorKind::kUsage,
                "bridging needs crack growth: the stationary explicit run has no bridging",
                {.file = scene.source, .field = "fracture.J_tip_c",
                 .expected = "a [fracture] table (growth) or no [bridging]"});
  if (options.fields_every > 0 && out_h5.empty())
    throw Error(ErrorKind::kUsage, "--fields-every needs --out FILE.h5",
                {.field = "--fields-every"});
  const double cell = ParseQuantity(options.cell, Dimension::Length());
  mpm::SolverOptions opt;
  opt.shape = options.shape == "linear" ? mpm::ShapeFunction::kLinear : mpm::ShapeFunction::kGimp;
  opt.scheme = options.scheme == "usf"     ? mpm::UpdateScheme::kUSF
               : options.scheme == "usavg" ? mpm::UpdateScheme::kUSAVG
                                           : mpm::UpdateScheme::kUSL;
  opt.cfl_factor = options.cfl;
  opt.threads = options.threads;
  opt.target_displacement = scene.run.load_point_displacement.value_or(0.5e-3);
  opt.fields_every = options.fields_every;
  opt.progress = !common.quiet;
  const pipeline::MpmStationaryRun run =
      pipeline::SimulateMpmStationary(scene, cell, options.ppc, opt, out_h5);
  if (!csv.empty()) pipeline::WriteMpmHistoryCsv(csv, run.summary, run.contour_cells);
  if (common.json) {
    PrintJson(MpmStationaryJson(run, out_h5));
  } else {
    std::cout << run.summary.BriefReport() << "\n";
    if (!run.xdmf_path.empty()) std::cout << "wrote " << out_h5 << " and " << run.xdmf_path << "\n";
  }
  const mpm::Summary& s = run.summary;
  if (s.status != RunStatus::kOk) {
    std::cerr << "bridgefit simulate: MPM run " << RunStatusName(s.status) << ": " << s.message
              << "\n";
    return 1;
  }
  return 0;
}

}  // namespace bridgefit::cli
