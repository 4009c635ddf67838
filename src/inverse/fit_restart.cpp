// The restart stage of FitBridgingLaw (fit.cpp): a fit that stopped in a
// local minimum its own profiles found below is started again there, and
// the earlier rounds' points keep the intervals honest (docs/FIT.md
// "Profiles you can trust").

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "fit_impl.hpp"

namespace bridgefit::inverse::fit_internal {

// A profile point below the optimum means the search stopped in a
// local minimum (the profile re-optimises the other parameters from other
// starts). The fit restarts there: a full local search from that point's
// parameters; nullopt when no point is lower or the search does not beat
// the optimum. The restart is listed among the starts.
std::optional<LocalResult> RestartFromProfiles(const FitContext& c, const LocalResult& best,
                                               double threshold, FitSummary& s) {
  const ProfilePoint* lowest = nullptr;
  const Profile* owner = nullptr;
  const double below = best.chi2 - BelowOptimumTolerance(threshold, best.chi2);
  for (const Profile& profile : s.profiles)
    for (const ProfilePoint& p : profile.points)
      if (p.ok && p.chi2 < below && (!lowest || p.chi2 < lowest->chi2)) {
        lowest = &p;
        owner = &profile;
      }
  if (!lowest) return std::nullopt;
  std::vector<double> x0(c.n_free);
  for (int k = 0; k < c.n_free; ++k)
    x0[k] = ToBox(c.free[k], lowest->parameters[c.free[k]], c.options);
  // A local search (a global optimizer's own polish, BOBYQA, for those).
  const Optimizer optimizer = c.options.optimizer == Optimizer::kDirect || c.options.optimizer == Optimizer::kCrs2
                                  ? Optimizer::kBobyqa
                                  : c.options.optimizer;
  LocalResult r = MinimizeLocal(c.objective, optimizer, x0, c.options.max_evaluations);
  StartResult start;
  for (int k = 0; k < c.n_free; ++k) {
    start.start[c.free[k]] = lowest->parameters[c.free[k]];
    start.end[c.free[k]] = FromBox(c.free[k], r.x[k], c.options);
  }
  start.cost = r.chi2;
  start.evaluations = r.evaluations;
  const bool stress = owner->parameter == kSigmaC;
  start.stop_reason = fmt::format(
      "restart from the {} profile's point at {:.5g} {} (chi^2 {:.5g}, below the optimum's {:.5g}): {}",
      ParameterName(owner->parameter), lowest->value * (stress ? 1e-6 : 1.0),
      stress ? "MPa" : "J/m^2", lowest->chi2, best.chi2, r.stop_reason);
  s.starts.push_back(start);
  if (!(r.chi2 < below)) return std::nullopt;
  return r;
}

// After a restart: the profile points of the earlier rounds (each one a
// parameter set with the chi^2 it gave) that lie within the threshold of
// the new optimum are inside every parameter's 95% region (the profile at a
// value is at most any chi^2 found there), however the new profiles ended.
// An interval that does not reach them is widened to them and marked
// non-smooth: the landscape has more than one basin (validation #232: the
// restarted fit's profiles were smooth around the new optimum and their
// intervals excluded the truth by 3-5 half-widths, unwarned, where the
// first round's had been flagged and wide).
void WidenToEarlierPoints(const FitContext& c, const std::vector<ProfilePoint>& earlier,
                          double optimum_chi2, double threshold, FitSummary& s) {
  for (int index : c.free) {
    ParameterEstimate& e = EstimateOf(s, index);
    double low = e.ci95_low, high = e.ci95_high;
    const ProfilePoint* farthest = nullptr;
    for (const ProfilePoint& p : earlier) {
      if (!p.ok || p.chi2 - optimum_chi2 > threshold) continue;
      const double v = p.parameters[index];
      if (std::isfinite(low) && v < low) low = v, farthest = &p;
      if (std::isfinite(high) && v > high) high = v, farthest = &p;
    }
    if (!farthest) continue;
    const bool stress = index == kSigmaC;
    const std::string reason = fmt::format(
        "a point found before the fit's restart ({} = {:.5g} {}, chi^2 {:.5g}) lies within the "
        "threshold of the new optimum's {:.5g} but outside the profile's interval: the chi^2 has "
        "more than one basin; the interval is widened to it",
        ParameterName(index), farthest->parameters[index] * (stress ? 1e-6 : 1.0),
        stress ? "MPa" : "J/m^2", farthest->chi2, optimum_chi2);
    e.ci95_low = low;
    e.ci95_high = high;
    if (e.interval_status == IntervalStatus::kReliable || e.interval_status == IntervalStatus::kOpen)
      e.interval_status = IntervalStatus::kUnreliableNonSmooth;
    e.interval_reason += (e.interval_reason.empty() ? "" : "; ") + reason;
    if (e.note.find("interval unreliable") == std::string::npos)
      e.note = "interval unreliable (" + std::string(IntervalStatusName(e.interval_status)) +
               "): " + e.interval_reason + "; " + e.note;
  }
}

}  // namespace bridgefit::inverse::fit_internal
