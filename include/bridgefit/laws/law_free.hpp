#pragma once
// The bridging law read from measured curves without assuming its shape,
// PHYSICS.md sections 3, 7 and 10 (issue 21).
//
// Two routes, one discretisation. sigma is piecewise linear on a uniform grid
// of nodes g_0 = 0 < ... < g_{M-1} = the largest opening, with nodal values
// s_j (hat functions phi_j), so W(delta) = int_0^delta sigma is exact:
//   W(delta) = sum_j a_j(delta) s_j,   a_j(delta) = int_0^delta phi_j.
//
// 1. J_ff(delta*) route, eq. (1): during growth J_tip = J_tip,c and
//      J_ff_i = J_tip,c + W(delta_i),   delta_i = delta*_i - delta*_onset,
//    so sigma = dJ_ff/d delta*. The opening is counted from the onset of
//    growth (the first bridged surface starts at zero opening; with a sharp
//    notch delta*_onset is ~0 anyway). J_tip,c is the fitted J_ff at the
//    onset (an unknown of the same least squares, not one noisy sample);
//    samples before the onset (J_tip still rising) are not used.
// 2. R(delta_root) route, eq. (3), elastic zone: with f = R - J_tip,c,
//      f_i = sum_j [a_j(delta_i) - delta_i phi_j(delta_i) / 2] s_j,
//    exact for piecewise-linear sigma. delta_root is the opening at the
//    initial notch root (it keeps growing past delta_c in steady state,
//    where R stays at J_tip,c + J_B). Null space: s_j = C g_j gives f = 0
//    exactly (a linear spring dissipates nothing; (sigma/delta)' =
//    -2 f'/delta^2 fixes sigma/delta only up to a constant). We remove it by
//    s_{M-1} = 0, sigma = 0 at the largest opening. That is the truth only
//    where the data reach steady state; otherwise the result is the member
//    of the family sigma + C delta with sigma(delta_max) = 0, the true law
//    has C = sigma(delta_max) / delta_max >= 0, and the result says so
//    (identified = false, a note, null_space_slope_min).
//
// Regularisation (both routes): weighted penalised least squares
//   min_x sum_i ((y_i - (A x)_i) / u_i)^2 + lambda sum_j (s_{j-1} - 2 s_j + s_{j+1})^2,
// x = (J_tip,c unless given, s). The second-difference penalty leaves linear
// sigma unbiased (the linear law costs nothing). lambda is chosen on a log
// grid by modified generalised cross-validation,
//   V = n chi^2 / (n - gamma tr H)^2,  gamma = 1.4
// (it does not trust the stated u_i's scale). Plain GCV (gamma = 1) now and
// then falls into its near-interpolating minimum: on synthetic J_ff data with
// 0.5 % noise, 1.5-3.5 % of the seeds gave a sigma RMS error of 5-25 % of
// sigma_c; gamma = 1.4 (Kim & Gu 2004, the default of R's gss) left
// none above 3 % in 200 seeds per law. Options: the unbiased predictive risk
// chi^2 + 2 tr H or the discrepancy principle chi^2 <= n (both trust the
// u_i; measured worse on the J_ff route). The band is Wahba's Bayesian
// posterior covariance s^2 (A^T W A + lambda P)^-1, whose pointwise intervals
// cover the truth on average over the points (Nychka 1988) because they
// include the smoothing bias on average, which the plain sampling covariance
// does not; s^2 = max(1, chi^2 / (n - tr H)) widens it when the data scatter
// more than their stated u_i. Where the criterion's best fit lies in the
// penalty's null space (tr H within 0.5 of its dimension: sigma linear),
// that band is only the line's own and a curved law the data do not resolve
// falls out of it (exponential law over 0.3 delta_c: 76 % of the nodes
// covered); the band then allows for the best curved alternative (the
// criterion's best fit with tr H >= the null space + 0.5): its covariance
// plus d d^T, d the step from the line to it (91.7 %; a note says so).
// Negative fitted sigma is clipped to 0 (a note counts the nodes; the band
// is left as computed). The range's ends: sigma there is a
// one-sided derivative, and the penalty chosen for the whole range holds it
// (a plateau law whose drop starts within the last fifth of the data was
// read as a straight line, 20 % of the peak off inside a band of a few %).
// The route is run again on the samples within end_window_fraction of the
// range from each end alone (its own penalty by the same criterion); over
// the half of each window next to its end the band is the union of both
// bands (the R route: its start only, law_free_ends.cpp).
// sigma_standard_error stays the whole fit's.
//
// Steady state: the samples from index p on are "flat within their noise"
// when they cover at least `plateau_span` of the opening range and
// `plateau_min_points` samples and a weighted straight line through them has
// a slope within plateau_z standard errors of zero (the standard error from
// the stated u_i, scaled up by the line's own scatter when that is larger)
// and a rise still allowed over the tail ((|slope| + plateau_z SE) x span)
// of at most plateau_rise_fraction of the curve's rise to the plateau (an
// equivalence test: scattered data that merely fail to show a rise are not
// a plateau); the smallest such p starts the plateau. Then J_B = plateau mean -
// J_tip,c and delta_c = the opening (from the onset) where the plateau
// starts: where the curve levels off to within the noise, which for laws
// that fade smoothly to zero lies below the true delta_c (measured 0.78-1.0
// delta_c at 0.5 % noise). Otherwise (PHYSICS.md section 7) J_B >= J_max -
// J_tip,c with J_max the largest fitted value, lowered by bound_z standard
// errors of that difference (from the fit's covariance; J_B.standard_error
// holds it), and delta_c >= the largest opening, with identified = false.
//
// Onset of growth (J_ff route, when not given): the sample k where the
// least-squares slope through the onset_window samples up to k exceeds the
// next step's slope (k -> k+1) the most; accepted only when that slope is
// onset_kink_ratio times every later window's slope, else the first sample
// is the onset and a note says so.

#include <optional>
#include <string>
#include <vector>

namespace bridgefit::laws {

enum class PenaltyRule {
  kGeneralisedCrossValidation,  // V = n chi^2 / (n - gamma tr H)^2
  kUnbiasedRisk,                // chi^2 + 2 tr H (trusts the stated u_i)
  kDiscrepancy                  // the largest lambda with chi^2 <= n (trusts the stated u_i)
};

struct LawFreeOptions {
  int grid_points = 41;  // sigma nodes from 0 to the largest opening
  int min_points = 10;   // fewer usable samples throw
  PenaltyRule penalty_rule = PenaltyRule::kGeneralisedCrossValidation;
  double gcv_gamma = 1.4;      // GCV's dof inflation (1: plain GCV)
  double band_z = 1.959964;    // half-width of the band in standard errors (95 %)
  // Without steady state J_B >= (largest fitted value - J_tip,c), lowered by
  // bound_z of its standard errors (one-sided 95 %): a bound from noisy data
  // read at its estimate lies above the truth half the time near steady state.
  double bound_z = 1.644854;
  // The penalty's share of J_tip,c's (and the rise's) standard error: the
  // fit again with the penalty times this factor (less smoothing, less
  // bias); the change joins the standard error in quadrature. Where the law
  // curves steeply at the onset (cubic: sigma(0) = 0; exponential) the
  // chosen penalty bends sigma there and J_tip,c reads 1-2 standard errors
  // off (closed-form data, 0.5 % noise); 0: off.
  double penalty_share_factor = 0.01;
  double plateau_span = 0.15;  // flat tail must cover this fraction of the opening range
  int plateau_min_points = 6;
  double plateau_z = 2.0;  // flatness test threshold (standard errors)
  // ... and the rise the tail still allows over its span (|slope| +
  // plateau_z SE) must be at most this fraction of the curve's rise to the
  // plateau: flatness established, not just "not rejected" by noisy data.
  double plateau_rise_fraction = 0.1;
  // Onset detection (J_ff route, when the caller gives no onset; see above).
  int onset_window = 4;
  double onset_kink_ratio = 5.0;
  // A node is resolved where its band's half-width is at most this share of
  // the peak sigma: there the data pin sigma; elsewhere the curve is the
  // penalty's shape inside a wide band (LawFreeResult::resolved).
  double resolved_fraction = 0.10;
  // The range's ends: sigma there is a one-sided derivative, held by the
  // penalty chosen for the whole range. The route is run again on the
  // samples within this fraction of the range from an end alone (its own
  // penalty); over the half of that window next to its end the band is the
  // union of both bands (0: off). J route: both ends. R route: the start,
  // sigma at the window's far end pinned to the whole fit's (R fixes sigma
  // only up to + C delta otherwise); its end is sigma = 0 in steady state
  // and unresolved without. A window with fewer than end_window_min_points
  // samples leaves its end unresolved (a note).
  double end_window_fraction = 0.5;
  int end_window_min_points = 6;
  bool IsValid(std::string* why) const;
};

// J_ff route input. The onset is given by index (into the samples as
// passed) or by opening (the nearest sample); neither: detected.
struct FarFieldJSamples {
  std::vector<double> opening;      // delta* at the initial notch root [m]
  std::vector<double> J_ff;         // far-field J [J/m^2]
  std::vector<double> uncertainty;  // standard uncertainty of J_ff [J/m^2]
  // Standard uncertainty of each opening [m] (empty: none). It enters as J_ff
  // uncertainty sigma(delta_i) u_x,i (effective variance: sigma from a first
  // fit, two more passes).
  std::vector<double> opening_uncertainty;
  std::optional<int> onset_index;
  std::optional<double> onset_opening;  // [m]
};

// R route input (elastic zone).
struct RCurveSamples {
  std::vector<double> opening;      // delta_root, at the initial notch root [m]
  std::vector<double> R;            // energy released per unit growth [J/m^2]
  std::vector<double> uncertainty;  // standard uncertainty of R [J/m^2]
  std::optional<double> J_tip_c;    // [J/m^2]; absent: fitted as R at delta_root = 0
};

enum class LawFreeRoute { kFarFieldJ, kElasticZoneR };

// J_B or delta_c: a point value when identified, else a lower bound.
struct LawFreeEstimate {
  double value = 0.0;
  // J_B: from the plateau mean and J_tip,c (their covariance neglected);
  // delta_c: not estimated (0), as for a bound.
  double standard_error = 0.0;
  bool identified = false;  // false: `value` is a lower bound (PHYSICS.md section 7)
};

struct LawFreeResult {
  LawFreeRoute route = LawFreeRoute::kFarFieldJ;
  // sigma on the grid, opening counted from the onset of growth.
  std::vector<double> delta;                     // [m]
  std::vector<double> sigma;                     // clipped at 0 [Pa]
  std::vector<double> sigma_standard_error;      // [Pa]
  // sigma -+ band_z se, unclipped, widened at the range's ends to hold the
  // end windows' bands (LawFreeOptions::end_window_fraction) [Pa]
  std::vector<double> sigma_lower, sigma_upper;
  double J_tip_c = 0.0;                          // [J/m^2]
  double J_tip_c_standard_error = 0.0;           // 0 when given
  bool J_tip_c_given = false;
  LawFreeEstimate J_B;      // [J/m^2]
  LawFreeEstimate delta_c;  // [m]
  // The data reach steady state: J_B, delta_c and (R route) the C delta
  // term of sigma are fixed. False: bounds only, and on the R route sigma
  // is known only up to + C delta with C >= null_space_slope_min.
  bool identified = false;
  double null_space_slope_min = 0.0;    // [Pa/m], R route when not identified
  int onset_index = 0;                  // J_ff route: into the samples as passed
  bool onset_detected = false;          // J_ff route: found by the unit, not given
  int points_used = 0;                  // samples in the least squares
  int plateau_points = 0;               // samples in the flat tail (0: none)
  double penalty = 0.0;                 // lambda
  double penalty_log10_relative = 0.0;  // log10(lambda / (tr A^T W A / tr P))
  double effective_dof = 0.0;           // tr H
  double chi2 = 0.0;                    // weighted residual sum at the chosen lambda
  double noise_scale = 1.0;             // s = sqrt(max(1, chi2 / (n - tr H))), applied to the band
  double run_seconds = 0.0;
  // Per node: the band's half-width is at most resolved_fraction x the peak
  // sigma (MarkResolved). None on the R route without steady state (sigma
  // is known there only up to + C delta).
  std::vector<char> resolved;
  double resolved_fraction = LawFreeOptions{}.resolved_fraction;
  std::vector<std::string> notes;  // warnings and what was assumed

  bool IsValid(std::string* why) const;
  int ResolvedCount() const;
  // Several lines: route, J_tip,c, J_B, delta_c (value or bound), penalty,
  // fit quality, notes.
  std::string Summary() const;
};

// Sets r.resolved and r.resolved_fraction from the band (the one rule; the
// file reader applies it to files written before the flag existed).
void MarkResolved(double fraction, LawFreeResult& r);

// Samples may come in any order (they are sorted by opening). Throw
// bridgefit::Error (kInput) naming the field and what was expected for sizes
// that differ, non-finite values, u <= 0, fewer than min_points usable
// samples, or openings that repeat; kUsage for invalid options. A fit that
// cannot identify J_B / delta_c is a result, not an error.
LawFreeResult LawFromFarFieldJ(const FarFieldJSamples& data, const LawFreeOptions& options = {});
LawFreeResult LawFromRCurve(const RCurveSamples& data, const LawFreeOptions& options = {});

}  // namespace bridgefit::laws
