#pragma once
// Private: the crack band of a sequence (sequence.cpp), frame by frame.

#include <vector>

#include "bridgefit/dic/sequence.hpp"

namespace bridgefit::dic::detail {

// Sets each frame's active points before it is correlated and completes
// them afterwards, so that the crack location reads the same points as with
// every point correlated:
//   Prepare:  the path scan about the line given, plus the last frame's
//             reads (COD windows about the line it used, its Williams
//             window widened by the last move of the window's centre);
//   Complete: after locating, the points this frame's location read but were
//             not correlated are added to the frame (Correlator::Extend) and
//             the crack is located again (the path scan is unchanged, so the
//             line and the window's centre are too).
// Without a line the first frames are correlated whole until a path is
// found; then the path found stands in for the line. Inactive with
// full_field or the J integral (every point).
class BandTracker {
 public:
  BandTracker(const CrackSequenceOptions& o, const CrackPathOptions& path_opt, Correlator* c);
  void Prepare();
  // `field` and `r` of the frame just correlated and located; both are
  // replaced by the completed ones.
  void Complete(DisplacementField* field, FrameResult* r);
  // Whether r's location (its COD windows and Williams window, no path
  // scan) read points of `field` that were not correlated.
  bool Lacks(const DisplacementField& field, const FrameResult& r) const;

 private:
  bool Enabled() const { return !o_.full_field && !o_.j_integral.enabled; }
  CrackBandReads LocationReads(const FrameResult& r) const;
  std::vector<char> Missing(const FrameResult& r) const;

  const CrackSequenceOptions& o_;
  const CrackPathOptions& path_opt_;
  Correlator* c_;
  std::vector<char> usable_;  // not masked by the ROI, mask or a fixed crack band
  std::vector<char> active_;  // this frame's points
  bool have_line_ = false;    // a scan line: the line given or a path found
  CrackLine scan_line_;
  bool have_last_ = false;    // the last frame's reads
  CrackLine last_line_;
  bool last_window_ = false;
  double last_cx_ = 0, last_cy_ = 0, last_move_ = 0;
};

}  // namespace bridgefit::dic::detail
