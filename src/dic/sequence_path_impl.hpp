#pragma once
// Private: the sequence's crack path (sequence.cpp, sequence_path.cpp).
//
// The crack path is a material line: in reference coordinates it does not
// move from frame to frame, and a growing crack's early frames hold a part
// of the path its later frames hold. Frames with a small opening resolve it
// badly or not at all (no jump above the noise), and the length they read
// along the line given then depends on that line. After the last frame the
// most precise path found (its angle measured, then the smallest standard
// error at its ends, then the largest summed jump of its crack points; a
// standard error fitted, not curved, its frame's length not in doubt) is the
// sequence's path (SequencePathFrame), and every frame without a path of
// its own, or whose own is not resolved and disagrees with it
// (TakesSequencePath), is located again along it; an unresolved one that
// agrees takes that reading where it is better (ReadsBetterAlongSequencePath).
// Their fields are kept until then, compactly (statuses, and the
// displacements of the points that were correlated), within a memory
// budget; frames beyond it keep their own reading.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "bridgefit/dic/sequence.hpp"

namespace bridgefit::dic::detail {

// The standard error of a frame's path at its ends, +inf where it has none
// (no fit of its own: too few points for one).
double PathSe(const CrackPathResult& path);

// True where a frame's own path is resolved to the path's resolution (half
// the hint tolerance): such a frame never takes the sequence's path.
bool PathResolved(const CrackPathResult& path, const CrackPathOptions& o);

// Whether a frame with this path can take the sequence's path at all
// (TakesSequencePath): no path, or with a line given (only then is a
// standard error worked out) one not resolved.
bool MayTakeSequencePath(const CrackPathResult& path, const CrackPathOptions& o);

class KeptFields {
 public:
  explicit KeptFields(double budget_mb) : budget_bytes_(budget_mb * 1048576.0) {}
  // Keeps frame k's field where it may take the sequence's path, budget
  // allowing.
  void Offer(std::size_t frame, const DisplacementField& field, const FrameResult& r,
             const CrackPathOptions& path_opt);
  bool Has(std::size_t frame) const;
  DisplacementField Restore(std::size_t frame) const;
  std::size_t Dropped() const { return dropped_; }

 private:
  struct Kept {
    std::size_t frame;
    int nx, ny;
    std::shared_ptr<const std::vector<double>> x, y;
    std::vector<PointStatus> status;
    std::vector<std::uint32_t> index;  // points not masked
    std::vector<double> u, v;          // at index
  };
  double budget_bytes_;
  double used_bytes_ = 0;
  std::size_t dropped_ = 0;
  std::vector<Kept> kept_;
};

// The frame whose path is the sequence's (-1: none): the most precise, its
// angle measured first.
int SequencePathFrame(const std::vector<FrameResult>& frames);

// A frame takes the sequence's path where it has none of its own (or one
// without a standard error: too few points for one), or where its own is
// not resolved (its standard error above the path's resolution)
// and lies further from the sequence's, at an end of its cracked length,
// than twice their uncertainties there (the standard errors and the
// resolution in quadrature): a few scattered points off the crack (aldic
// 0120 at y = 582: 9 points, RMS 13.5 px, 36 px off the later frames').
// An unresolved path that agrees keeps its frame's reading unless the
// reading along the sequence's path is better (ReadsBetterAlongSequencePath).
// (Taking every unresolved frame onto the sequence's path moved the 4-frame
// aldic crop's 0240 onto a path 7 px off its own, where no opening was
// left; the sequence's own path is as good as its standard error, which on
// real frames with failed subsets understates it.)
bool TakesSequencePath(const FrameResult& frame, const FrameResult& source,
                       const CrackPathOptions& path_opt);

// Frame r located again in `field` along the source frame's path (no path
// search), with its own path kept for the report and no field; `lacks(field,
// result)` says whether the location read points that were not correlated
// (crack band).
template <class Lacks>
FrameResult LocatedAlongSequencePath(const DisplacementField& field,
                                     const CrackSequenceOptions& options,
                                     const CrackPathOptions& path_opt, int source,
                                     const FrameResult& source_frame, const Lacks& lacks,
                                     const FrameResult& r) {
  CrackSequenceOptions along = options;
  along.find_path = false;
  along.has_line = true;
  along.tip.line = source_frame.line_used;
  FrameResult again;
  again.image = r.image;
  again.correlation = r.correlation;
  LocateCrackInField(field, along, path_opt, &again);
  again.path = r.path;
  again.path_from_frame = source;
  again.path_disagrees_with_hint = source_frame.path_disagrees_with_hint;
  // Points the location read that the crack band did not correlate (its
  // band followed this frame's own reading): a tip there may be off.
  again.tip_beyond_band = again.has_length && lacks(field, again);
  again.flagged = !again.Flags().empty();
  MeasureFrameJ(field, options, &again);
  return again;
}

// Whether a frame whose own path is not resolved but agrees with the
// sequence's reads its length better along the sequence's path: a length
// where its own path gave none (its points were jumps the line through them
// does not carry: aldic 0240 at y = 582, 7 points at an RMS of 15 px, no
// opening along them, 37.3 px along the sequence's path as with the line at
// y = 600), or one of a smaller uncertainty, a reading whose methods
// disagree counted at what they would need to agree and one at the field's
// edge not at all, and no new doubt about the Williams fit or the band
// (aldic's full field without ROI read 0540 at 10.8 +- 48 px along 6
// points 17 px below the sequence's path, 48.4 +- 4.9 px along it).
bool ReadsBetterAlongSequencePath(const FrameResult& along, const FrameResult& own,
                                  const CrackSequenceOptions& options);

// After the last frame: the frames kept that take the sequence's path (or
// read better along it), located again along it; out->sequence_path_frame
// and fields_not_kept set.
template <class Lacks>
void ApplySequencePath(const KeptFields& kept, const CrackSequenceOptions& options,
                       const CrackPathOptions& path_opt, const Lacks& lacks,
                       CrackSequenceResult* out) {
  out->fields_not_kept = kept.Dropped();
  if (!options.find_path || !options.sequence_path) return;
  std::vector<FrameResult>& frames = out->frames;
  const int source = SequencePathFrame(frames);
  out->sequence_path_frame = source;
  if (source < 0) return;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    // Kept: the frame may take the sequence's path (KeptFields::Offer).
    if (static_cast<int>(k) == source || !kept.Has(k)) continue;
    const bool takes = TakesSequencePath(frames[k], frames[source], path_opt);
    FrameResult along = LocatedAlongSequencePath(kept.Restore(k), options, path_opt, source,
                                                 frames[source], lacks, frames[k]);
    if (!takes && !ReadsBetterAlongSequencePath(along, frames[k], options)) {
      // Its own path agrees with the sequence's, which is resolved (a frame
      // whose path is not is in doubt and never the source): confirmed.
      if (frames[k].path_unresolved) {
        frames[k].path_unresolved = false;
        frames[k].flagged = !frames[k].Flags().empty();
      }
      continue;
    }
    along.field = std::move(frames[k].field);
    frames[k] = std::move(along);
  }
}

}  // namespace bridgefit::dic::detail
