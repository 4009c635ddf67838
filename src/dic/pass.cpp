// One correlation pass over the grid (Correlator::Impl::Pass) as stages:
//   start:       static statuses, reference centres X + u_r(X)
//   guessed:     points with a guess (previous frame, lattice), in parallel
//   propagation: wavefronts from converged points, each front point from its
//                best-ZNCC converged neighbour (displacement extrapolated by
//                its gradient), NCC retry of +-local_search_radius on failure
//   seeds:       NCC search (+-seed_search_radius) at the most interior
//                unreached point when no front is left
// Large grids without guesses run a coarse lattice (every 4th point) first
// and start the other points from their nearest lattice point.
#include <algorithm>
#include <cmath>
#include <limits>

#include <omp.h>
#include <opencv2/imgproc.hpp>

#include "correlation_impl.hpp"

namespace bridgefit::dic::detail {
namespace {

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

// A neighbour's motion carried to point i: u(x_i) = u_b + grad u_b (x_i - x_b).
Params Extrapolate(const Params& pb, double dx, double dy) {
  Params p = pb;
  p[0] += p[1] * dx + p[2] * dy;
  p[6] += p[7] * dx + p[8] * dy;
  return p;
}

class PassRunner {
 public:
  PassRunner(CorrelatorState& impl, const Image& def_image,
             const InterpolatedImage& def_interp)
      : m_(impl),
        def_image_(def_image),
        def_interp_(def_interp),
        n_(impl.grid.size()),
        M_(impl.opt.subset_size / 2),
        nthreads_(impl.Threads()),
        profile_(impl.opt.profile_stages) {}

  std::vector<PointResult> Run(const std::vector<Params>& guess,
                               const std::vector<char>& has_guess, std::size_t* solves,
                               const std::vector<PointResult>* prior, const std::vector<char>* keep);

 private:
  void Start(const std::vector<PointResult>* prior, const std::vector<char>* keep);
  PointResult SolvePoint(size_t i, const Params& p, Workspace& ws) const {
    const ReferenceView ref{&m_.ref_interp, &m_.ref_nodes};
    ReferenceSubset* cache = m_.ref_cache.empty() ? nullptr : &m_.ref_cache[i];
    return SolveIcgn(ref, def_interp_, cx_[i], cy_[i], p, m_.opt, cache, ws, profile_);
  }
  bool Search(size_t i, double gu, double gv, int radius, Params* q, Workspace& ws) const;
  void SolveGuessed(const std::vector<Params>& g, const std::vector<char>& hg);
  std::vector<size_t> FrontierOf(const std::vector<size_t>& from, const std::vector<char>& act,
                                 int stride) const;
  int Neighbours(size_t i, int stride, size_t* out) const;
  void SolveFront(const std::vector<size_t>& front, int stride);
  void MarkLeaving(const std::vector<char>& act, const std::vector<Params>& guess,
                   const std::vector<char>& has_guess);
  size_t PickSeed(const std::vector<char>& act, int stride) const;
  void SolveSeed(size_t seed, const std::vector<Params>& guess, const std::vector<char>& has_guess);
  void Propagate(const std::vector<char>& act, int stride, const std::vector<Params>& guess,
                 const std::vector<char>& has_guess);
  void LatticeGuesses(int stride, std::vector<Params>* g, std::vector<char>* hg) const;
  Workspace& ThreadWorkspace() { return m_.workspaces[omp_get_thread_num()]; }

  CorrelatorState& m_;
  const Image& def_image_;
  const InterpolatedImage& def_interp_;
  const size_t n_;
  const int M_, nthreads_;
  const bool profile_;
  std::vector<PointResult> res_;
  std::vector<char> done_, active_;
  mutable std::vector<char> in_front_;  // FrontierOf's marks, all zero between calls
  std::vector<double> cx_, cy_;
  std::size_t count_ = 0;
};

// Stage start: static statuses, the reference centres, and the points whose
// result in this frame is known already (`keep`: taken from `prior`).
void PassRunner::Start(const std::vector<PointResult>* prior, const std::vector<char>* keep) {
  res_.assign(n_, PointResult{});
  done_.assign(n_, 0);
  in_front_.assign(n_, 0);
  active_.assign(n_, 0);
  cx_.resize(n_);
  cy_.resize(n_);
  for (size_t i = 0; i < n_; ++i) {
    active_[i] = m_.eligible[i] && m_.ref_known[i];
    if (m_.eligible[i] && !m_.ref_known[i]) {
      res_[i].status = m_.lost_status.empty() ? PointStatus::kUnreached : m_.lost_status[i];
      done_[i] = 1;
    }
    if (!m_.eligible[i]) {
      res_[i].status = m_.grid.status[i];
      done_[i] = 1;
    }
    cx_[i] = m_.grid.x[i] + m_.ref_p[i][0];
    cy_[i] = m_.grid.y[i] + m_.ref_p[i][6];
    if (keep && (*keep)[i] && active_[i]) {
      res_[i] = (*prior)[i];
      done_[i] = 1;
    }
  }
}

bool PassRunner::Search(size_t i, double gu, double gv, int radius, Params* q,
                        Workspace& ws) const {
  StageClock clock(profile_);
  double u, v, peak;
  const bool found = IntegerSearch(m_.ref_image, def_image_, cx_[i], cy_[i], gu, gv, M_, radius,
                                   &u, &v, &peak);
  clock.Lap(&ws.times.search);
  if (!found) return false;
  *q = Params{};
  (*q)[0] = u;
  (*q)[6] = v;
  return true;
}

// Stage guessed: points with a guess, in parallel; converged ones are done.
void PassRunner::SolveGuessed(const std::vector<Params>& g, const std::vector<char>& hg) {
  std::vector<size_t> list;
  for (size_t i = 0; i < n_; ++i)
    if (active_[i] && !done_[i] && hg[i]) list.push_back(i);
  std::size_t count = 0;
#pragma omp parallel for num_threads(nthreads_) schedule(dynamic, 16) reduction(+ : count)
  for (size_t k = 0; k < list.size(); ++k) {
    const size_t i = list[k];
    const PointResult r = SolvePoint(i, g[i], ThreadWorkspace());
    ++count;
    if (r.status == PointStatus::kOk) {
      res_[i] = r;
      done_[i] = 1;
    }
  }
  count_ += count;
}

int PassRunner::Neighbours(size_t i, int stride, size_t* out) const {
  const int nx = m_.grid.nx, ny = m_.grid.ny;
  int m = 0;
  const int ix = static_cast<int>(i % nx), iy = static_cast<int>(i / nx);
  if (ix >= stride) out[m++] = i - stride;
  if (ix + stride < nx) out[m++] = i + stride;
  if (iy >= stride) out[m++] = i - static_cast<size_t>(stride) * nx;
  if (iy + stride < ny) out[m++] = i + static_cast<size_t>(stride) * nx;
  return m;
}

std::vector<size_t> PassRunner::FrontierOf(const std::vector<size_t>& from,
                                           const std::vector<char>& act, int stride) const {
  std::vector<size_t> front;
  // in_front_ is all zero between calls (cleared below): no O(n) per front.
  for (size_t i : from) {
    if (res_[i].status != PointStatus::kOk) continue;
    size_t nb[4];
    const int m = Neighbours(i, stride, nb);
    for (int k = 0; k < m; ++k)
      if (act[nb[k]] && !done_[nb[k]] && !in_front_[nb[k]]) {
        in_front_[nb[k]] = 1;
        front.push_back(nb[k]);
      }
  }
  for (size_t i : front) in_front_[i] = 0;
  return front;
}

// Stage propagation, one front: each point from its best converged
// neighbour; on failure an NCC search around that guess and a second solve.
void PassRunner::SolveFront(const std::vector<size_t>& front, int stride) {
  std::vector<PointResult> out(front.size());
  std::size_t count = 0;
  // Small fronts run serially: a parallel region costs more than they do.
#pragma omp parallel for num_threads(nthreads_) schedule(dynamic, 8) reduction(+ : count) \
    if (front.size() >= 48)
  for (size_t k = 0; k < front.size(); ++k) {
    Workspace& ws = ThreadWorkspace();
    const size_t i = front[k];
    size_t nb[4];
    const int m = Neighbours(i, stride, nb);
    int best = -1;
    for (int j = 0; j < m; ++j)
      if (done_[nb[j]] && res_[nb[j]].status == PointStatus::kOk &&
          (best < 0 || res_[nb[j]].zncc > res_[nb[best]].zncc))
        best = j;
    Params p{};
    if (best >= 0) p = Extrapolate(res_[nb[best]].p, cx_[i] - cx_[nb[best]], cy_[i] - cy_[nb[best]]);
    PointResult r = SolvePoint(i, p, ws);
    ++count;
    Params q;
    if (r.status != PointStatus::kOk && r.status != PointStatus::kOutOfImage &&
        Search(i, p[0], p[6], m_.opt.local_search_radius, &q, ws)) {
      const PointResult r2 = SolvePoint(i, q, ws);
      ++count;
      if (r2.status == PointStatus::kOk || r2.zncc > r.zncc) r = r2;
    }
    out[k] = r;
  }
  count_ += count;
  for (size_t k = 0; k < front.size(); ++k) {
    res_[front[k]] = out[k];
    done_[front[k]] = 1;
  }
}

// Unprocessed points whose subset, moved like the converged points on
// average, would leave the image: out of image, no seed attempt.
void PassRunner::MarkLeaving(const std::vector<char>& act, const std::vector<Params>& guess,
                             const std::vector<char>& has_guess) {
  double mu = 0, mv = 0;
  size_t m = 0;
  for (size_t i = 0; i < n_; ++i)
    if (done_[i] && m_.eligible[i] && res_[i].status == PointStatus::kOk) {
      mu += res_[i].p[0];
      mv += res_[i].p[6];
      ++m;
    }
  if (m == 0) return;
  mu /= m;
  mv /= m;
  for (size_t i = 0; i < n_; ++i) {
    if (!act[i] || done_[i]) continue;
    const double gu = has_guess[i] ? guess[i][0] : mu, gv = has_guess[i] ? guess[i][6] : mv;
    if (!def_interp_.Inside(cx_[i] + gu - M_, cy_[i] + gv - M_) ||
        !def_interp_.Inside(cx_[i] + gu + M_, cy_[i] + gv + M_)) {
      res_[i].status = PointStatus::kOutOfImage;
      done_[i] = 1;
    }
  }
}

// The most interior unprocessed point of `act` (grid distance transform in
// steps of `stride`, the set's own neighbourhood, image border counted as
// processed); n when none is left. (With one-point steps every point of a
// lattice set lay one step from a point outside it: the seed was the first
// in scan order, the field's corner, and on aldic's unspeckled border all
// 40 seed attempts of the first frame's coarse pass failed.)
size_t PassRunner::PickSeed(const std::vector<char>& act, int stride) const {
  const int nx = m_.grid.nx, ny = m_.grid.ny;
  std::vector<int> dist(n_, -1);
  std::vector<size_t> queue;
  for (size_t i = 0; i < n_; ++i)
    if (!(act[i] && !done_[i])) {
      dist[i] = 0;
      queue.push_back(i);
    }
  if (queue.size() == n_) return n_;
  for (size_t q = 0; q < queue.size(); ++q) {
    size_t nb[4];
    const int m = Neighbours(queue[q], stride, nb);
    for (int k = 0; k < m; ++k)
      if (dist[nb[k]] < 0) {
        dist[nb[k]] = dist[queue[q]] + 1;
        queue.push_back(nb[k]);
      }
  }
  size_t seed = n_;
  int best_d = -1;
  for (size_t i = 0; i < n_; ++i) {
    if (!(act[i] && !done_[i])) continue;
    const int ix = static_cast<int>(i % nx), iy = static_cast<int>(i / nx);
    const int di = dist[i] < 0 ? std::numeric_limits<int>::max() : dist[i];
    const int d = std::min({di, ix / stride + 1, iy / stride + 1, (nx - 1 - ix) / stride + 1,
                            (ny - 1 - iy) / stride + 1});
    if (d > best_d) {
      best_d = d;
      seed = i;
    }
  }
  return seed;
}

// Stage seeds: integer guess by NCC within +-seed_search_radius around the
// point's own guess or the mean motion of converged points (0 when none).
void PassRunner::SolveSeed(size_t seed, const std::vector<Params>& guess,
                           const std::vector<char>& has_guess) {
  double gu = 0, gv = 0;
  size_t ng = 0;
  for (size_t i = 0; i < n_; ++i)
    if (done_[i] && res_[i].status == PointStatus::kOk && m_.eligible[i]) {
      gu += res_[i].p[0];
      gv += res_[i].p[6];
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
  Workspace& ws = m_.workspaces[0];
  PointResult r;
  r.status = PointStatus::kOutOfImage;  // unless the search window fits
  Params q;
  if (Search(seed, gu, gv, m_.opt.seed_search_radius, &q, ws)) {
    r = SolvePoint(seed, q, ws);
    ++count_;
  }
  res_[seed] = r;
  done_[seed] = 1;
}

// Wavefront propagation over the points flagged in `act` on a lattice of
// the given stride, then seeds for what no front reached.
void PassRunner::Propagate(const std::vector<char>& act, int stride,
                           const std::vector<Params>& guess, const std::vector<char>& has_guess) {
  std::vector<size_t> good;
  for (size_t i = 0; i < n_; ++i)
    if (done_[i] && res_[i].status == PointStatus::kOk) good.push_back(i);
  std::vector<size_t> front = FrontierOf(good, act, stride);
  int seed_attempts = 0;
  for (;;) {
    while (!front.empty()) {
      SolveFront(front, stride);
      front = FrontierOf(front, act, stride);
    }
    MarkLeaving(act, guess, has_guess);
    const size_t seed = PickSeed(act, stride);
    if (seed == n_ || seed_attempts >= m_.opt.max_seed_attempts) break;
    ++seed_attempts;
    SolveSeed(seed, guess, has_guess);
    front = FrontierOf({seed}, act, stride);
  }
}

// Guesses for the points off the lattice: the nearest converged lattice
// point's motion, extrapolated.
void PassRunner::LatticeGuesses(int stride, std::vector<Params>* g, std::vector<char>* hg) const {
  const int nx = m_.grid.nx, ny = m_.grid.ny;
  g->assign(n_, Params{});
  hg->assign(n_, 0);
  for (size_t i = 0; i < n_; ++i) {
    if (!active_[i] || done_[i]) continue;
    const int ix = static_cast<int>(i % nx), iy = static_cast<int>(i / nx);
    const int bx = ix - ix % stride, by = iy - iy % stride;
    double best_d = 1e300;
    for (int jy : {by, by + stride})
      for (int jx : {bx, bx + stride}) {
        if (jx >= nx || jy >= ny) continue;
        const size_t j = static_cast<size_t>(jy) * nx + jx;
        if (!done_[j] || res_[j].status != PointStatus::kOk) continue;
        const double d = std::hypot(jx - ix, jy - iy);
        if (d < best_d) {
          best_d = d;
          (*g)[i] = Extrapolate(res_[j].p, cx_[i] - cx_[j], cy_[i] - cy_[j]);
          (*hg)[i] = 1;
        }
      }
  }
}

std::vector<PointResult> PassRunner::Run(const std::vector<Params>& guess,
                                         const std::vector<char>& has_guess,
                                         std::size_t* solves,
                                         const std::vector<PointResult>* prior,
                                         const std::vector<char>* keep) {
  Start(prior, keep);
  const int coarse_stride = 4;
  bool any_guess = false;
  size_t n_active = 0;
  for (size_t i = 0; i < n_; ++i) {
    any_guess = any_guess || (active_[i] && has_guess[i]);
    n_active += active_[i] ? 1 : 0;
  }
  if (!any_guess && n_active >= 1500) {
    // Coarse lattice first (few, serial-ish fronts), then every other point
    // from its nearest converged lattice point in one parallel loop.
    std::vector<char> coarse(n_, 0);
    for (size_t i = 0; i < n_; ++i) {
      const int ix = static_cast<int>(i % m_.grid.nx), iy = static_cast<int>(i / m_.grid.nx);
      coarse[i] = active_[i] && ix % coarse_stride == 0 && iy % coarse_stride == 0;
    }
    Propagate(coarse, coarse_stride, guess, has_guess);
    std::vector<Params> g2;
    std::vector<char> hg2;
    LatticeGuesses(coarse_stride, &g2, &hg2);
    SolveGuessed(g2, hg2);
  } else {
    SolveGuessed(guess, has_guess);
    // The update test's lattice first, by fronts along the lattice: its
    // points get the same results whatever else is active (with a crack
    // band most of them have no active neighbour), so band and full field
    // update the reference at the same frames.
    if (m_.sample_stride > 1) {
      std::vector<char> lattice(n_, 0);
      for (size_t i = 0; i < n_; ++i) lattice[i] = active_[i] && m_.OnLattice(i, m_.sample_stride);
      Propagate(lattice, m_.sample_stride, guess, has_guess);
    }
  }
  Propagate(active_, 1, guess, has_guess);
  *solves += count_;
  return std::move(res_);
}

}  // namespace

std::vector<PointResult> RunPass(CorrelatorState& state, const Image& def_image,
                                 const InterpolatedImage& def_interp,
                                 const std::vector<Params>& guess,
                                 const std::vector<char>& has_guess, std::size_t* solves,
                                 const std::vector<PointResult>* prior,
                                 const std::vector<char>* keep) {
  state.workspaces.resize(std::max(state.Threads(), 1));
  PassRunner runner(state, def_image, def_interp);
  return runner.Run(guess, has_guess, solves, prior, keep);
}

}  // namespace bridgefit::dic::detail
