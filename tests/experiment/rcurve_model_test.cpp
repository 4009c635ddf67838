// The energy method on records made by the project's reduced model (issue #6
// acceptance): without bridging R is flat at J_tip,c, with a linear
// softening law the energy method recovers the model's own R_energy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "bridgefit/scene/reference.hpp"
#include "bridgefit/experiment/rcurve.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/models/reduced.hpp"

namespace bridgefit::experiment {
namespace {

constexpr double kJtip = 2210.0;

Scene CtScene() { return ReferenceCtScene(); }  // J_tip,c = kJtip

// Linear loading at a0 up to the first simulated point, then the model's points.
ExperimentRecord RecordFrom(const SimulationResult& sim) {
  ExperimentRecord r;
  r.source = "reduced model";
  const SimulationPoint& first = sim.points.front();
  for (int i = 0; i < 20; ++i) {
    r.load.push_back(first.load * i / 20.0);
    r.displacement.push_back(first.displacement * i / 20.0);
    r.crack_length.push_back(first.crack_length);
  }
  for (const SimulationPoint& p : sim.points) {
    r.load.push_back(p.load);
    r.displacement.push_back(p.displacement);
    r.crack_length.push_back(p.crack_length);
  }
  return r;
}

double Interpolate(const SimulationResult& sim, double a) {
  const auto& p = sim.points;
  for (std::size_t k = 1; k < p.size(); ++k)
    if (p[k].crack_length >= a) {
      const double t = (a - p[k - 1].crack_length) / (p[k].crack_length - p[k - 1].crack_length);
      return p[k - 1].R_energy + t * (p[k].R_energy - p[k - 1].R_energy);
    }
  return p.back().R_energy;
}

class ReducedRecord : public ::testing::Test {
 protected:
  static const models::ReducedModel& Model() {
    static const models::ReducedModel model = [] {
      specimen::CrackPlaneOptions mesh;
      mesh.max_crack_length = 0.08;
      return models::ReducedModel(CtScene(), mesh);
    }();
    return model;
  }
  static RCurveOptions Options() {
    RCurveOptions o;
    o.method = RMethod::kEnergy;
    o.specimen = CtScene().specimen;
    o.material = CtScene().material;
    o.crack_length_noise = 0.0;  // a model's crack lengths are exact: every step is an increment
    return o;
  }
};

TEST_F(ReducedRecord, NoBridgingGivesFlatR) {
  const SimulationResult sim = Model().Run(nullptr, kJtip, {});
  ASSERT_EQ(sim.status, RunStatus::kOk) << sim.message;
  const RCurveResult r = ComputeRCurve(RecordFrom(sim), Options());
  ASSERT_GT(r.curve.size(), 20u);
  double worst = 0.0;
  for (std::size_t i = 0; i < r.curve.size(); ++i) {
    EXPECT_NEAR(r.curve.R[i], kJtip, 0.02 * kJtip) << "a = " << r.curve.crack_length[i];
    worst = std::max(worst, std::abs(r.curve.R[i] / kJtip - 1.0));
  }
  std::printf("reduced-model record without bridging: %zu points, max |R/J_tip,c - 1| = %.3f%%\n",
              r.curve.size(), 100 * worst);
}

TEST_F(ReducedRecord, LinearSofteningRecoversModelEnergyR) {
  const laws::LawShape shape = laws::MakeLinearShape();
  const laws::BridgingLaw law{&shape, 0.45e6, 2.0 * 500.0 / 0.45e6};
  const SimulationResult sim = Model().Run(&law, kJtip, {});
  ASSERT_EQ(sim.status, RunStatus::kOk) << sim.message;
  const RCurveResult r = ComputeRCurve(RecordFrom(sim), Options());
  ASSERT_GT(r.curve.size(), 20u);
  double worst = 0.0;
  for (std::size_t i = 0; i < r.curve.size(); ++i) {
    const double expected = Interpolate(sim, r.curve.crack_length[i]);
    EXPECT_NEAR(r.curve.R[i], expected, 0.02 * expected) << "a = " << r.curve.crack_length[i];
    worst = std::max(worst, std::abs(r.curve.R[i] / expected - 1.0));
  }
  std::printf("reduced-model record, linear law: %zu points, R %.0f..%.0f J/m^2, max |R/R_energy - 1| = %.3f%%\n",
              r.curve.size(), r.curve.R.front(), r.curve.R.back(), 100 * worst);
  // The curve rises: bridging.
  EXPECT_GT(r.curve.R.back(), r.curve.R.front() + 200.0);
}

}  // namespace
}  // namespace bridgefit::experiment
