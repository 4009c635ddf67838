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
  // The reduced model's largest (far-field) element as a multiple of its
  // default (CT W/40, DCB h: models::ReducedOptions mesh.coarse_factor).
  // Below 1 the far field is refined too: refining `resolution` alone does
  // not refine it (docs/REDUCED.md section 5), so a record meant to be made
  // by a model finer than the fit's everywhere takes e.g. 0.5.
  double far_field = 1.0;
  int loading_rows = 20, growth_rows = 400;
  double load_noise = 0.005;           // relative, 1 sigma
  double displacement_noise = 1e-6;    // [m], 1 sigma
  double crack_noise = 0.3e-3;         // [m], 1 sigma
  double displacement_rate = 1e-3 / 60.0;  // [m/s], sets the time column
  int frames = 10;                     // speckle frames (0: none)
  int image_width = 400, image_height = 300;  // [px]
  // The image window; NaN: chosen by SynthImageWindow (the default window
  // where it fits the specimen, else one that does).
  double scale = NAN;                  // [m/px]
  double image_x0 = NAN;               // image's left edge from the load line [m]
  // false: each frame is the unbridged LEFM field of K = sqrt(E' J_ff) (the
  // reduced model's J_ff). true (needs [bridging]): a bridged crack
  // (dic::BridgedCrackField, semi-infinite, plane elasticity) whose faces
  // from the notch root a0 to the tip carry the scene's law and whose
  // applied K is solved so that K_tip = sqrt(E' J_tip,c): the frames then
  // obey PHYSICS eq. (1) exactly (J_ff = J_tip,c + W(delta_root)) with the
  // opening of this field, not the finite specimen's (issue 21).
  bool bridged_field = false;
  bool progress = false;
  void Check() const;  // throws Error (kUsage / kInput) naming the field
};

// The speckle frames' window along the crack (issue 15). The default,
// 20 mm + width x 0.15 mm from the load line, is kept where it holds the
// notch tip (at least 5% of the width in from the left edge) and stays on the
// specimen (W for a CT, L for a DCB). Where it does not and neither is given,
// the window runs from a tenth of the ligament before a0 to the specimen's
// end, and `note` says so; a given window (either value) that does not fit is
// kept and `warning` says why (the other value takes its default).
struct SynthWindow {
  double x0 = NAN;     // [m]
  double scale = NAN;  // [m/px]
  bool fits = true;    // holds the notch tip and stays on the specimen
  std::string note, warning;
};
SynthWindow SynthImageWindow(const SpecimenSpec& specimen, int image_width_px, double given_x0,
                             double given_scale);

// What the frames' field is not: they show a crack in an infinite plate
// (the LEFM field of the model's J_ff, or the bridged crack), not the
// specimen's own field. For a DCB (whose arms bend) always a note, with the
// image's height against the beam's 2 h where the speckle runs past it; for
// a CT where the image is taller than the specimen. Empty otherwise.
std::string SynthFieldNote(const SpecimenSpec& specimen, const SynthWindow& window,
                           int image_height_px);

struct SynthFrame {
  int index = 0;
  std::size_t record_row = 0;  // the record row the frame was taken at
  double crack_length = 0.0;   // [m], the true tip
  double K_I = 0.0;            // [Pa m^0.5]
  double J_ff = NAN;           // far-field J the K is made from [J/m^2]
  double delta_root = NAN;     // bridged field: opening at the notch root [m]
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
  SynthWindow window;              // the frames' window (with frames)
  double wall_s = 0.0;
  std::string TruthCsv() const;  // images/truth.csv: the true tip per frame
};

SynthTest MakeSyntheticTest(const SynthRequest& request);

// DIR/record_name, DIR/images/frame_NN.png and DIR/images/truth.csv.
void WriteSyntheticTest(const SynthTest& test, const std::filesystem::path& dir,
                        const std::string& record_name);

std::string SynthFrameName(int frame);  // "frame_NN.png"

}  // namespace bridgefit::pipeline
