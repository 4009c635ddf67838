// Correlated residuals (docs/FIT.md "Correlated residuals"): an R curve whose
// errors are shared by neighbouring points carries fewer independent pieces
// than points, and intervals computed as if they were independent are too
// narrow. Oracle: coverage of the 95% intervals over many noise draws on the
// analytic model (its own truth, so no model error), with AR(1) noise of
// known correlation and correctly stated per-point uncertainties.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "bridgefit/inverse/fit.hpp"

namespace bridgefit::inverse {
namespace {

constexpr double kModulus = 1e9;  // E' of the analytic model [Pa]
constexpr double kA0 = 0.03;      // [m]

// The analytic model's R curve with AR(1) relative noise: e_i = rho e_(i-1)
// + sqrt(1 - rho^2) sd z_i (marginal sd `sd`, the stated uncertainty).
FitData Ar1Data(const laws::LawShape& shape, const LawParameters& truth, int n, double sd,
                double rho, std::mt19937& rng) {
  const AnalyticForwardModel model(kModulus, kA0);
  FitData data;
  for (int i = 0; i < n; ++i) data.crack_length.push_back(kA0 + 0.08 * (i + 1) / n);
  const ForwardPrediction p = model.Predict(shape, truth, data.crack_length, RKind::kEnergy);
  std::normal_distribution<double> gauss(0.0, 1.0);
  double e = sd * gauss(rng);
  for (double r : p.R) {
    data.R.push_back(r * (1.0 + e));
    data.R_uncertainty.push_back(sd * r);
    e = rho * e + std::sqrt(1.0 - rho * rho) * sd * gauss(rng);
  }
  return data;
}

struct Coverage {
  int fits = 0, covered_tip = 0, covered_sigma = 0, inflated = 0;
};

Coverage RunDraws(double rho, int draws) {
  const laws::LawShape shape = laws::MakeLinearShape();
  const LawParameters truth{1.0e6, 500.0, 2210.0};  // steady state at 36 mm of 80
  const AnalyticForwardModel model(kModulus, kA0);
  FitOptions options;
  options.starts = 2;
  options.profile_likelihood = false;  // Jacobian intervals: the same s^2
  options.outlier_threshold = 0.0;
  std::mt19937 rng(2026);
  Coverage c;
  for (int k = 0; k < draws; ++k) {
    const FitData data = Ar1Data(shape, truth, 60, 0.01, rho, rng);
    const FitSummary s = FitBridgingLaw(model, shape, data, options);
    if (!s.converged || !s.J_tip_c.identified || !s.sigma_c.identified) continue;
    ++c.fits;
    c.covered_tip += s.J_tip_c.ci95_low <= truth.J_tip_c && truth.J_tip_c <= s.J_tip_c.ci95_high;
    c.covered_sigma += s.sigma_c.ci95_low <= truth.sigma_c && truth.sigma_c <= s.sigma_c.ci95_high;
    c.inflated += s.interval_inflation > 1.0;
  }
  std::printf("rho %.2f: %d fits, J_tip_c covered %d, sigma_c covered %d, intervals widened in %d\n",
              rho, c.fits, c.covered_tip, c.covered_sigma, c.inflated);
  return c;
}

// Independent noise: the 95% intervals cover about 95% (the correction acts
// only where the lag-1 correlation is significant, in about 2.5% of draws).
// Strongly correlated noise (rho 0.8, variance of a mean x 9): without the
// correction (measured 2026-12-02 with the inflation forced to 1) J_tip,c's
// interval covered 81 and sigma_c's 79 of these 120 draws (68%, 66%); with
// it 113 and 114. The coverage must be back near 95%. 120 draws each: a binomial 95% coverage
// gives >= 107 of 120 with probability 0.99; the limits below are that.
TEST(CorrelatedResiduals, IntervalsCoverTheTruthUnderAr1Noise) {
  const Coverage independent = RunDraws(0.0, 120);
  ASSERT_GE(independent.fits, 115);
  EXPECT_GE(independent.covered_tip, independent.fits * 107 / 120);
  EXPECT_GE(independent.covered_sigma, independent.fits * 107 / 120);
  EXPECT_LE(independent.inflated, independent.fits / 10);
  const Coverage correlated = RunDraws(0.8, 120);
  ASSERT_GE(correlated.fits, 115);
  EXPECT_GE(correlated.covered_tip, correlated.fits * 107 / 120);
  EXPECT_GE(correlated.covered_sigma, correlated.fits * 107 / 120);
  EXPECT_GE(correlated.inflated, correlated.fits * 9 / 10);
}

}  // namespace
}  // namespace bridgefit::inverse
