// Fitting the load-displacement record itself (FitTarget::kLoad): a noisy
// record of the MDF sample's test (truncated at a = 70 mm, before steady
// state) made by the reduced model at 0.125 mm elements, fitted with the
// model at 1 mm, so the fit does not see its own discretisation in the data.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/scene/reference.hpp"

namespace bridgefit::inverse {
namespace {

constexpr double kRelativeLoadNoise = 0.005;  // the sample's: 0.5% of the reading

// A test record like `bridgefit synth`: 20 rows of linear loading, then 400
// rows evenly spaced along the simulated growth path, load noise 0.5% of the
// reading (Gaussian, seeded).
ExperimentRecord Record(const Scene& scene, double resolution, unsigned seed) {
  models::ReducedOptions options;
  options.mesh.resolution = resolution;
  options.mesh.max_crack_length = 0.070;
  const SimulationResult sim = models::SimulateReduced(scene, options);
  EXPECT_EQ(sim.status, RunStatus::kOk) << sim.message;
  ExperimentRecord record = RecordAlongPath(sim, 20, 400);
  record.source = "load_fit_test";
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (double& load : record.load) load *= 1.0 + kRelativeLoadNoise * gauss(rng);
  return record;
}

std::unique_ptr<SimulationForwardModel> FitModel(const Scene& scene, double resolution = 1e-3) {
  models::ReducedOptions options;
  options.mesh.resolution = resolution;
  options.mesh.max_crack_length = 0.075;
  return MakeReducedForwardModel(scene, options);
}

// Row uncertainties: the record's noise, 0.5% of a typical load.
FitData LoadData(const ExperimentRecord& record) {
  double peak = 0.0;
  for (double p : record.load) peak = std::max(peak, p);
  return FitData::FromRecord(record, kRelativeLoadNoise * 0.6 * peak, 0.0);
}

TEST(LoadFit, TruncatedMdfRecordGivesSigmaCAndLowerBounds) {
  Scene truth = ReferenceCtScene();
  AddLinearBridging(truth, 0.45e6, 500.0);
  const ExperimentRecord record = Record(truth, 0.125e-3, 1);
  Scene fit_scene = truth;
  fit_scene.bridging.reset();
  const auto model = FitModel(fit_scene);
  FitOptions options;
  options.starts = 2;
  // A start an R-curve fit could give: J_tip,c and J_B off by 10-40%.
  options.initial = {NAN, 300.0, 2000.0};
  const FitSummary s = FitBridgingLaw(*model, laws::MakeLinearShape(), LoadData(record), options);
  std::cout << s.BriefReport();
  EXPECT_TRUE(s.converged) << s.stop_reason;
  EXPECT_TRUE(s.bridging_detected);
  EXPECT_FALSE(s.steady_state_reached);
  EXPECT_NEAR(s.sigma_c.value, 0.45e6, 0.05 * 0.45e6);
  EXPECT_LE(s.sigma_c.ci95_low, 0.45e6);
  EXPECT_GE(s.sigma_c.ci95_high, 0.45e6);
  EXPECT_NEAR(s.J_tip_c.value, 2210.0, 0.02 * 2210.0);
  // PHYSICS 7: bounds, never point values, and below the truth.
  EXPECT_FALSE(s.J_B.identified);
  EXPECT_FALSE(s.delta_c.identified);
  EXPECT_LT(s.J_B.lower_bound, 500.0);
  EXPECT_GT(s.J_B.lower_bound, 100.0);
  EXPECT_LT(s.delta_c.lower_bound, 2 * 500.0 / 0.45e6);
  // The fitted load follows the record to its noise (0.5% of ~1000 N).
  EXPECT_LT(s.rms_residual, 10.0);
  ASSERT_EQ(s.fitted_load.size(), s.fitted_displacement.size());
  EXPECT_GT(s.fitted_crack_length.back(), 0.069);
}

// At 1 and 2 mm elements (at 2 mm the fit finds a weak, long zone that adds
// 0.5% to R by the end: below the models' R accuracy, so no bridging).
TEST(LoadFit, FlatRecordHasNoBridging) {
  Scene truth = ReferenceCtScene();
  truth.fracture->J_tip_c = 1450.0;
  const ExperimentRecord record = Record(truth, 0.125e-3, 2);
  for (double resolution : {1e-3, 2e-3}) {
    const auto model = FitModel(truth, resolution);
    FitOptions options;
    options.starts = 2;
    options.initial = {NAN, 0.05 * 1400.0, 1400.0};
    const FitSummary s = FitBridgingLaw(*model, laws::MakeLinearShape(), LoadData(record), options);
    std::cout << s.BriefReport();
    EXPECT_TRUE(s.converged) << s.stop_reason;
    EXPECT_FALSE(s.bridging_detected) << resolution << ": " << s.verdict;
    EXPECT_NEAR(s.J_tip_c.value, 1450.0, 0.02 * 1450.0);
  }
}

TEST(LoadFit, ModelWithoutARecordIsAReportedFailure) {
  ExperimentRecord record;
  for (int i = 1; i <= 10; ++i) {
    record.displacement.push_back(1e-4 * i);
    record.load.push_back(100.0 * i);
  }
  const AnalyticForwardModel analytic(3e9, 0.03);
  FitOptions options;
  options.starts = 1;
  options.initial = {1e6, 500.0, 2000.0};
  FitSummary s;
  ASSERT_NO_THROW(s = FitBridgingLaw(analytic, laws::MakeLinearShape(),
                                     FitData::FromRecord(record, 1.0, 0.0), options));
  EXPECT_FALSE(s.converged);
  EXPECT_NE(s.stop_reason.find("no load-displacement record"), std::string::npos) << s.stop_reason;
}

// u^2 = u_P^2 + (dP/dd u_d)^2 with the record's slope; rows at d <= 0 dropped.
TEST(LoadFit, RowUncertaintyCombinesLoadAndDisplacementNoise) {
  ExperimentRecord record;
  const double stiffness = 2e6;  // [N/m]
  for (int i = 0; i <= 20; ++i) {
    record.displacement.push_back(1e-5 * i);
    record.load.push_back(stiffness * 1e-5 * i);
  }
  const FitData data = FitData::FromRecord(record, 3.0, 1e-6);
  ASSERT_EQ(data.size(), 20u);
  EXPECT_EQ(data.target, FitTarget::kLoad);
  for (double u : data.load_uncertainty) EXPECT_NEAR(u, std::hypot(3.0, 2.0), 1e-9);
  EXPECT_TRUE(FitData::FromRecord(record, 0.0, 0.0).load_uncertainty.empty());
}

// A law that reaches steady state within a few model steps is not resolved:
// the load prediction says so instead of fitting the model's own error.
TEST(LoadFit, ShortBridgingZoneIsNotResolved) {
  const Scene scene = ReferenceCtScene();
  const auto model = FitModel(scene);
  const std::vector<double> displacements{0.5e-3, 0.9e-3};
  const LawParameters short_zone{20e6, 300.0, 1200.0};  // delta_c = 30 um
  const ForwardPrediction p = model->PredictLoad(laws::MakeLinearShape(), short_zone, displacements);
  EXPECT_FALSE(p.ok());
  EXPECT_NE(p.message.find("not resolved"), std::string::npos) << p.message;
  const ForwardPrediction ok =
      model->PredictLoad(laws::MakeLinearShape(), {0.45e6, 500.0, 2210.0}, displacements);
  ASSERT_TRUE(ok.ok()) << ok.message;
  EXPECT_EQ(ok.load.size(), 2u);
  EXPECT_DOUBLE_EQ(ok.crack_length_physical[0], 0.030);  // on the linear branch
}

}  // namespace
}  // namespace bridgefit::inverse
