// Issue 7 acceptance with the reduced model: recovery past steady state,
// lower bounds for a truncated curve, and "no bridging" for a flat curve.
// Data: R_energy of the reduced model itself (1 mm elements) with 1% noise.
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/models/reduced.hpp"

namespace bridgefit::inverse {
namespace {

const std::string kScene = std::string(BRIDGEFIT_TEST_DATA_DIR) + "/scenes/ct_mdf.toml";

struct Fixture {
  std::unique_ptr<SimulationForwardModel> forward;
};

// The CT scene of the reduced-model issue, grown to 86 mm.
Fixture& Ct() {
  static Fixture f = [] {
    models::ReducedOptions options;
    options.mesh.resolution = 1e-3;
    options.mesh.max_crack_length = 0.086;
    return Fixture{MakeReducedForwardModel(io::ReadSceneFile(kScene), options)};
  }();
  return f;
}

FitData Data(const LawParameters& truth, double a_max, unsigned seed) {
  const laws::LawShape shape = laws::MakeLinearShape();
  FitData data;
  for (double a = 0.031; a <= a_max + 1e-9; a += 0.001) data.crack_length.push_back(a);
  const ForwardPrediction p = Ct().forward->Predict(shape, truth, data.crack_length, RKind::kEnergy);
  EXPECT_TRUE(p.ok()) << p.message;
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (double r : p.R) {
    data.R.push_back(r * (1.0 + 0.01 * gauss(rng)));
    data.R_uncertainty.push_back(0.01 * r);
  }
  return data;
}

FitOptions Options() {
  FitOptions o;
  o.starts = 3;
  return o;
}

TEST(ReducedFit, RecoversAllThreePastSteadyState) {
  const LawParameters truth{1.0e6, 500.0, 2210.0};  // steady state near a = 71 mm
  const FitData data = Data(truth, 0.085, 1);
  const FitSummary s = FitBridgingLaw(*Ct().forward, laws::MakeLinearShape(), data, Options());
  std::cout << s.BriefReport();
  EXPECT_TRUE(s.converged) << s.stop_reason;
  EXPECT_TRUE(s.steady_state_reached) << s.verdict;
  EXPECT_NEAR(s.sigma_c.value, truth.sigma_c, 0.02 * truth.sigma_c);
  EXPECT_NEAR(s.J_B.value, truth.J_B, 0.02 * truth.J_B);
  EXPECT_NEAR(s.J_tip_c.value, truth.J_tip_c, 0.02 * truth.J_tip_c);
  EXPECT_LE(s.sigma_c.ci95_low, truth.sigma_c);
  EXPECT_GE(s.sigma_c.ci95_high, truth.sigma_c);
  EXPECT_LE(s.J_B.ci95_low, truth.J_B);
  EXPECT_GE(s.J_B.ci95_high, truth.J_B);
  EXPECT_LE(s.J_tip_c.ci95_low, truth.J_tip_c);
  EXPECT_GE(s.J_tip_c.ci95_high, truth.J_tip_c);
}

TEST(ReducedFit, TruncatedAt70mmGivesLowerBounds) {
  const LawParameters truth{0.45e6, 500.0, 2210.0};
  const FitData data = Data(truth, 0.070, 2);
  const FitSummary s = FitBridgingLaw(*Ct().forward, laws::MakeLinearShape(), data, Options());
  std::cout << s.BriefReport();
  EXPECT_FALSE(s.steady_state_reached) << s.verdict;
  EXPECT_NEAR(s.sigma_c.value, truth.sigma_c, 0.03 * truth.sigma_c);
  EXPECT_FALSE(s.J_B.identified);
  EXPECT_FALSE(s.delta_c.identified);
  EXPECT_TRUE(std::isnan(s.J_B.value));
  EXPECT_GT(s.J_B.lower_bound, 0.0);
  EXPECT_LT(s.J_B.lower_bound, truth.J_B);
  EXPECT_GT(s.delta_c.lower_bound, 0.0);
  EXPECT_LT(s.delta_c.lower_bound, 2.0 * truth.J_B / truth.sigma_c);
}

TEST(ReducedFit, FlatCurveMeansNoBridging) {
  const LawParameters truth{0.45e6, 0.0, 1450.0};
  const FitData data = Data(truth, 0.070, 3);
  const FitSummary s = FitBridgingLaw(*Ct().forward, laws::MakeLinearShape(), data, Options());
  std::cout << s.BriefReport();
  EXPECT_FALSE(s.bridging_detected) << s.verdict;
  EXPECT_NEAR(s.J_tip_c.value, 1450.0, 0.02 * 1450.0);
}

}  // namespace
}  // namespace bridgefit::inverse
