#include "bridgefit/pipeline/synth.hpp"

#include <algorithm>
#include <memory>
#include <random>

#include <fmt/format.h>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/specimen/calibrations.hpp"

namespace bridgefit::pipeline {

std::string SynthFrameName(int frame) { return fmt::format("frame_{:02d}.png", frame); }

void SynthRequest::Check() const {
  scene.Validate();
  if (!scene.fracture)
    throw Error(ErrorKind::kInput, "synth needs a [fracture] table", {.file = scene.source});
  if (loading_rows < 2 || growth_rows < 2)
    throw Error(ErrorKind::kUsage, "need at least 2 loading and 2 growth points");
  if (!std::isnan(scale) && !(scale > 0 && std::isfinite(scale)))
    throw Error(ErrorKind::kUsage, "the image scale must be a positive length per pixel",
                {.field = "--scale", .value = fmt::format("{} m", scale), .expected = "e.g. 0.15 mm"});
  if (!(far_field > 0 && far_field <= 1))
    throw Error(ErrorKind::kUsage, "the far-field factor must be in (0, 1]",
                {.field = "--far-field", .value = fmt::format("{}", far_field),
                 .expected = "1 (the model's default far field) or less (refined)"});
  if (bridged_field && !scene.bridging)
    throw Error(ErrorKind::kInput, "a bridged field needs a [bridging] table",
                {.file = scene.source, .field = "bridging"});
  if (!std::isnan(image_x0) && !std::isfinite(image_x0))
    throw Error(ErrorKind::kUsage, "the image's left edge must be a finite length",
                {.field = "--image-x0", .expected = "e.g. 20 mm"});
}

namespace {

// Exact rows: linear loading at a0 up to initiation, then growth rows evenly
// spaced along the simulated path; time at a constant displacement rate.
ExperimentRecord ExactRows(const SynthRequest& request, const SimulationResult& sim,
                           std::vector<std::size_t>& growth_index) {
  ExperimentRecord exact =
      RecordAlongPath(sim, request.loading_rows, request.growth_rows, &growth_index);
  exact.time.assign(exact.size(), 0.0);
  for (std::size_t i = 1; i < exact.size(); ++i)
    exact.time[i] = exact.time[i - 1] + std::abs(exact.displacement[i] - exact.displacement[i - 1]) /
                                            request.displacement_rate;
  return exact;
}

// Frame 0 unloaded (row 0), frames 1.. spread over the growth rows from
// initiation to the last row: each frame's growth row index and record row.
void FrameRows(const SynthRequest& request, std::size_t growth_count,
               std::vector<std::size_t>& frame_growth, std::vector<std::size_t>& frame_row) {
  const int frames = request.frames;
  frame_growth.assign(frames, 0);
  frame_row.assign(frames, 0);
  for (int f = 1; f < frames; ++f) {
    const std::size_t g =
        frames <= 2 ? 0
                    : static_cast<std::size_t>(
                          std::llround(double(f - 1) * (growth_count - 1) / (frames - 2)));
    frame_growth[f] = std::min(g, growth_count - 1);
    frame_row[f] = request.loading_rows + frame_growth[f];
  }
}

// The noisy record; with frames, an `image` column names the frame taken at
// a row (the link `bridgefit rcurve --crack-length-from` uses).
std::string NoisyRecordCsv(const SynthRequest& request, const ExperimentRecord& exact,
                           const std::vector<std::size_t>& frame_row, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::string csv = std::string("time [s], load [N], displacement [mm], crack_length [mm]") +
                    (request.frames > 0 ? ", image\n" : "\n");
  for (std::size_t i = 0; i < exact.size(); ++i) {
    const double load = exact.load[i] * (1.0 + request.load_noise * normal(rng));
    const double disp =
        exact.displacement[i] + (i == 0 ? 0.0 : request.displacement_noise * normal(rng));
    const double crack = exact.crack_length[i] + request.crack_noise * normal(rng);
    csv += fmt::format("{:.4f}, {:.5f}, {:.6f}, {:.4f}", exact.time[i], load, disp * 1e3,
                       crack * 1e3);
    if (request.frames > 0) {
      const auto it = std::find(frame_row.begin(), frame_row.end(), i);
      csv += ", " + (it == frame_row.end()
                         ? std::string()
                         : "images/" + SynthFrameName(static_cast<int>(it - frame_row.begin())));
    }
    csv += "\n";
  }
  return csv;
}

// The plate the frames show: isotropic (the scene's mu and kappa) or, for
// an orthotropic scene, Lekhnitskii's plate driven by the same Westergaard
// functions (dic::BridgedCrackField::SetOrthotropic) with 2 mu = E'/2, so
// that K / (2 mu) and traction / (2 mu) keep their meaning and the opening
// is the plate's. Before 2026-12-04 an orthotropic scene was drawn as an
// isotropic plate with mu = G12, nu = nu12, whose J(K) and opening differ
// from the scene's (E').
struct FramePlate {
  double mu = 0, kappa = 0;
  bool orthotropic = false;
  specimen::InPlaneCompliance b;
  FramePlate(const Scene& scene, double E_eff) {
    const MaterialSpec& m = scene.material;
    orthotropic = m.orthotropic;
    if (orthotropic) {
      b = specimen::OrthotropicInPlaneCompliance(m, scene.specimen.plane);
      mu = 0.25 * E_eff;
      kappa = 1.0;
      return;
    }
    mu = m.AxialModulus() / (2 * (1 + m.nu));
    kappa = specimen::KolosovConstant(m, scene.specimen.plane);
  }
  void Apply(dic::BridgedCrackField* f) const {
    if (orthotropic) f->SetOrthotropic(b.b11, b.b22, b.b12, b.b66, 2 * mu);
  }
};

// The unbridged K field of a frame on an orthotropic plate (Sih, Paris &
// Irwin: BridgedCrackField without tractions).
dic::BridgedCrackField OrthotropicKField(const dic::ModeICrackField& lefm, const FramePlate& plate) {
  dic::BridgedCrackField b;
  b.tip_x = lefm.tip_x;
  b.tip_y = lefm.tip_y;
  b.translation_x = lefm.translation_x;
  b.translation_y = lefm.translation_y;
  b.k_over_2mu = lefm.k_over_2mu;
  b.segments = 1;
  plate.Apply(&b);
  b.Solve();
  return b;
}

// A bridged frame (SynthRequest::bridged_field): faces from the notch root
// to the tip closed by the scene's law, the applied K found by the secant
// method on K_tip(K_applied) = K_tip,c (monotone, smooth). Lengths in px.
dic::BridgedCrackField BridgedFrame(const SynthRequest& request, const dic::ModeICrackField& lefm,
                                    double zone_px, double scale, const FramePlate& plate,
                                    double E_eff) {
  const laws::BridgingLaw law = request.scene.bridging->Law();
  const double mu = plate.mu;
  dic::BridgedCrackField b;
  plate.Apply(&b);
  b.tip_x = lefm.tip_x;
  b.tip_y = lefm.tip_y;
  b.kappa = lefm.kappa;
  b.translation_x = lefm.translation_x;
  b.translation_y = lefm.translation_y;
  b.zone_length = zone_px;
  b.segments = 120;
  b.traction_over_2mu = [law, scale, mu](double delta_px) {
    return law.Traction(delta_px * scale) / (2 * mu);
  };
  const double target =
      std::sqrt(E_eff * request.scene.fracture->J_tip_c) / (2 * mu) / std::sqrt(scale);
  auto tip_error = [&](double k) {
    b.k_over_2mu = k;
    b.Solve();
    return b.TipKOver2mu() - target;
  };
  double k0 = target, k1 = 1.5 * target;
  double f0 = tip_error(k0), f1 = tip_error(k1);
  for (int it = 0; it < 30 && std::abs(f1) > 1e-7 * target; ++it) {
    const double k2 = f1 == f0 ? k1 * 1.1 : k1 - f1 * (k1 - k0) / (f1 - f0);
    k0 = k1;
    f0 = f1;
    k1 = std::max(k2, target);
    f1 = tip_error(k1);
  }
  if (std::abs(f1) > 1e-5 * target)
    throw Error(ErrorKind::kRuntime, "synth: the bridged frame's applied K did not converge",
                {.value = fmt::format("K_tip error {:.3g} of the target", f1 / target)});
  return b;
}

// The bridged field (hundreds of terms per point) tabulated every kTableStep
// px and interpolated bilinearly, except in cells that straddle the crack
// faces, where it is evaluated exactly (the opening is a jump there). Every
// 2 px instead of every pixel: a quarter of the evaluations (they were three
// quarters of `synth --bridged-field`'s time); the bilinear error, h^2/8
// |u''|, is about 2e-4 px 10 px from the tip (K field, K = 0.94 MPa m^0.5
// at 0.1 mm/px), far below the DIC's noise (5e-3 px).
constexpr int kTableStep = 2;
dic::DisplacementFunction Tabulated(const dic::BridgedCrackField& b, int width, int height) {
  constexpr double h = kTableStep;
  const int nx = (width + 2) / kTableStep + 2, ny = (height + 2) / kTableStep + 2;  // from -1 px
  auto u = std::make_shared<std::vector<double>>(static_cast<size_t>(nx) * ny);
  auto v = std::make_shared<std::vector<double>>(u->size());
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      b(h * i - 1.0, h * j - 1.0, &(*u)[j * nx + i], &(*v)[j * nx + i]);
  return [b, u, v, nx, ny, h](double X, double Y, double* ux, double* vy) {
    const double fx = (X + 1) / h, fy = (Y + 1) / h;
    const int i = static_cast<int>(std::floor(fx)), j = static_cast<int>(std::floor(fy));
    const bool faces = X < b.tip_x + h && std::abs(Y - b.tip_y) < h + 0.5;
    if (faces || i < 0 || j < 0 || i + 1 >= nx || j + 1 >= ny) return b(X, Y, ux, vy);
    const double tx = fx - i, ty = fy - j;
    auto lerp = [&](const std::vector<double>& a) {
      const size_t k = static_cast<size_t>(j) * nx + i;
      return (1 - ty) * ((1 - tx) * a[k] + tx * a[k + 1]) +
             ty * ((1 - tx) * a[k + nx] + tx * a[k + nx + 1]);
    };
    *ux = lerp(*u);
    *vy = lerp(*v);
  };
}

// Speckle frames: frame 0 unloaded, then the LEFM field of the far-field K
// (tip plus bridging, so the opening grows as in the test) at each frame's
// simulated crack length, with a small rigid motion.
void RenderFrames(const SynthRequest& request, const SimulationResult& sim,
                  const std::vector<std::size_t>& growth_index,
                  const std::vector<std::size_t>& frame_growth,
                  const std::vector<std::size_t>& frame_row, SynthTest& test) {
  const FramePlate plate(request.scene, test.effective_modulus);
  const double mu = plate.mu, kappa = plate.kappa;
  dic::SpeckleOptions so;
  so.width = request.image_width;
  so.height = request.image_height;
  so.speckle_radius_px = 2.0;
  so.seed = request.seed;
  const dic::SpeckleRenderer renderer(so);
  Progress progress("synth: speckle frames", request.frames, request.progress);
  for (int f = 0; f < request.frames; ++f) {
    SynthFrame frame;
    frame.index = f;
    frame.record_row = frame_row[f];
    frame.field.tip_y = 0.5 * request.image_height;
    frame.field.kappa = kappa;
    frame.crack_length = request.scene.specimen.notch;
    if (f > 0) {
      const SimulationPoint& p = sim.points[growth_index[frame_growth[f]]];
      frame.crack_length = p.crack_length;
      frame.J_ff = std::isfinite(p.J_ff) ? p.J_ff : request.scene.fracture->J_tip_c;
      frame.K_I = std::sqrt(test.effective_modulus * frame.J_ff);
    }
    frame.field.tip_x = (frame.crack_length - test.window.x0) / test.window.scale;
    frame.field.k_over_2mu = frame.K_I / (2 * mu) / std::sqrt(test.window.scale);
    frame.field.translation_x = 0.3 * f;
    frame.field.translation_y = -0.2 * f;
    const double zone_px = (frame.crack_length - request.scene.specimen.notch) / test.window.scale;
    if (f > 0 && request.bridged_field && zone_px > 0.5) {
      const dic::BridgedCrackField b =
          BridgedFrame(request, frame.field, zone_px, test.window.scale, plate, test.effective_modulus);
      frame.field.k_over_2mu = b.k_over_2mu;
      frame.K_I = b.k_over_2mu * 2 * mu * std::sqrt(test.window.scale);
      frame.J_ff = frame.K_I * frame.K_I / test.effective_modulus;
      frame.delta_root = b.OpeningAt(zone_px) * test.window.scale;
      frame.image = renderer.Render(Tabulated(b, request.image_width, request.image_height),
                                    request.seed * 1000 + f);
    } else {
      if (f > 0 && request.bridged_field) {  // at the notch: no zone yet, K = K_tip,c
        frame.J_ff = request.scene.fracture->J_tip_c;
        frame.K_I = std::sqrt(test.effective_modulus * frame.J_ff);
        frame.field.k_over_2mu = frame.K_I / (2 * mu) / std::sqrt(test.window.scale);
        frame.delta_root = 0;
      }
      if (f == 0)
        frame.image = renderer.RenderReference(request.seed * 1000 + f);
      else if (plate.orthotropic)
        frame.image = renderer.Render(OrthotropicKField(frame.field, plate), request.seed * 1000 + f);
      else
        frame.image = renderer.Render(frame.field, request.seed * 1000 + f);
    }
    test.frames.push_back(std::move(frame));
    progress.Update(f + 1);
  }
  progress.Finish();
}

}  // namespace

SynthWindow SynthImageWindow(const SpecimenSpec& specimen, int image_width_px, double given_x0,
                             double given_scale) {
  constexpr double kDefaultX0 = 20e-3, kDefaultScale = 0.15e-3;
  SynthWindow w;
  w.x0 = std::isfinite(given_x0) ? given_x0 : kDefaultX0;
  w.scale = std::isfinite(given_scale) ? given_scale : kDefaultScale;
  const double end = specimen.type == SpecimenType::kCT ? specimen.width : specimen.length;
  const double a0 = specimen.notch;
  if (!(end > a0 && a0 > 0 && image_width_px > 0)) return w;  // nothing to check against
  auto fits = [&](double x0, double scale) {
    const double tip_px = (a0 - x0) / scale;
    return tip_px >= 0.05 * image_width_px && x0 + image_width_px * scale <= end * (1 + 1e-9);
  };
  if (fits(w.x0, w.scale)) return w;
  const std::string end_name = specimen.type == SpecimenType::kCT ? "W" : "L";
  const std::string was = fmt::format("{:.4g}..{:.4g} mm at {:.4g} mm/px", w.x0 * 1e3,
                                      (w.x0 + image_width_px * w.scale) * 1e3, w.scale * 1e3);
  if (std::isfinite(given_x0) || std::isfinite(given_scale)) {
    w.fits = false;
    w.warning = fmt::format(
        "synth: the image window {} does not hold the notch tip (a0 = {:.4g} mm) at least 5% of "
        "the width inside its left edge, or runs past the specimen's end ({} = {:.4g} mm); the "
        "frames show less of the crack than they could: set --image-x0 and --scale (or leave "
        "both out for a window that fits)",
        was, a0 * 1e3, end_name, end * 1e3);
    return w;
  }
  w.x0 = std::max(0.0, a0 - 0.1 * (end - a0));
  w.scale = (end - w.x0) / image_width_px;
  w.note = fmt::format(
      "synth: the default image window ({}) does not fit this specimen (a0 = {:.4g} mm, {} = "
      "{:.4g} mm): frames span {:.4g}..{:.4g} mm at {:.4g} mm/px instead (--image-x0 and --scale "
      "set it)",
      was, a0 * 1e3, end_name, end * 1e3, w.x0 * 1e3, end * 1e3, w.scale * 1e3);
  return w;
}

std::string SynthFieldNote(const SpecimenSpec& specimen, const SynthWindow& window,
                           int image_height_px) {
  const bool dcb = specimen.type == SpecimenType::kDCB;
  const double tall = dcb ? 2.0 * specimen.height : specimen.height;  // the specimen's height
  const double image = image_height_px * window.scale;
  const bool past = tall > 0 && image > tall * (1 + 1e-9);
  if (!dcb && !past) return {};
  std::string text = fmt::format(
      "synth: the frames show a crack in an infinite plate (the LEFM field of the model's J_ff, "
      "or the bridged crack), not this {}'s own field{}",
      dcb ? "DCB" : "CT", dcb ? " (its arms bend; their free faces are not modelled)" : "");
  if (past)
    text += fmt::format(
        "; the image is {:.4g} mm tall against the specimen's {:.4g} mm ({}): its "
        "speckle beyond that is not on the specimen",
        image * 1e3, tall * 1e3, dcb ? "2 h" : "H");
  return text + ". Crack lengths and J_ff are this field's (truth.csv).";
}

SynthTest MakeSyntheticTest(const SynthRequest& request) {
  request.Check();
  Stopwatch watch;
  SynthTest test;
  test.effective_modulus =
      specimen::EffectiveModulus(request.scene.material, request.scene.specimen.plane);
  if (request.frames > 0) {
    test.window = SynthImageWindow(request.scene.specimen, request.image_width, request.image_x0,
                                   request.scale);
    const std::string field =
        SynthFieldNote(request.scene.specimen, test.window, request.image_height);
    if (!field.empty()) test.window.note += (test.window.note.empty() ? "" : "\n") + field;
  }
  models::ReducedOptions options;
  if (std::isfinite(request.resolution)) options.mesh.resolution = request.resolution;
  options.mesh.coarse_factor = request.far_field;
  options.progress = request.progress;
  test.simulation = models::SimulateReduced(request.scene, options);
  const SimulationResult& sim = test.simulation;
  if (sim.status != RunStatus::kOk || sim.points.size() < 2)
    throw Error(ErrorKind::kRuntime, "the forward model failed: " + sim.message,
                {.file = request.scene.source});
  std::vector<std::size_t> growth_index;  // nearest simulated point of each growth row
  test.exact = ExactRows(request, sim, growth_index);
  std::vector<std::size_t> frame_growth, frame_row;
  FrameRows(request, growth_index.size(), frame_growth, frame_row);
  std::mt19937_64 rng(request.seed);
  test.record_csv = NoisyRecordCsv(request, test.exact, frame_row, rng);
  RenderFrames(request, sim, growth_index, frame_growth, frame_row, test);
  test.wall_s = watch.Seconds();
  return test;
}

std::string SynthTest::TruthCsv() const {
  std::string truth =
      "frame, record_row, crack_length [mm], tip_x [px], tip_y [px], K_I [MPa m^0.5], "
      "translation_x [px], translation_y [px], J_ff [J/m^2], delta_root [mm]\n";
  auto num = [](double v, double scale) {
    return std::isfinite(v) ? fmt::format("{:.6g}", v * scale) : std::string();
  };
  for (const SynthFrame& f : frames)
    truth += fmt::format("{}, {}, {:.4f}, {:.3f}, {:.3f}, {:.5f}, {:.3f}, {:.3f}, {}, {}\n",
                         f.index, f.record_row, f.crack_length * 1e3, f.field.tip_x,
                         f.field.tip_y, f.K_I * 1e-6, f.field.translation_x,
                         f.field.translation_y, num(f.J_ff, 1), num(f.delta_root, 1e3));
  return truth;
}

void WriteSyntheticTest(const SynthTest& test, const std::filesystem::path& dir,
                        const std::string& record_name) {
  std::filesystem::create_directories(dir);
  WriteTextFileAtomic(dir / record_name, test.record_csv);
  if (test.frames.empty()) return;
  const std::filesystem::path images = dir / "images";
  std::filesystem::create_directories(images);
  for (const SynthFrame& f : test.frames) dic::WriteImage(images / SynthFrameName(f.index), f.image, 8);
  WriteTextFileAtomic(images / "truth.csv", test.TruthCsv());
}

}  // namespace bridgefit::pipeline
