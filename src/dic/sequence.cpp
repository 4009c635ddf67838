#include "bridgefit/dic/sequence.hpp"

#include <cmath>
#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"

namespace bridgefit::dic {

bool CrackSequenceOptions::IsValid(std::string* why) const {
  if (!(scale_m_per_px > 0) || !std::isfinite(scale_m_per_px)) {
    if (why) *why = "scale must be a positive length per pixel";
    return false;
  }
  if (!std::isfinite(offset_m)) {
    if (why) *why = "offset must be finite";
    return false;
  }
  CorrelationOptions c = correlation;
  c.has_crack = true;
  c.crack = tip.line;
  return c.IsValid(why) && tip.IsValid(why);
}

std::string CrackSequenceResult::BriefReport() const {
  size_t with_tip = 0;
  for (const FrameResult& f : frames) with_tip += f.has_length ? 1 : 0;
  return fmt::format("{} frames, {} with a crack tip, {} points per frame, {:.2f} s, {:.0f} points/s",
                     frames.size(), with_tip, points, wall_s, points_per_s);
}

CrackSequenceResult AnalyzeCrackSequence(const std::vector<std::filesystem::path>& images,
                                         const CrackSequenceOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid DIC options: " + why);
  if (images.empty()) throw Error(ErrorKind::kInput, "no images given");
  Stopwatch watch;
  CorrelationOptions copt = options.correlation;
  copt.has_crack = true;
  copt.crack = options.tip.line;
  const Image reference = ReadImage(images[0]);
  std::unique_ptr<Correlator> correlator;
  try {
    correlator = std::make_unique<Correlator>(copt, reference);
  } catch (const Error& e) {
    throw e.WithContext({.file = images[0].string()});
  }
  CrackSequenceResult out;
  out.points = correlator->Grid().size();
  FrameResult first;
  first.image = images[0].string();
  first.valid_fraction = 1.0;
  if (options.keep_fields) first.field = correlator->Grid();
  out.frames.push_back(std::move(first));
  Progress progress("dic", images.size() - 1, options.show_progress);
  double solve_seconds = 0, solves = 0;
  for (size_t k = 1; k < images.size(); ++k) {
    const Image frame = ReadImage(images[k]);
    if (frame.width != reference.width || frame.height != reference.height)
      throw Error(ErrorKind::kInput,
                  fmt::format("image size {}x{} differs from the reference {}x{} ({})", frame.width,
                              frame.height, reference.width, reference.height, images[0].string()),
                  {.file = images[k].string(), .expected = "all images with the same size"});
    FrameResult r;
    r.image = images[k].string();
    DisplacementField field = correlator->Next(frame, &r.correlation);
    solve_seconds += r.correlation.wall_s;
    solves += r.correlation.points_per_s * r.correlation.wall_s;
    r.valid_fraction = field.ValidFraction();
    r.tip = LocateCrackTip(field, options.tip, options.method);
    if (r.tip.tip.found) {
      r.has_length = true;
      r.crack_length_raw_m = r.tip.tip.s_px * options.scale_m_per_px + options.offset_m;
      // At least the grid resolution: one station / sqrt(12).
      const double sigma_px =
          std::max(r.tip.tip.uncertainty_px, options.tip.station_spacing_px / std::sqrt(12.0));
      r.uncertainty_m = sigma_px * options.scale_m_per_px;
    }
    if (options.keep_fields) r.field = std::move(field);
    out.frames.push_back(std::move(r));
    progress.Update(k);
  }
  progress.Finish();
  std::vector<double> values, sigmas;
  std::vector<char> valid;
  for (const FrameResult& f : out.frames) {
    values.push_back(f.crack_length_raw_m);
    sigmas.push_back(f.uncertainty_m);
    valid.push_back(f.has_length ? 1 : 0);
  }
  const std::vector<double> mono = MonotoneNonDecreasing(values, sigmas, valid);
  for (size_t k = 0; k < out.frames.size(); ++k)
    if (out.frames[k].has_length) out.frames[k].crack_length_m = mono[k];
  out.wall_s = watch.Seconds();
  out.points_per_s = solve_seconds > 0 ? solves / solve_seconds : 0;
  return out;
}

}  // namespace bridgefit::dic
