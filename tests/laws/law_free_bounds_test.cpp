// The law-free routes' stated uncertainties of J_B's lower bound and of
// J_tip,c against the truth of closed-form data (law_free_synthetic.hpp):
// coverage over many seeds, the oracle for a one-sided bound and a 95 %
// interval.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "bridgefit/laws/law_free.hpp"
#include "law_free_synthetic.hpp"

namespace bridgefit::laws {
namespace {

using namespace synthetic;

// The PHYSICS 7 lower bound J_B >= (largest fitted value - J_tip,c) read
// at its estimate lies above the truth about half the time where the data
// near steady state without establishing it (found 2026-12-05 on synth's
// cubic 3 MPa run: J_B >= 159.2 and, by the R route, >= 200.6 J/m^2 for a
// true 150). Lowered by bound_z standard errors it is one-sided 95 % where
// the fit is unbiased: linear and exponential laws, data ending at 0.6 and
// 0.95 delta_c, 40 seeds, both routes: the bound lies above the true rise
// at the last opening (J_ff: W; R: W - sigma delta / 2; both <= J_B) in at
// most 7.5 % of the unidentified runs (measured 8 of 309). The cubic law
// (sigma(0) = 0, rising steeply) is not: the penalty bends sigma near the
// onset, J_tip,c reads about one of its standard errors low and the rise
// as much high, so its bounds lie above the truth in 19 of 141 runs with
// the penalty's share in the standard error (printed, and docs/LAW_FREE.md;
// 36 without it, 117 unlowered). Unlowered, every family's bounds did in at
// least a quarter.
TEST(LawFree, TheLowerBoundOfJBHoldsOneSided) {
  int runs = 0, above = 0, raw_above = 0, cubic_runs = 0, cubic_above = 0;
  for (const Truth& truth : Families())
    for (double end : {0.6, 0.95})
      for (unsigned seed = 1; seed <= 40; ++seed) {
        const BridgingLaw law = truth.Law();
        const double x_max = end * kDeltaC;
        const LawFreeResult j = LawFromFarFieldJ(MakeFarFieldJ(truth, end, seed));
        const LawFreeResult rc = LawFromRCurve(MakeRCurve(truth, end, seed));
        const std::pair<const LawFreeResult*, double> cases[] = {
            {&j, law.Work(x_max)}, {&rc, ElasticZoneR(law, x_max, kJtipc) - kJtipc}};
        for (const auto& [r, rise] : cases) {
          if (r->J_B.identified) continue;
          EXPECT_GT(r->J_B.standard_error, 0.0);
          const bool is_above = r->J_B.value > rise;
          if (truth.name == "cubic") {
            ++cubic_runs;
            cubic_above += is_above;
            continue;
          }
          ++runs;
          above += is_above;
          raw_above += r->J_B.value + LawFreeOptions{}.bound_z * r->J_B.standard_error > rise;
        }
      }
  std::printf(
      "  lower bounds of J_B above the true rise: linear, exponential %d of %d "
      "(unlowered: %d); cubic %d of %d\n",
      above, runs, raw_above, cubic_above, cubic_runs);
  ASSERT_GT(runs, 200);
  EXPECT_LE(above, 0.075 * runs);
  EXPECT_GE(raw_above, runs / 4);
}

// J_tip,c's 95 % interval on laws that curve steeply at the onset: the
// chosen penalty bends sigma there and J_tip,c read 1-2 standard errors off
// (cubic low, exponential high; closed-form J_ff, 0.5 % noise): 56 of 360
// intervals missed the truth (cubic, data to 1.4 delta_c: 14 of 40). With
// the penalty's share (the fit again at 0.01 x the penalty, the change in
// quadrature) 18 of 360, at most 4 of 40 in any case.
TEST(LawFree, JTipCIntervalHoldsOnLawsThatCurveAtTheOnset) {
  int runs = 0, outside = 0;
  for (const Truth& truth : Families())
    for (double end : {0.6, 0.95, 1.4}) {
      int here = 0;
      double z2 = 0;
      for (unsigned seed = 1; seed <= 40; ++seed) {
        const LawFreeResult r = LawFromFarFieldJ(MakeFarFieldJ(truth, end, seed));
        const double z = (r.J_tip_c - kJtipc) / r.J_tip_c_standard_error;
        here += std::abs(z) > LawFreeOptions{}.band_z;
        z2 += z * z;
      }
      std::printf("  J_tip,c %-11s to %.2f delta_c: RMS z %.2f, %d of 40 outside 95 %%\n",
                  truth.name.c_str(), end, std::sqrt(z2 / 40), here);
      EXPECT_LE(here, 5) << truth.name << " to " << end << " delta_c";
      runs += 40;
      outside += here;
    }
  EXPECT_LE(outside, 0.075 * runs);
}

// The range's ends: sigma there is a one-sided derivative, held by the
// penalty chosen for the whole range. A plateau law whose drop starts within
// the last fifth or third of the data (sigma_c to 0.5 delta_c, then linear
// to zero; or to 0.4, then to 0.8; data to 0.6 delta_c, 0.5 % noise) was
// read as the penalty's straight line, off by up to 20 % of the peak at
// nodes marked resolved. Measured here without the end windows
// (end_window_fraction = 0, asserted so the case stays exercised) and with.
TEST(LawFree, ADropNearTheRangesEndIsNotReadAsTheStraightLine) {
  const Truth plateaus[] = {MakeTruth("plateau to 0.5", MakeTrilinearShape(1, 0.25, 1, 0.5, 1)),
                            MakeTruth("plateau to 0.4", MakeTrilinearShape(1, 0.2, 1, 0.4, 1))};
  LawFreeOptions without;
  without.end_window_fraction = 0.0;
  for (const Truth& truth : plateaus) {
    const BridgingLaw law = truth.Law();
    struct Tally {
      int resolved = 0, off = 0, end_nodes = 0, end_misses = 0;
      double worst = 0.0;
    } tally[2];
    for (unsigned seed = 400; seed < 430; ++seed)
      for (int with = 0; with < 2; ++with) {
        Tally& t = tally[with];
        const LawFreeResult r =
            LawFromFarFieldJ(MakeFarFieldJ(truth, 0.6, seed), with ? LawFreeOptions{} : without);
        const double peak = *std::max_element(r.sigma.begin(), r.sigma.end());
        for (size_t j = 0; j < r.delta.size(); ++j) {
          const double exact = law.Traction(r.delta[j]);
          if (r.resolved[j]) {
            ++t.resolved;
            const double error = std::abs(r.sigma[j] - exact) / peak;
            t.worst = std::max(t.worst, error);
            t.off += error > 0.10;
          }
          if (r.delta[j] >= 0.75 * r.delta.back()) {
            ++t.end_nodes;
            t.end_misses += exact < r.sigma_lower[j] || exact > r.sigma_upper[j];
          }
        }
      }
    for (int with = 0; with < 2; ++with)
      std::printf("  %s, %s end windows: %d resolved nodes, %d beyond 10 %% of the peak (worst "
                  "%.1f %%); band misses %d of %d nodes past 0.75 of the range\n",
                  truth.name.c_str(), with ? "with" : "without", tally[with].resolved,
                  tally[with].off, 100 * tally[with].worst, tally[with].end_misses,
                  tally[with].end_nodes);
    const Tally& before = tally[0];
    const Tally& now = tally[1];
    EXPECT_GE(before.end_misses, before.end_nodes / 10) << truth.name;  // the case is exercised
    EXPECT_GT(now.resolved, 30 * 41 / 2) << truth.name;  // the rule still resolves the rest
    EXPECT_LE(now.off, 0.005 * now.resolved) << truth.name;
    EXPECT_LE(now.end_misses, 0.05 * now.end_nodes) << truth.name;
  }
}

// The R route's start: the cubic law rises steeply from sigma(0) = 0, and
// with steady state reached (data to 1.4 delta_c) the penalty chosen for the
// whole range bent sigma over the first nodes: 11 of 1179 resolved nodes
// more than 10 % of the peak off (worst 23.2 %) over seeds 300 .. 329. The
// start window (sigma pinned at its far end to the whole fit's) holds most
// of it (3 of 1171); measured here without and with on other seeds.
TEST(LawFree, TheRCurvesStartHoldsTheCubicRise) {
  const Truth truth = MakeTruth("cubic", MakeCubicShape());
  const BridgingLaw law = truth.Law();
  LawFreeOptions without;
  without.end_window_fraction = 0.0;
  int resolved[2] = {0, 0}, off[2] = {0, 0}, start_misses[2] = {0, 0}, start_nodes = 0;
  for (unsigned seed = 500; seed < 530; ++seed)
    for (int with = 0; with < 2; ++with) {
      const LawFreeResult r =
          LawFromRCurve(MakeRCurve(truth, 1.4, seed), with ? LawFreeOptions{} : without);
      ASSERT_TRUE(r.identified) << r.Summary();
      const double peak = *std::max_element(r.sigma.begin(), r.sigma.end());
      for (size_t j = 0; j < r.delta.size(); ++j) {
        const double exact = law.Traction(r.delta[j]);
        if (r.resolved[j]) {
          ++resolved[with];
          off[with] += std::abs(r.sigma[j] - exact) > 0.10 * peak;
        }
        if (r.delta[j] <= 0.25 * r.delta.back()) {
          start_nodes += with;
          start_misses[with] += exact < r.sigma_lower[j] || exact > r.sigma_upper[j];
        }
      }
    }
  std::printf("  R route, cubic to 1.4 delta_c: resolved %d / %d nodes, beyond 10 %% of the peak "
              "%d / %d, band misses over the first quarter %d / %d of %d (without / with the "
              "start window)\n",
              resolved[0], resolved[1], off[0], off[1], start_misses[0], start_misses[1],
              start_nodes);
  // Measured 17 / 5 resolved nodes off, 45 / 29 start misses of 300.
  EXPECT_GT(resolved[1], 30 * 41 / 2);
  EXPECT_LT(off[1], off[0]);
  EXPECT_LE(off[1], 0.01 * resolved[1]);
  EXPECT_LT(start_misses[1], start_misses[0]);
  EXPECT_LE(start_misses[1], 0.12 * start_nodes);
}

// Where a window next to an end holds too few samples for a fit of its own
// (or its own fit fails), that end is not marked resolved and a note says so: openings crowded
// towards the range's start (x ~ k^2), 4 of 14 samples in its last half.
TEST(LawFree, AnEndWithTooFewSamplesIsNotMarkedResolved) {
  const Truth truth = MakeTruth("linear", MakeLinearShape());
  const BridgingLaw law = truth.Law();
  FarFieldJSamples d;
  Noise noise(7);
  for (int k = 0; k < 14; ++k) {
    const double x = 0.5 * kDeltaC * (k / 13.0) * (k / 13.0);
    const double J = FarFieldJ(law, x, kJtipc);
    d.opening.push_back(x);
    d.uncertainty.push_back(0.001 * J);
    d.J_ff.push_back(J + 0.001 * J * noise.Next());
  }
  d.onset_index = 0;
  const LawFreeResult r = LawFromFarFieldJ(d);
  const bool noted = std::any_of(r.notes.begin(), r.notes.end(), [](const std::string& n) {
    return n.find("range's end") != std::string::npos &&
           n.find("rests on the penalty alone") != std::string::npos;
  });
  EXPECT_TRUE(noted) << r.Summary();
  int resolved_before = 0;
  for (size_t j = 0; j < r.delta.size(); ++j) {
    if (r.delta[j] >= 0.75 * r.delta.back()) EXPECT_FALSE(r.resolved[j]) << "node " << j;
    else resolved_before += r.resolved[j];
  }
  EXPECT_GT(resolved_before, 0) << r.Summary();  // the rest is judged by its band
  // Allowed a window of 4 samples, its own fit fails (3 unknowns the
  // penalty leaves free: GCV has no degrees of freedom left): the same, with
  // the reason, never an error for the whole result.
  LawFreeOptions four;
  four.end_window_min_points = 4;
  const LawFreeResult f = LawFromFarFieldJ(d, four);
  EXPECT_TRUE(std::any_of(f.notes.begin(), f.notes.end(), [](const std::string& n) {
    return n.find("range's end") != std::string::npos &&
           n.find("its own fit failed") != std::string::npos;
  })) << f.Summary();
  for (size_t j = 0; j < f.delta.size(); ++j)
    if (f.delta[j] >= 0.75 * f.delta.back()) EXPECT_FALSE(f.resolved[j]) << "node " << j;
}

}  // namespace
}  // namespace bridgefit::laws
