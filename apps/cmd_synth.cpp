// `bridgefit synth`: a synthetic fracture test from a scene, by the reduced
// forward model: a load-displacement record with noise and, optionally, a
// short speckle sequence whose crack tip follows the simulated crack length.
//   bridgefit synth data_samples/mdf_ct/scene.toml --out data_samples/mdf_ct --seed 1
//   bridgefit synth scene.toml --out DIR --seed 7 --frames 0        (record only)
// Writes DIR/record.csv (`time [s], load [N], displacement [mm], crack_length [mm]`),
// DIR/images/frame_NN.png and DIR/images/truth.csv (true tip per frame).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <random>
#include <string>

#include <fmt/format.h>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/dic/image.hpp"
#include "bridgefit/dic/speckle.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/models/reduced.hpp"
#include "command.hpp"

namespace bridgefit::cli {
namespace {

class SynthCommand final : public Command {
 public:
  const char* name() const override { return "synth"; }
  const char* description() const override {
    return "Synthetic test from a scene: noisy load-displacement record and speckle images";
  }
  void Register(CLI::App& sub) override {
    sub.add_option("scene", scene_, "Scene TOML (the truth)")->required();
    sub.add_option("--out", out_, "Output folder")->required();
    sub.add_option("--seed", seed_, "Random seed (noise and speckle)")->default_val(1);
    sub.add_option("--resolution", resolution_, "Reduced model element size, e.g. '0.5 mm'");
    sub.add_option("--loading-points", loading_points_, "Rows before initiation")->default_val(20);
    sub.add_option("--growth-points", growth_points_, "Rows during growth")->default_val(400);
    sub.add_option("--load-noise", load_noise_, "Relative load noise, 1 sigma")->default_val(0.005);
    sub.add_option("--displacement-noise", disp_noise_, "Displacement noise, 1 sigma")
        ->default_val("1 um");
    sub.add_option("--crack-noise", crack_noise_, "Crack-length noise, 1 sigma")->default_val("0.3 mm");
    sub.add_option("--record-name", record_name_, "File name of the record")->default_val("record.csv");
    sub.add_option("--rate", rate_, "Displacement rate")->default_val("1 mm");
    sub.add_option("--frames", frames_, "Speckle frames (0: none)")->default_val(10);
    sub.add_option("--image-width", image_width_, "px")->default_val(400);
    sub.add_option("--image-height", image_height_, "px")->default_val(300);
    scale_option_ = sub.add_option("--scale", scale_, "Image scale per px (default 0.15 mm, or "
                                   "what fits the specimen)")->default_val("0.15 mm");
    x0_option_ = sub.add_option("--image-x0", image_x0_,
                                "Distance of the image's left edge from the load line (default "
                                "20 mm, or what fits the specimen)")
                     ->default_val("20 mm");
  }

  int Run(const CommonOptions& common) override {
    const Scene scene = io::ReadSceneFile(scene_);
    scene.Validate();
    if (!scene.fracture)
      throw Error(ErrorKind::kInput, "synth needs a [fracture] table", {.file = scene.source});
    if (loading_points_ < 2 || growth_points_ < 2)
      throw Error(ErrorKind::kUsage, "need at least 2 loading and 2 growth points");
    const double disp_noise = ParseOptionQuantity(disp_noise_, Dimension::Length(), "--displacement-noise");
    const double crack_noise = ParseOptionQuantity(crack_noise_, Dimension::Length(), "--crack-noise");
    const double rate = ParseOptionQuantity(rate_, Dimension::Length(), "--rate") / 60.0;  // per minute
    Stopwatch watch;

    models::ReducedOptions options;
    if (!resolution_.empty())
      options.mesh.resolution = ParseOptionQuantity(resolution_, Dimension::Length(), "--resolution");
    options.progress = !common.quiet;
    const SimulationResult sim = models::SimulateReduced(scene, options);
    if (sim.status != RunStatus::kOk || sim.points.size() < 2)
      throw Error(ErrorKind::kRuntime, "the forward model failed: " + sim.message, {.file = scene.source});

    // Exact rows: linear loading at a0 up to initiation, then growth rows
    // evenly spaced along the simulated path; time at a constant
    // displacement rate along it.
    std::vector<size_t> growth_index;  // nearest simulated point of each growth row
    ExperimentRecord exact = RecordAlongPath(sim, loading_points_, growth_points_, &growth_index);
    exact.time.assign(exact.size(), 0.0);
    for (size_t i = 1; i < exact.size(); ++i)
      exact.time[i] = exact.time[i - 1] +
                      std::abs(exact.displacement[i] - exact.displacement[i - 1]) / rate;

    // Speckle frames: frame 0 unloaded (row 0), frames 1.. spread over the
    // growth rows from initiation to the last row; each frame's growth row
    // index and record row.
    std::vector<size_t> frame_growth(frames_, 0), frame_row(frames_, 0);
    for (int f = 1; f < frames_; ++f) {
      const size_t g = frames_ <= 2 ? 0
                                    : static_cast<size_t>(std::llround(
                                          double(f - 1) * (growth_index.size() - 1) / (frames_ - 2)));
      frame_growth[f] = std::min(g, growth_index.size() - 1);
      frame_row[f] = loading_points_ + frame_growth[f];
    }
    auto frame_name = [](int f) { return fmt::format("frame_{:02d}.png", f); };

    std::mt19937_64 rng(seed_);
    std::normal_distribution<double> normal(0.0, 1.0);
    // With frames, an `image` column names the frame taken at a row (the
    // link `bridgefit rcurve --crack-length-from` uses).
    std::string csv = std::string("time [s], load [N], displacement [mm], crack_length [mm]") +
                      (frames_ > 0 ? ", image\n" : "\n");
    for (size_t i = 0; i < exact.size(); ++i) {
      const double load = exact.load[i] * (1.0 + load_noise_ * normal(rng));
      const double disp = exact.displacement[i] + (i == 0 ? 0.0 : disp_noise * normal(rng));
      const double crack = exact.crack_length[i] + crack_noise * normal(rng);
      csv += fmt::format("{:.4f}, {:.5f}, {:.6f}, {:.4f}", exact.time[i], load, disp * 1e3,
                         crack * 1e3);
      if (frames_ > 0) {
        const auto it = std::find(frame_row.begin(), frame_row.end(), i);
        csv += ", " + (it == frame_row.end() ? std::string()
                                             : "images/" + frame_name(static_cast<int>(it - frame_row.begin())));
      }
      csv += "\n";
    }
    std::filesystem::create_directories(out_);
    WriteTextFileAtomic(std::filesystem::path(out_) / record_name_, csv);

    // Speckle sequence: frame 0 unloaded, then frames spread over the growth.
    int frames_written = 0;
    if (frames_ > 0) {
      double scale = ParseOptionQuantity(scale_, Dimension::Length(), "--scale");
      double x0 = ParseOptionQuantity(image_x0_, Dimension::Length(), "--image-x0");
      // Issue 15: the window must hold the notch tip and stay on the
      // specimen (W for a CT, L for a DCB). The defaults (20 mm + 400 x
      // 0.15 mm) are kept where they do; otherwise, unless given, the
      // window runs from a tenth of the ligament before a0 to the end.
      const SpecimenSpec& spec = scene.specimen;
      const double end = spec.type == SpecimenType::kCT ? spec.width : spec.length;
      const double a0 = spec.notch;
      auto fits = [&](double origin, double per_px) {
        const double tip_px = (a0 - origin) / per_px;
        return tip_px >= 0.05 * image_width_ && origin + image_width_ * per_px <= end + 1e-12;
      };
      if (end > a0 && a0 > 0 && !fits(x0, scale)) {
        const bool given = scale_option_->count() > 0 || x0_option_->count() > 0;
        if (!given) {
          x0 = std::max(0.0, a0 - 0.1 * (end - a0));
          scale = (end - x0) / image_width_;
          std::cerr << fmt::format(
              "synth: image window {:.4g}..{:.4g} mm ({:.4g} mm/px) to fit the specimen (a0 = "
              "{:.4g} mm, end {:.4g} mm); --image-x0 and --scale set it\n",
              x0 * 1e3, (x0 + image_width_ * scale) * 1e3, scale * 1e3, a0 * 1e3, end * 1e3);
        } else {
          std::cerr << fmt::format(
              "warning: synth: the image window {:.4g}..{:.4g} mm does not hold the notch tip "
              "(a0 = {:.4g} mm) inside it or runs past the specimen end ({:.4g} mm)\n",
              x0 * 1e3, (x0 + image_width_ * scale) * 1e3, a0 * 1e3, end * 1e3);
        }
      }
      const MaterialSpec& m = scene.material;
      const double E = m.AxialModulus();
      const double nu = m.orthotropic ? m.nu12 : m.nu;
      const bool strain = scene.specimen.plane == PlaneCondition::kPlaneStrain;
      const double E_eff = strain ? E / (1 - nu * nu) : E;
      const double mu = m.orthotropic ? m.G12 : E / (2 * (1 + nu));
      const double kappa = strain ? 3 - 4 * nu : (3 - nu) / (1 + nu);
      dic::SpeckleOptions so;
      so.width = image_width_;
      so.height = image_height_;
      so.speckle_radius_px = 2.0;
      so.seed = seed_;
      const dic::SpeckleRenderer renderer(so);
      const std::filesystem::path dir = std::filesystem::path(out_) / "images";
      std::filesystem::create_directories(dir);
      std::string truth =
          "frame, record_row, crack_length [mm], tip_x [px], tip_y [px], K_I [MPa m^0.5], "
          "translation_x [px], translation_y [px]\n";
      Progress progress("synth: speckle frames", frames_, !common.quiet);
      for (int f = 0; f < frames_; ++f) {
        dic::ModeICrackField field;
        field.tip_y = 0.5 * image_height_;
        field.kappa = kappa;
        double a = scene.specimen.notch, K = 0.0;
        const size_t row = frame_row[f];
        if (f > 0) {
          const SimulationPoint& p = sim.points[growth_index[frame_growth[f]]];
          a = p.crack_length;
          // Far-field K (tip plus bridging), so the opening grows as in the test.
          const double J = std::isfinite(p.J_ff) ? p.J_ff : scene.fracture->J_tip_c;
          K = std::sqrt(E_eff * J);
        }
        field.tip_x = (a - x0) / scale;
        field.k_over_2mu = K / (2 * mu) / std::sqrt(scale);
        field.translation_x = 0.3 * f;
        field.translation_y = -0.2 * f;
        const dic::Image image = f == 0 ? renderer.RenderReference(seed_ * 1000 + f)
                                        : renderer.Render(field, seed_ * 1000 + f);
        dic::WriteImage(dir / frame_name(f), image, 8);
        truth += fmt::format("{}, {}, {:.4f}, {:.3f}, {:.3f}, {:.5f}, {:.3f}, {:.3f}\n", f, row, a * 1e3,
                             field.tip_x, field.tip_y, K * 1e-6, field.translation_x, field.translation_y);
        ++frames_written;
        progress.Update(f + 1);
      }
      progress.Finish();
      WriteTextFileAtomic(dir / "truth.csv", truth);
    }

    if (common.json) {
      PrintJson({{"record", (std::filesystem::path(out_) / record_name_).string()},
                 {"rows", exact.size()},
                 {"frames", frames_written},
                 {"initiation_load_N", sim.points.front().load},
                 {"final_crack_length_m", sim.points.back().crack_length},
                 {"wall_s", watch.Seconds()}});
    } else {
      std::cout << fmt::format("synth: {} rows, {} frames in {} ({:.2f} s)\n", exact.size(),
                               frames_written, out_, watch.Seconds());
    }
    return 0;
  }

 private:
  std::string scene_, out_, record_name_ = "record.csv", resolution_, disp_noise_, crack_noise_, rate_, scale_, image_x0_;
  CLI::Option* scale_option_ = nullptr;
  CLI::Option* x0_option_ = nullptr;
  std::uint64_t seed_ = 1;
  int loading_points_ = 20, growth_points_ = 400, frames_ = 10, image_width_ = 400,
      image_height_ = 300;
  double load_noise_ = 0.005;
};

}  // namespace

std::unique_ptr<Command> MakeSynthCommand() { return std::make_unique<SynthCommand>(); }

}  // namespace bridgefit::cli
