#pragma once
// Subset digital image correlation (DIC) on a regular grid of points.
//
// Per point: integer initial guess by normalized cross-correlation (NCC) in a
// search window, then sub-pixel refinement by inverse-compositional
// Gauss-Newton (IC-GN, ZNSSD criterion) with a first- or second-order subset
// shape function and cubic B-spline (prefiltered coefficients) or Keys
// bicubic interpolation. Points start from a converged neighbour (wavefront
// propagation from seeds, best-ZNCC neighbour first), or from the previous
// frame along a sequence. A crack band (subsets straddling the crack line) is
// excluded, so nothing is propagated or smoothed across the crack.
//
//   CorrelationOptions options;  options.subset_size = 31;  options.step = 5;
//   Correlator correlator(options, reference);
//   DisplacementField field = correlator.Next(frame);

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bridgefit/dic/image.hpp"

namespace bridgefit::dic {

enum class ShapeFunction { kFirstOrder, kSecondOrder };
enum class Interpolation { kBSpline3, kBicubicKeys };

// Per-point outcome (never a sentinel value in u or v).
enum class PointStatus : std::uint8_t {
  kOk = 0,          // converged, ZNCC above the threshold
  kMasked,          // outside the region of interest or mask
  kCrackBand,       // subset straddles the crack line: not correlated
  kOutOfImage,      // subset (reference or deformed) leaves the image
  kNoConvergence,   // IC-GN did not converge within max_iterations
  kLowCorrelation,  // converged but ZNCC below min_zncc
  kUnreached,       // no converged neighbour and no seed found
};
const char* PointStatusName(PointStatus status);

// A straight crack line in reference-image pixels, from (x0, y0) (the notch
// side) towards (x1, y1).
struct CrackLine {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double Length() const;
  // Along-line coordinate s (from (x0,y0)) and signed normal distance n
  // (positive on the left of the direction of travel in image axes).
  void ToLocal(double x, double y, double* s, double* n) const;
  void FromLocal(double s, double n, double* x, double* y) const;
};

struct CorrelationOptions {
  int subset_size = 31;  // odd, pixels
  int step = 5;          // grid spacing, pixels
  ShapeFunction shape = ShapeFunction::kFirstOrder;
  Interpolation interpolation = Interpolation::kBSpline3;
  int max_iterations = 40;
  double convergence_px = 1e-3;  // |dp| with gradients scaled by the subset half-size
  double min_zncc = 0.8;
  int seed_search_radius = 40;   // px, NCC search around the seed guess
  int local_search_radius = 8;   // px, NCC retry when a neighbour's guess fails
  int max_seed_attempts = 40;
  // Region of interest [roi_x0, roi_x1) x [roi_y0, roi_y1) in pixels; a
  // negative bound means the image edge.
  int roi_x0 = -1, roi_y0 = -1, roi_x1 = -1, roi_y1 = -1;
  // Optional mask (same size as the reference; > 0 means use). A subset is
  // used only when its centre pixel is inside the mask.
  Image mask;
  // Crack band: subsets that intersect this line are excluded.
  bool has_crack = false;
  CrackLine crack;
  // Sequences: change the reference to the previous frame when the valid
  // fraction or the mean ZNCC drops below these (incremental mode). Points
  // lost at an update (failed in the new reference's frame: across an
  // open crack) stay lost and leave the fraction.
  bool incremental = true;
  double update_min_valid_fraction = 0.9;
  double update_min_mean_zncc = 0.9;
  // The update test reads the grid points on a lattice of this stride (every
  // k-th point in x and y; 0: the largest stride leaving >= 256 points, a
  // multiple of 4 from 4 on). With an active set (Correlator::SetActive)
  // those points are correlated too, so the test - and with it the
  // reference of every frame - is the same whatever the active set; they are
  // reported kMasked unless active.
  int update_sample_stride = 0;
  int threads = 0;  // OpenMP threads, 0 = default
  // Time the stages of every solve into CorrelationSummary::stages (costs a
  // clock read per stage; off for production runs).
  bool profile_stages = false;

  bool IsValid(std::string* why) const;
};

// Displacements of material points given by their reference coordinates
// (x, y), on an nx by ny grid (index = iy * nx + ix). SoA, pixels.
struct DisplacementField {
  int nx = 0, ny = 0;
  std::vector<double> x, y;                   // reference positions, px
  std::vector<double> u, v;                   // displacement, px
  std::vector<double> dudx, dudy, dvdx, dvdy; // displacement gradient
  std::vector<double> zncc;
  std::vector<int> iterations;
  std::vector<PointStatus> status;

  std::size_t size() const { return x.size(); }
  bool ok(std::size_t i) const { return status[i] == PointStatus::kOk; }
  // Valid points over points that were meant to be correlated (excludes
  // masked and crack-band points).
  double ValidFraction() const;
  double MeanZncc() const;  // over valid points
};

struct CorrelationSummary {
  int frame = 0;            // index of the frame in the sequence (0 = reference)
  int reference_frame = 0;  // frame used as reference for the last pass
  int reference_updates = 0;
  std::size_t points = 0;   // correlated (not masked, not crack band)
  std::size_t valid = 0;
  double mean_zncc = 0;
  double mean_iterations = 0;
  double wall_s = 0;
  double points_per_s = 0;  // IC-GN point solves per second of wall time
  std::size_t solves = 0;   // IC-GN solves (a point may need a retry from an NCC guess)
  // Seconds per stage of the last frame, summed over threads (filled
  // with CorrelationOptions::profile_stages): setup (interpolant of the frame),
  // NCC search, reference subsets (f, grad f, Hessian), interpolation of the
  // deformed subsets, residual and gradient, update (solve, warp
  // composition, convergence test), propagation (the rest: guesses, fronts,
  // seeds, bookkeeping; meaningful on one thread).
  struct StageSeconds {
    double setup = 0, search = 0, reference = 0, interpolation = 0, residual = 0, update = 0,
           propagation = 0;
  } stages;
  std::string BriefReport() const;
};

class Correlator {
 public:
  // Throws Error(kUsage) when options are invalid, Error(kInput) when the
  // reference and the mask disagree in size or the crack line leaves the image.
  Correlator(const CorrelationOptions& options, const Image& reference);
  ~Correlator();
  Correlator(const Correlator&) = delete;
  Correlator& operator=(const Correlator&) = delete;

  // The grid of reference points and their static status (masked, crack band).
  const DisplacementField& Grid() const;
  // Correlates the next frame of the sequence; displacements are always
  // relative to the original reference (accumulated through intermediate
  // references in incremental mode). Throws Error(kInput) when the frame's
  // size differs from the reference.
  DisplacementField Next(const Image& frame, CorrelationSummary* summary = nullptr);
  // Restricts the following frames to the grid points with active[i] != 0
  // (size Grid().size(); empty: every point); the others are reported
  // kMasked and cost nothing. A point that comes back after a reference
  // update takes its position in the current reference from its known
  // neighbours. Throws Error(kUsage) on a size mismatch.
  void SetActive(const std::vector<char>& active);
  // Adds the points of `active` to the frame last correlated by Next (the
  // points correlated already keep their results): they are correlated in
  // that frame against its reference, from the guesses its pass had and from
  // their solved neighbours. Returns the frame's whole field; `summary` (that
  // of Next, or null) is updated to the frame's totals. The following frames
  // keep the union as their active set. Throws Error(kUsage) before the
  // first frame or on a size mismatch.
  DisplacementField Extend(const std::vector<char>& active, CorrelationSummary* summary = nullptr);
  // The crack as located in the frame last correlated (it holds until the
  // next call: the sequence calls it for every frame whose tip it finds):
  // along `line` from its start to `length_px` (the tip). Subsets across it
  // (the crack band's rule) leave the reference-update test (a crack is not
  // decorrelation), and at an update they are lost like failed points: in
  // the new reference their subset holds the open gap, which does not move
  // with the material, and its increments read it (measured: 0.3-0.5 px off
  // on a bridged crack opened 0.7 px, the crack path found 2-7 px off).
  // length_px <= 0 clears it. Throws Error(kUsage) for a line shorter than
  // 1 px.
  void SetLocatedCrack(const CrackLine& line, double length_px);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One pair, no sequence state.
DisplacementField CorrelatePair(const Image& reference, const Image& deformed,
                                const CorrelationOptions& options,
                                CorrelationSummary* summary = nullptr);

}  // namespace bridgefit::dic
