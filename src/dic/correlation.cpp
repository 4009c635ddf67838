// Subset DIC: NCC integer search, IC-GN refinement (Pan et al. 2013, ZNSSD;
// second-order warp composition after Gao et al. 2015), wavefront
// propagation from seeds, incremental reference update along a sequence.
#include "bridgefit/dic/correlation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <omp.h>
#include <opencv2/imgproc.hpp>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "interpolation.hpp"

namespace bridgefit::dic {

const char* PointStatusName(PointStatus status) {
  switch (status) {
    case PointStatus::kOk: return "ok";
    case PointStatus::kMasked: return "masked";
    case PointStatus::kCrackBand: return "crack_band";
    case PointStatus::kOutOfImage: return "out_of_image";
    case PointStatus::kNoConvergence: return "no_convergence";
    case PointStatus::kLowCorrelation: return "low_correlation";
    case PointStatus::kUnreached: return "unreached";
  }
  return "unknown";
}

double CrackLine::Length() const { return std::hypot(x1 - x0, y1 - y0); }
void CrackLine::ToLocal(double x, double y, double* s, double* n) const {
  const double L = Length();
  const double tx = (x1 - x0) / L, ty = (y1 - y0) / L;
  *s = (x - x0) * tx + (y - y0) * ty;
  *n = -(x - x0) * ty + (y - y0) * tx;
}
void CrackLine::FromLocal(double s, double n, double* x, double* y) const {
  const double L = Length();
  const double tx = (x1 - x0) / L, ty = (y1 - y0) / L;
  *x = x0 + s * tx - n * ty;
  *y = y0 + s * ty + n * tx;
}

bool CorrelationOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (subset_size < 7 || subset_size % 2 == 0) return fail("subset size must be odd and >= 7");
  if (step < 1) return fail("step must be >= 1 px");
  if (max_iterations < 1) return fail("max_iterations must be >= 1");
  if (!(convergence_px > 0)) return fail("convergence_px must be > 0");
  if (!(min_zncc > -1 && min_zncc < 1)) return fail("min_zncc must be in (-1, 1)");
  if (seed_search_radius < 0 || local_search_radius < 0) return fail("search radii must be >= 0");
  if (has_crack && !(crack.Length() > 1.0)) return fail("crack line must be longer than 1 px");
  if (threads < 0) return fail("threads must be >= 0");
  return true;
}

double DisplacementField::ValidFraction() const {
  std::size_t used = 0, good = 0;
  for (PointStatus s : status) {
    if (s == PointStatus::kMasked || s == PointStatus::kCrackBand) continue;
    ++used;
    if (s == PointStatus::kOk) ++good;
  }
  return used ? static_cast<double>(good) / used : 0.0;
}

double DisplacementField::MeanZncc() const {
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < size(); ++i)
    if (ok(i)) {
      sum += zncc[i];
      ++n;
    }
  return n ? sum / n : 0.0;
}

std::string CorrelationSummary::BriefReport() const {
  return fmt::format(
      "frame {}: reference {} ({} updates), {}/{} points valid, mean ZNCC {:.4f}, "
      "{:.1f} iterations/point, {:.2f} s, {:.0f} points/s",
      frame, reference_frame, reference_updates, valid, points, mean_zncc, mean_iterations,
      wall_s, points_per_s);
}

namespace {

using detail::InterpolatedImage;
constexpr int kNp = 12;  // parameters stored per point (second order; first order leaves 6 at 0)
// Parameter layout: u ux uy uxx uxy uyy | v vx vy vxx vxy vyy
using Params = std::array<double, kNp>;

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

struct PointResult {
  Params p{};
  double zncc = 0;
  int iterations = 0;
  PointStatus status = PointStatus::kUnreached;
};

// Per-thread buffers for one subset.
struct Workspace {
  std::vector<float> f, g, J;
};

// IC-GN on one subset centred at (xc, yc) in the reference (may be
// fractional), starting from p.
template <int NP>
PointResult SolveIcgn(const InterpolatedImage& ref, const InterpolatedImage& def, double xc,
                      double yc, const Params& p0, const CorrelationOptions& opt, Workspace& ws) {
  constexpr bool kSecond = NP == 12;
  const int M = opt.subset_size / 2;
  const int side = 2 * M + 1, n = side * side;
  PointResult out;
  out.p = p0;
  if (!ref.Inside(xc - M, yc - M) || !ref.Inside(xc + M, yc + M)) {
    out.status = PointStatus::kOutOfImage;
    return out;
  }
  ws.f.resize(n);
  ws.J.resize(static_cast<size_t>(n) * NP);
  // Reference subset, its gradient and the Gauss-Newton Hessian, once.
  double fsum = 0;
  for (int k = 0, dy = -M; dy <= M; ++dy)
    for (int dx = -M; dx <= M; ++dx, ++k) {
      float gx, gy;
      ws.f[k] = ref.ValueGrad(xc + dx, yc + dy, &gx, &gy);
      fsum += ws.f[k];
      float* J = ws.J.data() + static_cast<size_t>(k) * NP;
      if constexpr (kSecond) {
        const float qx = 0.5f * dx * dx, qxy = static_cast<float>(dx * dy), qy = 0.5f * dy * dy;
        const float g[2] = {gx, gy};
        for (int c = 0; c < 2; ++c) {
          J[6 * c + 0] = g[c];
          J[6 * c + 1] = g[c] * dx;
          J[6 * c + 2] = g[c] * dy;
          J[6 * c + 3] = g[c] * qx;
          J[6 * c + 4] = g[c] * qxy;
          J[6 * c + 5] = g[c] * qy;
        }
      } else {
        J[0] = gx; J[1] = gx * dx; J[2] = gx * dy;
        J[3] = gy; J[4] = gy * dx; J[5] = gy * dy;
      }
    }
  const double fmean = fsum / n;
  double fss = 0;
  Eigen::Matrix<double, NP, NP> H = Eigen::Matrix<double, NP, NP>::Zero();
  // Hessian sum J J^T: float partial sums per subset row, double across rows.
  for (int k0 = 0; k0 < n; k0 += side) {
    Eigen::Matrix<float, NP, NP> Hrow = Eigen::Matrix<float, NP, NP>::Zero();
    for (int k = k0; k < k0 + side; ++k) {
      ws.f[k] -= static_cast<float>(fmean);
      fss += static_cast<double>(ws.f[k]) * ws.f[k];
      const Eigen::Map<const Eigen::Matrix<float, NP, 1>> j(ws.J.data() + static_cast<size_t>(k) * NP);
      Hrow.noalias() += j * j.transpose();
    }
    H += Hrow.template cast<double>();
  }
  const double fnorm = std::sqrt(fss);
  Eigen::LDLT<Eigen::Matrix<double, NP, NP>> ldlt(H);
  if (fnorm < 1e-6 * n || ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-12)) {
    out.status = PointStatus::kLowCorrelation;  // no texture
    return out;
  }
  // Internal parameter vector in J order: first order [u ux uy v vx vy].
  auto to_dp = [&](const Eigen::Matrix<double, NP, 1>& d) {
    Params dp{};
    if constexpr (kSecond) {
      for (int i = 0; i < 12; ++i) dp[i] = d[i];
    } else {
      dp[0] = d[0]; dp[1] = d[1]; dp[2] = d[2]; dp[6] = d[3]; dp[7] = d[4]; dp[8] = d[5];
    }
    return dp;
  };
  Params& p = out.p;
  double znssd = 4.0;
  for (int it = 1; it <= opt.max_iterations; ++it) {
    out.iterations = it;
    // Deformed subset g(W(xi; p)); the warp is affine (or quadratic) in the
    // local coordinates, evaluated incrementally along rows.
    double gsum = 0, gss = 0;
    std::vector<float>& gbuf = ws.g;
    gbuf.resize(n);
    bool outside = false;
    if constexpr (kSecond) {
      for (int k = 0, dy = -M; dy <= M && !outside; ++dy)
        for (int dx = -M; dx <= M; ++dx, ++k) {
          const double X = xc + dx + p[0] + p[1] * dx + p[2] * dy + 0.5 * p[3] * dx * dx +
                           p[4] * dx * dy + 0.5 * p[5] * dy * dy;
          const double Y = yc + dy + p[6] + p[7] * dx + p[8] * dy + 0.5 * p[9] * dx * dx +
                           p[10] * dx * dy + 0.5 * p[11] * dy * dy;
          if (!def.Inside(X, Y)) {
            outside = true;
            break;
          }
          const float v = def.Value(X, Y);
          gbuf[k] = v;
          gsum += v;
        }
    } else {
      // Affine warp: the subset is inside when its four corners are; the
      // positions advance by constant steps along a row.
      const double ax = 1 + p[1], bx = p[2], ay = p[7], by = 1 + p[8];
      for (int cy = -M; cy <= M && !outside; cy += 2 * M)
        for (int cx = -M; cx <= M; cx += 2 * M)
          if (!def.Inside(xc + p[0] + ax * cx + bx * cy, yc + p[6] + ay * cx + by * cy))
            outside = true;
      if (!outside)
        for (int k = 0, dy = -M; dy <= M; ++dy) {
          const double X0 = xc + p[0] - ax * M + bx * dy, Y0 = yc + p[6] - ay * M + by * dy;
          float row_sum = 0.0f;
          for (int j = 0; j < side; ++j, ++k) {
            const float v = def.Value(X0 + ax * j, Y0 + ay * j);
            gbuf[k] = v;
            row_sum += v;
          }
          gsum += row_sum;
        }
    }
    if (outside) {
      out.status = PointStatus::kOutOfImage;
      return out;
    }
    const double gmean = gsum / n;
    for (int k = 0; k < n; ++k) {
      gbuf[k] -= static_cast<float>(gmean);
      gss += static_cast<double>(gbuf[k]) * gbuf[k];
    }
    const double gnorm = std::sqrt(gss);
    if (gnorm < 1e-6 * n) {
      out.status = PointStatus::kLowCorrelation;
      return out;
    }
    const float ratio = static_cast<float>(fnorm / gnorm);
    Eigen::Matrix<double, NP, 1> b = Eigen::Matrix<double, NP, 1>::Zero();
    double cross = 0;
    {
      Eigen::Matrix<float, NP, 1> bf = Eigen::Matrix<float, NP, 1>::Zero();
      for (int k = 0; k < n; ++k) {
        const float e = ws.f[k] - ratio * gbuf[k];
        cross += static_cast<double>(ws.f[k]) * gbuf[k];
        bf.noalias() += e * Eigen::Map<const Eigen::Matrix<float, NP, 1>>(
                                ws.J.data() + static_cast<size_t>(k) * NP);
        if ((k & 255) == 255) {  // keep float partial sums short
          b += bf.template cast<double>();
          bf.setZero();
        }
      }
      b += bf.template cast<double>();
    }
    znssd = 2.0 - 2.0 * cross / (fnorm * gnorm);
    const Eigen::Matrix<double, NP, 1> d = -ldlt.solve(b);
    const Params dp = to_dp(d);
    ComposeInverse(p, dp, kSecond);
    double norm2 = dp[0] * dp[0] + dp[6] * dp[6] +
                   M * M * (dp[1] * dp[1] + dp[2] * dp[2] + dp[7] * dp[7] + dp[8] * dp[8]);
    if constexpr (kSecond)
      norm2 += 0.25 * M * M * M * M *
               (dp[3] * dp[3] + dp[4] * dp[4] + dp[5] * dp[5] + dp[9] * dp[9] + dp[10] * dp[10] +
                dp[11] * dp[11]);
    if (!std::isfinite(norm2) || std::abs(p[0]) > 1e5 || std::abs(p[6]) > 1e5) {
      out.status = PointStatus::kNoConvergence;
      return out;
    }
    if (std::sqrt(norm2) < opt.convergence_px) {
      out.zncc = 1.0 - 0.5 * znssd;
      out.status = out.zncc >= opt.min_zncc ? PointStatus::kOk : PointStatus::kLowCorrelation;
      return out;
    }
  }
  out.zncc = 1.0 - 0.5 * znssd;
  out.status = PointStatus::kNoConvergence;
  return out;
}

PointResult Solve(const InterpolatedImage& ref, const InterpolatedImage& def, double xc, double yc,
                  const Params& p0, const CorrelationOptions& opt, Workspace& ws) {
  return opt.shape == ShapeFunction::kSecondOrder ? SolveIcgn<12>(ref, def, xc, yc, p0, opt, ws)
                                                  : SolveIcgn<6>(ref, def, xc, yc, p0, opt, ws);
}

// Integer displacement of the subset at round(xc, yc) by NCC
// (TM_CCOEFF_NORMED) within +-radius of the guess. False when the window
// leaves the image.
bool IntegerSearch(const Image& ref, const Image& def, double xc, double yc, double gu, double gv,
                   int M, int radius, double* u, double* v, double* peak) {
  const int cx = static_cast<int>(std::lround(xc)), cy = static_cast<int>(std::lround(yc));
  if (cx - M < 0 || cy - M < 0 || cx + M >= ref.width || cy + M >= ref.height) return false;
  const int side = 2 * M + 1;
  int wx0 = static_cast<int>(std::lround(cx + gu)) - M - radius;
  int wy0 = static_cast<int>(std::lround(cy + gv)) - M - radius;
  int wx1 = wx0 + side + 2 * radius, wy1 = wy0 + side + 2 * radius;
  wx0 = std::max(wx0, 0);
  wy0 = std::max(wy0, 0);
  wx1 = std::min(wx1, def.width);
  wy1 = std::min(wy1, def.height);
  if (wx1 - wx0 < side || wy1 - wy0 < side) return false;
  const cv::Mat ref_mat(ref.height, ref.width, CV_32F, const_cast<float*>(ref.pixels.data()));
  const cv::Mat def_mat(def.height, def.width, CV_32F, const_cast<float*>(def.pixels.data()));
  const cv::Mat templ = ref_mat(cv::Rect(cx - M, cy - M, side, side));
  const cv::Mat window = def_mat(cv::Rect(wx0, wy0, wx1 - wx0, wy1 - wy0));
  cv::Mat score;
  cv::matchTemplate(window, templ, score, cv::TM_CCOEFF_NORMED);
  double max_val = 0;
  cv::Point loc;
  cv::minMaxLoc(score, nullptr, &max_val, nullptr, &loc);
  if (!std::isfinite(max_val)) return false;
  *u = (wx0 + loc.x + M) - xc;
  *v = (wy0 + loc.y + M) - yc;
  *peak = max_val;
  return true;
}

}  // namespace

struct Correlator::Impl {
  CorrelationOptions opt;
  DisplacementField grid;        // positions and static status
  std::vector<char> eligible;    // correlate this point
  Image ref_image;               // current reference
  InterpolatedImage ref_interp;
  int ref_index = 0;
  std::vector<Params> ref_p;     // point motion original -> current reference
  std::vector<char> ref_known;
  Image prev_image;
  int frame_index = 0;
  std::vector<Params> prev_total;  // last frame's total motion
  std::vector<char> prev_ok;
  std::vector<PointStatus> prev_status;
  // Why a point has no known position in the current reference (it failed
  // in that frame): reported for it from then on.
  std::vector<PointStatus> lost_status;
  int updates = 0;

  int Threads() const { return opt.threads > 0 ? opt.threads : omp_get_max_threads(); }

  void BuildGrid(const Image& reference) {
    const int M = opt.subset_size / 2;
    const int x0 = std::max(opt.roi_x0 < 0 ? 0 : opt.roi_x0, M + 2);
    const int y0 = std::max(opt.roi_y0 < 0 ? 0 : opt.roi_y0, M + 2);
    const int x1 = std::min(opt.roi_x1 < 0 ? reference.width : opt.roi_x1, reference.width - M - 3);
    const int y1 = std::min(opt.roi_y1 < 0 ? reference.height : opt.roi_y1, reference.height - M - 3);
    if (x1 < x0 || y1 < y0)
      throw Error(ErrorKind::kInput, "region of interest holds no complete subset",
                  {.field = "roi", .expected = "a region larger than one subset inside the image"});
    grid.nx = (x1 - x0) / opt.step + 1;
    grid.ny = (y1 - y0) / opt.step + 1;
    const size_t n = static_cast<size_t>(grid.nx) * grid.ny;
    grid.x.resize(n); grid.y.resize(n);
    grid.u.assign(n, 0); grid.v.assign(n, 0);
    grid.dudx.assign(n, 0); grid.dudy.assign(n, 0); grid.dvdx.assign(n, 0); grid.dvdy.assign(n, 0);
    grid.zncc.assign(n, 0); grid.iterations.assign(n, 0);
    grid.status.assign(n, PointStatus::kUnreached);
    eligible.assign(n, 1);
    const double L = opt.has_crack ? opt.crack.Length() : 0;
    double tx = 0, ty = 0;
    if (opt.has_crack) {
      tx = (opt.crack.x1 - opt.crack.x0) / L;
      ty = (opt.crack.y1 - opt.crack.y0) / L;
    }
    // Half extent of a subset square along the line normal and along the line.
    const double half_n = (M + 0.5) * (std::abs(tx) + std::abs(ty)) + 0.5;
    const double half_s = (M + 0.5) * (std::abs(tx) + std::abs(ty));
    for (int iy = 0; iy < grid.ny; ++iy)
      for (int ix = 0; ix < grid.nx; ++ix) {
        const size_t i = static_cast<size_t>(iy) * grid.nx + ix;
        grid.x[i] = x0 + ix * opt.step;
        grid.y[i] = y0 + iy * opt.step;
        if (!opt.mask.empty() &&
            opt.mask.at(static_cast<int>(grid.x[i]), static_cast<int>(grid.y[i])) <= 0) {
          grid.status[i] = PointStatus::kMasked;
          eligible[i] = 0;
          continue;
        }
        if (opt.has_crack) {
          double s, nn;
          opt.crack.ToLocal(grid.x[i], grid.y[i], &s, &nn);
          if (std::abs(nn) <= half_n && s >= -half_s && s <= L + half_s) {
            grid.status[i] = PointStatus::kCrackBand;
            eligible[i] = 0;
          }
        }
      }
  }

  // One pass: every eligible point from `guess` (where given) or by
  // wavefront propagation from converged neighbours and seeds.
  std::vector<PointResult> Pass(const Image& def_image, const InterpolatedImage& def_interp,
                                const std::vector<Params>& guess, const std::vector<char>& has_guess,
                                std::size_t* solves) {
    const size_t n = grid.size();
    const int M = opt.subset_size / 2;
    const int nthreads = Threads();
    std::vector<PointResult> res(n);
    std::vector<char> done(n, 0);
    std::vector<double> cx(n), cy(n);
    std::vector<char> active(n, 0);
    for (size_t i = 0; i < n; ++i) {
      active[i] = eligible[i] && ref_known[i];
      if (eligible[i] && !ref_known[i]) {
        res[i].status = lost_status.empty() ? PointStatus::kUnreached : lost_status[i];
        done[i] = 1;
      }
      if (!eligible[i]) {
        res[i].status = grid.status[i];
        done[i] = 1;
      }
      cx[i] = grid.x[i] + ref_p[i][0];
      cy[i] = grid.y[i] + ref_p[i][6];
    }
    std::size_t count = 0;
    // Points with a guess, in parallel; converged ones are done.
    auto solve_guessed = [&](const std::vector<Params>& g, const std::vector<char>& hg) {
      std::vector<size_t> list;
      for (size_t i = 0; i < n; ++i)
        if (active[i] && !done[i] && hg[i]) list.push_back(i);
#pragma omp parallel num_threads(nthreads) reduction(+ : count)
      {
        Workspace ws;
#pragma omp for schedule(dynamic, 16)
        for (size_t k = 0; k < list.size(); ++k) {
          const size_t i = list[k];
          PointResult r = Solve(ref_interp, def_interp, cx[i], cy[i], g[i], opt, ws);
          ++count;
          if (r.status == PointStatus::kOk) {
            res[i] = r;
            done[i] = 1;
          }
        }
      }
    };
    // Wavefront propagation over the points flagged in `act` on a lattice of
    // the given stride, then seeds for what no front reached.
    auto propagate = [&](const std::vector<char>& act, int stride) {
      auto neighbours = [&](size_t i, size_t* out) {
        int m = 0;
        const int ix = static_cast<int>(i % grid.nx), iy = static_cast<int>(i / grid.nx);
        if (ix >= stride) out[m++] = i - stride;
        if (ix + stride < grid.nx) out[m++] = i + stride;
        if (iy >= stride) out[m++] = i - static_cast<size_t>(stride) * grid.nx;
        if (iy + stride < grid.ny) out[m++] = i + static_cast<size_t>(stride) * grid.nx;
        return m;
      };
      auto frontier_of = [&](const std::vector<size_t>& from) {
        std::vector<size_t> front;
        std::vector<char> in_front(n, 0);
        for (size_t i : from) {
          if (res[i].status != PointStatus::kOk) continue;
          size_t nb[4];
          const int m = neighbours(i, nb);
          for (int k = 0; k < m; ++k)
            if (act[nb[k]] && !done[nb[k]] && !in_front[nb[k]]) {
              in_front[nb[k]] = 1;
              front.push_back(nb[k]);
            }
        }
        return front;
      };
      std::vector<size_t> good;
      for (size_t i = 0; i < n; ++i)
        if (done[i] && res[i].status == PointStatus::kOk) good.push_back(i);
      std::vector<size_t> front = frontier_of(good);
      int seed_attempts = 0;
      for (;;) {
        while (!front.empty()) {
          std::vector<PointResult> out(front.size());
          // Small fronts run serially: a parallel region costs more than they do.
  #pragma omp parallel num_threads(nthreads) reduction(+ : count) if (front.size() >= 48)
          {
            Workspace ws;
  #pragma omp for schedule(dynamic, 8)
            for (size_t k = 0; k < front.size(); ++k) {
              const size_t i = front[k];
              size_t nb[4];
              const int m = neighbours(i, nb);
              int best = -1;
              for (int j = 0; j < m; ++j)
                if (done[nb[j]] && res[nb[j]].status == PointStatus::kOk &&
                    (best < 0 || res[nb[j]].zncc > res[nb[best]].zncc))
                  best = j;
              Params p{};
              if (best >= 0) {
                const size_t b = nb[best];
                p = res[b].p;
                const double dx = cx[i] - cx[b], dy = cy[i] - cy[b];
                p[0] += p[1] * dx + p[2] * dy;
                p[6] += p[7] * dx + p[8] * dy;
              }
              PointResult r = Solve(ref_interp, def_interp, cx[i], cy[i], p, opt, ws);
              ++count;
              if (r.status != PointStatus::kOk && r.status != PointStatus::kOutOfImage) {
                double u, v, peak;
                if (IntegerSearch(ref_image, def_image, cx[i], cy[i], p[0], p[6], M,
                                  opt.local_search_radius, &u, &v, &peak)) {
                  Params q{};
                  q[0] = u;
                  q[6] = v;
                  PointResult r2 = Solve(ref_interp, def_interp, cx[i], cy[i], q, opt, ws);
                  ++count;
                  if (r2.status == PointStatus::kOk || r2.zncc > r.zncc) r = r2;
                }
              }
              out[k] = r;
            }
          }
          for (size_t k = 0; k < front.size(); ++k) {
            res[front[k]] = out[k];
            done[front[k]] = 1;
          }
          front = frontier_of(front);
        }
        // Unprocessed points whose subset, moved like the converged points on
        // average, would leave the image: out of image, no seed attempt.
        {
          double mu = 0, mv = 0;
          size_t m = 0;
          for (size_t i = 0; i < n; ++i)
            if (done[i] && eligible[i] && res[i].status == PointStatus::kOk) {
              mu += res[i].p[0];
              mv += res[i].p[6];
              ++m;
            }
          if (m > 0) {
            mu /= m;
            mv /= m;
            for (size_t i = 0; i < n; ++i) {
              if (!act[i] || done[i]) continue;
              const double gu = has_guess[i] ? guess[i][0] : mu, gv = has_guess[i] ? guess[i][6] : mv;
              if (!def_interp.Inside(cx[i] + gu - M, cy[i] + gv - M) ||
                  !def_interp.Inside(cx[i] + gu + M, cy[i] + gv + M)) {
                res[i].status = PointStatus::kOutOfImage;
                done[i] = 1;
              }
            }
          }
        }
        // Seed the most interior unprocessed point (grid distance transform).
        std::vector<int> dist(n, -1);
        std::vector<size_t> queue;
        for (size_t i = 0; i < n; ++i)
          if (!(act[i] && !done[i])) {
            dist[i] = 0;
            queue.push_back(i);
          }
        if (queue.size() == n) break;  // nothing left
        if (seed_attempts >= opt.max_seed_attempts) break;
        for (size_t q = 0; q < queue.size(); ++q) {
          size_t nb[4];
          const int m = neighbours(queue[q], nb);
          for (int k = 0; k < m; ++k)
            if (dist[nb[k]] < 0) {
              dist[nb[k]] = dist[queue[q]] + 1;
              queue.push_back(nb[k]);
            }
        }
        // Unprocessed points on the image border get distance from the edge too.
        size_t seed = n;
        int best_d = -1;
        for (size_t i = 0; i < n; ++i) {
          if (!(act[i] && !done[i])) continue;
          const int ix = static_cast<int>(i % grid.nx), iy = static_cast<int>(i / grid.nx);
          const int di = dist[i] < 0 ? std::numeric_limits<int>::max() : dist[i];
          const int d = std::min({di, ix + 1, iy + 1, grid.nx - ix, grid.ny - iy});
          if (d > best_d) {
            best_d = d;
            seed = i;
          }
        }
        ++seed_attempts;
        // Guess: the mean motion of converged points (0 when none).
        double gu = 0, gv = 0;
        size_t ng = 0;
        for (size_t i = 0; i < n; ++i)
          if (done[i] && res[i].status == PointStatus::kOk && eligible[i]) {
            gu += res[i].p[0];
            gv += res[i].p[6];
            ++ng;
          }
        if (ng) {
          gu /= ng;
          gv /= ng;
        }
        if (has_guess[seed]) {
          gu = guess[seed][0];
          gv = guess[seed][6];
        }
        Workspace ws;
        double u, v, peak;
        PointResult r;
        r.status = PointStatus::kOutOfImage;  // unless the search window fits
        if (IntegerSearch(ref_image, def_image, cx[seed], cy[seed], gu, gv, M,
                          opt.seed_search_radius, &u, &v, &peak)) {
          Params q{};
          q[0] = u;
          q[6] = v;
          r = Solve(ref_interp, def_interp, cx[seed], cy[seed], q, opt, ws);
          ++count;
        }
        res[seed] = r;
        done[seed] = 1;
        front = frontier_of({seed});
      }
    };
    const int coarse_stride = 4;
    bool any_guess = false;
    size_t n_active = 0;
    for (size_t i = 0; i < n; ++i) {
      any_guess = any_guess || (active[i] && has_guess[i]);
      n_active += active[i] ? 1 : 0;
    }
    if (!any_guess && n_active >= 1500) {
      // Coarse lattice first (few, serial-ish fronts), then every other point
      // from its nearest converged lattice point in one parallel loop.
      std::vector<char> coarse(n, 0);
      for (size_t i = 0; i < n; ++i) {
        const int ix = static_cast<int>(i % grid.nx), iy = static_cast<int>(i / grid.nx);
        coarse[i] = active[i] && ix % coarse_stride == 0 && iy % coarse_stride == 0;
      }
      propagate(coarse, coarse_stride);
      std::vector<Params> g2(n);
      std::vector<char> hg2(n, 0);
      for (size_t i = 0; i < n; ++i) {
        if (!active[i] || done[i]) continue;
        const int ix = static_cast<int>(i % grid.nx), iy = static_cast<int>(i / grid.nx);
        const int bx = ix - ix % coarse_stride, by = iy - iy % coarse_stride;
        double best_d = 1e300;
        for (int jy : {by, by + coarse_stride})
          for (int jx : {bx, bx + coarse_stride}) {
            if (jx >= grid.nx || jy >= grid.ny) continue;
            const size_t j = static_cast<size_t>(jy) * grid.nx + jx;
            if (!done[j] || res[j].status != PointStatus::kOk) continue;
            const double d = std::hypot(jx - ix, jy - iy);
            if (d < best_d) {
              best_d = d;
              Params p = res[j].p;
              const double dx = cx[i] - cx[j], dy = cy[i] - cy[j];
              p[0] += p[1] * dx + p[2] * dy;
              p[6] += p[7] * dx + p[8] * dy;
              g2[i] = p;
              hg2[i] = 1;
            }
          }
      }
      solve_guessed(g2, hg2);
    } else {
      solve_guessed(guess, has_guess);
    }
    propagate(active, 1);
    *solves += count;
    return res;
  }

  // Fills unknown reference motions from known same-side grid neighbours
  // (never across crack-band or masked points, which are not eligible).
  void FillUnknown(std::vector<Params>& p, std::vector<char>& known) const {
    const size_t n = grid.size();
    for (int sweep = 0; sweep < 50; ++sweep) {
      bool changed = false;
      std::vector<char> newly(n, 0);
      std::vector<Params> add(n);
      for (size_t i = 0; i < n; ++i) {
        if (known[i] || !eligible[i]) continue;
        const int ix = static_cast<int>(i % grid.nx), iy = static_cast<int>(i / grid.nx);
        Params sum{};
        int m = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int jx = ix + dx, jy = iy + dy;
            if (jx < 0 || jy < 0 || jx >= grid.nx || jy >= grid.ny) continue;
            const size_t j = static_cast<size_t>(jy) * grid.nx + jx;
            if (!known[j] || !eligible[j]) continue;
            for (int k = 0; k < kNp; ++k) sum[k] += p[j][k];
            ++m;
          }
        if (m >= 2) {
          for (int k = 0; k < kNp; ++k) add[i][k] = sum[k] / m;
          newly[i] = 1;
          changed = true;
        }
      }
      for (size_t i = 0; i < n; ++i)
        if (newly[i]) {
          p[i] = add[i];
          known[i] = 1;
        }
      if (!changed) break;
    }
  }

  DisplacementField Next(const Image& frame, CorrelationSummary* summary) {
    if (frame.width != ref_image.width || frame.height != ref_image.height)
      throw Error(ErrorKind::kInput,
                  fmt::format("image size {}x{} differs from the reference {}x{}", frame.width,
                              frame.height, grid_width, grid_height),
                  {.expected = "all images of a sequence with the same size"});
    Stopwatch watch;
    ++frame_index;
    const size_t n = grid.size();
    const InterpolatedImage def_interp(frame, opt.interpolation);
    std::size_t solves = 0;
    std::vector<PointResult> res;
    for (int attempt = 0; attempt < 2; ++attempt) {
      // Guesses: last frame's total motion expressed from the current reference.
      std::vector<Params> guess(n);
      std::vector<char> has_guess(n, 0);
      for (size_t i = 0; i < n; ++i) {
        if (!prev_ok.empty() && prev_ok[i] && ref_known[i]) {
          guess[i] = Increment(prev_total[i], ref_p[i]);
          has_guess[i] = 1;
        }
      }
      res = Pass(frame, def_interp, guess, has_guess, &solves);
      size_t used = 0, good = 0;
      double zsum = 0;
      for (size_t i = 0; i < n; ++i) {
        if (!eligible[i]) continue;
        ++used;
        if (res[i].status == PointStatus::kOk) {
          ++good;
          zsum += res[i].zncc;
        }
      }
      const double valid_fraction = used ? static_cast<double>(good) / used : 0;
      const double mean_zncc = good ? zsum / good : 0;
      const bool poor = valid_fraction < opt.update_min_valid_fraction ||
                        mean_zncc < opt.update_min_mean_zncc;
      if (attempt == 0 && poor && opt.incremental && ref_index != frame_index - 1 &&
          !prev_image.empty()) {
        // Reference update: the previous frame becomes the reference.
        ref_image = prev_image;
        ref_interp = InterpolatedImage(ref_image, opt.interpolation);
        ref_p = prev_total;
        ref_known = prev_ok;
        FillUnknown(ref_p, ref_known);
        for (size_t i = 0; i < n; ++i)
          if (!ref_known[i]) lost_status[i] = prev_status[i];
        ref_index = frame_index - 1;
        ++updates;
        continue;
      }
      break;
    }
    // Accumulate: total = increment o reference motion.
    DisplacementField field = grid;
    std::vector<Params> total(n);
    std::vector<char> ok(n, 0);
    double zsum = 0, itsum = 0;
    size_t used = 0, good = 0;
    for (size_t i = 0; i < n; ++i) {
      field.status[i] = res[i].status;
      field.zncc[i] = res[i].zncc;
      field.iterations[i] = res[i].iterations;
      if (!eligible[i]) continue;
      ++used;
      itsum += res[i].iterations;
      if (res[i].status != PointStatus::kOk) continue;
      total[i] = Accumulate(res[i].p, ref_p[i]);
      ok[i] = 1;
      ++good;
      zsum += res[i].zncc;
      field.u[i] = total[i][0];
      field.v[i] = total[i][6];
      field.dudx[i] = total[i][1];
      field.dudy[i] = total[i][2];
      field.dvdx[i] = total[i][7];
      field.dvdy[i] = total[i][8];
    }
    prev_total = std::move(total);
    prev_ok = std::move(ok);
    prev_status = field.status;
    prev_image = frame;
    if (summary) {
      summary->frame = frame_index;
      summary->reference_frame = ref_index;
      summary->reference_updates = updates;
      summary->points = used;
      summary->valid = good;
      summary->mean_zncc = good ? zsum / good : 0;
      summary->mean_iterations = used ? itsum / used : 0;
      summary->wall_s = watch.Seconds();
      summary->points_per_s = summary->wall_s > 0 ? solves / summary->wall_s : 0;
    }
    return field;
  }

  // Total motion from the increment d (current reference -> frame) and the
  // reference motion r (original -> current reference): u = u_r + d,
  // F = F_d F_r (first-order terms; second-order terms of d are kept as is).
  static Params Accumulate(const Params& d, const Params& r) {
    Params t = d;
    t[0] = r[0] + d[0];
    t[6] = r[6] + d[6];
    const double Fd[2][2] = {{1 + d[1], d[2]}, {d[7], 1 + d[8]}};
    const double Fr[2][2] = {{1 + r[1], r[2]}, {r[7], 1 + r[8]}};
    t[1] = Fd[0][0] * Fr[0][0] + Fd[0][1] * Fr[1][0] - 1;
    t[2] = Fd[0][0] * Fr[0][1] + Fd[0][1] * Fr[1][1];
    t[7] = Fd[1][0] * Fr[0][0] + Fd[1][1] * Fr[1][0];
    t[8] = Fd[1][0] * Fr[0][1] + Fd[1][1] * Fr[1][1] - 1;
    return t;
  }
  // Inverse of Accumulate: increment d with total t = d o r.
  static Params Increment(const Params& t, const Params& r) {
    Params d = t;
    d[0] = t[0] - r[0];
    d[6] = t[6] - r[6];
    const double Ft[2][2] = {{1 + t[1], t[2]}, {t[7], 1 + t[8]}};
    const double Fr[2][2] = {{1 + r[1], r[2]}, {r[7], 1 + r[8]}};
    const double det = Fr[0][0] * Fr[1][1] - Fr[0][1] * Fr[1][0];
    const double Ri[2][2] = {{Fr[1][1] / det, -Fr[0][1] / det}, {-Fr[1][0] / det, Fr[0][0] / det}};
    d[1] = Ft[0][0] * Ri[0][0] + Ft[0][1] * Ri[1][0] - 1;
    d[2] = Ft[0][0] * Ri[0][1] + Ft[0][1] * Ri[1][1];
    d[7] = Ft[1][0] * Ri[0][0] + Ft[1][1] * Ri[1][0];
    d[8] = Ft[1][0] * Ri[0][1] + Ft[1][1] * Ri[1][1] - 1;
    return d;
  }

  int grid_width = 0, grid_height = 0;
};

Correlator::Correlator(const CorrelationOptions& options, const Image& reference)
    : impl_(std::make_unique<Impl>()) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid DIC options: " + why);
  BF_CHECK_INPUT(!reference.empty(), "reference image is empty");
  if (!options.mask.empty() &&
      (options.mask.width != reference.width || options.mask.height != reference.height))
    throw Error(ErrorKind::kInput, "mask size differs from the reference image",
                {.field = "mask", .expected = fmt::format("{}x{}", reference.width, reference.height)});
  if (options.has_crack) {
    const CrackLine& c = options.crack;
    auto inside = [&](double x, double y) {
      return x >= 0 && y >= 0 && x <= reference.width - 1 && y <= reference.height - 1;
    };
    if (!inside(c.x0, c.y0) || !inside(c.x1, c.y1))
      throw Error(ErrorKind::kInput, "crack line leaves the image",
                  {.field = "--crack-line",
                   .value = fmt::format("{},{},{},{}", c.x0, c.y0, c.x1, c.y1),
                   .expected = fmt::format("end points inside 0..{} x 0..{} px", reference.width - 1,
                                           reference.height - 1)});
  }
  Impl& m = *impl_;
  m.opt = options;
  m.grid_width = reference.width;
  m.grid_height = reference.height;
  m.BuildGrid(reference);
  m.ref_image = reference;
  m.ref_interp = InterpolatedImage(reference, options.interpolation);
  m.ref_p.assign(m.grid.size(), Params{});
  m.ref_known.assign(m.grid.size(), 1);
  m.lost_status.assign(m.grid.size(), PointStatus::kUnreached);
}

Correlator::~Correlator() = default;
const DisplacementField& Correlator::Grid() const { return impl_->grid; }
DisplacementField Correlator::Next(const Image& frame, CorrelationSummary* summary) {
  return impl_->Next(frame, summary);
}

DisplacementField CorrelatePair(const Image& reference, const Image& deformed,
                                const CorrelationOptions& options, CorrelationSummary* summary) {
  Correlator correlator(options, reference);
  return correlator.Next(deformed, summary);
}

}  // namespace bridgefit::dic
