// Williams-series tip (crack.hpp, kWilliams): the window of continuum about
// the tip, the 1-D search of the tip along the line, and the test of the
// answer's sensitivity to the window.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "crack_impl.hpp"
#include "orthotropic_series.hpp"
#include "williams_basis.hpp"

namespace bridgefit::dic::detail {
namespace {

struct WilliamsFit {
  double ssr = std::numeric_limits<double>::infinity();
  double k = 0;  // K_I per (fit radius)^0.5, in the series' own scale (its sign: opening)
  double rotation = 0;  // the rigid rotation column's coefficient: radians x the fit radius
  int rows = 0, cols = 0;
};

// The tip's near field: Williams' series (isotropic, kappa) or, for an
// orthotropic plate, Lekhnitskii's (orthotropic_series.hpp, orders
// 1..mode1_terms), and the closing-traction fields below.
struct TipBasis {
  const CrackTipOptions* o = nullptr;
  std::optional<OrthotropicSeries> ortho;
  std::vector<double> k_factor;  // K_I per unit coefficient, per series column
  explicit TipBasis(const CrackTipOptions& options) : o(&options) {
    if (options.Orthotropic()) {
      ortho.emplace(options.s11, options.s22, options.s12, options.s66, 1, options.mode1_terms);
      k_factor = ortho->ModeIFactor();
    } else {
      k_factor.assign(options.mode1_terms + options.mode2_terms, 0.0);
      k_factor[0] = 1.0;  // the mode I n = 1 column: K / (2 mu) / sqrt(2 pi) per unit
    }
  }
  int SeriesColumns() const {
    return ortho ? ortho->Columns() : o->mode1_terms + o->mode2_terms;
  }
  // u1/u2 of each series column at (x, y) in the crack frame.
  void Eval(double x, double y, double* u1, double* u2) const {
    if (ortho) {
      ortho->Eval(std::hypot(x, y), std::atan2(y, x), u1, u2);
      return;
    }
    const WilliamsPowers powers = WilliamsPowers::AtPoint(
        x, y, 1, std::max({1, o->mode1_terms, 2 * o->mode2_terms - 1}));
    int c = 0;
    for (int n = 1; n <= o->mode1_terms; ++n, ++c) powers.ModeI(n, o->kappa, u1 + c, u2 + c);
    for (int m = 0; m < o->mode2_terms; ++m, ++c)
      powers.ModeII(2 * m + 1, o->kappa, u1 + c, u2 + c);
  }
  // Closing traction sigma22 = 1 on the faces: strains (s12, s22) sigma22,
  // as (s12 / s22 x, y); isotropic s12 / s22 = -nu' = -(3 - kappa)/(1 + kappa).
  double LateralRatio() const {
    return ortho ? o->s12 / o->s22 : -(3 - o->kappa) / (1 + o->kappa);
  }
};

// min |A c - b|: the normal equations of the unit-norm columns (Cholesky,
// LDLT), about 4x fewer operations than a pivoted QR of the 2N x 9-11
// matrix; the scan makes about 500 such fits a frame. Where the scaled Gram
// matrix is near singular (rcond < 1e-10: its condition is that of A
// squared) the pivoted QR answers instead. The residual is then formed from
// A itself, so its accuracy does not depend on the Gram matrix's.
Eigen::VectorXd LeastSquares(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  const Eigen::VectorXd norm = A.colwise().norm().transpose();
  if ((norm.array() > 0).all()) {
    const Eigen::VectorXd inv = norm.cwiseInverse();
    const Eigen::MatrixXd As = A * inv.asDiagonal();
    Eigen::MatrixXd G(A.cols(), A.cols());
    G.setZero();
    G.selfadjointView<Eigen::Lower>().rankUpdate(As.transpose());
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(G.selfadjointView<Eigen::Lower>());
    if (ldlt.info() == Eigen::Success && ldlt.rcond() > 1e-10)
      return inv.asDiagonal() * ldlt.solve(As.transpose() * b);
  }
  return Eigen::ColPivHouseholderQR<Eigen::MatrixXd>(A).solve(b);
}

// `closing_terms` (0-2) adds the fields of a closing traction on the faces
// uniform (sigma22 = 1: u = (r x, y)) and linear along the crack (Airy
// x^3/6, sigma22 = x: u = (r x^2/2 - y^2/2, x y)), r = s12 / s22 (-nu' when
// isotropic): near the tip of a bridged crack the faces carry tractions,
// which the traction-free series cannot follow.
WilliamsFit FitWilliams(const std::vector<const LocalPoint*>& pts, double s_tip,
                        const TipBasis& basis, int closing_terms = 0) {
  WilliamsFit fit;
  const CrackTipOptions& o = *basis.o;
  const double L = o.line.Length();
  const double tx = (o.line.x1 - o.line.x0) / L, ty = (o.line.y1 - o.line.y0) / L;
  const int series = basis.SeriesColumns();
  const double lateral = basis.LateralRatio();
  const int cols = 3 + series + closing_terms;
  const int rows = 2 * static_cast<int>(pts.size());
  if (rows < 2 * cols) return fit;
  Eigen::MatrixXd A(rows, cols);
  Eigen::VectorXd b(rows);
  std::vector<double> f1(series), f2(series);
  const double R = o.fit_radius_px;  // normalizes r for conditioning
  for (size_t k = 0; k < pts.size(); ++k) {
    const LocalPoint& p = *pts[k];
    const double xl = (p.s - s_tip) / R, yl = p.n / R;
    const int ru = 2 * static_cast<int>(k), rv = ru + 1;
    // Rigid motion in image axes: translation, rotation about the tip.
    A(ru, 0) = 1; A(rv, 0) = 0;
    A(ru, 1) = 0; A(rv, 1) = 1;
    const double dx = xl * tx - yl * ty, dy = xl * ty + yl * tx;
    A(ru, 2) = -dy; A(rv, 2) = dx;
    int c = 3;
    auto put = [&](double fx, double fy) {  // local -> image axes
      A(ru, c) = fx * tx - fy * ty;
      A(rv, c) = fx * ty + fy * tx;
      ++c;
    };
    basis.Eval(xl, yl, f1.data(), f2.data());
    for (int j = 0; j < series; ++j) put(f1[j], f2[j]);
    if (closing_terms >= 1) put(lateral * xl, yl);
    if (closing_terms >= 2) put(0.5 * lateral * xl * xl - 0.5 * yl * yl, xl * yl);
    b(ru) = p.u;
    b(rv) = p.v;
  }
  const Eigen::VectorXd c = LeastSquares(A, b);
  fit.ssr = (A * c - b).squaredNorm();
  for (int j = 0; j < series; ++j) fit.k += basis.k_factor[j] * c(3 + j);
  fit.rotation = c(2);
  fit.rows = rows;
  fit.cols = cols;
  return fit;
}

// Grid points by what they say about the continuum: not read (masked, a
// fixed crack band, or within the band half width of the line), correlated
// and failed (out of image, no convergence, low correlation, unreached), ok.
enum class PointKind : char { kIgnored, kFailed, kOk };

std::vector<PointKind> Kinds(const DisplacementField& f, const CrackTipOptions& o) {
  std::vector<PointKind> kind(f.size(), PointKind::kIgnored);
  for (size_t i = 0; i < f.size(); ++i) {
    if (f.status[i] == PointStatus::kMasked || f.status[i] == PointStatus::kCrackBand) continue;
    double s, n;
    o.line.ToLocal(f.x[i], f.y[i], &s, &n);
    if (std::abs(n) < o.band_half_width_px) continue;
    kind[i] = f.ok(i) ? PointKind::kOk : PointKind::kFailed;
  }
  return kind;
}

// A continuum point is ok and has no failed point among its 8 grid
// neighbours (fields that are not a grid, ny == 1: ok alone).
bool Continuum(const DisplacementField& f, const std::vector<PointKind>& kind, size_t i) {
  if (kind[i] != PointKind::kOk) return false;
  if (f.ny <= 1 || static_cast<size_t>(f.nx) * f.ny != f.size()) return true;
  const int ix = static_cast<int>(i % f.nx), iy = static_cast<int>(i / f.nx);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int jx = ix + dx, jy = iy + dy;
      if (jx < 0 || jy < 0 || jx >= f.nx || jy >= f.ny) continue;
      if (kind[static_cast<size_t>(jy) * f.nx + jx] == PointKind::kFailed) return false;
    }
  return true;
}

// Sizes of the 8-connected clusters of failed grid points (0 elsewhere;
// fields that are not a grid: 1 per failed point).
std::vector<int> FailedClusterSizes(const DisplacementField& f, const std::vector<PointKind>& kind) {
  std::vector<int> size(f.size(), 0);
  const bool grid = f.ny > 1 && static_cast<size_t>(f.nx) * f.ny == f.size();
  std::vector<size_t> stack, members;
  for (size_t seed = 0; seed < f.size(); ++seed) {
    if (kind[seed] != PointKind::kFailed || size[seed] != 0) continue;
    members.clear();
    stack.assign(1, seed);
    size[seed] = -1;  // visited
    while (!stack.empty()) {
      const size_t i = stack.back();
      stack.pop_back();
      members.push_back(i);
      if (!grid) continue;
      const int ix = static_cast<int>(i % f.nx), iy = static_cast<int>(i / f.nx);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int jx = ix + dx, jy = iy + dy;
          if (jx < 0 || jy < 0 || jx >= f.nx || jy >= f.ny) continue;
          const size_t j = static_cast<size_t>(jy) * f.nx + jx;
          if (kind[j] != PointKind::kFailed || size[j] != 0) continue;
          size[j] = -1;
          stack.push_back(j);
        }
    }
    for (size_t i : members) size[i] = static_cast<int>(members.size());
  }
  return size;
}

// The distance from the centre to the nearest failed point of a cluster of
// at least min_failed_cluster points (a hole, a grip, the notch, the image's
// edge; 8-connected), per direction seen from the centre: a point farther
// than that in its direction lies behind the cluster (in its shadow) and is
// not read. Each failed point hides the directions within its grid cell's
// half diagonal (8-connected neighbours leave no gap between their
// shadows); a failed point within that half diagonal of the centre hides
// every direction. Smaller clusters only take their neighbours out of the
// fit (Continuum). Fields that are not a grid: no clusters, no shadow.
class Shadow {
 public:
  static constexpr int kBins = 2048;
  Shadow(const DisplacementField& f, const std::vector<PointKind>& kind, double xc, double yc,
         const CrackTipOptions& o)
      : xc_(xc), yc_(yc), nearest_(kBins, std::numeric_limits<double>::infinity()) {
    clear_radius_ = o.fit_radius_px;
    const bool grid = f.ny > 1 && f.nx > 1 && static_cast<size_t>(f.nx) * f.ny == f.size();
    if (!grid) return;
    const double half_diagonal =
        0.5 * std::hypot(f.x[1] - f.x[0], f.y[static_cast<size_t>(f.nx)] - f.y[0]);
    const double reach = o.fit_radius_px + half_diagonal;
    const std::vector<int> cluster = FailedClusterSizes(f, kind);
    const double bin = 2.0 * std::numbers::pi / kBins;
    for (size_t i = 0; i < f.size(); ++i) {
      if (cluster[i] < o.min_failed_cluster) continue;
      const double dx = f.x[i] - xc, dy = f.y[i] - yc, r = std::hypot(dx, dy);
      if (r >= reach) continue;
      clear_radius_ = std::min(clear_radius_, r);
      // 5% more than the half diagonal: no gap at a bin's edge.
      const double half = r <= 1.05 * half_diagonal ? std::numbers::pi
                                                    : std::asin(1.05 * half_diagonal / r);
      const int b0 = Bin(dx, dy), span = static_cast<int>(std::ceil(half / bin));
      for (int k = -std::min(span, kBins / 2); k <= std::min(span, kBins / 2); ++k) {
        double& near = nearest_[static_cast<size_t>(((b0 + k) % kBins + kBins) % kBins)];
        near = std::min(near, r);
      }
    }
  }
  bool Hides(double x, double y) const {
    const double dx = x - xc_, dy = y - yc_;
    return std::hypot(dx, dy) > nearest_[static_cast<size_t>(Bin(dx, dy))];
  }
  // Within this distance of the centre nothing is hidden (<= fit radius).
  double ClearRadius() const { return clear_radius_; }

 private:
  static int Bin(double dx, double dy) {
    const double t = std::atan2(dy, dx) + std::numbers::pi;  // [0, 2 pi]
    return std::min(kBins - 1, static_cast<int>(t / (2.0 * std::numbers::pi) * kBins));
  }
  double xc_, yc_, clear_radius_ = 0;
  std::vector<double> nearest_;
};

// Whether a window of `radius` about (xc, yc) reaches point p: within the
// radius, outside the band about the line and not behind the line's start
// (the notch root: behind it lies the notch, a slot, often unspeckled
// background that moves with the camera, not the crack's flanks; aldic
// without ROI fitted its notch flanks into the early frames' tips).
bool InWindow(const LocalPoint& p, double xc, double yc, double radius, const CrackTipOptions& o) {
  return std::hypot(p.x - xc, p.y - yc) < radius && std::abs(p.n) >= o.band_half_width_px &&
         p.s >= 0;
}

// The points the window reads: continuum, not hidden, in its reach.
std::vector<const LocalPoint*> WindowPoints(const std::vector<LocalPoint>& pts,
                                            const std::vector<char>& readable, double xc,
                                            double yc, double radius, const CrackTipOptions& o) {
  std::vector<const LocalPoint*> set;
  for (const LocalPoint& p : pts)
    if (readable[p.index] && InWindow(p, xc, yc, radius, o)) set.push_back(&p);
  return set;
}

// Too small or too one-sided for the Williams fit: ahead of the centre,
// above and below the line each, the window keeps fewer points than that
// quadrant of the disk of min_fit_radius_fraction x fit radius holds grid
// positions (any status, outside the band). A disk cut all round at radius
// r is short when r < that fraction of the fit radius (the earlier rule, to
// about one grid step: the cut's inner neighbours are no continuum); a
// cluster that hides one sector leaves the rest of the disk. Nothing is
// required behind the centre (an ROI may end there).
bool WindowShort(const DisplacementField& f, const std::vector<const LocalPoint*>& set,
                 double s_centre, const CrackTipOptions& o) {
  const double r_min = o.min_fit_radius_fraction * o.fit_radius_px;
  int need_above = 0, need_below = 0, kept_above = 0, kept_below = 0;
  for (size_t i = 0; i < f.size(); ++i) {
    double s, n;
    o.line.ToLocal(f.x[i], f.y[i], &s, &n);
    if (s <= s_centre || std::abs(n) < o.band_half_width_px || std::hypot(s - s_centre, n) >= r_min)
      continue;
    ++(n > 0 ? need_above : need_below);
  }
  for (const LocalPoint* p : set)
    if (p->s > s_centre) ++(p->n > 0 ? kept_above : kept_below);
  return kept_above < need_above || kept_below < need_below;
}

struct TipScan {
  bool found = false;
  double s = 0, sigma = 0;
  WilliamsFit fit;
  bool interior_lo = false, interior_hi = false;
};

// Grid scan of the residual over [lo, hi] (quarter-station spacing), golden
// section about the best node; sigma from Delta SSR = SSR / (N - p).
TipScan ScanTip(const std::vector<const LocalPoint*>& set, double lo, double hi,
                const TipBasis& basis, int closing_terms = 0) {
  const CrackTipOptions& o = *basis.o;
  TipScan out;
  const double h = std::max(0.5, 0.25 * o.station_spacing_px);
  std::vector<double> grid_s;
  for (double s = lo; s <= hi + 1e-9; s += h) grid_s.push_back(s);
  // The scan's fits are independent (about 100 QR solves of 2N x 9-12).
  std::vector<double> grid_ssr(grid_s.size());
#pragma omp parallel for schedule(dynamic, 2)
  for (size_t k = 0; k < grid_s.size(); ++k)
    grid_ssr[k] = FitWilliams(set, grid_s[k], basis, closing_terms).ssr;
  size_t best = 0;
  for (size_t k = 1; k < grid_s.size(); ++k)
    if (grid_ssr[k] < grid_ssr[best]) best = k;
  if (grid_s.empty() || !std::isfinite(grid_ssr[best])) return out;
  double a = grid_s[best] - h, c = grid_s[best] + h;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = c - g * (c - a), x2 = a + g * (c - a);
  auto ssr = [&](double s) { return FitWilliams(set, s, basis, closing_terms).ssr; };
  double f1 = ssr(x1), f2 = ssr(x2);
  for (int it = 0; it < 30 && c - a > 1e-3; ++it) {
    if (f1 < f2) {
      c = x2; x2 = x1; f2 = f1; x1 = c - g * (c - a); f1 = ssr(x1);
    } else {
      a = x1; x1 = x2; f1 = f2; x2 = a + g * (c - a); f2 = ssr(x2);
    }
  }
  out.s = 0.5 * (a + c);
  out.fit = FitWilliams(set, out.s, basis, closing_terms);
  const double e = std::max(h, 1.0);
  const double fp = ssr(out.s + e), fm = ssr(out.s - e);
  const double curv = (fp + fm - 2 * out.fit.ssr) / (e * e);
  const double sigma2 = out.fit.ssr / std::max(1, out.fit.rows - out.fit.cols - 1);
  out.sigma = curv > 0 ? std::sqrt(2.0 * sigma2 / curv) : o.station_spacing_px;
  out.interior_lo = out.s > lo + 0.5 * h || lo <= 0.0;
  out.interior_hi = out.s < hi - 0.5 * h || hi >= o.line.Length();
  out.found = std::isfinite(out.s);
  return out;
}

// The window's share of the tip's uncertainty: the tip found in a window of
// kWindowModelRadius x the fit radius minus the tip. A field the series does
// not hold (a second crack, a grip, a zone the closing terms miss) pulls
// the tip by an amount that changes with the window; the white-noise sigma
// does not see it (a second crack as strong 25 px above, its tip 30 px
// behind: the tip 10.8 px short at a sigma of 0.2 px). The smaller window's
// own extra noise explains shift^2 = sigma_small^2 - sigma^2 on average
// (nested fits); the rest is the share.
constexpr double kWindowModelRadius = 0.7;

void WindowShare(const std::vector<LocalPoint>& pts, const std::vector<char>& readable, double xs,
                 double ys, double lo, double hi, const TipBasis& basis, const TipScan& scan,
                 CrackTipResult& res) {
  const CrackTipOptions& o = *basis.o;
  const TipScan smaller = ScanTip(
      WindowPoints(pts, readable, xs, ys, kWindowModelRadius * o.fit_radius_px, o), lo, hi, basis);
  if (!smaller.found) return;
  const double shift = smaller.s - scan.s;
  const double noise2 = std::max(0.0, smaller.sigma * smaller.sigma - scan.sigma * scan.sigma);
  res.williams_window_shift_px = shift;
  res.williams_window_share_px = std::sqrt(std::max(0.0, shift * shift - noise2));
}

// A rigid rotation of the window enters the fit's rigid columns to first
// order only; its second-order part, the equibiaxial contraction
// -(1 - cos theta) r, is no traction-free field and pulls the tip (an LEFM
// field turned by 1 / 2 / 3 degrees, 15 mm window: +0.28 / +1.2 mm / no
// Williams tip). Where that part at the fit radius exceeds
// kRotationResidualShare x the fit's RMS residual, the fit's rotation is
// taken out of the deformed positions exactly (about the window's centre;
// the translation this leaves is the fit's) and the scan repeated, twice at
// most (the second pass removes what the first estimate missed).
constexpr double kRotationResidualShare = 0.1;

bool RotationMatters(const TipScan& scan, double radius) {
  if (!scan.found || scan.fit.rows == 0) return false;
  const double theta = scan.fit.rotation / radius;
  const double rms = std::sqrt(scan.fit.ssr / scan.fit.rows);
  return radius * (1.0 - std::cos(theta)) > kRotationResidualShare * rms;
}

// The points with the rotation theta (radians, counter-clockwise in image
// axes) taken out of their deformed positions about (xc, yc).
std::vector<LocalPoint> Unrotated(const std::vector<LocalPoint>& pts, double theta, double xc,
                                  double yc, const CrackLine& line) {
  const double c = std::cos(theta), sn = std::sin(theta);
  const double L = line.Length();
  const double tx = (line.x1 - line.x0) / L, ty = (line.y1 - line.y0) / L;
  std::vector<LocalPoint> out = pts;
  for (LocalPoint& p : out) {
    const double dx = p.x + p.u - xc, dy = p.y + p.v - yc;
    p.u = xc + c * dx + sn * dy - p.x;
    p.v = yc - sn * dx + c * dy - p.y;
    p.us = p.u * tx + p.v * ty;
    p.un = -p.u * ty + p.v * tx;
  }
  return out;
}

}  // namespace

// Stages: window centre -> continuum not hidden by a failed cluster ->
// enough of it ahead of the centre on both sides of the line? -> tip scan ->
// the scan again with the radius one station smaller: a tip that moves by
// more than twice its uncertainty (at least one station / sqrt(12)) is
// unstable, not used -> the model's shares of the uncertainty (closing
// tractions, the window's size).
void WilliamsTip(const DisplacementField& field, const std::vector<LocalPoint>& pts,
                 const CrackTipOptions& o, CrackTipResult& res) {
  const double ds = o.station_spacing_px;
  const double s_start = res.sqrt_cod.found ? std::clamp(res.sqrt_cod.s_px, res.jump.s_px - o.fit_radius_px, res.jump.s_px)
                                            : res.jump.s_px;
  double xs, ys;
  o.line.FromLocal(s_start, 0, &xs, &ys);
  res.williams_window = true;
  res.williams_centre_s_px = s_start;
  const std::vector<PointKind> kind = Kinds(field, o);
  const Shadow shadow(field, kind, xs, ys, o);
  res.williams_clear_radius_px = shadow.ClearRadius();
  std::vector<char> readable(field.size(), 0);
  int hidden = 0;
  // Where the field reaches behind the line's start by more than a band
  // half width (the notch root lies inside it, not at its edge), the
  // subsets of points within a band half width in front of the root
  // straddle the notch as those near the line straddle the crack: not read
  // (aldic without ROI: flank subsets there, up to 3 px apart between runs,
  // had moved 0240's tip by 2.7 px between band and full field).
  const bool root_inside = std::any_of(pts.begin(), pts.end(), [&](const LocalPoint& p) {
    return p.s < -o.band_half_width_px;
  });
  const double s_read = root_inside ? o.band_half_width_px : 0.0;
  for (const LocalPoint& p : pts) {
    if (!Continuum(field, kind, p.index) || p.s < s_read) continue;
    const bool behind = shadow.Hides(p.x, p.y);
    if (behind && InWindow(p, xs, ys, o.fit_radius_px, o)) ++hidden;
    readable[p.index] = behind ? 0 : 1;
  }
  res.williams_hidden_points = hidden;
  const std::vector<const LocalPoint*> set =
      WindowPoints(pts, readable, xs, ys, o.fit_radius_px, o);
  res.williams_points = static_cast<int>(set.size());
  if (WindowShort(field, set, s_start, o)) {
    res.williams_window_short = true;  // too little continuum ahead: no Williams tip
    return;
  }
  const double lo = std::max(0.0, s_start - 0.5 * o.fit_radius_px);
  const double hi = std::min(o.line.Length(), s_start + 0.5 * o.fit_radius_px);
  const TipBasis basis(o);
  std::vector<const LocalPoint*> fit_set = set;
  TipScan scan = ScanTip(fit_set, lo, hi, basis);
  std::vector<LocalPoint> unrotated;
  const std::vector<LocalPoint>* use = &pts;
  for (int pass = 0; pass < 2 && RotationMatters(scan, o.fit_radius_px); ++pass) {
    res.williams_rotation_rad +=
        std::asin(std::clamp(scan.fit.rotation / o.fit_radius_px, -1.0, 1.0));
    unrotated = Unrotated(pts, res.williams_rotation_rad, xs, ys, o.line);
    use = &unrotated;
    fit_set = WindowPoints(unrotated, readable, xs, ys, o.fit_radius_px, o);
    scan = ScanTip(fit_set, lo, hi, basis);
  }
  const std::vector<LocalPoint>& fit_pts = *use;
  if (!scan.found) return;
  TipEstimate& t = res.williams;
  t.s_px = scan.s;
  t.uncertainty_px = scan.sigma;
  // K_I / (2 mu) of the isotropic fit; an orthotropic plate has no mu (NaN).
  res.k_over_2mu_sqrt_px = basis.ortho ? std::numeric_limits<double>::quiet_NaN()
                                       : scan.fit.k * std::sqrt(2.0 * std::numbers::pi) /
                                             std::sqrt(o.fit_radius_px);
  res.williams_residual_px = std::sqrt(scan.fit.ssr / std::max(1, scan.fit.rows));
  t.found = scan.fit.k > 0 && scan.interior_lo && scan.interior_hi;
  if (!scan.interior_hi || scan.s > res.last_station_px) res.tip_at_edge = true;
  SetPosition(o.line, &t);
  if (!t.found) return;
  const TipScan inner =
      ScanTip(WindowPoints(fit_pts, readable, xs, ys, o.fit_radius_px - ds, o), lo, hi, basis);
  // The fit's sigma, at least the grid's resolution (one station / sqrt(12)).
  const double resolved = std::max(scan.sigma, ds / std::sqrt(12.0));
  const double tol = 2.0 * resolved;
  res.williams_shift_px = inner.found ? inner.s - scan.s : std::numeric_limits<double>::infinity();
  res.williams_unstable = !(std::abs(res.williams_shift_px) <= tol);
  // The model's share: the tip with closing tractions on the faces allowed
  // (a bridged crack's near-tip field) minus the traction-free tip; on a
  // bridged crack the traction-free tip lies behind the true one (measured
  // 3-6 px on synth's bridged frames, 0.3-0.6 mm), the closing fit within
  // about 1 px. The closing terms expand the tractions about the tip: a
  // zone shorter than the window (a law that peaks and ends near the tip:
  // cubic, 3 MPa, delta_c 0.09 mm, 6-7 px behind) is followed only in a
  // smaller window, so the fit runs again in the smallest window the tip
  // fit accepts (min_fit_radius_fraction x the radius) and the larger shift
  // counts. Added to the tip's uncertainty (with the grid's resolution, one
  // station / sqrt(12), an independent share), so that a bridged frame's
  // length is not stated tighter than the model allows.
  const TipScan closed = ScanTip(fit_set, lo, hi, basis, 2);
  res.williams_closing_shift_px = closed.found ? closed.s - scan.s : 0.0;
  const TipScan closed_small =
      ScanTip(WindowPoints(fit_pts, readable, xs, ys, o.min_fit_radius_fraction * o.fit_radius_px, o),
              lo, hi, basis, 2);
  res.williams_closing_shift_small_px = closed_small.found ? closed_small.s - scan.s : 0.0;
  const double closing = std::max(std::abs(res.williams_closing_shift_px),
                                  std::abs(res.williams_closing_shift_small_px));
  WindowShare(fit_pts, readable, xs, ys, lo, hi, basis, scan, res);
  t.uncertainty_px = std::sqrt(resolved * resolved + closing * closing +
                               res.williams_window_share_px * res.williams_window_share_px);
}

}  // namespace bridgefit::dic::detail
