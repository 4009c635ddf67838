// A bridged crack (BridgedCrackField with the project's bridging laws) as an
// FE-like field on a 1 mm node grid, written in every field format, read back
// and located: the Williams tip within 0.5 mm of the true tip.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <gtest/gtest.h>

#include "bridgefit/dic/fields.hpp"
#include "bridgefit/dic/sequence.hpp"
#include "bridgefit/dic/speckle.hpp"
#include "bridgefit/laws/law.hpp"

namespace bridgefit::dic {
namespace {
namespace fs = std::filesystem;

// MDF-like: E = 3 GPa, nu = 0.3 (plane stress); lengths in mm.
constexpr double kMu = 3e9 / (2 * 1.3);  // Pa

BridgedCrackField MakeBridged(double tip_x, const laws::BridgingLaw& law, double k_over_2mu) {
  BridgedCrackField b;
  b.tip_x = tip_x;
  b.tip_y = 20.5;
  b.k_over_2mu = k_over_2mu;
  b.translation_x = 0.02;
  b.translation_y = -0.01;
  b.rotation = 2e-4;
  b.traction_over_2mu = [law](double delta_mm) { return law.Traction(delta_mm * 1e-3) / (2 * kMu); };
  b.zone_length = 40;
  b.segments = 400;
  b.Solve();
  return b;
}

TEST(BridgedCrackField, MatchesLefmWithoutTractionsAndOpeningIsTheFieldsJump) {
  BridgedCrackField free;
  free.tip_x = 10;
  free.tip_y = 5;
  free.k_over_2mu = 0.03;
  free.Solve();
  ModeICrackField lefm;
  lefm.tip_x = 10;
  lefm.tip_y = 5;
  lefm.k_over_2mu = 0.03;
  for (double x : {-7.0, 3.0, 14.5}) {
    for (double y : {-3.5, 0.5, 6.0}) {
      double u0, v0, u1, v1;
      free(x, y, &u0, &v0);
      lefm(x, y, &u1, &v1);
      EXPECT_NEAR(u0, u1, 1e-12);
      EXPECT_NEAR(v0, v1, 1e-12);
    }
  }
  const laws::LawShape shape = laws::MakeLinearShape();
  const laws::BridgingLaw law{&shape, 2e6, 0.3e-3};
  const BridgedCrackField b = MakeBridged(50, law, 0.025);
  // Tractions close the crack: K at the tip below the applied one.
  EXPECT_LT(b.TipKOver2mu(), 0.9 * b.k_over_2mu);
  EXPECT_GT(b.TipKOver2mu(), 0.0);
  for (double r : {1.0, 5.0, 12.0, 30.0}) {
    double ua, va, ub, vb;
    b(50 - r, 20.5 + 1e-7, &ua, &va);
    b(50 - r, 20.5 - 1e-7, &ub, &vb);
    EXPECT_NEAR(va - vb, b.OpeningAt(r), 2e-3 * b.OpeningAt(r)) << "r = " << r;
    // The traction follows the law at the solved opening.
    EXPECT_NEAR(b.TractionAt(r) * 2 * kMu, law.Traction(b.OpeningAt(r) * 1e-3),
                0.02 * law.sigma_c)
        << "r = " << r;
  }
}

FieldFile Sample(const BridgedCrackField& b, bool px) {
  FieldFile f;
  f.unit = px ? "px" : "mm";
  f.m_per_unit = px ? 0 : 1e-3;
  DisplacementField& d = f.field;
  for (int iy = 0; iy <= 40; ++iy)
    for (int ix = 0; ix <= 100; ++ix) {
      double u, v;
      b(ix, iy, &u, &v);
      d.x.push_back(ix);
      d.y.push_back(iy);
      d.u.push_back(u);
      d.v.push_back(v);
      d.zncc.push_back(1);
      d.iterations.push_back(0);
      d.status.push_back(PointStatus::kOk);
    }
  d.nx = 101;
  d.ny = 41;
  return f;
}

class BridgedRoundTrip : public ::testing::TestWithParam<FieldFormat> {};

TEST_P(BridgedRoundTrip, WilliamsTipWithinHalfAMillimetre) {
  const FieldFormat format = GetParam();
  const fs::path dir = fs::temp_directory_path() /
                       ("bf_bridged_" + std::to_string(::getpid()) + "_" + FieldFormatName(format));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const bool px = format == FieldFormat::kDice;  // DICe is pixel-based: 1 px = 1 mm
  // Two laws (linear and exponential shapes), two strengths, growing tips.
  const laws::LawShape linear = laws::MakeLinearShape();
  const laws::LawShape expo = laws::MakeExponentialShape(3.0);
  struct Case {
    double tip;
    laws::BridgingLaw law;
    double k;
  };
  const std::vector<Case> cases = {{38.4, {&linear, 2e6, 0.3e-3}, 0.025},
                                   {52.7, {&linear, 3e6, 0.5e-3}, 0.03},
                                   {66.2, {&expo, 2.5e6, 0.6e-3}, 0.03}};
  std::vector<FieldFile> frames;
  for (const Case& c : cases) frames.push_back(Sample(MakeBridged(c.tip, c.law, c.k), px));
  if (format == FieldFormat::kNcorr) {
    WriteNcorrFile(dir / "run.mat", frames, {.spacing_px = 4});
  } else {
    for (size_t k = 0; k < frames.size(); ++k)
      WriteFieldFile(dir / ("frame_" + std::to_string(k + 1) + ".txt"), frames[k], format);
  }
  for (bool line : {true, false}) {
    SCOPED_TRACE(line ? "line given" : "path found");
    CrackSequenceOptions o;
    o.scale_m_per_px = px ? 1e-3 : 0;
    o.show_progress = false;
    o.tip.threshold_floor_px = 0.001;
    o.path.min_jump_px = 0.001;
    o.has_line = line;
    o.tip.line = {0, 20.5, 100, 20.5};
    const CrackSequenceResult r = AnalyzeCrackFields(ExpandFieldArguments({dir.string()}), o);
    ASSERT_EQ(r.frames.size(), cases.size());
    for (size_t k = 0; k < cases.size(); ++k) {
      const FrameResult& f = r.frames[k];
      ASSERT_TRUE(f.has_length) << f.image;
      EXPECT_EQ(f.tip.method, TipMethod::kWilliams);
      const double a_mm = f.crack_length_raw_m * 1e3;
      EXPECT_NEAR(a_mm, cases[k].tip, 0.5) << f.image;
      EXPECT_NEAR(f.tip.williams.s_px, cases[k].tip, 0.5) << f.image;
      std::printf("%s %s frame %zu: a %.3f mm (truth %.1f) williams %.3f +- %.3f flags [%s]\n",
                  FieldFormatName(format), line ? "line" : "path", k, a_mm, cases[k].tip,
                  f.tip.williams.s_px, f.uncertainty_m * 1e3, f.Flags().c_str());
    }
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Formats, BridgedRoundTrip,
                         ::testing::Values(FieldFormat::kCsv, FieldFormat::kAramis, FieldFormat::kDice,
                                           FieldFormat::kDavis, FieldFormat::kNcorr),
                         [](const auto& info) { return std::string(FieldFormatName(info.param)); });

}  // namespace
}  // namespace bridgefit::dic
