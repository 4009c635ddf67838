// mpm::Solver::Impl: construction (particle sort, time step, ramp, damping),
// the loading ramp and the crack geometry (node sides, segment buckets).

#include "solver_impl.hpp"

namespace bridgefit::mpm {

Solver::Impl::Impl(Model m, SolverOptions o) : model(std::move(m)), opt(std::move(o)) {
  std::string why;
  if (!opt.IsValid(&why))
    throw Error(ErrorKind::kInput, "invalid MPM options: " + why);
  model.Validate();
  threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();
  h = model.grid.cell;
  inv_h = 1.0 / h;
  x0 = model.grid.x0;
  y0 = model.grid.y0;
  nx = model.grid.nx;
  ny = model.grid.ny;
  N = model.grid.NodeCount();
  for (auto* a : {&gm, &gpx, &gpy, &gfx, &gfy, &gqx, &gqy, &gvx, &gvy, &gdvx, &gdvy})
    a->assign(2 * N, 0.0);
  node_constraint.assign(N, -1);
  for (std::size_t c = 0; c < model.constraints.size(); ++c)
    for (int n : model.constraints[c].nodes) node_constraint[n] = static_cast<int>(c);
  lp = opt.shape == ShapeFunction::kGimp ? 0.5 / model.ppc : 0.0;
  inv_lp = lp > 0.0 ? 1.0 / lp : 0.0;

  // Particles sorted by row then column: each thread's chunk covers a band
  // of grid rows, so its private scatter buffer is a band, not the grid.
  const auto& s = model.particles;
  std::vector<std::size_t> order(s.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const long ra = std::lround(std::floor((s.y[a] - y0) * inv_h * 4.0));
    const long rb = std::lround(std::floor((s.y[b] - y0) * inv_h * 4.0));
    if (ra != rb) return ra < rb;
    return s.x[a] < s.x[b];
  });
  P = s.size();
  for (auto* a : {&px, &py, &vx, &vy, &mass, &vol, &sxx, &syy, &sxy, &hxx, &hxy, &hyx, &hyy,
                  &ux, &uy, &w, &dexx, &deyy, &dgxy})
    a->assign(P, 0.0);
  mask.assign(P, 0);
  for (std::size_t k = 0; k < P; ++k) {
    const std::size_t q = order[k];
    px[k] = s.x[q];
    py[k] = s.y[q];
    vx[k] = s.vx[q];
    vy[k] = s.vy[q];
    vol[k] = s.volume[q];
    mass[k] = s.volume[q] * model.density;
  }
  chunk.resize(threads + 1);
  for (int tt = 0; tt <= threads; ++tt) chunk[tt] = P * tt / threads;
  bands.resize(threads);

  for (const auto& pt : model.crack) {
    cx.push_back(pt[0]);
    cy.push_back(pt[1]);
  }
  const std::size_t nc = cx.size();
  for (auto* a : {&uax, &uay, &ubx, &uby, &ctraction}) a->assign(nc, 0.0);
  node_above.assign(N, 1);
  UpdateCrackGeometry();

  // Time step: CFL on the largest wave speed.
  const double c = model.law->MaxWaveSpeed(model.density);
  BF_CHECK_INPUT(std::isfinite(c) && c > 0.0, "wave speed is not positive");
  // uGIMP nodes at the edge of a particle's support have mass ~ t^2 and
  // stiffness ~ t^2 / l: omega^2 ~ c^2 / (l h^2), so particles smaller than
  // the ppc = 2 size (l = 1/4) need a proportionally shorter step.
  const double gimp_factor = lp > 0.0 ? std::min(1.0, std::sqrt(4.0 * lp)) : 1.0;
  dt = opt.cfl_factor * gimp_factor * h / c;
  omega1 = model.lowest_frequency > 0.0 ? model.lowest_frequency : 0.0;
  if (opt.ramp_time > 0.0) {
    ramp_time = opt.ramp_time;
  } else if (omega1 > 0.0) {
    ramp_time = opt.ramp_periods * 2.0 * M_PI / omega1;
  } else {
    ramp_time = 0.0;
  }
  BF_CHECK_INPUT(opt.target_displacement == 0.0 || ramp_time > 0.0,
                 "a loading ramp needs ramp_time or the model's lowest frequency");
  alpha = opt.damping >= 0.0 ? opt.damping : opt.damping_ratio * 2.0 * omega1;
  if (opt.max_time > 0.0) {
    max_time = opt.max_time;
  } else {
    BF_CHECK_INPUT(omega1 > 0.0, "max_time is needed when the model has no frequency estimate");
    max_time = ramp_time + 12.0 * 2.0 * M_PI / omega1;
  }
  double ke = 0, area = 0;
  for (std::size_t p = 0; p < P; ++p) {
    ke += 0.5 * mass[p] * (vx[p] * vx[p] + vy[p] * vy[p]);
    area += vol[p];
  }
  initial_energy = ke * model.thickness;
  const double modulus = model.density * c * c;
  const double strain_scale = opt.target_displacement / std::sqrt(area);
  energy_floor = 1e-8 * modulus * area * model.thickness * strain_scale * strain_scale + 1e-300;
  kinetic = initial_energy;
  message = "running";
}

double Solver::Impl::Rate(double time) const {
  if (ramp_time <= 0.0 || time >= ramp_time) return 0.0;
  return opt.target_displacement / ramp_time * (1.0 - std::cos(2.0 * M_PI * time / ramp_time));
}

double Solver::Impl::Displacement(double time) const {
  if (ramp_time <= 0.0) return 0.0;
  if (time >= ramp_time) return opt.target_displacement;
  return opt.target_displacement / ramp_time *
         (time - ramp_time / (2.0 * M_PI) * std::sin(2.0 * M_PI * time / ramp_time));
}

// ------------------------------------------------------------ crack geometry
void Solver::Impl::UpdateCrackGeometry() {
  if (cx.empty()) return;
  crack_xmin = *std::min_element(cx.begin(), cx.end());
  crack_xmax = *std::max_element(cx.begin(), cx.end());
  crack_ymin = *std::min_element(cy.begin(), cy.end());
  crack_ymax = *std::max_element(cy.begin(), cy.end());
  segment_bucket.assign(nx, {});
  for (std::size_t k = 0; k + 1 < cx.size(); ++k) {
    const double lo = std::min(cx[k], cx[k + 1]), hi = std::max(cx[k], cx[k + 1]);
    const int c0 = std::max(0, static_cast<int>(std::floor((lo - x0) * inv_h)) - 2);
    const int c1 = std::min(nx - 1, static_cast<int>(std::floor((hi - x0) * inv_h)) + 2);
    for (int c = c0; c <= c1; ++c) segment_bucket[c].push_back(static_cast<int>(k));
  }
  // Node side for nodes near the crack: left of the crack direction = above.
  const double reach = 2.5 * h;
  for (int j = 0; j < ny; ++j) {
    const double y = y0 + j * h;
    for (int i = 0; i < nx; ++i) {
      const double x = x0 + i * h;
      const std::size_t n = static_cast<std::size_t>(j) * nx + i;
      if (x < crack_xmin - reach || x > crack_xmax + reach || y < crack_ymin - reach ||
          y > crack_ymax + reach) {
        node_above[n] = y >= 0.5 * (crack_ymin + crack_ymax) ? 1 : 0;
        continue;
      }
      std::size_t seg = NearestSegment(x, y);
      node_above[n] =
          Orient(cx[seg], cy[seg], cx[seg + 1], cy[seg + 1], x, y) > 0.0 ? 1 : 0;
    }
  }
}

}  // namespace bridgefit::mpm
