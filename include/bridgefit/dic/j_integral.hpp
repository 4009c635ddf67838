#pragma once
// The J integral and the notch-root opening delta* from a measured
// displacement field (PHYSICS sections 3, 4 and 10, the J-integral route).
//
// Stages:
//  1. Gradients: per valid point, a least-squares polynomial (order 1 or 2)
//     in (x, y) over a (2w+1)^2 window of valid neighbours that are on the
//     same side of the crack (a 2-D Savitzky-Golay filter: the window is the
//     smoothing); rotated into the crack frame (axis 1 along the growth
//     direction, origin at the tip).
//  2. Stresses, plane stress, axis 1 along the crack:
//       eps = S sigma,  S = [1/E1, -nu12/E1, 0; -nu12/E1, 1/E2, 0; 0, 0, 1/G12]
//     (isotropic: E1 = E2 = E, G12 = E / (2 (1 + nu))); W = sigma : eps / 2.
//  3. Equivalent domain integral (Shih, Moran & Nakamura 1986), eq. (J1):
//       J = int_A (sigma_ij u_i,1 - W delta_1j) q,j dA
//     over the grid cells of the annulus r_in < |x - c| < r_out, with
//     q = 1 - s(t), t = (r - r_in) / (r_out - r_in), s the C2 smoothstep
//     6t^5 - 15t^4 + 10t^3 (smooth q: the cell-sum quadrature converges fast).
//     Invalid points and the crack band are left out of the sum and counted.
//     On faces that carry a bridging traction sigma(delta) inside the annulus
//     the sum equals J_tip + int q sigma(delta) (-d delta / dx1) dx1 (PHYSICS
//     eq. 4): a domain whose annulus crosses the faces behind the notch root
//     gives J_ff (eq. 1); a domain around the tip only gives J(x), and J_tip
//     only when the traction law is supplied (the face term is then
//     subtracted using the measured opening profile).
//  4. delta*: per side of the crack, the normal displacement of the valid
//     points in the first rows beside the band within +-L of the root,
//     fitted as a0 + a1 s + a2 s^2 + a3 n (s along the line from the root,
//     n the normal distance) and extrapolated to (s, n) = (0, 0+-); the
//     opening is a0(upper) - a0(lower) (the n term removes the elastic
//     strain across the band, PHYSICS sec. 9); its standard uncertainty from
//     the fits' residuals.
//
//   JIntegralOptions options;  options.domains = {...};
//   JIntegralResult result = ComputeJIntegral(field, crack, elastic, options);

#include <functional>
#include <string>
#include <vector>

#include "bridgefit/dic/correlation.hpp"

namespace bridgefit::dic {

// Plane-stress elastic constants, axis 1 along the crack (Pa).
struct ElasticConstants {
  enum class Kind { kIsotropic, kOrthotropic };
  Kind kind = Kind::kIsotropic;
  double E = 0, nu = 0;                      // isotropic
  double E1 = 0, E2 = 0, G12 = 0, nu12 = 0;  // orthotropic
  static ElasticConstants Isotropic(double E, double nu);
  static ElasticConstants Orthotropic(double E1, double E2, double G12, double nu12);
  // Throws Error(kInput) naming the constant: moduli > 0, compliance
  // positive definite (|nu12| < sqrt(E1 / E2), -1 < nu < 0.5 in plane stress).
  void Validate() const;
};

// The crack in the field's own units (metres, or px when
// JIntegralOptions::metres_per_unit != 1): tip, growth direction, and the
// initial notch root as a distance behind the tip along the line.
struct CrackGeometry {
  double tip_x = 0, tip_y = 0;
  double direction_x = 1, direction_y = 0;
  double root_distance = 0;  // notch root at tip - root_distance * direction
};

enum class DomainKind {
  kFarField,  // annulus crosses the faces behind the notch root: J_ff
  kTip,       // annulus around the tip, inside the bridging zone: J(x)
};

// One integration domain. Lengths in `JIntegralOptions::domain_units`.
// The centre lies on the crack line at `centre_offset` ahead of the tip
// (negative: behind). A far-field domain must have r_in >= the distance from
// its centre to the root and to the tip.
struct DomainSpec {
  DomainKind kind = DomainKind::kFarField;
  double r_in = 0, r_out = 0;
  double centre_offset = 0;
};

enum class DomainUnits { kMetres, kGridPoints };

struct JIntegralOptions {
  double metres_per_unit = 1.0;  // field and crack units -> m (e.g. m per px)
  DomainUnits domain_units = DomainUnits::kGridPoints;
  std::vector<DomainSpec> domains;
  // Gradient window half-width (points) and polynomial order (1 or 2).
  int window_half_width = 2;
  int fit_order = 2;
  int min_window_points = 8;  // valid same-side neighbours needed for a gradient
  // A domain with less than this fraction of its annulus cells usable
  // (valid with a gradient) gets kTooFewValid instead of a J.
  double min_valid_fraction = 0.75;
  // delta*: rows beside the band used per side, and the stretch along the
  // line (in domain_units): opening_half_length behind the root (toward the
  // notch mouth) and opening_ahead_length ahead of it (toward the tip; 0:
  // opening_half_length). Toward the tip the opening bends down, more so as
  // DIC subsets smooth it, and a quadratic through it reads the root low.
  int opening_rows = 3;
  double opening_half_length = 8;
  double opening_ahead_length = 0;
  // Optional bridging traction sigma(delta) (Pa of m): when set, tip domains
  // also report J_tip = J(x) - face term (PHYSICS eq. 4).
  std::function<double(double)> bridging_traction;

  bool IsValid(std::string* why) const;
};

enum class DomainStatus {
  kOk,
  kLeavesField,     // the annulus is not inside the grid
  kTooFewValid,     // usable fraction below min_valid_fraction
  kDoesNotEnclose,  // far-field domain whose annulus reaches into the zone
};
const char* DomainStatusName(DomainStatus status);

struct DomainResult {
  DomainSpec spec;                 // as given
  double r_in_m = 0, r_out_m = 0;  // in metres
  DomainStatus status = DomainStatus::kOk;
  double j = 0;                  // J_m^2 of eq. (J1) (0 unless kOk)
  bool has_j_tip = false;        // tip domain with a traction law
  double face_term = 0;          // int q sigma (-d delta/dx1) dx1, J/m^2
  double j_tip = 0;              // j - face_term, J/m^2
  std::size_t cells = 0;         // grid cells in the annulus
  std::size_t used = 0;          // of them valid with a gradient
  double excluded_fraction = 0;  // 1 - used / cells
};

struct NotchRootOpening {
  bool ok = false;
  std::string why;       // when !ok: a side lacked points, or the root is too near the tip
  double delta = 0;      // normal opening at the root, m
  // Its standard uncertainty, m: the fit residuals' and, in quadrature,
  // delta_model_std.
  double delta_std = 0;
  // Half the difference to the opening read without the rows' linear trend
  // in n (each side's value at the nearest row carried to the line): the
  // extrapolation across the band (16 px at subset 31) is a model, and on
  // bridged synth frames the two readings bracket the true opening
  // (-0.6 and +0.8 um at 47.6 um). m.
  double delta_model_std = 0;
  double sliding = 0;    // tangential jump at the root, m
  int points_upper = 0, points_lower = 0;
};

struct JIntegralResult {
  std::vector<DomainResult> domains;
  // Over the kOk far-field domains: mean J_ff and the spread
  // (max - min) / mean, %; spread only with at least two domains.
  int far_field_ok = 0;
  double j_ff = 0;
  double j_ff_spread_percent = 0;
  NotchRootOpening root_opening;
  std::size_t gradient_points = 0;  // points with a fitted gradient
  double wall_s = 0;
  std::string Summary() const;
};

// Throws Error(kUsage) for invalid options, Error(kInput) for a field that is
// not a regular grid, a non-finite value at a valid point (naming the array
// and index), bad elastic constants or a degenerate crack direction. Domain
// failures are statuses, never exceptions.
JIntegralResult ComputeJIntegral(const DisplacementField& field, const CrackGeometry& crack,
                                 const ElasticConstants& elastic, const JIntegralOptions& options);

}  // namespace bridgefit::dic
