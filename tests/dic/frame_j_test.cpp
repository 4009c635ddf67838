// J per frame (dic::ComputeFrameJ) on fields that carry what no crack
// does: a rigid rotation (a specimen turning in its grips) and a uniform
// dilatation (a 2D DIC's magnification change from out-of-plane motion, a
// thermal or moisture strain). Both are stress-free; read as strain they
// load the crack's faces and J_ff was far off with status ok.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "bridgefit/dic/frame_j.hpp"
#include "lefm_grid_field.hpp"

namespace bridgefit::dic {
namespace {

using namespace test_fields;

// J per frame of LefmField's crack with the notch root at its tip (the
// line starts at x = -150 px).
FrameJOptions RootAtTheTip() {
  FrameJOptions o;
  o.enabled = true;
  o.elastic = ElasticConstants::Isotropic(kE, kNu);
  o.notch_length_m = 150.5 * kPx;
  return o;
}

// A rigid rotation of the whole field (a specimen turning in its grips)
// enters the small-strain gradient as the equibiaxial strain
// -(1 - cos theta): an LEFM field turned by 1 degree read J_ff 31.5 J/m^2
// for 200 (status ok), by 3 degrees -1364. ComputeFrameJ takes it out:
// the field turned exactly (deformed positions, about a point off the
// field's centre) by 0-10 degrees gives J_ff within 2 % of K^2 / E and
// within 0.1 % of the unturned field's, domains and field-wide fit alike.
TEST(FrameJ, ARigidRotationOfTheFieldLeavesJUnchanged) {
  const ModeICrackField m = LefmField();
  const CrackGeometry crack = CrackOf(m.tip_x, m.tip_y, 1, 0);
  const FrameJOptions o = RootAtTheTip();
  const double exact = JFromKOver2mu(m.k_over_2mu);
  double plain = 0, plain_fit = 0;
  for (double degrees : {0.0, 1.0, 3.0, 10.0}) {
    SCOPED_TRACE(degrees);
    const double theta = degrees * std::numbers::pi / 180;
    DisplacementField f = SampleGrid(m, crack, 150, 150, 2);
    for (std::size_t i = 0; i < f.size(); ++i) {
      const double X = f.x[i] + f.u[i] - 40, Y = f.y[i] + f.v[i] + 70;
      f.u[i] = std::cos(theta) * X - std::sin(theta) * Y + 40 - f.x[i];
      f.v[i] = std::sin(theta) * X + std::cos(theta) * Y - 70 - f.y[i];
    }
    const FrameJ j = ComputeFrameJ(f, m.tip_x, m.tip_y, 150.5, 1, 0, 2.0, kPx, 0, o);
    ASSERT_EQ(j.status, FrameJStatus::kOk) << j.why;
    ASSERT_EQ(j.fit.status, FieldFitJStatus::kOk);
    if (degrees == 0) {
      plain = j.J_ff;
      plain_fit = j.fit.J;
    }
    std::printf("turned %.0f deg: J_ff %.3f (fit %.3f, exact %.3f) J/m^2, rotation taken out %.5f rad\n",
                degrees, j.J_ff, j.fit.J, exact, j.rigid_rotation_rad);
    EXPECT_NEAR(j.J_ff / exact, 1.0, 0.02);
    EXPECT_NEAR(j.J_ff / plain, 1.0, 1e-3);
    EXPECT_NEAR(j.fit.J / plain_fit, 1.0, 1e-3);
    if (degrees > 0) EXPECT_NEAR(j.rigid_rotation_rad, theta, 1e-3);
  }
}

// A uniform dilatation e (u += e (x - x0), v += e (y - y0)) on the LEFM
// field with 0.3 % noise: 1e-4 read J_ff +29 % (domains) and +26 % (fit)
// on a field in mm (docs/LAW_FREE.md). The field-wide fit shows it (|e| >
// 3 standard errors), takes it out of J and of the field the domains read:
// J_ff within 2 % of K^2 / E at e = 1e-4 and 1e-3; at e = 0 nothing is
// taken out and the frame's J is the plain fit's.
TEST(FrameJ, AnApparentDilatationIsTakenOut) {
  const ModeICrackField m = LefmField();
  const CrackGeometry crack = CrackOf(m.tip_x, m.tip_y, 1, 0);
  const FrameJOptions o = RootAtTheTip();
  const double exact = JFromKOver2mu(m.k_over_2mu);
  for (double e : {0.0, 1e-4, 1e-3}) {
    SCOPED_TRACE(e);
    DisplacementField f = SampleGrid(m, crack, 150, 150, 2);
    AddNoise(&f, 0.003, 11);
    for (std::size_t i = 0; i < f.size(); ++i) {
      f.u[i] += e * (f.x[i] - 37);
      f.v[i] += e * (f.y[i] + 21);
    }
    const FrameJ j = ComputeFrameJ(f, m.tip_x, m.tip_y, 150.5, 1, 0, 2.0, kPx, 0, o);
    ASSERT_EQ(j.status, FrameJStatus::kOk) << j.why;
    ASSERT_EQ(j.fit.status, FieldFitJStatus::kOk) << j.fit.why;
    std::printf("dilatation %.0e: J_ff %.3f (fit %.3f +- %.3f, exact %.3f) J/m^2, read %.3g +- %.2g, "
                "taken out: %s\n",
                e, j.J_ff, j.fit.J, j.fit.J_uncertainty, exact, j.fit.dilatation,
                j.fit.dilatation_se, j.fit.dilatation_removed ? "yes" : "no");
    EXPECT_EQ(j.fit.dilatation_removed, e > 0);
    EXPECT_NEAR(j.J_ff / exact, 1.0, 0.02);
    EXPECT_NEAR(j.fit.J / exact, 1.0, 0.02);
    if (e > 0) EXPECT_NEAR(j.fit.dilatation / e, 1.0, 0.05);
  }
}

}  // namespace
}  // namespace bridgefit::dic
