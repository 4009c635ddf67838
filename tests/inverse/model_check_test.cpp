// --model auto: fit with a cheap model, check with an accurate one, correct by
// output space mapping. Oracles: identical models (accepted, no correction);
// a cheap model with a known smooth bias (the corrected fit must land where a
// fit with the accurate model itself lands); a failing accurate model.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "bridgefit/inverse/model_check.hpp"
#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/models/reduced.hpp"

namespace bridgefit::inverse {
namespace {

const std::string kScene = std::string(BRIDGEFIT_TEST_DATA_DIR) + "/scenes/ct_mdf.toml";

std::shared_ptr<SimulationForwardModel> Reduced() {
  static std::shared_ptr<SimulationForwardModel> forward = [] {
    models::ReducedOptions options;
    options.mesh.resolution = 1e-3;
    options.mesh.max_crack_length = 0.086;
    return std::shared_ptr<SimulationForwardModel>(
        MakeReducedForwardModel(io::ReadSceneFile(kScene), options));
  }();
  return forward;
}

// The reduced model with R scaled by 1 + bias (a - 30 mm)/40 mm: a cheap
// model that is wrong by a smooth, known amount.
class Biased final : public ForwardModel {
 public:
  Biased(const ForwardModel& base, double bias) : base_(base), bias_(bias) {}
  std::string Name() const override { return "biased"; }
  ForwardPrediction Predict(const laws::LawShape& shape, const LawParameters& p,
                            const std::vector<double>& a, RKind kind) const override {
    ForwardPrediction out = base_.Predict(shape, p, a, kind);
    for (std::size_t i = 0; i < out.R.size(); ++i) out.R[i] *= 1.0 + bias_ * (a[i] - 0.030) / 0.040;
    return out;
  }

 private:
  const ForwardModel& base_;
  double bias_;
};

class Failing final : public ForwardModel {
 public:
  std::string Name() const override { return "failing"; }
  ForwardPrediction Predict(const laws::LawShape&, const LawParameters&,
                            const std::vector<double>&, RKind) const override {
    ForwardPrediction out;
    out.status = RunStatus::kFailed;
    out.message = "always fails";
    return out;
  }
};

FitData Data(const ForwardModel& model, const LawParameters& truth) {
  FitData data;
  for (double a = 0.031; a <= 0.085 + 1e-9; a += 0.002) data.crack_length.push_back(a);
  const ForwardPrediction p =
      model.Predict(laws::MakeLinearShape(), truth, data.crack_length, RKind::kEnergy);
  EXPECT_TRUE(p.ok()) << p.message;
  data.R = p.R;
  for (double r : p.R) data.R_uncertainty.push_back(0.01 * r);
  return data;
}

FitOptions Options() {
  FitOptions o;
  o.starts = 2;
  o.profile_likelihood = false;
  return o;
}

const LawParameters kTruth{1.0e6, 500.0, 2210.0};

TEST(ModelCheck, IdenticalModelsAreAcceptedWithoutCorrection) {
  const FitData data = Data(*Reduced(), kTruth);
  ModelCheckResult r;
  const FitSummary s = FitWithModelCheck(*Reduced(), *Reduced(), laws::MakeLinearShape(), data,
                                         Options(), ModelCheckOptions{}, &r);
  std::printf("%s\n", r.outcome.c_str());
  EXPECT_FALSE(r.corrected);
  EXPECT_TRUE(r.accurate_ok);
  EXPECT_EQ(r.accurate_runs, 1);
  EXPECT_LT(r.discrepancy_at_cheap_optimum, 1e-12);
  EXPECT_NE(s.sigma_c.decided_by.find("checked by reduced"), std::string::npos)
      << s.sigma_c.decided_by;
}

TEST(ModelCheck, SpaceMappingMovesABiasedCheapFitOntoTheAccurateModelsOptimum) {
  const Biased cheap(*Reduced(), 0.06);  // up to 6% high at the end of the data
  const FitData data = Data(*Reduced(), kTruth);
  const FitSummary direct_cheap = FitBridgingLaw(cheap, laws::MakeLinearShape(), data, Options());
  const FitSummary direct_accurate =
      FitBridgingLaw(*Reduced(), laws::MakeLinearShape(), data, Options());
  ModelCheckResult r;
  const FitSummary s = FitWithModelCheck(cheap, *Reduced(), laws::MakeLinearShape(), data,
                                         Options(), ModelCheckOptions{}, &r);
  std::printf("%s\ncheap fit: sigma_c %.4g J_B %.4g J_tip_c %.4g; corrected: %.4g %.4g %.4g; "
              "accurate fit: %.4g %.4g %.4g\n",
              r.outcome.c_str(), direct_cheap.best_parameters[0], direct_cheap.best_parameters[1],
              direct_cheap.best_parameters[2], s.best_parameters[0], s.best_parameters[1],
              s.best_parameters[2], direct_accurate.best_parameters[0],
              direct_accurate.best_parameters[1], direct_accurate.best_parameters[2]);
  EXPECT_TRUE(r.corrected);
  EXPECT_GT(r.discrepancy_at_cheap_optimum, 0.03);
  EXPECT_LE(r.accurate_runs, 1 + ModelCheckOptions{}.max_corrections);
  // The biased model alone misses the truth by more than the corrected fit.
  double cheap_error = 0.0;
  for (int i = 0; i < kParameterCount; ++i) {
    const double truth = i == 0 ? kTruth.sigma_c : i == 1 ? kTruth.J_B : kTruth.J_tip_c;
    EXPECT_NEAR(s.best_parameters[i] / direct_accurate.best_parameters[i], 1.0, 0.01)
        << ParameterName(i);
    cheap_error = std::max(cheap_error, std::abs(direct_cheap.best_parameters[i] / truth - 1.0));
  }
  EXPECT_GT(cheap_error, 0.03);
  EXPECT_NE(s.sigma_c.decided_by.find("corrected to reduced"), std::string::npos)
      << s.sigma_c.decided_by;
}

TEST(ModelCheck, AFailingAccurateModelLeavesTheCheapFitWithTheReason) {
  const FitData data = Data(*Reduced(), kTruth);
  ModelCheckResult r;
  const FitSummary s = FitWithModelCheck(*Reduced(), Failing(), laws::MakeLinearShape(), data,
                                         Options(), ModelCheckOptions{}, &r);
  EXPECT_FALSE(r.accurate_ok);
  EXPECT_FALSE(r.corrected);
  EXPECT_NE(r.outcome.find("always fails"), std::string::npos) << r.outcome;
  EXPECT_NEAR(s.sigma_c.value, kTruth.sigma_c, 0.01 * kTruth.sigma_c);
}

}  // namespace
}  // namespace bridgefit::inverse
