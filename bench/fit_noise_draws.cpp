// Is the fit's sigma_c biased on the truncated MDF case of issue 7
// ((0.45 MPa, 500, 2210) to a = 70 mm, CT of tests/data/scenes/ct_mdf.toml)?
// Fits many 1% noise draws made exactly as tests/inverse/reduced_fit_test.cpp
// makes its data (R_energy of the same reduced model, 1 mm steps from 31 mm,
// R (1 + 0.01 g), seed = draw) and reports the mean and spread of the error.
//   bf_fit_noise_bench [resolution_mm=1] [draws=100] [first_seed=1] [profile=0]
//                      [out.csv] [starts=3]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/models/reduced.hpp"

using namespace bridgefit;
using namespace bridgefit::inverse;

int main(int argc, char** argv) {
  const double resolution = (argc > 1 ? std::atof(argv[1]) : 1.0) * 1e-3;
  const int draws = argc > 2 ? std::atoi(argv[2]) : 100;
  const int first_seed = argc > 3 ? std::atoi(argv[3]) : 1;
  const bool profile = argc > 4 && std::atoi(argv[4]) != 0;
  const std::string csv_path = argc > 5 ? argv[5] : "";
  const int starts = argc > 6 ? std::atoi(argv[6]) : 3;
  const Scene scene =
      io::ReadSceneFile(std::string(BRIDGEFIT_SOURCE_DIR) + "/tests/data/scenes/ct_mdf.toml");
  models::ReducedOptions options;
  options.mesh.resolution = resolution;
  options.mesh.max_crack_length = 0.086;
  const auto forward = MakeReducedForwardModel(scene, options);
  const SimulationForwardModel& model = *forward;
  const LawParameters truth{0.45e6, 500.0, 2210.0};
  const laws::LawShape shape = laws::MakeLinearShape();
  FitData clean;
  for (double a = 0.031; a <= 0.070 + 1e-9; a += 0.001) clean.crack_length.push_back(a);
  const ForwardPrediction p = model.Predict(shape, truth, clean.crack_length, RKind::kEnergy);
  if (!p.ok()) {
    std::fprintf(stderr, "forward model failed: %s\n", p.message.c_str());
    return 1;
  }
  FitOptions fo;  // as the test: BOBYQA (default), 3 starts (the optimizer bench: 4)
  fo.starts = starts;
  fo.profile_likelihood = profile;

  std::string csv =
      "seed, sigma_c [Pa], sigma_c error [%], J_tip_c error [%], J_B lower bound [J/m^2], "
      "steady state, bridging, sigma_c ci95 low [Pa], sigma_c ci95 high [Pa], evaluations, cpu "
      "[s]\n";
  std::vector<double> errors;
  int covered = 0, with_ci = 0, within3 = 0, wrong_verdict = 0;
  // seed 0: the noise-free curve (the estimator's bias without noise).
  for (int seed = first_seed - 1; seed < first_seed + draws; ++seed) {
    const bool noise_free = seed == first_seed - 1;
    FitData data = clean;
    data.R.clear();
    std::mt19937 rng(static_cast<unsigned>(seed));
    std::normal_distribution<double> gauss(0.0, 1.0);
    for (double r : p.R) {
      data.R.push_back(noise_free ? r : r * (1.0 + 0.01 * gauss(rng)));
      data.R_uncertainty.push_back(0.01 * r);
    }
    const std::clock_t cpu0 = std::clock();
    const FitSummary s = FitBridgingLaw(model, shape, data, fo);
    const double cpu_s = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
    const double error = 100.0 * (s.sigma_c.value / truth.sigma_c - 1.0);
    char line[512];
    std::snprintf(line, sizeof line, "%s, %.1f, %.3f, %.3f, %.1f, %d, %d, %.1f, %.1f, %d, %.2f\n",
                  noise_free ? "none" : std::to_string(seed).c_str(), s.sigma_c.value, error,
                  100.0 * (s.J_tip_c.value / truth.J_tip_c - 1.0), s.J_B.lower_bound,
                  s.steady_state_reached ? 1 : 0, s.bridging_detected ? 1 : 0, s.sigma_c.ci95_low,
                  s.sigma_c.ci95_high, s.evaluations, cpu_s);
    csv += line;
    std::printf("%s", line);
    std::fflush(stdout);
    if (noise_free) continue;
    if (s.steady_state_reached || !s.bridging_detected || !std::isfinite(error)) {
      ++wrong_verdict;
      continue;
    }
    errors.push_back(error);
    if (std::abs(error) <= 3.0) ++within3;
    if (std::isfinite(s.sigma_c.ci95_low) && std::isfinite(s.sigma_c.ci95_high)) {
      ++with_ci;
      if (s.sigma_c.ci95_low <= truth.sigma_c && truth.sigma_c <= s.sigma_c.ci95_high) ++covered;
    }
  }
  const double n = static_cast<double>(errors.size());
  double mean = 0, var = 0;
  for (double e : errors) mean += e / n;
  for (double e : errors) var += (e - mean) * (e - mean) / (n - 1);
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted.empty() ? NAN : sorted[sorted.size() / 2];
  std::printf(
      "# resolution %.2f mm, %d draws (seeds %d..%d), profile %d: sigma_c error mean %+.2f %% "
      "(standard error %.2f), SD %.2f %%, median %+.2f %%, min %+.2f, max %+.2f; |error| <= 3 %%: "
      "%d of %zu; wrong verdicts %d; CI covers the truth: %d of %d\n",
      resolution * 1e3, draws, first_seed, first_seed + draws - 1, profile ? 1 : 0, mean,
      std::sqrt(var / n), std::sqrt(var), median, sorted.empty() ? NAN : sorted.front(),
      sorted.empty() ? NAN : sorted.back(), within3, errors.size(), wrong_verdict, covered,
      with_ci);
  if (!csv_path.empty()) std::ofstream(csv_path) << csv;
  return 0;
}
