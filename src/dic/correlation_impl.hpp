#pragma once
// Private: the state of a Correlator (current reference, per-point
// reference motion and cached reference data, last frame's results) and its
// stages. Pass (pass.cpp) correlates one frame; Next (correlation.cpp)
// wraps it with the reference update and the accumulation of motions.

#include <vector>

#include "bridgefit/dic/correlation.hpp"
#include "icgn.hpp"
#include "interpolation.hpp"

namespace bridgefit::dic {
namespace detail {

// Whether a subset of half size `half_size` (px) centred at (x, y)
// straddles the crack `line` from its start to `length_px` along it: the
// static crack band (CorrelationOptions::crack) and the crack located in a
// frame (Correlator::SetLocatedCrack) share this rule.
class SubsetAcrossCrack {
 public:
  SubsetAcrossCrack(const CrackLine& line, double length_px, int half_size);
  bool operator()(double x, double y) const;

 private:
  CrackLine line_;
  double length_ = 0, half_s_ = 0, half_n_ = 0;
};

// The data of a Correlator (what a pass reads and writes).
struct CorrelatorState {
  CorrelationOptions opt;
  DisplacementField grid;        // positions and static status
  std::vector<char> eligible;    // correlate this point
  std::vector<char> static_eligible;  // from the grid (ROI, mask, crack band)
  std::vector<char> active_set;  // SetActive's points (empty: all)
  int sample_stride = 1;         // the update test's lattice (update_sample_stride)
  std::vector<char> hidden;      // correlated for the update test only: reported masked
  std::vector<PointStatus> static_status;
  Image ref_image;               // current reference
  detail::InterpolatedImage ref_interp;
  detail::NodeMaps ref_nodes;    // first order: f and grad f at pixel nodes
  std::vector<detail::ReferenceSubset> ref_cache;  // per point, for the current reference
  int ref_index = 0;
  std::vector<Params> ref_p;     // point motion original -> current reference
  std::vector<char> ref_known;
  std::vector<char> ref_lost;    // failed in the current reference's frame: never filled
  // Subsets across the crack located in the frame last correlated
  // (SetLocatedCrack; empty: none known).
  std::vector<char> across_crack;
  bool AcrossCrack(size_t i) const { return !across_crack.empty() && across_crack[i]; }
  Image prev_image;
  int frame_index = 0;
  std::vector<Params> prev_total;  // last frame's total motion
  std::vector<char> prev_ok;
  std::vector<PointStatus> prev_status;
  // Why a point has no known position in the current reference (it failed
  // in that frame): reported for it from then on.
  std::vector<PointStatus> lost_status;
  int updates = 0;
  // The frame last correlated (Next), for Extend: its interpolant, the
  // guesses its pass started from, its point results and its cost so far.
  detail::InterpolatedImage frame_interp;
  std::vector<Params> frame_guess;
  std::vector<char> frame_has_guess;
  std::vector<PointResult> frame_res;
  std::size_t frame_solves = 0;
  double frame_wall_s = 0;
  int grid_width = 0, grid_height = 0;
  std::vector<detail::Workspace> workspaces;  // one per thread

  int Threads() const;
  bool OnLattice(size_t i, int stride) const {
    return static_cast<int>(i % grid.nx) % stride == 0 && static_cast<int>(i / grid.nx) % stride == 0;
  }
};

// One pass: every eligible point from `guess` (where given) or by
// wavefront propagation from converged neighbours and seeds (pass.cpp).
// Points with (*keep)[i] take (*prior)[i] as their result (solved already in
// this frame) and start fronts into the others.
std::vector<PointResult> RunPass(CorrelatorState& state, const Image& def_image,
                                 const InterpolatedImage& def_interp,
                                 const std::vector<Params>& guess,
                                 const std::vector<char>& has_guess, std::size_t* solves,
                                 const std::vector<PointResult>* prior = nullptr,
                                 const std::vector<char>* keep = nullptr);

}  // namespace detail

struct Correlator::Impl : detail::CorrelatorState {
  using Params = detail::Params;
  using PointResult = detail::PointResult;

  void BuildGrid(const Image& reference);
  // Makes `image` the reference: interpolant, node maps, empty per-point cache.
  void SetReference(const Image& image);

  std::vector<PointResult> Pass(const Image& def_image, const detail::InterpolatedImage& def_interp,
                                const std::vector<Params>& guess,
                                const std::vector<char>& has_guess, std::size_t* solves) {
    return detail::RunPass(*this, def_image, def_interp, guess, has_guess, solves);
  }
  void FillUnknown(std::vector<Params>& p, std::vector<char>& known) const;
  // At a reference update with an active set: the motion of every point not
  // correlated in the new reference's frame (outside the active set),
  // bilinear between the update test's lattice points around it, where all
  // four were correlated there.
  void FillFromLattice(std::vector<Params>& p, std::vector<char>& known) const;
  void SetActive(const std::vector<char>& active);
  void SetLocatedCrack(const CrackLine& line, double length_px);
  // eligible = static and (active or on the update test's lattice: stride 4
  // before the first frame, whose coarse pass runs on that lattice, then
  // sample_stride); hidden = eligible and not active.
  void ApplyActive();

  DisplacementField Next(const Image& frame, CorrelationSummary* summary);
  DisplacementField Extend(const std::vector<char>& active, CorrelationSummary* summary);
  // The frame's field from its point results (total motion = increment o
  // reference motion); keeps them as the next frame's guesses and fills the
  // summary's counts.
  DisplacementField Collect(const std::vector<PointResult>& res, CorrelationSummary* summary);
  static Params Accumulate(const Params& d, const Params& r);
  static Params Increment(const Params& t, const Params& r);
};

}  // namespace bridgefit::dic
