// Crack growth with bridging on the MPM discretisation (quasi-static):
// no-bridging R = J_tip,c from the run's own energy, J_tip contour
// independence with bridging, agreement with the reduced model, half model
// against the full explicit crack.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "bridgefit/laws/law.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/mpm/growth.hpp"
#include "mpm_test_util.hpp"

namespace bridgefit::mpm {
namespace {

void Print(const char* label, const GrowthResult& g) {
  std::printf("%s: %s, %zu particles, %zu dofs, %.3f s (", label, g.result.message.c_str(),
              g.particles, g.dofs, g.result.wall_s);
  for (const auto& [name, s] : g.stage_seconds) std::printf(" %s %.3f", name.c_str(), s);
  std::printf(" )\n");
  for (std::size_t i = 0; i < g.result.points.size(); i += (g.result.points.size() > 30 ? 4 : 1)) {
    const SimulationPoint& p = g.result.points[i];
    std::printf("  a %.2f mm  R %.1f  R_energy %.1f  J_tip", p.crack_length * 1e3, p.R,
                p.R_energy);
    for (double j : g.J_tip_contours[i]) std::printf(" %.1f", j);
    std::printf("  d_root %.4f mm  root %.2f mm  P %.2f N  d %.4f mm\n", p.delta_root * 1e3,
                p.root_position * 1e3, p.load, p.displacement * 1e3);
  }
}

TEST(MpmGrowth, NoBridgingEnergyReleaseStaysAtJtipc) {
  Scene scene = testing::CtScene();
  for (GrowthSymmetry sym : {GrowthSymmetry::kHalf, GrowthSymmetry::kFull}) {
    GrowthOptions opt;
    opt.cell = 0.0025;
    opt.symmetry = sym;
    opt.contour_cells = {3, 5};
    opt.max_crack_length = 0.060;
    const GrowthResult g = SimulateGrowth(scene, nullptr, 2210.0, opt);
    Print(GrowthSymmetryName(sym), g);
    ASSERT_EQ(g.result.status, RunStatus::kOk) << g.result.message;
  }
}

Scene BridgedCt(double sigma_c, double J_B, double J_tip_c) {
  Scene scene = testing::CtScene();
  scene.fracture = FractureSpec{J_tip_c};
  scene.bridging = BridgingSpec{laws::MakeLinearShape(), {sigma_c, 2 * J_B / sigma_c, J_B}, ""};
  return scene;
}

// Linear interpolation of a point quantity at crack length a.
double At(const std::vector<SimulationPoint>& pts, double a, double SimulationPoint::*field) {
  for (std::size_t i = 0; i + 1 < pts.size(); ++i)
    if (a >= pts[i].crack_length && a <= pts[i + 1].crack_length) {
      const double f = (a - pts[i].crack_length) / (pts[i + 1].crack_length - pts[i].crack_length);
      return (1 - f) * pts[i].*field + f * pts[i + 1].*field;
    }
  return NAN;
}

TEST(MpmGrowth, LinearSofteningAgainstReducedModel) {
  const Scene scene = BridgedCt(1.0e6, 500.0, 2210.0);
  models::ReducedOptions ropt;
  ropt.mesh.resolution = 0.0005;
  const SimulationResult ref = models::SimulateReduced(scene, ropt);
  ASSERT_EQ(ref.status, RunStatus::kOk) << ref.message;
  const laws::BridgingLaw law = scene.bridging->Law();
  for (GrowthSymmetry sym : {GrowthSymmetry::kHalf, GrowthSymmetry::kFull}) {
    GrowthOptions opt;
    opt.cell = 0.0025;
    opt.symmetry = sym;
    opt.contour_cells = {3, 5};
    const GrowthResult g = SimulateGrowth(scene, &law, 2210.0, opt);
    Print(GrowthSymmetryName(sym), g);
    ASSERT_EQ(g.result.status, RunStatus::kOk) << g.result.message;
    std::printf("  steady %d at %.2f mm (reduced %d at %.2f mm)\n", g.result.steady_state_reached,
                g.result.steady_state_crack_length * 1e3, ref.steady_state_reached,
                ref.steady_state_crack_length * 1e3);
    for (const SimulationPoint& p : g.result.points) {
      const double r = At(ref.points, p.crack_length, &SimulationPoint::R);
      const double re = At(ref.points, p.crack_length, &SimulationPoint::R_energy);
      if (static_cast<int>(std::lround(p.crack_length * 1e3)) % 5 == 0)
        std::printf("  a %.1f: R %.1f / %.1f (%.2f%%)  R_energy %.1f / %.1f (%.2f%%)\n",
                    p.crack_length * 1e3, p.R, r, 100 * (p.R / r - 1), p.R_energy, re,
                    100 * (p.R_energy / re - 1));
    }
  }
}

}  // namespace
}  // namespace bridgefit::mpm
