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
#include "bridgefit/dic/crack_path.hpp"
#include "bridgefit/dic/frame_j.hpp"

namespace bridgefit::dic {

struct CrackSequenceOptions {
  CorrelationOptions correlation;  // has_crack/crack are set by the sequence
  CrackTipOptions tip;             // tip.line: the crack line given (a hint), if has_line
  bool has_line = true;            // false: no line given, the path is found from the data
  // true: the crack path is found in every frame (tip.line only a hint; the
  // correlation has no crack band, the tip search drops the points near the
  // found path instead); false: tip.line is taken as the crack (band on it).
  bool find_path = true;
  CrackPathOptions path;  // has_hint/hint are set from tip.line
  TipMethod method = TipMethod::kWilliams;
  double scale_m_per_px = 0;  // > 0
  double offset_m = 0;
  // false (default): each frame correlates only the crack band, the points
  // its crack location reads (CrackBandPoints; completed after locating, so
  // the lengths are those of the full field); true: every grid point.
  bool full_field = false;
  bool keep_fields = false;   // keep each frame's displacement field
  // Per-frame J_ff and delta* (dic/frame_j.hpp) while each field is in
  // memory. With it enabled every grid point is correlated (as with
  // full_field): the far-field domains reach beyond the crack band.
  FrameJOptions j_integral;
  bool show_progress = true;  // on stderr
  // find_path: after the last frame, frames without a path of their own,
  // or whose own is not resolved and disagrees with the sequence's most
  // precise path, are located again along that one (the path is a material
  // line: src/dic/sequence_path_impl.hpp). Their fields are kept until
  // then, at most kept_fields_mb; frames beyond it keep their own reading.
  bool sequence_path = true;
  double kept_fields_mb = 256;

  bool IsValid(std::string* why) const;
};

// The rule behind FrameResult::LengthDoubtful, on a Flags() string as the
// DIC CSV and HDF5 hold it.
bool FlagsDoubtLength(const std::string& flags);

struct FrameResult {
  std::string image;
  bool has_length = false;     // false: no detectable opening (or no tip)
  // A length is only as good as its flags: a flagged frame may be wrong by
  // more than its uncertainty (see Flags()).
  bool flagged = false;
  bool path_not_found = false;     // find_path and no path: the given line was used
  bool path_disagrees_with_hint = false;
  // Without a crack line: the path found does not resolve where the crack
  // runs (its standard error above half hint_tolerance_px, or too few
  // independent points for one) and no resolved path of the sequence
  // confirms it: a few points off the crack are a path in any direction.
  bool path_unresolved = false;
  // Crack band: some points the crack location read were not correlated
  // (three extensions of the band did not catch up with the path found).
  bool tip_beyond_band = false;
  // The length lies below an earlier frame's and a later frame's, which
  // agree with each other, by more than twice the uncertainties
  // (FlagLengthDrops): a crack does not heal.
  bool length_drop = false;
  CrackPathResult path;            // find_path only
  CrackLine line_used;             // the line the crack length is measured along
  // "tip_at_edge;methods_disagree;..." ("" = none; docs/DIC.md, Flags);
  // path_curved: the straight
  // path fits the crack points badly (the length along it may be off; see
  // path.polyline_x/y).
  std::string Flags() const;
  // Flags that put the length itself in doubt: every flag but
  // path_disagrees_with_line (the given line was off; the length is measured
  // along the path found). A doubtful length stays out of the monotone fit
  // and out of the R curve built from the frames.
  bool LengthDoubtful() const { return FlagsDoubtLength(Flags()); }
  double crack_length_m = 0;   // monotone in time
  double crack_length_raw_m = 0;  // this frame's own estimate
  double uncertainty_m = 0;
  CrackTipResult tip;
  CorrelationSummary correlation;
  double valid_fraction = 0;
  FrameJ j;  // status kNotRequested unless options.j_integral.enabled
  // The field's rigid rotation, taken out before locating (radians,
  // counter-clockwise; 0 below 1 - cos = 1e-7: WithoutRigidRotation).
  double rigid_rotation_rad = 0;
  // The frame whose path this frame's length is measured along (-1: its
  // own path, or the line given); `path` stays this frame's own.
  int path_from_frame = -1;
  DisplacementField field;  // only with keep_fields
};

struct CrackSequenceResult {
  std::vector<FrameResult> frames;  // frames[0] is the reference
  double wall_s = 0;
  double points_per_s = 0;  // IC-GN solves per second over the whole run
  std::size_t points = 0;   // grid points per frame
  double mean_correlated_points = 0;  // per deformed frame (the crack band, or every point)
  bool j_integral = false;  // frames carry J_ff and delta* (options.j_integral.enabled)
  // Exported fields (AnalyzeCrackFields): the fields' coordinate unit ("px",
  // "mm", ...), in which the *_px members are.
  std::string length_unit = "px";
  // The frame whose path is the sequence's (-1: none, or not sought), and
  // the frames whose fields did not fit kept_fields_mb.
  int sequence_path_frame = -1;
  std::size_t fields_not_kept = 0;
  std::string BriefReport() const;
};

// Tip and path settings that follow from the subset size and the grid step
// (band half width subset/2 + 1, side depth 2.5 steps, Williams radius
// max(60, 5 subsets), path resolution half a step + 1 px); sets
// correlation.subset_size and .step too.
void SetGridDefaults(int subset_px, int step_px, CrackSequenceOptions* options);

// Path options of a sequence: the hint from tip.line; without a line the
// path runs across the image (width x height px; 0: the field's extent).
CrackPathOptions PathOptionsFor(const CrackSequenceOptions& options, int width, int height);

// One frame's crack from its displacement field: the path (find_path), the
// tip along it (or along the given line), the raw length with its
// uncertainty and the flags. Fills r's path, tip, length and flag members.
void LocateCrackInField(const DisplacementField& field, const CrackSequenceOptions& options,
                        const CrackPathOptions& path_opt, FrameResult* r);

// r->j from the field when options.j_integral.enabled (kNoTip without a
// tip), along the line the length is measured on.
void MeasureFrameJ(const DisplacementField& field, const CrackSequenceOptions& options,
                   FrameResult* r);

// Sets length_drop (and flagged) on every frame k with a length not in doubt
// that lies below an earlier frame i's and a later frame j's (any frames
// with a length) by more than twice their uncertainties in quadrature,
// where j is not itself below i by that much: an isolated drop. (A frame
// read too long is no evidence against the frames after it: without a later
// frame as long as it, nothing is flagged.) Call before MakeMonotone.
void FlagLengthDrops(std::vector<FrameResult>* frames);

// crack_length_m of the frames with a length not in doubt: non-decreasing
// in time (weighted isotonic regression of their raw lengths). A frame whose
// length is in doubt (LengthDoubtful) keeps its raw length (it may lie below
// its predecessors) and its flags.
void MakeMonotone(std::vector<FrameResult>* frames);

// Tip and path settings for exported fields, in the field's unit: stations
// every point spacing, band half width `band` (points this close to the crack
// are ignored: smeared subsets), side depth 2.5 spacings, Williams radius
// max(10 band, 12 spacings), path resolution 1.5 spacings.
void SetFieldDefaults(double spacing, double band, CrackSequenceOptions* options);

// The settings of AnalyzeCrackFields that follow the fields: with
// `from_spacing`, SetFieldDefaults(the first file's point spacing, `band`
// or 1.5 spacings); then the Williams radius and the jump threshold's floor
// (also the path's smallest jump) where given.
struct FieldSettings {
  bool from_spacing = true;
  double band = 0;        // <= 0: 1.5 point spacings [field unit]
  double fit_radius = 0;  // > 0: Williams fit radius and sqrt window [field unit]
  // Floor of the jump threshold: a length ("0.001mm"), or for fields in px
  // also a pixel count ("0.5px"); empty: the options' own.
  std::string threshold;
};

// Crack length from exported displacement fields, one file per frame, read
// one at a time (fields are relative to the reference already, so every file
// is a frame). Lengths use options.scale_m_per_px as metres per field unit:
// for fields in a length unit it is overwritten from the file (all files must
// share it); for fields in px it must be given. The tip and path settings
// follow `settings` (FieldSettings); `used` (optional) receives the options
// as applied (scale in metres per field unit). Throws Error(kInput) naming
// the file.
CrackSequenceResult AnalyzeCrackFields(const std::vector<std::filesystem::path>& files,
                                       CrackSequenceOptions options,
                                       const FieldSettings& settings = {},
                                       CrackSequenceOptions* used = nullptr);

// What one frame's crack location reads, for the crack band: the path scan
// about `scan_line` (find_path with a line: |n| <= path search half width +
// gap + side depth, s over the line's extent +- half a station), the COD
// profile's side windows about `cod_line` (|n| <= band half width + side
// depth, s from -1.01 to L + 1.01 stations) and the Williams window about
// (window_x, window_y) (radius fit_radius_px + window_margin_px).
struct CrackBandReads {
  bool scan = false;
  CrackLine scan_line;
  bool cod = false;
  CrackLine cod_line;
  bool window = false;
  double window_x = 0, window_y = 0, window_margin_px = 0;
};

// The grid points in `reads` (1) and the others (0). Static exclusions (ROI,
// mask) stay with the Correlator.
std::vector<char> CrackBandPoints(const DisplacementField& grid, const CrackSequenceOptions& options,
                                  const CrackBandReads& reads);

// Throws Error(kInput) naming the file for unreadable images or a size
// mismatch, Error(kUsage) for invalid options, Error(kInput) for a crack
// line outside the image.
CrackSequenceResult AnalyzeCrackSequence(const std::vector<std::filesystem::path>& images,
                                         const CrackSequenceOptions& options);

}  // namespace bridgefit::dic
