// One effective modulus for an orthotropic DCB (issue 16): synth's speckle
// field (K = sqrt(E' J_ff)), the analytic model and the reduced model's
// crack plane all use specimen::EffectiveModulus (Sih-Paris-Irwin), which
// for this composite (E1 19.3 GPa, E2 6 GPa, G12 3 GPa, nu12 0.3, plane
// stress) is about 7.0 GPa: synth and the analytic model used E1 before.
#include <gtest/gtest.h>

#include <cmath>

#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/synth.hpp"
#include "bridgefit/specimen/calibrations.hpp"
#include "bridgefit/specimen/crack_plane.hpp"

namespace bridgefit::pipeline {
namespace {

TEST(EffectiveModulus, SynthAnalyticAndReducedAgreeForAnOrthotropicDcb) {
  Scene scene = io::ReadSceneFile(std::string(BRIDGEFIT_TEST_DATA_DIR) + "/scenes/dcb_composite.toml");
  ASSERT_TRUE(scene.material.orthotropic);
  ASSERT_EQ(scene.specimen.type, SpecimenType::kDCB);
  const double expected = specimen::EffectiveModulus(scene.material, scene.specimen.plane);
  // Sih-Paris-Irwin against the plain E1: a real difference, not a rounding.
  EXPECT_NEAR(expected, 7.0e9, 0.05e9);

  const auto analytic = inverse::MakeAnalyticForwardModel(scene);
  EXPECT_DOUBLE_EQ(analytic->effective_modulus(), expected);

  specimen::CrackPlaneOptions plane;
  plane.resolution = 2e-3;
  plane.max_crack_length = scene.specimen.notch + 0.02;
  EXPECT_DOUBLE_EQ(specimen::BuildCrackPlaneModel(scene, plane).effective_modulus, expected);

  SynthRequest request;
  request.scene = scene;
  request.resolution = 0.5e-3;
  request.frames = 3;
  request.image_width = 64;
  request.image_height = 48;
  request.scale = 1e-3;
  request.image_x0 = scene.specimen.notch - 0.02;
  const SynthTest test = MakeSyntheticTest(request);
  EXPECT_DOUBLE_EQ(test.effective_modulus, expected);
  ASSERT_EQ(test.frames.size(), 3u);
  for (const SynthFrame& f : test.frames) {
    if (f.index == 0) continue;
    ASSERT_GT(f.J_ff, 0.0);
    EXPECT_NEAR(f.K_I * f.K_I / f.J_ff / expected, 1.0, 1e-12) << "frame " << f.index;
  }
}

}  // namespace
}  // namespace bridgefit::pipeline
