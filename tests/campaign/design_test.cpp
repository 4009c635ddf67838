// Experiment design (issue 19). Oracles: PHYSICS 6 (on the CT of the issues,
// W = 100 mm, a0 = 30 mm, E = 3 GPa, J_tip,c = 2210 J/m^2, linear softening
// sigma_c = 1 MPa, J_B = 500 J/m^2, two independent models put the onset of
// steady state near a = 71 mm); the design's onset at the sample's own size
// is `simulate`'s on the same scene; the smallest size it recommends reaches
// steady state with the fit's three points past the onset when simulated on
// its own, and the next smaller size on the grid does not.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "bridgefit/campaign/design.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/models/reduced.hpp"

namespace bridgefit::campaign {
namespace {

namespace fs = std::filesystem;

Scene MdfSceneWithSigmaC1MPa() {
  Scene scene = io::ReadSceneFile(fs::path(BRIDGEFIT_SOURCE_DIR) / "data_samples/mdf_ct/scene.toml");
  laws::LawScales given;
  given.sigma_c = 1e6;
  given.J_B = 500;
  scene.bridging->scales = laws::CompleteScales(scene.bridging->shape, given);
  return scene;
}

TEST(Design, OnsetAtTheSampleSizeMatchesPhysicsAndSimulate) {
  const Scene scene = MdfSceneWithSigmaC1MPa();
  DesignRequest request;
  request.scene = scene;
  request.sizes = {0.100};
  request.resolution_fraction = 1.0 / 100;  // 1 mm elements at W = 100 mm
  const DesignResult design = RunDesign(request);
  ASSERT_EQ(design.sizes.size(), 1u);
  const DesignSize& d = design.sizes[0];
  ASSERT_TRUE(d.reached) << d.message;
  // PHYSICS 6: near 71 mm (two independent models); our model within 5%.
  EXPECT_NEAR(d.onset, 71e-3, 0.05 * 71e-3) << d.onset;
  // simulate on the same scene (its whole window, 1 mm elements).
  Scene same = scene;
  same.run.max_crack_length.reset();
  models::ReducedOptions options;
  options.mesh.resolution = 1e-3;
  const SimulationResult run = models::SimulateReduced(same, options);
  ASSERT_TRUE(run.steady_state_reached);
  EXPECT_NEAR(d.onset, run.steady_state_crack_length, 1e-3);  // one crack increment
  std::printf("W = 100 mm: onset %.2f mm, window to %.2f mm, %d R points past\n", d.onset * 1e3,
              d.window_end * 1e3, d.points_past);
}

TEST(Design, SmallestRecommendedSizeReachesSteadyStateAndTheNextSmallerDoesNot) {
  DesignRequest request;
  request.scene = MdfSceneWithSigmaC1MPa();
  request.sizes = {0.050, 0.075, 0.100, 0.125, 0.150, 0.200};
  request.resolution_fraction = 1.0 / 50;
  const DesignResult design = RunDesign(request);
  std::printf("%s", design.BriefReport().c_str());
  ASSERT_GT(design.smallest, 0) << "the grid should bracket the answer";
  // The recommended size, simulated on its own scene (not through RunDesign).
  const auto simulate = [&](double size) {
    Scene s = ScaledScene(request.scene, size);
    s.run.max_crack_length.reset();
    models::ReducedOptions options;
    options.mesh.resolution = size / 50;
    return models::SimulateReduced(s, options);
  };
  const double chosen = request.sizes[design.smallest];
  const SimulationResult big = simulate(chosen);
  ASSERT_TRUE(big.steady_state_reached);
  const double a0 = big.points.front().crack_length, end = big.points.back().crack_length;
  int past = 0;
  for (int i = 0; i < request.r_points; ++i)
    past += a0 + i * (end - a0) / (request.r_points - 1) >= big.steady_state_crack_length;
  EXPECT_GE(past, request.points_past_onset);
  const SimulationResult smaller = simulate(request.sizes[design.smallest - 1]);
  bool smaller_identifies = false;
  if (smaller.steady_state_reached) {
    const double b0 = smaller.points.front().crack_length, bend = smaller.points.back().crack_length;
    int n = 0;
    for (int i = 0; i < request.r_points; ++i)
      n += b0 + i * (bend - b0) / (request.r_points - 1) >= smaller.steady_state_crack_length;
    smaller_identifies = n >= request.points_past_onset;
  }
  EXPECT_FALSE(smaller_identifies);
}

TEST(Design, ScalingKeepsTheShapeAndRefusesBadRequests) {
  const Scene scene = MdfSceneWithSigmaC1MPa();
  const Scene half = ScaledScene(scene, 0.05);
  EXPECT_DOUBLE_EQ(half.specimen.width, 0.05);
  EXPECT_DOUBLE_EQ(half.specimen.notch / half.specimen.width, scene.specimen.notch / scene.specimen.width);
  EXPECT_DOUBLE_EQ(half.specimen.height / half.specimen.width, scene.specimen.height / scene.specimen.width);
  EXPECT_DOUBLE_EQ(half.specimen.thickness, scene.specimen.thickness);
  DesignRequest request;
  request.scene = scene;
  std::string why;
  EXPECT_FALSE(request.IsValid(&why));  // no sizes
  request.sizes = {0.1, 0.05};
  EXPECT_FALSE(request.IsValid(&why));
  EXPECT_NE(why.find("ascending"), std::string::npos) << why;
  request.sizes = {0.05, 0.1};
  request.scene.bridging.reset();
  EXPECT_FALSE(request.IsValid(&why));
  EXPECT_NE(why.find("[bridging]"), std::string::npos) << why;
}

// A size whose model run stopped early is unknown, never "bound only": the
// recommendation then says it may be too large (the exponential law's reduced
// model stops early on some DCB sizes).
TEST(Design, SizesThatDidNotRunMakeTheRecommendationUncertain) {
  DesignResult r;
  r.sizes.resize(4);
  r.sizes[0].status = RunStatus::kNotConverged;
  r.sizes[2].identifies = true;
  r.sizes[3].status = RunStatus::kNotConverged;  // above: does not matter
  r.smallest = 2;
  EXPECT_EQ(r.UnknownBelowSmallest(), 1);
  EXPECT_NE(r.Warning().find("may be smaller"), std::string::npos) << r.Warning();
  r.sizes[0].status = RunStatus::kOk;
  EXPECT_EQ(r.UnknownBelowSmallest(), 0);
  EXPECT_TRUE(r.Warning().empty());
  r.smallest = -1;  // none identifies: every size counts
  EXPECT_EQ(r.UnknownBelowSmallest(), 1);
  EXPECT_FALSE(r.Warning().empty());
}

}  // namespace
}  // namespace bridgefit::campaign
