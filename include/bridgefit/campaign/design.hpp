#pragma once
// Experiment design (issue 19): for a material and law (from a scene; later
// from a fit), which specimen size would reach steady state early enough for
// a fit to identify J_B and delta_c? Geometrically similar specimens of the
// scene's shape are run by the reduced model over a size grid.
//
//   CT:  size = W; height, notch a0 (and a0/W, H/W) scale with it; B fixed.
//   DCB: size = L; arm height h and notch a0 scale with it; width b fixed.
//
// A size identifies J_B when steady state begins inside its growth window
// with at least `points_past_onset` R points past the onset, for R points
// evenly spaced over the window (`r_points` of them): the fit's own rule
// (inverse::FitBridgingLaw needs 3 data points past the onset).
//
// Over the ranks of an MPI job (`mpirun -n N bridgefit design`, issue 20) the
// sizes' forward runs are dealt statically (run i on rank i mod N) and every
// rank receives every run's result bit for bit: the result does not depend
// on the number of ranks (docs/MPI.md).

#include <string>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/scene/scene.hpp"

namespace bridgefit::parallel {
class Communicator;
}

namespace bridgefit::campaign {

struct DesignRequest {
  Scene scene;  // needs [fracture] and [bridging]; its specimen is the shape scaled
  std::vector<double> sizes;  // [m], ascending: CT W, DCB L
  // Element size as a fraction of the characteristic size (CT W, DCB h);
  // 0: the reduced model's default (CT W/200, DCB h/4).
  double resolution_fraction = 0.0;
  int r_points = 20;          // R points over the growth window of a test
  int points_past_onset = 3;  // the fit's rule
  // Ranks of one job sharing the sizes' runs (collective: every rank makes
  // the same design at the same time). Null or one rank: this process alone.
  parallel::Communicator* ranks = nullptr;
  bool IsValid(std::string* why) const;
};

struct DesignSize {
  double size = 0.0;       // [m]
  Scene scene;             // the scaled scene that was run
  double notch = 0.0;      // a0 [m]
  double window_end = 0.0; // last crack length of the model's window [m]
  bool reached = false;    // steady state inside the window
  double onset = NAN;      // steady-state onset crack length [m], NaN when not reached
  int points_past = 0;     // R points of the test past the onset
  bool identifies = false; // points_past >= points_past_onset
  RunStatus status = RunStatus::kOk;
  std::string message;     // the model's, when it did not run to the end
  double wall_s = 0.0;
};

struct DesignResult {
  std::vector<DesignSize> sizes;
  int smallest = -1;  // index of the smallest identifying size; -1: none on the grid
  // Sizes below the smallest identifying one (all sizes when none identifies)
  // whose model run stopped early: for them the answer is unknown, so the
  // smallest size may be smaller than `smallest` says.
  int UnknownBelowSmallest() const;
  // Empty, or a sentence saying why the recommendation may be wrong.
  std::string Warning() const;
  std::string BriefReport() const;
};

// The scene scaled to `size` (see above); validated.
Scene ScaledScene(const Scene& scene, double size);
// The characteristic size of a scene: CT W, DCB L.
double SceneSize(const Scene& scene);

// from, from + step, ... up to `to` (inclusive within 1e-9 relative) [m];
// throws Error(kUsage) for a bad range (field names the option).
std::vector<double> SizeGrid(double from, double to, double step, const std::string& field);

DesignResult RunDesign(const DesignRequest& request);

// Several designs at once (a fit's bound law and its region): their runs
// (size x request) are one list of independent items, dealt over `ranks`
// (null: this process alone) as above; each request's own `ranks` is not
// used. Validates every request first (Error kInput).
std::vector<DesignResult> RunDesigns(const std::vector<DesignRequest>& requests,
                                     parallel::Communicator* ranks);

}  // namespace bridgefit::campaign
