// Every optimizer on the three fit cases of issue 7 with the reduced model:
// evaluations, wall time and final error. Writes PREFIX.csv and, with
// gnuplot, PREFIX.png (time against error).
//   bf_inverse_bench docs/fit_bench [resolution_mm=0.5]
#include <cmath>
#include <ctime>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <string>

#include <fmt/format.h>

#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/models/reduced.hpp"

using namespace bridgefit;
using namespace bridgefit::inverse;

namespace {

struct Case {
  const char* name;
  LawParameters truth;
  double a_max;
};

FitData MakeData(const ForwardModel& model, const LawParameters& truth, double a_max, unsigned seed) {
  FitData data;
  for (double a = 0.031; a <= a_max + 1e-9; a += 0.001) data.crack_length.push_back(a);
  const ForwardPrediction p =
      model.Predict(laws::MakeLinearShape(), truth, data.crack_length, RKind::kEnergy);
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (double r : p.R) {
    data.R.push_back(r * (1.0 + 0.01 * gauss(rng)));
    data.R_uncertainty.push_back(0.01 * r);
  }
  return data;
}

// Largest relative error over the parameters that the case can identify.
double Error(const FitSummary& s, const Case& c) {
  double error = std::abs(s.J_tip_c.value - c.truth.J_tip_c) / c.truth.J_tip_c;
  if (c.truth.J_B == 0.0) return s.bridging_detected ? INFINITY : error;
  if (!s.bridging_detected) return INFINITY;
  error = std::max(error, std::abs(s.sigma_c.value - c.truth.sigma_c) / c.truth.sigma_c);
  if (std::isfinite(s.J_B.value))
    error = std::max(error, std::abs(s.J_B.value - c.truth.J_B) / c.truth.J_B);
  else if (!(s.J_B.lower_bound < c.truth.J_B))
    return INFINITY;  // a bound above the truth is wrong
  return error;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string prefix = argc > 1 ? argv[1] : "fit_bench";
  const double resolution = (argc > 2 ? std::atof(argv[2]) : 0.5) * 1e-3;
  const Scene scene = io::ReadSceneFile(std::string(BRIDGEFIT_SOURCE_DIR) +
                                        "/tests/data/scenes/ct_mdf.toml");
  models::ReducedOptions options;
  options.mesh.resolution = resolution;
  options.mesh.max_crack_length = 0.086;
  const auto forward = MakeReducedForwardModel(scene, options);
  const SimulationForwardModel& model = *forward;

  const Case cases[] = {{"recovery_1MPa", {1.0e6, 500.0, 2210.0}, 0.085},
                        {"truncated_0.45MPa", {0.45e6, 500.0, 2210.0}, 0.070},
                        {"flat_pb", {0.45e6, 0.0, 1450.0}, 0.070}};
  std::ofstream csv(prefix + ".csv");
  std::map<std::string, std::string> plot_rows;  // optimizer -> "cpu error" lines (no profile)
  csv << "case, optimizer, profile, evaluations, failed, wall [s], cpu [s], max relative error, "
         "converged, verdict\n";
  std::printf("%-18s %-11s %-7s %6s %6s %8s %8s %9s\n", "case", "optimizer", "profile", "evals",
              "failed", "wall_s", "cpu_s", "error");
  for (const Case& c : cases) {
    const FitData data = MakeData(model, c.truth, c.a_max, 1);
    for (Optimizer o : {Optimizer::kCeresLm, Optimizer::kBobyqa, Optimizer::kNelderMead,
                        Optimizer::kCobyla, Optimizer::kDirect, Optimizer::kCrs2}) {
      for (bool profile : {false, true}) {
        if (profile && o != Optimizer::kCeresLm && o != Optimizer::kBobyqa) continue;
        FitOptions fo;
        fo.optimizer = o;
        fo.profile_likelihood = profile;
        const std::clock_t cpu0 = std::clock();
        const FitSummary s = FitBridgingLaw(model, laws::MakeLinearShape(), data, fo);
        const double cpu_s = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
        const double error = Error(s, c);
        std::printf("%-18s %-11s %-7s %6d %6d %8.3f %8.3f %9.4f\n", c.name, OptimizerName(o),
                    profile ? "yes" : "no", s.evaluations, s.failed_evaluations, s.wall_s, cpu_s,
                    error);
        std::fflush(stdout);
        if (!profile && std::isfinite(error))
          plot_rows[OptimizerName(o)] += fmt::format("{:.5f} {:.6f} {}\n", cpu_s,
                                                     std::max(error, 1e-5), c.name);
        csv << fmt::format("{}, {}, {}, {}, {}, {:.4f}, {:.4f}, {:.5f}, {}, \"{}\"\n", c.name,
                           OptimizerName(o), profile ? "yes" : "no", s.evaluations,
                           s.failed_evaluations, s.wall_s, cpu_s, error, s.converged ? 1 : 0,
                           s.verdict);
      }
    }
  }
  csv.close();
  // One block per optimizer (gnuplot 'index'), in a fixed order.
  const char* order[] = {"ceres-lm", "bobyqa", "neldermead", "cobyla", "direct", "crs2"};
  std::ofstream dat(prefix + "_plot.dat");
  for (const char* name : order) dat << "# " << name << "\n" << plot_rows[name] << "\n\n";
  dat.close();
  const std::string script = prefix + ".gp";
  std::ofstream gp(script);
  gp << "set terminal pngcairo size 900,600\nset output '" << prefix << ".png'\n"
     << "set logscale xy\nset xlabel 'CPU time per fit [s] (reduced model, no profile)'\n"
     << "set ylabel 'largest relative parameter error'\nset key outside right\nset grid\n"
     << "set title 'Optimizers on the three issue-7 cases (wrong verdicts not shown)'\n"
     << "plot for [i=0:5] '" << prefix << "_plot.dat' index i using 1:2 with points "
     << "pointsize 2 pointtype (i+4) title word('ceres-lm bobyqa neldermead cobyla direct crs2', i+1)\n";
  gp.close();
  if (std::system(("gnuplot '" + script + "' 2>/dev/null").c_str()) != 0)
    std::fprintf(stderr, "gnuplot failed; the CSV is written\n");
  return 0;
}
