// A joint fit of a subset of the law's parameters (issue 19: "sigma_c, J_B,
// delta_c, J_tip,c, or a subset named by the user"; docs/CAMPAIGN.md "A
// subset shared"). Oracle: R curves of CT specimens made by the analytic
// model (its own truth) with 2% noise, of one sigma_c and J_B but tip
// toughnesses 20% apart (boards of different tip toughness): the all-shared
// joint fit is rejected, the fit sharing sigma_c and J_B is accepted with
// k_shared (n - 1) degrees of freedom, covers the shared truth, and gives
// each specimen its own J_tip,c within its stated interval of its truth;
// the wrong subset (J_tip,c shared, sigma_c not) is rejected.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/pipeline/joint_fit.hpp"

#include "analytic_campaign.hpp"

namespace bridgefit::pipeline {
namespace {

using test::Campaign;
using test::kNoise;

Campaign Make(const std::vector<inverse::LawParameters>& laws, unsigned seed_base) {
  return test::Make(laws, seed_base, /*profiles=*/true);
}

FitRequest Specimen(double notch, const inverse::LawParameters& law, unsigned seed) {
  return test::Specimen(notch, law, seed, /*profiles=*/true);
}

unsigned SeedBase() {
  const char* offset = std::getenv("BRIDGEFIT_JOINT_SEED");
  return 300 + (offset ? static_cast<unsigned>(std::strtoul(offset, nullptr, 10)) : 0u);
}

TEST(JointSubset, TipToughnessOfEachBoardSigmaCAndJBShared) {
  const Stopwatch clock;
  const inverse::LawParameters law{2.0e6, 500.0, 2210.0};
  std::vector<inverse::LawParameters> laws(3, law);
  laws[1].J_tip_c *= 1.2;
  laws[2].J_tip_c /= 1.2;
  const Campaign c = Make(laws, SeedBase());
  for (std::size_t k = 0; k < c.runs.size(); ++k)
    std::printf("%s alone:\n%s", c.names[k].c_str(), c.runs[k].summary.BriefReport().c_str());

  // All four shared: rejected (on 3 x 2 dof).
  const JointFitRun all = c.Joint();
  std::printf("%s", all.BriefReport().c_str());
  EXPECT_EQ(all.consistency.degrees_of_freedom, 6);
  EXPECT_FALSE(all.consistency.consistent()) << all.consistency.Summary();
  EXPECT_LT(all.consistency.p_value, 1e-6);
  EXPECT_TRUE(all.own_values.empty());

  // sigma_c and J_B shared, J_tip,c each board's own: accepted on 2 x 2 dof.
  const JointFitRun subset = c.Joint({true, true, false});
  std::printf("%s", subset.BriefReport().c_str());
  const inverse::FitSummary& f = subset.summary;
  ASSERT_TRUE(f.converged) << f.stop_reason;
  EXPECT_EQ(subset.shared, (inverse::SharedParameters{true, true, false}));
  EXPECT_EQ(subset.consistency.degrees_of_freedom, 4);
  EXPECT_TRUE(subset.consistency.consistent()) << subset.consistency.Summary();
  EXPECT_TRUE(subset.flagged.empty());
  ASSERT_TRUE(f.sigma_c.identified && f.J_B.identified) << f.verdict;
  EXPECT_TRUE(f.sigma_c.ci95_low <= law.sigma_c && law.sigma_c <= f.sigma_c.ci95_high);
  EXPECT_TRUE(f.J_B.ci95_low <= law.J_B && law.J_B <= f.J_B.ci95_high);
  // J_tip,c is no joint estimate: each specimen's own, covering its truth.
  EXPECT_FALSE(std::isfinite(f.J_tip_c.value));
  ASSERT_EQ(subset.own_values.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    const OwnParameterValue& v = subset.own_values[k];
    EXPECT_EQ(v.specimen, c.names[k]);
    EXPECT_EQ(v.parameter, inverse::kJTipC);
    EXPECT_TRUE(v.ci95_low <= laws[k].J_tip_c && laws[k].J_tip_c <= v.ci95_high)
        << v.specimen << ": " << v.value << " [" << v.ci95_low << ", " << v.ci95_high
        << "], truth " << laws[k].J_tip_c;
    // The interval holds the conditional one (shared held at the joint values).
    EXPECT_LE(v.ci95_low, v.conditional_ci95_low);
    EXPECT_GE(v.ci95_high, v.conditional_ci95_high);
  }
  // Every specimen reaches steady state here: each carries both shared ones.
  ASSERT_EQ(subset.carriers.size(), 2u);
  for (const ParameterCarriers& carriers : subset.carriers) EXPECT_EQ(carriers.specimens, c.names);

  // The wrong subset - J_tip,c shared, sigma_c each board's own - is
  // rejected: what differs must not be shared (on 2 x 2 dof too).
  const JointFitRun wrong = c.Joint({false, true, true});
  std::printf("wrong subset: %s\n", wrong.consistency.Summary().c_str());
  EXPECT_EQ(wrong.consistency.degrees_of_freedom, 4);
  EXPECT_FALSE(wrong.consistency.consistent());
  EXPECT_LT(wrong.consistency.p_value, 1e-6);
  std::printf("three joint fits with the fits alone: %.1f s\n", clock.Seconds());
}

// The profiled own values are the specimen's least chi^2 at the shared
// values given: one (J_tip,c) against a 401-point scan, two (J_B and
// J_tip,c, sigma_c shared) against a 61 x 61 grid, both in ln p.
TEST(JointSubset, ProfiledOwnValuesAreTheLeastChi2OfAScan) {
  const inverse::LawParameters truth{2.0e6, 500.0, 2652.0};
  const FitRequest r = Specimen(0.035, truth, 7);
  const auto model = inverse::MakeAnalyticForwardModel(r.scene);
  const inverse::FitData data = inverse::FitData::FromRCurve(*r.rcurve, inverse::RKind::kEnergy);
  const laws::LawShape shape = laws::MakeLinearShape();
  const inverse::FitOptions box;
  const std::array<double, 3> start = {2.1e6, 450.0, 2400.0};
  const inverse::LawParameters shared{2.1e6, 480.0, 1000.0};  // off the truth; J_tip,c unused
  const inverse::OwnParameterProfiledModel one(*model, data, {true, true, false}, box.lower,
                                               box.upper, start);
  const inverse::LawParameters p1 = one.Profiled(shape, shared);
  EXPECT_EQ(p1.sigma_c, shared.sigma_c);
  EXPECT_EQ(p1.J_B, shared.J_B);
  double least = INFINITY;
  for (int i = 0; i <= 400; ++i) {
    const double j = 2652.0 * std::exp(-0.5 + i / 400.0);
    least = std::min(least, one.Chi2(shape, {shared.sigma_c, shared.J_B, j}));
  }
  EXPECT_LE(one.Chi2(shape, p1), least * (1 + 1e-9));
  const inverse::OwnParameterProfiledModel two(*model, data, {true, false, false}, box.lower,
                                               box.upper, start);
  const inverse::LawParameters p2 = two.Profiled(shape, shared);
  EXPECT_EQ(p2.sigma_c, shared.sigma_c);
  least = INFINITY;
  for (int i = 0; i <= 60; ++i)
    for (int j = 0; j <= 60; ++j)
      least = std::min(least, two.Chi2(shape, {shared.sigma_c, 500.0 * std::exp(-1.0 + i / 30.0),
                                               2652.0 * std::exp(-0.3 + j / 100.0)}));
  std::printf("one own: J_tip,c %.2f; two own: J_B %.2f, J_tip,c %.2f; chi^2 %.4g (grid %.4g)\n",
              p1.J_tip_c, p2.J_B, p2.J_tip_c, two.Chi2(shape, p2), least);
  EXPECT_LE(two.Chi2(shape, p2), least * (1 + 1e-9));
  // The model predicts its own data's axis only.
  EXPECT_FALSE(one.Predict(shape, shared, {0.04, 0.05}, inverse::RKind::kEnergy).ok());
}

TEST(JointSubset, SharedParameterNamesAreChecked) {
  EXPECT_EQ(inverse::ParseSharedParameters({"J_tip_c", "sigma_c"}),
            (inverse::SharedParameters{true, false, true}));
  EXPECT_EQ(inverse::SharedParametersText({true, false, true}), "sigma_c, J_tip_c");
  for (const std::vector<std::string>& bad : std::vector<std::vector<std::string>>{
           {}, {"Jtip"}, {"delta_c"}, {"sigma_c", "sigma_c"}})
    EXPECT_THROW(inverse::ParseSharedParameters(bad), Error);
}

}  // namespace
}  // namespace bridgefit::pipeline
