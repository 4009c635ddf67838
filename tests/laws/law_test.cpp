#include "bridgefit/laws/law.hpp"

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "bridgefit/core/error.hpp"
#include "bridgefit/laws/rcurve_theory.hpp"

namespace bridgefit::laws {
namespace {

// Adaptive Simpson quadrature: the oracle for J_B = int_0^delta_c sigma.
double Simpson(const std::function<double(double)>& f, double a, double b, double fa, double fm,
               double fb, double whole, double tol, int depth) {
  const double m = 0.5 * (a + b);
  const double lm = 0.5 * (a + m), rm = 0.5 * (m + b);
  const double flm = f(lm), frm = f(rm);
  const double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
  const double right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
  if (depth <= 0 || std::abs(left + right - whole) <= 15.0 * tol)
    return left + right + (left + right - whole) / 15.0;
  return Simpson(f, a, m, fa, flm, fm, left, tol / 2, depth - 1) +
         Simpson(f, m, b, fm, frm, fb, right, tol / 2, depth - 1);
}
double Integrate(const std::function<double(double)>& f, double a, double b, double tol) {
  const double fa = f(a), fb = f(b), fm = f(0.5 * (a + b));
  return Simpson(f, a, b, fa, fm, fb, (b - a) / 6.0 * (fa + 4 * fm + fb), tol, 60);
}

// A table through `s` at d = j / N (the last point 0 at d = 1), monotone cubic between.
LawShape MonotoneCubicTable(const std::vector<double>& s) {
  LawShape shape{.family = LawFamily::kTable, .interpolation = TableInterpolation::kMonotoneCubic};
  for (size_t j = 0; j < s.size(); ++j) shape.d_points.push_back(double(j) / (s.size() - 1));
  shape.s_points = s;
  return shape;
}

std::vector<LawShape> AllShapes() {
  double sc = 0, dc = 0;
  return {MakeLinearShape(), MakeCubicShape(), MakeTriangularShape(0.1),
          MakeTriangularShape(0.37), MakeExponentialShape(3.0),
          MakeTrilinearShape(1.0, 0.2, 0.6, 0.55, 0.25),
          MakeTableShape({0.0, 0.2e-3, 1.0e-3, 2.0e-3}, {0.0, 0.8e6, 0.3e6, 0.0}, &sc, &dc),
          MonotoneCubicTable({0.1, 0.9, 1.0, 0.4, 0.3, 0.0})};
}

TEST(Laws, CubicRCurveClosedForm) {
  // J_B = J_tip,c: R / J_tip,c = 1 + d^3 (4 - 3 d).
  const LawShape shape = MakeCubicShape();
  const double J_tip_c = 2210.0, delta_c = 2e-3;
  const double sigma_c = J_tip_c / (9.0 / 16.0 * delta_c);
  const BridgingLaw law{&shape, sigma_c, delta_c};
  EXPECT_NEAR(law.BridgingToughness(), J_tip_c, 1e-9 * J_tip_c);
  const double d[] = {0.25, 0.5, 0.75, 1.0};
  const double expected[] = {1.0508, 1.3125, 1.7383, 2.000};
  for (int i = 0; i < 4; ++i) {
    const double r = ElasticZoneR(law, d[i] * delta_c, J_tip_c) / J_tip_c;
    EXPECT_NEAR(r, expected[i], 1e-4) << "d = " << d[i];
    EXPECT_NEAR(r, 1.0 + std::pow(d[i], 3) * (4 - 3 * d[i]), 1e-12);
  }
}

TEST(Laws, LinearSofteningRIsLinearInDeltaRoot) {
  const LawShape shape = MakeLinearShape();
  const double sigma_c = 0.45e6, delta_c = 2.222e-3, J_tip_c = 2210.0;
  const BridgingLaw law{&shape, sigma_c, delta_c};
  for (double f : {0.0, 0.1, 0.33, 0.8, 0.999}) {
    const double delta_root = f * delta_c;
    EXPECT_NEAR(ElasticZoneR(law, delta_root, J_tip_c), J_tip_c + 0.5 * sigma_c * delta_root,
                1e-9);
  }
  EXPECT_NEAR(ElasticZoneR(law, 1.5 * delta_c, J_tip_c), J_tip_c + 0.5 * sigma_c * delta_c, 1e-9);
}

TEST(Laws, BridgingToughnessMatchesQuadrature) {
  for (const LawShape& shape : AllShapes()) {
    const double sigma_c = 0.7e6, delta_c = 3.1e-3;
    const BridgingLaw law{&shape, sigma_c, delta_c};
    const double quad = Integrate([&](double x) { return law.Traction(x); }, 0.0, delta_c, 1e-12);
    EXPECT_NEAR(law.BridgingToughness(), quad, 1e-8 * quad) << LawFamilyName(shape.family);
    // W(delta) at an interior point too.
    const double mid = 0.43 * delta_c;
    const double quad_mid = Integrate([&](double x) { return law.Traction(x); }, 0.0, mid, 1e-12);
    EXPECT_NEAR(law.Work(mid), quad_mid, 1e-8 * quad_mid) << LawFamilyName(shape.family);
  }
}

TEST(Laws, PublishedShapeAreas) {
  EXPECT_DOUBLE_EQ(MakeLinearShape().Area(), 0.5);
  EXPECT_DOUBLE_EQ(MakeCubicShape().Area(), 9.0 / 16.0);
  EXPECT_DOUBLE_EQ(MakeTriangularShape(0.25).Area(), 0.5);
  EXPECT_NEAR(MakeExponentialShape(2.0).Area(), (1 - std::exp(-2.0)) / 2.0, 1e-15);
}

TEST(Laws, PeakIsSigmaC) {
  for (const LawShape& shape : AllShapes()) {
    const BridgingLaw law{&shape, 1.0e6, 1e-3};
    double peak = 0.0;
    for (int i = 0; i <= 30000; ++i) peak = std::max(peak, law.Traction(1e-3 * i / 30000.0));
    EXPECT_NEAR(peak, 1.0e6, 1e-3 * 1.0e6) << LawFamilyName(shape.family);
    EXPECT_EQ(law.Traction(1e-3), 0.0);
    EXPECT_EQ(law.Traction(2e-3), 0.0);
  }
}

TEST(Laws, ElasticUnloadingTowardOrigin) {
  const LawShape shape = MakeLinearShape();
  const BridgingLaw law{&shape, 1.0e6, 1e-3};
  const double delta_max = 0.4e-3;
  const double peak = law.Traction(delta_max);  // 0.6 MPa
  EXPECT_NEAR(law.TractionWithHistory(0.2e-3, delta_max), 0.5 * peak, 1e-6);
  EXPECT_NEAR(law.TractionWithHistory(0.5e-3, delta_max), law.Traction(0.5e-3), 1e-6);
  EXPECT_EQ(law.TractionWithHistory(0.5e-3, 1.2e-3), 0.0);  // broken for good
  EXPECT_NEAR(law.Recoverable(delta_max), 0.5 * peak * delta_max, 1e-12);
  EXPECT_NEAR(law.Dissipated(delta_max) + law.Recoverable(delta_max), law.Work(delta_max), 1e-12);
}

TEST(Laws, AnyTwoScalesFixTheThird) {
  const LawShape cubic = MakeCubicShape();
  const LawScales a = CompleteScales(cubic, {0.45e6, NAN, 500.0});
  EXPECT_NEAR(a.delta_c, 500.0 / (9.0 / 16.0 * 0.45e6), 1e-15);
  const LawScales b = CompleteScales(cubic, {NAN, a.delta_c, 500.0});
  EXPECT_NEAR(b.sigma_c, 0.45e6, 1e-6);
  const LawScales c = CompleteScales(cubic, {0.45e6, a.delta_c, NAN});
  EXPECT_NEAR(c.J_B, 500.0, 1e-9);
  EXPECT_THROW(CompleteScales(cubic, {0.45e6, NAN, NAN}), Error);
  EXPECT_THROW(CompleteScales(cubic, {0.45e6, 1e-3, 500.0}), Error);
  EXPECT_THROW(CompleteScales(cubic, {-1.0, 1e-3, NAN}), Error);
  // The linear-softening lower bound of the MDF study: J_B = 500, sigma_c = 0.45 MPa.
  const LawScales mdf = CompleteScales(MakeLinearShape(), {0.45e6, NAN, 500.0});
  EXPECT_NEAR(mdf.delta_c, 2.2222e-3, 1e-7);
}

TEST(Laws, ImpossibleShapesAreRejected) {
  EXPECT_THROW(MakeTriangularShape(1.0), Error);
  EXPECT_THROW(MakeExponentialShape(-1.0), Error);
  EXPECT_THROW(MakeTrilinearShape(1.0, 0.6, 0.5, 0.4, 0.2), Error);
  double sc, dc;
  EXPECT_THROW(MakeTableShape({0.0, 1e-3}, {1e6, 0.5e6}, &sc, &dc), Error);  // no zero at end
  EXPECT_THROW(MakeTableShape({0.1e-3, 1e-3}, {1e6, 0.0}, &sc, &dc), Error);  // not from 0
  EXPECT_THROW(ParseLawFamily("quadratic"), Error);
}

TEST(Laws, TipJContourFormsAgree) {
  // A contour crossing inside the zone at COD delta_x sees J(x) = J_tip + W(delta_x);
  // one enclosing the zone sees J_ff = J_tip + W(delta_root): both give J_tip.
  const LawShape shape = MakeCubicShape();
  const BridgingLaw law{&shape, 0.8e6, 2e-3};
  const double J_tip = 1500.0, delta_x = 0.6e-3, delta_root = 1.4e-3;
  EXPECT_NEAR(TipJFromContourInside(law, J_tip + law.Work(delta_x), delta_x), J_tip, 1e-9);
  EXPECT_NEAR(TipJFromContourEnclosing(law, FarFieldJ(law, delta_root, J_tip), delta_root), J_tip,
              1e-9);
}

TEST(Laws, TruncationBounds) {
  const TruncationBounds b = BoundsFromTruncatedCurve(2650.0, 2210.0, 1.9e-3, 0.07);
  EXPECT_DOUBLE_EQ(b.J_B_lower, 440.0);
  EXPECT_DOUBLE_EQ(b.delta_c_lower, 1.9e-3);
  EXPECT_THROW(BoundsFromTruncatedCurve(NAN, 2210.0, 1e-3, 0.07), Error);
}

// The monotone cubic table (PCHIP): a straight line exactly; on each segment
// within its end values (so >= 0, peak = the largest point); the cubic law
// interpolated at N knots 2.3 to 6 times closer than straight segments, both
// converging at second order (PCHIP's slope is O(h) off only where the law's
// slope vanishes: the peak between knots and d = 1; O(h^2) elsewhere).
TEST(Laws, MonotoneCubicTable) {
  const LawShape line = MonotoneCubicTable({1.0, 0.75, 0.5, 0.25, 0.0});
  for (int i = 0; i <= 100; ++i)
    EXPECT_NEAR(ShapeValue(line, i / 100.0), i < 100 ? 1.0 - i / 100.0 : 0.0, 1e-15);
  EXPECT_NEAR(line.Area(), 0.5, 1e-15);

  const LawShape bumpy = MonotoneCubicTable({0.1, 0.9, 1.0, 0.4, 0.3, 0.0});
  for (int i = 0; i < 1000; ++i) {
    const double d = i / 1000.0;
    const size_t j = static_cast<size_t>(d * 5.0);
    const double lo = std::min(bumpy.s_points[j], bumpy.s_points[j + 1]);
    const double hi = std::max(bumpy.s_points[j], bumpy.s_points[j + 1]);
    EXPECT_GE(ShapeValue(bumpy, d), lo - 1e-15) << d;
    EXPECT_LE(ShapeValue(bumpy, d), hi + 1e-15) << d;
  }

  const LawShape cubic = MakeCubicShape();
  auto worst = [&](int knots, TableInterpolation how) {
    std::vector<double> s;
    for (int j = 0; j <= knots; ++j) s.push_back(ShapeValue(cubic, double(j) / knots));
    LawShape table = MonotoneCubicTable(s);
    table.interpolation = how;
    double e = 0.0;
    for (int i = 0; i < 2000; ++i)
      e = std::max(e, std::abs(ShapeValue(table, i / 2000.0) - ShapeValue(cubic, i / 2000.0)));
    return e;
  };
  // Measured max |error|, monotone cubic / straight: N = 3 0.096 / 0.28,
  // N = 5 0.051 / 0.115, N = 6 0.019 / 0.082, N = 24 0.00094 / 0.0057, N = 48 0.00023 / 0.0014.
  for (int knots : {3, 4, 5, 6, 12, 24})
    EXPECT_LT(worst(knots, TableInterpolation::kMonotoneCubic),
              worst(knots, TableInterpolation::kLinear) / 2.0)
        << knots;
  for (TableInterpolation how : {TableInterpolation::kMonotoneCubic, TableInterpolation::kLinear})
    EXPECT_GT(std::log2(worst(24, how) / worst(48, how)), 1.9);
}

// Ceres Jets differentiate R(delta_root; sigma_c, delta_c) like finite differences do.
TEST(Laws, JetDerivativesMatchFiniteDifferences) {
  using Jet = ceres::Jet<double, 2>;
  for (const LawShape& shape : AllShapes()) {
    const double sigma_c = 0.6e6, delta_c = 2.5e-3, J_tip_c = 2210.0, delta_root = 0.9e-3;
    const LawT<Jet> law{&shape, Jet(sigma_c, 0), Jet(delta_c, 1)};
    const Jet r = ElasticZoneR(law, Jet(delta_root), Jet(J_tip_c));
    auto R = [&](double s, double d) {
      const BridgingLaw l{&shape, s, d};
      return ElasticZoneR(l, delta_root, J_tip_c);
    };
    const double hs = 1e-3 * sigma_c, hd = 1e-6 * delta_c;
    const double dR_ds = (R(sigma_c + hs, delta_c) - R(sigma_c - hs, delta_c)) / (2 * hs);
    const double dR_dd = (R(sigma_c, delta_c + hd) - R(sigma_c, delta_c - hd)) / (2 * hd);
    EXPECT_NEAR(r.a, R(sigma_c, delta_c), 1e-9);
    EXPECT_NEAR(r.v[0], dR_ds, 1e-6 * std::abs(dR_ds) + 1e-12) << LawFamilyName(shape.family);
    EXPECT_NEAR(r.v[1], dR_dd, 1e-5 * std::abs(dR_dd) + 1e-6) << LawFamilyName(shape.family);
  }
}

}  // namespace
}  // namespace bridgefit::laws
