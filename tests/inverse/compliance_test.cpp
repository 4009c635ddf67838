// Compliance along the crack (inverse::FitComplianceAlongCrack) and a
// compliance in series with a simulated specimen
// (SimulationForwardModel::SetSeriesCompliance).
// Oracles: a record built as s C_m(a) + C_s from a closed-form beam
// compliance gives back s and C_s; a series spring moves every point of the
// model's path by C_s P, so the load at d is the series-free model's load at
// d - C_s P.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bridgefit/core/error.hpp"
#include "bridgefit/inverse/compliance.hpp"
#include "bridgefit/inverse/forward_model.hpp"
#include "bridgefit/laws/law.hpp"

namespace bridgefit::inverse {
namespace {

// A DCB with root rotation: C(a) = 8 (a + Delta)^3 / (E b h^3).
double BeamCompliance(double a) {
  const double E = 20e9, b = 0.025, h = 0.0027, delta = 0.003;
  return 8.0 * std::pow(a + delta, 3) / (E * b * h * h * h);
}

ComplianceCurve BeamCurve() {
  ComplianceCurve curve;
  for (double a = 0.030; a <= 0.1000001; a += 0.0005) {
    curve.crack_length.push_back(a);
    curve.compliance.push_back(BeamCompliance(a));
  }
  return curve;
}

TEST(ComplianceAlongCrack, RecoversScaleAndSeriesCompliance) {
  const double s = 0.6, Cs = 1.0e-5;  // m/N; C(40 mm) is about 8.5e-5 m/N
  std::vector<double> a, C;
  std::mt19937 rng(7);
  std::normal_distribution<double> crack_noise(0.0, 0.3e-3);
  for (int i = 0; i < 200; ++i) {
    const double crack = 0.035 + 0.060 * i / 199.0;
    a.push_back(crack);
    C.push_back(s * BeamCompliance(crack) + Cs);
  }
  ComplianceFit fit = FitComplianceAlongCrack(BeamCurve(), a, C, {}, "exact");
  EXPECT_NEAR(fit.scale, s, 1e-3 * s);  // the curve's linear interpolation
  EXPECT_NEAR(fit.series_compliance, Cs, 1e-3 * Cs + 1e-3 * s * BeamCompliance(0.035));
  EXPECT_LT(fit.rms_relative, 1e-4);
  EXPECT_EQ(fit.rows, 200);
  EXPECT_NEAR(fit.crack_min, 0.035, 1e-12);

  // 0.3 mm of crack noise (about 1% in C): still within 1% and 10%.
  for (double& crack : a) crack += crack_noise(rng);
  fit = FitComplianceAlongCrack(BeamCurve(), a, C, {}, "noisy");
  EXPECT_NEAR(fit.scale, s, 0.01 * s);
  EXPECT_NEAR(fit.series_compliance, Cs, 0.1 * Cs);
  EXPECT_GT(fit.rms_relative, 3e-3);

  // The scale alone cannot absorb the series spring: it leaves a residual.
  ComplianceFitOptions scale_only;
  scale_only.fit_series = false;
  const ComplianceFit alone = FitComplianceAlongCrack(BeamCurve(), a, C, scale_only, "noisy");
  EXPECT_EQ(alone.series_compliance, 0.0);
  EXPECT_GT(alone.rms_relative, 2.0 * fit.rms_relative);
}

// A record that asks for a negative series compliance (the model too
// compliant at long cracks): C_s is held at 0 and the scale refitted, with
// the free fit's value kept for the message; equal to the scale-only fit.
TEST(ComplianceAlongCrack, SeriesComplianceNeverNegative) {
  const double s = 0.8, Cs = -6.0e-6;  // m/N, about -7% of C at 40 mm
  std::vector<double> a, C;
  for (int i = 0; i < 150; ++i) {
    const double crack = 0.035 + 0.060 * i / 149.0;
    a.push_back(crack);
    C.push_back(s * BeamCompliance(crack) + Cs);
  }
  const ComplianceFit fit = FitComplianceAlongCrack(BeamCurve(), a, C, {}, "negative");
  EXPECT_TRUE(fit.series_at_bound);
  EXPECT_EQ(fit.series_compliance, 0.0);
  EXPECT_NEAR(fit.series_unconstrained, Cs, 1e-3 * s * BeamCompliance(0.035));
  ComplianceFitOptions scale_only;
  scale_only.fit_series = false;
  const ComplianceFit alone = FitComplianceAlongCrack(BeamCurve(), a, C, scale_only, "negative");
  EXPECT_NEAR(fit.scale, alone.scale, 1e-12);
  EXPECT_NE(fit.Summary().find("negative series compliance"), std::string::npos) << fit.Summary();
  // A bound of its own (e.g. a known fixture compliance) holds the same way.
  ComplianceFitOptions floor;
  floor.min_series_compliance = 2e-6;
  const ComplianceFit held = FitComplianceAlongCrack(BeamCurve(), a, C, floor, "negative");
  EXPECT_EQ(held.series_compliance, 2e-6);
}

TEST(ComplianceAlongCrack, ClearErrors) {
  const ComplianceCurve curve = BeamCurve();
  // Crack lengths outside the model's range: too few rows, named.
  try {
    FitComplianceAlongCrack(curve, {0.2, 0.21, 0.22}, {1e-4, 1e-4, 1e-4}, {}, "record.csv");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("record.csv"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("crack_length"), std::string::npos) << e.what();
  }
  // A compliance that falls as the crack grows is not an elastic specimen's.
  std::vector<double> a, C;
  for (int i = 0; i < 20; ++i) {
    a.push_back(0.04 + 0.002 * i);
    C.push_back(1e-4 / (1.0 + i));
  }
  EXPECT_THROW(FitComplianceAlongCrack(curve, a, C, {}, "record.csv"), Error);
  ComplianceFitOptions bad;
  bad.min_rows = 1;
  EXPECT_FALSE(bad.IsValid(nullptr));
}

// A path of three crack lengths; the model's load with a series spring is
// the series-free model's load at the displacement the spring leaves.
TEST(SeriesCompliance, MovesThePathByCsTimesLoad) {
  auto simulate = [](const laws::BridgingLaw*, double) {
    SimulationResult r;
    r.model = "fake";
    for (auto [a, P, d] : {std::tuple{0.030, 100.0, 1.0e-3}, {0.031, 95.0, 1.2e-3},
                           {0.032, 88.0, 1.5e-3}, {0.033, 80.0, 1.9e-3}}) {
      SimulationPoint p;
      p.crack_length = a, p.load = P, p.displacement = d, p.R = 1000.0, p.delta_root = 0.0;
      r.points.push_back(p);
    }
    return r;
  };
  SimulationForwardModel plain("fake", simulate), sprung("fake", simulate);
  const double Cs = 2e-6;  // m/N: 0.2 mm at 100 N
  sprung.SetSeriesCompliance(Cs);
  EXPECT_EQ(sprung.series_compliance(), Cs);
  const laws::LawShape shape = laws::MakeLinearShape();
  const LawParameters p{.sigma_c = 1e6, .J_B = 0.0, .J_tip_c = 1000.0};
  // On the linear branch: P = d / (C0 + Cs), C0 = 1e-5 m/N.
  ForwardPrediction q = sprung.PredictLoad(shape, p, {0.6e-3});
  ASSERT_TRUE(q.ok()) << q.message;
  EXPECT_NEAR(q.load[0], 0.6e-3 / (1e-5 + Cs), 1e-9);
  // Along the path: at the second point moved by Cs P (1.2 + 0.19 mm) the
  // load is that point's; half way to the third, half way between loads.
  q = sprung.PredictLoad(shape, p, {1.2e-3 + Cs * 95.0, 0.5 * (1.39e-3 + 1.5e-3 + Cs * 88.0)});
  ASSERT_TRUE(q.ok()) << q.message;
  EXPECT_NEAR(q.load[0], 95.0, 1e-9);
  EXPECT_NEAR(q.load[1], 91.5, 1e-9);
  EXPECT_NEAR(q.crack_length_physical[1], 0.0315, 1e-12);
  // The series-free model at the same displacement gives a different load.
  const ForwardPrediction r = plain.PredictLoad(shape, p, {1.2e-3 + Cs * 95.0});
  ASSERT_TRUE(r.ok());
  EXPECT_LT(r.load[0], 94.0);
}

}  // namespace
}  // namespace bridgefit::inverse
