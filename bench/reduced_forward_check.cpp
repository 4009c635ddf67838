// The reduced model's forward runs as a fit makes them: one crack-plane model,
// many laws. Times a run (best and median of `reps`) and writes every point of
// every run to OUT (17 digits), so that two builds can be compared number by
// number (scripts/compare_forward.py OLD NEW).
//   bf_reduced_forward_bench OUT [resolution_mm=0.5] [reps=20] [solver=hybrid|bordered|dense]
//       [only: runs whose "geometry draw" name contains it] [tolerance=1e-10]
//   BF_SWEEP=N: instead, N random linear laws (seeded; sigma_c 0.03-10 MPa,
//   J_B 1-5000 J/m^2, J_tip_c 300-3000 J/m^2, log-uniform) on each geometry,
//   one run each: the spread a fit's searches visit, failures included.
// Cases: the CT of tests/data/scenes/ct_mdf.toml grown to 85 mm with linear
// softening (the issue-7 truths and a fit's spread of sigma_c and J_B), the
// cubic, triangular and exponential shapes, no bridging; and the DCB of
// data_samples/dcb_composite/scene.toml with linear softening.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/models/reduced.hpp"

using namespace bridgefit;

namespace {
struct Draw {
  const char* name;
  laws::LawShape shape;
  double sigma_c, J_B, J_tip_c;  // J_B = 0: no bridging
};
}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(
        stderr,
        "usage: bf_reduced_forward_bench OUT [resolution_mm] [reps] [solver] [only] [tolerance]\n");
    return 2;
  }
  const double h = (argc > 2 ? std::atof(argv[2]) : 0.5) * 1e-3;
  const int reps = argc > 3 ? std::atoi(argv[3]) : 20;
  const std::string solver_name = argc > 4 ? argv[4] : "hybrid";
  const std::string only = argc > 5 ? argv[5] : "";
  models::ReducedOptions options;
  if (argc > 6) options.tolerance = std::atof(argv[6]);
  options.solver = solver_name == "dense"      ? models::ReducedOptions::Solver::kDense
                   : solver_name == "bordered" ? models::ReducedOptions::Solver::kBordered
                                               : models::ReducedOptions::Solver::kHybrid;
  const std::string root = BRIDGEFIT_SOURCE_DIR;
  std::FILE* out = std::fopen(argv[1], "w");
  if (!out) return 1;

  const laws::LawShape linear = laws::MakeLinearShape();
  const std::vector<Draw> ct_draws = {
      {"linear_1MPa", linear, 1.0e6, 500.0, 2210.0},
      {"linear_0.45MPa", linear, 0.45e6, 500.0, 2210.0},
      {"linear_0.2MPa", linear, 0.2e6, 800.0, 2000.0},
      {"linear_3MPa", linear, 3.0e6, 300.0, 2400.0},
      {"linear_0.05MPa", linear, 0.05e6, 50.0, 1450.0},
      {"cubic", laws::MakeCubicShape(), 0.6e6, 500.0, 2210.0},
      {"triangular", laws::MakeTriangularShape(0.2), 0.6e6, 500.0, 2210.0},
      {"exponential", laws::MakeExponentialShape(5.0), 0.6e6, 500.0, 2210.0},
      {"none", linear, 0.45e6, 0.0, 1450.0}};
  struct Geometry {
    const char* name;
    std::string scene;
    double a_max;
    std::vector<Draw> draws;
  };
  const std::vector<Geometry> geometries = {
      {"ct", root + "/tests/data/scenes/ct_mdf.toml", 0.085, ct_draws},
      {"dcb",
       root + "/data_samples/dcb_composite/scene.toml",
       0.0,
       {{"linear", linear, 0.9e6, 607.0, 359.0},
        {"cubic", laws::MakeCubicShape(), 2.0e6, 300.0, 400.0}}}};
  double total_best = 0.0;
  for (const Geometry& geometry : geometries) {
    const Scene scene = io::ReadSceneFile(geometry.scene);
    specimen::CrackPlaneOptions mesh;
    mesh.resolution = h;
    mesh.max_crack_length = geometry.a_max;  // 0: the scene's default
    const models::ReducedModel model(scene, mesh);
    std::vector<Draw> draws = geometry.draws;
    if (const char* sweep = std::getenv("BF_SWEEP")) {
      draws.clear();
      std::mt19937 rng(7);
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      auto log_uniform = [&](double lo, double hi) { return lo * std::pow(hi / lo, unit(rng)); };
      static std::vector<std::string> names;
      names.resize(std::atoi(sweep));
      for (std::string& name : names) {
        const double sigma_c = log_uniform(0.03e6, 10e6), J_B = log_uniform(1.0, 5000.0);
        const double J_tip_c = log_uniform(300.0, 3000.0);
        name = fmt::format("sweep_{:.4g}_{:.4g}_{:.4g}", sigma_c * 1e-6, J_B, J_tip_c);
        draws.push_back({name.c_str(), linear, sigma_c, J_B, J_tip_c});
      }
    }
    for (const Draw& d : draws) {
      if ((std::string(geometry.name) + " " + d.name).find(only) == std::string::npos) continue;
      const laws::BridgingLaw law{&d.shape, d.sigma_c, d.J_B / (d.shape.Area() * d.sigma_c)};
      const laws::BridgingLaw* law_ptr = d.J_B > 0.0 ? &law : nullptr;
      std::vector<double> seconds;
      SimulationResult result;
      for (int i = 0; i < reps; ++i) {
        const auto start = std::chrono::steady_clock::now();
        result = model.Run(law_ptr, d.J_tip_c, options);
        seconds.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
      std::sort(seconds.begin(), seconds.end());
      total_best += seconds.front();
      std::printf(
          "%s %-16s %4zu points  newton %6.0f  best %.3f ms  median %.3f ms  %s\n", geometry.name,
          d.name, result.points.size(),
          result.figures.count("newton_iterations") ? result.figures["newton_iterations"] : 0.0,
          seconds.front() * 1e3, seconds[seconds.size() / 2] * 1e3, RunStatusName(result.status));
      std::fprintf(out, "# %s %s status %s steady %d %.17g\n", geometry.name, d.name,
                   RunStatusName(result.status), result.steady_state_reached ? 1 : 0,
                   result.steady_state_crack_length);
      for (const SimulationPoint& p : result.points)
        std::fprintf(out, "%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                     p.crack_length, p.R, p.R_energy, p.J_tip, p.J_ff, p.delta_root,
                     p.root_position, p.bridging_zone_length, p.load, p.displacement, p.cmod);
    }
  }
  std::printf("sum of best run times: %.3f ms\n", total_best * 1e3);
  std::fclose(out);
  return 0;
}
