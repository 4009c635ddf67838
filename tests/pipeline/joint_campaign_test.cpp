// Issue 19's acceptance campaign by the load-displacement joint fit
// (docs/CAMPAIGN.md "Two sizes by their load records"; it replaces the
// R-curve route's version, whose joint fit covered the truth without the
// accuracy: sigma_c 1.54 [0.82, 2.71] MPa for 1 MPa): CT specimens of the
// MDF board (E 3 GPa, a0 = 0.3 W, H = 1.2 W) of two sizes, one linear law
// (sigma_c 0.45 MPa, J_B 500 J/m^2, J_tip,c 2210 J/m^2), records made by
// `synth`'s reduced model at a 4x finer element size than the fit's, 0.5%
// load noise, each record to 0.8 W (the design window). The sizes come from
// `bridgefit design data_samples/mdf_ct/scene.toml --sigma-c 0.45MPa --jb
// 500J/m^2 --size 50mm:500mm:50mm`: at this law steady state begins at
// 0.74 W (a = 296 mm at W = 400 mm, the smallest size with 3 R points past it;
// W = 50 .. 250 mm never reach it). So one W = 50 mm specimen (bound only)
// and one W = 400 mm specimen; then a third, W = 50 mm of twice the sigma_c.
// Each is fitted alone to its record (initial-slope compliance calibration),
// then jointly.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

#include "bridgefit/core/progress.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/joint_fit.hpp"
#include "bridgefit/pipeline/synth.hpp"

namespace bridgefit::pipeline {
namespace {
namespace fs = std::filesystem;

constexpr double kSigmaC = 0.45e6, kJB = 500.0, kJTip = 2210.0;

struct Ct {
  std::string name;
  double width;       // W [m]
  double resolution;  // the fit's element size [m]; the record's is a quarter
  double sigma_c;     // [Pa]
  std::uint64_t seed;
};

struct Specimen {
  FitRequest request;
  FitRun run;
};

// The seeds: 1, 2, 3, 4 plus BRIDGEFIT_JOINT_SEED (default 0), for checks by hand.
std::uint64_t Seed(std::uint64_t k) {
  const char* offset = std::getenv("BRIDGEFIT_JOINT_SEED");
  return k + (offset ? std::strtoull(offset, nullptr, 10) : 0);
}

// The MDF sample's CT scaled to width W (H and a0 with it, B fixed), its
// record to 0.8 W.
Scene Sized(double width, double sigma_c) {
  Scene s = io::ReadSceneFile(std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/mdf_ct/scene.toml");
  const double f = width / s.specimen.width;
  s.specimen.width *= f;
  s.specimen.height *= f;
  s.specimen.notch *= f;
  s.run.max_crack_length = 0.8 * width;
  s.bridging->scales.sigma_c = sigma_c;
  s.bridging->scales.J_B = kJB;
  s.bridging->scales.delta_c = 2.0 * kJB / sigma_c;  // linear law: J_B = sigma_c delta_c / 2
  s.fracture->J_tip_c = kJTip;
  return s;
}

Specimen Make(const Ct& ct) {
  SynthRequest synth;
  synth.scene = Sized(ct.width, ct.sigma_c);
  synth.seed = ct.seed;
  synth.resolution = 0.25 * ct.resolution;
  synth.frames = 0;
  synth.growth_rows = 120;
  synth.load_noise = 0.005;
  const SynthTest test = MakeSyntheticTest(synth);
  const fs::path file = fs::temp_directory_path() /
                        fmt::format("bf_joint_campaign_{}_{}_{}.csv", ::getpid(), ct.name, ct.seed);
  { std::ofstream(file) << test.record_csv; }
  Specimen s;
  s.request.input_path = file.string();
  s.request.scene = synth.scene;
  s.request.scene.bridging.reset();  // the truth is not the fit's to know
  s.request.resolution = ct.resolution;
  s.request.law = laws::LawFamily::kLinear;
  s.request.target = inverse::FitTarget::kLoad;
  s.request.calibration = inverse::ComplianceCalibrationMode::kInitialSlope;
  s.request.fit.starts = 2;
  const Stopwatch clock;
  s.run = RunFit(s.request);
  fs::remove(file);
  std::printf("%s (W %.0f mm, seed %d, sigma_c %.2f MPa): fitted alone at %.2g mm in %.1f s, "
              "modulus factor %.4f\n",
              ct.name.c_str(), ct.width * 1e3, static_cast<int>(ct.seed), ct.sigma_c * 1e-6,
              ct.resolution * 1e3, clock.Seconds(), s.run.calibration.modulus_factor);
  return s;
}

// Each specimen made and fitted once for every test of this file.
const Specimen& Get(const Ct& ct) {
  static std::map<std::string, Specimen> made;
  auto it = made.find(ct.name);
  if (it == made.end()) it = made.emplace(ct.name, Make(ct)).first;
  return it->second;
}

// Fit element sizes W / 100 (at W / 50 the small CT's own model error is 3
// noise SD rms: too coarse). One CT per size.
const Ct kSmall{"W50", 0.050, 0.5e-3, kSigmaC, Seed(1)};
const Ct kLarge{"W400", 0.400, 4e-3, kSigmaC, Seed(2)};
const Ct kOther{"W50-2x", 0.050, 0.5e-3, 2.0 * kSigmaC, Seed(3)};  // twice sigma_c

JointFitRun Joint(const std::vector<Ct>& cts) {
  std::vector<FitRequest> requests;
  std::vector<const FitRun*> runs;
  std::vector<std::string> names;
  for (const Ct& ct : cts) {
    requests.push_back(Get(ct).request);
    runs.push_back(&Get(ct).run);
    names.push_back(ct.name);
  }
  return RunJointFit(requests, runs, names);
}

void Print(const std::string& what, const inverse::FitSummary& f) {
  std::printf("%-8s sigma_c %.4g [%.4g, %.4g] MPa, J_B %.4g [%.4g, %.4g] (bound %.4g), "
              "J_tip,c %.5g [%.5g, %.5g]\n",
              what.c_str(), f.sigma_c.value * 1e-6, f.sigma_c.ci95_low * 1e-6,
              f.sigma_c.ci95_high * 1e-6, f.J_B.value, f.J_B.ci95_low, f.J_B.ci95_high,
              f.J_B.lower_bound, f.J_tip_c.value, f.J_tip_c.ci95_low, f.J_tip_c.ci95_high);
  std::printf("         statistical: sigma_c [%.4g, %.4g] MPa (bias %+.3g), J_B [%.4g, %.4g] "
              "(bias %+.3g), J_tip,c [%.5g, %.5g] (bias %+.3g)\n",
              f.sigma_c.statistical_ci95_low * 1e-6, f.sigma_c.statistical_ci95_high * 1e-6,
              f.sigma_c.model_bias * 1e-6, f.J_B.statistical_ci95_low,
              f.J_B.statistical_ci95_high, f.J_B.model_bias, f.J_tip_c.statistical_ci95_low,
              f.J_tip_c.statistical_ci95_high, f.J_tip_c.model_bias);
}

bool Covers(const inverse::ParameterEstimate& e, double truth) {
  return e.ci95_low <= truth && truth <= e.ci95_high;
}

// One joint fit serves both halves of issue 19's acceptance point (one run
// of the three-specimen campaign costs about as much as the two-size one
// alone; the suite is at its time limit): the two-size campaign plus a CT of
// twice the sigma_c is rejected and that CT alone flagged; the joint fit of
// the rest is then the two-size campaign's own joint fit (the same fitter and
// options; each specimen alone is also re-started from the three-specimen
// optimum, which can only lower its chi^2 alone and so raise the likelihood
// ratio: the acceptance is not made easier). On it: one law accepted, J_B
// within 5% and sigma_c within 3% of the truth, every total interval
// covering it. Checked by hand 2026-12-03: the two-size campaign run alone
// gave the same estimates (LR 6.00 against 6.01 here, seed offset 0).
TEST(JointCampaign, TwoSizesIdentifyWhatTheSmallOneCannotAndAnotherLawIsFlagged) {
  const Stopwatch clock;
  // Alone: the small CT gives J_B only as a lower bound, below the truth;
  // the large one reaches steady state.
  const inverse::FitSummary& small = Get(kSmall).run.summary;
  Print(kSmall.name, small);
  EXPECT_FALSE(small.steady_state_reached);
  EXPECT_FALSE(small.J_B.identified);
  EXPECT_LE(small.J_B.lower_bound, kJB);
  const inverse::FitSummary& large = Get(kLarge).run.summary;
  Print(kLarge.name, large);
  EXPECT_TRUE(large.steady_state_reached);
  EXPECT_TRUE(large.J_B.identified);
  Print(kOther.name, Get(kOther).run.summary);

  const JointFitRun joint = Joint({kSmall, kLarge, kOther});
  std::printf("%s", joint.BriefReport().c_str());
  EXPECT_FALSE(joint.consistency.consistent()) << joint.consistency.Summary();
  EXPECT_LT(joint.consistency.p_value, 1e-4);
  ASSERT_EQ(joint.flagged, (std::vector<std::string>{kOther.name}));
  ASSERT_TRUE(joint.summary_without_flagged.has_value());

  // The two-size campaign {W50, W400}.
  const inverse::FitSummary& f = *joint.summary_without_flagged;
  Print("joint", f);
  ASSERT_TRUE(f.converged) << f.stop_reason;
  EXPECT_TRUE(joint.consistency_without_flagged.consistent())
      << joint.consistency_without_flagged.Summary();
  EXPECT_EQ(joint.consistency_without_flagged.degrees_of_freedom, 3);
  ASSERT_TRUE(f.J_B.identified && f.sigma_c.identified && f.J_tip_c.identified) << f.verdict;
  EXPECT_NE(f.verdict.find("inside the windows of W400"), std::string::npos) << f.verdict;
  // Issue 19: J_B within 5%, sigma_c within 3%, every (total) interval
  // covering the truth.
  EXPECT_NEAR(f.J_B.value, kJB, 0.05 * kJB);
  EXPECT_NEAR(f.sigma_c.value, kSigmaC, 0.03 * kSigmaC);
  EXPECT_TRUE(Covers(f.sigma_c, kSigmaC));
  EXPECT_TRUE(Covers(f.J_B, kJB));
  EXPECT_TRUE(Covers(f.J_tip_c, kJTip));
  // Who carries what (pipeline::kCarrierRule): J_B only the large CT, the
  // small one never reaching steady state; J_tip,c both; sigma_c the large
  // one alone since the model error holds the far field's share (docs/
  // FIT.md "The far field"): the small CT's own sigma_c interval, [0.302,
  // 0.648] MPa with a predicted bias of -0.060 MPa (statistical [0.421,
  // 0.468]), is 16 times the joint one, beyond the rule's 10.
  const auto carriers = [&](int parameter) {
    for (const ParameterCarriers& c : joint.carriers_without_flagged)
      if (c.parameter == parameter) return c.specimens;
    ADD_FAILURE() << "no carriers of " << inverse::ParameterName(parameter);
    return std::vector<std::string>{};
  };
  EXPECT_EQ(carriers(inverse::kJB), (std::vector<std::string>{kLarge.name}));
  EXPECT_EQ(carriers(inverse::kSigmaC), (std::vector<std::string>{kLarge.name}));
  EXPECT_EQ(carriers(inverse::kJTipC), (std::vector<std::string>{kSmall.name, kLarge.name}));
  std::printf("campaign: %.1f s with the fits alone\n", clock.Seconds());
}

// By hand (BRIDGEFIT_JOINT_LOAD_SUBSET=1; minutes, beyond the suite's
// budget): the same three CTs by their load records with sigma_c each
// board's own (joint = ["J_B", "J_tip_c"]). The CT of twice the sigma_c then
// differs only in what is not shared: the joint fit is accepted on 2 x 2 dof,
// nobody flagged, J_B and J_tip,c cover the truth, and each board's own
// sigma_c covers its own truth (0.45, 0.45, 0.90 MPa).
TEST(JointCampaign, ByHandSigmaCOfEachBoardByTheLoadRoute) {
  if (!std::getenv("BRIDGEFIT_JOINT_LOAD_SUBSET"))
    GTEST_SKIP() << "by hand: BRIDGEFIT_JOINT_LOAD_SUBSET=1 (minutes)";
  const Stopwatch clock;
  std::vector<FitRequest> requests;
  std::vector<const FitRun*> runs;
  std::vector<std::string> names;
  for (const Ct& ct : {kSmall, kLarge, kOther}) {
    requests.push_back(Get(ct).request);
    runs.push_back(&Get(ct).run);
    names.push_back(ct.name);
  }
  const JointFitRun joint = RunJointFit(requests, runs, names, nullptr, {false, true, true});
  std::printf("%s", joint.BriefReport().c_str());
  const inverse::FitSummary& f = joint.summary;
  ASSERT_TRUE(f.converged) << f.stop_reason;
  EXPECT_EQ(joint.consistency.degrees_of_freedom, 4);
  EXPECT_TRUE(joint.consistency.consistent()) << joint.consistency.Summary();
  EXPECT_TRUE(joint.flagged.empty());
  EXPECT_TRUE(Covers(f.J_B, kJB));
  EXPECT_TRUE(Covers(f.J_tip_c, kJTip));
  ASSERT_EQ(joint.own_values.size(), 3u);
  const double truth[] = {kSigmaC, kSigmaC, 2.0 * kSigmaC};
  for (std::size_t k = 0; k < 3; ++k) {
    const OwnParameterValue& v = joint.own_values[k];
    EXPECT_TRUE(v.ci95_low <= truth[k] && truth[k] <= v.ci95_high)
        << v.specimen << ": " << v.value << " [" << v.ci95_low << ", " << v.ci95_high << "]";
  }
  std::printf("by hand: %.1f s with the fits alone\n", clock.Seconds());
}

}  // namespace
}  // namespace bridgefit::pipeline
