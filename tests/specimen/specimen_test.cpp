// Specimen calibrations and the finite-element crack-plane Green's function,
// checked against handbook LEFM solutions (ASTM E399, Saxena-Hudak, corrected
// beam theory, Tada's edge crack).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "bridgefit/scene/reference.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/specimen/calibrations.hpp"
#include "bridgefit/specimen/crack_plane.hpp"

namespace bridgefit {
namespace {

Scene CtScene(double notch_over_w, PlaneCondition plane = PlaneCondition::kPlaneStress) {
  Scene scene = ReferenceCtScene(notch_over_w * 0.1);
  scene.specimen.plane = plane;
  return scene;
}

Scene DcbScene() {
  Scene scene;
  scene.source = "test";
  scene.specimen.type = SpecimenType::kDCB;
  scene.specimen.width = 0.025;   // b
  scene.specimen.height = 0.003;  // h (one arm)
  scene.specimen.length = 0.15;
  scene.specimen.notch = 0.05;
  scene.material.orthotropic = true;
  scene.material.E1 = 120e9;
  scene.material.E2 = 9e9;
  scene.material.G12 = 5e9;
  scene.material.G13 = 5e9;
  scene.material.nu12 = 0.3;
  scene.fracture = FractureSpec{300.0};
  return scene;
}

std::vector<double> NoClosing(int tip) { return std::vector<double>(tip + 1, 0.0); }

TEST(CtCalibration, MatchesE399Table) {
  // ASTM E399 tabulates f(0.5) = 9.66 and f(0.45) = 8.34.
  EXPECT_NEAR(specimen::CtGeometryFactor(0.5), 9.66, 0.005);
  EXPECT_NEAR(specimen::CtGeometryFactor(0.45), 8.34, 0.005);
  EXPECT_THROW(specimen::CtGeometryFactor(0.1), Error);
  EXPECT_THROW(specimen::CtLoadLineComplianceFactor(0.99), Error);
}

TEST(EffectiveModulus, IsotropicLimitOfOrthotropic) {
  MaterialSpec iso{.E = 3e9, .nu = 0.3};
  MaterialSpec ortho{.orthotropic = true, .E1 = 3e9, .E2 = 3e9, .G12 = 3e9 / 2.6, .nu12 = 0.3};
  for (auto plane : {PlaneCondition::kPlaneStress, PlaneCondition::kPlaneStrain})
    EXPECT_NEAR(specimen::EffectiveModulus(ortho, plane) / specimen::EffectiveModulus(iso, plane),
                1.0, 1e-12);
  EXPECT_NEAR(specimen::EffectiveModulus(iso, PlaneCondition::kPlaneStrain), 3e9 / 0.91, 1.0);
}

// K/P within 1% of E399 and load-line compliance within 2% of Saxena-Hudak,
// in plane stress and plane strain (E' = E / (1 - nu^2)).
class CtFiniteElement : public ::testing::TestWithParam<PlaneCondition> {};
INSTANTIATE_TEST_SUITE_P(Planes, CtFiniteElement,
                         ::testing::Values(PlaneCondition::kPlaneStress,
                                           PlaneCondition::kPlaneStrain));
TEST_P(CtFiniteElement, FiniteElementMatchesE399AndSaxenaHudak) {
  const Scene scene = CtScene(0.3, GetParam());
  specimen::CrackPlaneOptions options;
  options.max_crack_length = 0.08;
  const auto model = specimen::BuildCrackPlaneModel(scene, options);
  const double W = scene.specimen.width;
  const double E = model.effective_modulus;
  double worst_k = 0.0, worst_c = 0.0;
  for (int tip = 1; tip < model.size(); ++tip) {
    const double a = model.CrackLength(tip);
    const double alpha = a / W;
    if (std::fmod(std::lround(alpha * 1000.0), 50) != 0) continue;  // a/W = 0.30, 0.35, ...
    const auto state = models::SolveLinearTip(model, tip, 1.0, NoClosing(tip));
    const double K = std::sqrt(state.J_tip * E);               // per unit load p = P/B
    const double K_e399 = specimen::CtGeometryFactor(alpha) / std::sqrt(W);
    const double C = 2.0 * state.half_gauge_opening;  // load-line opening per unit p
    const double C_sh = specimen::CtLoadLineComplianceFactor(alpha) / E;
    std::printf("a/W=%.3f K/K_E399=%.5f C/C_SH=%.5f\n", alpha, K / K_e399, C / C_sh);
    worst_k = std::max(worst_k, std::abs(K / K_e399 - 1.0));
    worst_c = std::max(worst_c, std::abs(C / C_sh - 1.0));
  }
  EXPECT_LT(worst_k, 0.01);
  EXPECT_LT(worst_c, 0.02);
}

// Isotropic DCB (the composite sample's geometry), plane stress and strain:
// corrected beam theory (chi = 0.663 here) and the elastic foundation agree
// with the finite-element model to 1%.
TEST(CrackPlaneModel, IsotropicDcbMatchesBeamTheories) {
  for (auto plane : {PlaneCondition::kPlaneStress, PlaneCondition::kPlaneStrain}) {
    Scene scene;
    scene.source = "test";
    scene.specimen = {.type = SpecimenType::kDCB, .width = 0.025, .height = 0.0027,
                      .length = 0.123, .notch = 0.0376, .plane = plane};
    scene.material = {.E = 19.3e9, .nu = 0.3};
    const auto model = specimen::BuildCrackPlaneModel(scene, {});
    auto beam = specimen::DcbBeamFromScene(scene.specimen, scene.material);
    // A plane-strain arm bends with E / (1 - nu^2).
    if (plane == PlaneCondition::kPlaneStrain) beam.E1 = beam.E2 = 19.3e9 / (1.0 - 0.09);
    for (int tip = 1; tip < model.size(); tip += 20) {
      const double a = model.CrackLength(tip);
      const auto state = models::SolveLinearTip(model, tip, 1.0 / 0.025, NoClosing(tip));
      const double C = 2.0 * state.half_load_line_displacement;
      EXPECT_NEAR(C / specimen::DcbCbtCompliance(beam, a), 1.0, 0.01) << a;
      EXPECT_NEAR(state.J_tip / specimen::DcbCbtEnergyReleaseRate(beam, a, 1.0), 1.0, 0.01) << a;
      EXPECT_NEAR(C / specimen::DcbFoundationCompliance(beam, a), 1.0, 0.01) << a;
    }
  }
}

TEST(CrackPlaneModel, DcbMatchesCorrectedBeamTheory) {
  const Scene scene = DcbScene();
  specimen::CrackPlaneOptions options;
  options.max_crack_length = 0.1;
  const auto model = specimen::BuildCrackPlaneModel(scene, options);
  const auto beam = specimen::DcbBeamFromScene(scene.specimen, scene.material);
  const double b = scene.specimen.width;
  double worst_c = 0.0, worst_g = 0.0;
  for (int tip = 1; tip < model.size(); tip += 10) {
    const double a = model.CrackLength(tip);
    const auto state = models::SolveLinearTip(model, tip, 1.0 / b, NoClosing(tip));  // P = 1 N
    const double C = 2.0 * state.half_load_line_displacement;
    const double C_cbt = specimen::DcbCbtCompliance(beam, a);
    const double G_cbt = specimen::DcbCbtEnergyReleaseRate(beam, a, 1.0);
    const double C_bef = specimen::DcbFoundationCompliance(beam, a);
    std::printf("a=%.1f mm C/C_cbt=%.5f G/G_cbt=%.5f C/C_bef=%.5f\n", a * 1e3, C / C_cbt,
                state.J_tip / G_cbt, C / C_bef);
    worst_c = std::max(worst_c, std::abs(C / C_cbt - 1.0));
    worst_g = std::max(worst_g, std::abs(state.J_tip / G_cbt - 1.0));
  }
  EXPECT_LT(worst_c, 0.02);
  EXPECT_LT(worst_g, 0.02);
}

// Uniform pressure on the faces of an edge crack: K = sigma sqrt(pi a) F(a/b).
TEST(CrackPlaneModel, EdgeCrackFacePressureMatchesHandbook) {
  const specimen::EdgeCrackStrip strip{.width = 0.1, .half_height = 0.3, .notch = 0.01,
                                       .max_crack_length = 0.06};
  const MaterialSpec material{.E = 1e9, .nu = 0.25};
  const auto model = specimen::BuildEdgeCrackStripModel(strip, material,
                                                        PlaneCondition::kPlaneStrain, {});
  const double sigma = 1e6, h = model.resolution;
  double worst = 0.0;
  for (int tip = 1; tip < model.size(); ++tip) {
    const double a = model.CrackLength(tip);
    if (std::fmod(std::lround(a / strip.width * 1000.0), 50) != 0) continue;
    // Pressure on the retained faces as opening (negative closing) nodal forces.
    std::vector<double> closing(tip + 1, 0.0);
    // Node 0 (a0 - h) gets the other half of its face from the load pattern.
    for (int r = 0; r <= tip; ++r) closing[r] = -sigma * (r == 0 ? 0.5 * h : h);
    const auto state = models::SolveLinearTip(model, tip, sigma, closing);
    const double K = std::sqrt(state.J_tip * model.effective_modulus);
    const double K_ref = sigma * std::sqrt(M_PI * a) * specimen::EdgeCrackFactor(a / strip.width);
    std::printf("a/b=%.3f K/K_tada=%.5f\n", a / strip.width, K / K_ref);
    worst = std::max(worst, std::abs(K / K_ref - 1.0));
  }
  EXPECT_LT(worst, 0.01);
}

TEST(CrackPlaneModel, BadGeometriesGiveClearErrors) {
  Scene shallow = CtScene(0.1);
  try {
    specimen::BuildCrackPlaneModel(shallow, {});
    FAIL() << "a0/W = 0.1 accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.context().field, "specimen.notch");
    EXPECT_NE(std::string(e.what()).find("a0/W"), std::string::npos);
  }
  Scene thin = CtScene(0.3);
  thin.specimen.thickness = 0.0;
  try {
    specimen::BuildCrackPlaneModel(thin, {});
    FAIL() << "zero thickness accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.context().field, "specimen.thickness");
  }
}

}  // namespace
}  // namespace bridgefit
