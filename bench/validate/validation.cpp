// The validation campaign's draw, run and per-case check (validation.hpp).

#include "validation.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <cmath>
#include <random>

#include <unistd.h>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/input_limits.hpp"
#include "bridgefit/dic/sequence.hpp"
#include "bridgefit/dic/settings.hpp"
#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/pipeline/fit.hpp"
#include "bridgefit/pipeline/law_free.hpp"
#include "bridgefit/pipeline/synth.hpp"
#include "bridgefit/specimen/crack_plane.hpp"

namespace bridgefit::validate {
namespace {

// Uniform and log-uniform draws from one engine.
struct Draw {
  std::mt19937_64 rng;
  double Uniform(double low, double high) {
    return std::uniform_real_distribution<double>(low, high)(rng);
  }
  double LogUniform(double low, double high) {
    return std::exp(Uniform(std::log(low), std::log(high)));
  }
  bool Chance(double p) { return Uniform(0.0, 1.0) < p; }
  template <class T>
  T Pick(const std::vector<T>& items) {
    return items[std::uniform_int_distribution<std::size_t>(0, items.size() - 1)(rng)];
  }
};

// CT, W 50-100 mm (H = 1.2 W, B 10-20 mm, a0 0.3-0.4 W), stopped between
// 30% and 95% of the way from a0 to 0.9 W (the reduction's validity limit).
void DrawCt(Draw& d, Scene& s) {
  SpecimenSpec& sp = s.specimen;
  sp.type = SpecimenType::kCT;
  sp.width = d.Uniform(0.050, 0.100);
  sp.height = 1.2 * sp.width;
  sp.thickness = d.Uniform(0.010, 0.020);
  sp.notch = d.Uniform(0.30, 0.40) * sp.width;
  sp.plane = PlaneCondition::kPlaneStress;
  s.run.max_crack_length = sp.notch + d.Uniform(0.30, 0.95) * (0.9 * sp.width - sp.notch);
}

// DCB, arm h 5-12 mm, L 150-250 mm, b 20-25 mm, a0 40-60 mm, stopped
// between 30% and 95% of the way from a0 to L - 4 h.
void DrawDcb(Draw& d, Scene& s) {
  SpecimenSpec& sp = s.specimen;
  sp.type = SpecimenType::kDCB;
  sp.width = d.Uniform(0.020, 0.025);
  sp.height = d.Uniform(0.005, 0.012);
  sp.length = d.Uniform(0.150, 0.250);
  sp.notch = d.Uniform(0.040, 0.060);
  sp.plane = PlaneCondition::kPlaneStress;
  const double end = sp.length - 4.0 * sp.height;
  s.run.max_crack_length = sp.notch + d.Uniform(0.30, 0.95) * (end - sp.notch);
}

// Isotropic: MDF-like, E 2-4 GPa. Orthotropic: wood loaded across the grain
// with the crack along it (E1 along the crack 8-14 GPa, E2 0.5-1.2 GPa,
// G12 0.5-0.9 GPa, nu12 0.3-0.45).
void DrawMaterial(Draw& d, Scene& s) {
  MaterialSpec& m = s.material;
  m.density = d.Uniform(500.0, 800.0);
  m.orthotropic = d.Chance(0.35);
  if (!m.orthotropic) {
    m.E = d.Uniform(2e9, 4e9);
    m.nu = d.Uniform(0.2, 0.35);
    return;
  }
  m.E1 = d.Uniform(8e9, 14e9);
  m.E2 = d.Uniform(0.5e9, 1.2e9);
  m.G12 = d.Uniform(0.5e9, 0.9e9);
  m.nu12 = d.Uniform(0.30, 0.45);
}

// Law family with its default shape; sigma_c 0.3-3 MPa, J_B 100-1500 J/m^2,
// J_tip,c 300-3000 J/m^2 (log-uniform): bridging zones from a few mm to
// longer than the ligament, so some tests reach steady state and some stop
// before it.
void DrawLaw(Draw& d, Scene& s) {
  const laws::LawFamily family =
      d.Pick<laws::LawFamily>({laws::LawFamily::kLinear, laws::LawFamily::kCubic,
                               laws::LawFamily::kExponential, laws::LawFamily::kTriangular});
  BridgingSpec b;
  b.shape = *laws::DefaultShape(family);
  laws::LawScales given;
  given.sigma_c = d.LogUniform(0.3e6, 3e6);
  given.J_B = d.LogUniform(100.0, 1500.0);
  b.scales = laws::CompleteScales(b.shape, given);
  s.bridging = b;
  s.fracture = FractureSpec{d.LogUniform(300.0, 3000.0)};
}

// The warnings `bridgefit fit` gives for the whole run (stderr lines, exit
// status, sentences the output marks as warnings): not converged, the
// reduction's warnings, a model error not estimated, a model note (the
// compliance calibration's warning).
std::vector<std::string> CaseWarnings(const pipeline::FitRun& run) {
  std::vector<std::string> out;
  if (!run.summary.converged) out.push_back("not converged: " + run.summary.stop_reason);
  for (const std::string& w : run.input.reduction_warnings) out.push_back("reduction: " + w);
  if (run.model_error.status != inverse::ModelErrorStatus::kEstimated)
    out.push_back("model error: " + run.model_error.Summary());
  if (!run.model_note.empty()) out.push_back("model note: " + run.model_note);
  if (!run.model_error.warning.empty()) out.push_back("model error: " + run.model_error.warning);
  return out;
}

ParameterCheck CheckParameter(const inverse::ParameterEstimate& e, double truth, bool case_warned,
                              double cr_sd, double model_bias) {
  ParameterCheck c;
  c.truth = truth;
  c.value = e.value;
  c.low = e.ci95_low;
  c.high = e.ci95_high;
  c.stat_low = e.statistical_ci95_low;
  c.stat_high = e.statistical_ci95_high;
  c.lower_bound = e.lower_bound;
  c.identified = e.identified;
  c.interval_status = inverse::IntervalStatusName(e.interval_status);
  c.interval_reason = e.interval_reason;
  // An interval that is not reliable is a warning on stderr (an open one
  // is printed as NaN ends: no claim, so no coverage either).
  c.warned = case_warned || !e.interval_reliable();
  c.has_interval = e.identified && std::isfinite(e.value) && std::isfinite(c.low) &&
                   std::isfinite(c.high);
  c.error_ratio = NAN;
  c.width_ratio = NAN;
  c.cr_width_ratio = NAN;
  if (c.has_interval) {
    c.covered = c.low <= truth && truth <= c.high;
    const double half = truth >= c.value ? c.high - c.value : c.value - c.low;
    c.error_ratio = std::abs(c.value - truth) / std::max(half, 1e-300);
    const double stat_width = c.stat_high - c.stat_low;
    if (std::isfinite(stat_width) && stat_width > 0.0) c.width_ratio = (c.high - c.low) / stat_width;
    if (std::isfinite(cr_sd) && cr_sd > 0.0) {
      c.cr_width_ratio = (c.high - c.low) / (2.0 * 1.96 * cr_sd);
      c.model_error_small = std::isfinite(model_bias) && std::abs(model_bias) <= 0.3 * cr_sd;
    }
    c.failure = c.error_ratio > 2.0;
  }
  // A reported lower bound must never exceed the truth.
  c.bound_above_truth = std::isfinite(c.lower_bound) && c.lower_bound > truth * (1.0 + 1e-9);
  c.failure = c.failure || c.bound_above_truth;
  c.silent_failure = c.failure && !c.warned;
  return c;
}

// BF_VALIDATE_DIC_CSV=FILE: one row per DIC frame after the reference
// appended to FILE (header when new): each tip method's length and 1-sigma
// uncertainty, the path against the line, the flags, the error against the
// true tip (lengths in mm).
void AppendDicFrames(const std::string& file, const ValidationCase& spec,
                     const pipeline::SynthTest& test, const dic::CrackSequenceResult& dic) {
  static std::mutex mutex;
  const std::lock_guard<std::mutex> lock(mutex);
  const bool is_new = !std::filesystem::exists(file);
  std::ofstream out(file, std::ios::app);
  if (is_new)
    out << "case, frame, truth_mm, raw_mm, monotone_mm, u_mm, method, williams_mm, u_williams_mm, "
           "sqrt_mm, u_sqrt_mm, jump_mm, u_jump_mm, path_points, path_rms_px, line_rms_all_px, "
           "hint_offset_px, line_se_px, hint_angle_deg, cracked_px, curvature_per_px, "
           "curvature_se_per_px, williams_shift_px, flags\n";
  const double mm = 1e3 * test.window.scale;  // px -> mm
  auto at = [&](const dic::TipEstimate& t) {  // along the line used, as the frame's length
    return t.found ? fmt::format("{:.4f}, {:.4f}", t.s_px * mm + 1e3 * test.window.x0,
                                 t.uncertainty_px * mm)
                   : std::string("nan, nan");
  };
  for (std::size_t k = 1; k < dic.frames.size(); ++k) {
    const dic::FrameResult& f = dic.frames[k];
    const dic::CrackTipResult& t = f.tip;
    out << fmt::format("{}, {}, {:.4f}, {:.4f}, {:.4f}, {:.4f}, {}, {}, {}, {}, {}, {:.3f}, {:.3f}, "
                       "{:.2f}, {:.2f}, {:.3f}, {:.1f}, {:.3g}, {:.3g}, {:.3f}, {}\n",
                       spec.index, k, 1e3 * test.frames[k].crack_length,
                       f.has_length ? 1e3 * f.crack_length_raw_m : NAN,
                       f.has_length ? 1e3 * f.crack_length_m : NAN, 1e3 * f.uncertainty_m,
                       dic::TipMethodName(t.method), at(t.williams), at(t.sqrt_cod),
                       at(t.jump), f.path.inliers, f.path.rms_residual_px,
                       f.path.line_rms_all_px, f.path.hint_max_offset_px, f.path.line_se_px,
                       f.path.hint_angle_deg, f.path.cracked_length_px, f.path.curvature_per_px,
                       f.path.curvature_se_per_px, t.williams_shift_px, f.Flags());
  }
}

// The images route's DIC: the frames written as `bridgefit synth` writes
// them (a temporary folder, removed after), analysed with `bridgefit dic`'s
// defaults along the synth window's crack line (the image's middle row;
// scale and left edge from the window, as scripts/demo.sh gives them), each
// length compared with the frame's true tip. A flagged frame, or one after
// the reference without a length, is a case warning (`bridgefit dic` prints
// both).
pipeline::FitRequest::FrameCrackLengths MeasureFrames(const ValidationCase& spec,
                                                      const pipeline::SynthTest& test, int threads,
                                                      CaseResult& result) {
  static std::atomic<unsigned> serial{0};
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      fmt::format("bf_validate_{}_{}_{}", static_cast<long>(::getpid()), spec.index, serial++);
  struct Remove {  // the folder goes whatever happens
    std::filesystem::path dir;
    ~Remove() {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  } remove{dir};
  pipeline::WriteSyntheticTest(test, dir, "record.csv");
  std::vector<std::filesystem::path> images;
  for (const pipeline::SynthFrame& f : test.frames)
    images.push_back(dir / "images" / pipeline::SynthFrameName(f.index));
  dic::DicSettings settings;
  settings.scale_m_per_px = test.window.scale;
  settings.offset_m = test.window.x0;
  const double row = 0.5 * kImageHeight;
  settings.crack_line = dic::CrackLine{0.0, row, kImageWidth - 1.0, row};
  settings.threads = threads;
  // As `bridgefit dic --scene`: the plate's constants for the tip fit.
  dic::CrackSequenceOptions dic_options = dic::MakeSequenceOptions(settings);
  pipeline::TipMaterialFromScene(spec.scene, &dic_options.tip);
  const dic::CrackSequenceResult dic = dic::AnalyzeCrackSequence(images, dic_options);
  if (const char* csv = std::getenv("BF_VALIDATE_DIC_CSV")) AppendDicFrames(csv, spec, test, dic);
  pipeline::FitRequest::FrameCrackLengths frames;
  frames.source = "DIC of validation case " + std::to_string(spec.index);
  double sum = 0.0, worst = 0.0;
  for (std::size_t k = 0; k < dic.frames.size(); ++k) {
    const dic::FrameResult& f = dic.frames[k];
    frames.image.push_back(f.image);
    frames.crack_length.push_back(f.has_length ? f.crack_length_m : NAN);
    if (k == 0) continue;  // the reference
    const std::string file = std::filesystem::path(f.image).filename().string();
    if (!f.has_length) {
      result.warnings.push_back("DIC " + file + ": no crack length");
      ++result.dic_flagged;
      continue;
    }
    if (f.flagged) {
      result.warnings.push_back("DIC " + file + ": flagged " + f.Flags());
      ++result.dic_flagged;
    }
    const double error = f.crack_length_m - test.frames[k].crack_length;
    sum += error;
    worst = std::max(worst, std::abs(error));
    ++result.dic_frames;
  }
  if (result.dic_frames > 0) {
    result.dic_mean_error = sum / result.dic_frames;
    result.dic_max_abs_error = worst;
  }
  return frames;
}

// The request `bridgefit fit RECORD --scene S --law FAMILY` makes (apps/
// cmd_fit.cpp defaults: BOBYQA, 4 starts, profiles, --resolution auto), with
// the route's flags: --rcurve-method mbt, or --fit-to load-displacement
// --calibrate-compliance=crack. The scene given to the fit holds no truth
// beyond the specimen and material a user would know.
pipeline::FitRequest FitRequestFor(const ValidationCase& spec, ExperimentRecord record,
                                   int threads) {
  pipeline::FitRequest request;
  request.record = std::move(record);
  request.scene.source = "validation case " + std::to_string(spec.index);
  request.scene.specimen = spec.scene.specimen;
  request.scene.material = spec.scene.material;
  request.scene_path = request.scene.source;
  request.law = spec.scene.bridging->shape.family;
  request.fit.threads = threads;
  if (spec.route == Route::kMbt) {
    request.reduction.method = experiment::RMethod::kMbt;
    request.reduction_given = true;
  } else if (spec.route == Route::kLoad) {
    request.target = inverse::FitTarget::kLoad;
    request.calibration = inverse::ComplianceCalibrationMode::kAlongCrack;
  }
  return request;
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace

const char* RouteName(Route route) {
  switch (route) {
    case Route::kEnergy: return "energy";
    case Route::kMbt: return "mbt";
    case Route::kLoad: return "load";
    case Route::kImages: return "images";
  }
  return "?";
}

std::string ValidationCase::Label() const {
  const SpecimenSpec& sp = scene.specimen;
  const bool ct = sp.type == SpecimenType::kCT;
  return fmt::format("#{} {} {}={:.0f}mm {} {} {}", index, ct ? "CT" : "DCB", ct ? "W" : "h",
                     (ct ? sp.width : sp.height) * 1e3, scene.material.orthotropic ? "ortho" : "iso",
                     laws::LawFamilyName(scene.bridging->shape.family), RouteName(route));
}

ValidationCase DrawCase(std::uint64_t campaign_seed, int index, const DrawOptions& options) {
  ValidationCase c;
  c.index = index;
  // One engine per case, seeded from (campaign, index): a case draws the
  // same whatever the number of cases or jobs.
  std::seed_seq seq{campaign_seed, static_cast<std::uint64_t>(index), std::uint64_t{17}};
  Draw d{std::mt19937_64(seq)};
  c.seed = d.rng();
  c.scene.source = "validation case " + std::to_string(index);
  const bool ct = !d.Chance(options.dcb_fraction);
  if (ct) DrawCt(d, c.scene);
  else DrawDcb(d, c.scene);
  DrawMaterial(d, c.scene);
  DrawLaw(d, c.scene);
  // Routes: CT energy 85% / load 15%; DCB energy 40% / MBT 35% / load 25%
  // (a load fit costs 10-300 s against a few seconds for an energy fit).
  const double r = d.Uniform(0.0, 1.0);
  if (ct) c.route = r < 0.85 ? Route::kEnergy : Route::kLoad;
  else c.route = r < 0.4 ? Route::kEnergy : (r < 0.75 ? Route::kMbt : Route::kLoad);
  if (options.energy_only) c.route = Route::kEnergy;
  c.load_noise = d.LogUniform(0.002, 0.01);
  c.displacement_noise = d.LogUniform(0.3e-6, 3e-6);
  c.crack_noise = d.LogUniform(0.05e-3, 0.3e-3);
  c.generation_resolution = specimen::DefaultResolution(c.scene.specimen) / 4.0;
  c.generation_far_field = options.far_field;
  c.scene.Validate();
  return c;
}

CaseResult RunCase(const ValidationCase& spec, int threads) {
  CaseResult result;
  result.spec = spec;
  try {
    const auto t0 = std::chrono::steady_clock::now();
    pipeline::SynthRequest synth;
    synth.scene = spec.scene;
    synth.seed = spec.seed;
    synth.resolution = spec.generation_resolution;
    synth.far_field = spec.generation_far_field;
    synth.load_noise = spec.load_noise;
    synth.displacement_noise = spec.displacement_noise;
    synth.crack_noise = spec.crack_noise;
    const bool images = spec.route == Route::kImages;
    synth.frames = images ? kImageFrames : 0;
    synth.image_width = kImageWidth;
    synth.image_height = kImageHeight;
    result.generation_failed = true;  // until the record is made
    const pipeline::SynthTest test = pipeline::MakeSyntheticTest(synth);
    result.truth_steady_state = test.simulation.steady_state_reached;
    result.max_crack_length = test.simulation.points.back().crack_length;
    result.truth_R_rise = test.simulation.points.back().R / spec.scene.fracture->J_tip_c - 1.0;
    // The record read back from the CSV `bridgefit synth` writes, as the
    // CLI reads it (rounded to the written digits).
    // BF_VALIDATE_RECORD_DIR: each case's record as written (case_N.csv), to
    // rerun its fit with the CLI on exactly the harness's data.
    if (const char* dir = std::getenv("BF_VALIDATE_RECORD_DIR"))
      std::ofstream(std::string(dir) + "/case_" + std::to_string(spec.index) + ".csv") << test.record_csv;
    const io::CsvTable table = io::ParseCsvTable(test.record_csv, spec.Label(), InputLimits{});
    ExperimentRecord record = io::RecordFromCsvTable(table, io::RecordColumns{});
    record.source = spec.Label();
    result.generate_s = Seconds(t0);
    result.generation_failed = false;

    pipeline::FitRequest request = FitRequestFor(spec, std::move(record), threads);
    if (images) {
      const auto t_dic = std::chrono::steady_clock::now();
      request.frame_crack_lengths = MeasureFrames(spec, test, threads, result);
      result.dic_s = Seconds(t_dic);
    }
    const auto t1 = std::chrono::steady_clock::now();
    const pipeline::FitRun run = pipeline::RunFit(request);
    result.fit_s = Seconds(t1);
    if (std::getenv("BF_VALIDATE_VERBOSE"))  // the fit's report, as `bridgefit fit` prints it
      std::fprintf(stderr, "%s: model error: %s\n%s", spec.Label().c_str(),
                   run.model_error.Summary().c_str(), run.BriefReport().c_str());
    const inverse::FitSummary& s = run.summary;
    result.fit_steady_state = s.steady_state_reached;
    result.bridging_detected = s.bridging_detected;
    result.converged = s.converged;
    result.misfit_points = s.misfit.points;
    result.fit_resolution = run.resolution;
    result.data_points = s.data_points;
    for (std::string& w : CaseWarnings(run)) result.warnings.push_back(std::move(w));
    const bool case_warned = !result.warnings.empty();
    const laws::LawScales& truth = spec.scene.bridging->scales;
    const inverse::ModelErrorEstimate& me = run.model_error;
    const std::array<const inverse::ParameterEstimate*, 3> estimates = {&s.sigma_c, &s.J_B, &s.J_tip_c};
    const std::array<double, 3> truths = {truth.sigma_c, truth.J_B, spec.scene.fracture->J_tip_c};
    for (int p = 0; p < 3; ++p)
      result.parameters[p] = CheckParameter(*estimates[p], truths[p], case_warned,
                                            me.statistical_sd[p], me.parameter_bias[p]);
    result.ran = true;
  } catch (const std::exception& e) {
    result.error = e.what();
  }
  return result;
}

}  // namespace bridgefit::validate
