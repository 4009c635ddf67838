// IC-GN on one subset (see icgn.hpp for the stages). First order: affine
// warp, reference rows read from the node maps, H^-1 cached per point;
// second order: Gao et al. (2015) 6x6 warp matrix, data built per solve.
#include "icgn.hpp"

#include <cmath>

namespace bridgefit::dic::detail {
namespace {

// Degree-2 polynomial in (x, y), basis [x^2, xy, y^2, x, y, 1].
using Poly = std::array<double, 6>;
Poly TruncatedProduct(const Poly& p, const Poly& q) {
  return {p[0] * q[5] + p[3] * q[3] + p[5] * q[0],
          p[1] * q[5] + p[3] * q[4] + p[4] * q[3] + p[5] * q[1],
          p[2] * q[5] + p[4] * q[4] + p[5] * q[2],
          p[3] * q[5] + p[5] * q[3],
          p[4] * q[5] + p[5] * q[4],
          p[5] * q[5]};
}
// Gao et al. (2015) 6x6 warp matrix acting on [x^2, xy, y^2, x, y, 1].
Eigen::Matrix<double, 6, 6> WarpMatrix2(const Params& p) {
  const Poly a{0.5 * p[3], p[4], 0.5 * p[5], 1 + p[1], p[2], p[0]};
  const Poly b{0.5 * p[9], p[10], 0.5 * p[11], p[7], 1 + p[8], p[6]};
  const Poly rows[6] = {TruncatedProduct(a, a), TruncatedProduct(a, b), TruncatedProduct(b, b),
                        a, b, Poly{0, 0, 0, 0, 0, 1}};
  Eigen::Matrix<double, 6, 6> W;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) W(r, c) = rows[r][c];
  return W;
}

// W(p) <- W(p) o W(dp)^-1 (inverse-compositional update).
void ComposeInverse(Params& p, const Params& dp, bool second_order) {
  if (!second_order) {
    Eigen::Matrix3d W, D;
    W << 1 + p[1], p[2], p[0], p[7], 1 + p[8], p[6], 0, 0, 1;
    D << 1 + dp[1], dp[2], dp[0], dp[7], 1 + dp[8], dp[6], 0, 0, 1;
    const Eigen::Matrix3d R = W * D.inverse();
    p[0] = R(0, 2); p[1] = R(0, 0) - 1; p[2] = R(0, 1);
    p[6] = R(1, 2); p[7] = R(1, 0); p[8] = R(1, 1) - 1;
    return;
  }
  const Eigen::Matrix<double, 6, 6> R = WarpMatrix2(p) * WarpMatrix2(dp).inverse();
  p[0] = R(3, 5); p[1] = R(3, 3) - 1; p[2] = R(3, 4);
  p[3] = 2 * R(3, 0); p[4] = R(3, 1); p[5] = 2 * R(3, 2);
  p[6] = R(4, 5); p[7] = R(4, 3); p[8] = R(4, 4) - 1;
  p[9] = 2 * R(4, 0); p[10] = R(4, 1); p[11] = 2 * R(4, 2);
}

// Convergence norm |dp| (OpenCorr's): translation plus gradient terms times
// the subset half size M (second-order terms times M^2 / 2).
double IncrementNorm(const Params& dp, int M, bool second_order) {
  double norm2 = dp[0] * dp[0] + dp[6] * dp[6] +
                 M * M * (dp[1] * dp[1] + dp[2] * dp[2] + dp[7] * dp[7] + dp[8] * dp[8]);
  if (second_order)
    norm2 += 0.25 * M * M * M * M *
             (dp[3] * dp[3] + dp[4] * dp[4] + dp[5] * dp[5] + dp[9] * dp[9] + dp[10] * dp[10] +
              dp[11] * dp[11]);
  return std::sqrt(norm2);
}

// Rows of the reference subset: f, df/dx, df/dy with a row stride.
struct SubsetRows {
  const float *f, *fx, *fy;
  int stride;
};

// Reference rows: straight from the node maps at an integer centre,
// otherwise interpolated into the workspace.
// The end-of-iteration test shared by both warp orders: a diverged warp ends as
// kNoConvergence, a converged one as kOk or kLowCorrelation (by its ZNCC).
// Returns false while the iteration should go on.
bool IterationEnds(double norm, const Params& p, double zncc, const CorrelationOptions& opt,
                   PointResult* out) {
  if (!std::isfinite(norm) || std::abs(p[0]) > 1e5 || std::abs(p[6]) > 1e5) {
    out->status = PointStatus::kNoConvergence;
    return true;
  }
  out->zncc = zncc;
  if (norm < opt.convergence_px) {
    out->status = out->zncc >= opt.min_zncc ? PointStatus::kOk : PointStatus::kLowCorrelation;
    return true;
  }
  return false;
}

SubsetRows ReferenceRows(const ReferenceView& ref, double xc, double yc, int M, Workspace& ws) {
  const int side = 2 * M + 1;
  if (ref.nodes && !ref.nodes->empty() && xc == std::floor(xc) && yc == std::floor(yc)) {
    const size_t offset = static_cast<size_t>(static_cast<int>(yc) - M) * ref.nodes->width +
                          (static_cast<int>(xc) - M);
    return {ref.nodes->value.data() + offset, ref.nodes->gx.data() + offset,
            ref.nodes->gy.data() + offset, ref.nodes->width};
  }
  const size_t n = static_cast<size_t>(side) * side;
  ws.f.resize(n);
  ws.fx.resize(n);
  ws.fy.resize(n);
  for (int k = 0, dy = -M; dy <= M; ++dy)
    for (int dx = -M; dx <= M; ++dx, ++k)
      ws.f[k] = ref.image->ValueGrad(xc + dx, yc + dy, &ws.fx[k], &ws.fy[k]);
  return {ws.f.data(), ws.fx.data(), ws.fy.data(), side};
}

// Stage reference (first order): fmean, |f~|, H = sum J J^T with
// J = [fx, fx dx, fx dy, fy, fy dx, fy dy], and sum f~ J. Row sums in float,
// rows combined in double with their dy.
void BuildReferenceSubset(const SubsetRows& rows, int M, ReferenceSubset* out) {
  const int side = 2 * M + 1, n = side * side;
  double fsum = 0;
  for (int r = 0; r < side; ++r) {
    const float* f = rows.f + static_cast<size_t>(r) * rows.stride;
    float s = 0;
#pragma omp simd reduction(+ : s)
    for (int j = 0; j < side; ++j) s += f[j];
    fsum += s;
  }
  out->fmean = fsum / n;
  const float fm = static_cast<float>(out->fmean);
  // Moments sum q phi_i phi_j, phi = [1, dx, dy], for q = fx^2, fx fy, fy^2:
  // index 0: 1, 1: dx, 2: dy, 3: dx^2, 4: dx dy, 5: dy^2.
  double mxx[6] = {}, mxy[6] = {}, myy[6] = {}, fj[6] = {}, fss = 0;
  for (int r = 0; r < side; ++r) {
    const size_t o = static_cast<size_t>(r) * rows.stride;
    const float *f = rows.f + o, *fx = rows.fx + o, *fy = rows.fy + o;
    const double dy = r - M;
    float sff = 0, a0 = 0, a1 = 0, a2 = 0, b0 = 0, b1 = 0, b2 = 0, c0 = 0, c1 = 0, c2 = 0;
    float jx0 = 0, jx1 = 0, jy0 = 0, jy1 = 0;
#pragma omp simd reduction(+ : sff, a0, a1, a2, b0, b1, b2, c0, c1, c2, jx0, jx1, jy0, jy1)
    for (int j = 0; j < side; ++j) {
      const float dx = static_cast<float>(j - M);
      const float ft = f[j] - fm, gx = fx[j], gy = fy[j];
      const float qxx = gx * gx, qxy = gx * gy, qyy = gy * gy;
      sff += ft * ft;
      a0 += qxx; a1 += qxx * dx; a2 += qxx * dx * dx;
      b0 += qxy; b1 += qxy * dx; b2 += qxy * dx * dx;
      c0 += qyy; c1 += qyy * dx; c2 += qyy * dx * dx;
      jx0 += ft * gx; jx1 += ft * gx * dx;
      jy0 += ft * gy; jy1 += ft * gy * dx;
    }
    fss += sff;
    auto add = [dy](double* m, float s0, float s1, float s2) {
      m[0] += s0; m[1] += s1; m[2] += dy * s0; m[3] += s2; m[4] += dy * s1; m[5] += dy * dy * s0;
    };
    add(mxx, a0, a1, a2);
    add(mxy, b0, b1, b2);
    add(myy, c0, c1, c2);
    fj[0] += jx0; fj[1] += jx1; fj[2] += dy * jx0;
    fj[3] += jy0; fj[4] += jy1; fj[5] += dy * jy0;
  }
  // phi_i phi_j -> moment index.
  static constexpr int kMoment[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
  Eigen::Matrix<double, 6, 6> H;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int m = kMoment[i][j];
      H(i, j) = mxx[m];
      H(i, 3 + j) = mxy[m];
      H(3 + i, j) = mxy[m];
      H(3 + i, 3 + j) = myy[m];
    }
  out->fnorm = std::sqrt(fss);
  for (int i = 0; i < 6; ++i) out->fJ[i] = fj[i];
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(H);
  out->textured = out->fnorm >= 1e-6 * n && ldlt.info() == Eigen::Success && ldlt.rcond() > 1e-12;
  if (out->textured) out->Hinv = ldlt.solve(Eigen::Matrix<double, 6, 6>::Identity());
  out->ready = true;
}

// Stage interpolation (first order): g(W(xi; p)) row by row; the affine
// warp moves by constant steps along a row. False when the warped subset
// leaves the image (it is inside when its four corners are).
bool SampleAffineSubset(const InterpolatedImage& def, double xc, double yc, const Params& p, int M,
                        float* g) {
  const int side = 2 * M + 1;
  const double ax = 1 + p[1], bx = p[2], ay = p[7], by = 1 + p[8];
  for (int cy = -M; cy <= M; cy += 2 * M)
    for (int cx = -M; cx <= M; cx += 2 * M)
      if (!def.Inside(xc + p[0] + ax * cx + bx * cy, yc + p[6] + ay * cx + by * cy)) return false;
  for (int r = 0, dy = -M; dy <= M; ++dy, ++r)
    def.SampleRow(xc + p[0] - ax * M + bx * dy, yc + p[6] - ay * M + by * dy, ax, ay, side,
                  g + static_cast<size_t>(r) * side);
  return true;
}

// Stage residual (first order): g~ = g - mean g, |g~|, sum f~ g~ and
// b = sum (f~ - |f~|/|g~| g~) J = sum f~ J - |f~|/|g~| sum g~ J.
struct Residual {
  Eigen::Matrix<double, 6, 1> b;
  double gnorm = 0, cross = 0;
};
Residual ComputeResidual(const SubsetRows& rows, const ReferenceSubset& ref, const float* g,
                         int M) {
  const int side = 2 * M + 1, n = side * side;
  double gsum = 0;
  for (int r = 0; r < side; ++r) {
    const float* gr = g + static_cast<size_t>(r) * side;
    float s = 0;
#pragma omp simd reduction(+ : s)
    for (int j = 0; j < side; ++j) s += gr[j];
    gsum += s;
  }
  const float gm = static_cast<float>(gsum / n), fm = static_cast<float>(ref.fmean);
  double gss = 0, cross = 0, gj[6] = {};
  for (int r = 0; r < side; ++r) {
    const size_t o = static_cast<size_t>(r) * rows.stride;
    const float *f = rows.f + o, *fx = rows.fx + o, *fy = rows.fy + o;
    const float* gr = g + static_cast<size_t>(r) * side;
    const double dy = r - M;
    float sgg = 0, sfg = 0, x0 = 0, x1 = 0, y0 = 0, y1 = 0;
#pragma omp simd reduction(+ : sgg, sfg, x0, x1, y0, y1)
    for (int j = 0; j < side; ++j) {
      const float dx = static_cast<float>(j - M);
      const float gt = gr[j] - gm;
      sgg += gt * gt;
      sfg += (f[j] - fm) * gt;
      x0 += gt * fx[j]; x1 += gt * fx[j] * dx;
      y0 += gt * fy[j]; y1 += gt * fy[j] * dx;
    }
    gss += sgg;
    cross += sfg;
    gj[0] += x0; gj[1] += x1; gj[2] += dy * x0;
    gj[3] += y0; gj[4] += y1; gj[5] += dy * y0;
  }
  Residual out;
  out.gnorm = std::sqrt(gss);
  out.cross = cross;
  const double ratio = out.gnorm > 0 ? ref.fnorm / out.gnorm : 0.0;
  for (int i = 0; i < 6; ++i) out.b[i] = ref.fJ[i] - ratio * gj[i];
  return out;
}

PointResult SolveFirstOrder(const ReferenceView& ref, const InterpolatedImage& def, double xc,
                            double yc, const Params& p0, const CorrelationOptions& opt,
                            ReferenceSubset* cache, Workspace& ws, bool profile) {
  const int M = opt.subset_size / 2, side = 2 * M + 1, n = side * side;
  StageClock clock(profile);
  PointResult out;
  out.p = p0;
  ReferenceSubset local;
  ReferenceSubset& data = cache ? *cache : local;
  const SubsetRows rows = ReferenceRows(ref, xc, yc, M, ws);
  if (!data.ready) BuildReferenceSubset(rows, M, &data);
  clock.Lap(&ws.times.reference);
  if (!data.textured) {
    out.status = PointStatus::kLowCorrelation;  // no texture
    return out;
  }
  ws.g.resize(n);
  Params& p = out.p;
  for (int it = 1; it <= opt.max_iterations; ++it) {
    out.iterations = it;
    const bool inside = SampleAffineSubset(def, xc, yc, p, M, ws.g.data());
    clock.Lap(&ws.times.interpolation);
    if (!inside) {
      out.status = PointStatus::kOutOfImage;
      return out;
    }
    const Residual res = ComputeResidual(rows, data, ws.g.data(), M);
    clock.Lap(&ws.times.residual);
    if (res.gnorm < 1e-6 * n) {
      out.status = PointStatus::kLowCorrelation;
      return out;
    }
    const double zncc = res.cross / (data.fnorm * res.gnorm);  // = 1 - ZNSSD / 2
    // Stage update: dp = -H^-1 b in J order [u ux uy v vx vy].
    const Eigen::Matrix<double, 6, 1> d = -(data.Hinv * res.b);
    Params dp{};
    dp[0] = d[0]; dp[1] = d[1]; dp[2] = d[2]; dp[6] = d[3]; dp[7] = d[4]; dp[8] = d[5];
    ComposeInverse(p, dp, false);
    const double norm = IncrementNorm(dp, M, false);
    clock.Lap(&ws.times.update);
    if (IterationEnds(norm, p, zncc, opt, &out)) return out;
  }
  out.status = PointStatus::kNoConvergence;  // never reported valid
  return out;
}

// Second order: quadratic warp, J and H built per solve (12 parameters).
PointResult SolveSecondOrder(const ReferenceView& ref, const InterpolatedImage& def, double xc,
                             double yc, const Params& p0, const CorrelationOptions& opt,
                             Workspace& ws, bool profile) {
  constexpr int NP = 12;
  const int M = opt.subset_size / 2, side = 2 * M + 1, n = side * side;
  StageClock clock(profile);
  PointResult out;
  out.p = p0;
  ws.f.resize(n);
  ws.J.resize(static_cast<size_t>(n) * NP);
  double fsum = 0;
  for (int k = 0, dy = -M; dy <= M; ++dy)
    for (int dx = -M; dx <= M; ++dx, ++k) {
      float gx, gy;
      ws.f[k] = ref.image->ValueGrad(xc + dx, yc + dy, &gx, &gy);
      fsum += ws.f[k];
      float* J = ws.J.data() + static_cast<size_t>(k) * NP;
      const float qx = 0.5f * dx * dx, qxy = static_cast<float>(dx * dy), qy = 0.5f * dy * dy;
      const float gc[2] = {gx, gy};
      for (int c = 0; c < 2; ++c) {
        J[6 * c + 0] = gc[c];
        J[6 * c + 1] = gc[c] * dx;
        J[6 * c + 2] = gc[c] * dy;
        J[6 * c + 3] = gc[c] * qx;
        J[6 * c + 4] = gc[c] * qxy;
        J[6 * c + 5] = gc[c] * qy;
      }
    }
  const double fmean = fsum / n;
  double fss = 0;
  Eigen::Matrix<double, NP, NP> H = Eigen::Matrix<double, NP, NP>::Zero();
  for (int k0 = 0; k0 < n; k0 += side) {  // float partial sums per row, double across rows
    Eigen::Matrix<float, NP, NP> Hrow = Eigen::Matrix<float, NP, NP>::Zero();
    for (int k = k0; k < k0 + side; ++k) {
      ws.f[k] -= static_cast<float>(fmean);
      fss += static_cast<double>(ws.f[k]) * ws.f[k];
      const Eigen::Map<const Eigen::Matrix<float, NP, 1>> j(ws.J.data() + static_cast<size_t>(k) * NP);
      Hrow.noalias() += j * j.transpose();
    }
    H += Hrow.cast<double>();
  }
  const double fnorm = std::sqrt(fss);
  const Eigen::LDLT<Eigen::Matrix<double, NP, NP>> ldlt(H);
  clock.Lap(&ws.times.reference);
  if (fnorm < 1e-6 * n || ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-12)) {
    out.status = PointStatus::kLowCorrelation;  // no texture
    return out;
  }
  Params& p = out.p;
  ws.g.resize(n);
  for (int it = 1; it <= opt.max_iterations; ++it) {
    out.iterations = it;
    double gsum = 0;
    for (int k = 0, dy = -M; dy <= M; ++dy)
      for (int dx = -M; dx <= M; ++dx, ++k) {
        const double X = xc + dx + p[0] + p[1] * dx + p[2] * dy + 0.5 * p[3] * dx * dx +
                         p[4] * dx * dy + 0.5 * p[5] * dy * dy;
        const double Y = yc + dy + p[6] + p[7] * dx + p[8] * dy + 0.5 * p[9] * dx * dx +
                         p[10] * dx * dy + 0.5 * p[11] * dy * dy;
        if (!def.Inside(X, Y)) {
          out.status = PointStatus::kOutOfImage;
          return out;
        }
        ws.g[k] = def.Value(X, Y);
        gsum += ws.g[k];
      }
    clock.Lap(&ws.times.interpolation);
    const double gmean = gsum / n;
    double gss = 0, cross = 0;
    for (int k = 0; k < n; ++k) {
      ws.g[k] -= static_cast<float>(gmean);
      gss += static_cast<double>(ws.g[k]) * ws.g[k];
      cross += static_cast<double>(ws.f[k]) * ws.g[k];
    }
    const double gnorm = std::sqrt(gss);
    if (gnorm < 1e-6 * n) {
      out.status = PointStatus::kLowCorrelation;
      return out;
    }
    const float ratio = static_cast<float>(fnorm / gnorm);
    Eigen::Matrix<double, NP, 1> b = Eigen::Matrix<double, NP, 1>::Zero();
    Eigen::Matrix<float, NP, 1> bf = Eigen::Matrix<float, NP, 1>::Zero();
    for (int k = 0; k < n; ++k) {
      const float e = ws.f[k] - ratio * ws.g[k];
      bf.noalias() += e * Eigen::Map<const Eigen::Matrix<float, NP, 1>>(
                              ws.J.data() + static_cast<size_t>(k) * NP);
      if ((k & 255) == 255) {  // keep float partial sums short
        b += bf.cast<double>();
        bf.setZero();
      }
    }
    b += bf.cast<double>();
    const double zncc = cross / (fnorm * gnorm);
    clock.Lap(&ws.times.residual);
    const Eigen::Matrix<double, NP, 1> d = -ldlt.solve(b);
    Params dp{};
    for (int i = 0; i < NP; ++i) dp[i] = d[i];
    ComposeInverse(p, dp, true);
    const double norm = IncrementNorm(dp, M, true);
    clock.Lap(&ws.times.update);
    if (IterationEnds(norm, p, zncc, opt, &out)) return out;
  }
  out.status = PointStatus::kNoConvergence;
  return out;
}

}  // namespace

PointResult SolveIcgn(const ReferenceView& ref, const InterpolatedImage& def, double xc, double yc,
                      const Params& p0, const CorrelationOptions& opt, ReferenceSubset* cache,
                      Workspace& ws, bool profile) {
  const int M = opt.subset_size / 2;
  if (!ref.image->Inside(xc - M, yc - M) || !ref.image->Inside(xc + M, yc + M)) {
    PointResult out;
    out.p = p0;
    out.status = PointStatus::kOutOfImage;
    return out;
  }
  return opt.shape == ShapeFunction::kSecondOrder
             ? SolveSecondOrder(ref, def, xc, yc, p0, opt, ws, profile)
             : SolveFirstOrder(ref, def, xc, yc, p0, opt, cache, ws, profile);
}

}  // namespace bridgefit::dic::detail
