// Experiment design from a fit file (issue 19). A synthetic record of the
// MDF sample's CT (W = 100 mm, sigma_c 0.45 MPa, J_B 500 J/m^2, stopped at
// a = 70 mm: it never reaches steady state) goes through the product's chain
// (synth -> in-process energy R curve -> load-displacement fit -> fit file),
// so its J_B is only a lower bound. Oracles:
// (a) the design read from the file uses the file's bound values: the scene
// route given the same values explicitly gives identical onsets; (b) the
// region's smallest size, simulated on its own with the region's worst-case
// law, reaches steady state with the fit's three points past the onset, and
// the next smaller size on the grid does not; (c) a file without a law, a
// non-HDF5 file and an R-curve file are refused naming the file and what is
// expected; a campaign.h5 gives its joint fit, or says which specimen it used.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <utility>

#include "../cli/cli_helpers.hpp"
#include "bridgefit/campaign/design_fit.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/pipeline/fit_file.hpp"
#include "bridgefit/pipeline/synth.hpp"

namespace bridgefit::campaign {
namespace {

namespace fs = std::filesystem;

const fs::path kDir = fs::temp_directory_path() / ("bf_design_fit_" + std::to_string(::getpid()));

// The fit file of the small CT, made once for every test here.
class DesignFit : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::create_directories(kDir);
    // The MDF sample's scene and truth (W = 100 mm, sigma_c 0.45 MPa, J_B
    // 500 J/m^2), stopped at a = 70 mm, before steady state.
    const Scene truth =
        io::ReadSceneFile(fs::path(BRIDGEFIT_SOURCE_DIR) / "data_samples/mdf_ct/scene.toml");
    pipeline::SynthRequest synth;
    synth.scene = truth;
    synth.seed = 1;
    synth.resolution = 0.25e-3;
    synth.frames = 0;
    const pipeline::SynthTest test = pipeline::MakeSyntheticTest(synth);
    { std::ofstream(kDir / "record.csv") << test.record_csv; }
    request_ = new pipeline::FitRequest;
    request_->input_path = (kDir / "record.csv").string();
    request_->scene = truth;
    request_->scene.bridging.reset();  // the truth is not the fit's to know
    request_->resolution = 1e-3;
    request_->law = laws::LawFamily::kLinear;
    request_->target = inverse::FitTarget::kLoad;  // sigma_c to a few % (the MDF sample's route)
    run_ = new pipeline::FitRun(pipeline::RunFit(*request_));
    pipeline::WriteFitFile((kDir / "fit.h5").string(), *request_, *run_);
  }
  static void TearDownTestSuite() {
    delete request_;
    delete run_;
    fs::remove_all(kDir);
  }
  static pipeline::FitRequest* request_;
  static pipeline::FitRun* run_;
};
pipeline::FitRequest* DesignFit::request_ = nullptr;
pipeline::FitRun* DesignFit::run_ = nullptr;

std::string ErrorOf(const fs::path& path) {
  try {
    ReadDesignLaw(path);
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for " << path;
  return "";
}

bool Identifies(const SimulationResult& run, int r_points, int past_needed) {
  if (!run.steady_state_reached || run.status != RunStatus::kOk) return false;
  const double a0 = run.points.front().crack_length, end = run.points.back().crack_length;
  int past = 0;
  for (int i = 0; i < r_points; ++i)
    past += a0 + i * (end - a0) / (r_points - 1) >= run.steady_state_crack_length;
  return past >= past_needed;
}

TEST_F(DesignFit, ReadsTheBoundAndTheSpecimenTheFitUsed) {
  const inverse::FitSummary& s = run_->summary;
  ASSERT_FALSE(s.J_B.identified) << "the W = 50 mm CT should give J_B as a bound: " << s.verdict;
  ASSERT_GT(s.J_B.lower_bound, 0);
  const pipeline::FittedLaw law = ReadDesignLaw(kDir / "fit.h5");
  EXPECT_EQ(law.J_B.lower_bound, s.J_B.lower_bound);
  EXPECT_EQ(law.sigma_c.value, s.sigma_c.value);
  EXPECT_EQ(law.sigma_c.ci95_low, s.sigma_c.ci95_low);
  EXPECT_EQ(law.J_tip_c.value, s.J_tip_c.value);
  EXPECT_FALSE(law.J_B.identified);
  EXPECT_EQ(law.shape.family, laws::LawFamily::kLinear);
  EXPECT_EQ(law.scene.specimen.width, request_->scene.specimen.width);
  EXPECT_EQ(law.scene.specimen.notch, request_->scene.specimen.notch);
  EXPECT_EQ(law.scene.material.E, request_->scene.material.E);
  std::printf("fit: sigma_c %.4g [%.4g, %.4g] MPa, J_B >= %.4g J/m^2, J_tip,c %.5g J/m^2\n",
              s.sigma_c.value * 1e-6, s.sigma_c.ci95_low * 1e-6, s.sigma_c.ci95_high * 1e-6,
              s.J_B.lower_bound, s.J_tip_c.value);
}

// (a) and (b).
TEST_F(DesignFit, BoundLawMatchesTheSceneRouteAndTheRegionsSmallestSizeIsTheFirstThatIdentifies) {
  FitDesignRequest request;
  request.law = ReadDesignLaw(kDir / "fit.h5");
  ASSERT_FALSE(run_->summary.J_B.identified) << run_->summary.verdict;
  request.sizes = {0.050, 0.100, 0.150, 0.200, 0.250, 0.300};
  request.resolution_fraction = 1.0 / 50;
  request.grid = 2;             // the corners
  request.jb_cap_factor = 1.5;  // J_B from the bound to 1.5 x the bound
  const FitDesignResult r = RunFitDesign(request);
  std::printf("%s", r.BriefReport().c_str());

  // (a) the scene route with the fit's bound values given explicitly.
  DesignRequest scene_route;
  scene_route.scene = request_->scene;
  scene_route.scene.fracture = FractureSpec{run_->summary.J_tip_c.value};
  BridgingSpec bridging;
  bridging.shape = laws::MakeLinearShape();
  laws::LawScales given;
  given.sigma_c = run_->summary.sigma_c.value;
  given.J_B = run_->summary.J_B.lower_bound;
  bridging.scales = laws::CompleteScales(bridging.shape, given);
  scene_route.scene.bridging = bridging;
  scene_route.sizes = request.sizes;
  scene_route.resolution_fraction = request.resolution_fraction;
  const DesignResult expected = RunDesign(scene_route);
  ASSERT_EQ(r.sizes.size(), expected.sizes.size());
  for (std::size_t k = 0; k < r.sizes.size(); ++k) {
    EXPECT_EQ(r.sizes[k].bound_identifies, expected.sizes[k].identifies) << k;
    if (expected.sizes[k].reached)
      EXPECT_EQ(r.sizes[k].bound_onset, expected.sizes[k].onset) << k;
    else
      EXPECT_TRUE(std::isnan(r.sizes[k].bound_onset)) << k;
  }
  EXPECT_EQ(r.smallest_bound, expected.smallest);
  EXPECT_EQ(r.bound.J_B, run_->summary.J_B.lower_bound);
  EXPECT_EQ(r.region.size(), 4u);

  // (b) the region's answer, checked by the reduced model on its own.
  ASSERT_GT(r.smallest_region, 0) << "the grid should bracket the region's answer";
  EXPECT_LE(r.smallest_bound, r.smallest_region);  // the bound law lies at the region's low J_B
  const int k = r.smallest_region;
  const int worst = r.sizes[k - 1].worst_law;
  ASSERT_GE(worst, 0);
  const auto simulate = [&](double size) {
    Scene s = ScaledScene(DesignScene(request, r.region[worst]), size);
    models::ReducedOptions options;
    options.mesh.resolution = size * request.resolution_fraction;
    return models::SimulateReduced(s, options);
  };
  EXPECT_TRUE(Identifies(simulate(request.sizes[k]), request.r_points, request.points_past_onset));
  EXPECT_FALSE(
      Identifies(simulate(request.sizes[k - 1]), request.r_points, request.points_past_onset));
}

// (c) bad input names the file and what is expected.
TEST_F(DesignFit, RefusesFilesThatHoldNoFitNamingThem) {
  {
    io::H5Writer no_law(kDir / "no_law.h5");
    no_law.WriteAttribute("/fit", "kind", "fit");
    no_law.WriteAttribute("/fit", "verdict", "no bridging detected");
    no_law.Commit();
  }
  std::string e = ErrorOf(kDir / "no_law.h5");
  EXPECT_NE(e.find("no_law.h5"), std::string::npos) << e;
  EXPECT_NE(e.find("no fitted bridging law"), std::string::npos) << e;
  EXPECT_NE(e.find("bridgefit fit --out"), std::string::npos) << e;

  { std::ofstream(kDir / "text.h5") << "crack_length [mm], R [J/m^2]\n30, 2210\n"; }
  e = ErrorOf(kDir / "text.h5");
  EXPECT_NE(e.find("text.h5"), std::string::npos) << e;
  EXPECT_NE(e.find("not an HDF5 file"), std::string::npos) << e;
  EXPECT_NE(e.find("bridgefit fit --out"), std::string::npos) << e;

  {
    io::H5Writer rcurve(kDir / "rcurve.h5");
    RCurve curve;
    curve.method = "energy";
    curve.crack_length = {0.03, 0.031};
    curve.R = {2210, 2300};
    io::WriteRecordH5(rcurve, curve, "/rcurve");
    rcurve.Commit();
  }
  e = ErrorOf(kDir / "rcurve.h5");
  EXPECT_NE(e.find("rcurve.h5"), std::string::npos) << e;
  EXPECT_NE(e.find("R curve"), std::string::npos) << e;
  EXPECT_NE(e.find("fit it first"), std::string::npos) << e;

  e = ErrorOf(kDir / "missing.h5");
  EXPECT_NE(e.find("missing.h5"), std::string::npos) << e;
}

// A fit file written before /fit/scene and /fit/law_shape: the scene file
// its `scene` attribute names and the family's default shape, said so.
TEST_F(DesignFit, OlderFitFileTakesTheSceneItNamesAndSaysSo) {
  const std::string scene =
      (fs::path(BRIDGEFIT_SOURCE_DIR) / "data_samples/mdf_ct/scene.toml").string();
  {
    io::H5Writer old(kDir / "old.h5");
    old.WriteAttribute("/fit", "kind", "fit");
    old.WriteAttribute("/fit", "scene", scene);
    old.WriteAttribute("/fit", "law", "linear");
    for (const auto& [name, value] :
         {std::pair<const char*, double>{"sigma_c", 0.45e6}, {"J_B", NAN}, {"J_tip_c", 2210.0}}) {
      const std::string pg = std::string("/fit/parameters/") + name;
      old.WriteAttribute(pg, "value", value);
      old.WriteAttribute(pg, "lower_bound", std::isnan(value) ? 210.0 : NAN);
      old.WriteAttribute(pg, "identified", std::isnan(value) ? 0.0 : 1.0);
    }
    old.Commit();
  }
  const pipeline::FittedLaw law = ReadDesignLaw(kDir / "old.h5");
  EXPECT_NE(law.note.find("predates /fit/scene"), std::string::npos) << law.note;
  EXPECT_NE(law.note.find("default"), std::string::npos) << law.note;
  EXPECT_EQ(law.scene.specimen.width, 0.100);
  EXPECT_EQ(law.J_B.lower_bound, 210.0);
  EXPECT_FALSE(law.J_B.identified);
  EXPECT_FALSE(law.scene.bridging.has_value());  // the scene's own law is not the fit's
}

// A campaign.h5 (its layout: each specimen's fit file under /specimens/NAME,
// /campaign/statistics, /campaign/joint): the joint fit when there is one,
// else the specimen giving the campaign's J_B bound, named.
TEST_F(DesignFit, CampaignFileGivesItsJointFitOrNamesTheSpecimen) {
  const auto campaign = [&](const fs::path& path, bool joint) {
    io::H5Writer file(path);
    file.CopyFileInto(kDir / "fit.h5", "/specimens/A");
    file.CopyFileInto(kDir / "fit.h5", "/specimens/B");
    file.WriteStrings("/campaign/specimen_names", {"A", "B"});
    file.WriteAttribute("/campaign/statistics/J_B", "bound_from", "B");
    if (joint) {
      file.WriteStrings("/campaign/joint/specimens", {"A", "B"});
      for (const char* name : {"sigma_c", "J_B", "delta_c", "J_tip_c"}) {
        const std::string pg = std::string("/campaign/joint/parameters/") + name;
        const bool jb = std::string(name) == "J_B";
        file.WriteAttribute(pg, "value",
                            jb                               ? 640.0
                            : std::string(name) == "sigma_c" ? 1.1e6
                                                             : 2200.0);
        file.WriteAttribute(pg, "ci95_low", jb ? 450.0 : NAN);
        file.WriteAttribute(pg, "ci95_high", jb ? 860.0 : NAN);
        file.WriteAttribute(pg, "lower_bound", NAN);
        file.WriteAttribute(pg, "identified", 1.0);
      }
    }
    file.Commit();
  };
  campaign(kDir / "campaign.h5", false);
  const pipeline::FittedLaw one = ReadDesignLaw(kDir / "campaign.h5");
  EXPECT_NE(one.note.find("specimen B"), std::string::npos) << one.note;
  EXPECT_EQ(one.J_B.lower_bound, run_->summary.J_B.lower_bound);
  campaign(kDir / "joint.h5", true);
  const pipeline::FittedLaw joint = ReadDesignLaw(kDir / "joint.h5");
  EXPECT_NE(joint.note.find("joint fit of 2"), std::string::npos) << joint.note;
  EXPECT_TRUE(joint.J_B.identified);
  EXPECT_EQ(joint.J_B.value, 640.0);
  EXPECT_EQ(joint.sigma_c.value, 1.1e6);
  EXPECT_EQ(joint.scene.specimen.width, request_->scene.specimen.width);
}

// The command: the fit file's route prints both answers and draws the chart;
// the scene's route refuses the fit-only flags.
TEST_F(DesignFit, CommandPrintsBothAnswersAndDrawsTheChart) {
  const bridgefit::testing::CliResult r = bridgefit::testing::RunCli(
      "design " + (kDir / "fit.h5").string() + " --size 50mm:100mm:50mm --grid 2 --chart " +
      (kDir / "chart").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("bound law: sigma_c"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("lower bound up to a cap of 2 x the bound"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("every law of the region"), std::string::npos) << r.out;
  EXPECT_GT(fs::file_size(kDir / "chart" / "onset.png"), 1000u);
  const bridgefit::testing::CliResult bad =
      bridgefit::testing::RunCli("design " + std::string(BRIDGEFIT_SOURCE_DIR) +
                                 "/data_samples/mdf_ct/scene.toml --size 50mm:60mm:10mm --chart x");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("take a fit file"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace bridgefit::campaign
