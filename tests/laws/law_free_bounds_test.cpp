// The law-free routes' stated uncertainties of J_B's lower bound and of
// J_tip,c against the truth of closed-form data (law_free_synthetic.hpp):
// coverage over many seeds, the oracle for a one-sided bound and a 95 %
// interval.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <utility>

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

}  // namespace
}  // namespace bridgefit::laws
