// --model auto as a library call: the reduced fit checked by the MPM growth
// simulation and corrected by space mapping when they differ by more than
// the tolerance (moved from the CLI tests FitModelAuto.*, issue 16). Oracle:
// the MDF sample's truth (scene [bridging]: sigma_c 0.45 MPa); MPM at 2.5 mm
// is within about 1% of the converged R here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "bridgefit/inverse/model_error.hpp"
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
  request.mpm_cell = 2.5e-3;  // the rules below at a given cell; --mpm-cell auto at the end
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

// Issue 17: a correction to MPM is accepted only when MPM itself is
// converged enough for it (MPM at half the cell, at the corrected
// parameters, moves R by less than half the correction). At 1 mm the
// reduced model and MPM at 2.5 mm differ by about 1% and MPM's own step to
// 1.25 mm is about half of that (measured 0.52%): whichever side of the
// rule it falls, the output must follow it - rejected: the reduced fit,
// with a warning that says why; accepted: the corrected fit, no warning.
TEST(PipelineModelAuto, ACorrectionFollowsMpmsOwnConvergence) {
  const FitRun run = RunFit(AutoRequest(0.002));
  ASSERT_TRUE(run.model_checked);
  const inverse::ModelCheckResult& c = run.model_check;
  std::printf("%s\n%s\nMPM convergence %.4f\n", c.outcome.c_str(), run.model_check_warning.c_str(),
              run.mpm_convergence);
  EXPECT_TRUE(c.corrected);
  EXPECT_GE(c.accurate_runs, 2);
  EXPECT_LE(c.accurate_runs, 5);
  ASSERT_TRUE(std::isfinite(run.mpm_convergence));
  const bool corrected_fit = run.summary.sigma_c.decided_by.find("corrected to mpm") != std::string::npos;
  if (run.mpm_convergence > 0.5 * c.discrepancy_at_cheap_optimum) {
    EXPECT_FALSE(corrected_fit);
    EXPECT_NE(run.model_check_warning.find("not converged enough"), std::string::npos)
        << run.model_check_warning;
    EXPECT_NE(run.BriefReport().find("warning: --model auto"), std::string::npos);
  } else {
    EXPECT_TRUE(corrected_fit);
    EXPECT_TRUE(run.model_check_warning.empty()) << run.model_check_warning;
  }
  EXPECT_NEAR(run.summary.sigma_c.value, 0.45e6, 0.05 * 0.45e6);
}

// A reduced model far coarser than MPM's own error (4 mm elements): the
// correction is larger than MPM's step to half its cell, so it is accepted
// and the fit is the corrected model's.
TEST(PipelineModelAuto, ACorrectionLargerThanMpmsOwnErrorIsAccepted) {
  FitRequest request = AutoRequest(0.002);
  request.resolution = 4e-3;
  const FitRun run = RunFit(request);
  ASSERT_TRUE(run.model_checked);
  const inverse::ModelCheckResult& c = run.model_check;
  std::printf("%s\n%s\nMPM convergence %.4f\n", c.outcome.c_str(), run.model_check_warning.c_str(),
              run.mpm_convergence);
  EXPECT_TRUE(c.corrected);
  ASSERT_TRUE(std::isfinite(run.mpm_convergence));
  EXPECT_LE(run.mpm_convergence, 0.5 * c.discrepancy_at_cheap_optimum);
  EXPECT_TRUE(run.model_check_warning.empty()) << run.model_check_warning;
  EXPECT_LT(c.discrepancy_final, c.discrepancy_at_cheap_optimum);
  EXPECT_NE(run.summary.sigma_c.decided_by.find("corrected to mpm"), std::string::npos);
  EXPECT_NEAR(run.summary.sigma_c.value, 0.45e6, 0.05 * 0.45e6);
  // Issue 17, model error in every interval: the corrected fit's is MPM's own
  // (order 1 from 2.5 and 1.25 mm) through a refit without it. On this
  // noise-free record the predicted bias moves sigma_c and J_tip,c towards
  // the truth (2230 J/m^2 at 2.5 mm, bias +17 J/m^2, truth 2210), and the
  // total intervals hold it.
  const inverse::ModelErrorEstimate& e = run.model_error;
  std::printf("%s\n", e.Summary().c_str());
  EXPECT_EQ(e.model, "mpm");
  ASSERT_TRUE(e.estimated()) << e.reason;
  const struct {
    const char* name;
    const inverse::ParameterEstimate& estimate;
    double truth;
  } checks[] = {{"sigma_c", run.summary.sigma_c, 0.45e6}, {"J_tip_c", run.summary.J_tip_c, 2210.0}};
  for (const auto& [name, p, truth] : checks) {
    std::printf("%s = %.6g, bias %.4g, total [%.6g, %.6g], statistical [%.6g, %.6g]\n",
                name, p.value, p.model_bias, p.ci95_low, p.ci95_high,
                p.statistical_ci95_low, p.statistical_ci95_high);
    ASSERT_TRUE(std::isfinite(p.model_bias));
    EXPECT_LT(std::abs(p.value - p.model_bias - truth), std::abs(p.value - truth)) << name;
    EXPECT_LE(p.ci95_low, truth) << name;
    EXPECT_GE(p.ci95_high, truth) << name;
    EXPECT_LE(p.ci95_low, p.statistical_ci95_low) << name;
    EXPECT_GE(p.ci95_high, p.statistical_ci95_high) << name;
  }
}

// An MPM cell too coarse for the scene is said, never silent: 25 mm cells
// leave fewer than 10 cells over the MDF sample's 40 mm of growth.
TEST(PipelineModelAuto, AnMpmCellTooCoarseForTheSceneIsWarned) {
  FitRequest request = AutoRequest(0.03);
  request.mpm_cell = 5e-3;
  const FitRun run = RunFit(request);
  ASSERT_TRUE(run.model_checked);
  std::printf("%s\n%s\n", run.model_check.outcome.c_str(), run.model_check_warning.c_str());
  EXPECT_NE(run.model_check_warning.find("too coarse for this scene"), std::string::npos)
      << run.model_check_warning;
}

// The same rule when MPM is the fit's model (--model mpm): the model error
// is not estimated for MPM, and its reason says the cell is too coarse.
TEST(PipelineModelAuto, AnMpmFitOnACellTooCoarseForTheSceneIsWarned) {
  FitRequest request = AutoRequest(0.03);
  request.model = ModelChoice::kMpm;
  request.mpm_cell = 5e-3;  // 8 cells over the data's 40 mm of growth
  const FitRun run = RunFit(request);
  std::printf("%s\n", run.model_error.reason.c_str());
  EXPECT_FALSE(run.model_error.estimated());
  EXPECT_NE(run.model_error.reason.find("too coarse for this specimen"), std::string::npos)
      << run.model_error.reason;
  EXPECT_NE(run.model_error.reason.find("cells over the data's"), std::string::npos);
}

// --mpm-cell auto (issue 17: the MPM cell chosen as the reduced model's
// size is): the coarsest valid cell (2.5 mm here: 40 mm of growth) is kept
// when MPM's own error there, twice its R step to half the cell (order 1),
// is below half the tolerance; measured on this sample: step 0.52%, error
// 1.03%.
TEST(PipelineModelAuto, AutoCellKeepsTheCoarsestCellWhenMpmsOwnErrorIsSmall) {
  FitRequest request = AutoRequest(0.03);
  request.mpm_cell = NAN;
  const FitRun run = RunFit(request);
  ASSERT_TRUE(run.model_checked);
  std::printf("%s\n%s\n", run.mpm_cell_choice.c_str(), run.model_check_warning.c_str());
  EXPECT_DOUBLE_EQ(run.mpm_cell, 2.5e-3);
  ASSERT_TRUE(std::isfinite(run.mpm_convergence));
  EXPECT_LE(2.0 * run.mpm_convergence, 0.5 * 0.03);
  EXPECT_NE(run.mpm_cell_choice.find("accepted"), std::string::npos) << run.mpm_cell_choice;
  EXPECT_TRUE(run.model_check_warning.empty()) << run.model_check_warning;
  EXPECT_NE(run.BriefReport().find("--mpm-cell auto: 2.5 mm"), std::string::npos);
}

// A tolerance MPM at 2.5 mm cannot resolve (half of 1.5% is below its 1.03%
// error): the cell is halved; at 1.25 mm the error is, to order 1, the
// step that led there (about 0.5%), below 0.75%: accepted at 1.25 mm. The
// same rule against a tolerance the cell cannot meet within three halvings
// would warn (AutoCellThatCannotMeetTheToleranceIsWarned).
TEST(PipelineModelAuto, AutoCellIsHalvedWhenMpmsOwnErrorIsAboveHalfTheTolerance) {
  FitRequest request = AutoRequest(0.015);
  request.mpm_cell = NAN;
  const FitRun run = RunFit(request);
  ASSERT_TRUE(run.model_checked);
  std::printf("%s\n%s\n", run.mpm_cell_choice.c_str(), run.model_check_warning.c_str());
  EXPECT_DOUBLE_EQ(run.mpm_cell, 1.25e-3);
  ASSERT_TRUE(std::isfinite(run.mpm_convergence));
  EXPECT_LE(2.0 * run.mpm_convergence, 0.5 * 0.015);
  EXPECT_NE(run.mpm_cell_choice.find("2.5 mm"), std::string::npos) << run.mpm_cell_choice;
  EXPECT_NE(run.mpm_cell_choice.find("accepted"), std::string::npos) << run.mpm_cell_choice;
  EXPECT_EQ(run.model_check_warning.find("--mpm-cell auto"), std::string::npos)
      << run.model_check_warning;
  EXPECT_NEAR(run.summary.sigma_c.value, 0.45e6, 0.05 * 0.45e6);
}

// A tolerance the cell cannot meet within the halvings allowed (none here,
// so that the test stays cheap; the default is three): the finest tried is
// used and the output says the check cannot resolve differences that
// small, never silently.
TEST(PipelineModelAuto, AutoCellThatCannotMeetTheToleranceIsWarned) {
  FitRequest request = AutoRequest(0.015);
  request.mpm_cell = NAN;
  request.mpm_cell_halvings = 0;
  const FitRun run = RunFit(request);
  ASSERT_TRUE(run.model_checked);
  std::printf("%s\n%s\n", run.mpm_cell_choice.c_str(), run.model_check_warning.c_str());
  EXPECT_DOUBLE_EQ(run.mpm_cell, 2.5e-3);
  EXPECT_GT(2.0 * run.mpm_convergence, 0.5 * 0.015);
  EXPECT_NE(run.mpm_cell_choice.find("not converged enough"), std::string::npos);
  EXPECT_NE(run.model_check_warning.find("--mpm-cell auto"), std::string::npos)
      << run.model_check_warning;
  EXPECT_NE(run.BriefReport().find("warning: --model auto"), std::string::npos);
}

}  // namespace
}  // namespace bridgefit::pipeline
