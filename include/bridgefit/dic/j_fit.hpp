#pragma once
// Far-field J from a field-wide fit (issue 21's J route; PHYSICS sections
// 3 and 10): the displacement field outside a circle that holds the
// bridging zone and the near-tip region is, for a linear elastic body with
// traction-free crack faces outside the circle, a Laurent-Williams series
// about the circle's centre c on the crack line (crack frame x1 along the
// growth, faces at t = +-pi):
//   u(r, t) = rigid motion + e (x1, x2)
//             + sum_{n = lo..hi, n != 0} r^(n/2) [a_n f_n^I(t) + b_n f_n^II(t)]
// (e a uniform dilatation, stress-free: FieldFitJResult::dilatation)
// (f_n the Williams eigenfunctions, dic/crack.hpp's kWilliams basis; the
// negative n are the terms singular at c: the zone's closing tractions and
// the tip's offset from c; the positive n the applied K and the body's
// geometry). The series is fitted by least squares to ALL valid points
// outside the circle (not an annulus), and J is the contour integral
//   J = int_G (W n_1 - sigma_ij n_j u_i,1) ds
// of the fitted field on the circle: every term is an exact traction-free
// solution, so J is path independent for the fit and equals J_ff (the
// circle encloses the zone), cross terms (n, 2 - n) included. J is a
// quadratic form c^T Q c of the coefficients; its standard uncertainty is
// 2 Q c propagated through the fit with the residuals' own spatial
// correlation and unequal size (a spatial HAC estimate, Bartlett weights
// over correlation_lag grid lags: DIC errors are correlated over a subset
// and larger where the strain varies), combined with the change of J when the circle grows by `check_points`
// (truncation and near-zone error). Plane stress, isotropic or
// orthotropic with axis 1 along the crack: for an orthotropic material the
// series is Lekhnitskii's (the two traction-free terms of each order from
// the complex potentials A_k z_k^(n/2), z_k = x1 + mu_k x2; Sih, Paris &
// Irwin 1965 for n = 1), with the orthotropic stiffness in the integrand;
// the points fitted are those with min_k |z_k| >= the exclusion radius
// about the centre (where the series converges: the circle when isotropic,
// further out across the crack where a root's |mu_k| < 1).

#include <string>

#include "bridgefit/dic/correlation.hpp"
#include "bridgefit/dic/j_integral.hpp"

namespace bridgefit::dic {

struct FieldFitJOptions {
  int lowest_order = -13;  // n from lowest_order to highest_order, n != 0,
  int highest_order = 4;   // mode I and II (mode II n = 2 is the rotation)
  // The check fit: the exclusion radius larger by this many grid points.
  double check_points = 4;
  int min_points = 200;    // valid points outside the circle
  // Poor fit: the residual RMS above this fraction of the RMS of the fitted
  // displacement less the rigid motion (a wrong line, centre or field).
  double max_residual_fraction = 0.05;
  // Grid lags (x and y) over which the residuals' correlation is summed.
  int correlation_lag = 12;
  // The residuals summed are each tile's as a fit without the tile sees
  // them (tiles of tile_points x tile_points grid points): the part of a
  // patchy DIC error the series absorbs shows. 0: the plain residuals.
  // 24 (120 px at a 5 px step) covered the synthetic image runs' J errors
  // (docs/LAW_FREE.md "What the residuals miss"); 12 left 3 of 45 frames
  // beyond 2 u.
  int tile_points = 24;
  // A dilatation beyond this many standard errors is taken out of the field
  // (FieldFitJResult::dilatation).
  double dilatation_z = 3;
  bool IsValid(std::string* why) const;
};

enum class FieldFitJStatus {
  kNotRequested,
  kOk,
  kTooFewPoints,  // fewer than min_points valid points outside the circle
  kPoorFit,       // residual RMS above max_residual_fraction of the fitted displacement
};
const char* FieldFitJStatusName(FieldFitJStatus status);  // "ok", "not_isotropic", ...

struct FieldFitJResult {
  FieldFitJStatus status = FieldFitJStatus::kNotRequested;
  std::string why;
  double J = 0;               // J_ff of the fit [J/m^2]
  double J_uncertainty = 0;   // standard uncertainty [J/m^2]
  double J_statistical = 0;   // its part from the fit's covariance (correlation-scaled) [J/m^2]
  double J_check = 0;         // the check fit's J (circle check_points larger) [J/m^2]
  double K_I = 0;             // n = 1 mode I coefficient as K [Pa m^0.5]
  double residual_rms_m = 0;  // RMS displacement residual per component [m]
  double signal_rms_m = 0;    // RMS of the fitted displacement less the rigid motion [m]
  double correlation_factor = 1;  // J's variance over the white-noise estimate's
  // The field's uniform dilatation (strain) and its standard error: fitted
  // beside the series; where it exceeds dilatation_z standard errors the
  // fit with it gives J, the dilatation left out (dilatation_removed), and
  // the domain integral reads the field less it. A uniform isotropic strain is no
  // elastic field of a plate with traction-free crack faces (it needs
  // sigma_22 on them): it is stress-free, a 2D DIC's magnification change
  // from out-of-plane motion (dz / working distance), or a thermal or
  // moisture strain. Read as stress it was an equibiaxial load on the faces:
  // 1e-4 (30 um towards a camera 300 mm away) gave J_ff +26 % (fit) and
  // +29 % (domains) on an LEFM field.
  double dilatation = 0, dilatation_se = 0;
  bool dilatation_removed = false;
  int points = 0;             // valid points fitted
  int terms = 0;              // coefficients fitted
};

// `field` in its own units (px with metres_per_unit the scale); centre and
// direction of the crack line in those units; `exclusion_radius` too.
// Points whose status is not ok (the caller marks the crack band) are left
// out. Never throws for a field that cannot be fitted (a status); throws
// Error(kUsage) for invalid options.
FieldFitJResult FitFarFieldJ(const DisplacementField& field, double centre_x, double centre_y,
                             double direction_x, double direction_y, double exclusion_radius,
                             const ElasticConstants& elastic, double metres_per_unit,
                             const FieldFitJOptions& options);

}  // namespace bridgefit::dic
