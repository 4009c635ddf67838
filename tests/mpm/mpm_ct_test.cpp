// CT specimen in the static limit: load-line compliance against Saxena-Hudak,
// the contour J against K^2/E' from ASTM E399 (a/W = 0.5, the standard's
// K_Ic range), contour independence, and J against the energy release rate
// of the model's own compliance curve (G = P^2/(2B) dC/da).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "bridgefit/mpm/solver.hpp"
#include "mpm_test_util.hpp"

namespace bridgefit::mpm {
namespace {

constexpr double kW = 0.100, kB = 0.0127, kE = 3e9;

Summary RunCt(double notch, double cell, std::vector<int> contours) {
  const Model model = BuildSpecimenModel(testing::CtScene(notch), cell, 2);
  SolverOptions opt;
  opt.threads = 1;  // tests may share the cores: no OpenMP barriers
  opt.target_displacement = 0.5e-3;
  opt.contour_cells = std::move(contours);
  opt.history_every = 200;
  Solver solver(model, opt);
  return solver.Run();
}

class MpmCtStatic : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    summary_ = new Summary(RunCt(0.050, 0.0025, {3, 5}));
    std::printf("%s\n", summary_->BriefReport().c_str());
  }
  static void TearDownTestSuite() {
    delete summary_;
    summary_ = nullptr;
  }
  static Summary* summary_;
};
Summary* MpmCtStatic::summary_ = nullptr;

TEST_F(MpmCtStatic, SettlesQuasiStatically) {
  ASSERT_EQ(summary_->status, RunStatus::kOk) << summary_->message;
  const HistorySample& last = summary_->history.back();
  EXPECT_LT(last.kinetic, 1e-6 * last.strain);
  // Linear elasticity: stored energy = P d / 2 at rest.
  EXPECT_NEAR(last.strain / (0.5 * last.load * last.displacement), 1.0, 0.01);
}

TEST_F(MpmCtStatic, LoadLineComplianceWithin3PercentOfSaxenaHudak) {
  ASSERT_EQ(summary_->status, RunStatus::kOk) << summary_->message;
  const double compliance = summary_->final_load_line_cod / summary_->final_load;
  const double expected = testing::SaxenaHudak(0.5) / (kE * kB);
  EXPECT_NEAR(compliance / expected, 1.0, 0.03)
      << "C = " << compliance << " m/N, Saxena-Hudak " << expected;
}

TEST_F(MpmCtStatic, ContourJWithin3PercentOfE399AndContourIndependent) {
  ASSERT_EQ(summary_->status, RunStatus::kOk) << summary_->message;
  const double K = summary_->final_load / (kB * std::sqrt(kW)) * testing::E399Factor(0.5);
  const double expected = K * K / kE;  // plane stress: E' = E
  ASSERT_EQ(summary_->final_J.size(), 2u);
  for (const JResult& j : summary_->final_J)
    EXPECT_NEAR(j.J / expected, 1.0, 0.03) << j.half_cells << " cells: J = " << j.J
                                           << ", K^2/E' = " << expected;
  EXPECT_NEAR(summary_->final_J[0].J / summary_->final_J[1].J, 1.0, 0.02);
  // No crack-face tractions yet: J_tip = J.
  EXPECT_EQ(summary_->final_J[0].J_tip, summary_->final_J[0].J);
}

TEST(MpmCt, ContourJEqualsEnergyReleaseRateOfTheModelsCompliance) {
  // Coarse cells: the oracle is the model itself (energy balance), not a
  // handbook, so discretisation error cancels. Tips on node lines.
  const double h = 0.005;
  const Summary shorter = RunCt(0.025, h, {2, 3});
  const Summary middle = RunCt(0.030, h, {2, 3});
  const Summary longer = RunCt(0.035, h, {2, 3});
  for (const Summary* s : {&shorter, &middle, &longer})
    ASSERT_EQ(s->status, RunStatus::kOk) << s->message;
  auto compliance = [](const Summary& s) { return s.final_displacement / s.final_load; };
  const double dC_da = (compliance(longer) - compliance(shorter)) / 0.010;
  const double P = middle.final_load;
  const double G = P * P / (2.0 * kB) * dC_da;
  for (const JResult& j : middle.final_J)
    std::printf("J(%d cells) = %.2f J/m^2, G from dC/da = %.2f J/m^2 (ratio %.4f)\n",
                j.half_cells, j.J, G, j.J / G);
  for (const JResult& j : middle.final_J)
    EXPECT_NEAR(j.J / G, 1.0, 0.02) << j.half_cells << " cells: J = " << j.J << ", G = " << G;
}

}  // namespace
}  // namespace bridgefit::mpm
