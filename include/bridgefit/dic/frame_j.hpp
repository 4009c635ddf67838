#pragma once
// Per-frame far-field J and notch-root opening delta* along a DIC sequence
// (PHYSICS sections 3 and 10, the J-integral route; issue 21), computed from
// each frame's field while it is in memory (dic/j_integral.hpp does the
// integral; this unit places the domains and the crack band per frame).
//
// Per frame with a tip: the crack runs along the line the length is
// measured on; the notch root sits at s_root = (notch_length - offset) /
// scale along it (px), so root_distance = s_tip - s_root. The far-field
// domains are annuli centred on the zone's midpoint with r_in >= half the
// zone plus `margin_points`, nested between that and the largest radius
// that stays inside the grid. Points within the crack band (band half
// width of the tip options) of the line behind the tip are set to
// kCrackBand first: with the path found from the data they are correlated
// across the faces and smeared. delta*'s stretch along the line reaches
// integral.opening_half_length behind the root and opening_ahead_fraction
// of the zone ahead of it (2 points at least). A tip at or behind the
// root gives delta* = 0 (the root is the tip: no growth yet). A tip past
// the root by less than that stretch (a zone of 0-2 grid steps, where the
// fitted profile would reach past the tip) gives the near-tip opening of
// a sharp crack with the frame's J_ff at the root's distance r behind the
// tip, delta* = sqrt(32 r J_ff / (pi E')) (the mode-I LEFM crack opening
// 8 K sqrt(r / 2 pi) / E' with K^2 = E' J_ff; the relation the reduced
// model's inverse::AnalyticDeltaRoot iterates), with its
// standard uncertainty from the tip's (half the spread of delta* over r
// -+ u_r, 0 floored), J_ff's and kNearTipModelRelative of delta* for the
// bridging the relation ignores: it is exact for a traction-free zone and
// reads high by up to 2x for a zone whose bridging carries all of J_ff
// (Dugdale); on zones of 0.2-1 mm whose bridging carries < 10 % of J_ff
// it reads 1.2-2.6 % high (the bridged crack of tests/dic/j_fit_test.cpp,
// FrameJ.*). Without FrameJOptions::effective_modulus such a frame has no
// delta* (a status).

#include <string>

#include "bridgefit/dic/correlation.hpp"
#include "bridgefit/dic/j_fit.hpp"
#include "bridgefit/dic/j_integral.hpp"

namespace bridgefit::dic {

struct FrameJOptions {
  bool enabled = false;
  ElasticConstants elastic;
  // Crack length of the initial notch root [m], measured as the crack
  // lengths are (along the line, times the scale, plus the offset).
  double notch_length_m = 0;
  int far_field_domains = 3;
  double margin_points = 2;  // r_in beyond half the zone, grid points
  // delta*'s stretch ahead of the root (toward the tip) as a fraction of
  // the zone (2 points at least, integral.opening_half_length at most);
  // behind the root it is integral.opening_half_length.
  double opening_ahead_fraction = 0.35;
  // E' for the near-tip delta* (specimen::EffectiveModulus of the scene's
  // plate; pipeline::FrameJOptionsFromScene sets it) [Pa]; 0: not known.
  double effective_modulus = 0;
  // Gradient window, fit order, valid fraction, opening rows and half
  // length; `domains`, `metres_per_unit` and `domain_units` are set per frame.
  JIntegralOptions integral;
  // The field-wide fit (dic/j_fit.hpp) about the same centre, outside the
  // domains' inner circle plus fit_margin_points: J_ff beside the domains'.
  bool field_fit = true;
  double fit_margin_points = 0;
  FieldFitJOptions fit;
  bool IsValid(std::string* why) const;
};

// The near-tip delta*'s allowance for the bridging it ignores (see above).
inline constexpr double kNearTipModelRelative = 0.1;

// How a frame's delta* was read.
enum class DeltaStarMethod {
  kNone,     // not read (delta_star_ok false)
  kProfile,  // the opening profile fitted about the root (stage 4 of j_integral.hpp)
  kAtRoot,   // the tip at or behind the root: 0
  kNearTip   // the tip past the root by less than the fitted stretch: near-tip LEFM
};
const char* DeltaStarMethodName(DeltaStarMethod method);  // "none", "profile", ...

enum class FrameJStatus {
  kNotRequested,
  kOk,
  kNoTip,            // the frame has no crack tip (reference frame, no opening)
  kNoFarFieldDomain  // every far-field domain failed (why: their statuses)
};
const char* FrameJStatusName(FrameJStatus status);  // "ok", "no_tip", ...

struct FrameJ {
  FrameJStatus status = FrameJStatus::kNotRequested;
  std::string why;                // status detail ("" when ok)
  double J_ff = 0;                // mean over the kOk far-field domains [J/m^2] (0 unless ok)
  double J_ff_spread_percent = 0; // (max - min) / mean over them [%]
  int domains_ok = 0, domains = 0;
  double root_distance_m = 0;     // tip to notch root along the line [m]
  // The field's rigid rotation taken out before the integral (radians,
  // counter-clockwise in the field's axes; 0 where below 1 - cos = 1e-7).
  double rigid_rotation_rad = 0;
  // The field was a scattered list, resampled onto a lattice for J
  // (dic::ResampleOntoGrid).
  bool resampled = false;
  bool delta_star_ok = false;
  std::string delta_star_why;     // when !delta_star_ok
  double delta_star = 0;          // opening at the notch root [m] (0 unless ok)
  double delta_star_uncertainty = 0;  // standard uncertainty [m]
  DeltaStarMethod delta_star_method = DeltaStarMethod::kNone;
  FieldFitJResult fit;                // the field-wide fit's J_ff (status kNotRequested when off)
};

// `field` in px (reference positions); tip and line from a located frame;
// tip_uncertainty_px the tip's standard uncertainty along the line (for the
// near-tip delta*). Never throws for a frame that cannot be measured (a status); throws
// Error(kUsage) for invalid options.
FrameJ ComputeFrameJ(const DisplacementField& field, double tip_x_px, double tip_y_px,
                     double tip_s_px, double line_dx, double line_dy, double band_half_width_px,
                     double scale_m_per_px, double offset_m, const FrameJOptions& options,
                     double tip_uncertainty_px = 0);

}  // namespace bridgefit::dic
