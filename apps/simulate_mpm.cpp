// The MPM branch of `bridgefit simulate`: crack growth with bridging when the
// scene has [fracture] (quasi-static, half or full model), else a stationary
// crack with the explicit solver.
//   bridgefit simulate ct.toml --model mpm --cell "2.5 mm" --json          (growth)
//   bridgefit simulate ct.toml --model mpm --full --contours 3,5 --csv r.csv
//   bridgefit simulate stationary.toml --model mpm --out run.h5 --fields-every 500
#include "simulate_mpm.hpp"

#include <cmath>
#include <iostream>
#include <optional>

#include <fmt/format.h>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/mpm/growth.hpp"
#include "bridgefit/mpm/output.hpp"
#include "bridgefit/mpm/solver.hpp"

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
  std::optional<laws::BridgingLaw> law;
  if (scene.bridging) law = scene.bridging->Law();
  const mpm::GrowthResult g =
      mpm::SimulateGrowth(scene, law ? &*law : nullptr, scene.fracture->J_tip_c, opt);
  const SimulationResult& result = g.result;
  if (!out_h5.empty()) WriteSimulationH5(out_h5, result, scene);
  if (!csv.empty()) WriteTextFileAtomic(csv, PointsCsv(result));
  if (common.json) {
    nlohmann::json out = ResultJson(result);
    out["solver"] = "quasi-static (implicit MPM)";
    out["symmetry"] = g.half ? "half" : "full";
    out["cell_m"] = g.cell;
    out["increment_m"] = g.increment;
    out["particles"] = g.particles;
    out["dofs"] = g.dofs;
    // One static solve per crack length: no time steps to count.
    out["particle_steps_per_s"] = nullptr;
    out["contour_cells"] = g.contour_cells;
    nlohmann::json per_point = nlohmann::json::array();
    for (std::size_t i = 0; i < g.J_tip_contours.size(); ++i) {
      nlohmann::json row = nlohmann::json::array();
      for (double j : g.J_tip_contours[i]) row.push_back(NumberOrNull(j));
      per_point.push_back(row);
    }
    out["J_tip_contours_J_per_m2"] = per_point;
    nlohmann::json stages = nlohmann::json::object();
    for (const auto& [name, seconds] : g.stage_seconds) stages[name] = seconds;
    out["stage_seconds"] = stages;
    PrintJson(out);
  } else {
    std::cout << fmt::format(
        "model mpm ({}), quasi-static {} model: cell {:.4g} mm, {} particles, {} equations, "
        "increment {:.4g} mm, {:.3f} s\n",
        RunStatusName(result.status), g.half ? "half" : "full", g.cell * 1e3, g.particles,
        g.dofs, g.increment * 1e3, result.wall_s);
    PrintPointsTable(result);
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
  mpm::Model model = mpm::BuildSpecimenModel(scene, cell, options.ppc);
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
  std::string why;
  if (!opt.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid MPM options: " + why);

  mpm::Solver solver(model, opt);
  std::unique_ptr<mpm::RunWriter> writer;
  if (!out_h5.empty()) {
    writer = std::make_unique<mpm::RunWriter>(out_h5);
    if (opt.fields_every > 0)
      solver.SetFieldsCallback([&](long step, double time, const mpm::ParticleFields& f) {
        writer->AddFields(step, time, f);
      });
  }
  const mpm::Summary s = solver.Run();
  if (writer) writer->Finish(s, solver.model(), opt);

  const int main_contour = 0;
  if (!csv.empty()) {
    std::string text = "time_s,load_N,displacement_m,load_line_cod_m,kinetic_J,strain_J";
    for (int k : opt.contour_cells) text += fmt::format(",J_{}cells_J_per_m2", k);
    text += "\n";
    for (const auto& h : s.history) {
      text += fmt::format("{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}", h.time, h.load,
                          h.displacement, h.load_line_cod, h.kinetic, h.strain);
      for (double j : h.J) text += fmt::format(",{:.9g}", j);
      text += "\n";
    }
    WriteTextFileAtomic(csv, text);
  }
  if (common.json) {
    nlohmann::json history = nlohmann::json::array();
    for (const auto& h : s.history)
      history.push_back({{"time_s", h.time},
                         {"load_N", NumberOrNull(h.load)},
                         {"displacement_m", h.displacement},
                         {"load_line_cod_m", NumberOrNull(h.load_line_cod)},
                         {"J_J_per_m2", NumberOrNull(h.J.empty() ? NAN : h.J[main_contour])}});
    nlohmann::json contours = nlohmann::json::array();
    for (const auto& j : s.final_J)
      contours.push_back({{"half_cells", j.half_cells}, {"J_J_per_m2", NumberOrNull(j.J)}});
    PrintJson({{"model", "mpm"},
               {"status", RunStatusName(s.status)},
               {"message", s.message},
               {"description", solver.model().description},
               {"wall_s", s.wall_s},
               {"steps", s.steps},
               {"particles", s.particles},
               {"threads", s.threads},
               {"dt_s", s.dt},
               {"particle_steps_per_s", s.particle_steps_per_s},
               {"max_kinetic_to_strain_energy", s.max_kinetic_to_strain},
               {"final_load_N", NumberOrNull(s.final_load)},
               {"final_displacement_m", s.final_displacement},
               {"final_J", contours},
               {"out", out_h5},
               {"history", history}});
  } else {
    std::cout << s.BriefReport() << "\n";
    if (!out_h5.empty() && writer)
      std::cout << "wrote " << out_h5 << " and " << writer->xdmf_path().string() << "\n";
  }
  if (s.status != RunStatus::kOk) {
    std::cerr << "bridgefit simulate: MPM run " << RunStatusName(s.status) << ": " << s.message
              << "\n";
    return 1;
  }
  return 0;
}

}  // namespace bridgefit::cli
