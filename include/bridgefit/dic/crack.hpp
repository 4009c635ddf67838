#pragma once
// Crack tip and crack length from a DIC displacement field (PHYSICS.md 9).
//
// The crack line (reference pixels) runs from (x0, y0) on the notch side
// into the material. Stations along it carry the displacement jump (COD
// profile): on each side a plane u(s, n) is fitted to the valid points just
// outside the crack band and extrapolated to n = 0, so the elastic strain
// between +-h is removed to first order. Tip methods:
//  kWilliams: least-squares fit of the near-tip field (mode I terms n=1..N,
//             mode II terms n=1,3,.., rigid motion), linear in the
//             coefficients, 1-D search of the tip along the line on the
//             residual; gives K_I / (2 mu) and the fit residual.
//  kJump:     end of the opened region where the extrapolated opening drops
//             below max(threshold floor, k * noise): biased ahead of the tip.
//  kSqrtCod:  COD^2 linear in s behind the tip (LEFM COD ~ sqrt(r)); fallback.

#include <string>
#include <vector>

#include "bridgefit/dic/correlation.hpp"

namespace bridgefit::dic {

enum class TipMethod { kWilliams, kJump, kSqrtCod };
const char* TipMethodName(TipMethod method);
// "williams" | "jump" | "sqrt"; throws Error(kUsage) otherwise.
TipMethod ParseTipMethod(const std::string& text);

struct CrackTipOptions {
  CrackLine line;
  double station_spacing_px = 5;    // COD profile spacing (use the grid step)
  double band_half_width_px = 16;   // points closer to the line than this are ignored
  double side_depth_px = 15;        // normal extent of the point rows used per side
  double threshold_floor_px = 0.02; // physical floor of the jump threshold
  double noise_factor = 5;          // threshold = max(floor, factor * noise of the jump)
  // Length over which the field's errors are correlated (overlapping
  // subsets share speckle: a subset): the opening's noise is read again from
  // differences of stations whose windows share no point (this plus two
  // station spacings apart) off the first opened run and this far around
  // it, and raises the threshold where it exceeds the neighbours' reading.
  // 0: neighbours only.
  double noise_correlation_px = 0;
  int mode1_terms = 4;              // Williams mode I terms n = 1..N
  int mode2_terms = 2;              // Williams mode II terms n = 1, 3, ..
  double kappa = (3.0 - 0.3) / 1.3; // Kolosov constant (plane stress, nu = 0.3)
  // An orthotropic plate with axis 1 along the crack, plane-stress
  // compliances [1/Pa] (s11 = 1/E1, s22 = 1/E2, s12 = -nu12/E1, s66 =
  // 1/G12); all 0: isotropic (kappa). The tip fit then uses Lekhnitskii's
  // series (orders 1..mode1_terms, both modes) in place of Williams'.
  double s11 = 0, s22 = 0, s12 = 0, s66 = 0;
  bool Orthotropic() const { return s11 != 0 || s22 != 0 || s12 != 0 || s66 != 0; }
  double fit_radius_px = 80;        // Williams fit: points within this radius (at most)
  // Williams window from the data: a failed grid point of an 8-connected
  // cluster of at least this many failed points hides what lies behind it.
  int min_failed_cluster = 3;
  // The window must keep, ahead of its centre and on each side of the line,
  // at least the points of that quadrant of the disk of this fraction of
  // fit_radius_px; otherwise no Williams tip.
  double min_fit_radius_fraction = 0.5;
  double sqrt_window_px = 60;       // sqrt COD fit: window behind the jump tip
  // The closed stretch allowed before the first opened run (see
  // CrackTipResult::closed_lead_px); 0: three stations or the noise's
  // correlation length and two stations (a station's window reaching over
  // the run's correlated error), whichever is longer.
  double max_closed_lead_px = 0;
  double MaxClosedLeadPx() const;
  bool IsValid(std::string* why) const;
};

struct CodProfile {
  std::vector<double> s_px;        // station position along the line
  std::vector<double> opening_px;  // normal jump (positive = open)
  std::vector<double> sliding_px;  // tangential jump
  std::vector<char> valid;         // enough points on both sides
};

struct TipEstimate {
  bool found = false;
  double s_px = 0;            // along the line from (x0, y0)
  double x_px = 0, y_px = 0;  // image position
  double uncertainty_px = 0;  // one standard deviation
};

struct CrackTipResult {
  CodProfile cod;
  bool opening_detected = false;  // some opening above the threshold
  double threshold_px = 0;        // threshold actually used by kJump
  double noise_px = 0;            // robust noise of the opening profile
  TipEstimate williams, jump, sqrt_cod;
  // Share of the sqrt-COD fit's stations within band_half_width_px of its
  // tip: there the opening is read from points about as far from the tip as
  // from the faces and smoothed over a subset reaching past the tip (the tip
  // seems further ahead); MethodsDisagree allows it that share of a band ahead.
  double sqrt_near_tip_share = 0;
  double k_over_2mu_sqrt_px = 0;  // Williams: K_I / (2 mu), px^0.5
  double williams_residual_px = 0;  // RMS residual of the field fit
  int williams_points = 0;
  // Centre of the Williams fit window along the line (the sqrt-COD tip
  // clamped to [jump tip - fit radius, jump tip], else the jump tip): the
  // fit reads the valid points within fit_radius_px of it.
  bool williams_window = false;
  double williams_centre_s_px = 0;
  // The window reads only the continuum: ok points none of whose grid
  // neighbours failed, within fit_radius_px, and not hidden - seen from the
  // centre - behind a failed point of a cluster of min_failed_cluster or
  // more (a hole, a grip, the notch, the image's edge).
  // williams_clear_radius_px: the nearest such failed point (<= fit radius;
  // nothing closer is hidden); williams_hidden_points: continuum points in
  // the window left out as hidden.
  double williams_clear_radius_px = 0;
  int williams_hidden_points = 0;
  // Too little continuum ahead of the centre, above or below the line (less
  // than that quadrant of the disk of min_fit_radius_fraction x fit radius
  // holds): no Williams tip.
  bool williams_window_short = false;
  // The tip found with the radius one station smaller, minus the tip; more
  // than twice its uncertainty (at least one station / sqrt(12)) apart: the
  // tip is unstable, reported but never the length (the fallback is).
  double williams_shift_px = 0;
  bool williams_unstable = false;
  // The Williams tip refitted with closing tractions on the faces (uniform
  // and linear, a bridged crack's near-tip field) minus the traction-free
  // tip, in the fit's window and in the smallest it accepts
  // (min_fit_radius_fraction x fit_radius_px: a zone shorter than the
  // window); the larger is part of williams.uncertainty_px (in quadrature).
  double williams_closing_shift_px = 0;
  double williams_closing_shift_small_px = 0;
  // The tip found in the window of kWindowModelRadius x the fit radius minus
  // the tip; what of it the smaller window's extra noise does not explain
  // (the misfit of a field the series does not hold: a second crack, a
  // grip) is part of williams.uncertainty_px (added in quadrature).
  double williams_window_shift_px = 0;
  double williams_window_share_px = 0;
  // The window's rigid rotation taken out before the fit (radians,
  // counter-clockwise in image axes; 0 where its second-order part is below
  // a tenth of the fit's residual): the series' rigid columns hold a
  // rotation to first order only.
  double williams_rotation_rad = 0;
  TipMethod method = TipMethod::kWilliams;  // the method that gave `tip`
  TipEstimate tip;
  // The found tips differ by more than their stated uncertainties allow
  // (MethodsDisagree: k = 2, each at least one station / sqrt(12); the COD
  // tips may also lie up to a band half width ahead, their documented bias).
  bool methods_disagree = false;
  // The opening still exceeds the threshold at the last station with data on
  // both sides (or the Williams minimum sits at the end of the line): the
  // crack may run beyond the field, so the length is a lower bound.
  bool tip_at_edge = false;
  double last_station_px = 0;  // s of the last station with data on both sides
  // Valid stations read closed (below the threshold) between the line's
  // start and the first opened run, times the station spacing, px. A crack
  // is open from its notch: a run that begins after a closed stretch is not
  // a crack grown from the line's start (a strain concentration, an edge
  // effect, a path found across the crack), and its length from the start
  // means nothing. Detached: more than max_closed_lead_px (CrackTipOptions).
  double closed_lead_px = 0;
  bool opening_detached = false;
};

// The rule of CrackTipResult::methods_disagree, on the found tips of r:
// pairwise |s_a - s_b| > 2 sqrt(sigma_a^2 + sigma_b^2) (each sigma at least
// one station / sqrt(12)), except that the COD tips may lie further ahead
// (their documented bias: the opening read from outside the band runs on
// past the tip): the jump tip up to band_half_width_px ahead of the others,
// the sqrt tip up to sqrt_near_tip_share x band_half_width_px ahead of the
// Williams tip.
bool MethodsDisagree(const CrackTipResult& r, const CrackTipOptions& o);

// The common uncertainty the found tips would need for that rule to pass
// (the largest pairwise distance beyond the allowed bias / (2 sqrt 2)), px;
// 0 where they lie within it. What a reading whose methods disagree is
// worth when compared with another.
double AgreementSigma(const CrackTipResult& r, const CrackTipOptions& o);

// Throws Error(kUsage) for invalid options.
CrackTipResult LocateCrackTip(const DisplacementField& field, const CrackTipOptions& options,
                              TipMethod preferred);

// Weighted isotonic (non-decreasing) regression by pool-adjacent-violators.
// Entries with valid[i] == 0 are skipped and returned unchanged; weights are
// 1 / sigma^2.
std::vector<double> MonotoneNonDecreasing(const std::vector<double>& values,
                                          const std::vector<double>& sigmas,
                                          const std::vector<char>& valid);

}  // namespace bridgefit::dic
