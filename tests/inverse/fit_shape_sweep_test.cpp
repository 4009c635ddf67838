// The tabulated law's knots against the true law over laws (cubic,
// exponential, linear), noise levels and specimens (CT and DCB, the reduced
// model and the analytic model of each scene): a sweep, run by hand
// (--gtest_also_run_disabled_tests), that prints every knot's error as a
// fraction of sigma_c, the AICc of each family and the wall time.
// BRIDGEFIT_SWEEP_INTERPOLATION=linear compares with straight segments;
// BRIDGEFIT_SWEEP_MODELS=analytic skips the reduced model;
// BRIDGEFIT_SWEEP_NOISE=0.0001 (one level) measures the bias alone;
// BRIDGEFIT_SWEEP_LAWS=cubic keeps the laws whose names it contains;
// BRIDGEFIT_SWEEP_SMOOTHNESS=0 drops the table's roughness penalty.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bridgefit/inverse/fit_shape.hpp"
#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/models/reduced.hpp"

namespace bridgefit::inverse {
namespace {

// Truth by sigma_c and delta_c (J_B = k sigma_c delta_c, k the law's area),
// so that every law reaches steady state well inside the data's growth.
struct Specimen {
  std::string name;
  std::string scene;
  double a_max;    // [m]
  double sigma_c;  // [Pa]
  double delta_c;  // [m]
  double J_tip_c;  // [J/m^2]
};

FitData MakeData(const ForwardModel& model, const laws::LawShape& shape, const LawParameters& p,
                 double a0, double a_max, int n, double noise, unsigned seed) {
  FitData data;
  for (int i = 0; i < n; ++i)
    data.crack_length.push_back(a0 + (a_max - a0) * std::pow((i + 1.0) / n, 2));
  const ForwardPrediction r = model.Predict(shape, p, data.crack_length, RKind::kEnergy);
  EXPECT_TRUE(r.ok()) << r.message;
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (double v : r.R) {
    data.R.push_back(v * (1.0 + noise * gauss(rng)));
    data.R_uncertainty.push_back(noise * v);
  }
  return data;
}

void RunCase(const ForwardModel& model, const std::string& label, const laws::LawShape& truth_shape,
             const LawParameters& truth, double a0, double a_max, int n, double noise) {
  const FitData data = MakeData(model, truth_shape, truth, a0, a_max, n, noise, 31);
  const ForwardPrediction p = model.Predict(truth_shape, truth, {a_max}, RKind::kEnergy);
  FitOptions options;
  options.starts = 3;
  options.profile_likelihood = false;
  ShapeFitOptions shape_options;
  const char* interpolation = std::getenv("BRIDGEFIT_SWEEP_INTERPOLATION");
  if (interpolation && std::string(interpolation) == "linear")
    shape_options.table_interpolation = laws::TableInterpolation::kLinear;
  if (const char* smoothness = std::getenv("BRIDGEFIT_SWEEP_SMOOTHNESS"))
    shape_options.smoothness = std::atof(smoothness);
  const auto start = std::chrono::steady_clock::now();
  const auto c = CompareLawFamiliesWithShapes(model, {laws::MakeLinearShape(), truth_shape},
                                              {ShapeFamily::kTable}, data, options, shape_options);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("== %s, %d points, noise %.3g, J_B %.0f, steady state at %.1f mm, %.1f s\n",
              label.c_str(), n, noise, truth.J_B, p.steady_state_crack_length * 1e3, wall);
  for (const LawComparison& f : c)
    std::printf("   %-12s k %5.2f chi2 %9.2f AICc %9.2f\n", f.law.c_str(), f.parameters,
                f.summary.chi2, f.aicc);
  const LawComparison& t = c.back();
  if (!t.summary.converged) {
    std::printf("   table not converged: %s\n", t.note.c_str());
    std::fflush(stdout);
    return;
  }
  const double sigma_c = t.summary.best_parameters[kSigmaC];
  const double delta_c = t.summary.best_parameters[kJB] / (t.shape.Area() * sigma_c);
  const double true_delta_c = truth.J_B / (truth_shape.Area() * truth.sigma_c);
  std::printf("   table N = %zu, sigma_c %.4f MPa, knot errors [sigma_c]:",
              t.shape.d_points.size() - 1, sigma_c * 1e-6);
  double worst = 0.0;
  for (size_t k = 0; k + 1 < t.shape.d_points.size(); ++k) {
    const double delta = t.shape.d_points[k] * delta_c;
    const double error = (sigma_c * t.shape.s_points[k] -
                          truth.sigma_c * laws::ShapeValue(truth_shape, delta / true_delta_c)) /
                         truth.sigma_c;
    worst = std::max(worst, std::abs(error));
    std::printf(" %+.3f", error);
  }
  std::printf("  worst %.3f\n", worst);
  std::fflush(stdout);
}

TEST(FitShapeSweep, DISABLED_TableKnotsOverLawsNoiseAndSpecimens) {
  const std::string dir = std::string(BRIDGEFIT_TEST_DATA_DIR) + "/scenes/";
  const Specimen specimens[] = {
      {"CT", dir + "ct_mdf.toml", 0.080, 2.0e6, 0.4e-3, 2210.0},
      {"DCB", dir + "dcb_composite.toml", 0.110, 5.0e6, 0.15e-3, 350.0},
  };
  const char* models_env = std::getenv("BRIDGEFIT_SWEEP_MODELS");
  const std::string models = models_env ? models_env : "analytic,reduced";
  const laws::LawShape laws_[] = {laws::MakeCubicShape(), laws::MakeExponentialShape(3.0),
                                  laws::MakeLinearShape()};
  const char* noise_env = std::getenv("BRIDGEFIT_SWEEP_NOISE");
  const std::vector<double> noises =
      noise_env ? std::vector<double>{std::atof(noise_env)} : std::vector<double>{0.005, 0.02};
  const char* laws_env = std::getenv("BRIDGEFIT_SWEEP_LAWS");
  for (const Specimen& s : specimens) {
    const Scene scene = io::ReadSceneFile(s.scene);
    const double a0 = scene.specimen.notch;
    std::vector<std::pair<std::string, std::unique_ptr<ForwardModel>>> fits;
    if (models.find("analytic") != std::string::npos)
      fits.emplace_back("analytic", MakeAnalyticForwardModel(scene));
    if (models.find("reduced") != std::string::npos) {
      models::ReducedOptions options;
      options.mesh.resolution = 1e-3;
      options.mesh.max_crack_length = s.a_max + 0.002;
      fits.emplace_back("reduced", MakeReducedForwardModel(scene, options));
    }
    for (const auto& [model_name, model] : fits)
      for (const laws::LawShape& law : laws_) {
        const std::string name(laws::LawFamilyName(law.family));
        if (laws_env && std::string(laws_env).find(name) == std::string::npos) continue;
        for (double noise : noises) {
          const LawParameters truth{s.sigma_c, law.Area() * s.sigma_c * s.delta_c, s.J_tip_c};
          RunCase(*model,
                  s.name + " " + model_name + " " + std::string(laws::LawFamilyName(law.family)),
                  law, truth, a0, s.a_max, model_name == "analytic" ? 400 : 100, noise);
        }
      }
  }
}

}  // namespace
}  // namespace bridgefit::inverse
