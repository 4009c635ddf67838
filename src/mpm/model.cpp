#include "bridgefit/mpm/model.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/specimen/calibrations.hpp"

namespace bridgefit::mpm {

ParticleSeed FillParticles(const GridSpec& grid, int ppc,
                           const std::function<bool(double, double)>& inside) {
  ParticleSeed seed;
  const double sub = grid.cell / ppc;
  const double volume = sub * sub;
  for (int j = 0; j + 1 < grid.ny; ++j)
    for (int sj = 0; sj < ppc; ++sj) {
      const double y = grid.NodeY(j) + (sj + 0.5) * sub;
      for (int i = 0; i + 1 < grid.nx; ++i)
        for (int si = 0; si < ppc; ++si) {
          const double x = grid.NodeX(i) + (si + 0.5) * sub;
          if (!inside(x, y)) continue;
          seed.x.push_back(x);
          seed.y.push_back(y);
          seed.volume.push_back(volume);
          seed.vx.push_back(0.0);
          seed.vy.push_back(0.0);
        }
    }
  return seed;
}

void Model::Validate() const {
  BF_CHECK_INPUT(law != nullptr, "the model has no constitutive law");
  BF_CHECK_INPUT(density > 0.0, "density must be positive for the explicit MPM solver",
                 {.field = "material.density", .value = fmt::format("{:g}", density),
                  .expected = "> 0 kg/m^3 for the stationary explicit run (e.g. density = "
                              "\"609 kg/m^3\"); the quasi-static growth run (a scene with "
                              "[fracture]) needs none"});
  BF_CHECK_INPUT(grid.cell > 0.0 && grid.nx >= 4 && grid.ny >= 4, "grid too small");
  BF_CHECK_INPUT(ppc >= 1 && ppc <= 8, "particles per cell must be 1..8",
                 {.field = "ppc", .value = std::to_string(ppc)});
  BF_CHECK_INPUT(particles.size() > 0, "the model has no particles");
  BF_CHECK_INPUT(thickness > 0.0, "thickness must be positive");
  const double h = grid.cell;
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const double fx = (particles.x[p] - grid.x0) / h, fy = (particles.y[p] - grid.y0) / h;
    BF_CHECK_INPUT(fx > 1.0 && fy > 1.0 && fx < grid.nx - 2.0 && fy < grid.ny - 2.0,
                   "a particle lies within one cell of the grid edge",
                   {.value = fmt::format("({:g}, {:g}) m", particles.x[p], particles.y[p])});
  }
  const int nodes = static_cast<int>(grid.NodeCount());
  for (const auto& c : constraints)
    for (int n : c.nodes)
      BF_CHECK_INPUT(n >= 0 && n < nodes, "constraint node out of the grid", {.field = c.name});
  BF_CHECK_INPUT(load_constraint < static_cast<int>(constraints.size()),
                 "load constraint index out of range");
  BF_CHECK_INPUT(crack.empty() || crack.size() >= 2, "a crack needs at least two points");
}

namespace {

// Grid aligned with x = 0 on node lines and y = 0 on cell centres (the crack
// plane lies between particle rows, never through a node).
GridSpec MakeGrid(double xmin, double xmax, double ymax, double h, bool half = false) {
  GridSpec g;
  g.cell = h;
  const int margin = 3;
  const int i0 = static_cast<int>(std::floor(xmin / h + 1e-9)) - margin;
  const int i1 = static_cast<int>(std::ceil(xmax / h - 1e-9)) + margin;
  const int k = static_cast<int>(std::floor(-ymax / h - 0.5 + 1e-9)) - margin;
  g.x0 = i0 * h;
  g.nx = i1 - i0 + 1;
  g.y0 = (k + 0.5) * h;
  g.ny = 2 * (-k) ;
  if (half) {
    // Half model: node row j = margin on the symmetry plane y = 0.
    const int top = static_cast<int>(std::ceil(ymax / h - 1e-9)) + margin;
    g.y0 = -margin * h;
    g.ny = top + margin + 1;
  }
  return g;
}

std::vector<std::array<double, 2>> StraightCrack(double mouth, double tip, double h) {
  std::vector<double> xs;
  const double step = 0.5 * h;
  for (double x = tip; x > mouth - 1e-12; x -= step) xs.push_back(x);
  if (xs.back() > mouth + 1e-12) xs.push_back(mouth);
  std::reverse(xs.begin(), xs.end());
  bool has_zero = false;
  for (double x : xs) has_zero |= std::abs(x) < 1e-9 * h;
  if (!has_zero && mouth < 0.0 && tip > 0.0) {
    xs.push_back(0.0);
    std::sort(xs.begin(), xs.end());
  }
  std::vector<std::array<double, 2>> crack;
  for (double x : xs) crack.push_back({x, 0.0});
  return crack;
}

// Saxena-Hudak E'BC (for the frequency estimate only).
double SaxenaHudak(double u) {
  u = std::clamp(u, 0.2, 0.9);
  const double r = (1.0 + u) / (1.0 - u);
  return r * r *
         (2.1630 + 12.219 * u - 20.065 * u * u - 0.9925 * u * u * u + 20.609 * std::pow(u, 4) -
          9.9314 * std::pow(u, 5));
}

Model BuildModel(const Scene& scene, double cell, int ppc, PinModel pins, bool half) {
  const SpecimenSpec& s = scene.specimen;
  BF_CHECK_INPUT(cell > 0.0, "cell size must be positive", {.field = "cell"});
  BF_CHECK_INPUT(ppc >= 1 && ppc <= 8, "particles per cell must be 1..8",
                 {.field = "ppc", .value = std::to_string(ppc)});
  Model m;
  m.ppc = ppc;
  m.half = half;
  m.plane = s.plane;
  m.density = scene.material.density;
  m.law = std::make_shared<LinearElastic>(LinearElastic::FromMaterial(scene.material, s.plane));
  m.effective_modulus = specimen::EffectiveModulus(scene.material, s.plane);
  const double h = cell;
  if (s.type == SpecimenType::kCT) {
    const double W = s.width;
    const double H = s.height > 0.0 ? s.height : 1.2 * W;
    const double a0 = s.notch;
    BF_CHECK_INPUT(W / h >= 8.0, "cell too coarse for the specimen",
                   {.field = "cell", .value = fmt::format("{:g} mm", h * 1e3),
                    .expected = fmt::format("<= W/8 = {:g} mm", W / 8 * 1e3)});
    m.thickness = s.thickness;
    m.description = fmt::format("CT W={:g} mm a0={:g} mm cell={:g} mm ppc={}", W * 1e3,
                                a0 * 1e3, h * 1e3, ppc);
    m.grid = MakeGrid(-0.25 * W, W, 0.5 * H, h, half);
    const double pin_y = 0.275 * W, radius = 0.125 * W;
    const bool holes = pins == PinModel::kHoles;
    m.particles = FillParticles(m.grid, ppc, [&](double x, double y) {
      if (x < -0.25 * W || x > W || std::abs(y) > 0.5 * H) return false;
      if (half && y <= 0.0) return false;
      if (holes && std::hypot(x, std::abs(y) - pin_y) < radius) return false;
      return true;
    });
    for (int side = 0; side < (half ? 1 : 2); ++side) {
      NodeConstraint c;
      const double sign = side == 0 ? 1.0 : -1.0;
      c.name = side == 0 ? "top pin" : "bottom pin";
      c.constrain_y = true;
      c.share_y = 0.5 * sign;
      const double yc = sign * pin_y;
      if (holes) {
        c.constrain_x = true;
        c.radial = true;
        c.unilateral = true;
        c.center_x = 0.0;
        c.center_y = yc;
        for (int j = 0; j < m.grid.ny; ++j)
          for (int i = 0; i < m.grid.nx; ++i)
            if (std::hypot(m.grid.NodeX(i), m.grid.NodeY(j) - yc) < radius)
              c.nodes.push_back(j * m.grid.nx + i);
      } else {
        const int i = static_cast<int>(std::lround(-m.grid.x0 / h));
        const int j = static_cast<int>(std::lround((yc - m.grid.y0) / h));
        c.nodes.push_back(j * m.grid.nx + i);
      }
      m.constraints.push_back(std::move(c));
    }
    m.load_constraint = 0;
    if (!half) m.crack = StraightCrack(-0.25 * W - h, a0, h);
    // omega_1 ~ sqrt(k / m_eff): k = E'/(E'BC) per unit thickness, m_eff a
    // quarter of the specimen mass.
    const double k = m.effective_modulus / SaxenaHudak(a0 / W);
    const double mass = m.density * 1.25 * W * H;
    m.lowest_frequency = std::sqrt(k / (0.25 * mass));
  } else {
    const double L = s.length, arm = s.height, a0 = s.notch;
    BF_CHECK_INPUT(arm / h >= 2.0, "cell too coarse for the DCB arm",
                   {.field = "cell", .value = fmt::format("{:g} mm", h * 1e3),
                    .expected = fmt::format("<= h/2 = {:g} mm", arm / 2 * 1e3)});
    m.thickness = s.width;
    m.description = fmt::format("DCB L={:g} mm h={:g} mm a0={:g} mm cell={:g} mm ppc={}",
                                L * 1e3, arm * 1e3, a0 * 1e3, h * 1e3, ppc);
    m.grid = MakeGrid(0.0, L, arm, h, half);
    m.particles = FillParticles(m.grid, ppc, [&](double x, double y) {
      return x >= 0.0 && x <= L && std::abs(y) <= arm && (!half || y > 0.0);
    });
    for (int side = 0; side < (half ? 1 : 2); ++side) {
      NodeConstraint c;
      const double sign = side == 0 ? 1.0 : -1.0;
      c.name = side == 0 ? "top arm end" : "bottom arm end";
      c.constrain_y = true;
      c.share_y = 0.5 * sign;
      for (int j = 0; j < m.grid.ny; ++j)
        for (int i = 0; i < m.grid.nx; ++i) {
          const double x = m.grid.NodeX(i), y = m.grid.NodeY(j);
          if (x <= 1e-12 && y * sign > 0.0 && std::abs(y) <= arm + 1.5 * h)
            c.nodes.push_back(j * m.grid.nx + i);
        }
      m.constraints.push_back(std::move(c));
    }
    m.load_constraint = 0;
    if (!half) m.crack = StraightCrack(-h, a0, h);
    // Cantilever arm of length a0: omega = 1.875^2 sqrt(E I / (rho A a0^4)).
    const double E = scene.material.AxialModulus();
    m.lowest_frequency = 3.516 * std::sqrt(E * arm * arm / (12.0 * m.density)) / (a0 * a0);
  }
  m.Validate();
  return m;
}

}  // namespace

Model BuildSpecimenModel(const Scene& scene, double cell, int ppc, PinModel pins) {
  return BuildModel(scene, cell, ppc, pins, false);
}

Model BuildHalfSpecimenModel(const Scene& scene, double cell, int ppc) {
  return BuildModel(scene, cell, ppc, PinModel::kHoles, true);
}
}  // namespace bridgefit::mpm
