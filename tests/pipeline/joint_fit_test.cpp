// The joint fit of several specimens (issue 19; pipeline/joint_fit.hpp):
// R curves of CT specimens with different notches made by the analytic model
// (its own oracle) with 2% noise. Specimens of one law: the likelihood ratio
// says consistent and the joint intervals cover the truth, narrower than any
// specimen's alone; one specimen of another law: the test says not
// consistent. Specimens that cannot join are refused by name.
#include "bridgefit/pipeline/joint_fit.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdio>

#include "bridgefit/core/error.hpp"

#include "analytic_campaign.hpp"

namespace bridgefit::pipeline {
namespace {

using test::Campaign;
using test::kNoise;

Campaign Make(const std::vector<inverse::LawParameters>& laws, unsigned seed_base = 100) {
  return test::Make(laws, seed_base, /*profiles=*/false);
}

const inverse::LawParameters kTruth{1.0e6, 500.0, 2210.0};

// Eight campaigns of four specimens of one law (steady state not reached:
// sigma_c from the rising R curves, J_B a bound). Per campaign the joint
// 95% intervals of sigma_c and J_tip,c should cover the truth and the test
// say consistent; over eight, with 95% coverage and a uniform p under the
// null, 3 or more misses of one kind have probability 0.6% (binomial), so
// at most 2 are allowed. The joint J_tip,c interval is narrower than every
// specimen's alone, sigma_c's than their mean.
TEST(JointFit, OneLawIsConsistentAndCoversTheTruth) {
  int covered_sigma = 0, covered_tip = 0, consistent = 0, flagged = 0;
  for (unsigned campaign = 0; campaign < 8; ++campaign) {
    const Campaign c = Make({kTruth, kTruth, kTruth, kTruth}, 100 + 100 * campaign);
    const JointFitRun joint = c.Joint();
    if (campaign == 0) std::printf("%s", joint.BriefReport().c_str());
    const inverse::FitSummary& s = joint.summary;
    std::printf("campaign %u: sigma_c %.4g [%.4g, %.4g] MPa, J_tip,c %.5g [%.5g, %.5g], p %.3g\n",
                campaign, s.sigma_c.value * 1e-6, s.sigma_c.ci95_low * 1e-6,
                s.sigma_c.ci95_high * 1e-6, s.J_tip_c.value, s.J_tip_c.ci95_low, s.J_tip_c.ci95_high,
                joint.consistency.p_value);
    ASSERT_TRUE(s.converged) << s.stop_reason;
    ASSERT_TRUE(s.sigma_c.identified && s.J_tip_c.identified);
    EXPECT_EQ(s.data_points, 160);
    EXPECT_EQ(joint.consistency.degrees_of_freedom, 9);
    covered_sigma += s.sigma_c.ci95_low <= kTruth.sigma_c && kTruth.sigma_c <= s.sigma_c.ci95_high;
    covered_tip += s.J_tip_c.ci95_low <= kTruth.J_tip_c && kTruth.J_tip_c <= s.J_tip_c.ci95_high;
    consistent += joint.consistency.consistent();
    flagged += static_cast<int>(joint.flagged.size());
    double sigma_widths = 0.0;
    int sigma_identified = 0;
    for (const FitRun& r : c.runs) {
      if (r.summary.sigma_c.identified) {
        sigma_widths += r.summary.sigma_c.ci95_high - r.summary.sigma_c.ci95_low;
        ++sigma_identified;
      }
      if (r.summary.J_tip_c.identified) {
        EXPECT_LT(s.J_tip_c.ci95_high - s.J_tip_c.ci95_low,
                  r.summary.J_tip_c.ci95_high - r.summary.J_tip_c.ci95_low);
      }
    }
    // sigma_c from rising R curves: its Jacobian width depends on where the
    // estimate falls (J_B's correlation), so against the specimens' mean.
    if (sigma_identified > 0) {
      EXPECT_LT(s.sigma_c.ci95_high - s.sigma_c.ci95_low, sigma_widths / sigma_identified);
    }
  }
  EXPECT_GE(covered_sigma, 6);
  EXPECT_GE(covered_tip, 6);
  EXPECT_GE(consistent, 6);
  EXPECT_LE(flagged, 2);  // 32 specimens at alpha / 4 = 1.25% each: about 0.4 expected
}

TEST(JointFit, AnotherLawIsNotConsistent) {
  inverse::LawParameters other = kTruth;
  other.sigma_c *= 2.0;  // a different board: twice the bridging strength
  const Campaign c = Make({kTruth, kTruth, other});
  const JointFitRun joint = c.Joint();
  std::printf("%s", joint.BriefReport().c_str());
  EXPECT_FALSE(joint.consistency.consistent()) << joint.consistency.Summary();
  EXPECT_LT(joint.consistency.p_value, 1e-4);
  EXPECT_NE(joint.consistency.Summary().find("NOT described by one law"), std::string::npos);
  // The specimen of the other law is the one flagged.
  EXPECT_EQ(joint.flagged, (std::vector<std::string>{"CT-3"}));
}

TEST(JointFit, SpecimensThatCannotJoinAreNamed) {
  Campaign c = Make({kTruth, kTruth});
  c.runs[1].shape = laws::MakeExponentialShape(3.0);
  try {
    c.Joint();
    FAIL() << "a specimen with another law shape joined";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("CT-2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("law shape"), std::string::npos) << e.what();
  }
}

// The chi^2 upper tail against table values (Abramowitz and Stegun 26.4).
TEST(JointFit, ChiSquareSurvivalMatchesTables) {
  EXPECT_NEAR(inverse::ChiSquareSurvival(3.841, 1), 0.05, 2e-4);
  EXPECT_NEAR(inverse::ChiSquareSurvival(16.919, 9), 0.05, 2e-4);
  EXPECT_NEAR(inverse::ChiSquareSurvival(21.666, 9), 0.01, 1e-4);
  EXPECT_NEAR(inverse::ChiSquareSurvival(2.0, 2), std::exp(-1.0), 1e-12);
  EXPECT_DOUBLE_EQ(inverse::ChiSquareSurvival(0.0, 3), 1.0);
}

}  // namespace
}  // namespace bridgefit::pipeline
