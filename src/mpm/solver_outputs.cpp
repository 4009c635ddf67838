// mpm::Solver::Impl: what the solver reports: strain energy, the J contour
// integral, the COD, history samples and particle fields.

#include "solver_impl.hpp"

namespace bridgefit::mpm {

double Solver::Impl::StrainEnergyPerThickness() const {
  double se = 0.0;
#pragma omp parallel for num_threads(threads) reduction(+ : se) if (threads > 1)
  for (std::size_t p = 0; p < P; ++p) se += vol[p] * w[p];
  return se;
}

void Solver::Impl::Fail(const std::string& why) {
  status = RunStatus::kUnstable;
  message = why;
  if (opt.cfl_factor > 1.0)
    message += fmt::format("; the CFL factor {:g} exceeds 1, beyond the explicit stability limit",
                           opt.cfl_factor);
}

// ------------------------------------------------------------ J integral
JResult Solver::Impl::ComputeJ(int k) const {
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

double Solver::Impl::CodAt(double x) const {
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

HistorySample Solver::Impl::Sample() const {
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

ParticleFields Solver::Impl::Fields() const {
  ParticleFields f;
  f.x = px; f.y = py; f.ux = ux; f.uy = uy; f.vx = vx; f.vy = vy;
  f.sxx = sxx; f.syy = syy; f.sxy = sxy; f.strain_energy_density = w;
  return f;
}

}  // namespace bridgefit::mpm
