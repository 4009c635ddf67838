// Subset DIC: options, results, the grid, and the sequence logic of a
// Correlator (incremental reference update, accumulation of motions). One
// pass over the grid is in pass.cpp, IC-GN on one subset in icgn.cpp.
#include "bridgefit/dic/correlation.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <omp.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "correlation_impl.hpp"

namespace bridgefit::dic {

using detail::kNp;

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
  if (update_sample_stride < 0) return fail("update sample stride must be >= 0");
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

int detail::CorrelatorState::Threads() const {
  return opt.threads > 0 ? opt.threads : omp_get_max_threads();
}

detail::SubsetAcrossCrack::SubsetAcrossCrack(const CrackLine& line, double length_px, int half_size)
    : line_(line), length_(length_px) {
  const double L = line.Length();
  const double tx = L > 0 ? (line.x1 - line.x0) / L : 0, ty = L > 0 ? (line.y1 - line.y0) / L : 0;
  // Half extent of a subset square along the line normal and along the line.
  half_s_ = (half_size + 0.5) * (std::abs(tx) + std::abs(ty));
  half_n_ = half_s_ + 0.5;
}

bool detail::SubsetAcrossCrack::operator()(double x, double y) const {
  if (!(length_ > 0)) return false;
  double s, n;
  line_.ToLocal(x, y, &s, &n);
  return std::abs(n) <= half_n_ && s >= -half_s_ && s <= length_ + half_s_;
}

void Correlator::Impl::BuildGrid(const Image& reference) {
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
  const detail::SubsetAcrossCrack band(opt.crack, opt.has_crack ? opt.crack.Length() : 0, M);
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
      if (opt.has_crack && band(grid.x[i], grid.y[i])) {
        grid.status[i] = PointStatus::kCrackBand;
        eligible[i] = 0;
      }
    }
}

void Correlator::Impl::SetLocatedCrack(const CrackLine& line, double length_px) {
  if (!(length_px > 0)) {
    across_crack.clear();
    return;
  }
  if (!(line.Length() >= 1.0))
    throw Error(ErrorKind::kUsage, "the located crack's line must be at least 1 px long");
  const detail::SubsetAcrossCrack across(line, length_px, opt.subset_size / 2);
  across_crack.assign(grid.size(), 0);
  for (size_t i = 0; i < grid.size(); ++i) across_crack[i] = across(grid.x[i], grid.y[i]) ? 1 : 0;
}

void Correlator::Impl::SetActive(const std::vector<char>& active) {
  const size_t n = grid.size();
  if (!active.empty() && active.size() != n)
    throw Error(ErrorKind::kUsage, "active point list differs from the grid",
                {.value = std::to_string(active.size()), .expected = std::to_string(n)});
  active_set = active;
  ApplyActive();
}

void Correlator::Impl::ApplyActive() {
  const size_t n = grid.size();
  const int stride = prev_ok.empty() ? std::min(sample_stride, 4) : sample_stride;
  hidden.assign(n, 0);
  for (size_t i = 0; i < n; ++i) {
    const bool wanted = active_set.empty() || active_set[i];
    const bool on = static_eligible[i] && (wanted || OnLattice(i, stride));
    eligible[i] = on ? 1 : 0;
    hidden[i] = on && !wanted ? 1 : 0;
    grid.status[i] = static_eligible[i] && !on ? PointStatus::kMasked : static_status[i];
  }
  // Points back in play after a reference update: their motion to the
  // current reference from known neighbours.
  FillUnknown(ref_p, ref_known);
}

void Correlator::Impl::SetReference(const Image& image) {
  ref_image = image;
  ref_interp = detail::InterpolatedImage(ref_image, opt.interpolation);
  ref_nodes = detail::NodeMaps{};
  ref_cache.clear();
  if (opt.shape == ShapeFunction::kFirstOrder) {
    ref_nodes = ref_interp.Nodes();
    // About 350 bytes per point; very large grids rebuild the reference
    // data at every solve instead of holding it.
    constexpr std::size_t kMaxCacheBytes = std::size_t{256} << 20;
    if (grid.size() * sizeof(detail::ReferenceSubset) <= kMaxCacheBytes)
      ref_cache.assign(grid.size(), detail::ReferenceSubset{});
  }
}

// Outside the active set only the update test's lattice was correlated in
// the new reference's frame; filled from the active points' edge alone, the
// motion there was extrapolated over the whole field (0.3-0.5 px off 120 px
// from aldic's crack band, so the band's Williams fits read other fields
// than the full field's). The lattice cell around a point, its four corners
// correlated, gives it by bilinear interpolation instead (the motion is
// smooth there: the crack and its band are correlated in full).
void Correlator::Impl::FillFromLattice(std::vector<Params>& p, std::vector<char>& known) const {
  const int s = sample_stride;
  if (s <= 1 || active_set.empty()) return;
  // The corners are lattice points, which this never fills (a lattice
  // point is its own corner): the fill reads only motions known before it.
  for (size_t i = 0; i < grid.size(); ++i) {
    if (known[i] || !static_eligible[i] || ref_lost[i] || AcrossCrack(i)) continue;
    const int ix = static_cast<int>(i % grid.nx), iy = static_cast<int>(i / grid.nx);
    const int x0 = ix / s * s, y0 = iy / s * s;
    const int x1 = x0 + s < grid.nx ? x0 + s : x0, y1 = y0 + s < grid.ny ? y0 + s : y0;
    if ((x1 == x0 && ix != x0) || (y1 == y0 && iy != y0)) continue;  // beyond the last lattice line
    const double tx = x1 > x0 ? static_cast<double>(ix - x0) / s : 0.0;
    const double ty = y1 > y0 ? static_cast<double>(iy - y0) / s : 0.0;
    const size_t c[4] = {static_cast<size_t>(y0) * grid.nx + x0, static_cast<size_t>(y0) * grid.nx + x1,
                         static_cast<size_t>(y1) * grid.nx + x0, static_cast<size_t>(y1) * grid.nx + x1};
    const double w[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
    bool all = true;
    for (size_t j : c) all = all && known[j];
    if (!all) continue;
    Params sum{};
    for (int q = 0; q < 4; ++q)
      for (int k = 0; k < kNp; ++k) sum[k] += w[q] * p[c[q]][k];
    p[i] = sum;
    known[i] = 1;
  }
}

// Fills unknown reference motions from known same-side grid neighbours
// (never across crack-band or masked points, which are not eligible, and
// never for points lost at a reference update).
void Correlator::Impl::FillUnknown(std::vector<Params>& p, std::vector<char>& known) const {
  const size_t n = grid.size();
  for (int sweep = 0; sweep < 50; ++sweep) {
    bool changed = false;
    std::vector<char> newly(n, 0);
    std::vector<Params> add(n);
    for (size_t i = 0; i < n; ++i) {
      if (known[i] || !eligible[i] || ref_lost[i]) continue;
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

DisplacementField Correlator::Impl::Next(const Image& frame, CorrelationSummary* summary) {
  if (frame.width != ref_image.width || frame.height != ref_image.height)
    throw Error(ErrorKind::kInput,
                fmt::format("image size {}x{} differs from the reference {}x{}", frame.width,
                            frame.height, grid_width, grid_height),
                {.expected = "all images of a sequence with the same size"});
  Stopwatch watch;
  // With an active set: the update test's lattice for this frame.
  if (!active_set.empty()) ApplyActive();
  ++frame_index;
  const size_t n = grid.size();
  const double cpu0 = opt.profile_stages ? detail::StageClock::Seconds() : 0.0;
  frame_interp = detail::InterpolatedImage(frame, opt.interpolation);
  const double setup_s = opt.profile_stages ? detail::StageClock::Seconds() - cpu0 : 0.0;
  for (detail::Workspace& ws : workspaces) ws.times = detail::StageTimes{};
  std::size_t solves = 0;
  std::vector<PointResult> res;
  for (int attempt = 0; attempt < 2; ++attempt) {
    // Guesses: last frame's total motion expressed from the current reference.
    frame_guess.assign(n, Params{});
    frame_has_guess.assign(n, 0);
    for (size_t i = 0; i < n; ++i) {
      if (!prev_ok.empty() && prev_ok[i] && ref_known[i]) {
        frame_guess[i] = Increment(prev_total[i], ref_p[i]);
        frame_has_guess[i] = 1;
      }
    }
    res = Pass(frame, frame_interp, frame_guess, frame_has_guess, &solves);
    // The update test leaves out the points lost at the last update: a
    // crack fails the subsets across it for good, and once they had passed
    // the threshold they called a new reference at every frame (each
    // update adds the composed motions' error). Nor does it count subsets
    // across the crack located in the last frame: the crack, not
    // decorrelation. (Subsets moved out of the image still count: left out,
    // the real aldic sequence kept its first reference and lost the tip of
    // its last frame to the decorrelated zone ahead of it.)
    size_t used = 0, good = 0;
    double zsum = 0;
    for (size_t i = 0; i < n; ++i) {
      if (!eligible[i] || !OnLattice(i, sample_stride)) continue;
      if (ref_lost[i]) continue;
      if (AcrossCrack(i)) continue;
      ++used;
      if (res[i].status == PointStatus::kOk) {
        ++good;
        zsum += res[i].zncc;
      }
    }
    const double valid_fraction = used ? static_cast<double>(good) / used : 0;
    const double mean_zncc = good ? zsum / good : 0;
    const bool poor = used > 0 && (valid_fraction < opt.update_min_valid_fraction ||
                                   mean_zncc < opt.update_min_mean_zncc);
    if (attempt == 0 && poor && opt.incremental && ref_index != frame_index - 1 &&
        !prev_image.empty()) {
      // Reference update: the previous frame becomes the reference.
      SetReference(prev_image);
      ref_p = prev_total;
      ref_known = prev_ok;
      // A point that failed in the new reference frame (its subset across
      // the open crack, or decorrelated) has no motion there: it stays
      // lost. Filling it from its neighbours would average both faces and
      // bring it back as a valid point with the crack's jump smeared. A
      // point across the crack located there is lost too, whether it
      // failed or not: its subset in the new reference holds the gap.
      for (size_t i = 0; i < n; ++i) {
        ref_lost[i] = (eligible[i] && !prev_ok[i]) || AcrossCrack(i) ? 1 : 0;
        if (AcrossCrack(i)) ref_known[i] = 0;
      }
      FillFromLattice(ref_p, ref_known);
      FillUnknown(ref_p, ref_known);
      for (size_t i = 0; i < n; ++i)
        if (!ref_known[i]) lost_status[i] = AcrossCrack(i) ? PointStatus::kCrackBand : prev_status[i];
      ref_index = frame_index - 1;
      ++updates;
      continue;
    }
    break;
  }
  prev_image = frame;
  frame_res = res;
  DisplacementField field = Collect(res, summary);
  frame_solves = solves;
  frame_wall_s = watch.Seconds();
  if (summary) {
    summary->wall_s = frame_wall_s;
    summary->points_per_s = summary->wall_s > 0 ? solves / summary->wall_s : 0;
    summary->solves = solves;
    if (opt.profile_stages) {
      detail::StageTimes t;
      for (const detail::Workspace& ws : workspaces) t += ws.times;
      CorrelationSummary::StageSeconds& st = summary->stages;
      st.setup = setup_s;
      st.search = t.search;
      st.reference = t.reference;
      st.interpolation = t.interpolation;
      st.residual = t.residual;
      st.update = t.update;
      // The rest of the calling thread's time (one thread; with more the
      // workers' time is in the stages but not in this difference).
      st.propagation = std::max(0.0, detail::StageClock::Seconds() - cpu0 - setup_s -
                                         t.search - t.reference - t.interpolation - t.residual -
                                         t.update);
    }
  }
  return field;
}

// More points in the frame last correlated: against the same reference (no
// update), the new points from the guesses that frame's pass had and from
// fronts out of the points solved already, which keep their results.
DisplacementField Correlator::Impl::Extend(const std::vector<char>& active,
                                           CorrelationSummary* summary) {
  if (frame_index == 0 || frame_res.size() != grid.size())
    throw Error(ErrorKind::kUsage, "Correlator::Extend needs a frame correlated by Next");
  if (active.size() != grid.size())
    throw Error(ErrorKind::kUsage, "active point list differs from the grid",
                {.value = std::to_string(active.size()), .expected = std::to_string(grid.size())});
  Stopwatch watch;
  const size_t n = grid.size();
  const std::vector<char> before = eligible;
  std::vector<char> wanted(n, 0);
  for (size_t i = 0; i < n; ++i)
    wanted[i] = active_set.empty() || active_set[i] || active[i] ? 1 : 0;
  SetActive(wanted);
  // Converged points keep their results; the others try again where a new
  // point is next to them (a lattice point of the update test is isolated:
  // no front reached it), and keep their failure where none is (the same
  // neighbours again: in aldic's band without an ROI a tenth of the
  // frame's solves went to such retries, which the full field never makes).
  auto next_to_added = [&](size_t i) {
    const int ix = static_cast<int>(i % grid.nx), iy = static_cast<int>(i / grid.nx);
    const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
    for (int k = 0; k < 4; ++k) {
      const int jx = ix + dx[k], jy = iy + dy[k];
      if (jx < 0 || jy < 0 || jx >= grid.nx || jy >= grid.ny) continue;
      const size_t j = static_cast<size_t>(jy) * grid.nx + jx;
      if (eligible[j] && !before[j]) return true;
    }
    return false;
  };
  std::vector<char> keep(n, 0);
  for (size_t i = 0; i < n; ++i)
    keep[i] = before[i] && (frame_res[i].status == PointStatus::kOk || !next_to_added(i));
  for (detail::Workspace& ws : workspaces) ws.times = detail::StageTimes{};
  std::size_t solves = 0;
  frame_res = detail::RunPass(*this, prev_image, frame_interp, frame_guess, frame_has_guess, &solves,
                              &frame_res, &keep);
  DisplacementField field = Collect(frame_res, summary);
  frame_solves += solves;
  frame_wall_s += watch.Seconds();
  if (summary) {
    summary->wall_s = frame_wall_s;
    summary->solves = frame_solves;
    summary->points_per_s = frame_wall_s > 0 ? frame_solves / frame_wall_s : 0;
  }
  return field;
}

DisplacementField Correlator::Impl::Collect(const std::vector<PointResult>& res,
                                            CorrelationSummary* summary) {
  const size_t n = grid.size();
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
    if (!hidden.empty() && hidden[i]) continue;  // reported masked below
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
  // Correlated for the update test and the next frame's guesses only.
  for (size_t i = 0; i < n && !hidden.empty(); ++i)
    if (hidden[i]) {
      field.status[i] = PointStatus::kMasked;
      field.zncc[i] = 0;
      field.iterations[i] = 0;
    }
  if (summary) {
    summary->frame = frame_index;
    summary->reference_frame = ref_index;
    summary->reference_updates = updates;
    summary->points = used;
    summary->valid = good;
    summary->mean_zncc = good ? zsum / good : 0;
    summary->mean_iterations = used ? itsum / used : 0;
  }
  return field;
}

// Total motion from the increment d (current reference -> frame) and the
// reference motion r (original -> current reference): u = u_r + d,
// F = F_d F_r (first-order terms; second-order terms of d are kept as is).
detail::Params Correlator::Impl::Accumulate(const Params& d, const Params& r) {
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
detail::Params Correlator::Impl::Increment(const Params& t, const Params& r) {
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
  m.static_eligible = m.eligible;
  m.static_status = m.grid.status;
  m.sample_stride = options.update_sample_stride;
  if (m.sample_stride <= 0) {
    const double n = static_cast<double>(m.grid.size());
    m.sample_stride = n / 4 < 256 ? 1 : n / 16 < 256 ? 2 : 4 * std::max(1, static_cast<int>(std::sqrt(n / 256) / 4));
  }
  m.SetReference(reference);
  m.ref_p.assign(m.grid.size(), detail::Params{});
  m.ref_known.assign(m.grid.size(), 1);
  m.ref_lost.assign(m.grid.size(), 0);
  m.lost_status.assign(m.grid.size(), PointStatus::kUnreached);
}

Correlator::~Correlator() = default;
const DisplacementField& Correlator::Grid() const { return impl_->grid; }
DisplacementField Correlator::Next(const Image& frame, CorrelationSummary* summary) {
  return impl_->Next(frame, summary);
}
void Correlator::SetActive(const std::vector<char>& active) { impl_->SetActive(active); }
void Correlator::SetLocatedCrack(const CrackLine& line, double length_px) {
  impl_->SetLocatedCrack(line, length_px);
}
DisplacementField Correlator::Extend(const std::vector<char>& active, CorrelationSummary* summary) {
  return impl_->Extend(active, summary);
}

DisplacementField CorrelatePair(const Image& reference, const Image& deformed,
                                const CorrelationOptions& options, CorrelationSummary* summary) {
  Correlator correlator(options, reference);
  return correlator.Next(deformed, summary);
}

}  // namespace bridgefit::dic