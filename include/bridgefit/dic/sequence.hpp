#pragma once
// Crack length along an image sequence: correlate every frame against the
// first (incremental reference updates as needed), locate the tip in each,
// and make the crack length monotone in time (weighted isotonic regression).
// Crack length = distance along the crack line from (x0, y0) to the tip,
// times the scale, plus the offset.

#include <filesystem>
#include <string>
#include <vector>

#include "bridgefit/dic/correlation.hpp"
#include "bridgefit/dic/crack.hpp"

namespace bridgefit::dic {

struct CrackSequenceOptions {
  CorrelationOptions correlation;  // has_crack/crack are set from tip.line
  CrackTipOptions tip;
  TipMethod method = TipMethod::kWilliams;
  double scale_m_per_px = 0;  // > 0
  double offset_m = 0;
  bool keep_fields = false;   // keep each frame's displacement field
  bool show_progress = true;  // on stderr

  bool IsValid(std::string* why) const;
};

struct FrameResult {
  std::string image;
  bool has_length = false;     // false: no detectable opening (or no tip)
  double crack_length_m = 0;   // monotone in time
  double crack_length_raw_m = 0;  // this frame's own estimate
  double uncertainty_m = 0;
  CrackTipResult tip;
  CorrelationSummary correlation;
  double valid_fraction = 0;
  DisplacementField field;  // only with keep_fields
};

struct CrackSequenceResult {
  std::vector<FrameResult> frames;  // frames[0] is the reference
  double wall_s = 0;
  double points_per_s = 0;  // IC-GN solves per second over the whole run
  std::size_t points = 0;   // grid points per frame
  std::string BriefReport() const;
};

// Throws Error(kInput) naming the file for unreadable images or a size
// mismatch, Error(kUsage) for invalid options, Error(kInput) for a crack
// line outside the image.
CrackSequenceResult AnalyzeCrackSequence(const std::vector<std::filesystem::path>& images,
                                         const CrackSequenceOptions& options);

}  // namespace bridgefit::dic
