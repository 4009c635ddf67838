// The sequence's crack path and the frames located again along it
// (sequence_path_impl.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "sequence_path_impl.hpp"

namespace bridgefit::dic::detail {

double PathSe(const CrackPathResult& path) {
  // A fitted standard error of 0 (every crack point on one row of a
  // lattice) is a resolved path, not a missing fit.
  return path.found && path.line_se_fitted ? path.line_se_px
                                           : std::numeric_limits<double>::infinity();
}

bool PathResolved(const CrackPathResult& path, const CrackPathOptions& o) {
  return PathSe(path) <= 0.5 * o.hint_tolerance_px;
}

bool MayTakeSequencePath(const CrackPathResult& path, const CrackPathOptions& o) {
  return !path.found || !PathResolved(path, o);
}

void KeptFields::Offer(std::size_t frame, const DisplacementField& field, const FrameResult& r,
                       const CrackPathOptions& path_opt) {
  if (!MayTakeSequencePath(r.path, path_opt)) return;
  Kept k;
  k.frame = frame;
  k.nx = field.nx;
  k.ny = field.ny;
  // Frames of one grid (every image frame, an export's fixed mesh) share
  // their positions.
  const bool same_grid = !kept_.empty() && *kept_.back().x == field.x && *kept_.back().y == field.y;
  double bytes = static_cast<double>(field.size()) * sizeof(PointStatus);
  if (same_grid) {
    k.x = kept_.back().x;
    k.y = kept_.back().y;
  } else {
    bytes += 2.0 * static_cast<double>(field.size()) * sizeof(double);
  }
  for (std::size_t i = 0; i < field.size(); ++i)
    if (field.status[i] != PointStatus::kMasked) bytes += 2 * sizeof(double) + sizeof(std::uint32_t);
  if (used_bytes_ + bytes > budget_bytes_) {
    ++dropped_;
    return;
  }
  used_bytes_ += bytes;
  if (!same_grid) {
    k.x = std::make_shared<const std::vector<double>>(field.x);
    k.y = std::make_shared<const std::vector<double>>(field.y);
  }
  k.status = field.status;
  for (std::size_t i = 0; i < field.size(); ++i)
    if (field.status[i] != PointStatus::kMasked) {
      k.index.push_back(static_cast<std::uint32_t>(i));
      k.u.push_back(field.u[i]);
      k.v.push_back(field.v[i]);
    }
  kept_.push_back(std::move(k));
}

bool KeptFields::Has(std::size_t frame) const {
  for (const Kept& k : kept_)
    if (k.frame == frame) return true;
  return false;
}

DisplacementField KeptFields::Restore(std::size_t frame) const {
  DisplacementField f;
  for (const Kept& k : kept_) {
    if (k.frame != frame) continue;
    f.nx = k.nx;
    f.ny = k.ny;
    f.x = *k.x;
    f.y = *k.y;
    f.status = k.status;
    const std::size_t n = f.x.size();
    f.u.assign(n, 0.0);
    f.v.assign(n, 0.0);
    for (std::size_t j = 0; j < k.index.size(); ++j) {
      f.u[k.index[j]] = k.u[j];
      f.v[k.index[j]] = k.v[j];
    }
    // What the location does not read, zero (gradients, ZNCC, iterations).
    for (auto* a : {&f.dudx, &f.dudy, &f.dvdx, &f.dvdy, &f.zncc}) a->assign(n, 0.0);
    f.iterations.assign(n, 0);
  }
  return f;
}

int SequencePathFrame(const std::vector<FrameResult>& frames) {
  // Ranked by: the angle measured (a path that kept the hint's direction
  // follows the line given, and its offset-only standard error understates
  // its error at the ends: the MDF sample with the line tilted 2 degrees
  // about its far end took such a path, 14 px off at the notch, and read
  // 52.8 mm for 60), then the smaller standard error, then the larger
  // summed jump.
  int best = -1;
  bool best_measured = false;
  double best_se = std::numeric_limits<double>::infinity(), best_score = 0;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const FrameResult& f = frames[k];
    // A path without a standard error (too few independent points for one)
    // is no measurement of where the crack runs: never the sequence's.
    if (!f.path.found || !f.path.line_se_fitted || f.path.curved || !f.has_length ||
        f.LengthDoubtful())
      continue;
    double score = 0;
    for (std::size_t i = 0; i < f.path.point_jump_px.size(); ++i)
      if (i < f.path.inlier.size() && f.path.inlier[i]) score += f.path.point_jump_px[i];
    const bool measured = !f.path.angle_from_hint;
    const double se = PathSe(f.path);
    const bool better =
        best < 0 || (measured && !best_measured) ||
        (measured == best_measured && (se < best_se || (se == best_se && score > best_score)));
    if (better) {
      best_measured = measured;
      best_se = se;
      best_score = score;
      best = static_cast<int>(k);
    }
  }
  return best;
}

bool TakesSequencePath(const FrameResult& frame, const FrameResult& source,
                       const CrackPathOptions& path_opt) {
  // No path, or one whose line fit has no standard error (too few
  // independent points: aldic's full field put 5 such points 14-17 px off
  // the crack, at an RMS of 10-15 px, and read -1.5 +- 63 px): no
  // measurement of the line.
  if (!frame.path.found || !std::isfinite(PathSe(frame.path))) return true;
  if (!MayTakeSequencePath(frame.path, path_opt)) return false;
  // The larger distance of the source's line from this frame's path at the
  // ends of its cracked length, against twice their uncertainties there.
  const CrackLine& own = frame.line_used;
  const CrackLine& src = source.line_used;
  const double sx = src.x1 - src.x0, sy = src.y1 - src.y0, slen = std::hypot(sx, sy);
  const double ox = own.x1 - own.x0, oy = own.y1 - own.y0, olen = std::hypot(ox, oy);
  if (!(slen > 0) || !(olen > 0)) return false;
  double apart = 0;
  for (double s : {0.0, frame.path.cracked_length_px}) {
    const double x = own.x0 + s * ox / olen, y = own.y0 + s * oy / olen;
    apart = std::max(apart, std::abs(-(x - src.x0) * sy + (y - src.y0) * sx) / slen);
  }
  const double tolerance =
      2 * std::sqrt(std::pow(PathSe(frame.path), 2) + std::pow(PathSe(source.path), 2) +
                    std::pow(0.5 * path_opt.hint_tolerance_px, 2));
  return apart > tolerance;
}

namespace {

// A reading's uncertainty for comparing it with another, px: +inf without a
// length or at the field's edge (a bound, not a reading); where the methods
// disagree, at least what they would need to agree (AgreementSigma).
double ComparableSigmaPx(const FrameResult& f, const CrackSequenceOptions& o) {
  if (!f.has_length || f.tip.tip_at_edge) return std::numeric_limits<double>::infinity();
  double s = f.uncertainty_m / o.scale_m_per_px;
  if (f.tip.methods_disagree) s = std::max(s, AgreementSigma(f.tip, o.tip));
  return s;
}

// Doubts other than the methods' disagreement and the edge: the Williams
// fit's, points the crack band did not correlate, and an opening that does
// not reach back to the line's start.
bool OtherDoubt(const FrameResult& f) {
  return f.tip.williams_unstable || f.tip.williams_window_short || f.tip_beyond_band ||
         f.tip.opening_detached;
}

}  // namespace

bool ReadsBetterAlongSequencePath(const FrameResult& along, const FrameResult& own,
                                  const CrackSequenceOptions& options) {
  if (!along.has_length) return false;
  if (!own.has_length) return true;
  if (OtherDoubt(along) && !OtherDoubt(own)) return false;
  return ComparableSigmaPx(along, options) < ComparableSigmaPx(own, options);
}

}  // namespace bridgefit::dic::detail
