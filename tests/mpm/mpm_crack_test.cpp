// Explicit crack: crack-point openings against the particles beside the
// crack, and frictionless contact under a closing load.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "bridgefit/mpm/solver.hpp"
#include "mpm_test_util.hpp"

namespace bridgefit::mpm {
namespace {

constexpr double kCell = 0.005;

// Opening of the particle pair nearest the crack at x: uy(above) - uy(below).
double ParticleOpening(const Model& model, const ParticleFields& f, double x) {
  double best_above = 1e9, best_below = 1e9, uy_above = NAN, uy_below = NAN;
  for (std::size_t p = 0; p < f.x.size(); ++p) {
    const double y0 = f.y[p] - f.uy[p], x0 = f.x[p] - f.ux[p];
    const double d = std::abs(x0 - x) + std::abs(y0);
    if (y0 > 0.0 && d < best_above) {
      best_above = d;
      uy_above = f.uy[p];
    }
    if (y0 < 0.0 && d < best_below) {
      best_below = d;
      uy_below = f.uy[p];
    }
  }
  EXPECT_LT(best_above, 0.5 * model.grid.cell);
  EXPECT_LT(best_below, 0.5 * model.grid.cell);
  return uy_above - uy_below;
}

TEST(MpmCrack, CrackPointOpeningMatchesNearbyParticles) {
  const Model model = BuildSpecimenModel(testing::CtScene(), kCell, 2);
  SolverOptions opt;
  opt.threads = 1;
  opt.target_displacement = 0.5e-3;
  Solver solver(model, opt);
  const Summary s = solver.Run();
  ASSERT_EQ(s.status, RunStatus::kOk) << s.message;
  const ParticleFields f = solver.Fields();
  // Sub-cell points behind the tip (a0 = 30 mm): the particle pair sits
  // h/4 off the faces, so it adds the strain over h/2, small on free faces.
  for (double x : {-0.02, 0.0, 0.01, 0.02}) {
    const double cod = solver.CodAt(x);
    const double particles = ParticleOpening(model, f, x + 0.25 * kCell);
    const double cod_q = 0.5 * (cod + solver.CodAt(x + 0.5 * kCell));
    EXPECT_GT(cod, 0.0);
    EXPECT_NEAR(cod_q / particles, 1.0, 0.03) << "x = " << x << " COD " << cod_q
                                              << " particles " << particles;
  }
  // Opening decreases towards the tip and vanishes there.
  const auto points = solver.CrackPoints();
  for (std::size_t k = 1; k < points.size(); ++k) {
    if (points[k].x > -0.02) {
      EXPECT_LE(points[k].cod_normal, points[k - 1].cod_normal + 1e-9);
    }
  }
}

struct ClosingResult {
  double min_cod = 0.0;       // most negative crack-point opening [m]
  double min_gap = 0.0;       // min over columns of y(lowest above) - y(highest below)
};

ClosingResult CloseCrack(bool contact) {
  const Model model = BuildSpecimenModel(testing::CtScene(), kCell, 2);
  SolverOptions opt;
  opt.threads = 1;
  opt.contact = contact;
  opt.target_displacement = -0.3e-3;  // pins pushed together
  Solver solver(model, opt);
  const Summary s = solver.Run();
  EXPECT_NE(s.status, RunStatus::kUnstable) << s.message;
  ClosingResult r;
  for (const auto& p : solver.CrackPoints())
    if (p.x > -0.025 && p.x < 0.03) {
      r.min_cod = std::min(r.min_cod, p.cod_normal);
      if (std::getenv("DEBUG")) std::printf("x=%g cod=%g\n", p.x, p.cod_normal);
    }
  // Particle faces: per particle column behind the tip, the gap between the
  // lowest particle above the crack and the highest below, minus the
  // initial gap (h/ppc): negative means the faces passed through each other.
  const ParticleFields f = solver.Fields();
  r.min_gap = 1e9;
  const double sub = kCell / 2;
  for (double x = -0.025 + 0.5 * sub; x < 0.03; x += sub) {
    double lowest_above = 1e9, highest_below = -1e9;
    for (std::size_t p = 0; p < f.x.size(); ++p) {
      const double x0 = f.x[p] - f.ux[p], y0 = f.y[p] - f.uy[p];
      if (std::abs(x0 - x) > 1e-9 || std::abs(y0) > sub) continue;
      if (y0 > 0) lowest_above = std::min(lowest_above, f.y[p]);
      else highest_below = std::max(highest_below, f.y[p]);
    }
    r.min_gap = std::min(r.min_gap, lowest_above - highest_below - sub);
    if (std::getenv("DEBUG")) std::printf("x=%g gap=%g\n", x, lowest_above - highest_below - sub);
  }
  return r;
}

TEST(MpmCrack, FacesDoNotInterpenetrateUnderClosingLoad) {
  const ClosingResult with = CloseCrack(true);
  const ClosingResult without = CloseCrack(false);
  // Without contact the faces pass through each other (the test can fail).
  EXPECT_LT(without.min_cod, -0.1e-3);
  // With contact: interpenetration below 1% of the closing displacement.
  EXPECT_GT(with.min_cod, -3e-6) << "min COD " << with.min_cod;
  EXPECT_GT(with.min_gap, -3e-6) << "min particle gap " << with.min_gap;
}

}  // namespace
}  // namespace bridgefit::mpm
