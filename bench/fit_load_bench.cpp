// Speed against accuracy of the load-displacement fit (`fit --fit-to
// load-displacement`, docs/FIT.md) on the truncated MDF test of the samples
// ((0.45 MPa, 500, 2210) to a = 70 mm): records like `bridgefit synth` makes
// (20 loading rows, 400 growth rows, load noise 0.5% of the reading, seed =
// draw; draw 0 without noise: the fit's bias from the element size alone)
// from the reduced model at 0.0625 mm elements (the nearest to its continuum
// limit), fitted with the reduced model at several element sizes by the
// workflow `bridgefit fit RECORD --fit-to load-displacement` runs
// (pipeline::RunFit: the record's energy R curve, its fit as the start, then
// the load-displacement fit; the time per fit covers all of it).
//   bf_fit_load_bench OUT_PREFIX [draws=10] [sizes_mm=2,1,0.5]
// writes OUT_PREFIX.csv (one row per fit), OUT_PREFIX_summary.csv (one row
// per element size), OUT_PREFIX.gp and OUT_PREFIX.png (gnuplot, when found).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench_sizes.hpp"
#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/pipeline/fit.hpp"
#include "bridgefit/scene/reference.hpp"

using namespace bridgefit;
using namespace bridgefit::inverse;

namespace {

constexpr double kTruthSigmaC = 0.45e6;
constexpr double kLoadNoise = 0.005;

// The noise-free rows of the test (as `bridgefit synth`).
ExperimentRecord ExactRecord(const Scene& scene) {
  models::ReducedOptions options;
  options.mesh.resolution = 0.0625e-3;
  options.mesh.max_crack_length = 0.070;
  return RecordAlongPath(models::SimulateReduced(scene, options), 20, 400);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bf_fit_load_bench OUT_PREFIX [draws=10] [sizes_mm=2,1,0.5]\n");
    return 2;
  }
  const std::string prefix = argv[1];
  const int draws = argc > 2 ? std::atoi(argv[2]) : 10;
  const std::vector<double> sizes = ParseSizesMm(argc > 3 ? argv[3] : "2,1,0.5");
  Scene truth = ReferenceCtScene();
  AddLinearBridging(truth, kTruthSigmaC, 500.0);
  const ExperimentRecord exact = ExactRecord(truth);
  double peak = 0.0;
  for (double p : exact.load) peak = std::max(peak, p);

  std::string rows =
      "elements [mm], seed, sigma_c [Pa], sigma_c error [%], ci covers, J_B lower bound [J/m^2], "
      "evaluations, wall [s], cpu [s]\n";
  std::string summary =
      "elements [mm], draws, max abs error [%], mean error [%], sd [%], within 3%, within 5%, "
      "ci covers, mean wall [s], mean cpu [s], noise-free error [%]\n";
  for (double h : sizes) {
    pipeline::FitRequest request;
    request.scene = truth;
    request.scene.bridging.reset();
    request.target = FitTarget::kLoad;
    request.resolution = h;
    request.fit.starts = 2;
    request.reduction.load_noise = kLoadNoise * 0.6 * peak;  // [N], as declared to `fit`
    request.reduction.displacement_noise = 0.0;
    std::vector<double> errors;
    int covers = 0;
    double wall_sum = 0.0, cpu_sum = 0.0, noise_free = NAN;
    for (int seed = 0; seed <= draws; ++seed) {
      ExperimentRecord record = exact;
      std::mt19937 rng(seed);
      std::normal_distribution<double> gauss(0.0, 1.0);
      if (seed > 0)
        for (double& load : record.load) load *= 1.0 + kLoadNoise * gauss(rng);
      request.record = record;
      const auto wall0 = std::chrono::steady_clock::now();
      const std::clock_t cpu0 = std::clock();
      const FitSummary s = pipeline::RunFit(request).summary;
      const double cpu = double(std::clock() - cpu0) / CLOCKS_PER_SEC;
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
      const double error = 100.0 * (s.sigma_c.value / kTruthSigmaC - 1.0);
      const bool cover = s.sigma_c.ci95_low <= kTruthSigmaC && kTruthSigmaC <= s.sigma_c.ci95_high;
      if (seed == 0) {
        noise_free = error;
      } else {
        errors.push_back(error);
        covers += cover;
        wall_sum += wall;
        cpu_sum += cpu;
      }
      char line[256];
      std::snprintf(line, sizeof line, "%g, %d, %.6g, %+.3f, %s, %.4g, %d, %.3f, %.3f\n", h * 1e3,
                    seed, s.sigma_c.value, error, cover ? "yes" : "no", s.J_B.lower_bound,
                    s.evaluations, wall, cpu);
      rows += line;
      std::fputs(line, stdout);
    }
    double mean = 0.0, sd = 0.0, max_abs = 0.0;
    int within3 = 0, within5 = 0;
    for (double e : errors) {
      mean += e / errors.size();
      max_abs = std::max(max_abs, std::abs(e));
      within3 += std::abs(e) <= 3.0;
      within5 += std::abs(e) <= 5.0;
    }
    for (double e : errors) sd += (e - mean) * (e - mean) / std::max<std::size_t>(1, errors.size() - 1);
    char line[256];
    std::snprintf(line, sizeof line, "%g, %d, %.3f, %+.3f, %.3f, %d, %d, %d, %.3f, %.3f, %+.3f\n",
                  h * 1e3, draws, max_abs, mean, std::sqrt(sd), within3, within5, covers,
                  wall_sum / draws, cpu_sum / draws, noise_free);
    summary += line;
  }
  std::ofstream(prefix + ".csv") << rows;
  std::ofstream(prefix + "_summary.csv") << summary;
  std::fputs(summary.c_str(), stdout);
  // Chart: mean CPU time per fit against the largest |error| over the draws;
  // the script names its files relative to its own folder.
  const std::filesystem::path where = std::filesystem::path(prefix).parent_path();
  const std::string base = std::filesystem::path(prefix).filename().string();
  const std::string png = base + ".png";
  std::string gp = "set terminal pngcairo size 760,480 enhanced font 'Sans,11'\n";
  gp += "set output '" + png + "'\nset datafile separator ','\nset key bottom right\nset grid\n";
  gp += "set title 'Load-displacement fit, truncated MDF test: time against sigma_c error'\n";
  gp += "set xlabel 'CPU time per fit [s]'\nset ylabel 'sigma_c error over the draws [%]'\n";
  gp += "plot '" + base + "_summary.csv' skip 1 u 10:3:(sprintf('%g mm', $1)) w labels offset 0,1 notitle, "
        "'' skip 1 u 10:3 w lp pt 7 t 'largest |error| (noisy draws)', '' skip 1 u 10:5 w lp pt 5 t "
        "'SD (noisy draws)', '' skip 1 u 10:(abs($11)) w lp pt 9 t '|error| without noise'\n";
  std::ofstream(prefix + ".gp") << gp;
  const std::string dir = where.empty() ? std::string(".") : where.string();
  if (std::system(("cd '" + dir + "' && gnuplot '" + base + ".gp' 2>/dev/null").c_str()) != 0)
    std::fprintf(stderr, "gnuplot failed: %s.gp kept, no chart\n", prefix.c_str());
  return 0;
}
