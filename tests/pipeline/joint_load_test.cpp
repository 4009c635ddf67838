// The joint fit of load-displacement records (issue 19; pipeline/joint_fit.hpp):
// CT records made by `synth`'s reduced model (0.25 mm elements, 4x finer
// than the fit's) with one linear law (sigma_c 0.45 MPa, J_B 500 J/m^2,
// J_tip,c 2210 J/m^2) and 0.5% load noise, on boards whose modulus is off the
// scene's by -5%, 0 and +5% (the fit's scene states the nominal modulus:
// each specimen's own fit calibrates it). Each record is fitted alone to its
// load-displacement record (fit_to = "load-displacement", initial-slope
// calibration), then jointly with its modulus scale and series compliance
// held at its own calibrated values. Oracles: parameter recovery and the
// likelihood-ratio test (one law accepted; a board of twice the sigma_c
// rejected and flagged); a mixed campaign refused by name.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/inverse/joint.hpp"
#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/joint_fit.hpp"
#include "bridgefit/pipeline/synth.hpp"

namespace bridgefit::pipeline {
namespace {
namespace fs = std::filesystem;

constexpr double kSigmaC = 0.45e6, kJB = 500.0, kJTip = 2210.0;

struct Board {
  double notch;           // [m]
  double modulus_factor;  // the board's modulus over the scene's nominal one
  double sigma_c;         // [Pa]
  std::uint64_t seed;
};

struct Specimen {
  FitRequest request;
  FitRun run;
};

Scene Truth(const Board& b) {
  Scene s = io::ReadSceneFile(std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/mdf_ct/scene.toml");
  s.specimen.notch = b.notch;
  s.run.max_crack_length = b.notch + 0.030;
  s.bridging->scales.sigma_c = b.sigma_c;
  s.bridging->scales.delta_c = 2.0 * kJB / b.sigma_c;  // linear law: J_B = sigma_c delta_c / 2
  return s;
}

// `quick`: a fit at 2 mm without profiles, for a test that needs only a
// load-displacement fit to exist (the refusal below).
Specimen Make(const Board& b, bool quick = false) {
  SynthRequest synth;
  synth.scene = Truth(b);
  synth.scene.material.E *= b.modulus_factor;
  synth.seed = b.seed;
  synth.resolution = 0.25e-3;
  synth.frames = 0;
  synth.growth_rows = 120;
  synth.load_noise = 0.005;
  const SynthTest test = MakeSyntheticTest(synth);
  const fs::path file =
      fs::temp_directory_path() / fmt::format("bf_joint_load_{}_{}.csv", ::getpid(), b.seed);
  { std::ofstream(file) << test.record_csv; }
  Specimen s;
  s.request.input_path = file.string();
  s.request.scene = Truth(b);  // the nominal modulus: the calibration's to find the board's
  s.request.scene.bridging.reset();  // the truth is not the fit's to know
  s.request.resolution = 1e-3;
  s.request.law = laws::LawFamily::kLinear;
  s.request.target = inverse::FitTarget::kLoad;
  s.request.calibration = inverse::ComplianceCalibrationMode::kInitialSlope;
  s.request.fit.starts = 2;
  if (quick) s.request.resolution = 2e-3, s.request.fit.profile_likelihood = false;
  const Stopwatch clock;
  s.run = RunFit(s.request);
  fs::remove(file);
  std::printf("seed %d (a0 %.0f mm, E x %.2f, sigma_c %.2f MPa): fitted alone in %.1f s, "
              "modulus factor %.4f\n",
              static_cast<int>(b.seed), b.notch * 1e3, b.modulus_factor, b.sigma_c * 1e-6,
              clock.Seconds(), s.run.calibration.modulus_factor);
  return s;
}

// Each board fitted once for every test of this file.
const Specimen& Get(const Board& b) {
  static std::map<std::uint64_t, Specimen> made;
  auto it = made.find(b.seed);
  if (it == made.end()) it = made.emplace(b.seed, Make(b)).first;
  return it->second;
}

const Board kBoards[] = {{0.030, 1.00, kSigmaC, 11}, {0.035, 1.05, kSigmaC, 12},
                         {0.040, 0.95, kSigmaC, 13}};
const Board kOther = {0.035, 1.00, 2.0 * kSigmaC, 14};  // another board: twice sigma_c

JointFitRun Joint(const std::vector<Board>& boards, std::vector<std::string>* names = nullptr) {
  std::vector<FitRequest> requests;
  std::vector<const FitRun*> runs;
  std::vector<std::string> own;
  for (const Board& b : boards) {
    requests.push_back(Get(b).request);
    runs.push_back(&Get(b).run);
    own.push_back(fmt::format("CT-{}", b.seed));
  }
  if (names) *names = own;
  return RunJointFit(requests, runs, own);
}

void Print(const std::string& what, const inverse::FitSummary& f) {
  std::printf("%-8s sigma_c %.4g [%.4g, %.4g] MPa, J_B %.4g [%.4g, %.4g] (bound %.4g), "
              "J_tip,c %.5g [%.5g, %.5g]\n",
              what.c_str(), f.sigma_c.value * 1e-6, f.sigma_c.ci95_low * 1e-6,
              f.sigma_c.ci95_high * 1e-6, f.J_B.value, f.J_B.ci95_low, f.J_B.ci95_high,
              f.J_B.lower_bound, f.J_tip_c.value, f.J_tip_c.ci95_low, f.J_tip_c.ci95_high);
  if (std::isfinite(f.sigma_c.model_bias) || std::isfinite(f.J_tip_c.model_bias))
    std::printf("         statistical: sigma_c [%.4g, %.4g] MPa (model bias %+.3g), J_tip,c [%.5g, "
                "%.5g] (model bias %+.3g)\n",
                f.sigma_c.statistical_ci95_low * 1e-6, f.sigma_c.statistical_ci95_high * 1e-6,
                f.sigma_c.model_bias * 1e-6, f.J_tip_c.statistical_ci95_low,
                f.J_tip_c.statistical_ci95_high, f.J_tip_c.model_bias);
}

bool Covers(const inverse::ParameterEstimate& e, double truth) {
  return e.ci95_low <= truth && truth <= e.ci95_high;
}
double Width(const inverse::ParameterEstimate& e) { return e.ci95_high - e.ci95_low; }
// A single fit's statistical interval (its total one holds its model error
// too, which the joint interval does not).
double StatisticalWidth(const inverse::ParameterEstimate& e) {
  return std::isfinite(e.statistical_ci95_low) ? e.statistical_ci95_high - e.statistical_ci95_low
                                               : Width(e);
}

// The identity the profiled modulus scale rests on: the reduced model with
// every modulus x g and a series compliance C_s is the model at g = 1 under
// (sigma_c, g J_B, g J_tip,c) at displacements x g with C_s x g, its R / g.
TEST(JointLoad, ModulusScaleNeedsNoRebuild) {
  const Scene scene = Truth(kBoards[0]);
  models::ReducedOptions options;
  options.mesh.resolution = 1e-3;
  const double g = 1.04, series = 2e-7;  // [m/N]
  Scene stiffer = scene;
  stiffer.material.E *= g;
  const auto base = inverse::MakeReducedForwardModel(scene, options);
  auto built = inverse::MakeReducedForwardModel(stiffer, options);
  built->SetSeriesCompliance(series);
  inverse::FitData rows;
  rows.target = inverse::FitTarget::kLoad;
  for (int i = 1; i <= 60; ++i) rows.displacement.push_back(0.024e-3 * i), rows.load.push_back(1.0);
  const inverse::ModulusProfiledLoadModel scaled(*base, series, rows);
  const laws::LawShape linear = laws::MakeLinearShape();
  const inverse::LawParameters law{kSigmaC, kJB, kJTip};
  const inverse::ForwardPrediction want = built->PredictLoad(linear, law, rows.displacement);
  const inverse::ForwardPrediction got = scaled.PredictLoadAtScale(linear, law, rows.displacement, g);
  ASSERT_TRUE(want.ok() && got.ok()) << want.message << got.message;
  ASSERT_EQ(want.load.size(), got.load.size());
  double worst_load = 0.0, worst_R = 0.0, worst_a = 0.0;
  for (std::size_t i = 0; i < want.load.size(); ++i) {
    worst_load = std::max(worst_load, std::abs(got.load[i] / want.load[i] - 1.0));
    worst_R = std::max(worst_R, std::abs(got.R_physical[i] / want.R_physical[i] - 1.0));
    worst_a = std::max(worst_a, std::abs(got.crack_length_physical[i] - want.crack_length_physical[i]));
  }
  std::printf("scaled vs rebuilt: load %.2g, R %.2g (relative), crack length %.2g m\n", worst_load,
              worst_R, worst_a);
  EXPECT_LT(worst_load, 1e-6);
  EXPECT_LT(worst_R, 1e-6);
  EXPECT_LT(worst_a, 1e-9);
  // The path covers the growth (not only the linear branch).
  EXPECT_GT(want.crack_length_physical.back(), scene.specimen.notch + 10e-3);
}

// The profiled scale (Brent's minimiser) is the scan's least chi^2: a record
// of a board 3% stiffer than the model, at the truth's law and a law 10%
// off it, against 401 scales over the +-5% span.
TEST(JointLoad, ProfiledScaleIsTheLeastChi2OfAScan) {
  const Scene scene = Truth(kBoards[0]);
  models::ReducedOptions options;
  options.mesh.resolution = 1e-3;
  const auto base = inverse::MakeReducedForwardModel(scene, options);
  const laws::LawShape linear = laws::MakeLinearShape();
  const inverse::LawParameters truth{kSigmaC, kJB, kJTip};
  inverse::FitData rows;
  rows.target = inverse::FitTarget::kLoad;
  for (int i = 1; i <= 60; ++i) rows.displacement.push_back(0.02e-3 * i);
  const inverse::ModulusProfiledLoadModel probe(*base, 0.0, [&] {
    inverse::FitData r = rows;
    r.load.assign(r.displacement.size(), 1.0);
    return r;
  }());
  const inverse::ForwardPrediction record =
      probe.PredictLoadAtScale(linear, truth, rows.displacement, 1.03);
  ASSERT_TRUE(record.ok()) << record.message;
  rows.load = record.load;
  const inverse::ModulusProfiledLoadModel scaled(*base, 0.0, rows);
  for (const inverse::LawParameters& law : {truth, inverse::LawParameters{1.1 * kSigmaC, kJB, 0.9 * kJTip}}) {
    const auto chi2 = [&](double g) {
      const inverse::ForwardPrediction q = scaled.PredictLoadAtScale(linear, law, rows.displacement, g);
      double sum = 0.0;
      for (std::size_t i = 0; i < q.load.size(); ++i) sum += std::pow(q.load[i] - rows.load[i], 2);
      return q.ok() ? sum : INFINITY;
    };
    double best_g = NAN, best = INFINITY;
    for (int i = -200; i <= 200; ++i) {
      const double g = std::exp(0.05 * i / 200.0), c = chi2(g);
      if (c < best) best = c, best_g = g;
    }
    const double g = scaled.ProfiledScale(linear, law);
    std::printf("sigma_c %.3g MPa: profiled scale %.6f (chi^2 %.4g), scan's least %.6f (chi^2 %.4g)\n",
                law.sigma_c * 1e-6, g, chi2(g), best_g, best);
    EXPECT_LE(chi2(g), best * (1.0 + 1e-9) + 1e-12);
    if (law.sigma_c == kSigmaC) EXPECT_NEAR(g, 1.03, 1e-4);
  }
}

TEST(JointLoad, OneLawOnBoardsOfDifferentModulusIsRecovered) {
  for (const Board& b : kBoards) {
    const FitRun& run = Get(b).run;
    Print(fmt::format("CT-{}", b.seed), run.summary);
    // The calibration finds each board's modulus (the nuisance the joint fit holds).
    ASSERT_TRUE(run.calibration.calibrated());
    EXPECT_NEAR(run.calibration.modulus_factor, b.modulus_factor, 0.01 * b.modulus_factor);
  }
  const JointFitRun joint = Joint({kBoards[0], kBoards[1], kBoards[2]});
  std::printf("%s", joint.BriefReport().c_str());
  Print("joint", joint.summary);
  const inverse::FitSummary& f = joint.summary;
  ASSERT_TRUE(f.converged) << f.stop_reason;
  EXPECT_EQ(f.target, inverse::FitTarget::kLoad);
  EXPECT_TRUE(joint.consistency.consistent()) << joint.consistency.Summary();
  EXPECT_EQ(joint.consistency.degrees_of_freedom, 6);
  EXPECT_TRUE(joint.flagged.empty());
  // Each board's modulus factor, profiled at the joint law, is the board's.
  ASSERT_EQ(joint.specimen_modulus_factor.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_NEAR(joint.specimen_modulus_factor[k], kBoards[k].modulus_factor,
                0.01 * kBoards[k].modulus_factor);
  ASSERT_TRUE(f.sigma_c.identified && f.J_tip_c.identified) << f.verdict;
  EXPECT_TRUE(Covers(f.sigma_c, kSigmaC));
  // J_tip,c: the joint interval (with its model error, +1.1 J/m^2 predicted)
  // missed the truth by 0.5 J/m^2 here (2205.7 [2200.5, 2209.5]; statistical
  // [2201.9, 2209.2]); with seeds +100 the statistical interval missed too
  // (2205.5 [2201.8, 2209.2]), with +200 it covered (2206.9 [2203.1,
  // 2210.7]); 8 of the 9 single fits also land below 2210 (mean -4.4 J/m^2,
  // 0.2%), and at 0.5 mm elements the joint estimate is 2204.7: a bias of
  // this route (records from 0.25 mm elements) that neither the statistical
  // interval nor the Richardson model error (1, 2, 4 mm) holds
  // (docs/CAMPAIGN.md). Asserted: within 0.5%.
  EXPECT_NEAR(f.J_tip_c.value, kJTip, 0.005 * kJTip);
  if (f.J_B.identified) EXPECT_TRUE(Covers(f.J_B, kJB));
  else EXPECT_LE(f.J_B.lower_bound, kJB);
  // Narrower than every specimen's own statistical interval.
  for (const Board& b : kBoards) {
    const inverse::FitSummary& alone = Get(b).run.summary;
    ASSERT_TRUE(alone.sigma_c.identified && alone.J_tip_c.identified) << b.seed;
    EXPECT_LT(Width(f.sigma_c), StatisticalWidth(alone.sigma_c)) << b.seed;
    EXPECT_LT(Width(f.J_tip_c), StatisticalWidth(alone.J_tip_c)) << b.seed;
  }
}

TEST(JointLoad, AnotherLawIsRejectedAndFlagged) {
  const JointFitRun joint = Joint({kBoards[0], kBoards[1], kOther});
  std::printf("%s", joint.BriefReport().c_str());
  EXPECT_FALSE(joint.consistency.consistent()) << joint.consistency.Summary();
  EXPECT_LT(joint.consistency.p_value, 1e-4);
  EXPECT_EQ(joint.flagged, (std::vector<std::string>{"CT-14"}));
  ASSERT_TRUE(joint.summary_without_flagged.has_value());
  EXPECT_TRUE(joint.consistency_without_flagged.consistent())
      << joint.consistency_without_flagged.Summary();
}

// A campaign of R-curve and load fits is refused, naming the specimen and why.
// (Quick fits: the refusal comes before any work; under ctest each test is
// its own process, and the full fits cost this test 12.5 s.)
TEST(JointLoad, MixedCampaignIsRefusedByName) {
  const Specimen first = Make(kBoards[0], true), second = Make(kBoards[1], true);
  std::vector<FitRequest> requests = {first.request, second.request};
  FitRun as_r_curve = second.run;
  as_r_curve.load_data.reset();
  requests[1].target = inverse::FitTarget::kRCurve;
  const std::vector<const FitRun*> runs = {&first.run, &as_r_curve};
  try {
    RunJointFit(requests, runs, {"CT-11", "CT-12"});
    FAIL() << "an R-curve fit joined load-displacement fits";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("CT-12"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("like with like"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace bridgefit::pipeline
