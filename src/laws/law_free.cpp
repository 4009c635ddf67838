// The bridging law from J_ff(delta*) and from R(delta_root) without a law
// family (law_free.hpp has the equations and the choices).

#include "bridgefit/laws/law_free.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "bridgefit/core/error.hpp"
#include "law_free_impl.hpp"

namespace bridgefit::laws {
namespace law_free_detail {

// sigma, its standard error and band on the grid from the fit; nodes past
// `free_nodes` are fixed at zero. The standard error holds the penalty's
// share (sigma's change at the smaller penalty, `less`, less what that
// fit's own extra noise explains): where the penalty bends the curve (a
// kink, a plateau's end, the range's end on few degrees of freedom) the
// covariance alone left the band on the penalty's curve. Adds the clipping
// / monotonicity notes.
void FillSigma(const Grid& grid, const PenalisedFit& fit, int offset, int free_nodes,
               const PenaltySolution& less, const LawFreeOptions& options, LawFreeResult* r) {
  int clipped = 0, significantly_negative = 0;
  for (size_t j = 0; j < grid.nodes.size(); ++j) {
    const bool free = static_cast<int>(j) < free_nodes;
    const Eigen::Index k = offset + static_cast<Eigen::Index>(j);
    const double value = free ? fit.x[k] : 0.0;
    double se = 0.0;
    if (free) {
      const double variance = std::max(0.0, fit.covariance(k, k));
      double share2 = 0.0;
      if (less.x.size() > 0) {
        // The change at the smaller penalty less what its own extra noise
        // explains (nested fits: Var(change) = Var(less) - Var(fit)).
        const double change = less.x[k] - fit.x[k];
        share2 = std::max(0.0, change * change - std::max(0.0, less.variance[k] - variance));
      }
      se = std::sqrt(variance + share2);
    }
    r->delta.push_back(grid.nodes[j]);
    r->sigma.push_back(std::max(0.0, value));
    r->sigma_standard_error.push_back(se);
    r->sigma_lower.push_back(value - options.band_z * se);
    r->sigma_upper.push_back(value + options.band_z * se);
    clipped += value < 0.0;
    significantly_negative += value + options.band_z * se < 0.0;
  }
  if (clipped > 0)
    r->notes.push_back(fmt::format("negative sigma clipped to 0 at {} of {} grid nodes", clipped,
                                   grid.nodes.size()));
  if (significantly_negative > 0)
    r->notes.push_back(fmt::format(
        "the curve falls beyond its noise ({} grid nodes have sigma < 0 with their whole band): "
        "non-monotone data (unloading, edge effect or bad samples?)",
        significantly_negative));
}

// The fit at penalty_share_factor x its penalty, with its posterior
// variances at the chosen fit's noise scale (empty when off).
PenaltySolution LessSmoothed(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                             const Eigen::MatrixXd& P, const PenalisedFit& fit,
                             const LawFreeOptions& options) {
  if (!(options.penalty_share_factor > 0.0)) return {};
  return SolveAtPenalty(A, b, P, options.penalty_share_factor * fit.lambda, fit.noise_scale);
}

}  // namespace law_free_detail
namespace {

using namespace law_free_detail;

void CheckOptions(const LawFreeOptions& options) {
  std::string why;
  if (!options.IsValid(&why))
    throw Error(ErrorKind::kUsage, "invalid law-free options: " + why, {.field = "LawFreeOptions"});
}

// Samples [first, end) with openings counted from sample `first`.
Samples FromOnset(const Samples& s, int first) {
  Samples out;
  for (size_t i = first; i < s.x.size(); ++i) {
    out.x.push_back(s.x[i] - s.x[first]);
    out.y.push_back(s.y[i]);
    out.u.push_back(s.u[i]);
    out.order.push_back(s.order[i]);
  }
  return out;
}

// The samples' opening uncertainties from the onset on, in the order of
// FromOnset (zeros when the caller gives none); throws naming the field.
std::vector<double> OpeningUncertainty(const FarFieldJSamples& data, const Samples& s, int first) {
  const std::vector<double>& ux = data.opening_uncertainty;
  std::vector<double> out(s.x.size() - first, 0.0);
  if (ux.empty()) return out;
  BF_CHECK_INPUT(ux.size() == data.opening.size(), "every opening needs one uncertainty",
                 {.field = "opening_uncertainty",
                  .value = fmt::format("{} values", ux.size()),
                  .expected = fmt::format("{} (as many as opening), or none", data.opening.size())});
  for (size_t i = 0; i < ux.size(); ++i)
    BF_CHECK_INPUT(std::isfinite(ux[i]) && ux[i] >= 0.0,
                   "opening uncertainties must be finite and >= 0",
                   {.field = fmt::format("opening_uncertainty[{}]", i),
                    .value = std::to_string(ux[i]),
                    .expected = "u >= 0 [m]"});
  for (size_t k = first; k < s.x.size(); ++k) out[k - first] = ux[s.order[k]];
  return out;
}

// Onset as a sorted index: given by index or opening, else detected.
int ResolveOnset(const FarFieldJSamples& data, const Samples& s, const LawFreeOptions& options,
                 LawFreeResult* result) {
  const int n = static_cast<int>(s.x.size());
  BF_CHECK_INPUT(!(data.onset_index && data.onset_opening),
                 "give the onset of growth by index or by opening, not both",
                 {.field = "onset_index", .expected = "onset_index or onset_opening"});
  if (data.onset_index) {
    const int given = *data.onset_index;
    BF_CHECK_INPUT(given >= 0 && given < n, "the onset index is outside the samples",
                   {.field = "onset_index",
                    .value = std::to_string(given),
                    .expected = fmt::format("0 .. {}", n - 1)});
    return static_cast<int>(std::find(s.order.begin(), s.order.end(), given) - s.order.begin());
  }
  if (data.onset_opening) {
    const double at = *data.onset_opening;
    BF_CHECK_INPUT(std::isfinite(at), "the onset opening must be finite",
                   {.field = "onset_opening",
                    .value = std::to_string(at),
                    .expected = "an opening [m] within the samples"});
    int nearest = 0;
    for (int i = 1; i < n; ++i)
      if (std::abs(s.x[i] - at) < std::abs(s.x[nearest] - at)) nearest = i;
    return nearest;
  }
  std::string note;
  const int onset = DetectOnset(s, options, &note);
  result->onset_detected = true;
  if (!note.empty()) result->notes.push_back(note);
  return onset;
}

void RecordFit(const PenalisedFit& fit, int points, const LawFreeOptions& options,
               LawFreeResult* r) {
  r->points_used = points;
  r->penalty = fit.lambda;
  r->penalty_log10_relative = fit.log10_relative;
  r->effective_dof = fit.trace_h;
  r->chi2 = fit.chi2;
  r->noise_scale = fit.noise_scale;
  if (fit.at_search_edge)
    r->notes.push_back(
        fmt::format("the penalty sits on the edge of its search range "
                    "(log10 relative {:.1f}): the choice is not a true optimum",
                    fit.log10_relative));
  if (fit.null_space_allowance_dof > 0.0)
    r->notes.push_back(fmt::format(
        "the penalty chose sigma linear in delta (effective dof {:.1f}): the data do not resolve "
        "curvature, so the band allows for the best curved fit (effective dof {:.1f}), which a "
        "law that curves unseen may follow",
        fit.trace_h, fit.null_space_allowance_dof));
  if (fit.noise_scale > 1.5)
    r->notes.push_back(
        fmt::format("the data scatter {:.2f} times their stated uncertainty; the "
                    "band is widened by that factor",
                    fit.noise_scale));
  if (points < 2 * options.grid_points)
    r->notes.push_back(
        fmt::format("only {} samples for {} sigma nodes: between samples the "
                    "penalty, not the data, shapes sigma",
                    points, options.grid_points));
}

// J_B and delta_c from a plateau, else the PHYSICS.md section 7 bounds:
// `rise` the largest fitted value minus J_tip,c, `rise_se` its standard
// error.
void SteadyStateOrBounds(const Samples& g, const Plateau& plateau, double rise, double rise_se,
                         const char* curve, const LawFreeOptions& options, LawFreeResult* r) {
  r->identified = plateau.found;
  if (plateau.found) {
    r->plateau_points = static_cast<int>(g.x.size()) - plateau.start;
    r->J_B = {.value = plateau.mean - r->J_tip_c,
              .standard_error = std::hypot(plateau.mean_se, r->J_tip_c_standard_error),
              .identified = true};
    r->delta_c = {.value = g.x[plateau.start], .standard_error = 0.0, .identified = true};
    r->notes.push_back(fmt::format(
        "{} levels off from delta = {:.4g} mm over {} samples (steady state): J_B = plateau - "
        "J_tip,c; delta_c is where the curve is flat within its noise (a little below the "
        "true delta_c when the law fades smoothly)",
        curve, 1e3 * r->delta_c.value, r->plateau_points));
    return;
  }
  r->J_B = {.value = std::max(0.0, rise - options.bound_z * rise_se),
            .standard_error = rise_se,
            .identified = false};
  r->delta_c = {.value = g.x.back(), .identified = false};
  r->notes.push_back(fmt::format(
      "{} never levels off (no flat tail over the stated span): J_B >= {:.1f} J/m^2 (largest "
      "fitted value - J_tip,c = {:.1f}, lowered by {:.3g} of its standard errors, {:.1f}: "
      "one-sided 95 %) and delta_c >= {:.4g} mm (largest opening) are lower bounds (PHYSICS.md "
      "section 7), not values",
      curve, r->J_B.value, rise, options.bound_z, rise_se, 1e3 * r->delta_c.value));
}

// The standard error of the fitted combination a . x: the fit's covariance
// and, with `less_smoothed` (the fit at a smaller penalty; empty: none),
// the combination's change there in quadrature (the penalty's share).
double StandardError(const Eigen::RowVectorXd& a, const PenalisedFit& fit,
                     const Eigen::VectorXd& less_smoothed) {
  const double variance = (a * fit.covariance * a.transpose())(0, 0);
  const double share = less_smoothed.size() > 0 ? a.dot(less_smoothed - fit.x) : 0.0;
  return std::hypot(std::sqrt(std::max(0.0, variance)), share);
}

// J_tip,c's standard error: the constant column's (index 0).
double JTipStandardError(const PenalisedFit& fit, const Eigen::VectorXd& less_smoothed) {
  return StandardError(Eigen::RowVectorXd::Unit(fit.x.size(), 0), fit, less_smoothed);
}

// The largest fitted value minus the constant column's (J_tip,c), from the
// rows of the unweighted design, and its standard error.
std::pair<double, double> LargestRise(const Eigen::MatrixXd& rows, const PenalisedFit& fit,
                                      bool has_constant, const Eigen::VectorXd& less_smoothed) {
  Eigen::Index best = 0;
  (rows * fit.x).maxCoeff(&best);
  Eigen::RowVectorXd a = rows.row(best);
  if (has_constant) a(0) = 0.0;
  return {a.dot(fit.x), StandardError(a, fit, less_smoothed)};
}

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

bool LawFreeOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (grid_points < 4) return fail(fmt::format("grid_points must be >= 4, got {}", grid_points));
  if (min_points < 4) return fail(fmt::format("min_points must be >= 4, got {}", min_points));
  if (!(band_z > 0.0)) return fail("band_z must be > 0");
  if (!(bound_z >= 0.0)) return fail("bound_z must be >= 0");
  if (!(penalty_share_factor >= 0.0 && penalty_share_factor < 1.0))
    return fail("penalty_share_factor must be in [0, 1)");
  if (!(resolved_fraction > 0.0)) return fail("resolved_fraction must be > 0");
  if (!(end_window_fraction >= 0.0 && end_window_fraction <= 0.5))
    return fail("end_window_fraction must be in [0, 0.5]");
  if (end_window_min_points < 4) return fail("end_window_min_points must be >= 4");
  if (!(gcv_gamma >= 1.0 && gcv_gamma < 3.0)) return fail("gcv_gamma must be in [1, 3)");
  if (!(plateau_span > 0.0 && plateau_span < 1.0)) return fail("plateau_span must be in (0, 1)");
  if (plateau_min_points < 3) return fail("plateau_min_points must be >= 3");
  if (!(plateau_z > 0.0)) return fail("plateau_z must be > 0");
  if (!(plateau_rise_fraction > 0.0 && plateau_rise_fraction < 1.0))
    return fail("plateau_rise_fraction must be in (0, 1)");
  if (onset_window < 2) return fail("onset_window must be >= 2");
  if (!(onset_kink_ratio > 1.0)) return fail("onset_kink_ratio must be > 1");
  return true;
}

LawFreeResult LawFromFarFieldJ(const FarFieldJSamples& data, const LawFreeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CheckOptions(options);
  const Samples s = CheckAndSort(data.opening, data.J_ff, data.uncertainty, "opening", "J_ff",
                                 options.min_points);
  LawFreeResult r;
  r.route = LawFreeRoute::kFarFieldJ;
  const int onset = ResolveOnset(data, s, options, &r);
  r.onset_index = s.order[onset];
  const Samples g = FromOnset(s, onset);
  const int n = static_cast<int>(g.x.size());
  BF_CHECK_INPUT(n >= options.min_points, "too few samples after the onset of growth",
                 {.field = "J_ff",
                  .value = fmt::format("{} samples from the onset on", n),
                  .expected = fmt::format("at least {}", options.min_points)});

  // J_ff_i = J_tip,c + sum_j a_j(delta_i) s_j; unknowns (J_tip,c, s).
  const Grid grid = MakeGrid(g.x.back(), options.grid_points);
  const int m = options.grid_points;
  const std::vector<double> ux = OpeningUncertainty(data, s, onset);
  std::vector<double> u = g.u;
  // Unweighted rows (1, a_j(delta_i)), built once; each pass divides by u.
  Eigen::MatrixXd G(n, m + 1);
  for (int i = 0; i < n; ++i) {
    G(i, 0) = 1.0;
    G.block(i, 1, 1, m) = HatIntegrals(grid, g.x[i]);
  }
  Eigen::MatrixXd A(n, m + 1);
  Eigen::VectorXd b(n);
  const Eigen::MatrixXd D = SecondDifferences(m);
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(m + 1, m + 1);
  P.bottomRightCorner(m, m) = D.transpose() * D;
  PenalisedFit fit;
  // Effective variance: an opening's uncertainty u_x moves J_ff by sigma u_x,
  // so u_i^2 = u_J,i^2 + (sigma(delta_i) u_x,i)^2 with sigma from the
  // previous pass (Orear 1982); two passes after the first settle it.
  const bool has_ux = std::any_of(ux.begin(), ux.end(), [](double v) { return v > 0.0; });
  for (int pass = 0; pass < (has_ux ? 3 : 1); ++pass) {
    for (int i = 0; i < n; ++i) {
      if (pass > 0) {
        const double sigma_i = std::max(0.0, HatValues(grid, g.x[i]).dot(fit.x.tail(m)));
        u[i] = std::hypot(g.u[i], sigma_i * ux[i]);
      }
      A.row(i) = G.row(i) / u[i];
      b[i] = g.y[i] / u[i];
    }
    fit = SolvePenalised(A, b, P, options.penalty_rule, options.gcv_gamma);
  }

  const PenaltySolution less = LessSmoothed(A, b, P, fit, options);
  r.J_tip_c = fit.x[0];
  r.J_tip_c_standard_error = JTipStandardError(fit, less.x);
  FillSigma(grid, fit, 1, m, less, options, &r);
  RecordFit(fit, n, options, &r);
  const auto [rise, rise_se] = LargestRise(G, fit, true, less.x);
  SteadyStateOrBounds(g, FindPlateau(g, 0, options), rise, rise_se, "J_ff", options, &r);
  const auto unchecked = AllowForTheRangesEnds(g, ux, options, &r);
  MarkResolved(options.resolved_fraction, r);
  LeaveUnresolved(unchecked, r);
  r.run_seconds = Seconds(start);
  return r;
}

LawFreeResult LawFromRCurve(const RCurveSamples& data, const LawFreeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CheckOptions(options);
  const Samples s =
      CheckAndSort(data.opening, data.R, data.uncertainty, "delta_root", "R", options.min_points);
  BF_CHECK_INPUT(s.x.front() >= 0.0, "notch-root openings must be >= 0",
                 {.field = "delta_root",
                  .value = std::to_string(s.x.front()),
                  .expected = "openings >= 0 [m]"});
  if (data.J_tip_c)
    BF_CHECK_INPUT(std::isfinite(*data.J_tip_c) && *data.J_tip_c > 0.0,
                   "J_tip,c must be finite and positive",
                   {.field = "J_tip_c",
                    .value = std::to_string(*data.J_tip_c),
                    .expected = "a value > 0 [J/m^2], or none to fit it"});
  LawFreeResult r;
  r.route = LawFreeRoute::kElasticZoneR;
  r.J_tip_c_given = data.J_tip_c.has_value();
  const int n = static_cast<int>(s.x.size());

  // f_i = sum_j [a_j(delta_i) - delta_i phi_j(delta_i) / 2] s_j, with the
  // last node fixed (s_{M-1} = 0) to remove the null space s_j = C g_j.
  const Grid grid = MakeGrid(s.x.back(), options.grid_points);
  const RCurveSystem system = MakeRCurveSystem(s, grid, data.J_tip_c, 0.0);
  const Eigen::MatrixXd& A = system.A;
  const Eigen::VectorXd& b = system.b;
  const Eigen::MatrixXd& P = system.P;
  const int offset = system.offset, free_nodes = system.free_nodes;
  const PenalisedFit fit = SolvePenalised(A, b, P, options.penalty_rule, options.gcv_gamma);

  const PenaltySolution less = LessSmoothed(A, b, P, fit, options);
  r.J_tip_c = r.J_tip_c_given ? *data.J_tip_c : fit.x[0];
  r.J_tip_c_standard_error = r.J_tip_c_given ? 0.0 : JTipStandardError(fit, less.x);
  FillSigma(grid, fit, offset, free_nodes, less, options, &r);
  RecordFit(fit, n, options, &r);
  Eigen::MatrixXd rows = A;  // unweighted: R_i - (a given J_tip,c)
  for (int i = 0; i < n; ++i) rows.row(i) *= s.u[i];
  const auto [rise, rise_se] = LargestRise(rows, fit, !r.J_tip_c_given, less.x);
  SteadyStateOrBounds(s, FindPlateau(s, 0, options), rise, rise_se, "R", options, &r);
  if (!r.identified) {
    // sigma_true = sigma + C delta; sigma_true >= 0 everywhere needs C >= -sigma_j / g_j,
    // and sigma_true(delta_max) = C delta_max >= 0 needs C >= 0.
    for (int j = 1; j < free_nodes; ++j)
      r.null_space_slope_min = std::max(r.null_space_slope_min, -fit.x[offset + j] / grid.nodes[j]);
    r.notes.push_back(fmt::format(
        "without steady state R fixes sigma only up to + C delta (a linear spring dissipates "
        "nothing): the sigma shown is the member with sigma = 0 at the largest opening, the "
        "true law is sigma + C delta with unknown C >= {:.4g} Pa/m",
        r.null_space_slope_min));
  }
  const auto unchecked = AllowForTheRCurvesStart(s, data.J_tip_c, options, &r);
  MarkResolved(options.resolved_fraction, r);
  LeaveUnresolved(unchecked, r);
  r.run_seconds = Seconds(start);
  return r;
}

void MarkResolved(double fraction, LawFreeResult& r) {
  r.resolved_fraction = fraction;
  r.resolved.assign(r.delta.size(), 0);
  const bool up_to_c_delta = r.route == LawFreeRoute::kElasticZoneR && !r.identified;
  if (r.sigma.empty() || up_to_c_delta || r.sigma_lower.size() != r.sigma.size() ||
      r.sigma_upper.size() != r.sigma.size())
    return;
  const double peak = *std::max_element(r.sigma.begin(), r.sigma.end());
  for (size_t j = 0; j < r.sigma.size(); ++j)
    r.resolved[j] = peak > 0.0 && 0.5 * (r.sigma_upper[j] - r.sigma_lower[j]) <= fraction * peak;
}

int LawFreeResult::ResolvedCount() const {
  return static_cast<int>(std::count(resolved.begin(), resolved.end(), 1));
}

bool LawFreeResult::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  const size_t m = delta.size();
  if (m < 2) return fail("the sigma grid has fewer than two nodes");
  if (sigma.size() != m || sigma_standard_error.size() != m || sigma_lower.size() != m ||
      sigma_upper.size() != m)
    return fail("the sigma grid's columns differ in length");
  for (size_t j = 0; j < m; ++j) {
    if (!std::isfinite(delta[j]) || !std::isfinite(sigma[j]) || !std::isfinite(sigma_lower[j]) ||
        !std::isfinite(sigma_upper[j]))
      return fail(fmt::format("non-finite value at grid node {}", j));
    if (j > 0 && !(delta[j] > delta[j - 1])) return fail("grid openings must increase");
    if (sigma[j] < 0.0 || sigma_lower[j] > sigma_upper[j])
      return fail(fmt::format("sigma or its band is malformed at node {}", j));
  }
  if (!std::isfinite(J_tip_c) || !std::isfinite(J_B.value) || !std::isfinite(delta_c.value))
    return fail("J_tip,c, J_B and delta_c must be finite");
  if (J_B.identified != identified || delta_c.identified != identified)
    return fail("J_B, delta_c and the result disagree on identification");
  return true;
}

std::string LawFreeResult::Summary() const {
  const double z95 = LawFreeOptions{}.band_z;  // the 95 % band's z, its one home
  std::string out = fmt::format(
      "bridging law without a family, {} route: {} samples, sigma on {} nodes to {:.4g} mm\n",
      route == LawFreeRoute::kFarFieldJ ? "J_ff(delta*)" : "R(delta_root)", points_used,
      delta.size(), 1e3 * delta.back());
  if (route == LawFreeRoute::kFarFieldJ)
    out += fmt::format("  onset of growth: sample {} ({})\n", onset_index,
                       onset_detected ? "detected" : "given");
  out += J_tip_c_given
             ? fmt::format("  J_tip,c = {:.1f} J/m^2 (given)\n", J_tip_c)
             : fmt::format(
                   "  J_tip,c = {:.1f} +- {:.1f} J/m^2 (1 standard error; 95 %: {:.1f} .. "
                   "{:.1f})\n",
                   J_tip_c, J_tip_c_standard_error, J_tip_c - z95 * J_tip_c_standard_error,
                   J_tip_c + z95 * J_tip_c_standard_error);
  if (identified) {
    out += fmt::format(
        "  J_B = {:.1f} +- {:.1f} J/m^2 (1 standard error), delta_c = {:.4g} mm (steady state, {} "
        "samples)\n",
        J_B.value, J_B.standard_error, 1e3 * delta_c.value, plateau_points);
  } else {
    out += fmt::format("  not identified: J_B >= {:.1f} J/m^2, delta_c >= {:.4g} mm\n", J_B.value,
                       1e3 * delta_c.value);
  }
  if (!sigma.empty()) {
    // The peak with its band: a number printed without one would read as
    // sigma_c measured to its last digit.
    const size_t k = std::max_element(sigma.begin(), sigma.end()) - sigma.begin();
    const double half = 0.5 * (sigma_upper[k] - sigma_lower[k]);
    out +=
        fmt::format("  peak sigma {:.4g} MPa at delta {:.4g} mm (95 % band {:.4g} .. {:.4g} MPa)\n",
                    1e-6 * sigma[k], 1e3 * delta[k], 1e-6 * std::max(0.0, sigma_lower[k]),
                    1e-6 * sigma_upper[k]);
    const int count = ResolvedCount();
    if (count > 0) {
      size_t first = resolved.size(), last = 0;
      for (size_t j = 0; j < resolved.size(); ++j)
        if (resolved[j]) first = std::min(first, j), last = j;
      out += fmt::format(
          "  sigma resolved to +-{:.0f} % of the peak (95 % band) on {} of {} nodes, delta {:.4g} "
          ".. {:.4g} mm; elsewhere read the curve with its band\n",
          100 * resolved_fraction, count, resolved.size(), 1e3 * delta[first], 1e3 * delta[last]);
    } else if (!resolved.empty()) {
      out += fmt::format(
          "  sigma resolved to +-{:.0f} % of the peak nowhere: the curve is the penalty's shape "
          "inside its band (more frames pin it)\n",
          100 * resolved_fraction);
    }
    if (half > 0.5 * sigma[k])
      out += fmt::format(
          "  warning: the peak is not resolved (its band is +-{:.0f} % wide): the frames do not "
          "pin sigma there; more frames near that opening, or a family fit (`fit --law "
          "compare`), pin it better\n",
          100 * half / sigma[k]);
  }
  out += fmt::format(
      "  penalty {:.3g} (log10 relative {:.1f}), effective dof {:.1f}, chi2 {:.1f}, noise scale "
      "{:.2f}, {:.3f} s\n",
      penalty, penalty_log10_relative, effective_dof, chi2, noise_scale, run_seconds);
  for (const std::string& note : notes) out += "  note: " + note + "\n";
  return out;
}

}  // namespace bridgefit::laws
