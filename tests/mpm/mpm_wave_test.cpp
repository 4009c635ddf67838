// Dynamics oracle: the first axial mode of a fixed-free bar has period
// T = 4 L / c with c = sqrt(E / rho) (nu = 0, so plane stress is uniaxial).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "bridgefit/mpm/solver.hpp"

namespace bridgefit::mpm {
namespace {

struct BarResult {
  double period = 0.0;
  double expected = 0.0;
};

BarResult RunBar(ShapeFunction shape, UpdateScheme scheme) {
  const double h = 0.005, L = 0.2, H = 0.02, E = 1e9, rho = 1000.0, v0 = 0.1;
  Model m;
  m.grid = {.x0 = -4 * h, .y0 = -4 * h, .cell = h, .nx = 49, .ny = 13};
  m.ppc = 2;
  m.particles = FillParticles(m.grid, 2, [&](double x, double y) {
    return x > 0.0 && x < L && y > 0.0 && y < H;
  });
  // First mode shape of the fixed-free bar as the initial velocity.
  for (std::size_t p = 0; p < m.particles.size(); ++p)
    m.particles.vx[p] = v0 * std::sin(M_PI * m.particles.x[p] / (2.0 * L));
  m.law = std::make_shared<LinearElastic>(
      LinearElastic::Isotropic(E, 0.0, PlaneCondition::kPlaneStress));
  m.density = rho;
  NodeConstraint fixed;
  fixed.name = "fixed end";
  fixed.constrain_x = true;
  for (int j = 0; j < m.grid.ny; ++j)
    for (int i = 0; i < m.grid.nx; ++i)
      if (m.grid.NodeX(i) <= 1e-12) fixed.nodes.push_back(j * m.grid.nx + i);
  m.constraints = {fixed};
  const double c = std::sqrt(E / rho);
  BarResult r;
  r.expected = 4.0 * L / c;
  SolverOptions opt;
  opt.shape = shape;
  opt.scheme = scheme;
  opt.threads = 1;
  opt.damping = 0.0;
  opt.settle_ratio = 0.0;
  opt.max_time = 2.6 * r.expected;
  opt.contour_cells = {};
  Solver solver(m, opt);
  // Mean axial velocity of the free-end particles; its upward zero crossings
  // are one period apart (linear interpolation between steps).
  std::vector<double> crossings;
  double previous = 0.0;
  bool have_previous = false;
  while (solver.time() < opt.max_time && solver.Step()) {
    const ParticleFields f = solver.Fields();
    double sum = 0.0;
    int count = 0;
    for (std::size_t p = 0; p < f.x.size(); ++p)
      if (f.x[p] > L - h) {
        sum += f.vx[p];
        ++count;
      }
    const double v = sum / count;
    if (have_previous && previous < 0.0 && v >= 0.0) {
      const double frac = -previous / (v - previous);
      crossings.push_back(solver.time() - solver.dt() + frac * solver.dt());
    }
    previous = v;
    have_previous = true;
  }
  EXPECT_EQ(solver.status(), RunStatus::kOk) << solver.message();
  if (crossings.size() >= 2) r.period = crossings[1] - crossings[0];
  std::printf("%s %s: period %.6g s, analytic %.6g s, ratio %.5f\n", ShapeFunctionName(shape),
              UpdateSchemeName(scheme), r.period, r.expected, r.period / r.expected);
  return r;
}

TEST(MpmWave, FixedFreeBarFirstModePeriodGimpUsl) {
  const BarResult r = RunBar(ShapeFunction::kGimp, UpdateScheme::kUSL);
  EXPECT_NEAR(r.period / r.expected, 1.0, 0.02) << "period " << r.period << " s";
}

TEST(MpmWave, FixedFreeBarFirstModePeriodLinearUsf) {
  const BarResult r = RunBar(ShapeFunction::kLinear, UpdateScheme::kUSF);
  EXPECT_NEAR(r.period / r.expected, 1.0, 0.02) << "period " << r.period << " s";
}

TEST(MpmWave, FixedFreeBarFirstModePeriodGimpUsavg) {
  const BarResult r = RunBar(ShapeFunction::kGimp, UpdateScheme::kUSAVG);
  EXPECT_NEAR(r.period / r.expected, 1.0, 0.02) << "period " << r.period << " s";
}

}  // namespace
}  // namespace bridgefit::mpm
