// Experiment design: the reduced model over a grid of similar specimens.
#include "bridgefit/campaign/design.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <sstream>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/parallel/share_owned.hpp"

namespace bridgefit::campaign {

double SceneSize(const Scene& scene) {
  return scene.specimen.type == SpecimenType::kCT ? scene.specimen.width : scene.specimen.length;
}

Scene ScaledScene(const Scene& scene, double size) {
  Scene out = scene;
  const double f = size / SceneSize(scene);
  SpecimenSpec& s = out.specimen;
  s.notch *= f;
  s.height *= f;
  if (s.type == SpecimenType::kCT) s.width = size;  // B (thickness) stays
  else s.length = size;                              // b (width) stays
  if (out.run.max_crack_length) *out.run.max_crack_length *= f;
  out.Validate();
  return out;
}

std::vector<double> SizeGrid(double from, double to, double step, const std::string& field) {
  if (!(from > 0) || !(to >= from) || !(step > 0) || (to - from) / step > 1000)
    throw Error(ErrorKind::kUsage, "bad size range",
                {.field = field, .value = fmt::format("{:g} m to {:g} m by {:g} m", from, to, step),
                 .expected = "FROM:TO:STEP with 0 < FROM <= TO, STEP > 0, at most 1000 sizes, "
                             "e.g. 50mm:200mm:25mm"});
  std::vector<double> sizes;
  for (int i = 0; from + i * step <= to * (1 + 1e-9); ++i) sizes.push_back(from + i * step);
  return sizes;
}

bool DesignRequest::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!scene.fracture) return fail("the scene needs [fracture] (J_tip_c)");
  if (!scene.bridging) return fail("the scene needs [bridging] (the law to design for)");
  if (sizes.empty()) return fail("no sizes to try");
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    if (!(sizes[i] > 0)) return fail(fmt::format("size {} is not positive", sizes[i]));
    if (i > 0 && !(sizes[i] > sizes[i - 1])) return fail("sizes must be ascending");
  }
  if (!(resolution_fraction >= 0)) return fail("resolution_fraction must be >= 0");
  if (r_points < 3) return fail(fmt::format("r_points must be >= 3, got {}", r_points));
  if (points_past_onset < 1 || points_past_onset >= r_points)
    return fail("points_past_onset must be in 1 .. r_points - 1");
  return true;
}

namespace {

constexpr std::uint32_t kDesignMagic = 0x31444642;  // "BFD1": change it when the layout changes

// A size's scaled scene, before its run (every rank makes every one).
DesignSize PrepareSize(const DesignRequest& request, double size) {
  DesignSize d;
  d.size = size;
  d.scene = ScaledScene(request.scene, size);
  d.scene.run.max_crack_length.reset();  // the specimen's whole window, not the test's stop
  d.scene.run.grow = true;
  d.notch = d.scene.specimen.notch;
  return d;
}

// The reduced model's run of a prepared size, and what it says about J_B.
void RunSize(const DesignRequest& request, DesignSize& d) {
  models::ReducedOptions options;
  const double characteristic = d.scene.specimen.type == SpecimenType::kCT
                                    ? d.scene.specimen.width
                                    : d.scene.specimen.height;
  options.mesh.resolution = request.resolution_fraction * characteristic;
  const auto t0 = std::chrono::steady_clock::now();
  const SimulationResult run = models::SimulateReduced(d.scene, options);
  d.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  d.status = run.status;
  d.message = run.message;
  d.window_end = run.points.empty() ? d.notch : run.points.back().crack_length;
  d.reached = run.steady_state_reached && run.status == RunStatus::kOk;
  if (d.reached) {
    d.onset = run.steady_state_crack_length;
    const double step = (d.window_end - d.notch) / (request.r_points - 1);
    for (int i = 0; i < request.r_points; ++i)
      d.points_past += d.notch + i * step >= d.onset - 1e-12 * d.window_end;
    d.identifies = d.points_past >= request.points_past_onset;
  }
}

// What a run adds to a prepared size, as bytes between ranks.
template <class Io, class D>
void VisitRun(Io& io, D& d) {
  io.Field(d.window_end), io.Field(d.reached), io.Field(d.onset), io.Field(d.points_past);
  io.Field(d.identifies), io.Field(d.status), io.Field(d.message), io.Field(d.wall_s);
}

}  // namespace

std::vector<DesignResult> RunDesigns(const std::vector<DesignRequest>& requests,
                                     parallel::Communicator* ranks) {
  std::string why;
  for (const DesignRequest& request : requests)
    if (!request.IsValid(&why))
      throw Error(ErrorKind::kInput, why, {.file = request.scene.source, .field = "design"});
  // One list of independent runs: request r's size k is item r * sizes + k.
  std::vector<DesignResult> results(requests.size());
  std::vector<DesignSize*> items;
  for (std::size_t r = 0; r < requests.size(); ++r) {
    for (double size : requests[r].sizes) results[r].sizes.push_back(PrepareSize(requests[r], size));
    for (DesignSize& d : results[r].sizes) items.push_back(&d);
  }
  std::vector<std::size_t> request_of;
  for (std::size_t r = 0; r < requests.size(); ++r)
    request_of.insert(request_of.end(), requests[r].sizes.size(), r);
  const bool shared = ranks && ranks->size() > 1;
  for (std::size_t j = 0; j < items.size(); ++j)
    if (!shared || ranks->OwnerOf(j) == ranks->rank()) RunSize(requests[request_of[j]], *items[j]);
  if (shared)
    parallel::ShareOwned(
        *ranks, items.size(), kDesignMagic, "design runs",
        [&](std::size_t j, parallel::ByteWriter& out) { VisitRun(out, *items[j]); },
        [&](std::size_t j, parallel::ByteReader& in) { VisitRun(in, *items[j]); });
  for (DesignResult& result : results)
    for (std::size_t k = 0; k < result.sizes.size() && result.smallest < 0; ++k)
      if (result.sizes[k].identifies) result.smallest = static_cast<int>(k);
  return results;
}

DesignResult RunDesign(const DesignRequest& request) {
  return RunDesigns({request}, request.ranks).front();
}

int DesignResult::UnknownBelowSmallest() const {
  const int end = smallest >= 0 ? smallest : static_cast<int>(sizes.size());
  int unknown = 0;
  for (int i = 0; i < end; ++i) unknown += sizes[i].status != RunStatus::kOk;
  return unknown;
}

std::string DesignResult::Warning() const {
  const int unknown = UnknownBelowSmallest();
  if (unknown == 0) return "";
  return fmt::format(
      "the model could not run {} size(s) {} to the end of the window (status in the table): "
      "whether they identify J_B is unknown, so {}",
      unknown, smallest >= 0 ? "below the recommended one" : "on the grid",
      smallest >= 0 ? "the smallest size may be smaller"
                    : "try a finer --resolution-fraction or other sizes");
}

std::string DesignResult::BriefReport() const {
  std::ostringstream out;
  const bool ct = !sizes.empty() && sizes[0].scene.specimen.type == SpecimenType::kCT;
  out << fmt::format("  {:>10} {:>9} {:>12} {:>14} {:>11} {:>10}\n", ct ? "W [mm]" : "L [mm]",
                     "a0 [mm]", "window [mm]", "onset [mm]", "R points", "J_B");
  for (const DesignSize& d : sizes) {
    const std::string onset = d.reached ? fmt::format("{:.1f}", d.onset * 1e3) : "not reached";
    const std::string verdict = d.status != RunStatus::kOk ? RunStatusName(d.status)
                                : d.identifies              ? "identified"
                                                            : "bound only";
    out << fmt::format("  {:>10.1f} {:>9.1f} {:>12.1f} {:>14} {:>11} {:>10}\n", d.size * 1e3,
                       d.notch * 1e3, d.window_end * 1e3, onset,
                       d.reached ? fmt::format("{} past", d.points_past) : "-", verdict);
  }
  if (smallest >= 0)
    out << fmt::format("  smallest size that identifies J_B and delta_c: {} = {:.1f} mm\n",
                       ct ? "W" : "L", sizes[smallest].size * 1e3);
  else
    out << "  no size on this grid reaches steady state early enough: try larger sizes\n";
  if (const std::string w = Warning(); !w.empty()) out << "  warning: " << w << "\n";
  return out.str();
}

}  // namespace bridgefit::campaign
