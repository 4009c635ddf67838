#include "bridgefit/dic/sequence.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <string_view>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/dic/fields.hpp"
#include "crack_band_impl.hpp"
#include "sequence_path_impl.hpp"

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
  if (!(kept_fields_mb >= 0)) {
    if (why) *why = "kept fields budget must be >= 0 MB";
    return false;
  }
  if (!has_line && !find_path) {
    if (why) *why = "without a crack line the path must be found from the data";
    return false;
  }
  CorrelationOptions c = correlation;
  c.has_crack = has_line && !find_path;
  c.crack = tip.line;
  CrackTipOptions t = tip;
  if (!has_line) t.line = {0, 0, 2, 0};  // placeholder: the found path replaces it
  CrackPathOptions p = path;
  p.has_hint = has_line;
  p.hint = tip.line;
  return c.IsValid(why) && t.IsValid(why) && (!find_path || p.IsValid(why)) &&
         j_integral.IsValid(why);
}

std::string FrameResult::Flags() const {
  std::string out;
  auto add = [&](bool on, const char* name) {
    if (!on) return;
    if (!out.empty()) out += ";";
    out += name;
  };
  add(path_not_found, "path_not_found");
  add(path_disagrees_with_hint, "path_disagrees_with_line");
  add(path_unresolved, "path_unresolved");
  add(path.found && path.curved, "path_curved");
  add(tip.tip_at_edge, "tip_at_edge");
  add(tip.opening_detached, "opening_detached");
  add(tip.methods_disagree, "methods_disagree");
  add(tip.williams_unstable, "williams_unstable");
  add(tip.williams_window_short, "williams_window_short");
  add(tip_beyond_band, "tip_beyond_band");
  add(length_drop, "length_drop");
  return out;
}

bool FlagsDoubtLength(const std::string& flags) {
  std::size_t begin = 0;
  while (begin < flags.size()) {
    std::size_t end = flags.find(';', begin);
    if (end == std::string::npos) end = flags.size();
    const std::string_view flag(flags.data() + begin, end - begin);
    if (!flag.empty() && flag != "path_disagrees_with_line") return true;
    begin = end + 1;
  }
  return false;
}

std::string CrackSequenceResult::BriefReport() const {
  size_t with_tip = 0;
  for (const FrameResult& f : frames) with_tip += f.has_length ? 1 : 0;
  const std::string correlated =
      mean_correlated_points > 0
          ? fmt::format(" ({:.0f} correlated on average)", mean_correlated_points)
          : "";
  size_t along = 0;
  for (const FrameResult& f : frames) along += f.path_from_frame >= 0 ? 1 : 0;
  std::string path;
  if (along > 0)
    path = fmt::format("; {} frame(s) located along frame {}'s path (their own not resolved)", along,
                       sequence_path_frame);
  if (fields_not_kept > 0)
    path += fmt::format("; {} frame(s) kept their own reading (beyond the kept fields' budget)",
                        fields_not_kept);
  return fmt::format("{} frames, {} with a crack tip, {} grid points per frame{}, {:.2f} s, {:.0f} points/s{}",
                     frames.size(), with_tip, points, correlated, wall_s, points_per_s, path);
}

void SetGridDefaults(int subset_px, int step_px, CrackSequenceOptions* o) {
  o->correlation.subset_size = subset_px;
  o->correlation.step = step_px;
  o->tip.station_spacing_px = step_px;
  o->tip.band_half_width_px = subset_px / 2 + 1;
  o->tip.side_depth_px = 2.5 * step_px;
  o->tip.fit_radius_px = std::max(60.0, 5.0 * subset_px);
  o->tip.sqrt_window_px = o->tip.fit_radius_px;
  o->path.station_spacing_px = step_px;
  o->path.gap_px = o->tip.band_half_width_px;
  o->path.side_depth_px = std::max(o->tip.side_depth_px, 3.0 * step_px);
  // Where straddling subsets fail, the path is resolved to half a grid step.
  o->path.hint_tolerance_px = std::max(2.0, 0.5 * step_px + 1.0);
  o->path.curved_rms_px = o->path.hint_tolerance_px;
  o->path.error_correlation_px = subset_px;  // overlapping subsets share speckle
  o->tip.noise_correlation_px = subset_px;
}

void SetFieldDefaults(double spacing, double band, CrackSequenceOptions* o) {
  o->tip.station_spacing_px = spacing;
  o->tip.band_half_width_px = band;
  o->tip.side_depth_px = 2.5 * spacing;
  o->tip.fit_radius_px = std::max(10.0 * band, 12.0 * spacing);
  o->tip.sqrt_window_px = o->tip.fit_radius_px;
  o->path.station_spacing_px = spacing;
  o->path.gap_px = band;
  o->path.side_depth_px = 3.0 * spacing;
  o->path.hint_tolerance_px = 1.5 * spacing;
  o->path.curved_rms_px = 1.5 * spacing;
  o->path.error_correlation_px = 2 * band;  // band: half the subset of a DIC export
  o->tip.noise_correlation_px = 2 * band;
  o->path.search_half_width_px = std::max(o->path.search_half_width_px, 8.0 * spacing);
}

namespace {

// The first file's settings: its point spacing, the Williams radius and
// the jump threshold in the fields' unit.
void ApplyFieldSettings(const FieldFile& file, const std::string& name,
                        const FieldSettings& settings, CrackSequenceOptions* options) {
  if (settings.from_spacing) {
    const double spacing = FieldSpacing(file.field);
    BF_CHECK_INPUT(spacing > 0, "cannot tell the point spacing (fewer than two valid points)",
                   {.file = name});
    SetFieldDefaults(spacing, settings.band > 0 ? settings.band : 1.5 * spacing, options);
    // Scattered points: a station's window holds fewer of them than a
    // lattice's 3 x 3 (jittered by 0.2 step, 2-5 a side where 4 are
    // needed): one more spacing of depth.
    if (file.field.ny <= 1) options->tip.side_depth_px += spacing;
  }
  if (settings.fit_radius > 0)
    options->tip.fit_radius_px = options->tip.sqrt_window_px = settings.fit_radius;
  if (settings.threshold.empty()) return;
  try {
    options->tip.threshold_floor_px =
        ParseQuantity(settings.threshold, Dimension::Length()) / options->scale_m_per_px;
  } catch (const Error&) {
    if (!file.IsPixels()) throw;
    options->tip.threshold_floor_px = ParseQuantity(settings.threshold, Dimension::Pixel());
  }
  options->path.min_jump_px = options->tip.threshold_floor_px;
}

}  // namespace

CrackSequenceResult AnalyzeCrackFields(const std::vector<std::filesystem::path>& files,
                                       CrackSequenceOptions options,
                                       const FieldSettings& settings,
                                       CrackSequenceOptions* used) {
  if (files.empty()) throw Error(ErrorKind::kInput, "no field files given");
  Stopwatch watch;
  CrackSequenceResult out;
  out.j_integral = options.j_integral.enabled;
  // An Ncorr MAT file holds many frames: the count shown is of files.
  Progress progress("crack", files.size(), options.show_progress);
  CrackPathOptions path_opt;
  std::string unit, first_name;
  FieldFrames frames(files);
  FieldFile file;
  std::string name;
  detail::KeptFields kept(options.kept_fields_mb);
  for (size_t k = 0; frames.Next(&file, &name); ++k) {
    if (k == 0) {
      unit = file.unit;
      first_name = name;
      if (!file.IsPixels()) options.scale_m_per_px = file.m_per_unit;
      if (!(options.scale_m_per_px > 0))
        throw Error(ErrorKind::kUsage, "the fields are in px: a scale is needed",
                    {.file = name, .field = "--scale", .expected = "e.g. '0.05mm/px'"});
      ApplyFieldSettings(file, name, settings, &options);
      std::string why;
      if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid crack options: " + why);
      path_opt = PathOptionsFor(options, 0, 0);
      out.points = file.field.size();
    } else if (file.unit != unit) {
      throw Error(ErrorKind::kInput, "field unit differs from the first file's",
                  {.file = name, .field = "unit", .value = file.unit,
                   .expected = unit + " (as in " + first_name + ")"});
    }
    FrameResult r;
    r.image = name;
    try {
      LocateCrackInField(file.field, options, path_opt, &r);
      MeasureFrameJ(file.field, options, &r);
    } catch (const Error& e) {
      throw e.WithContext({.file = name});
    }
    if (options.find_path && options.sequence_path) kept.Offer(k, file.field, r, path_opt);
    if (options.keep_fields) r.field = std::move(file.field);
    out.frames.push_back(std::move(r));
    progress.Update(std::min(k + 1, files.size()));
  }
  progress.Finish();
  // Every point of a file was read: none lacking.
  detail::ApplySequencePath(
      kept, options, path_opt, [](const DisplacementField&, const FrameResult&) { return false; },
      &out);
  FlagLengthDrops(&out.frames);
  MakeMonotone(&out.frames);
  out.length_unit = unit;
  if (used) *used = options;
  out.wall_s = watch.Seconds();
  return out;
}

CrackPathOptions PathOptionsFor(const CrackSequenceOptions& options, int width, int height) {
  CrackPathOptions p = options.path;
  p.has_hint = options.has_line;
  p.hint = options.tip.line;
  if (!p.has_hint && width > 0 && height > 0) {
    p.bounds_x0 = p.bounds_y0 = 0;
    p.bounds_x1 = width - 1;
    p.bounds_y1 = height - 1;
  }
  return p;
}

void LocateCrackInField(const DisplacementField& given, const CrackSequenceOptions& options,
                        const CrackPathOptions& path_opt, FrameResult* r) {
  // The path, the openings and the tip fit read the field less its rigid
  // rotation (fields.hpp, WithoutRigidRotation).
  const DisplacementField field = WithoutRigidRotation(given, &r->rigid_rotation_rad);
  CrackTipOptions tip_opt = options.tip;
  bool have_line = options.has_line;
  if (options.find_path) {
    r->path = FindCrackPath(field, path_opt);
    if (r->path.found) {
      tip_opt.line = r->path.line;
      have_line = true;
      r->path_disagrees_with_hint = r->path.disagrees_with_hint;
      r->path_unresolved = !path_opt.has_hint && !detail::PathResolved(r->path, path_opt);
    } else {
      r->path_not_found = true;
    }
  }
  r->line_used = tip_opt.line;
  r->valid_fraction = field.ValidFraction();
  if (have_line) r->tip = LocateCrackTip(field, tip_opt, options.method);
  if (r->tip.tip.found) {
    r->has_length = true;
    r->crack_length_raw_m = r->tip.tip.s_px * options.scale_m_per_px + options.offset_m;
    // At least the grid resolution: one station / sqrt(12).
    const double sigma_px =
        std::max(r->tip.tip.uncertainty_px, options.tip.station_spacing_px / std::sqrt(12.0));
    r->uncertainty_m = sigma_px * options.scale_m_per_px;
  }
  r->flagged = !r->Flags().empty();
}

void MeasureFrameJ(const DisplacementField& field, const CrackSequenceOptions& options,
                   FrameResult* r) {
  if (!options.j_integral.enabled) return;
  if (!r->tip.tip.found) {
    r->j.status = FrameJStatus::kNoTip;
    r->j.why = "no crack tip in this frame";
    return;
  }
  const CrackLine& L = r->line_used;
  // A scattered field (an export off a lattice: an Aramis 3D nodemap) is
  // resampled onto one at its point spacing first.
  const bool scattered = field.ny <= 1;
  const DisplacementField resampled =
      scattered ? ResampleOntoGrid(field, FieldSpacing(field)) : DisplacementField{};
  r->j = ComputeFrameJ(scattered ? resampled : field, r->tip.tip.x_px, r->tip.tip.y_px,
                       r->tip.tip.s_px, L.x1 - L.x0, L.y1 - L.y0, options.tip.band_half_width_px,
                       options.scale_m_per_px, options.offset_m, options.j_integral,
                       r->uncertainty_m / options.scale_m_per_px);
  r->j.resampled = scattered && resampled.nx >= 3;
}

void FlagLengthDrops(std::vector<FrameResult>* frames) {
  std::vector<FrameResult>& f = *frames;
  auto below = [&](size_t hi, size_t lo) {  // lo's length below hi's beyond 2 sigma
    return f[hi].crack_length_raw_m - f[lo].crack_length_raw_m >
           2 * std::hypot(f[hi].uncertainty_m, f[lo].uncertainty_m);
  };
  std::vector<size_t> drops;
  for (size_t k = 0; k < f.size(); ++k) {
    if (!f[k].has_length || f[k].LengthDoubtful()) continue;
    bool drop = false;
    // Evidence: any frame with a length, in doubt or not (a frame read too
    // long before k is answered by the later frame that must match it).
    for (size_t i = 0; i < k && !drop; ++i) {
      if (!f[i].has_length || !below(i, k)) continue;
      for (size_t j = k + 1; j < f.size() && !drop; ++j)
        drop = f[j].has_length && below(j, k) && !below(i, j);
    }
    if (drop) drops.push_back(k);
  }
  for (size_t k : drops) {
    f[k].length_drop = true;
    f[k].flagged = true;
  }
}

void MakeMonotone(std::vector<FrameResult>* frames) {
  std::vector<double> values, sigmas;
  std::vector<char> valid;
  for (const FrameResult& f : *frames) {
    values.push_back(f.crack_length_raw_m);
    sigmas.push_back(f.uncertainty_m);
    // A doubtful length may be wrong by more than its uncertainty: pooled
    // with its neighbours it would move their lengths with it.
    valid.push_back(f.has_length && !f.LengthDoubtful() ? 1 : 0);
  }
  const std::vector<double> mono = MonotoneNonDecreasing(values, sigmas, valid);
  for (size_t k = 0; k < frames->size(); ++k)
    if ((*frames)[k].has_length) (*frames)[k].crack_length_m = mono[k];
}

CrackSequenceResult AnalyzeCrackSequence(const std::vector<std::filesystem::path>& images,
                                         const CrackSequenceOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid DIC options: " + why);
  if (images.empty()) throw Error(ErrorKind::kInput, "no images given");
  Stopwatch watch;
  CorrelationOptions copt = options.correlation;
  // With the path found from the data there is no crack band: subsets across
  // the crack smear or fail, and both the path search and the tip methods
  // skip the points within the band half width of the crack.
  copt.has_crack = options.has_line && !options.find_path;
  copt.crack = options.tip.line;
  const Image reference = ReadImage(images[0]);
  if (options.has_line) {
    const CrackLine& l = options.tip.line;
    auto inside = [&](double x, double y) {
      return x >= 0 && y >= 0 && x <= reference.width - 1 && y <= reference.height - 1;
    };
    if (!inside(l.x0, l.y0) || !inside(l.x1, l.y1))
      throw Error(ErrorKind::kInput, "crack line leaves the image",
                  {.file = images[0].string(), .field = "--crack-line",
                   .value = fmt::format("{},{},{},{}", l.x0, l.y0, l.x1, l.y1),
                   .expected = fmt::format("end points within 0..{} x 0..{} px", reference.width - 1,
                                           reference.height - 1)});
  }
  const CrackPathOptions path_opt = PathOptionsFor(options, reference.width, reference.height);
  std::unique_ptr<Correlator> correlator;
  try {
    correlator = std::make_unique<Correlator>(copt, reference);
  } catch (const Error& e) {
    throw e.WithContext({.file = images[0].string()});
  }
  CrackSequenceResult out;
  out.j_integral = options.j_integral.enabled;
  out.points = correlator->Grid().size();
  FrameResult first;
  first.image = images[0].string();
  first.valid_fraction = 1.0;
  if (options.j_integral.enabled) {
    first.j.status = FrameJStatus::kNoTip;
    first.j.why = "reference frame";
  }
  if (options.keep_fields) first.field = correlator->Grid();
  out.frames.push_back(std::move(first));
  Progress progress("dic", images.size() - 1, options.show_progress);
  double solve_seconds = 0, solves = 0, correlated = 0;
  detail::BandTracker band(options, path_opt, correlator.get());
  detail::KeptFields kept(options.kept_fields_mb);
  for (size_t k = 1; k < images.size(); ++k) {
    const Image frame = ReadImage(images[k]);
    if (frame.width != reference.width || frame.height != reference.height)
      throw Error(ErrorKind::kInput,
                  fmt::format("image size {}x{} differs from the reference {}x{} ({})", frame.width,
                              frame.height, reference.width, reference.height, images[0].string()),
                  {.file = images[k].string(), .expected = "all images with the same size"});
    FrameResult r;
    r.image = images[k].string();
    band.Prepare();
    DisplacementField field = correlator->Next(frame, &r.correlation);
    LocateCrackInField(field, options, path_opt, &r);
    band.Complete(&field, &r);  // the points the location read and the band lacked
    // The crack as located here: its subsets leave the update test and are
    // lost if this frame becomes the reference (Correlator::SetLocatedCrack).
    // Only a path resolved to its resolution locates the crack: the band of
    // a line off the crack (the line given where no path was found, or a
    // path found on a few scattered points) would be lost at an update, and
    // the next frames' paths found mid-gap of it (aldic, lines 18 px apart).
    if (r.tip.tip.found && (!options.find_path || detail::PathResolved(r.path, path_opt)))
      correlator->SetLocatedCrack(r.line_used, r.tip.tip.s_px);
    solve_seconds += r.correlation.wall_s;
    solves += static_cast<double>(r.correlation.solves);
    correlated += static_cast<double>(r.correlation.points);
    MeasureFrameJ(field, options, &r);
    if (options.find_path && options.sequence_path) kept.Offer(k, field, r, path_opt);
    if (options.keep_fields) r.field = std::move(field);
    out.frames.push_back(std::move(r));
    progress.Update(k);
  }
  progress.Finish();
  detail::ApplySequencePath(
      kept, options, path_opt,
      [&band](const DisplacementField& f, const FrameResult& r) { return band.Lacks(f, r); }, &out);
  FlagLengthDrops(&out.frames);
  MakeMonotone(&out.frames);
  out.wall_s = watch.Seconds();
  out.points_per_s = solve_seconds > 0 ? solves / solve_seconds : 0;
  out.mean_correlated_points = images.size() > 1 ? correlated / (images.size() - 1) : 0;
  return out;
}

}  // namespace bridgefit::dic
