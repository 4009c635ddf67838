// Laws with a fitted shape (bilinear, trilinear, tabulated; issue 21), on R
// curves made by the analytic forward model the fit uses (its own oracle),
// with seeded relative noise.
#include "bridgefit/inverse/fit_shape.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "bridgefit/core/error.hpp"

namespace bridgefit::inverse {
namespace {

constexpr double kModulus = 1e9;  // E' of the analytic model [Pa]
constexpr double kA0 = 0.03;      // [m]

// n R points of the analytic model from a0 to a_max, relative Gaussian noise
// `noise`, each with the uncertainty noise x R. The growth Delta a_i is
// spaced as i^2 (the notch-root opening, ~ sqrt(Delta a), about evenly):
// evenly spaced crack lengths leave the law below the first point's opening
// unseen (docs/FIT.md "Law families with a fitted shape").
FitData MakeData(const laws::LawShape& shape, const LawParameters& truth, double a_max, int n,
                 double noise, unsigned seed) {
  const AnalyticForwardModel model(kModulus, kA0);
  FitData data;
  for (int i = 0; i < n; ++i)
    data.crack_length.push_back(kA0 + (a_max - kA0) * std::pow((i + 1.0) / n, 2));
  const ForwardPrediction p = model.Predict(shape, truth, data.crack_length, RKind::kEnergy);
  EXPECT_TRUE(p.ok()) << p.message;
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (double r : p.R) {
    data.R.push_back(r * (1.0 + noise * gauss(rng)));
    data.R_uncertainty.push_back(noise * r);
  }
  return data;
}

FitOptions FastOptions() {
  FitOptions o;
  o.starts = 3;
  o.profile_likelihood = false;
  return o;
}

const LawComparison& Find(const std::vector<LawComparison>& c, const std::string& law) {
  const auto it = std::find_if(c.begin(), c.end(), [&](const auto& x) { return x.law == law; });
  static const LawComparison missing;  // NaN AICc: the checks that use it fail
  if (it == c.end()) ADD_FAILURE() << "no family " << law;
  return it == c.end() ? missing : *it;
}

// The fitted table against the true law at each knot's opening: the largest
// |difference| over the points at d in [0, 1] (the knots and the end) as a
// fraction of the true sigma_c.
double WorstKnotError(const LawComparison& f, const laws::LawShape& true_shape,
                      const LawParameters& truth) {
  const FitSummary& s = f.summary;
  const double sigma_c = s.best_parameters[kSigmaC];
  const double delta_c = s.best_parameters[kJB] / (f.shape.Area() * sigma_c);
  const double true_delta_c = truth.J_B / (true_shape.Area() * truth.sigma_c);
  double worst = 0.0;
  for (size_t k = 0; k < f.shape.d_points.size(); ++k) {
    const double delta = f.shape.d_points[k] * delta_c;
    const double fitted = sigma_c * f.shape.s_points[k];
    const double expected = truth.sigma_c * laws::ShapeValue(true_shape, delta / true_delta_c);
    const double se = k < f.shape_parameters.size() ? f.shape_parameters[k].standard_error : 0.0;
    std::printf("  knot d = %.3f: delta %.4f mm, sigma %.4f MPa (Wald se %.4f), truth %.4f MPa\n",
                f.shape.d_points[k], delta * 1e3, fitted * 1e-6, se * sigma_c * 1e-6,
                expected * 1e-6);
    worst = std::max(worst, std::abs(fitted - expected) / truth.sigma_c);
  }
  std::printf("  worst knot error: %.4f sigma_c\n", worst);
  return worst;
}

void Print(const std::vector<LawComparison>& comparison) {
  for (const auto& c : comparison)
    std::printf("  %-12s k %5.2f  chi2 %9.3f  AICc %9.3f  weight %.3f  %s\n", c.law.c_str(),
                c.parameters, c.summary.chi2, c.aicc, c.weight, c.note.c_str());
}

// Issue 21's acceptance, on an R curve of a record's size (the MDF sample's
// exact record gives 399 points) from the cubic law with 0.5% noise: the
// table's knots follow the cubic within 5% of sigma_c at every d in [0, 1],
// and AICc prefers the cubic or the table to the linear law. Measured: N = 6,
// knots +1.3, -0.6, +1.5, +0.5, -0.7, -1.1% and (d = 1) -0.6%; AICc cubic
// 432.0, table 438.2, linear 3104.0. With straight segments between the
// knots the d = 0 knot was +11.2% (a bias: +7.5..+14% also without noise,
// fit_shape.hpp), and sigma_c's interval missed 1 MPa.
TEST(FitShape, TableFollowsTheCubicLaw) {
  const laws::LawShape cubic = laws::MakeCubicShape();
  const LawParameters truth{1.0e6, 500.0, 2210.0};
  const FitData data = MakeData(cubic, truth, kA0 + 0.08, 400, 0.005, 31);
  const AnalyticForwardModel model(kModulus, kA0);
  const auto comparison = CompareLawFamiliesWithShapes(model, {laws::MakeLinearShape(), cubic},
                                                       {ShapeFamily::kTable}, data, FastOptions());
  Print(comparison);
  const LawComparison& table = Find(comparison, "table");
  ASSERT_TRUE(table.summary.converged) << table.note;
  const double best = std::min(Find(comparison, "cubic").aicc, table.aicc);
  EXPECT_LT(best, Find(comparison, "linear").aicc);
  for (const ParameterEstimate* e :
       {&table.summary.sigma_c, &table.summary.J_B, &table.summary.J_tip_c})
    std::printf("  %.6g [%.6g, %.6g] %s\n", e->value, e->ci95_low, e->ci95_high, e->note.c_str());
  EXPECT_LE(WorstKnotError(table, cubic, truth), 0.05);
}

// A law the table cannot draw exactly: exponential decay (alpha = 3), cut
// from exp(-3) = 0.05 to zero at delta_c. AICc still prefers the table or
// the exponential law to the linear one. The knots are printed, not held
// to 5%: the table's last segment must end at zero, so it ends early and
// the tail knots fall short. Measured (this seed, 100 points, N = 3): knots
// at d = 0, 1/3, 2/3 off by -1.2, -2.6, -4.4% of sigma_c and -5.2% at d = 1
// (straight segments: -5.1% and -5.8% at 1/3 and 2/3; docs/FIT.md).
TEST(FitShape, TableFollowsTheExponentialLaw) {
  const laws::LawShape exponential = laws::MakeExponentialShape(3.0);
  const LawParameters truth{1.0e6, 500.0, 2210.0};
  const FitData data = MakeData(exponential, truth, kA0 + 0.08, 100, 0.005, 32);
  const AnalyticForwardModel model(kModulus, kA0);
  const auto comparison = CompareLawFamiliesWithShapes(
      model, {laws::MakeLinearShape(), exponential}, {ShapeFamily::kTable}, data, FastOptions());
  Print(comparison);
  const LawComparison& table = Find(comparison, "table");
  ASSERT_TRUE(table.summary.converged) << table.note;
  EXPECT_LT(std::min(Find(comparison, "exponential").aicc, table.aicc),
            Find(comparison, "linear").aicc);
  WorstKnotError(table, exponential, truth);
}

void ExpectCovers(const ParameterEstimate& e, double truth, const char* name) {
  std::printf("  %-8s %.6g [%.6g, %.6g], truth %.6g\n", name, e.value, e.ci95_low, e.ci95_high,
              truth);
  EXPECT_LE(e.ci95_low, truth) << name;
  EXPECT_GE(e.ci95_high, truth) << name;
}

// A bilinear law with a steep first drop to a long tail (kink at d = 0.25,
// s = 0.3; the linear law is the kink at (0.5, 0.5)): the scale parameters
// within their intervals (widened for the shape), the kink within 1.96
// Wald standard errors.
TEST(FitShape, BilinearRecoversItsKink) {
  laws::LawShape bilinear{.family = laws::LawFamily::kTable};
  bilinear.d_points = {0.0, 0.25, 1.0};
  bilinear.s_points = {1.0, 0.3, 0.0};
  // delta_c = J_B / (0.275 sigma_c) = 0.91 mm: steady state at Delta a ~ 30 mm.
  const LawParameters truth{2.0e6, 500.0, 2210.0};
  const FitData data = MakeData(bilinear, truth, kA0 + 0.08, 100, 0.005, 41);
  const AnalyticForwardModel model(kModulus, kA0);
  const ShapeFit f = FitShapeFamily(model, ShapeFamily::kBilinear, data, FastOptions(), {});
  std::printf("%s", f.BriefReport().c_str());
  ASSERT_TRUE(f.fitted) << f.skip_reason;
  EXPECT_TRUE(f.summary.converged);
  EXPECT_TRUE(f.summary.steady_state_reached) << f.summary.verdict;
  EXPECT_EQ(f.parameters, 5);
  ExpectCovers(f.summary.sigma_c, truth.sigma_c, "sigma_c");
  ExpectCovers(f.summary.J_B, truth.J_B, "J_B");
  ExpectCovers(f.summary.J_tip_c, truth.J_tip_c, "J_tip_c");
  ASSERT_EQ(f.shape_parameters.size(), 2u);
  const double expected[] = {0.25, 0.3};
  for (int k = 0; k < 2; ++k) {
    const ShapeParameter& p = f.shape_parameters[k];
    ASSERT_TRUE(std::isfinite(p.standard_error)) << p.name;
    EXPECT_LE(std::abs(p.value - expected[k]), 1.96 * p.standard_error) << p.name;
  }
}

// The law module's trilinear law (a rise to the peak, a drop and a tail:
// (0, 0.5), (0.1, 1), (0.4, 0.3), (1, 0)): the scale parameters within
// their intervals and the break points within 1.96 Wald standard errors.
TEST(FitShape, TrilinearRecoversItsBreakPoints) {
  const laws::LawShape trilinear = laws::MakeTrilinearShape(0.5, 0.1, 1.0, 0.4, 0.3);
  const LawParameters truth{2.0e6, 500.0, 2210.0};
  const FitData data = MakeData(trilinear, truth, kA0 + 0.08, 100, 0.005, 43);
  const AnalyticForwardModel model(kModulus, kA0);
  const ShapeFit f = FitShapeFamily(model, ShapeFamily::kTrilinear, data, FastOptions(), {});
  std::printf("%s", f.BriefReport().c_str());
  ASSERT_TRUE(f.fitted) << f.skip_reason;
  EXPECT_EQ(f.parameters, 7);
  EXPECT_TRUE(f.summary.steady_state_reached) << f.summary.verdict;
  ExpectCovers(f.summary.sigma_c, truth.sigma_c, "sigma_c");
  ExpectCovers(f.summary.J_B, truth.J_B, "J_B");
  ExpectCovers(f.summary.J_tip_c, truth.J_tip_c, "J_tip_c");
  const double expected[] = {0.1, 0.4, 0.5, 1.0, 0.3};  // d1, d2, s0, s1, s2
  ASSERT_EQ(f.shape_parameters.size(), 5u);
  for (int k = 0; k < 5; ++k) {
    const ShapeParameter& p = f.shape_parameters[k];
    if (p.pinned) {
      EXPECT_EQ(p.name, "s1");
      continue;
    }
    EXPECT_LE(std::abs(p.value - expected[k]), 1.96 * p.standard_error) << p.name;
  }
}

// Too few points for a family's parameters: never a number. In the
// comparison the family is skipped (no AICc, weight 0) with its reason; a
// table with some knot counts too many for the data drops those, named.
TEST(FitShape, TooFewPointsSkipTheFamilyWithItsReason) {
  const laws::LawShape cubic = laws::MakeCubicShape();
  const LawParameters truth{1.0e6, 500.0, 2210.0};
  const AnalyticForwardModel model(kModulus, kA0);
  const FitData six = MakeData(cubic, truth, kA0 + 0.08, 6, 0.005, 5);
  const auto comparison = CompareLawFamiliesWithShapes(
      model, {laws::MakeLinearShape()}, {ShapeFamily::kBilinear, ShapeFamily::kTable}, six,
      FastOptions());
  Print(comparison);
  ASSERT_EQ(comparison.size(), 3u);
  EXPECT_TRUE(std::isfinite(comparison[0].aicc));
  EXPECT_DOUBLE_EQ(comparison[0].weight, 1.0);
  for (const char* law : {"bilinear", "table"}) {
    const LawComparison& c = Find(comparison, law);
    EXPECT_TRUE(std::isnan(c.aicc)) << law;
    EXPECT_EQ(c.weight, 0.0) << law;
    EXPECT_FALSE(c.summary.converged) << law;
    EXPECT_NE(c.note.find("too few"), std::string::npos) << c.note;
  }
  EXPECT_NE(
      Find(comparison, "bilinear").note.find("6 data points are too few for its 5 parameters"),
      std::string::npos);

  const FitData seven = MakeData(cubic, truth, kA0 + 0.08, 7, 0.005, 5);
  const ShapeFit six_knots =
      FitShapeFamily(model, ShapeFamily::kTable, seven, FastOptions(), {}, 6);
  EXPECT_FALSE(six_knots.fitted);
  EXPECT_EQ(six_knots.skip_reason,
            "table N = 6: 7 data points are too few for its 8 parameters (at least 10 needed)");

  const FitData eight = MakeData(cubic, truth, kA0 + 0.08, 8, 0.005, 5);
  const ShapeFit table = FitTableLaw(model, eight, FastOptions(), {});
  ASSERT_TRUE(table.fitted) << table.skip_reason;
  EXPECT_LE(table.knots, 4);
  EXPECT_TRUE(std::isnan(table.knots_aicc[2]) && std::isnan(table.knots_aicc[3]));
  EXPECT_NE(table.note.find("skipped: table N = 5: 8 data points are too few"), std::string::npos)
      << table.note;
}

TEST(FitShape, InvalidOptionsThrow) {
  const AnalyticForwardModel model(kModulus, kA0);
  const FitData data =
      MakeData(laws::MakeLinearShape(), {1.0e6, 500.0, 2210.0}, kA0 + 0.08, 20, 0.005, 5);
  ShapeFitOptions bad;
  bad.table_knots = {1};
  EXPECT_THROW(FitTableLaw(model, data, FastOptions(), bad), Error);
  bad = {};
  bad.smoothness = -1.0;
  EXPECT_THROW(FitShapeFamily(model, ShapeFamily::kBilinear, data, FastOptions(), bad), Error);
  EXPECT_THROW(FitShapeFamily(model, ShapeFamily::kTable, data, FastOptions(), {}, 1), Error);
}

}  // namespace
}  // namespace bridgefit::inverse
