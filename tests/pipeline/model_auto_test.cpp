// --model auto as a library call: the reduced fit checked by the MPM growth
// simulation and corrected by space mapping when they differ by more than
// the tolerance (moved from the CLI tests FitModelAuto.*, issue 16). Oracle:
// the MDF sample's truth (scene [bridging]: sigma_c 0.45 MPa); MPM at 2.5 mm
// is within about 1% of the converged R here.
#include <gtest/gtest.h>

#include <filesystem>

#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/fit.hpp"

namespace bridgefit::pipeline {
namespace {

namespace fs = std::filesystem;
const fs::path kSample = fs::path(BRIDGEFIT_SOURCE_DIR) / "data_samples" / "mdf_ct";

// `bridgefit fit record_exact.csv --rcurve-load-noise 0.01N
// --rcurve-displacement-noise 0.01um --rcurve-crack-noise 0.001mm --law
// linear --resolution 1mm --no-profile --model auto`.
FitRequest AutoRequest(double tolerance) {
  FitRequest request;
  request.input_path = (kSample / "record_exact.csv").string();
  request.scene_path = (kSample / "scene.toml").string();
  request.scene = io::ReadSceneFile(request.scene_path);
  request.reduction.load_noise = 0.01;
  request.reduction.displacement_noise = 0.01e-6;
  request.reduction.crack_length_noise = 0.001e-3;
  request.reduction_given = true;
  request.resolution = 1e-3;
  request.fit.profile_likelihood = false;
  request.fit.progress = false;
  request.model = ModelChoice::kAuto;
  request.model_tolerance = tolerance;
  return request;
}

TEST(PipelineModelAuto, TheMpmCheckAcceptsTheReducedFitWithinTolerance) {
  const FitRun run = RunFit(AutoRequest(0.03));
  ASSERT_TRUE(run.model_checked);
  const inverse::ModelCheckResult& c = run.model_check;
  std::printf("%s\n", c.outcome.c_str());
  EXPECT_EQ(c.accurate_model, "mpm");
  EXPECT_TRUE(c.accurate_ok);
  EXPECT_FALSE(c.corrected);
  EXPECT_EQ(c.accurate_runs, 1);
  EXPECT_LT(c.discrepancy_at_cheap_optimum, 0.03);
  EXPECT_GT(c.accurate_s, 0.0);
  EXPECT_EQ(run.summary.model, "reduced");
  EXPECT_NE(run.summary.sigma_c.decided_by.find("checked by mpm"), std::string::npos);
  EXPECT_NEAR(run.summary.sigma_c.value, 0.45e6, 0.05 * 0.45e6);
}

TEST(PipelineModelAuto, ATightToleranceCorrectsTheFitTowardTheMpmModel) {
  const FitRun run = RunFit(AutoRequest(0.002));
  ASSERT_TRUE(run.model_checked);
  const inverse::ModelCheckResult& c = run.model_check;
  std::printf("%s\n", c.outcome.c_str());
  EXPECT_TRUE(c.corrected);
  EXPECT_GE(c.accurate_runs, 2);
  EXPECT_LE(c.accurate_runs, 5);
  // The mapped model matches the MPM at the last iterate far better than the
  // reduced one did at its optimum.
  EXPECT_LT(c.discrepancy_final, c.discrepancy_at_cheap_optimum);
  EXPECT_NE(run.summary.sigma_c.decided_by.find("corrected to mpm"), std::string::npos);
  EXPECT_NEAR(run.summary.sigma_c.value, 0.45e6, 0.05 * 0.45e6);
}

}  // namespace
}  // namespace bridgefit::pipeline
