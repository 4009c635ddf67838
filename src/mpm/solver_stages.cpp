// mpm::Solver::Impl: one explicit step as named stages (P2G -> grid update ->
// G2P -> stress update -> crack), each stating its equation.

#include "solver_impl.hpp"

namespace bridgefit::mpm {

// ------------------------------------------------------------ stage 1
// ParticlesToGrid: m_i = sum S m_p, p_i = sum S m_p v_p, f_i = -sum V_p sigma_p grad S.
template <bool kGimp, bool mass_momentum, bool force>
void Solver::Impl::ParticlesToGrid() {
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

// Prescribed velocities on the constrained nodes' own field (field 0) in
// momentum `qx, qy` at rate `rate`.
void Solver::Impl::ConstrainVelocities(double rate) {
  const double mfloor = MassFloor();
  for (const auto& c : model.constraints)
    for (int n : c.nodes)
      if (gm[n] > mfloor) ApplyConstraint(c, n, 1.0, rate, gvx[n], gvy[n]);
}

// Sets the constrained components of momentum (qx, qy) of node n; returns
// the momentum change it made.
std::array<double, 2> Solver::Impl::ApplyConstraint(const NodeConstraint& c, int n, double m,
                                                    double rate, double& qx, double& qy) const {
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
void Solver::Impl::GridUpdate() {
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
void Solver::Impl::NodeVelocities(bool old) {
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
void Solver::Impl::Contact() {
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

double Solver::Impl::CodNormalAt(std::size_t k) const {
  const std::size_t s = std::min(k, cx.size() - 2);
  double tx = cx[s + 1] - cx[s], ty = cy[s + 1] - cy[s];
  const double len = std::hypot(tx, ty);
  tx /= len;
  ty /= len;
  return (uax[k] - ubx[k]) * (-ty) + (uay[k] - uby[k]) * tx;
}

double Solver::Impl::CodTangentialAt(std::size_t k) const {
  const std::size_t s = std::min(k, cx.size() - 2);
  double tx = cx[s + 1] - cx[s], ty = cy[s + 1] - cy[s];
  const double len = std::hypot(tx, ty);
  return ((uax[k] - ubx[k]) * tx + (uay[k] - uby[k]) * ty) / len;
}

double Solver::Impl::CodNormalAtProjection(std::size_t seg, double x, double y) const {
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
bool Solver::Impl::GridToParticles(bool kinematics, bool gradient, double dt_frac,
                                   double* ke_out) {
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
double Solver::Impl::StressUpdate() {
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
void Solver::Impl::MoveCrack() {
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
bool Solver::Impl::StepImpl() {
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

bool Solver::Impl::Step() {
  if (status != RunStatus::kOk) return false;
  return opt.shape == ShapeFunction::kGimp ? StepImpl<true>() : StepImpl<false>();
}

}  // namespace bridgefit::mpm
