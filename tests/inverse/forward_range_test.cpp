// SimulationForwardModel::Predict at the ends of the simulated crack
// lengths (issue 17). Oracle: a hand-made simulation (R known at every
// point) and a reducer that, like a data method applied to the model's
// record, starts two points after initiation.
#include <gtest/gtest.h>

#include <cmath>

#include "bridgefit/inverse/forward_model.hpp"
#include "bridgefit/laws/law.hpp"

namespace bridgefit::inverse {
namespace {

constexpr double kNotch = 0.050, kStep = 0.625e-3;

SimulationResult HandMade() {
  SimulationResult result;
  result.model = "hand-made";
  for (int k = 0; k < 40; ++k) {
    SimulationPoint p;
    p.crack_length = kNotch + k * kStep;
    p.R = p.R_energy = 2000.0 + 10.0 * k;
    p.delta_root = 1e-5 * k;
    result.points.push_back(p);
  }
  return result;
}

// As-data: the model's R from the third point (a0 + 1.25 mm) on, as a data
// method's reduction starts a step or two after initiation.
SimulationForwardModel AsDataModel() {
  SimulationForwardModel model("hand-made", [](const laws::BridgingLaw*, double) { return HandMade(); });
  model.SetReducer([](const SimulationResult& r) {
    SimulationForwardModel::Reduced out;
    for (std::size_t k = 2; k < r.points.size(); ++k) {
      out.crack_length.push_back(r.points[k].crack_length);
      out.R.push_back(r.points[k].R + 5.0);
      out.point.push_back(static_cast<int>(k));
    }
    return out;
  });
  return model;
}

// A data point between the notch and the reduction's first point (here
// a0 + 0.57 mm, below a0 + 1.25 mm by more than a step) takes the first
// reduced value; before, every such run failed ("outside the simulated
// crack lengths") and with it the model error's coarser solves of a DCB.
TEST(ForwardRange, AsDataHoldsTheFirstReducedValueDownToTheNotch) {
  const SimulationForwardModel model = AsDataModel();
  const laws::LawShape shape = laws::MakeLinearShape();
  const LawParameters p{0.45e6, 500.0, 2210.0};
  const ForwardPrediction at = model.Predict(shape, p, {kNotch + 0.57e-3, kNotch + 2.5e-3}, RKind::kAsData);
  ASSERT_TRUE(at.ok()) << at.message;
  ASSERT_EQ(at.R.size(), 2u);
  EXPECT_DOUBLE_EQ(at.R[0], 2000.0 + 20.0 + 5.0);  // the first reduced point's
  EXPECT_DOUBLE_EQ(at.R[1], 2000.0 + 40.0 + 5.0);  // a0 + 4 steps, exact
  // Below the model's initial crack length: still out of range (the
  // pipeline fits lengths read short at the notch, pipeline::HoldAtNotch).
  const ForwardPrediction below = model.Predict(shape, p, {kNotch - 0.7e-3}, RKind::kAsData);
  EXPECT_FALSE(below.ok());
  // The model's own R starts at the notch: no reach below it.
  const ForwardPrediction energy = model.Predict(shape, p, {kNotch - 0.01e-3}, RKind::kEnergy);
  EXPECT_FALSE(energy.ok());
}

}  // namespace
}  // namespace bridgefit::inverse
