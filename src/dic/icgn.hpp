#pragma once
// Private: inverse-compositional Gauss-Newton (IC-GN) on one subset, ZNSSD
// criterion (Pan et al. 2013), as named stages:
//   reference:     f, grad f, H = sum J J^T, sum f~ J   (once per point and reference)
//   interpolation: g(W(xi; p)) on the deformed image    (every iteration)
//   residual:      b = sum (f~ - |f~|/|g~| g~) J         (every iteration)
//   update:        dp = -H^-1 b, W(p) <- W(p) o W(dp)^-1, |dp| test
// with J = grad f . dW/dp. First-order subsets read f and grad f from the
// reference's node maps (integer centres) and keep H^-1 per point across
// iterations, retries and frames; second-order subsets build their data
// per solve.

#include <array>
#include <chrono>
#include <vector>

#include <Eigen/Dense>

#include "bridgefit/dic/correlation.hpp"
#include "interpolation.hpp"

namespace bridgefit::dic::detail {

constexpr int kNp = 12;  // parameters stored per point (second order; first order leaves 6 at 0)
// Parameter layout: u ux uy uxx uxy uyy | v vx vy vxx vxy vyy
using Params = std::array<double, kNp>;

struct PointResult {
  Params p{};
  double zncc = 0;
  int iterations = 0;
  PointStatus status = PointStatus::kUnreached;
};

// Seconds spent per stage (per thread, summed after a parallel loop).
struct StageTimes {
  double search = 0, reference = 0, interpolation = 0, residual = 0, update = 0;
  StageTimes& operator+=(const StageTimes& o) {
    search += o.search;
    reference += o.reference;
    interpolation += o.interpolation;
    residual += o.residual;
    update += o.update;
    return *this;
  }
};

// Accumulates the time since the last Lap into one stage (steady clock: a
// vDSO read of some 20 ns, where a thread CPU clock is a system call that
// would dominate the cheap stages); inert unless on.
class StageClock {
 public:
  explicit StageClock(bool on) : on_(on) {
    if (on_) last_ = Seconds();
  }
  void Lap(double* stage) {
    if (!on_) return;
    const double now = Seconds();
    *stage += now - last_;
    last_ = now;
  }
  static double Seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }

 private:
  bool on_;
  double last_ = 0;
};

// First-order reference data of one point, kept while the reference stays.
struct ReferenceSubset {
  bool ready = false;     // computed for the current reference
  bool textured = false;  // |f~| and H usable
  double fmean = 0, fnorm = 0;
  Eigen::Matrix<double, 6, 6> Hinv;
  Eigen::Matrix<double, 6, 1> fJ;  // sum f~ J
};

// Per-thread buffers (sized once, reused for every point).
struct Workspace {
  std::vector<float> f, fx, fy, g, J;
  StageTimes times;
};

// The reference image as IC-GN reads it.
struct ReferenceView {
  const InterpolatedImage* image = nullptr;
  const NodeMaps* nodes = nullptr;  // values and gradients at pixel nodes
};

// IC-GN at the reference point (xc, yc) (may be fractional) from p0.
// `cache` (first order only, may be null) holds the point's reference data.
PointResult SolveIcgn(const ReferenceView& ref, const InterpolatedImage& def, double xc, double yc,
                      const Params& p0, const CorrelationOptions& opt, ReferenceSubset* cache,
                      Workspace& ws, bool profile);

}  // namespace bridgefit::dic::detail
