// synth's image window follows the specimen (issue 15): on a W = 50 mm CT
// the old default window (20 mm + 400 x 0.15 mm) ran to 80 mm, past the
// back edge, and put the a0 = 20 mm tip on the image's left edge, silently.
// Oracles: geometry (the notch tip inside the window, the window on the
// specimen) and the frames' true tips (truth) inside the image; the bundled
// samples, where the default fits, keep it exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/synth.hpp"

namespace bridgefit::pipeline {
namespace {

Scene SmallCt() {
  Scene scene = io::ReadSceneFile(std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/mdf_ct/scene.toml");
  scene.specimen.width = 50e-3;
  scene.specimen.height = 60e-3;
  scene.specimen.notch = 20e-3;
  scene.run.max_crack_length = 35e-3;
  return scene;
}

bool Contains(const std::string& text, const std::string& word) {
  return text.find(word) != std::string::npos;
}

TEST(SynthWindow, DefaultKeptWhereItFitsTheSpecimen) {
  for (const char* sample : {"mdf_ct", "pb_ct", "dcb_composite"}) {
    const Scene scene =
        io::ReadSceneFile(std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/" + sample + "/scene.toml");
    const SynthWindow w = SynthImageWindow(scene.specimen, 400, NAN, NAN);
    EXPECT_EQ(w.x0, 20e-3) << sample;
    EXPECT_EQ(w.scale, 0.15e-3) << sample;
    EXPECT_TRUE(w.fits) << sample;
    EXPECT_TRUE(w.note.empty() && w.warning.empty()) << sample << ": " << w.note << w.warning;
  }
}

// The frames are a plate's field: said for a DCB (the bundled sample's
// 2 h = 5.4 mm under a 45 mm image) and for a CT shorter than the image,
// not for the bundled CTs (120 mm and more under 45 mm).
TEST(SynthWindow, APlateFieldOnASpecimenItDoesNotFitIsSaid) {
  for (const char* sample : {"mdf_ct", "pb_ct"}) {
    const Scene scene = io::ReadSceneFile(std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/" +
                                          sample + "/scene.toml");
    const SynthWindow w = SynthImageWindow(scene.specimen, 400, NAN, NAN);
    EXPECT_EQ(SynthFieldNote(scene.specimen, w, 300), "") << sample;
  }
  const Scene dcb = io::ReadSceneFile(std::string(BRIDGEFIT_SOURCE_DIR) +
                                      "/data_samples/dcb_composite/scene.toml");
  const SynthWindow w = SynthImageWindow(dcb.specimen, 400, NAN, NAN);
  const std::string note = SynthFieldNote(dcb.specimen, w, 300);
  for (const char* word : {"infinite plate", "DCB", "45 mm tall", "5.4 mm (2 h)", "truth.csv"})
    EXPECT_TRUE(Contains(note, word)) << word << " in: " << note;
  EXPECT_FALSE(Contains(SynthFieldNote(dcb.specimen, w, 30), "tall")) << "4.5 mm fits 5.4";
  Scene ct = SmallCt();
  ct.specimen.height = 30e-3;
  const SynthWindow wc = SynthImageWindow(ct.specimen, 400, NAN, NAN);
  const std::string ct_note = SynthFieldNote(ct.specimen, wc, 400);
  EXPECT_TRUE(Contains(ct_note, "against the specimen's 30 mm (H)")) << ct_note;
}

TEST(SynthWindow, SmallCtGetsAWindowOnTheSpecimenWithTheTipInside) {
  const Scene scene = SmallCt();
  const SynthWindow w = SynthImageWindow(scene.specimen, 400, NAN, NAN);
  EXPECT_TRUE(w.fits);
  const double tip_px = (scene.specimen.notch - w.x0) / w.scale;
  EXPECT_GE(tip_px, 0.05 * 400);
  EXPECT_LE(w.x0 + 400 * w.scale, scene.specimen.width * (1 + 1e-12));
  EXPECT_GE(w.x0, 0.0);
  // Said, with the numbers and the options that set it.
  for (const char* word : {"does not fit this specimen", "a0 = 20 mm", "W = 50 mm", "--image-x0", "--scale"})
    EXPECT_TRUE(Contains(w.note, word)) << word << " in: " << w.note;
  EXPECT_TRUE(w.warning.empty());
}

TEST(SynthWindow, GivenWindowThatDoesNotFitIsKeptAndWarned) {
  const Scene scene = SmallCt();
  const SynthWindow w = SynthImageWindow(scene.specimen, 400, 20e-3, NAN);  // x0 given: the old default
  EXPECT_EQ(w.x0, 20e-3);
  EXPECT_EQ(w.scale, 0.15e-3);
  EXPECT_FALSE(w.fits);
  for (const char* word : {"does not hold the notch tip", "W = 50 mm", "--image-x0", "--scale"})
    EXPECT_TRUE(Contains(w.warning, word)) << word << " in: " << w.warning;
  // A given window that fits: no word.
  const SynthWindow ok = SynthImageWindow(scene.specimen, 400, 15e-3, 0.08e-3);
  EXPECT_TRUE(ok.fits);
  EXPECT_TRUE(ok.note.empty() && ok.warning.empty());
}

// End to end: every frame's true tip is inside the image (at least 5% of
// the width from the left edge), as the truth file states it.
TEST(SynthWindow, FramesOfASmallCtShowTheCrackTip) {
  SynthRequest request;
  request.scene = SmallCt();
  request.resolution = 2e-3;
  request.growth_rows = 40;
  request.frames = 3;
  const SynthTest test = MakeSyntheticTest(request);
  ASSERT_EQ(test.frames.size(), 3u);
  EXPECT_FALSE(test.window.note.empty());
  for (const SynthFrame& f : test.frames) {
    EXPECT_GE(f.field.tip_x, 0.05 * request.image_width) << "frame " << f.index;
    EXPECT_LT(f.field.tip_x, request.image_width) << "frame " << f.index;
    EXPECT_NEAR(test.window.x0 + f.field.tip_x * test.window.scale, f.crack_length, 1e-12);
  }
  // The scale is checked before any work.
  request.scale = -1e-4;
  EXPECT_THROW(MakeSyntheticTest(request), Error);
}

// The generator's far field (SynthRequest::far_field): refining only the
// element size leaves the largest element at W/40 and the load-line
// compliance 0.7% below its converged value (docs/REDUCED.md section 5: MDF
// CT at 1 mm, 0.443516 um/N, far field W/160 0.446580); half the far-field
// element moves the initial compliance up, towards it, by 0.2-1%.
TEST(SynthWindow, AFinerFarFieldRaisesTheInitialCompliance) {
  SynthRequest request;
  request.scene = io::ReadSceneFile(std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/mdf_ct/scene.toml");
  request.resolution = 1e-3;
  request.growth_rows = 20;
  request.frames = 0;
  const auto compliance = [&](double far_field) {
    request.far_field = far_field;
    const SynthTest test = MakeSyntheticTest(request);
    return test.exact.displacement[1] / test.exact.load[1];  // on the linear loading branch
  };
  const double standard = compliance(1.0), refined = compliance(0.5);
  std::printf("initial compliance %.6g um/N (far field W/40), %.6g (W/80)\n", standard * 1e6,
              refined * 1e6);
  EXPECT_GT(refined / standard - 1.0, 0.002);
  EXPECT_LT(refined / standard - 1.0, 0.01);
  for (double bad : {0.0, 1.5, double(NAN)}) {
    request.far_field = bad;
    EXPECT_THROW(request.Check(), Error) << bad;
  }
}

}  // namespace
}  // namespace bridgefit::pipeline
