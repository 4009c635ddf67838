// The law-free routes (law_free.hpp) against the project's own closed forms:
// synthetic J_ff(delta*) and R(delta_root) from laws::FarFieldJ and
// laws::ElasticZoneR with 0.5 % Gaussian noise, fixed seeds (law_free_synthetic.hpp;
// the coverage of the stated bound and J_tip,c interval: law_free_bounds_test.cpp).

#include "bridgefit/laws/law_free.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/laws/rcurve_theory.hpp"
#include "law_free_synthetic.hpp"

namespace bridgefit::laws {
namespace {

using namespace synthetic;

struct Recovery {
  double sigma_rms = 0.0;      // RMS(sigma - truth) / sigma_c over 0.1 .. 0.9 delta_c
  double J_B_error = 0.0;      // J_B / truth - 1
  int covered = 0, nodes = 0;  // grid nodes in [0, delta_c] with the truth inside the band
};

Recovery Measure(const Truth& truth, const LawFreeResult& r) {
  const BridgingLaw law = truth.Law();
  Recovery m;
  double sum = 0.0;
  int count = 0;
  for (size_t j = 0; j < r.delta.size(); ++j) {
    const double exact = law.Traction(r.delta[j]);
    const double d = r.delta[j] / kDeltaC;
    if (d >= 0.1 && d <= 0.9) sum += std::pow(r.sigma[j] - exact, 2), ++count;
    if (d <= 1.0) {
      ++m.nodes;
      m.covered += exact >= r.sigma_lower[j] && exact <= r.sigma_upper[j];
    }
  }
  m.sigma_rms = std::sqrt(sum / count) / truth.sigma_c;
  m.J_B_error = r.J_B.value / kJB - 1.0;
  return m;
}

// sigma RMS error / sigma_c over [lo, hi] of `scale`, against sigma + slope delta.
double SigmaRms(const Truth& truth, const LawFreeResult& r, double lo, double hi, double scale,
                double slope = 0.0) {
  double sum = 0.0;
  int count = 0;
  for (size_t j = 0; j < r.delta.size(); ++j) {
    if (r.delta[j] < lo * scale || r.delta[j] > hi * scale) continue;
    const double fitted = r.sigma_upper[j] - (r.sigma_upper[j] - r.sigma_lower[j]) / 2;
    sum += std::pow(fitted + slope * r.delta[j] - truth.Law().Traction(r.delta[j]), 2);
    ++count;
  }
  return std::sqrt(sum / count) / truth.sigma_c;
}

bool HasNote(const LawFreeResult& r, const std::string& words) {
  for (const std::string& note : r.notes)
    if (note.find(words) != std::string::npos) return true;
  return false;
}

void ExpectRecovered(const Truth& truth, const LawFreeResult& r, int seed) {
  SCOPED_TRACE(truth.name + ", seed " + std::to_string(seed));
  const Recovery m = Measure(truth, r);
  std::string why;
  EXPECT_TRUE(r.IsValid(&why)) << why;
  EXPECT_TRUE(r.identified) << r.Summary();
  EXPECT_TRUE(r.J_B.identified && r.delta_c.identified);
  EXPECT_LT(m.sigma_rms, 0.05) << r.Summary();
  EXPECT_LT(std::abs(m.J_B_error), 0.05) << r.Summary();
  EXPECT_NEAR(r.J_tip_c, kJtipc, 0.01 * kJtipc);
  // delta_c: where the curve levels off within its noise, at most a little
  // past the truth (one grid of samples) and not far below it.
  EXPECT_LT(r.delta_c.value, 1.05 * kDeltaC);
  EXPECT_GT(r.delta_c.value, 0.6 * kDeltaC);
  std::printf(
      "  %-11s seed %d: sigma RMS %.2f %%, J_B %+.2f %%, delta_c %.3f delta_c, "
      "coverage %d/%d, lambda 10^%.1f\n",
      truth.name.c_str(), seed, 100 * m.sigma_rms, 100 * m.J_B_error, r.delta_c.value / kDeltaC,
      m.covered, m.nodes, r.penalty_log10_relative);
}

constexpr int kSeeds = 5;

TEST(LawFree, FarFieldJRecoversTheFamiliesAtSteadyState) {
  for (const Truth& truth : Families())
    for (int seed = 1; seed <= kSeeds; ++seed) {
      const LawFreeResult r = LawFromFarFieldJ(MakeFarFieldJ(truth, 1.4, seed));
      EXPECT_TRUE(r.onset_detected);
      EXPECT_EQ(r.onset_index, kPreOnset - 1);
      ExpectRecovered(truth, r, seed);
    }
}

TEST(LawFree, RCurveRecoversTheFamiliesAtSteadyState) {
  for (const Truth& truth : Families())
    for (int seed = 1; seed <= kSeeds; ++seed)
      ExpectRecovered(truth, LawFromRCurve(MakeRCurve(truth, 1.4, seed)), seed);
}

// A law of none of the three families (two kinks, starts at its peak), so
// that nothing above is tuned to them.
TEST(LawFree, BothRoutesRecoverATrilinearLaw) {
  const Truth truth = Trilinear();
  for (int seed = 1; seed <= kSeeds; ++seed) {
    ExpectRecovered(truth, LawFromFarFieldJ(MakeFarFieldJ(truth, 1.4, seed)), seed);
    ExpectRecovered(truth, LawFromRCurve(MakeRCurve(truth, 1.4, seed)), seed);
  }
}

// Data stopping at 0.6 delta_c: J_B and delta_c only bounded (PHYSICS.md
// section 7). J_ff still gives sigma over the data (no null space).
TEST(LawFree, FarFieldJStoppingEarlyGivesBoundsButSigma) {
  for (const Truth& truth : Families())
    for (int seed = 1; seed <= kSeeds; ++seed) {
      SCOPED_TRACE(truth.name + ", seed " + std::to_string(seed));
      const LawFreeResult r = LawFromFarFieldJ(MakeFarFieldJ(truth, 0.6, seed));
      std::string why;
      EXPECT_TRUE(r.IsValid(&why)) << why;
      EXPECT_FALSE(r.identified) << r.Summary();
      EXPECT_FALSE(r.J_B.identified);
      EXPECT_FALSE(r.delta_c.identified);
      const double W_end = truth.Law().Work(0.6 * kDeltaC);
      EXPECT_LT(r.J_B.value, kJB);
      EXPECT_NEAR(r.J_B.value, W_end, 0.05 * kJB);  // the bound is the work done so far
      EXPECT_LT(r.delta_c.value, kDeltaC);
      EXPECT_TRUE(HasNote(r, "never levels off")) << r.Summary();
      EXPECT_NE(r.Summary().find("not identified"), std::string::npos);
      const double rms = SigmaRms(truth, r, 0.1, 0.9, 0.6 * kDeltaC);
      EXPECT_LT(rms, 0.05) << r.Summary();
      std::printf("  %-11s seed %d: J_B >= %.0f (truth %.0f), sigma RMS %.2f %%\n",
                  truth.name.c_str(), seed, r.J_B.value, kJB, 100 * rms);
    }
}

// R stopping at 0.6 delta_c: sigma is known only up to + C delta. The
// result is the member with sigma(delta_max) = 0, so adding the true
// C = sigma(delta_max) / delta_max must give back the law.
TEST(LawFree, RCurveStoppingEarlyLeavesTheCDeltaTermOpen) {
  for (const Truth& truth : Families())
    for (int seed = 1; seed <= kSeeds; ++seed) {
      SCOPED_TRACE(truth.name + ", seed " + std::to_string(seed));
      const LawFreeResult r = LawFromRCurve(MakeRCurve(truth, 0.6, seed));
      std::string why;
      EXPECT_TRUE(r.IsValid(&why)) << why;
      EXPECT_FALSE(r.identified) << r.Summary();
      EXPECT_FALSE(r.J_B.identified);
      EXPECT_LT(r.J_B.value, kJB);
      EXPECT_GT(r.J_B.value, 0.0);
      EXPECT_LT(r.delta_c.value, kDeltaC);
      EXPECT_TRUE(HasNote(r, "never levels off")) << r.Summary();
      EXPECT_TRUE(HasNote(r, "C delta")) << r.Summary();
      const double delta_max = 0.6 * kDeltaC;
      const double C_true = truth.Law().Traction(delta_max) / delta_max;
      EXPECT_LE(r.null_space_slope_min, C_true);
      // Without C the law fails the accuracy asked of the steady-state fits ...
      const double rms_without = SigmaRms(truth, r, 0.1, 0.9, delta_max);
      EXPECT_GT(rms_without, 0.05);
      // ... with the true C it is the law.
      const double rms_with = SigmaRms(truth, r, 0.1, 0.9, delta_max, C_true);
      EXPECT_LT(rms_with, 0.05) << r.Summary();
      std::printf(
          "  %-11s seed %d: J_B >= %.0f, sigma RMS %.1f %% as given, %.2f %% with the "
          "true C delta\n",
          truth.name.c_str(), seed, r.J_B.value, 100 * rms_without, 100 * rms_with);
    }
}

TEST(LawFree, BandCoversTheTruth) {
  std::vector<Truth> laws = Families();
  laws.push_back(Trilinear());
  int route_covered[2] = {0, 0}, route_nodes[2] = {0, 0};
  for (int route = 0; route < 2; ++route)
    for (const Truth& truth : laws) {
      int covered = 0, nodes = 0;
      double half_width = 0.0;
      for (int seed = 100; seed < 150; ++seed) {
        const LawFreeResult r = route == 0 ? LawFromFarFieldJ(MakeFarFieldJ(truth, 1.4, seed))
                                           : LawFromRCurve(MakeRCurve(truth, 1.4, seed));
        const Recovery m = Measure(truth, r);
        covered += m.covered, nodes += m.nodes;
        for (size_t j = 0; j < r.delta.size(); ++j)
          if (r.delta[j] <= kDeltaC)
            half_width += (r.sigma_upper[j] - r.sigma_lower[j]) / 2 / truth.sigma_c;
      }
      const double coverage = double(covered) / nodes;
      route_covered[route] += covered, route_nodes[route] += nodes;
      // Measured 87-98 % per law (83-97 % before sigma's band took the
      // penalty's share, 2026-12-05); the sampling covariance of the same
      // fit (no smoothing bias) covers 71-94 %, three laws below 80 %.
      EXPECT_GE(coverage, 0.80) << truth.name << (route == 0 ? ", J_ff" : ", R");
      // Not covering by being vacuous: measured 1.8-5.4 % of sigma_c (1.4-4.3 %
      // before the penalty's share).
      EXPECT_LT(half_width / nodes, 0.06) << truth.name;
      std::printf(
          "  %s %-11s: 95 %% band covers %.1f %% of %d (seed, node) pairs, mean "
          "half-width %.1f %% of sigma_c\n",
          route == 0 ? "J_ff" : "R   ", truth.name.c_str(), 100 * coverage, nodes,
          100 * half_width / nodes);
    }
  // Pooled over the laws: measured 92.0 % (J_ff) and 94.5 % (R) with the
  // penalty's share in sigma's standard error, 89.8 % and 91.0 % without
  // (below these bounds); the sampling covariance gives 79.6 % and 85.6 %.
  EXPECT_GE(double(route_covered[0]) / route_nodes[0], 0.90);
  EXPECT_GE(double(route_covered[1]) / route_nodes[1], 0.92);
}

// A curved law seen over a short stretch of openings (exponential, 0.3
// delta_c): on about half the seeds GCV takes the penalty's null space
// (sigma linear, lambda ~ 1e5), and the Bayesian band is then the line's own
// uncertainty, which the curved law falls out of (covers 75.9 % of the
// nodes over 40 seeds). The band allows for the best curved alternative
// (law_free_fit.cpp, AllowForUnresolvedCurvature): measured 91.7 %.
TEST(LawFree, ALinearFitOfAShortCurvedStretchKeepsItsBand) {
  const Truth truth = MakeTruth("exponential", MakeExponentialShape(3.0));
  int covered = 0, nodes = 0, linear = 0, runs = 0;
  for (int seed = 200; seed < 240; ++seed) {
    const LawFreeResult r = LawFromFarFieldJ(MakeFarFieldJ(truth, 0.3, seed));
    ++runs;
    const bool allowed = std::any_of(r.notes.begin(), r.notes.end(), [](const std::string& n) {
      return n.find("sigma linear in delta") != std::string::npos;
    });
    linear += allowed;
    const BridgingLaw law = truth.Law();
    for (size_t j = 0; j < r.delta.size(); ++j) {
      const double exact = law.Traction(r.delta[j]);
      ++nodes;
      covered += exact >= r.sigma_lower[j] && exact <= r.sigma_upper[j];
    }
  }
  std::printf("sigma linear chosen on %d of %d runs; band covers %.1f %% of %d (seed, node) pairs\n",
              linear, runs, 100.0 * covered / nodes, nodes);
  EXPECT_GT(linear, runs / 4);  // the case this guards is exercised
  EXPECT_GE(double(covered) / nodes, 0.85);  // as the families' pooled bound (BandCoversTheTruth)
}

// Openings measured with an uncertainty u_x (the near-tip delta* of
// dic/frame_j.hpp states 10-40 %): the effective variance (u_J^2 +
// (sigma u_x)^2) accounts for the scatter it adds to J_ff, so chi^2 per
// degree of freedom is about 1 and the band still covers; without u_x the
// fit sees several times the scatter its u_J allow.
TEST(LawFree, OpeningUncertaintyEntersAsEffectiveVariance) {
  const Truth truth = MakeTruth("linear", MakeLinearShape());
  constexpr double kUx = 0.03 * kDeltaC;
  double ratio_with = 0.0, ratio_without = 0.0;
  int covered = 0, nodes = 0;
  constexpr int kSeeds = 20;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    FarFieldJSamples d = MakeFarFieldJ(truth, 1.4, seed);
    Noise noise(1000 + seed);
    d.onset_index = kPreOnset - 1;
    d.opening_uncertainty.assign(d.opening.size(), 0.0);
    for (size_t i = kPreOnset; i < d.opening.size(); ++i) {
      d.opening[i] += kUx * noise.Next();
      d.opening_uncertainty[i] = kUx;
    }
    const LawFreeResult with = LawFromFarFieldJ(d);
    d.opening_uncertainty.clear();
    const LawFreeResult without = LawFromFarFieldJ(d);
    ratio_with += with.chi2 / (with.points_used - with.effective_dof) / kSeeds;
    ratio_without += without.chi2 / (without.points_used - without.effective_dof) / kSeeds;
    const Recovery m = Measure(truth, with);
    covered += m.covered, nodes += m.nodes;
  }
  std::printf("chi^2 / (n - dof): %.2f with u_x, %.2f without; band covers %.1f %%\n", ratio_with,
              ratio_without, 100.0 * covered / nodes);
  EXPECT_NEAR(ratio_with, 1.0, 0.3);
  EXPECT_GT(ratio_without, 3.0);
  EXPECT_GE(double(covered) / nodes, 0.85);
}

// The onset given by index, by opening, or detected: the same fit.
TEST(LawFree, OnsetGivenOrDetectedAgree) {
  const Truth truth = MakeTruth("cubic", MakeCubicShape());
  FarFieldJSamples data = MakeFarFieldJ(truth, 1.4, 7);
  const LawFreeResult detected = LawFromFarFieldJ(data);
  data.onset_index = kPreOnset - 1;
  const LawFreeResult by_index = LawFromFarFieldJ(data);
  data.onset_index.reset();
  data.onset_opening = kOnsetOpening * 1.01;
  const LawFreeResult by_opening = LawFromFarFieldJ(data);
  EXPECT_TRUE(detected.onset_detected);
  EXPECT_FALSE(by_index.onset_detected);
  EXPECT_FALSE(by_opening.onset_detected);
  for (const LawFreeResult* r : {&by_index, &by_opening}) {
    EXPECT_EQ(r->onset_index, detected.onset_index);
    EXPECT_DOUBLE_EQ(r->J_tip_c, detected.J_tip_c);
    EXPECT_EQ(r->sigma, detected.sigma);
  }
  // An onset given too late (the 40th sample) moves J_tip,c up by the bridging work done.
  data.onset_opening.reset();
  data.onset_index = kPreOnset + 39;
  const LawFreeResult late = LawFromFarFieldJ(data);
  EXPECT_NEAR(late.J_tip_c - kJtipc, truth.Law().Work(40 * 1.4 * kDeltaC / kGrowth), 30.0);
}

// Data with no pre-onset rise: no kink, the first sample is the onset, said so.
TEST(LawFree, NoKinkTakesTheFirstSampleAsOnset) {
  const Truth truth = MakeTruth("linear", MakeLinearShape());
  FarFieldJSamples data = MakeFarFieldJ(truth, 1.4, 3);
  for (auto* v : {&data.opening, &data.J_ff, &data.uncertainty})
    v->erase(v->begin(), v->begin() + kPreOnset);
  const LawFreeResult r = LawFromFarFieldJ(data);
  EXPECT_EQ(r.onset_index, 0);
  EXPECT_TRUE(HasNote(r, "no kink")) << r.Summary();
  EXPECT_LT(Measure(truth, r).sigma_rms, 0.05) << r.Summary();
}

// Samples in any order: sorted by opening, the same result.
TEST(LawFree, SampleOrderDoesNotMatter) {
  const Truth truth = MakeTruth("exponential", MakeExponentialShape(3.0));
  const RCurveSamples data = MakeRCurve(truth, 1.4, 11);
  RCurveSamples reversed = data;
  std::reverse(reversed.opening.begin(), reversed.opening.end());
  std::reverse(reversed.R.begin(), reversed.R.end());
  std::reverse(reversed.uncertainty.begin(), reversed.uncertainty.end());
  const LawFreeResult a = LawFromRCurve(data), b = LawFromRCurve(reversed);
  EXPECT_EQ(a.sigma, b.sigma);
  EXPECT_DOUBLE_EQ(a.J_B.value, b.J_B.value);
}

// The summary prints the peak with its 95 % band (never a bare sigma_c):
// on 160 samples at 0.5 % the band holds the true sigma_c and is narrow,
// no warning; on the same data with u 20 times larger (10 %) the band is
// wider than +-50 % of the peak and a warning says the peak is not resolved.
TEST(LawFree, ThePeakIsPrintedWithItsBandAndAWideOneIsWarned) {
  const Truth truth = MakeTruth("linear", MakeLinearShape());
  FarFieldJSamples data = MakeFarFieldJ(truth, 1.4, 3);
  const LawFreeResult sharp = LawFromFarFieldJ(data);
  const size_t k = std::max_element(sharp.sigma.begin(), sharp.sigma.end()) - sharp.sigma.begin();
  EXPECT_LE(sharp.sigma_lower[k], truth.sigma_c);
  EXPECT_GE(sharp.sigma_upper[k], truth.sigma_c);
  const std::string text = sharp.Summary();
  EXPECT_NE(text.find(fmt::format("peak sigma {:.4g} MPa", 1e-6 * sharp.sigma[k])),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("(95 % band "), std::string::npos) << text;
  EXPECT_EQ(text.find("not resolved"), std::string::npos) << text;
  for (double& u : data.uncertainty) u *= 20.0;
  const LawFreeResult vague = LawFromFarFieldJ(data);
  EXPECT_NE(vague.Summary().find("warning: the peak is not resolved"), std::string::npos)
      << vague.Summary();
}

// Where the summary says sigma is resolved (band half-width <= 10 % of the
// peak), the truth is within 10 % of the peak of the curve: the claim holds
// if the band does. Four laws, J_ff at 0.5 % and 2 % noise (u scaled with
// it), 20 seeds each (measured: 5839 of 6560 nodes resolved, 99.1 % of
// them within 10 % of the peak); the R route without steady state resolves nothing
// (sigma there is known only up to + C delta).
TEST(LawFree, TheResolvedNodesAreWithinTheirShareOfThePeak) {
  std::vector<Truth> laws = Families();
  laws.push_back(Trilinear());
  int resolved = 0, within = 0, nodes = 0;
  for (const Truth& truth : laws)
    for (double scale : {1.0, 4.0})
      for (int seed = 200; seed < 220; ++seed) {
        FarFieldJSamples data = MakeFarFieldJ(truth, 1.4, seed);
        // Scale the noise about the noise-free value J = u / kNoise.
        for (size_t i = 0; i < data.J_ff.size(); ++i) {
          const double J = data.uncertainty[i] / kNoise;
          data.J_ff[i] = J + scale * (data.J_ff[i] - J);
          data.uncertainty[i] *= scale;
        }
        const LawFreeResult r = LawFromFarFieldJ(data);
        ASSERT_EQ(r.resolved.size(), r.delta.size());
        const double peak = *std::max_element(r.sigma.begin(), r.sigma.end());
        for (size_t j = 0; j < r.delta.size(); ++j) {
          ++nodes;
          if (!r.resolved[j]) continue;
          ++resolved;
          within += std::abs(r.sigma[j] - truth.Law().Traction(r.delta[j])) <= 0.10 * peak;
        }
      }
  const double share = double(within) / resolved;
  std::printf("resolved %d of %d nodes; within 10 %% of the peak there: %.1f %%\n", resolved, nodes,
              100 * share);
  EXPECT_GT(resolved, nodes / 4);  // not vacuous
  EXPECT_LT(resolved, nodes);      // and not everywhere
  EXPECT_GE(share, 0.95);
  const LawFreeResult open =
      LawFromRCurve(MakeRCurve(MakeTruth("linear", MakeLinearShape()), 0.6, 3));
  ASSERT_FALSE(open.identified);
  EXPECT_EQ(open.ResolvedCount(), 0);
}

// Data scattering twice their stated u: the band is widened and a note says so.
TEST(LawFree, UnderstatedUncertaintyWidensTheBand) {
  const Truth truth = MakeTruth("linear", MakeLinearShape());
  RCurveSamples data = MakeRCurve(truth, 1.4, 5);
  const LawFreeResult honest = LawFromRCurve(data);
  for (double& u : data.uncertainty) u /= 2.0;
  const LawFreeResult understated = LawFromRCurve(data);
  EXPECT_NEAR(understated.noise_scale, 2.0, 0.3);
  EXPECT_TRUE(HasNote(understated, "scatter")) << understated.Summary();
  const size_t mid = honest.delta.size() / 4;
  EXPECT_NEAR(understated.sigma_standard_error[mid] / honest.sigma_standard_error[mid], 1.0, 0.3);
}

// The optional penalty rules (they trust the stated u): the R route still
// recovers the law (measured worst 2.1 % and 2.9 % RMS over 200 seeds), the
// discrepancy principle ends with chi^2 <= n, or at the smallest penalty
// with a note when the stated u are too small for any penalty to reach it.
TEST(LawFree, OptionalPenaltyRulesRecoverTheLaw) {
  const Truth truth = MakeTruth("cubic", MakeCubicShape());
  for (PenaltyRule rule : {PenaltyRule::kUnbiasedRisk, PenaltyRule::kDiscrepancy}) {
    LawFreeOptions o;
    o.penalty_rule = rule;
    for (int seed = 1; seed <= 3; ++seed) {
      const LawFreeResult r = LawFromRCurve(MakeRCurve(truth, 1.4, seed), o);
      EXPECT_LT(Measure(truth, r).sigma_rms, 0.05) << r.Summary();
      if (rule == PenaltyRule::kDiscrepancy) {
        EXPECT_LE(r.chi2, r.points_used);
      }
    }
  }
  LawFreeOptions o;
  o.penalty_rule = PenaltyRule::kDiscrepancy;
  RCurveSamples data = MakeRCurve(truth, 1.4, 1);
  for (double& u : data.uncertainty) u /= 3.0;
  const LawFreeResult r = LawFromRCurve(data, o);
  EXPECT_NEAR(r.penalty_log10_relative, -10.0, 1e-9);
  EXPECT_TRUE(HasNote(r, "edge of its search range")) << r.Summary();
}

// Expects `call` to throw Error naming `field`.
template <class F>
void ExpectInputError(F call, const std::string& field) {
  try {
    call();
    ADD_FAILURE() << "no error for " << field;
  } catch (const Error& e) {
    EXPECT_EQ(e.context().field, field) << e.what();
    EXPECT_FALSE(e.context().expected.empty()) << e.what();
  }
}

TEST(LawFree, BadInputThrowsNamingTheField) {
  const Truth truth = MakeTruth("linear", MakeLinearShape());
  const FarFieldJSamples good = MakeFarFieldJ(truth, 1.4, 1);
  const RCurveSamples good_r = MakeRCurve(truth, 1.4, 1);
  {
    FarFieldJSamples d = good;
    d.J_ff[3] = NAN;
    ExpectInputError([&] { LawFromFarFieldJ(d); }, "J_ff[3]");
  }
  {
    FarFieldJSamples d = good;
    d.opening_uncertainty.assign(3, 1e-6);
    ExpectInputError([&] { LawFromFarFieldJ(d); }, "opening_uncertainty");
    d.opening_uncertainty.assign(d.opening.size(), 1e-6);
    d.opening_uncertainty[20] = -1e-6;
    ExpectInputError([&] { LawFromFarFieldJ(d); }, "opening_uncertainty[20]");
  }
  {
    RCurveSamples d = good_r;
    d.opening[17] = INFINITY;
    ExpectInputError([&] { LawFromRCurve(d); }, "delta_root[17]");
  }
  {
    RCurveSamples d = good_r;
    d.opening[20] = d.opening[40];  // repeated once sorted
    ExpectInputError([&] { LawFromRCurve(d); }, "delta_root[40]");
  }
  {
    FarFieldJSamples d = good;
    d.J_ff.pop_back();
    ExpectInputError([&] { LawFromFarFieldJ(d); }, "J_ff");
  }
  {
    FarFieldJSamples d = good;
    d.uncertainty[5] = 0.0;
    ExpectInputError([&] { LawFromFarFieldJ(d); }, "uncertainty[5]");
  }
  {
    RCurveSamples d = good_r;
    for (auto* v : {&d.opening, &d.R, &d.uncertainty}) v->resize(9);
    ExpectInputError([&] { LawFromRCurve(d); }, "delta_root");
  }
  {
    // Enough samples, but too few after the onset.
    FarFieldJSamples d = good;
    d.onset_index = static_cast<int>(d.J_ff.size()) - 5;
    ExpectInputError([&] { LawFromFarFieldJ(d); }, "J_ff");
  }
  {
    FarFieldJSamples d = good;
    d.onset_index = 1000;
    ExpectInputError([&] { LawFromFarFieldJ(d); }, "onset_index");
    d.onset_opening = 1e-5;
    ExpectInputError([&] { LawFromFarFieldJ(d); }, "onset_index");
  }
  {
    RCurveSamples d = good_r;
    d.J_tip_c = -1.0;
    ExpectInputError([&] { LawFromRCurve(d); }, "J_tip_c");
  }
}

TEST(LawFree, InvalidOptionsAreUsageErrors) {
  std::string why;
  EXPECT_TRUE(LawFreeOptions{}.IsValid(&why)) << why;
  LawFreeOptions o;
  o.grid_points = 2;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("grid_points"), std::string::npos);
  o = {};
  o.plateau_span = 1.5;
  EXPECT_FALSE(o.IsValid(&why));
  const Truth truth = MakeTruth("linear", MakeLinearShape());
  try {
    LawFromRCurve(MakeRCurve(truth, 1.4, 1), o);
    ADD_FAILURE() << "invalid options accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kUsage);
  }
}

}  // namespace
}  // namespace bridgefit::laws
