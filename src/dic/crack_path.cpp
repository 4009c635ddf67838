// The crack path from the displacement jump across the expected crack
// (see include/bridgefit/dic/crack_path.hpp for the method).
#include "bridgefit/dic/crack_path.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "weighted_poly_impl.hpp"

namespace bridgefit::dic {

bool CrackPathOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (has_hint && !(hint.Length() > 1)) return fail("crack line hint must be longer than 1 px");
  if (!(search_half_width_px > 0)) return fail("path search half width must be > 0");
  if (!(station_spacing_px > 0)) return fail("path station spacing must be > 0");
  if (!(gap_px >= 0) || !(side_depth_px > 0)) return fail("path gap must be >= 0, depth > 0");
  if (!(min_jump_px >= 0) || !(noise_factor >= 0)) return fail("path jump threshold must be >= 0");
  if (!(min_relative_jump >= 0 && min_relative_jump < 1))
    return fail("path relative jump must lie in [0, 1)");
  if (min_stations < 2) return fail("a path needs at least 2 stations");
  if (!(hint_tolerance_px > 0)) return fail("path-hint tolerance must be > 0");
  if (!(curved_rms_px > 0)) return fail("curved-path RMS threshold must be > 0");
  if (!(error_correlation_px >= 0)) return fail("error correlation length must be >= 0");
  return true;
}

std::string CrackPathResult::BriefReport() const {
  if (!found) return "crack path not found: " + why_not_found;
  return fmt::format(
      "crack path ({:.1f},{:.1f})->({:.1f},{:.1f}) px, angle {:.2f} deg, {} points over {:.0f} px, "
      "RMS {:.2f} px (all points {:.2f} px){}{}",
      line.x0, line.y0, line.x1, line.y1, angle_deg, inliers, cracked_length_px, rms_residual_px,
      line_rms_all_px,
      curved ? fmt::format(", curved: polyline of {} segments, RMS {:.2f} px", polyline_x.size() - 1,
                           polyline_rms_px)
             : "",
      disagrees_with_hint ? fmt::format(", {:.1f} px / {:.2f} deg off the given line",
                                        hint_max_offset_px, hint_angle_deg)
                          : "");
}

namespace {

// A scan frame: origin, unit direction t and normal (-ty, tx), as CrackLine.
struct Frame {
  double ox, oy, tx, ty;
  void ToLocal(double x, double y, double* s, double* n) const {
    *s = (x - ox) * tx + (y - oy) * ty;
    *n = -(x - ox) * ty + (y - oy) * tx;
  }
  void FromLocal(double s, double n, double* x, double* y) const {
    *x = ox + s * tx - n * ty;
    *y = oy + s * ty + n * tx;
  }
};

struct ColumnPoint {
  double n, un;
};

// Prefix sums over the points of one column sorted by n, so that a side
// window's straight-line fit u(n) = a + b n costs two binary searches.
class ColumnSums {
 public:
  explicit ColumnSums(const std::vector<ColumnPoint>& pts) : n_(pts.size()) {
    sums_.assign((pts.size() + 1) * 6, 0.0);
    for (size_t k = 0; k < pts.size(); ++k) {
      const double v[6] = {1, pts[k].n, pts[k].n * pts[k].n, pts[k].un, pts[k].n * pts[k].un,
                           pts[k].un * pts[k].un};
      for (int j = 0; j < 6; ++j) sums_[(k + 1) * 6 + j] = sums_[k * 6 + j] + v[j];
      ns_.push_back(pts[k].n);
    }
  }
  // Fit on points with lo <= n <= hi; value at n0, SSR and count.
  bool Fit(double lo, double hi, double n0, double* value, double* ssr, int* count,
           double* slope_out = nullptr) const {
    const size_t a = std::lower_bound(ns_.begin(), ns_.end(), lo) - ns_.begin();
    const size_t b = std::upper_bound(ns_.begin(), ns_.end(), hi) - ns_.begin();
    if (b <= a + 1) return false;
    double s[6];
    for (int j = 0; j < 6; ++j) s[j] = sums_[b * 6 + j] - sums_[a * 6 + j];
    const double m = s[0], mn = s[1] / m, mu = s[3] / m;
    const double snn = s[2] - m * mn * mn, snu = s[4] - m * mn * mu, suu = s[5] - m * mu * mu;
    double slope = 0;
    if (snn > 1e-9 * std::max(1.0, m)) slope = snu / snn;  // one row only: constant
    *value = mu + slope * (n0 - mn);
    if (slope_out) *slope_out = slope;
    *ssr = std::max(0.0, suu - slope * snu);
    *count = static_cast<int>(m);
    return true;
  }

 private:
  size_t n_;
  std::vector<double> sums_, ns_;
};

struct StationHit {
  double s = 0, n = 0, jump = 0;
};

// Points inside the gap belong to subsets that straddle the crack; each
// reads the two sides mixed by the share of its area on either side, so its
// fraction f = (u - below) / (above - below) ramps from 0 to 1 over one
// subset width w = 2 gap - 1 centred on the crack. The crack position is the
// least-squares fit of that ramp (0.1 px scan within half a gap of the
// coarse centre n0); without such points (failed subsets, exported fields
// with nodes on each side) the crack is midway between the points either side.
double RefineOnSmearedPoints(const std::vector<ColumnPoint>& pts, const ColumnSums& sums, double n0,
                             const CrackPathOptions& o) {
  const double g = o.gap_px, d = o.side_depth_px;
  double va, vb, ra, rb, sa, sb;
  int ca, cb;
  if (!sums.Fit(n0 + g, n0 + g + d, n0, &va, &ra, &ca, &sa) ||
      !sums.Fit(n0 - g - d, n0 - g, n0, &vb, &rb, &cb, &sb))
    return n0;
  std::vector<std::pair<double, double>> nf;  // (n, f)
  for (const ColumnPoint& p : pts) {
    if (std::abs(p.n - n0) > g + d) continue;
    const double above = va + sa * (p.n - n0), below = vb + sb * (p.n - n0);
    if (!(above - below > 0)) continue;
    nf.push_back({p.n, (p.un - below) / (above - below)});
  }
  int mixed = 0;
  double below_max = -1e300, above_min = 1e300;
  for (const auto& [n, f] : nf) {
    mixed += (f > 0.1 && f < 0.9) ? 1 : 0;
    if (f < 0.5) below_max = std::max(below_max, n);
    else above_min = std::min(above_min, n);
  }
  if (mixed < 1) {
    // A clean step (failed subsets, or nodes on either side): the crack lies
    // midway between the last point below and the first point above.
    if (below_max < above_min && above_min - below_max < 2 * (g + d)) return 0.5 * (below_max + above_min);
    return n0;
  }
  const double w = std::max(1.0, 2.0 * g - 1.0);
  // Where the crack can be: between the last point below whose subset is
  // whole on the lower face (f = 0 within the noise) and the first point
  // above whose subset is whole on the upper one, each half a subset away.
  // A subset across an open gap does not mix the faces by area (the gap's
  // pixels pull it; measured f = -0.06 and 1.06 just inside the subset's
  // reach), so the ramp's centre can fall outside: then the interval's middle.
  const double noise = std::sqrt((ra + rb) / std::max(1, ca + cb - 4)) / (va - vb);
  const double tol = std::max(0.03, 3.0 * std::abs(noise));
  double whole_below = -1e300, whole_above = 1e300;
  std::sort(nf.begin(), nf.end());  // by n (the ramp fit below does not mind the order)
  for (const auto& [n, f] : nf) {
    if (std::abs(f) > tol) break;
    whole_below = n;
  }
  for (auto it = nf.rbegin(); it != nf.rend(); ++it) {
    if (std::abs(1.0 - it->second) > tol) break;
    whole_above = it->first;
  }
  const double lo_bound = whole_below + 0.5 * w, hi_bound = whole_above - 0.5 * w;
  double best_n = n0, best_cost = std::numeric_limits<double>::infinity();
  for (double nc = n0 - 0.5 * g; nc <= n0 + 0.5 * g + 1e-9; nc += 0.1) {
    double cost = 0;
    for (const auto& [n, f] : nf) {
      const double ramp = std::clamp(0.5 + (n - nc) / w, 0.0, 1.0);
      cost += (f - ramp) * (f - ramp);
    }
    if (cost < best_cost) {
      best_cost = cost;
      best_n = nc;
    }
  }
  if (lo_bound <= hi_bound && hi_bound - lo_bound < 2 * g && (best_n < lo_bound || best_n > hi_bound))
    return 0.5 * (lo_bound + hi_bound);
  return best_n;
}

// The step in u_n across one column: the centre of the run where the jump
// J(n_c) >= max J / 2 (J > 0 = opening). False when no significant step.
bool ScanColumn(std::vector<ColumnPoint>& pts, double n_lo, double n_hi,
                const CrackPathOptions& o, StationHit* hit) {
  if (pts.size() < 6) return false;
  std::sort(pts.begin(), pts.end(), [](const ColumnPoint& a, const ColumnPoint& b) { return a.n < b.n; });
  const ColumnSums sums(pts);
  const double g = o.gap_px, d = o.side_depth_px;
  const double h = 0.5;  // trial spacing, px
  std::vector<double> trial_n, jump, sigma;
  for (double nc = n_lo; nc <= n_hi + 1e-9; nc += h) {
    double va, vb, ra, rb;
    int ca, cb;
    if (!sums.Fit(nc + g, nc + g + d, nc, &va, &ra, &ca) ||
        !sums.Fit(nc - g - d, nc - g, nc, &vb, &rb, &cb)) {
      trial_n.push_back(nc);
      jump.push_back(std::numeric_limits<double>::quiet_NaN());
      sigma.push_back(0);
      continue;
    }
    const double dof = std::max(1, ca + cb - 4);
    const double s2 = (ra + rb) / dof;
    trial_n.push_back(nc);
    jump.push_back(va - vb);
    // Extrapolating a line over about its own length doubles its noise.
    sigma.push_back(std::sqrt(s2 * (4.0 / ca + 4.0 / cb)));
  }
  size_t best = trial_n.size();
  for (size_t k = 0; k < trial_n.size(); ++k)
    if (std::isfinite(jump[k]) && (best == trial_n.size() || jump[k] > jump[best])) best = k;
  if (best == trial_n.size()) return false;
  const double jmax = jump[best];
  if (!(jmax > std::max(o.min_jump_px, o.noise_factor * sigma[best]))) return false;
  // Half-maximum run around the best trial, edges interpolated (a trial
  // without enough points on a side ends the run where it is).
  const double half = 0.5 * jmax;
  size_t lo = best, hi = best;
  while (lo > 0 && std::isfinite(jump[lo - 1]) && jump[lo - 1] >= half) --lo;
  while (hi + 1 < trial_n.size() && std::isfinite(jump[hi + 1]) && jump[hi + 1] >= half) ++hi;
  // The run must end inside the scan: a step at the scan edge may belong to
  // something outside it.
  if (lo == 0 || hi + 1 == trial_n.size()) return false;
  auto cross = [&](size_t in, size_t out) {
    if (!std::isfinite(jump[out])) return 0.5 * (trial_n[in] + trial_n[out]);
    const double f = (jump[in] - half) / (jump[in] - jump[out]);
    return trial_n[in] + f * (trial_n[out] - trial_n[in]);
  };
  const double n0 = 0.5 * (cross(lo, lo - 1) + cross(hi, hi + 1));
  hit->n = RefineOnSmearedPoints(pts, sums, n0, o);
  hit->jump = jmax;
  return true;
}

struct LineFit {
  double a = 0, b = 0;  // n = a + b s
  std::vector<char> inlier;
  double rms = 0;
  int count = 0;
  bool slope_from_hint = false;  // b = 0: the data do not resolve the angle
};

// Weighted (J^2) straight line through the station hits, outliers trimmed.
LineFit FitPath(const std::vector<StationHit>& hits) {
  LineFit fit;
  fit.inlier.assign(hits.size(), 1);
  for (int round = 0; round < 4; ++round) {
    double sw = 0, ss = 0, sn = 0, sss = 0, ssn = 0;
    for (size_t k = 0; k < hits.size(); ++k) {
      if (!fit.inlier[k]) continue;
      const double w = hits[k].jump * hits[k].jump;
      sw += w;
      ss += w * hits[k].s;
      sn += w * hits[k].n;
      sss += w * hits[k].s * hits[k].s;
      ssn += w * hits[k].s * hits[k].n;
    }
    if (!(sw > 0)) return fit;
    const double ms = ss / sw, mn = sn / sw, var = sss / sw - ms * ms;
    fit.b = var > 1e-12 ? (ssn / sw - ms * mn) / var : 0.0;
    fit.a = mn - fit.b * ms;
    if (round == 3) break;
    std::vector<double> res;
    for (size_t k = 0; k < hits.size(); ++k)
      if (fit.inlier[k]) res.push_back(std::abs(hits[k].n - fit.a - fit.b * hits[k].s));
    std::nth_element(res.begin(), res.begin() + res.size() / 2, res.end());
    const double robust = 1.4826 * res[res.size() / 2];
    const double limit = std::max(3.0 * robust, 1.0);
    bool changed = false;
    for (size_t k = 0; k < hits.size(); ++k) {
      const bool keep = std::abs(hits[k].n - fit.a - fit.b * hits[k].s) <= limit;
      if (keep != static_cast<bool>(fit.inlier[k])) changed = true;
      fit.inlier[k] = keep ? 1 : 0;
    }
    if (!changed) break;
  }
  double ssr = 0;
  fit.count = 0;
  for (size_t k = 0; k < hits.size(); ++k)
    if (fit.inlier[k]) {
      const double r = hits[k].n - fit.a - fit.b * hits[k].s;
      ssr += r * r;
      ++fit.count;
    }
  fit.rms = fit.count ? std::sqrt(ssr / fit.count) : 0;
  return fit;
}

// Variance factor for station errors correlated over error_correlation_px.
double CorrelationInflation(const CrackPathOptions& o) {
  return std::max(1.0, o.error_correlation_px / o.station_spacing_px);
}

// The weighted (J^2) fit of the inliers' n against s, with its sandwich
// standard errors: degree 1, or 0 where the slope is the hint's.
detail::WeightedPoly InlierFit(const std::vector<StationHit>& hits, const LineFit& fit, int degree,
                               const CrackPathOptions& o) {
  std::vector<double> s, n, w;
  for (size_t k = 0; k < hits.size(); ++k) {
    s.push_back(hits[k].s);
    n.push_back(hits[k].n);
    w.push_back(fit.inlier[k] ? hits[k].jump * hits[k].jump : 0.0);
  }
  return detail::FitWeightedPoly(s, n, w, degree, CorrelationInflation(o));
}

// With a hint, the path's angle is taken from the data only where the data
// resolve it: a slope within two standard errors of the hint's, or a run too
// short to fit one (no more than two independent points: errors correlate
// over error_correlation_px), keeps the hint's direction, through the
// weighted mean offset of the inliers.
void KeepHintDirectionUnlessResolved(const std::vector<StationHit>& hits, const CrackPathOptions& o,
                                     LineFit* fit) {
  const detail::WeightedPoly line = InlierFit(hits, *fit, 1, o);
  if (line.ok && std::abs(fit->b) >= 2 * line.CoefSe(1)) return;
  double sw = 0, sn = 0;
  int n = 0;
  for (size_t k = 0; k < hits.size(); ++k)
    if (fit->inlier[k]) {
      const double w = hits[k].jump * hits[k].jump;
      sw += w;
      sn += w * hits[k].n;
      ++n;
    }
  if (!(sw > 0)) return;
  fit->b = 0;
  fit->a = sn / sw;
  fit->slope_from_hint = true;
  double ssr = 0;
  for (size_t k = 0; k < hits.size(); ++k)
    if (fit->inlier[k]) ssr += (hits[k].n - fit->a) * (hits[k].n - fit->a);
  fit->rms = std::sqrt(ssr / n);
}

struct Scan {
  Frame frame;
  std::vector<StationHit> hits;
  LineFit fit;
  double score = 0;  // sum of the inliers' jumps
};

Scan ScanFrame(const DisplacementField& f, const Frame& frame, bool limit_to_hint,
               const CrackPathOptions& o) {
  Scan scan;
  scan.frame = frame;
  const double ds = o.station_spacing_px;
  double smin = 1e300, smax = -1e300, nmin = 1e300, nmax = -1e300;
  struct P { double s, n, un; };
  std::vector<P> pts;
  // With a hint, stations only over its extent (+- half a station), so the
  // scan reads the same points whatever else the field holds (a notch or a
  // grip behind the hint's start; the crack band's edges).
  const double s_lo = limit_to_hint ? -0.5 * ds : -1e300;
  const double s_hi = limit_to_hint ? o.hint.Length() + 0.5 * ds : 1e300;
  for (size_t i = 0; i < f.size(); ++i) {
    if (!f.ok(i)) continue;
    P p;
    frame.ToLocal(f.x[i], f.y[i], &p.s, &p.n);
    if (p.s < s_lo || p.s > s_hi) continue;
    p.un = -f.u[i] * frame.ty + f.v[i] * frame.tx;
    pts.push_back(p);
    smin = std::min(smin, p.s);
    smax = std::max(smax, p.s);
    nmin = std::min(nmin, p.n);
    nmax = std::max(nmax, p.n);
  }
  if (pts.empty()) return scan;
  const double reach = o.gap_px + o.side_depth_px;
  double n_lo = nmin + o.gap_px + 0.5 * o.side_depth_px, n_hi = nmax - o.gap_px - 0.5 * o.side_depth_px;
  if (limit_to_hint) {
    n_lo = std::max(n_lo, -o.search_half_width_px);
    n_hi = std::min(n_hi, o.search_half_width_px);
  }
  if (!(n_hi > n_lo)) return scan;
  const int stations = static_cast<int>(std::floor((smax - smin) / ds)) + 1;
  std::vector<std::vector<ColumnPoint>> columns(stations);
  for (const P& p : pts) {
    if (p.n < n_lo - reach || p.n > n_hi + reach) continue;
    const int k = static_cast<int>(std::floor((p.s - smin) / ds + 0.5));
    if (k >= 0 && k < stations) columns[k].push_back({p.n, p.un});
  }
  for (int k = 0; k < stations; ++k) {
    StationHit hit;
    if (ScanColumn(columns[k], n_lo, n_hi, o, &hit)) {
      hit.s = smin + k * ds;
      scan.hits.push_back(hit);
    }
  }
  // Near the tip the jump fades into the noise and its position with it:
  // stations below a tenth of the largest jump are left out.
  double jump_max = 0;
  for (const StationHit& h : scan.hits) jump_max = std::max(jump_max, h.jump);
  std::erase_if(scan.hits, [&](const StationHit& h) { return h.jump < o.min_relative_jump * jump_max; });
  // A crack is one connected run of stations (gaps of up to two stations):
  // the run with the largest summed jump; isolated hits elsewhere are noise.
  if (!scan.hits.empty()) {
    size_t best_begin = 0, best_end = 0, begin = 0;
    double best_sum = -1, sum = 0;
    for (size_t k = 0; k <= scan.hits.size(); ++k) {
      const bool breaks = k == scan.hits.size() || (k > begin && scan.hits[k].s - scan.hits[k - 1].s > 3.01 * ds);
      if (breaks) {
        if (sum > best_sum) {
          best_sum = sum;
          best_begin = begin;
          best_end = k;
        }
        begin = k;
        sum = 0;
      }
      if (k < scan.hits.size()) sum += scan.hits[k].jump;
    }
    scan.hits = std::vector<StationHit>(scan.hits.begin() + best_begin, scan.hits.begin() + best_end);
  }
  if (static_cast<int>(scan.hits.size()) < o.min_stations) return scan;
  scan.fit = FitPath(scan.hits);
  if (limit_to_hint) KeepHintDirectionUnlessResolved(scan.hits, o, &scan.fit);
  for (size_t k = 0; k < scan.hits.size(); ++k)
    if (scan.fit.inlier[k]) scan.score += scan.hits[k].jump;
  return scan;
}

// The field's bounding box.
struct FieldBox {
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
};
FieldBox BoxOf(const DisplacementField& field) {
  FieldBox b;
  for (size_t i = 0; i < field.size(); ++i) {
    b.xmin = std::min(b.xmin, field.x[i]);
    b.xmax = std::max(b.xmax, field.x[i]);
    b.ymin = std::min(b.ymin, field.y[i]);
    b.ymax = std::max(b.ymax, field.y[i]);
  }
  return b;
}

}  // namespace

CrackPathResult FindCrackPath(const DisplacementField& field, const CrackPathOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid crack path options: " + why);
  CrackPathResult res;
  const auto [xmin, xmax, ymin, ymax] = BoxOf(field);
  if (field.size() == 0) {
    res.why_not_found = "empty displacement field";
    return res;
  }
  Scan scan;
  if (o.has_hint) {
    const double L = o.hint.Length();
    const Frame fr{o.hint.x0, o.hint.y0, (o.hint.x1 - o.hint.x0) / L, (o.hint.y1 - o.hint.y0) / L};
    scan = ScanFrame(field, fr, true, o);
  } else {  // along x and along y; the stronger crack wins
    const Scan sx = ScanFrame(field, {xmin, 0.5 * (ymin + ymax), 1, 0}, false, o);
    const Scan sy = ScanFrame(field, {0.5 * (xmin + xmax), ymin, 0, 1}, false, o);
    scan = sx.score >= sy.score ? sx : sy;
  }
  if (scan.fit.count < o.min_stations) {
    res.why_not_found = fmt::format("a displacement jump above the noise on {} of {} stations needed",
                                    scan.fit.count, o.min_stations);
    return res;
  }
  // Crack points in image axes; the inliers' extent along the path.
  const Frame& fr = scan.frame;
  double s_first = 1e300, s_last = -1e300;
  for (size_t k = 0; k < scan.hits.size(); ++k) {
    double x, y;
    fr.FromLocal(scan.hits[k].s, scan.hits[k].n, &x, &y);
    res.point_x.push_back(x);
    res.point_y.push_back(y);
    res.point_jump_px.push_back(scan.hits[k].jump);
    res.inlier.push_back(scan.fit.inlier[k]);
    if (scan.fit.inlier[k]) {
      s_first = std::min(s_first, scan.hits[k].s);
      s_last = std::max(s_last, scan.hits[k].s);
    }
  }
  res.inliers = scan.fit.count;
  res.rms_residual_px = scan.fit.rms;
  // Direction of the fitted line in image axes; n = a + b s in the scan frame.
  const double norm = std::hypot(1.0, scan.fit.b);
  double dx = (fr.tx - scan.fit.b * fr.ty) / norm, dy = (fr.ty + scan.fit.b * fr.tx) / norm;
  double px, py;  // a point on the line (s = 0)
  fr.FromLocal(0, scan.fit.a, &px, &py);
  res.cracked_length_px = (s_last - s_first) * norm;
  if (!o.has_hint) {
    // The notch is the end of the detected run with the larger opening.
    std::vector<std::pair<double, double>> sj;
    for (size_t k = 0; k < scan.hits.size(); ++k)
      if (scan.fit.inlier[k]) sj.push_back({scan.hits[k].s, scan.hits[k].jump});
    std::sort(sj.begin(), sj.end());
    const size_t m = std::max<size_t>(1, sj.size() / 3);
    double head = 0, tail = 0;
    for (size_t k = 0; k < m; ++k) {
      head += sj[k].second;
      tail += sj[sj.size() - 1 - k].second;
    }
    if (tail > head) {
      dx = -dx;
      dy = -dy;
    }
  }
  // Start and end: the hint's ends projected on the path, or the field's
  // extent along it.
  double t0, t1;
  if (o.has_hint) {
    // Where the path crosses the normals to the hint at its two ends, so a
    // hint moved across the crack keeps the same origin.
    const double L = o.hint.Length();
    const double hx = (o.hint.x1 - o.hint.x0) / L, hy = (o.hint.y1 - o.hint.y0) / L;
    const double dh = dx * hx + dy * hy;
    if (dh < 0.5) {
      res.why_not_found = "the fitted path runs more than 60 degrees off the given line";
      return res;
    }
    t0 = ((o.hint.x0 - px) * hx + (o.hint.y0 - py) * hy) / dh;
    t1 = ((o.hint.x1 - px) * hx + (o.hint.y1 - py) * hy) / dh;
  } else {
    // Where the line crosses the field's bounding box (slab intersection).
    t0 = -1e300;
    t1 = 1e300;
    auto slab = [&](double p0, double d, double lo, double hi) {
      if (std::abs(d) < 1e-12) return;
      const double ta = (lo - p0) / d, tb = (hi - p0) / d;
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
    };
    const bool bounds = o.bounds_x1 > o.bounds_x0 && o.bounds_y1 > o.bounds_y0;
    slab(px, dx, bounds ? o.bounds_x0 : xmin, bounds ? o.bounds_x1 : xmax);
    slab(py, dy, bounds ? o.bounds_y0 : ymin, bounds ? o.bounds_y1 : ymax);
  }
  res.line = {px + t0 * dx, py + t0 * dy, px + t1 * dx, py + t1 * dy};
  if (!(res.line.Length() > 1)) {
    res.why_not_found = "the fitted path has no length inside the field";
    return res;
  }
  res.angle_deg = std::atan2(dy, dx) * 180.0 / std::numbers::pi;
  // The line's standard error at the ends of the cracked length, with or
  // without a hint (without one a few points far from the crack - a strain
  // concentration at a notch root - are a path in any direction).
  {
    const int degree = scan.fit.slope_from_hint ? 0 : 1;
    const detail::WeightedPoly fit = InlierFit(scan.hits, scan.fit, degree, o);
    res.line_se_fitted = fit.ok;
    res.angle_from_hint = scan.fit.slope_from_hint;
    // At least what the points' own resolution (hint_tolerance_px / 2 each)
    // leaves at an end of the line (variance 4 / n for a slope and an
    // offset, 1 / n for an offset, with the stations' correlation): three
    // points on one grid row fit with no residual, and their standard error
    // of 0 had made a path 18 px off the crack aldic's most precise.
    const double point_sigma = 0.5 * o.hint_tolerance_px;
    const double floor_se =
        point_sigma * std::sqrt((degree == 1 ? 4.0 : 1.0) * CorrelationInflation(o) /
                                std::max(1, scan.fit.count));
    res.line_se_px = fit.ok ? std::max({fit.Se(s_first), fit.Se(s_last), floor_se}) : 0.0;
  }
  if (o.has_hint) {
    const double a = scan.fit.a, b = scan.fit.b;
    res.hint_max_offset_px = std::max(std::abs(a + b * s_first), std::abs(a + b * s_last));
    res.hint_angle_deg = std::atan(b) * 180.0 / std::numbers::pi;
    // Disagree beyond twice the line's uncertainty at an end of the cracked
    // length: its resolution (hint_tolerance_px is two of its sigmas) and its
    // standard error there, in quadrature.
    res.disagrees_with_hint =
        res.hint_max_offset_px > 2 * std::hypot(0.5 * o.hint_tolerance_px, res.line_se_px);
  }
  // Fit quality of the line over every crack point; a polyline where it is
  // poor (a kinked or curved crack), its points ordered along the path.
  {
    std::vector<std::pair<double, size_t>> order;
    std::vector<double> ps, pn, pw;
    double ss = 0;
    for (size_t k = 0; k < res.point_x.size(); ++k) {
      double s, n;
      res.line.ToLocal(res.point_x[k], res.point_y[k], &s, &n);
      order.push_back({s, k});
      ss += n * n;
      ps.push_back(s);
      pn.push_back(n);
      pw.push_back(res.point_jump_px[k] * res.point_jump_px[k]);
    }
    res.line_rms_all_px = std::sqrt(ss / std::max<size_t>(1, order.size()));
    // Curved: off the line by more than the resolution, and the bend is
    // resolved (a parabola's curvature beyond twice its standard error).
    const detail::WeightedPoly bend = detail::FitWeightedPoly(ps, pn, pw, 2, CorrelationInflation(o));
    if (bend.ok) {
      res.curvature_per_px = bend.c[2];
      res.curvature_se_per_px = bend.CoefSe(2);
    }
    res.curved = res.line_rms_all_px > o.curved_rms_px && bend.ok &&
                 std::abs(res.curvature_per_px) > 2 * res.curvature_se_per_px;
    if (res.curved) {
      std::sort(order.begin(), order.end());
      std::vector<double> xs, ys;
      for (const auto& [s, k] : order) {
        xs.push_back(res.point_x[k]);
        ys.push_back(res.point_y[k]);
      }
      FitCrackPolyline(xs, ys, o.curved_rms_px, o.min_stations, &res.polyline_x, &res.polyline_y,
                       &res.polyline_rms_px);
    }
  }
  res.found = true;
  return res;
}

}  // namespace bridgefit::dic
