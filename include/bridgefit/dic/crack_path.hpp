#pragma once
// The crack path found from a displacement field (PHYSICS.md 9), so that the
// crack line a user gives is only a hint.
//
// Along stations s_k across the expected crack (every `station_spacing_px`
// along the hint direction, or along x and along y when there is no hint),
// the normal displacement u_n(n) of the points in the station's column is
// split at a trial position n_c: a straight line u_n(n) is fitted on each side
// to the points at gap <= |n - n_c| <= gap + depth and both are evaluated at
// n_c; their difference J(n_c) is the displacement jump if the crack lies at
// n_c. Points closer than the gap to the crack are smeared or failed subsets,
// so |J| is flat (at the opening) while both windows stay clear of the crack
// and falls off symmetrically once one window takes in the crack: the crack is
// at the centre of the run where |J| >= max|J| / 2. Stations whose
// max|J| >= max(min_jump_px, noise_factor x side-fit residual) are crack
// points (those below `min_relative_jump` of the largest are dropped: their
// position fades with the jump, and only the connected run of stations -
// gaps of up to two - with the largest summed jump is kept); a straight line n = a + b s is fitted to them (weights J^2,
// outliers beyond 3 robust sigma or 1 px dropped, three rounds). With a hint,
// a fitted slope within two standard errors of the hint's keeps the hint's
// direction (a short or scattered run cannot resolve the angle).
//
// The path starts at the hint's start point projected on the fitted line, or,
// without a hint, where the line enters the field on the notch side (the end
// of the detected run with the larger opening) and runs to the field's far
// edge. It disagrees with the hint when the two lines are further apart at an
// end of the cracked length than twice the line's uncertainty there (the
// resolution `hint_tolerance_px` / 2 and the standard error in quadrature). Standard errors: weighted least squares with the sandwich
// (heteroscedastic) covariance, times n / (n - p), inflated for the
// correlation of neighbouring stations (`error_correlation_px`).

#include <string>
#include <vector>

#include "bridgefit/dic/correlation.hpp"

namespace bridgefit::dic {

struct CrackPathOptions {
  bool has_hint = false;
  CrackLine hint;                    // start point on the notch side and direction
  // With a hint: scan n within +- this of the hint, over the hint's extent
  // (s from -1/2 to L + 1/2 station).
  double search_half_width_px = 40;
  double station_spacing_px = 5;
  double gap_px = 16;                // half width of the smeared band (subset/2 + 1)
  double side_depth_px = 15;         // normal extent of each side window
  double min_jump_px = 0.02;         // physical floor of a detectable jump
  double noise_factor = 5;           // jump > factor x residual of the side fits
  double min_relative_jump = 0.1;    // stations below this share of the largest jump are dropped
  int min_stations = 3;              // crack points needed for a path
  // Without a hint the path runs across this box (the image: 0, 0, width - 1,
  // height - 1); lengths count from where it enters. Empty: the field's extent.
  double bounds_x0 = 0, bounds_y0 = 0, bounds_x1 = -1, bounds_y1 = -1;
  // The path's resolution, as two standard deviations (where straddling
  // subsets fail, half a grid step and more). Path vs hint: further apart at
  // an end of the cracked length than 2 sqrt((this / 2)^2 + se^2), se the
  // fitted line's standard error there = disagree.
  double hint_tolerance_px = 2;
  // The crack points' position errors are correlated over this length
  // along the path (DIC subsets of this size overlap; 0: independent): the
  // line's and the curvature's standard errors are inflated by
  // sqrt(max(1, this / station spacing)).
  double error_correlation_px = 0;
  // Curved: the RMS normal distance of all crack points (outliers of the
  // line fit included) to the line exceeds this AND a parabola through them
  // (weights J^2) has a curvature beyond twice its own standard error. The
  // path is then also given as a polyline (FitCrackPolyline).
  double curved_rms_px = 2;
  bool IsValid(std::string* why) const;
};

struct CrackPathResult {
  bool found = false;
  CrackLine line;  // the path: notch-side start -> far edge of the field (px)
  // Crack points (one per station where the jump was detected), image px,
  // with their jump and whether the line fit kept them.
  std::vector<double> point_x, point_y, point_jump_px;
  std::vector<char> inlier;
  int inliers = 0;
  double rms_residual_px = 0;    // normal RMS distance of the inliers to the line
  double cracked_length_px = 0;  // extent of the inliers along the path
  double angle_deg = 0;          // path direction in image axes (atan2(dy, dx))
  // Against the hint (has_hint only).
  double hint_max_offset_px = 0;  // largest distance between the lines over the cracked length
  double hint_angle_deg = 0;      // path angle minus hint angle
  bool disagrees_with_hint = false;
  // Fit quality of the straight line over every crack point, and the
  // polyline where it fits badly (vertices notch side first; empty when the
  // line fits: then the path is the line).
  double line_rms_all_px = 0;
  // Parabola n = c0 + c1 s + c2 s^2 through every crack point: c2 [1/px]
  // and its standard error (sandwich, correlation-inflated).
  double curvature_per_px = 0, curvature_se_per_px = 0;
  // Standard error of the fitted line at the ends of the cracked length
  // (the larger of the two), px; at least what the points'
  // resolution (hint_tolerance_px / 2 each) leaves there.
  double line_se_px = 0;
  bool line_se_fitted = false;  // false: too few independent points for one
  // The data did not resolve the angle: the line keeps the hint's direction
  // (line_se_px is then the offset's alone).
  bool angle_from_hint = false;
  bool curved = false;
  std::vector<double> polyline_x, polyline_y;
  double polyline_rms_px = 0;  // RMS distance of the crack points to the polyline
  std::string why_not_found;  // when !found
  std::string BriefReport() const;
};

// A polyline through crack points ordered along the path: split where a
// point lies further than `tolerance` from the chord of its run (recursively,
// runs of at least `min_points`), each run's points fitted by a straight line
// (least squares), vertices where neighbouring lines meet (the runs' common
// point when they are nearly parallel), ends projected on the first and last
// lines. Returns the vertices (>= 2) and the RMS distance of the points to
// the polyline in *rms.
void FitCrackPolyline(const std::vector<double>& x, const std::vector<double>& y, double tolerance,
                      int min_points, std::vector<double>* vx, std::vector<double>* vy, double* rms);

// Never throws for data reasons (a missing path is a result); throws
// Error(kUsage) for invalid options.
CrackPathResult FindCrackPath(const DisplacementField& field, const CrackPathOptions& options);

}  // namespace bridgefit::dic
