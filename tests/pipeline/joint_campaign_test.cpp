// Issue 19's synthetic campaign: CT specimens of two sizes made by the reduced
// model at a 4x finer element size than the fit's, one linear-softening law
// (sigma_c 1 MPa, J_B 500 J/m^2, J_tip,c 2210 J/m^2; `bridgefit design` on
// the MDF scene: W = 50 mm never reaches steady state, W = 100 mm does at
// 70.5 mm), 0.5% load noise, 0.3 mm crack-reading noise. Each record goes
// through the product's chain (in-process energy R curve -> fit), then the
// joint fit of all four.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/joint_fit.hpp"
#include "bridgefit/pipeline/synth.hpp"

namespace bridgefit::pipeline {
namespace {
namespace fs = std::filesystem;

Scene Sized(double width, double sigma_c) {
  Scene s = io::ReadSceneFile(std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/mdf_ct/scene.toml");
  const double f = width / s.specimen.width;
  s.specimen.width *= f;
  s.specimen.height *= f;
  s.specimen.notch *= f;
  s.run.max_crack_length = 0.95 * s.specimen.width - 2e-3;
  s.bridging->scales.sigma_c = sigma_c;
  s.bridging->scales.delta_c = 2.0 * s.bridging->scales.J_B / sigma_c;
  return s;
}

struct Specimen {
  FitRequest request;
  FitRun run;
};

Specimen Make(double width, double sigma_c, std::uint64_t seed) {
  SynthRequest synth;
  synth.scene = Sized(width, sigma_c);
  synth.seed = seed;
  synth.resolution = 0.25e-3;
  synth.frames = 0;
  synth.load_noise = 0.005;
  const SynthTest test = MakeSyntheticTest(synth);
  Specimen s;
  const fs::path file = fs::temp_directory_path() /
                        fmt::format("bf_joint_campaign_{}_{}_{}.csv", ::getpid(), width * 1e3, seed);
  { std::ofstream(file) << test.record_csv; }
  s.request.input_path = file.string();
  s.request.scene = synth.scene;
  s.request.scene.bridging.reset();  // the truth is not the fit's to know
  s.request.resolution = 1e-3;
  s.request.law = laws::LawFamily::kLinear;
  s.run = RunFit(s.request);
  fs::remove(file);
  return s;
}

constexpr double kSigmaC = 1.0e6, kJB = 500.0, kJTip = 2210.0;

void Print(const char* what, const inverse::FitSummary& f) {
  std::printf("%-10s sigma_c %.4g [%.4g, %.4g] MPa, J_B %.4g [%.4g, %.4g] (bound %.4g), J_tip,c %.5g [%.5g, %.5g]\n",
              what, f.sigma_c.value * 1e-6, f.sigma_c.ci95_low * 1e-6, f.sigma_c.ci95_high * 1e-6,
              f.J_B.value, f.J_B.ci95_low, f.J_B.ci95_high, f.J_B.lower_bound, f.J_tip_c.value,
              f.J_tip_c.ci95_low, f.J_tip_c.ci95_high);
}

// The small specimens alone: J_B only as a lower bound, the bound below the
// truth (it was 824 and 1118 J/m^2 against 500 before the bound used the
// elastic-zone R and was lowered for its uncertainty). The joint fit of all
// four: one law (the test accepts), J_B identified, every interval covering
// the truth.
TEST(JointCampaign, TwoSizesIdentifyWhatTheSmallOnesCannot) {
  std::vector<Specimen> specimens;
  for (std::uint64_t seed : {1, 2}) specimens.push_back(Make(0.050, kSigmaC, seed));
  for (std::uint64_t seed : {3, 4}) specimens.push_back(Make(0.100, kSigmaC, seed));
  std::vector<FitRequest> requests;
  std::vector<const FitRun*> runs;
  const std::vector<std::string> names = {"W50-1", "W50-2", "W100-1", "W100-2"};
  for (std::size_t k = 0; k < specimens.size(); ++k) {
    Print(names[k].c_str(), specimens[k].run.summary);
    requests.push_back(specimens[k].request);
    runs.push_back(&specimens[k].run);
  }
  // The small ones alone: J_B only as a lower bound, below the truth.
  for (int k : {0, 1}) {
    EXPECT_FALSE(specimens[k].run.summary.J_B.identified) << names[k];
    EXPECT_LE(specimens[k].run.summary.J_B.lower_bound, kJB) << names[k];
  }
  const JointFitRun joint = RunJointFit(requests, runs, names);
  std::printf("%s", joint.BriefReport().c_str());
  const inverse::FitSummary& f = joint.summary;
  EXPECT_TRUE(joint.consistency.consistent()) << joint.consistency.Summary();
  EXPECT_TRUE(joint.flagged.empty());
  ASSERT_TRUE(f.J_B.identified) << f.verdict;
  // Issue 19 asks J_B within 5% and sigma_c within 3% of the truth. On this
  // route (energy R curves from the noisy records) the joint fit gives J_B
  // 653 [448, 862] J/m^2 and sigma_c 1.54 [0.82, 2.71] MPa (measured
  // 2026-12-02): the truth inside, the accuracy not reached - each R curve
  // alone constrains sigma_c only to a factor of 5-50. Not asserted here;
  // the load-displacement joint fit (not built) is the route for it.
  EXPECT_LE(f.J_B.ci95_low, kJB);
  EXPECT_GE(f.J_B.ci95_high, kJB);
  EXPECT_LE(f.sigma_c.ci95_low, kSigmaC);
  EXPECT_GE(f.sigma_c.ci95_high, kSigmaC);
  EXPECT_LE(f.J_tip_c.ci95_low, kJTip);
  EXPECT_GE(f.J_tip_c.ci95_high, kJTip);
}

}  // namespace
}  // namespace bridgefit::pipeline
