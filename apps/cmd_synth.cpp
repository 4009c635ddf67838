// `bridgefit synth`: a synthetic fracture test from a scene, by the reduced
// forward model: a load-displacement record with noise and, optionally, a
// short speckle sequence whose crack tip follows the simulated crack length.
//   bridgefit synth data_samples/mdf_ct/scene.toml --out data_samples/mdf_ct --seed 1
//   bridgefit synth scene.toml --out DIR --seed 7 --frames 0        (record only)
// Writes DIR/record.csv (`time [s], load [N], displacement [mm], crack_length [mm]`),
// DIR/images/frame_NN.png and DIR/images/truth.csv (true tip per frame).

#include <filesystem>
#include <iostream>
#include <string>

#include <fmt/format.h>

#include "bridgefit/core/units.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/synth.hpp"
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
    sub.add_option("--far-field", far_field_,
                   "Reduced model's far-field element as a multiple of its default (W/40 CT, h "
                   "DCB); below 1 refines the far field too")
        ->default_val(1.0);
    sub.add_option("--loading-points", loading_points_, "Rows before initiation")->default_val(20);
    sub.add_option("--growth-points", growth_points_, "Rows during growth")->default_val(400);
    sub.add_option("--load-noise", load_noise_, "Relative load noise, 1 sigma")->default_val(0.005);
    sub.add_option("--displacement-noise", disp_noise_, "Displacement noise, 1 sigma")
        ->default_val("1 um");
    sub.add_option("--crack-noise", crack_noise_, "Crack-length noise, 1 sigma")->default_val("0.3 mm");
    sub.add_option("--record-name", record_name_, "File name of the record")->default_val("record.csv");
    sub.add_option("--rate", rate_, "Displacement rate")->default_val("1 mm");
    sub.add_option("--frames", frames_, "Speckle frames (0: none)")->default_val(10);
    sub.add_flag("--bridged-field", bridged_field_,
                 "Frames show a bridged crack (the scene's law on the faces from the notch root, "
                 "K_tip = K_tip,c) instead of the LEFM field of the model's J_ff");
    sub.add_option("--image-width", image_width_, "px")->default_val(400);
    sub.add_option("--image-height", image_height_, "px")->default_val(300);
    sub.add_option("--scale", scale_,
                   "Image scale per px (default 0.15 mm where the default window fits the "
                   "specimen, else what fits it)");
    sub.add_option("--image-x0", image_x0_,
                   "Distance of the image's left edge from the load line (default 20 mm where "
                   "the default window fits the specimen, else a tenth of the ligament before a0)");
  }

  int Run(const CommonOptions& common) override {
    pipeline::SynthRequest request;
    request.scene = io::ReadSceneFile(scene_);
    request.seed = seed_;
    if (!resolution_.empty())
      request.resolution = ParseOptionQuantity(resolution_, Dimension::Length(), "--resolution");
    request.far_field = far_field_;
    request.loading_rows = loading_points_;
    request.growth_rows = growth_points_;
    request.load_noise = load_noise_;
    request.displacement_noise =
        ParseOptionQuantity(disp_noise_, Dimension::Length(), "--displacement-noise");
    request.crack_noise = ParseOptionQuantity(crack_noise_, Dimension::Length(), "--crack-noise");
    request.displacement_rate =
        ParseOptionQuantity(rate_, Dimension::Length(), "--rate") / 60.0;  // per minute
    request.frames = frames_;
    if (frames_ > 0 && !scale_.empty())
      request.scale = ParseOptionQuantity(scale_, Dimension::Length(), "--scale");
    if (frames_ > 0 && !image_x0_.empty())
      request.image_x0 = ParseOptionQuantity(image_x0_, Dimension::Length(), "--image-x0");
    request.image_width = image_width_;
    request.bridged_field = bridged_field_;
    request.image_height = image_height_;
    request.progress = !common.quiet;
    const pipeline::SynthTest test = pipeline::MakeSyntheticTest(request);
    pipeline::WriteSyntheticTest(test, out_, record_name_);
    const int frames_written = static_cast<int>(test.frames.size());
    if (!test.window.note.empty()) std::cerr << test.window.note << "\n";
    if (!test.window.warning.empty()) std::cerr << "warning: " << test.window.warning << "\n";
    if (common.json) {
      PrintJson({{"record", (std::filesystem::path(out_) / record_name_).string()},
                 {"rows", test.exact.size()},
                 {"frames", frames_written},
                 {"initiation_load_N", test.simulation.points.front().load},
                 {"final_crack_length_m", test.simulation.points.back().crack_length},
                 {"image_x0_m", frames_written > 0 ? nlohmann::json(test.window.x0) : nlohmann::json()},
                 {"image_scale_m_per_px",
                  frames_written > 0 ? nlohmann::json(test.window.scale) : nlohmann::json()},
                 {"image_window_fits", test.window.fits},
                 {"wall_s", test.wall_s}});
    } else {
      std::cout << fmt::format("synth: {} rows, {} frames in {} ({:.2f} s)\n", test.exact.size(),
                               frames_written, out_, test.wall_s);
      if (frames_written > 0)
        std::cout << fmt::format("  image window {:.4g}..{:.4g} mm from the load line, {:.4g} mm/px\n",
                                 test.window.x0 * 1e3,
                                 (test.window.x0 + image_width_ * test.window.scale) * 1e3,
                                 test.window.scale * 1e3);
    }
    return 0;
  }

 private:
  std::string scene_, out_, record_name_ = "record.csv", resolution_, disp_noise_, crack_noise_, rate_, scale_, image_x0_;
  std::uint64_t seed_ = 1;
  int loading_points_ = 20, growth_points_ = 400, frames_ = 10, image_width_ = 400,
      image_height_ = 300;
  double load_noise_ = 0.005, far_field_ = 1.0;
  bool bridged_field_ = false;
};

}  // namespace

std::unique_ptr<Command> MakeSynthCommand() { return std::make_unique<SynthCommand>(); }

}  // namespace bridgefit::cli
