#include "bridgefit/mpm/solver.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <type_traits>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "shape.hpp"

namespace bridgefit::mpm {

const char* ShapeFunctionName(ShapeFunction shape) {
  return shape == ShapeFunction::kGimp ? "uGIMP" : "linear";
}
const char* UpdateSchemeName(UpdateScheme scheme) {
  switch (scheme) {
    case UpdateScheme::kUSF: return "USF";
    case UpdateScheme::kUSL: return "USL";
    case UpdateScheme::kUSAVG: return "USAVG";
  }
  return "?";
}

bool SolverOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!(cfl_factor > 0.0 && cfl_factor <= 10.0)) return fail("cfl_factor must be in (0, 10]");
  if (threads < 0) return fail("threads must be >= 0");
  if (!(target_displacement >= 0.0 || target_displacement < 0.0))
    return fail("target_displacement must be finite");
  if (!(ramp_time >= 0.0) || !(ramp_periods > 0.0)) return fail("ramp time must be positive");
  if (!(settle_ratio >= 0.0)) return fail("settle_ratio must be >= 0");
  if (!(max_time >= 0.0) || max_steps < 0) return fail("max_time/max_steps must be >= 0");
  if (!(damping_ratio >= 0.0)) return fail("damping_ratio must be >= 0");
  if (feedback_damping && !(kinetic_target > 0.0 && feedback_gain > 0.0))
    return fail("feedback damping needs kinetic_target > 0 and feedback_gain > 0");
  if (!(energy_growth_limit > 1.0)) return fail("energy_growth_limit must be > 1");
  if (history_every < 1) return fail("history_every must be >= 1");
  for (int k : contour_cells)
    if (k < 1) return fail("contour half sizes must be >= 1 cell");
  if (fields_every < 0) return fail("fields_every must be >= 0");
  return true;
}

std::string Summary::BriefReport() const {
  std::string s = fmt::format(
      "MPM {}: {} ({} steps of {:.3g} s, t = {:.4g} s, {} particles, {} nodes, {} threads, "
      "{:.3g} s wall, {:.3g} M particle-steps/s); P = {:.5g} N at {:.5g} mm; max KE/SE {:.3g}",
      RunStatusName(status), message, steps, dt, time, particles, nodes, threads, wall_s,
      particle_steps_per_s * 1e-6, final_load, final_displacement * 1e3, max_kinetic_to_strain);
  for (const auto& j : final_J)
    s += fmt::format("; J({} cells) = {:.5g} J/m^2", j.half_cells, j.J);
  return s;
}

namespace {

using Clock = std::chrono::steady_clock;
using detail::Weights;

inline double Orient(double ax, double ay, double bx, double by, double cx, double cy) {
  return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

}  // namespace

struct Solver::Impl {
  Model model;
  SolverOptions opt;
  int threads = 1;

  // Grid.
  double h = 0, inv_h = 0, x0 = 0, y0 = 0;
  int nx = 0, ny = 0;
  std::size_t N = 0;
  std::vector<double> gm, gpx, gpy, gfx, gfy, gqx, gqy;  // 2 fields x N
  // Node velocities for the gather: v = p*/m, dv = (p* - p)/m (0 on empty nodes).
  std::vector<double> gvx, gvy, gdvx, gdvy;
  std::vector<int> node_constraint;                       // -1 or constraint index

  struct Band {
    int row0 = 0, rows = 0;
    std::vector<double> m, px, py, fx, fy;
  };
  std::vector<Band> bands;
  std::vector<std::size_t> chunk;  // thread t owns particles [chunk[t], chunk[t+1])

  // Particles (SoA).
  std::size_t P = 0;
  double lp = 0;      // half size in cell units (uGIMP)
  double inv_lp = 0;  // 1 / lp
  std::vector<double> px, py, vx, vy, mass, vol, sxx, syy, sxy, hxx, hxy, hyx, hyy, ux, uy,
      w, dexx, deyy, dgxy;
  std::vector<std::uint16_t> mask;

  // Crack (SoA over crack points).
  std::vector<double> cx, cy, uax, uay, ubx, uby, ctraction;
  double crack_xmin = 0, crack_xmax = 0, crack_ymin = 0, crack_ymax = 0;
  std::vector<std::int8_t> node_above;  // 1 above, 0 below (left of the crack direction)
  // Crack segments by cell column (segments within two columns), so the
  // crossing tests look at a handful of segments, not the whole crack.
  std::vector<std::vector<int>> segment_bucket;

  // State.
  double t = 0, dt = 0, alpha = 0, omega1 = 0, ramp_time = 0, max_time = 0;
  long step = 0;
  RunStatus status = RunStatus::kOk;
  std::string message = "not started";
  double external_work = 0, initial_energy = 0, energy_floor = 0;
  double kinetic = 0, strain = 0;
  double reaction_load = 0;  // per unit thickness
  double max_ke_se = 0;
  std::vector<HistorySample> history;
  FieldsCallback fields_callback;
  double stage_time[8] = {0};
  const char* stage_names[8] = {"particles_to_grid", "grid_update", "grid_to_particles",
                                "stress_update", "crack", "energies_and_checks", "J_integral",
                                "output"};

  Impl(Model m, SolverOptions o) : model(std::move(m)), opt(std::move(o)) {
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

  double Rate(double time) const {
    if (ramp_time <= 0.0 || time >= ramp_time) return 0.0;
    return opt.target_displacement / ramp_time * (1.0 - std::cos(2.0 * M_PI * time / ramp_time));
  }
  double Displacement(double time) const {
    if (ramp_time <= 0.0) return 0.0;
    if (time >= ramp_time) return opt.target_displacement;
    return opt.target_displacement / ramp_time *
           (time - ramp_time / (2.0 * M_PI) * std::sin(2.0 * M_PI * time / ramp_time));
  }

  // ------------------------------------------------------------ crack geometry
  void UpdateCrackGeometry() {
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

  std::size_t NearestSegment(double x, double y) const {
    const int column = static_cast<int>(std::floor((x - x0) * inv_h));
    const std::vector<int>* bucket =
        column >= 0 && column < nx && !segment_bucket[column].empty() ? &segment_bucket[column]
                                                                      : nullptr;
    std::size_t best = 0;
    double best_d = 1e300;
    const std::size_t count = bucket ? bucket->size() : cx.size() - 1;
    for (std::size_t q = 0; q < count; ++q) {
      const std::size_t k = bucket ? static_cast<std::size_t>((*bucket)[q]) : q;
      const double ax = cx[k], ay = cy[k], bx = cx[k + 1], by = cy[k + 1];
      const double dx = bx - ax, dy = by - ay;
      const double len2 = dx * dx + dy * dy;
      double s = len2 > 0 ? ((x - ax) * dx + (y - ay) * dy) / len2 : 0.0;
      s = std::clamp(s, 0.0, 1.0);
      const double ex = ax + s * dx - x, ey = ay + s * dy - y;
      const double d = ex * ex + ey * ey;
      if (d < best_d) {
        best_d = d;
        best = k;
      }
    }
    return best;
  }

  // Bit k of the mask: the line from the particle to node k of its patch
  // crosses the crack (the node then takes the particle into field 1).
  std::uint16_t CrackMask(double x, double y, const Weights& wt) const {
    if (cx.empty()) return 0;
    const double reach = (1.0 + lp) * h + 1e-12;
    if (x < crack_xmin - reach - h || x > crack_xmax + reach + h || y < crack_ymin - reach - h ||
        y > crack_ymax + reach + h)
      return 0;
    // Candidate segments overlapping the patch's box.
    const double bx0 = x0 + wt.i0 * h, bx1 = bx0 + 2 * h;
    const double by0 = y0 + wt.j0 * h, by1 = by0 + 2 * h;
    const int column = static_cast<int>(std::floor((x - x0) * inv_h));
    if (column < 0 || column >= nx) return 0;
    std::size_t cand[16];
    int nc = 0;
    for (int kk : segment_bucket[column]) {
      if (nc == 16) break;
      const std::size_t k = static_cast<std::size_t>(kk);
      const double sx0 = std::min(cx[k], cx[k + 1]), sx1 = std::max(cx[k], cx[k + 1]);
      const double sy0 = std::min(cy[k], cy[k + 1]), sy1 = std::max(cy[k], cy[k + 1]);
      if (sx1 < std::min(bx0, x) || sx0 > std::max(bx1, x) || sy1 < std::min(by0, y) ||
          sy0 > std::max(by1, y))
        continue;
      cand[nc++] = k;
    }
    if (nc == 0) return 0;
    std::uint16_t bits = 0;
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) {
        const double nxp = x0 + (wt.i0 + a) * h, nyp = y0 + (wt.j0 + b) * h;
        for (int q = 0; q < nc; ++q) {
          const std::size_t k = cand[q];
          const double o1 = Orient(cx[k], cy[k], cx[k + 1], cy[k + 1], x, y);
          const double o2 = Orient(cx[k], cy[k], cx[k + 1], cy[k + 1], nxp, nyp);
          if (!((o1 < 0.0) != (o2 < 0.0)) || o1 == 0.0 || o2 == 0.0) continue;
          // Endpoints on the particle-node line count as on its positive side,
          // so a line through a joint crosses exactly one of the two segments.
          const double o3 = Orient(x, y, nxp, nyp, cx[k], cy[k]);
          const double o4 = Orient(x, y, nxp, nyp, cx[k + 1], cy[k + 1]);
          if ((o3 < 0.0) != (o4 < 0.0)) {
            bits |= static_cast<std::uint16_t>(1u << (b * 3 + a));
            break;
          }
        }
      }
    return bits;
  }

  template <bool kGimp>
  inline void ComputeWeights(double x, double y, Weights& wt) const {
    detail::PatchWeights<kGimp>(x, y, x0, y0, inv_h, lp, inv_lp, wt);
  }

  // ------------------------------------------------------------ stage 1
  // ParticlesToGrid: m_i = sum S m_p, p_i = sum S m_p v_p, f_i = -sum V_p sigma_p grad S.
  template <bool kGimp, bool mass_momentum, bool force>
  void ParticlesToGrid() {
    const bool direct = threads == 1;
    if (mass_momentum) {
      std::fill(gm.begin(), gm.end(), 0.0);
      std::fill(gpx.begin(), gpx.end(), 0.0);
      std::fill(gpy.begin(), gpy.end(), 0.0);
    }
    if (force) {
      std::fill(gfx.begin(), gfx.end(), 0.0);
      std::fill(gfy.begin(), gfy.end(), 0.0);
    }
#pragma omp parallel num_threads(threads) if (threads > 1)
    {
      const int tid = omp_get_thread_num();
      const std::size_t b0 = chunk[tid], b1 = chunk[tid + 1];
      double *m_, *px_, *py_, *fx_, *fy_;
      int row0 = 0;
      std::size_t stride = N;
      if (direct) {
        m_ = gm.data(); px_ = gpx.data(); py_ = gpy.data(); fx_ = gfx.data(); fy_ = gfy.data();
      } else {
        // Private band buffer covering the rows this chunk touches.
        double ylo = 1e300, yhi = -1e300;
        for (std::size_t p = b0; p < b1; ++p) {
          ylo = std::min(ylo, py[p]);
          yhi = std::max(yhi, py[p]);
        }
        Band& band = bands[tid];
        if (b1 > b0) {
          band.row0 = std::max(0, static_cast<int>(std::floor((ylo - y0) * inv_h - lp)) - 1);
          const int row1 =
              std::min(ny - 1, static_cast<int>(std::floor((yhi - y0) * inv_h - lp)) + 3);
          band.rows = row1 - band.row0 + 1;
        } else {
          band.rows = 0;
        }
        const std::size_t size = 2 * static_cast<std::size_t>(band.rows) * nx;
        for (auto* a : {&band.m, &band.px, &band.py, &band.fx, &band.fy})
          if (a->size() < size) a->resize(size);
        if (mass_momentum) {
          std::fill_n(band.m.begin(), size, 0.0);
          std::fill_n(band.px.begin(), size, 0.0);
          std::fill_n(band.py.begin(), size, 0.0);
        }
        if (force) {
          std::fill_n(band.fx.begin(), size, 0.0);
          std::fill_n(band.fy.begin(), size, 0.0);
        }
        m_ = band.m.data(); px_ = band.px.data(); py_ = band.py.data();
        fx_ = band.fx.data(); fy_ = band.fy.data();
        row0 = band.row0;
        stride = static_cast<std::size_t>(band.rows) * nx;
      }
      Weights wt;
      for (std::size_t p = b0; p < b1; ++p) {
        ComputeWeights<kGimp>(px[p], py[p], wt);
        std::uint16_t bits;
        if (mass_momentum) {
          bits = CrackMask(px[p], py[p], wt);
          mask[p] = bits;
        } else {
          bits = mask[p];
        }
        const double mp = mass[p], mvx = mp * vx[p], mvy = mp * vy[p];
        const double V = vol[p];
        const double s11 = V * sxx[p], s22 = V * syy[p], s12 = V * sxy[p];
        // Most particles are away from the crack (bits == 0): no field offsets.
        auto scatter = [&](auto cracked) {
          for (int b = 0; b < 3; ++b) {
            const std::size_t row = static_cast<std::size_t>(wt.j0 + b - row0) * nx + wt.i0;
            const double syb = wt.sy[b], gyb = wt.gy[b];
            for (int a = 0; a < 3; ++a) {
              const double S = wt.sx[a] * syb;
              std::size_t k = row + a;
              if constexpr (decltype(cracked)::value) k += ((bits >> (b * 3 + a)) & 1u) * stride;
              if constexpr (mass_momentum) {
                m_[k] += S * mp;
                px_[k] += S * mvx;
                py_[k] += S * mvy;
              }
              if constexpr (force) {
                const double gxs = wt.gx[a] * syb, gys = wt.sx[a] * gyb;
                fx_[k] -= s11 * gxs + s12 * gys;
                fy_[k] -= s12 * gxs + s22 * gys;
              }
            }
          }
        };
        if (bits == 0) scatter(std::false_type{});
        else scatter(std::true_type{});
      }
      if (!direct) {
#pragma omp barrier
        // Reduction of the bands, row by row (race-free: one writer per row).
#pragma omp for schedule(static)
        for (int j = 0; j < ny; ++j) {
          for (int tt = 0; tt < threads; ++tt) {
            const Band& band = bands[tt];
            if (j < band.row0 || j >= band.row0 + band.rows) continue;
            const std::size_t bstride = static_cast<std::size_t>(band.rows) * nx;
            for (int f = 0; f < 2; ++f) {
              const std::size_t src = f * bstride + static_cast<std::size_t>(j - band.row0) * nx;
              const std::size_t dst = f * N + static_cast<std::size_t>(j) * nx;
              for (int i = 0; i < nx; ++i) {
                if (mass_momentum) {
                  gm[dst + i] += band.m[src + i];
                  gpx[dst + i] += band.px[src + i];
                  gpy[dst + i] += band.py[src + i];
                }
                if (force) {
                  gfx[dst + i] += band.fx[src + i];
                  gfy[dst + i] += band.fy[src + i];
                }
              }
            }
          }
        }
      }
    }
  }

  // Nodes with less mass than this are left out (v = 0).
  double MassFloor() const { return 1e-9 * model.density * h * h; }

  // Prescribed velocities on the constrained nodes' own field (field 0) in
  // momentum `qx, qy` at rate `rate`.
  void ConstrainVelocities(double rate) {
    const double mfloor = MassFloor();
    for (const auto& c : model.constraints)
      for (int n : c.nodes)
        if (gm[n] > mfloor) ApplyConstraint(c, n, 1.0, rate, gvx[n], gvy[n]);
  }

  // Sets the constrained components of momentum (qx, qy) of node n; returns
  // the momentum change it made.
  std::array<double, 2> ApplyConstraint(const NodeConstraint& c, int n, double m, double rate,
                                        double& qx, double& qy) const {
    const double vx_p = c.share_x * rate, vy_p = c.share_y * rate;
    if (c.radial) {
      double ex = x0 + (n % nx) * h - c.center_x, ey = y0 + (n / nx) * h - c.center_y;
      const double r = std::hypot(ex, ey);
      if (r <= 0.0) return {0.0, 0.0};
      ex /= r;
      ey /= r;
      const double vn_pin = vx_p * ex + vy_p * ey;
      const double vn = (qx * ex + qy * ey) / m;
      if (c.unilateral && vn >= vn_pin) return {0.0, 0.0};  // separating
      const double dq = m * (vn_pin - vn);
      qx += dq * ex;
      qy += dq * ey;
      return {dq * ex, dq * ey};
    }
    std::array<double, 2> d{0.0, 0.0};
    if (c.constrain_x) {
      d[0] = m * vx_p - qx;
      qx = m * vx_p;
    }
    if (c.constrain_y) {
      d[1] = m * vy_p - qy;
      qy = m * vy_p;
    }
    return d;
  }

  // ------------------------------------------------------------ stage 2
  // GridUpdate: p* = p + dt (f - alpha p); contact; p* = m v_prescribed on constraints.
  void GridUpdate() {
    const double mfloor = MassFloor();
    const double a = alpha;
    const std::size_t total = 2 * N;
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
    for (std::size_t k = 0; k < total; ++k) {
      if (gm[k] > mfloor) {
        gqx[k] = gpx[k] + dt * (gfx[k] - a * gpx[k]);
        gqy[k] = gpy[k] + dt * (gfy[k] - a * gpy[k]);
      } else {
        gqx[k] = gqy[k] = gpx[k] = gpy[k] = 0.0;
      }
    }
    if (opt.contact && !cx.empty()) Contact();
    // Reactions: R = (p*_constrained - p*_free)/dt, the force the constraint adds.
    const double rate_new = Rate(t + dt), rate_mid = Rate(t + 0.5 * dt);
    double work = 0.0, load = 0.0;
    for (std::size_t c = 0; c < model.constraints.size(); ++c) {
      const auto& con = model.constraints[c];
      double rx = 0.0, ry = 0.0;
      for (int n : con.nodes) {
        const double m = gm[n];
        if (m <= mfloor) continue;
        const auto dq = ApplyConstraint(con, n, m, rate_new, gqx[n], gqy[n]);
        rx += dq[0] / dt;
        ry += dq[1] / dt;
      }
      work += dt * (rx * con.share_x + ry * con.share_y) * rate_mid;
      const double share = std::hypot(con.share_x, con.share_y);
      if (static_cast<int>(c) == model.load_constraint && share > 0.0)
        load = (rx * con.share_x + ry * con.share_y) / share;
    }
    external_work += work * model.thickness;
    reaction_load = load;
    NodeVelocities(false);
  }

  // v_i = p*_i/m_i and dv_i = (p*_i - p_i)/m_i once per node, so the gather
  // needs no divisions. `old`: v_i = p_i/m_i (USF strain before the forces).
  void NodeVelocities(bool old) {
    const double mfloor = MassFloor();
    const std::size_t total = 2 * N;
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
    for (std::size_t k = 0; k < total; ++k) {
      const double m = gm[k];
      if (m > mfloor) {
        const double inv = 1.0 / m;
        if (old) {
          gvx[k] = gpx[k] * inv;
          gvy[k] = gpy[k] * inv;
          gdvx[k] = gdvy[k] = 0.0;
        } else {
          gvx[k] = gqx[k] * inv;
          gvy[k] = gqy[k] * inv;
          gdvx[k] = (gqx[k] - gpx[k]) * inv;
          gdvy[k] = (gqy[k] - gpy[k]) * inv;
        }
      } else {
        gvx[k] = gvy[k] = gdvx[k] = gdvy[k] = 0.0;
      }
    }
  }

  // Frictionless contact on nodes with both fields: remove the closing
  // normal relative velocity that would make the faces interpenetrate.
  void Contact() {
    const double mfloor = MassFloor();
    for (std::size_t n = 0; n < N; ++n) {
      if (gm[n] <= mfloor || gm[N + n] <= mfloor) continue;
      const double x = x0 + (n % nx) * h, y = y0 + (n / nx) * h;
      const std::size_t seg = NearestSegment(x, y);
      double tx = cx[seg + 1] - cx[seg], ty = cy[seg + 1] - cy[seg];
      const double len = std::hypot(tx, ty);
      if (len <= 0.0) continue;
      tx /= len;
      ty /= len;
      const double nxn = -ty, nyn = tx;  // normal pointing to the upper face
      const std::size_t ka = node_above[n] ? n : N + n, kb = node_above[n] ? N + n : n;
      const double ma = gm[ka], mb = gm[kb];
      const double dvn = (gqx[ka] / ma - gqx[kb] / mb) * nxn + (gqy[ka] / ma - gqy[kb] / mb) * nyn;
      if (dvn >= 0.0) continue;
      // Closing allowed until the gap is shut; a negative gap (overlap) is
      // pushed open within the step.
      const double gap = CodNormalAtProjection(seg, x, y);
      const double allowed = -gap / dt;
      if (dvn >= allowed || (dvn >= 0.0 && gap >= 0.0)) continue;
      const double dp = (dvn - allowed) * ma * mb / (ma + mb);
      gqx[ka] -= dp * nxn;
      gqy[ka] -= dp * nyn;
      gqx[kb] += dp * nxn;
      gqy[kb] += dp * nyn;
    }
  }

  double CodNormalAt(std::size_t k) const {
    const std::size_t s = std::min(k, cx.size() - 2);
    double tx = cx[s + 1] - cx[s], ty = cy[s + 1] - cy[s];
    const double len = std::hypot(tx, ty);
    tx /= len;
    ty /= len;
    return (uax[k] - ubx[k]) * (-ty) + (uay[k] - uby[k]) * tx;
  }
  double CodTangentialAt(std::size_t k) const {
    const std::size_t s = std::min(k, cx.size() - 2);
    double tx = cx[s + 1] - cx[s], ty = cy[s + 1] - cy[s];
    const double len = std::hypot(tx, ty);
    return ((uax[k] - ubx[k]) * tx + (uay[k] - uby[k]) * ty) / len;
  }
  double CodNormalAtProjection(std::size_t seg, double x, double y) const {
    const double dx = cx[seg + 1] - cx[seg], dy = cy[seg + 1] - cy[seg];
    double s = ((x - cx[seg]) * dx + (y - cy[seg]) * dy) / (dx * dx + dy * dy);
    s = std::clamp(s, 0.0, 1.0);
    return (1.0 - s) * CodNormalAt(seg) + s * CodNormalAt(seg + 1);
  }

  // ------------------------------------------------------------ stage 3
  // GridToParticles: v_p += sum S (p*_i - p_i)/m_i (FLIP), x_p += dt sum S p*_i/m_i;
  // with `gradient`: L_p = sum (v_i (x) grad S), d_eps = sym(L) dt_frac
  // (v_i from NodeVelocities: after the update, or before it for USF).
  template <bool kGimp>
  bool GridToParticles(bool kinematics, bool gradient, double dt_frac, double* ke_out) {
    const double xlo = x0 + (1.0 + lp) * h, xhi = x0 + (nx - 2.0 - lp) * h;
    const double ylo = y0 + (1.0 + lp) * h, yhi = y0 + (ny - 2.0 - lp) * h;
    int left_grid = 0;
    double ke = 0.0;
    const double beta_dt = dt * (opt.particle_damping >= 0.0 ? opt.particle_damping : alpha);
    const double* __restrict vxg = gvx.data();
    const double* __restrict vyg = gvy.data();
    const double* __restrict dvxg = gdvx.data();
    const double* __restrict dvyg = gdvy.data();
#pragma omp parallel for num_threads(threads) schedule(static) reduction(+ : left_grid, ke) if (threads > 1)
    for (std::size_t p = 0; p < P; ++p) {
      Weights wt;
      ComputeWeights<kGimp>(px[p], py[p], wt);
      const std::uint16_t bits = mask[p];
      double dvx = 0, dvy = 0, nvx = 0, nvy = 0, lxx = 0, lxy = 0, lyx = 0, lyy = 0;
      auto gather = [&](auto cracked) {
        for (int b = 0; b < 3; ++b) {
          const std::size_t row = static_cast<std::size_t>(wt.j0 + b) * nx + wt.i0;
          const double syb = wt.sy[b], gyb = wt.gy[b];
          for (int a = 0; a < 3; ++a) {
            std::size_t k = row + a;
            if constexpr (decltype(cracked)::value) k += ((bits >> (b * 3 + a)) & 1u) * N;
            const double S = wt.sx[a] * syb;
            const double vxi = vxg[k], vyi = vyg[k];
            if (kinematics) {
              dvx += S * dvxg[k];
              dvy += S * dvyg[k];
              nvx += S * vxi;
              nvy += S * vyi;
            }
            if (gradient) {
              const double gxs = wt.gx[a] * syb, gys = wt.sx[a] * gyb;
              lxx += vxi * gxs;
              lxy += vxi * gys;
              lyx += vyi * gxs;
              lyy += vyi * gys;
            }
          }
        }
      };
      if (bits == 0) gather(std::false_type{});
      else gather(std::true_type{});
      if (kinematics) {
        vx[p] += dvx - beta_dt * vx[p];
        vy[p] += dvy - beta_dt * vy[p];
        px[p] += dt * nvx;
        py[p] += dt * nvy;
        ux[p] += dt * nvx;
        uy[p] += dt * nvy;
        ke += 0.5 * mass[p] * (vx[p] * vx[p] + vy[p] * vy[p]);
        if (!(px[p] > xlo && px[p] < xhi && py[p] > ylo && py[p] < yhi)) ++left_grid;
      }
      if (gradient) {
        const double d = dt * dt_frac;
        dexx[p] = lxx * d;
        deyy[p] = lyy * d;
        dgxy[p] = (lxy + lyx) * d;
        hxx[p] += lxx * d;
        hxy[p] += lxy * d;
        hyx[p] += lyx * d;
        hyy[p] += lyy * d;
      }
    }
    if (ke_out) *ke_out = ke;
    return left_grid == 0;
  }

  // ------------------------------------------------------------ stage 4
  // StressUpdate: sigma += C : d_eps (the law); w += (sigma_old + sigma_new)/2 : d_eps.
  double StressUpdate() {
    double se = 0.0;
#pragma omp parallel num_threads(threads) reduction(+ : se) if (threads > 1)
    {
      const int tid = omp_get_thread_num();
      const std::size_t b0 = chunk[tid], b1 = chunk[tid + 1];
      for (std::size_t p = b0; p < b1; ++p)
        w[p] += 0.5 * (sxx[p] * dexx[p] + syy[p] * deyy[p] + sxy[p] * dgxy[p]);
      if (b1 > b0)
        model.law->UpdateStress(b1 - b0, dexx.data() + b0, deyy.data() + b0, dgxy.data() + b0,
                                sxx.data() + b0, syy.data() + b0, sxy.data() + b0);
      for (std::size_t p = b0; p < b1; ++p) {
        w[p] += 0.5 * (sxx[p] * dexx[p] + syy[p] * deyy[p] + sxy[p] * dgxy[p]);
        se += vol[p] * w[p];
      }
    }
    return se;
  }

  // ------------------------------------------------------------ crack faces
  // Face velocity at a crack point: sum S p*_face / sum S m_face over its
  // cell's nodes (linear weights); faces and mid point move with them.
  void MoveCrack() {
    const double mfloor = MassFloor();
    for (std::size_t k = 0; k < cx.size(); ++k) {
      const double fx = (cx[k] - x0) * inv_h, fy = (cy[k] - y0) * inv_h;
      const int i = static_cast<int>(std::floor(fx)), j = static_cast<int>(std::floor(fy));
      if (i < 0 || j < 0 || i + 1 >= nx || j + 1 >= ny) continue;
      const double rx = fx - i, ry = fy - j;
      double ma = 0, qax = 0, qay = 0, mb = 0, qbx = 0, qby = 0;
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
          const std::size_t n = static_cast<std::size_t>(j + b) * nx + i + a;
          const double S = (a ? rx : 1.0 - rx) * (b ? ry : 1.0 - ry);
          const std::size_t ka = node_above[n] ? n : N + n, kb = node_above[n] ? N + n : n;
          if (gm[ka] > mfloor) {
            ma += S * gm[ka];
            qax += S * gqx[ka];
            qay += S * gqy[ka];
          }
          if (gm[kb] > mfloor) {
            mb += S * gm[kb];
            qbx += S * gqx[kb];
            qby += S * gqy[kb];
          }
        }
      if (ma <= 0.0 && mb <= 0.0) continue;
      double vax, vay, vbx, vby;
      if (ma > 0.0) { vax = qax / ma; vay = qay / ma; }
      else { vax = qbx / mb; vay = qby / mb; }
      if (mb > 0.0) { vbx = qbx / mb; vby = qby / mb; }
      else { vbx = vax; vby = vay; }
      uax[k] += dt * vax;
      uay[k] += dt * vay;
      ubx[k] += dt * vbx;
      uby[k] += dt * vby;
      cx[k] += 0.5 * dt * (vax + vbx);
      cy[k] += 0.5 * dt * (vay + vby);
    }
    UpdateCrackGeometry();
  }

  // ------------------------------------------------------------ the step
  template <bool kGimp>
  bool StepImpl() {
    auto tick = Clock::now();
    auto lap = [&](int stage) {
      const auto now = Clock::now();
      stage_time[stage] += std::chrono::duration<double>(now - tick).count();
      tick = now;
    };
    double ke = 0.0, se = strain;
    bool inside = true;
    switch (opt.scheme) {
      case UpdateScheme::kUSL:
        ParticlesToGrid<kGimp, true, true>();
        lap(0);
        GridUpdate();
        lap(1);
        inside = GridToParticles<kGimp>(true, true, 1.0, &ke);
        lap(2);
        se = StressUpdate();
        lap(3);
        break;
      case UpdateScheme::kUSF:
      case UpdateScheme::kUSAVG: {
        const double first = opt.scheme == UpdateScheme::kUSF ? 1.0 : 0.5;
        ParticlesToGrid<kGimp, true, false>();
        lap(0);
        // Strain from the velocities before the force update, constrained
        // (the momenta stay as mapped, so FLIP sees the whole change).
        NodeVelocities(true);
        ConstrainVelocities(Rate(t));
        GridToParticles<kGimp>(false, true, first, nullptr);
        lap(2);
        StressUpdate();
        lap(3);
        ParticlesToGrid<kGimp, false, true>();
        lap(0);
        GridUpdate();
        lap(1);
        const bool second = opt.scheme == UpdateScheme::kUSAVG;
        inside = GridToParticles<kGimp>(true, second, 0.5, &ke);
        lap(2);
        if (second) se = StressUpdate();
        else se = StrainEnergyPerThickness();
        lap(3);
        break;
      }
    }
    if (!cx.empty()) MoveCrack();
    lap(4);
    t += dt;
    ++step;
    kinetic = ke * model.thickness;
    strain = se * model.thickness;
    // Instability: NaN, particles off the grid, energy growing beyond the work put in.
    const double total = kinetic + strain;
    if (!std::isfinite(total) || !std::isfinite(reaction_load)) {
      Fail(fmt::format("non-finite energy or load at step {} (t = {:.4g} s)", step, t));
    } else if (!inside) {
      Fail(fmt::format("a particle left the grid at step {} (t = {:.4g} s)", step, t));
    } else if (step > 10 && total > opt.energy_growth_limit * (initial_energy + external_work) &&
               total > energy_floor) {
      Fail(fmt::format(
          "energy grew at step {} (t = {:.4g} s): kinetic + strain {:.4g} J exceeds {:g} x the "
          "initial energy plus external work ({:.4g} J)",
          step, t, total, opt.energy_growth_limit, initial_energy + external_work));
    }
    if (strain > energy_floor && t > 0.1 * ramp_time)
      max_ke_se = std::max(max_ke_se, kinetic / strain);
    if (opt.feedback_damping && strain > energy_floor && omega1 > 0.0) {
      // d alpha/dt = gain omega_1^2 (KE/SE / target - 1), alpha in [0, 4 omega_1].
      alpha += dt * opt.feedback_gain * omega1 * omega1 *
               (kinetic / (opt.kinetic_target * strain) - 1.0);
      alpha = std::clamp(alpha, 0.0, 4.0 * omega1);
    }
    lap(5);
    return status == RunStatus::kOk;
  }

  double StrainEnergyPerThickness() const {
    double se = 0.0;
#pragma omp parallel for num_threads(threads) reduction(+ : se) if (threads > 1)
    for (std::size_t p = 0; p < P; ++p) se += vol[p] * w[p];
    return se;
  }

  void Fail(const std::string& why) {
    status = RunStatus::kUnstable;
    message = why;
    if (opt.cfl_factor > 1.0)
      message += fmt::format("; the CFL factor {:g} exceeds 1, beyond the explicit stability limit",
                             opt.cfl_factor);
  }

  bool Step() {
    if (status != RunStatus::kOk) return false;
    return opt.shape == ShapeFunction::kGimp ? StepImpl<true>() : StepImpl<false>();
  }

  // ------------------------------------------------------------ J integral
  JResult ComputeJ(int k) const {
    JResult r;
    r.half_cells = k;
    r.J = r.face_term = r.J_tip = NAN;
    if (cx.size() < 2) return r;
    const std::size_t tip = cx.size() - 1;
    const double xt = cx[tip], yt = cy[tip];
    const int it = static_cast<int>(std::lround((xt - x0) * inv_h));
    const int jb = static_cast<int>(std::floor((yt - y0) * inv_h)), ja = jb + 1;
    const int iL = it - k, iR = it + k, jB = jb - (k - 1), jT = ja + (k - 1);
    if (iL < 0 || iR >= nx || jB < 0 || jT >= ny) return r;
    // Extrapolate sigma, u_{x,x}, u_{y,x}, w and v to the nodes (mass-weighted).
    const double xlo = x0 + (iL - 2) * h, xhi = x0 + (iR + 2) * h;
    const double ylo = y0 + (jB - 2) * h, yhi = y0 + (jT + 2) * h;
    constexpr int kQ = 9;  // m, sxx, syy, sxy, uxx, uyx, w, vx, vy
    std::vector<double> ext(2 * N * kQ, 0.0);
    Weights wt;
    for (std::size_t p = 0; p < P; ++p) {
      if (px[p] < xlo || px[p] > xhi || py[p] < ylo || py[p] > yhi) continue;
      if (opt.shape == ShapeFunction::kGimp) ComputeWeights<true>(px[p], py[p], wt);
      else ComputeWeights<false>(px[p], py[p], wt);
      const std::uint16_t bits = CrackMask(px[p], py[p], wt);
      const double q[kQ] = {1.0, sxx[p], syy[p], sxy[p], hxx[p], hyx[p], w[p], vx[p], vy[p]};
      for (int b = 0; b < 3; ++b)
        for (int a = 0; a < 3; ++a) {
          const double S = wt.sx[a] * wt.sy[b] * mass[p];
          if (S <= 0.0) continue;
          const std::size_t n = static_cast<std::size_t>(wt.j0 + b) * nx + wt.i0 + a;
          const std::size_t kk = (n + (((bits >> (b * 3 + a)) & 1u) ? N : 0)) * kQ;
          for (int c = 0; c < kQ; ++c) ext[kk + c] += S * q[c];
        }
    }
    // Integrand (W + K) n_x - t . u_{,x} at a node's own-side field.
    auto integrand = [&](int i, int j, double nxn, double nyn) {
      const std::size_t kk = (static_cast<std::size_t>(j) * nx + i) * kQ;
      const double m = ext[kk];
      if (m <= 0.0) return 0.0;
      const double s11 = ext[kk + 1] / m, s22 = ext[kk + 2] / m, s12 = ext[kk + 3] / m;
      const double uxx = ext[kk + 4] / m, uyx = ext[kk + 5] / m, wd = ext[kk + 6] / m;
      const double v1 = ext[kk + 7] / m, v2 = ext[kk + 8] / m;
      const double kd = 0.5 * model.density * (v1 * v1 + v2 * v2);
      return (wd + kd) * nxn - (s11 * nxn + s12 * nyn) * uxx - (s12 * nxn + s22 * nyn) * uyx;
    };
    const detail::ContourBox box{.iL = iL, .iR = iR, .jB = jB, .jT = jT, .half = false,
                                 .jb = jb, .ja = ja, .above = y0 + ja * h - yt,
                                 .below = yt - (y0 + jb * h)};
    const double J = detail::ContourIntegral(box, h, integrand);
    r.J = J;
    // Face term: sum sigma d(delta) from the tip back to the contour crossing.
    const double face = detail::FaceWork(
        cx, [&](std::size_t k) { return CodNormalAt(k); },
        [&](std::size_t k) { return ctraction[k]; }, x0 + iL * h);
    r.face_term = face;
    r.J_tip = J - face;
    return r;
  }

  double CodAt(double x) const {
    if (cx.size() < 2) return NAN;
    for (std::size_t k = 0; k + 1 < cx.size(); ++k) {
      const double xa = cx[k], xb = cx[k + 1];
      if ((x - xa) * (x - xb) <= 0.0) {
        const double f = xb != xa ? (x - xa) / (xb - xa) : 0.0;
        return (1.0 - f) * CodNormalAt(k) + f * CodNormalAt(k + 1);
      }
    }
    return NAN;
  }

  HistorySample Sample() const {
    HistorySample s;
    s.time = t;
    s.step = step;
    s.load = reaction_load * model.thickness;
    s.displacement = Displacement(t);
    s.load_line_cod = CodAt(0.0);
    s.kinetic = kinetic;
    s.strain = strain;
    s.external_work = external_work;
    s.damping = alpha;
    for (int k : opt.contour_cells) {
      const JResult j = ComputeJ(k);
      s.J.push_back(j.J);
      s.J_tip.push_back(j.J_tip);
    }
    return s;
  }

  ParticleFields Fields() const {
    ParticleFields f;
    f.x = px; f.y = py; f.ux = ux; f.uy = uy; f.vx = vx; f.vy = vy;
    f.sxx = sxx; f.syy = syy; f.sxy = sxy; f.strain_energy_density = w;
    return f;
  }
};

Solver::Solver(Model model, SolverOptions options)
    : impl_(std::make_unique<Impl>(std::move(model), std::move(options))) {}
Solver::~Solver() = default;

bool Solver::Step() { return impl_->Step(); }
void Solver::SetFieldsCallback(FieldsCallback callback) {
  impl_->fields_callback = std::move(callback);
}
RunStatus Solver::status() const { return impl_->status; }
const std::string& Solver::message() const { return impl_->message; }
double Solver::time() const { return impl_->t; }
double Solver::dt() const { return impl_->dt; }
long Solver::steps() const { return impl_->step; }
const Model& Solver::model() const { return impl_->model; }
const SolverOptions& Solver::options() const { return impl_->opt; }
ParticleFields Solver::Fields() const { return impl_->Fields(); }
double Solver::CodAt(double x) const { return impl_->CodAt(x); }
JResult Solver::ComputeJ(int half_cells) const { return impl_->ComputeJ(half_cells); }
HistorySample Solver::Sample() const { return impl_->Sample(); }

void Solver::SetCrackTraction(std::size_t k, double traction) {
  BF_CHECK_INPUT(k < impl_->ctraction.size(), "crack point index out of range");
  impl_->ctraction[k] = traction;
}

std::vector<CrackPointState> Solver::CrackPoints() const {
  const Impl& m = *impl_;
  std::vector<CrackPointState> out(m.cx.size());
  for (std::size_t k = 0; k < m.cx.size(); ++k) {
    auto& c = out[k];
    c.x = m.cx[k];
    c.y = m.cy[k];
    c.ux_above = m.uax[k];
    c.uy_above = m.uay[k];
    c.ux_below = m.ubx[k];
    c.uy_below = m.uby[k];
    c.cod_normal = m.CodNormalAt(k);
    c.cod_tangential = m.CodTangentialAt(k);
    c.traction = m.ctraction[k];
  }
  return out;
}

Summary Solver::Run() {
  Impl& m = *impl_;
  Stopwatch watch;
  Summary s;
  s.particles = m.P;
  s.nodes = m.N;
  s.threads = m.threads;
  s.dt = m.dt;
  const long start_step = m.step;
  const double period = m.omega1 > 0.0 ? 2.0 * M_PI / m.omega1 : 0.0;
  const long window = period > 0.0 ? std::max(1L, static_cast<long>(period / m.dt)) : 0;
  double window_max = 0.0;
  long window_start = m.step;
  bool settled = false;
  const long estimate = static_cast<long>(m.max_time / m.dt) + 1;
  Progress progress("MPM", static_cast<std::size_t>(estimate), m.opt.progress);
  auto record = [&]() {
    const auto tick = Clock::now();
    m.history.push_back(m.Sample());
    m.stage_time[6] += std::chrono::duration<double>(Clock::now() - tick).count();
  };
  auto fields = [&]() {
    if (!m.fields_callback) return;
    const auto tick = Clock::now();
    m.fields_callback(m.step, m.t, m.Fields());
    m.stage_time[7] += std::chrono::duration<double>(Clock::now() - tick).count();
  };
  if (m.step == 0) {
    record();
    if (m.opt.fields_every > 0) fields();
  }
  while (true) {
    if (!m.Step()) break;
    if (m.step % m.opt.history_every == 0) record();
    if (m.opt.fields_every > 0 && m.step % m.opt.fields_every == 0) fields();
    progress.Update(static_cast<std::size_t>(m.step));
    if (m.t >= m.ramp_time && m.opt.settle_ratio > 0.0 && window > 0) {
      window_max = std::max(window_max, m.strain > 0.0 ? m.kinetic / m.strain : 1.0);
      if (m.step - window_start >= window) {
        if (window_max < m.opt.settle_ratio) {
          settled = true;
          break;
        }
        window_max = 0.0;
        window_start = m.step;
      }
    } else {
      window_start = m.step;
    }
    if (m.t >= m.max_time) break;
    if (m.opt.max_steps > 0 && m.step - start_step >= m.opt.max_steps) break;
  }
  progress.Finish();
  // The last state is recorded also when the run stopped unstable (for the
  // diagnosis; its numbers may be non-finite).
  if (m.history.empty() || m.history.back().step != m.step) record();
  if (m.status == RunStatus::kOk) {
    if (m.opt.fields_every > 0 && m.step % m.opt.fields_every != 0) fields();
    if (settled) {
      m.message = fmt::format("settled: KE/SE < {:g} over one lowest-mode period",
                              m.opt.settle_ratio);
    } else if (m.opt.settle_ratio > 0.0 && window > 0) {
      m.status = RunStatus::kNotConverged;
      m.message = fmt::format("not settled by t = {:.4g} s (last KE/SE window max {:.3g})", m.t,
                              window_max);
    } else {
      m.message = "reached the end time";
    }
  }
  s.status = m.status;
  s.message = m.message;
  s.steps = m.step;
  s.time = m.t;
  s.wall_s = watch.Seconds();
  s.particle_steps_per_s =
      s.wall_s > 0.0 ? static_cast<double>(m.P) * (m.step - start_step) / s.wall_s : 0.0;
  s.max_kinetic_to_strain = m.max_ke_se;
  s.final_load = m.reaction_load * m.model.thickness;
  s.final_displacement = m.Displacement(m.t);
  s.final_load_line_cod = m.CodAt(0.0);
  for (int k : m.opt.contour_cells) s.final_J.push_back(m.ComputeJ(k));
  s.history = m.history;
  for (int st = 0; st < 8; ++st) s.stage_seconds.emplace_back(m.stage_names[st], m.stage_time[st]);
  return s;
}

}  // namespace bridgefit::mpm
