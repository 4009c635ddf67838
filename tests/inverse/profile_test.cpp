// Profiles you can trust (docs/FIT.md): the ends of the profile-likelihood
// intervals on forward models made to break them - a chi^2 that jumps next to
// the optimum or inside the interval, a narrow bump the profile comes back
// from, an optimum on the box edge - against the same fit on the smooth
// analytic model (its own oracle).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bridgefit/inverse/fit.hpp"

namespace bridgefit::inverse {
namespace {

constexpr double kModulus = 1e9;  // E' of the analytic model [Pa]
constexpr double kA0 = 0.03;      // [m]

// The analytic model, with R moved by +-3% point by point (alternately, which
// no other parameter can absorb) where sigma_c lies in [from, to): a step
// (to = infinity) or a bump of the chi^2 landscape along sigma_c.
class SteppedModel final : public ForwardModel {
 public:
  SteppedModel(double from, double to) : inner_(kModulus, kA0), from_(from), to_(to) {}
  std::string Name() const override { return "stepped-analytic"; }
  ForwardPrediction Predict(const laws::LawShape& shape, const LawParameters& p,
                            const std::vector<double>& crack_lengths, RKind kind) const override {
    ForwardPrediction out = inner_.Predict(shape, p, crack_lengths, kind);
    if (p.sigma_c >= from_ && p.sigma_c < to_)
      for (size_t i = 0; i < out.R.size(); ++i) out.R[i] *= i % 2 ? 1.03 : 0.97;
    return out;
  }

 private:
  AnalyticForwardModel inner_;
  double from_, to_;
};

// Steady state inside the window (36 mm of growth), 1% noise, 1% weights.
FitData MakeData() {
  const laws::LawShape shape = laws::MakeLinearShape();
  const AnalyticForwardModel model(kModulus, kA0);
  FitData data;
  for (int i = 0; i < 40; ++i) data.crack_length.push_back(kA0 + 0.08 * (i + 1) / 40);
  const ForwardPrediction p =
      model.Predict(shape, {1.0e6, 500.0, 2210.0}, data.crack_length, RKind::kEnergy);
  std::mt19937 rng(11);
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
  o.threads = 1;
  return o;
}

class Profiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    smooth_ = new FitSummary(FitBridgingLaw(AnalyticForwardModel(kModulus, kA0),
                                            laws::MakeLinearShape(), MakeData(), Options()));
  }
  static void TearDownTestSuite() { delete smooth_; }
  static FitSummary Fit(const ForwardModel& model, const FitOptions& options = Options()) {
    return FitBridgingLaw(model, laws::MakeLinearShape(), MakeData(), options);
  }
  static const FitSummary* smooth_;
};
const FitSummary* Profiles::smooth_ = nullptr;

// The smooth model: every interval reliable, nonzero, around its value.
TEST_F(Profiles, SmoothProfilesAreReliable) {
  const FitSummary& s = *smooth_;
  ASSERT_TRUE(s.steady_state_reached) << s.verdict;
  for (const ParameterEstimate* e : {&s.sigma_c, &s.J_B, &s.J_tip_c}) {
    EXPECT_EQ(e->interval_status, IntervalStatus::kReliable) << e->interval_reason;
    EXPECT_TRUE(e->interval_reason.empty());
    EXPECT_EQ(e->note, "CI from the profile likelihood");
    EXPECT_LT(e->ci95_low, e->value);
    EXPECT_GT(e->ci95_high, e->value);
  }
  for (const Profile& p : s.profiles) EXPECT_EQ(p.status, IntervalStatus::kReliable);
}

// chi^2 jumps 3e-5 (relative) above the optimum's sigma_c: the old step-out
// (first step 0.004 box, 5 bisections: 1.25e-4 box = 8.6e-4 relative) found
// no inside point and returned the optimum as the upper end, a zero-width
// side. Now the bisection goes down to the jump, the far side is re-solved,
// and the side is reported zero-width with no end printed.
TEST_F(Profiles, JumpNextToTheOptimumIsZeroWidthNotAnInterval) {
  const double v = smooth_->sigma_c.value;
  const SteppedModel model(v * (1.0 + 3e-5), INFINITY);
  const FitSummary s = Fit(model);
  ASSERT_NEAR(s.sigma_c.value, v, 1e-4 * v);
  EXPECT_EQ(s.sigma_c.interval_status, IntervalStatus::kUnreliableZeroWidth) << s.sigma_c.note;
  EXPECT_TRUE(std::isnan(s.sigma_c.ci95_high)) << s.sigma_c.ci95_high;
  EXPECT_NE(s.sigma_c.ci95_high, s.sigma_c.value);
  EXPECT_NE(s.sigma_c.interval_reason.find("jumps"), std::string::npos) << s.sigma_c.interval_reason;
  // The side away from the jump is the smooth model's.
  EXPECT_NEAR(s.sigma_c.ci95_low, smooth_->sigma_c.ci95_low, 1e-3 * v);
  EXPECT_NE(s.BriefReport().find("interval unreliable"), std::string::npos) << s.BriefReport();
}

// A step inside the smooth interval: the profile cannot come back, the side
// is non-smooth and its end is not printed (the old code printed the step as
// the end, a narrower interval than the data give).
TEST_F(Profiles, StepInsideTheIntervalIsNonSmooth) {
  const double v = smooth_->sigma_c.value, h = smooth_->sigma_c.ci95_high;
  const double step = v + 0.5 * (h - v);
  const SteppedModel model(step, INFINITY);
  const FitSummary s = Fit(model);
  ASSERT_NEAR(s.sigma_c.value, v, 1e-4 * v);
  EXPECT_EQ(s.sigma_c.interval_status, IntervalStatus::kUnreliableNonSmooth) << s.sigma_c.note;
  EXPECT_TRUE(std::isnan(s.sigma_c.ci95_high));
  EXPECT_NE(s.sigma_c.interval_reason.find("not smooth"), std::string::npos)
      << s.sigma_c.interval_reason;
}

// A narrow bump inside the interval: the profile comes back under the
// threshold past it, so the end is followed out to the smooth model's end
// (the old code stopped at the bump), with a warning.
TEST_F(Profiles, BumpIsCrossedAndTheIntervalWidened) {
  const double v = smooth_->sigma_c.value, h = smooth_->sigma_c.ci95_high;
  const SteppedModel model(v + 0.15 * (h - v), v + 0.7 * (h - v));
  const FitSummary s = Fit(model);
  ASSERT_NEAR(s.sigma_c.value, v, 1e-4 * v);
  EXPECT_EQ(s.sigma_c.interval_status, IntervalStatus::kUnreliableNonSmooth) << s.sigma_c.note;
  EXPECT_NEAR(s.sigma_c.ci95_high, h, 0.05 * (h - v)) << s.sigma_c.note;
  EXPECT_NE(s.sigma_c.note.find("CI from the profile likelihood"), std::string::npos);
  EXPECT_NE(s.sigma_c.interval_reason.find("widened"), std::string::npos)
      << s.sigma_c.interval_reason;
}

// The truth below the box: the optimum sits on the lower edge; that side is
// the box's, not the data's, and says so (the old code called it a flat
// profile).
TEST_F(Profiles, OptimumOnTheBoxEdgeEndsOnBound) {
  FitOptions options = Options();
  options.lower[kSigmaC] = 1.2 * smooth_->sigma_c.ci95_high;
  const FitSummary s = Fit(AnalyticForwardModel(kModulus, kA0), options);
  ASSERT_NEAR(s.sigma_c.value, options.lower[kSigmaC], 1e-3 * options.lower[kSigmaC]);
  EXPECT_EQ(s.sigma_c.interval_status, IntervalStatus::kEndsOnBound) << s.sigma_c.note;
  EXPECT_TRUE(std::isnan(s.sigma_c.ci95_low));
  EXPECT_FALSE(s.sigma_c.identified);
  EXPECT_NE(s.sigma_c.interval_reason.find("--bounds"), std::string::npos);
}

// A false basin: where sigma_c lies in [2.5, 3.5) MPa the model draws the
// curve of sigma_c / 3 with every point moved by +-2% alternately, so a
// search started there stops at about 3 MPa with a chi^2 about 160 above
// the true basin's; outside the band it is the analytic model.
class TrapModel final : public ForwardModel {
 public:
  TrapModel() : inner_(kModulus, kA0) {}
  std::string Name() const override { return "trap-analytic"; }
  ForwardPrediction Predict(const laws::LawShape& shape, const LawParameters& p,
                            const std::vector<double>& crack_lengths, RKind kind) const override {
    if (!(p.sigma_c >= 2.5e6 && p.sigma_c < 3.5e6)) return inner_.Predict(shape, p, crack_lengths, kind);
    LawParameters q = p;
    q.sigma_c = p.sigma_c / 3.0;
    ForwardPrediction out = inner_.Predict(shape, q, crack_lengths, kind);
    for (size_t i = 0; i < out.R.size(); ++i) out.R[i] *= i % 2 ? 1.02 : 0.98;
    return out;
  }

 private:
  AnalyticForwardModel inner_;
};

// One start inside the false basin: the profiles step out of it and find
// the true basin's lower chi^2, and the fit restarts from that profile
// point (it used to report the false optimum with its profile flagged
// "the fit stopped in a local minimum"). The result is the smooth model's
// fit (the trap lies far outside its intervals), the restart listed among
// the starts.
TEST_F(Profiles, AFalseBasinFoundByAProfileRestartsTheFit) {
  FitOptions options = Options();
  options.starts = 1;
  options.initial = {3.0e6, smooth_->J_B.value, smooth_->J_tip_c.value};
  const FitSummary s = Fit(TrapModel(), options);
  ASSERT_TRUE(s.converged) << s.stop_reason;
  EXPECT_NEAR(s.chi2, smooth_->chi2, 1e-3 * smooth_->chi2) << s.BriefReport();
  EXPECT_NEAR(s.sigma_c.value, smooth_->sigma_c.value, 1e-3 * smooth_->sigma_c.value);
  EXPECT_NEAR(s.J_tip_c.value, smooth_->J_tip_c.value, 1e-3 * smooth_->J_tip_c.value);
  EXPECT_EQ(s.sigma_c.interval_status, IntervalStatus::kReliable) << s.sigma_c.interval_reason;
  EXPECT_NEAR(s.sigma_c.ci95_low, smooth_->sigma_c.ci95_low, 2e-3 * smooth_->sigma_c.value);
  EXPECT_NEAR(s.sigma_c.ci95_high, smooth_->sigma_c.ci95_high, 2e-3 * smooth_->sigma_c.value);
  int restarts = 0;
  for (const StartResult& start : s.starts) restarts += start.stop_reason.rfind("restart from", 0) == 0;
  EXPECT_GE(restarts, 1);
  EXPECT_NE(s.stop_reason.find("after a restart"), std::string::npos) << s.stop_reason;
}

// J_tip,c outside [2190, 2225] J/m^2 draws the curve of 2250 J/m^2 with
// every point moved by +-5% alternately (a plateau no search can leave);
// inside it is the analytic model.
class PlateauModel final : public ForwardModel {
 public:
  PlateauModel() : inner_(kModulus, kA0) {}
  std::string Name() const override { return "plateau-analytic"; }
  ForwardPrediction Predict(const laws::LawShape& shape, const LawParameters& p,
                            const std::vector<double>& crack_lengths, RKind kind) const override {
    if (p.J_tip_c >= 2190.0 && p.J_tip_c <= 2225.0) return inner_.Predict(shape, p, crack_lengths, kind);
    LawParameters q = p;
    q.J_tip_c = 2250.0;
    ForwardPrediction out = inner_.Predict(shape, q, crack_lengths, kind);
    for (size_t i = 0; i < out.R.size(); ++i) out.R[i] *= i % 2 ? 1.05 : 0.95;
    return out;
  }

 private:
  AnalyticForwardModel inner_;
};

// A start 0.02 (box) from J_tip,c's lower bound: BOBYQA moves a start that
// close to a bound onto it (Powell's rule), here onto the plateau, and used
// to return the plateau's chi^2, far worse than the start's (only the
// restart from a profile point could recover it, and not here: chi^2 953
// against 49); the start is now kept when
// the search does worse, and the fit is the smooth one's.
TEST_F(Profiles, ASearchThatMovesItsStartOntoAPlateauKeepsTheStart) {
  FitOptions options = Options();
  options.starts = 1;
  options.optimizer = Optimizer::kBobyqa;  // the CLI's default
  options.lower[kJTipC] = 2000.0;
  options.upper[kJTipC] = 2000.0 + (smooth_->J_tip_c.value - 2000.0) / 0.02;
  options.initial = {smooth_->sigma_c.value, smooth_->J_B.value, smooth_->J_tip_c.value};
  const FitSummary s = Fit(PlateauModel(), options);
  // The start's own search ends there (no restart from a profile needed:
  // before, the restart was what recovered it).
  ASSERT_EQ(s.starts.size(), 1u) << s.starts.back().stop_reason;
  EXPECT_NEAR(s.starts[0].cost, smooth_->chi2, 1e-3 * smooth_->chi2) << s.starts[0].stop_reason;
  EXPECT_NEAR(s.chi2, smooth_->chi2, 1e-3 * smooth_->chi2) << s.BriefReport();
  EXPECT_NEAR(s.J_tip_c.value, smooth_->J_tip_c.value, 1e-3 * smooth_->J_tip_c.value);
  EXPECT_NEAR(s.sigma_c.value, smooth_->sigma_c.value, 1e-3 * smooth_->sigma_c.value);
}

TEST(IntervalStatus, Names) {
  EXPECT_STREQ(IntervalStatusName(IntervalStatus::kReliable), "reliable");
  EXPECT_STREQ(IntervalStatusName(IntervalStatus::kUnreliableZeroWidth), "unreliable_zero_width");
  EXPECT_STREQ(IntervalStatusName(IntervalStatus::kUnreliableNonSmooth), "unreliable_non_smooth");
  EXPECT_STREQ(IntervalStatusName(IntervalStatus::kEndsOnBound), "ends_on_bound");
  EXPECT_STREQ(IntervalStatusName(IntervalStatus::kOpen), "open");
}

}  // namespace
}  // namespace bridgefit::inverse
