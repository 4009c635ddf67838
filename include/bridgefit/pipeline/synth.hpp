#pragma once
// A synthetic fracture test from a scene (`bridgefit synth`, issue 16): the
// reduced model's path as a load-displacement record with noise and, when
// asked, a short speckle sequence whose crack tip follows the simulated
// crack length (a mode-I LEFM field with K = sqrt(E' J_ff), E' the one
// effective modulus of specimen::EffectiveModulus).

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/dic/image.hpp"
#include "bridgefit/dic/speckle.hpp"
#include "bridgefit/scene/scene.hpp"

namespace bridgefit::pipeline {

struct SynthRequest {
  Scene scene;  // the truth; needs [fracture]
  std::uint64_t seed = 1;     // noise and speckle
  double resolution = NAN;    // reduced model element size [m]; NaN: its default
  int loading_rows = 20, growth_rows = 400;
  double load_noise = 0.005;           // relative, 1 sigma
  double displacement_noise = 1e-6;    // [m], 1 sigma
  double crack_noise = 0.3e-3;         // [m], 1 sigma
  double displacement_rate = 1e-3 / 60.0;  // [m/s], sets the time column
  int frames = 10;                     // speckle frames (0: none)
  int image_width = 400, image_height = 300;  // [px]
  double scale = 0.15e-3;              // [m/px]
  double image_x0 = 20e-3;             // image's left edge from the load line [m]
  bool progress = false;
  void Check() const;  // throws Error (kUsage / kInput) naming the field
};

struct SynthFrame {
  int index = 0;
  std::size_t record_row = 0;  // the record row the frame was taken at
  double crack_length = 0.0;   // [m], the true tip
  double K_I = 0.0;            // [Pa m^0.5]
  double J_ff = NAN;           // far-field J the K is made from [J/m^2]
  dic::ModeICrackField field;  // the displacement field rendered
  dic::Image image;
};

struct SynthTest {
  SimulationResult simulation;  // the reduced model's path
  ExperimentRecord exact;       // rows along the path, without noise
  // The record as written: time [s], load [N], displacement [mm],
  // crack_length [mm] (noisy) and, with frames, the image each row names.
  std::string record_csv;
  std::vector<SynthFrame> frames;
  double effective_modulus = NAN;  // E' [Pa]
  double wall_s = 0.0;
  std::string TruthCsv() const;  // images/truth.csv: the true tip per frame
};

SynthTest MakeSyntheticTest(const SynthRequest& request);

// DIR/record_name, DIR/images/frame_NN.png and DIR/images/truth.csv.
void WriteSyntheticTest(const SynthTest& test, const std::filesystem::path& dir,
                        const std::string& record_name);

std::string SynthFrameName(int frame);  // "frame_NN.png"

}  // namespace bridgefit::pipeline
