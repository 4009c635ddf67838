// Crack tip location from a displacement field: COD profile, jump
// threshold, sqrt COD fit and Williams-series field fit.
#include "bridgefit/dic/crack.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "crack_impl.hpp"

namespace bridgefit::dic {

const char* TipMethodName(TipMethod method) {
  switch (method) {
    case TipMethod::kWilliams: return "williams";
    case TipMethod::kJump: return "jump";
    case TipMethod::kSqrtCod: return "sqrt";
  }
  return "unknown";
}

TipMethod ParseTipMethod(const std::string& text) {
  if (text == "williams") return TipMethod::kWilliams;
  if (text == "jump") return TipMethod::kJump;
  if (text == "sqrt") return TipMethod::kSqrtCod;
  throw Error(ErrorKind::kUsage, "unknown tip method",
              {.field = "--tip-method", .value = text, .expected = "williams, jump or sqrt"});
}

double CrackTipOptions::MaxClosedLeadPx() const {
  if (max_closed_lead_px > 0) return max_closed_lead_px;
  return std::max(3 * station_spacing_px, noise_correlation_px + 2 * station_spacing_px);
}

bool CrackTipOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (!(line.Length() > 1)) return fail("crack line must be longer than 1 px");
  if (!(station_spacing_px > 0)) return fail("station spacing must be > 0");
  if (!(band_half_width_px >= 0) || !(side_depth_px > 0)) return fail("band sizes must be > 0");
  if (!(threshold_floor_px >= 0) || !(noise_factor >= 0)) return fail("threshold must be >= 0");
  if (!(noise_correlation_px >= 0)) return fail("noise correlation length must be >= 0");
  if (mode1_terms < 1 || mode1_terms > 8 || mode2_terms < 0 || mode2_terms > 4)
    return fail("Williams terms: mode I 1..8, mode II 0..4");
  if (!(kappa > 1 && kappa <= 3)) return fail("kappa must lie in (1, 3]");
  if (Orthotropic() && !(s11 > 0 && s22 > 0 && s66 > 0 && s12 * s12 < s11 * s22))
    return fail("orthotropic compliances: s11, s22, s66 > 0 and s12^2 < s11 s22");
  if (!(fit_radius_px > 0) || !(sqrt_window_px > 0)) return fail("fit windows must be > 0");
  if (!(max_closed_lead_px >= 0)) return fail("closed lead must be >= 0");
  if (min_failed_cluster < 1 || !(min_fit_radius_fraction >= 0 && min_fit_radius_fraction <= 1))
    return fail("failed cluster size must be >= 1, minimum radius fraction in [0, 1]");
  return true;
}

namespace {

using detail::LocalPoint;
using detail::SetPosition;


std::vector<LocalPoint> ValidPoints(const DisplacementField& f, const CrackLine& line) {
  std::vector<LocalPoint> pts;
  const double L = line.Length();
  const double tx = (line.x1 - line.x0) / L, ty = (line.y1 - line.y0) / L;
  for (size_t i = 0; i < f.size(); ++i) {
    if (!f.ok(i)) continue;
    LocalPoint p;
    line.ToLocal(f.x[i], f.y[i], &p.s, &p.n);
    p.us = f.u[i] * tx + f.v[i] * ty;
    p.un = -f.u[i] * ty + f.v[i] * tx;
    p.x = f.x[i];
    p.y = f.y[i];
    p.u = f.u[i];
    p.v = f.v[i];
    p.index = i;
    pts.push_back(p);
  }
  return pts;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  const size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + m, v.end());
  return v[m];
}

// Plane fit value at (s0, n = 0) of component (us or un) for one side.
bool SideExtrapolation(const std::vector<const LocalPoint*>& side, double s0, double* ns,
                       double* nn) {
  if (side.size() < 4) return false;
  Eigen::MatrixXd A(side.size(), 3);
  Eigen::MatrixXd b(side.size(), 2);
  double nmin = 1e300, nmax = -1e300;
  for (size_t k = 0; k < side.size(); ++k) {
    A(k, 0) = 1;
    A(k, 1) = side[k]->s - s0;
    A(k, 2) = side[k]->n;
    b(k, 0) = side[k]->us;
    b(k, 1) = side[k]->un;
    nmin = std::min(nmin, side[k]->n);
    nmax = std::max(nmax, side[k]->n);
  }
  if (nmax - nmin < 1e-6) {  // one row only: no extrapolation in n
    A.col(2).setZero();
    Eigen::MatrixXd A2 = A.leftCols(2);
    const Eigen::MatrixXd c = A2.colPivHouseholderQr().solve(b);
    *ns = c(0, 0);
    *nn = c(0, 1);
    return true;
  }
  const Eigen::MatrixXd c = A.colPivHouseholderQr().solve(b);
  *ns = c(0, 0);
  *nn = c(0, 1);
  return std::isfinite(*ns) && std::isfinite(*nn);
}

CodProfile BuildCodProfile(const std::vector<LocalPoint>& pts, const CrackTipOptions& o) {
  CodProfile cod;
  const double L = o.line.Length();
  const double ds = o.station_spacing_px;
  const double n_in = o.band_half_width_px, n_out = o.band_half_width_px + o.side_depth_px;
  for (double s0 = 0; s0 <= L + 1e-9; s0 += ds) {
    std::vector<const LocalPoint*> above, below;
    for (const LocalPoint& p : pts) {
      if (std::abs(p.s - s0) > ds * 1.01) continue;
      const double an = std::abs(p.n);
      if (an < n_in || an > n_out) continue;
      (p.n > 0 ? above : below).push_back(&p);
    }
    double as = 0, an = 0, bs = 0, bn = 0;
    const bool ok = SideExtrapolation(above, s0, &as, &an) && SideExtrapolation(below, s0, &bs, &bn);
    cod.s_px.push_back(s0);
    cod.opening_px.push_back(ok ? an - bn : 0.0);
    cod.sliding_px.push_back(ok ? as - bs : 0.0);
    cod.valid.push_back(ok ? 1 : 0);
  }
  return cod;
}

// Robust noise of the opening: 1.4826 MAD / sqrt 2 of the differences of
// valid stations `lag` apart, neither of them in [skip_lo, skip_hi].
double OpeningNoise(const CodProfile& cod, size_t lag, long skip_lo, long skip_hi, size_t* pairs) {
  std::vector<double> diffs;
  auto skipped = [&](size_t k) { return static_cast<long>(k) >= skip_lo && static_cast<long>(k) <= skip_hi; };
  for (size_t k = lag; k < cod.s_px.size(); ++k)
    if (cod.valid[k] && cod.valid[k - lag] && !skipped(k) && !skipped(k - lag))
      diffs.push_back(cod.opening_px[k] - cod.opening_px[k - lag]);
  *pairs = diffs.size();
  if (diffs.empty()) return 0;
  std::vector<double> absd;
  const double med = Median(diffs);
  for (double d : diffs) absd.push_back(std::abs(d - med));
  return 1.4826 * Median(absd) / std::sqrt(2.0);
}

// The noise of neighbouring stations over the whole profile and the
// threshold an opened station must pass.
void OpeningNoiseAndThreshold(const CodProfile& cod, const CrackTipOptions& o, CrackTipResult& res) {
  size_t pairs = 0;
  res.noise_px = OpeningNoise(cod, 1, 0, -1, &pairs);
  res.threshold_px = std::max(o.threshold_floor_px, o.noise_factor * res.noise_px);
}

// Stations closer than the field's error correlation length share most of
// their error (overlapping subsets): their differences read a fraction of
// it (aldic, subset 31 px at 6 px stations: 0.005 px against 0.019 px), and
// a noise-made run passes a threshold set from them. The noise is read again
// from differences of stations whose errors no longer share points - a
// correlation length plus the two station spacings a station's own window
// spans (BuildCodProfile) - over the stations off the opened run and one
// correlation length around it (on it they would read the opening's
// slope); where too few are left for 8 such pairs, at the longest lag down
// to one correlation length that gives them. It only ever raises the
// threshold. True when it did.
bool CorrelatedNoiseOffTheRun(const CodProfile& cod, const CrackTipOptions& o, int first, int last,
                              CrackTipResult& res) {
  const double ds = o.station_spacing_px;
  if (!(o.noise_correlation_px > ds) || last < 0) return false;
  const size_t shortest = static_cast<size_t>(std::ceil(o.noise_correlation_px / ds - 1e-9));
  const size_t longest = static_cast<size_t>(std::ceil((o.noise_correlation_px + 2 * ds) / ds - 1e-9));
  const long skip_lo = first - static_cast<long>(shortest), skip_hi = last + static_cast<long>(shortest);
  for (size_t lag = longest; lag >= shortest; --lag) {
    size_t pairs = 0;
    const double noise = OpeningNoise(cod, lag, skip_lo, skip_hi, &pairs);
    if (pairs < 8) continue;
    if (!(noise > res.noise_px)) return false;
    res.noise_px = noise;
    res.threshold_px = std::max(o.threshold_floor_px, o.noise_factor * noise);
    return true;
  }
  return false;
}

// The first opened run from the notch side, allowing one-station gaps:
// its last station (-1 when none; its first in *first_out). Sets last_station_px and
// opening_detected (an opening spans at least two stations).
int FirstOpenedRun(const CodProfile& cod, CrackTipResult& res, int* first_out = nullptr) {
  const size_t ns = cod.s_px.size();
  const double thr = res.threshold_px;
  int first = -1, last = -1, gap = 0;
  for (size_t k = 0; k < ns; ++k) {
    if (!cod.valid[k]) {
      if (first >= 0 && ++gap > 2) break;
      continue;
    }
    if (cod.opening_px[k] >= thr) {
      if (first < 0) first = static_cast<int>(k);
      last = static_cast<int>(k);
      gap = 0;
    } else if (first >= 0) {
      if (++gap > 1) break;
    }
  }
  for (size_t k = 0; k < ns; ++k)
    if (cod.valid[k]) res.last_station_px = cod.s_px[k];
  // An opening must span at least two stations to count as a crack.
  int above = 0;
  for (int k = std::max(first, 0); first >= 0 && k <= last; ++k)
    if (cod.valid[k] && cod.opening_px[k] >= thr) ++above;
  res.opening_detected = above >= 2;
  if (first_out) *first_out = first;
  return last;
}

// The valid closed stations before the first opened run (its first station
// `first`), as a length along the line; detached beyond the allowed lead.
void ClosedLead(const CodProfile& cod, int first, const CrackTipOptions& o, CrackTipResult& res) {
  int closed = 0;
  for (int k = 0; k < first; ++k)
    if (cod.valid[k] && cod.opening_px[k] < res.threshold_px) ++closed;
  res.closed_lead_px = closed * o.station_spacing_px;
  res.opening_detached = res.closed_lead_px > o.MaxClosedLeadPx();
}

// Jump tip: where the opening falls through the threshold after the run's
// last station (linear between stations), +- the station spacing and noise.
void JumpTip(const CodProfile& cod, int last, const CrackTipOptions& o, CrackTipResult& res) {
  const size_t ns = cod.s_px.size();
  const double ds = o.station_spacing_px;
  const double thr = res.threshold_px;
  TipEstimate& t = res.jump;
  t.s_px = cod.s_px[last];
  size_t next = last + 1;
  while (next < ns && !cod.valid[next]) ++next;
  if (next < ns) {
    const double o1 = cod.opening_px[last], o2 = cod.opening_px[next];
    const double frac = o1 > o2 ? std::clamp((o1 - thr) / (o1 - o2), 0.0, 1.0) : 0.0;
    t.s_px = cod.s_px[last] + frac * (cod.s_px[next] - cod.s_px[last]);
    const double slope = std::abs(o1 - o2) / (cod.s_px[next] - cod.s_px[last]);
    t.uncertainty_px = std::hypot(ds / std::sqrt(12.0), slope > 0 ? res.noise_px / slope : ds);
  } else {
    t.uncertainty_px = ds;
    res.tip_at_edge = true;  // still open at the last station with data
  }
  t.found = true;
  SetPosition(o.line, &t);
}

// sqrt COD: COD^2 = A^2 (s_tip - s) on stations behind the jump tip.
void SqrtCodTip(const CodProfile& cod, int last, const CrackTipOptions& o, CrackTipResult& res) {
  const size_t ns = cod.s_px.size();
  const double thr = res.threshold_px;
  std::vector<double> s, o2;
  for (size_t k = 0; k < ns; ++k)
    if (cod.valid[k] && static_cast<int>(k) <= last && cod.opening_px[k] >= thr &&
        cod.s_px[k] >= res.jump.s_px - o.sqrt_window_px) {
      s.push_back(cod.s_px[k]);
      o2.push_back(cod.opening_px[k] * cod.opening_px[k]);
    }
  if (s.size() >= 3) {
    const double n = static_cast<double>(s.size());
    double sm = 0, om = 0;
    for (size_t k = 0; k < s.size(); ++k) {
      sm += s[k];
      om += o2[k];
    }
    sm /= n;
    om /= n;
    double sxx = 0, sxy = 0;
    for (size_t k = 0; k < s.size(); ++k) {
      sxx += (s[k] - sm) * (s[k] - sm);
      sxy += (s[k] - sm) * (o2[k] - om);
    }
    const double beta = sxy / sxx, alpha = om - beta * sm;
    if (beta < 0) {
      TipEstimate& t = res.sqrt_cod;
      t.s_px = -alpha / beta;
      double sse = 0;
      for (size_t k = 0; k < s.size(); ++k) {
        const double e = o2[k] - alpha - beta * s[k];
        sse += e * e;
      }
      const double sigma2 = s.size() > 2 ? sse / (n - 2) : 0;
      // Delta method on s_tip = -alpha / beta (intercept of the fitted line).
      const double var_beta = sigma2 / sxx;
      const double ds_dbeta = (sm - t.s_px) / beta;  // d s_tip / d beta with alpha = om - beta sm
      t.uncertainty_px = std::sqrt(sigma2 / n / (beta * beta) + ds_dbeta * ds_dbeta * var_beta);
      t.found = std::isfinite(t.s_px) && t.s_px > 0 && t.s_px < o.line.Length() * 1.5;
      const double reach = o.band_half_width_px;  // a subset's half width: it smooths that far
      res.sqrt_near_tip_share =
          static_cast<double>(std::count_if(s.begin(), s.end(), [&](double sk) { return t.s_px - sk < reach; })) / n;
      SetPosition(o.line, &t);
    }
  }
}

// Preferred method, then the fallbacks: Williams -> sqrt -> jump.
void ChooseTip(TipMethod preferred, const CrackTipOptions& o, CrackTipResult& res) {
  const TipEstimate* chosen = nullptr;
  const bool williams_usable = !res.williams_unstable;
  auto pick = [&](TipMethod m) {
    const TipEstimate& t = m == TipMethod::kWilliams ? res.williams
                           : m == TipMethod::kJump   ? res.jump
                                                     : res.sqrt_cod;
    if (!chosen && t.found && (m != TipMethod::kWilliams || williams_usable)) {
      chosen = &t;
      res.method = m;
    }
  };
  pick(preferred);
  pick(TipMethod::kWilliams);
  pick(TipMethod::kSqrtCod);
  pick(TipMethod::kJump);
  if (chosen) res.tip = *chosen;
  res.methods_disagree = MethodsDisagree(res, o);
}

}  // namespace

namespace {

// How far tip a lies from tip b beyond what their documented biases allow
// (a may lie up to ahead_allowed ahead of b), 0 where within it or either is
// missing.
double BeyondBias(const TipEstimate& a, const TipEstimate& b, double ahead_allowed) {
  if (!a.found || !b.found) return 0;
  const double d = a.s_px - b.s_px;  // a relative to b
  return d > ahead_allowed ? d - ahead_allowed : std::max(0.0, -d);
}

// The method pairs MethodsDisagree compares, with their allowances.
template <class PairFn>
void ForMethodPairs(const CrackTipResult& r, const CrackTipOptions& o, const PairFn& fn) {
  const TipEstimate &w = r.williams, &q = r.sqrt_cod, &j = r.jump;
  fn(q, w, BeyondBias(q, w, r.sqrt_near_tip_share * o.band_half_width_px));
  fn(j, w, BeyondBias(j, w, o.band_half_width_px));
  fn(j, q, BeyondBias(j, q, o.band_half_width_px));
}

}  // namespace

// Pairwise: |s_a - s_b| > 2 sqrt(sigma_a^2 + sigma_b^2), sigmas at least one
// station / sqrt(12). Both COD tips read the opening extrapolated from
// outside the band, which near the tip exceeds the faces' (the field at r ~
// band, not at the face), so the opening seems to run on: the jump tip (where
// it drops below a threshold) may lie up to a band half width ahead of the
// others, the sqrt tip by that share of it that its fit's stations near the
// tip carry. Never allowed: a COD tip behind.
bool MethodsDisagree(const CrackTipResult& r, const CrackTipOptions& o) {
  const double floor_sigma = o.station_spacing_px / std::sqrt(12.0);
  auto sig = [&](const TipEstimate& t) { return std::max(t.uncertainty_px, floor_sigma); };
  bool disagree = false;
  ForMethodPairs(r, o, [&](const TipEstimate& a, const TipEstimate& b, double beyond) {
    disagree = disagree || beyond > 2.0 * std::hypot(sig(a), sig(b));
  });
  return disagree;
}

double AgreementSigma(const CrackTipResult& r, const CrackTipOptions& o) {
  double sigma = 0;
  ForMethodPairs(r, o, [&](const TipEstimate&, const TipEstimate&, double beyond) {
    sigma = std::max(sigma, beyond / (2.0 * std::sqrt(2.0)));
  });
  return sigma;
}

// Stages: opening profile -> noise and threshold -> first opened run (again
// where the correlated noise off it raises the threshold) -> jump,
// sqrt-COD and Williams tips -> the preferred tip found.
CrackTipResult LocateCrackTip(const DisplacementField& field, const CrackTipOptions& o,
                              TipMethod preferred) {
  std::string why;
  if (!o.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid crack-tip options: " + why);
  CrackTipResult res;
  const std::vector<LocalPoint> pts = ValidPoints(field, o.line);
  res.cod = BuildCodProfile(pts, o);
  OpeningNoiseAndThreshold(res.cod, o, res);
  int first = -1;
  int last = FirstOpenedRun(res.cod, res, &first);
  if (CorrelatedNoiseOffTheRun(res.cod, o, first, last, res)) last = FirstOpenedRun(res.cod, res, &first);
  if (!res.opening_detected) return res;
  ClosedLead(res.cod, first, o, res);
  JumpTip(res.cod, last, o, res);
  SqrtCodTip(res.cod, last, o, res);
  detail::WilliamsTip(field, pts, o, res);
  ChooseTip(preferred, o, res);
  return res;
}

std::vector<double> MonotoneNonDecreasing(const std::vector<double>& values,
                                          const std::vector<double>& sigmas,
                                          const std::vector<char>& valid) {
  BF_CHECK_INPUT(values.size() == sigmas.size() && values.size() == valid.size(),
                 "monotone fit: values, sigmas and flags differ in length");
  struct Block { double mean, weight; size_t count; };
  std::vector<Block> blocks;
  std::vector<size_t> index;
  for (size_t i = 0; i < values.size(); ++i) {
    if (!valid[i]) continue;
    index.push_back(i);
    const double s = std::max(sigmas[i], 1e-12);
    blocks.push_back({values[i], 1.0 / (s * s), 1});
    while (blocks.size() >= 2 && blocks[blocks.size() - 2].mean > blocks.back().mean) {
      const Block b = blocks.back();
      blocks.pop_back();
      Block& a = blocks.back();
      a.mean = (a.mean * a.weight + b.mean * b.weight) / (a.weight + b.weight);
      a.weight += b.weight;
      a.count += b.count;
    }
  }
  std::vector<double> out = values;
  size_t k = 0;
  for (const Block& b : blocks)
    for (size_t j = 0; j < b.count; ++j) out[index[k++]] = b.mean;
  return out;
}

}  // namespace bridgefit::dic
