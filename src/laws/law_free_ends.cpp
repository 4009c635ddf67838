// The range's ends of the law-free routes (law_free.hpp, "The range's
// ends"): sigma there is a one-sided derivative, held by the penalty chosen
// for the whole range. A plateau law whose drop starts within the last
// fifth of the data was read as the penalty's straight line, up to 20 % of
// the peak off with a band of a few %, and marked resolved (closed-form
// J_ff, 0.5 % noise, 30 seeds: 61 resolved nodes off by more than 10 % of
// the peak); the cubic law's steep rise from sigma(0) = 0 likewise at the
// start. The route on the samples within end_window_fraction of the range
// from an end alone (its own penalty by the same criterion) fits the data
// there as well; over the half of that window next to its end the band is
// the union of both bands.

#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "bridgefit/core/error.hpp"
#include "bridgefit/laws/law.hpp"
#include "law_free_impl.hpp"

namespace bridgefit::laws::law_free_detail {
namespace {

// The band of a window's own fit at opening x (its grid from the window's
// first sample, `from`): linear between its nodes (the law module's
// piecewise-linear rule).
std::pair<double, double> WindowBandAt(const LawFreeResult& w, double from, double x) {
  const double at = std::clamp(x - from, w.delta.front(), w.delta.back());
  return {detail::PiecewiseValue(w.delta, w.sigma_lower, at),
          detail::PiecewiseValue(w.delta, w.sigma_upper, at)};
}

// r's band over [lo, hi] becomes its union with the window's; returns the
// nodes it widened.
int Union(const LawFreeResult& own, double from, double lo, double hi, LawFreeResult* r) {
  int widened = 0;
  for (size_t j = 0; j < r->delta.size(); ++j) {
    if (r->delta[j] < lo || r->delta[j] > hi) continue;
    const auto [lower, upper] = WindowBandAt(own, from, r->delta[j]);
    widened += lower < r->sigma_lower[j] || upper > r->sigma_upper[j];
    r->sigma_lower[j] = std::min(r->sigma_lower[j], lower);
    r->sigma_upper[j] = std::max(r->sigma_upper[j], upper);
  }
  return widened;
}

// An end the window cannot check (too few samples, or its own fit failed):
// left unresolved, with a note saying why.
void NoteUnchecked(bool tail, double lo, double hi, const std::string& why, LawFreeResult* r) {
  r->notes.push_back(fmt::format(
      "the range's {} ({:.4g} .. {:.4g} mm) rests on the penalty alone ({}); sigma there is "
      "not marked resolved",
      tail ? "end" : "start", 1e3 * lo, 1e3 * hi, why));
}

std::string TooFew(int count, const LawFreeOptions& options) {
  return fmt::format("{} samples lie within {:.0f} % of the range from it, {} are needed for a "
                     "fit of its own",
                     count, 100 * options.end_window_fraction, options.end_window_min_points);
}

void NoteWidened(int widened, LawFreeResult* r) {
  if (widened > 0)
    r->notes.push_back(fmt::format(
        "sigma at the range's ends is a one-sided derivative: the band there also holds a fit of "
        "the samples near the end alone (its own penalty), which widened it at {} nodes",
        widened));
}

// The unclipped fitted sigma of r at opening x (the band's middle).
double FittedSigmaAt(const LawFreeResult& r, double x) {
  const auto [lower, upper] = WindowBandAt(r, 0.0, x);
  return 0.5 * (lower + upper);
}

}  // namespace

OpeningIntervals AllowForTheRangesEnds(const Samples& g, const std::vector<double>& ux,
                                       const LawFreeOptions& options, LawFreeResult* r) {
  OpeningIntervals unchecked;
  if (!(options.end_window_fraction > 0.0)) return unchecked;
  LawFreeOptions inner = options;
  inner.end_window_fraction = 0.0;
  const double range = g.x.back();
  const double reach = options.end_window_fraction * range;
  int widened = 0;
  for (const bool tail : {false, true}) {
    FarFieldJSamples window;
    for (size_t i = 0; i < g.x.size(); ++i) {
      if (tail ? g.x[i] < range - reach : g.x[i] > reach) continue;
      window.opening.push_back(g.x[i]);
      window.J_ff.push_back(g.y[i]);
      window.uncertainty.push_back(g.u[i]);
      window.opening_uncertainty.push_back(ux[i]);
    }
    const int count = static_cast<int>(window.opening.size());
    const double lo = tail ? range - reach / 2 : 0.0, hi = tail ? range : reach / 2;
    if (count < options.end_window_min_points) {
      unchecked.push_back({lo, hi});
      NoteUnchecked(tail, lo, hi, TooFew(count, options), r);
      continue;
    }
    window.onset_index = 0;  // the window's first sample: J_tip,c becomes its constant
    inner.min_points = std::min(options.min_points, count);
    try {
      widened += Union(LawFromFarFieldJ(window, inner), window.opening.front(), lo, hi, r);
    } catch (const Error& e) {
      unchecked.push_back({lo, hi});
      NoteUnchecked(tail, lo, hi, std::string("its own fit failed: ") + e.what(), r);
    }
  }
  NoteWidened(widened, r);
  return unchecked;
}

OpeningIntervals AllowForTheRCurvesStart(const Samples& s, std::optional<double> J_tip_c,
                                         const LawFreeOptions& options, LawFreeResult* r) {
  OpeningIntervals unchecked;
  if (!(options.end_window_fraction > 0.0)) return unchecked;
  const double reach = options.end_window_fraction * s.x.back();
  Samples window;
  for (size_t i = 0; i < s.x.size() && s.x[i] <= reach; ++i) {
    window.x.push_back(s.x[i]);
    window.y.push_back(s.y[i]);
    window.u.push_back(s.u[i]);
  }
  const int count = static_cast<int>(window.x.size());
  if (count < options.end_window_min_points) {
    unchecked.push_back({0.0, reach / 2});
    NoteUnchecked(false, 0.0, reach / 2, TooFew(count, options), r);
    return unchecked;
  }
  // sigma at the window's far end pinned to the whole fit's there (only the
  // half next to the start is read).
  const double sigma_end = FittedSigmaAt(*r, window.x.back());
  const Grid grid = MakeGrid(window.x.back(), options.grid_points);
  const RCurveSystem sys = MakeRCurveSystem(window, grid, J_tip_c, sigma_end);
  PenalisedFit fit;
  try {
    fit = SolvePenalised(sys.A, sys.b, sys.P, options.penalty_rule, options.gcv_gamma);
  } catch (const Error& e) {
    unchecked.push_back({0.0, reach / 2});
    NoteUnchecked(false, 0.0, reach / 2, std::string("its own fit failed: ") + e.what(), r);
    return unchecked;
  }
  PenaltySolution less = LessSmoothed(sys.A, sys.b, sys.P, fit, options);
  // t_j = s_j - sigma_end (MakeRCurveSystem): back to sigma.
  fit.x.segment(sys.offset, sys.free_nodes).array() += sigma_end;
  if (less.x.size() > 0) less.x.segment(sys.offset, sys.free_nodes).array() += sigma_end;
  LawFreeResult own;
  FillSigma(grid, fit, sys.offset, sys.free_nodes, less, options, &own);
  NoteWidened(Union(own, 0.0, 0.0, reach / 2, r), r);
  return unchecked;
}

void LeaveUnresolved(const OpeningIntervals& intervals, LawFreeResult& r) {
  for (const auto& [lo, hi] : intervals)
    for (size_t j = 0; j < r.delta.size(); ++j)
      if (r.delta[j] >= lo && r.delta[j] <= hi) r.resolved[j] = 0;
}

}  // namespace bridgefit::laws::law_free_detail
