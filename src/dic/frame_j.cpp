// Per-frame J_ff and delta* along a DIC sequence (dic/frame_j.hpp).
#include "bridgefit/dic/frame_j.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/fields.hpp"

namespace bridgefit::dic {

bool FrameJOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (!enabled) return true;
  if (far_field_domains < 1 || far_field_domains > 10)
    return fail("far_field_domains must be in [1, 10]");
  if (!(margin_points >= 0)) return fail("margin_points must be >= 0");
  if (!(opening_ahead_fraction > 0 && opening_ahead_fraction < 1))
    return fail("opening_ahead_fraction must be in (0, 1)");
  if (!std::isfinite(notch_length_m)) return fail("notch_length_m must be finite");
  try {
    elastic.Validate();
  } catch (const Error& e) {
    return fail("elastic constants: " + e.message());
  }
  if (field_fit && !fit.IsValid(why)) return false;
  if (!(fit_margin_points >= 0)) return fail("fit_margin_points must be >= 0");
  JIntegralOptions probe = integral;
  probe.domains.clear();
  return probe.IsValid(why);
}

const char* FrameJStatusName(FrameJStatus status) {
  switch (status) {
    case FrameJStatus::kNotRequested: return "not_requested";
    case FrameJStatus::kOk: return "ok";
    case FrameJStatus::kNoTip: return "no_tip";
    case FrameJStatus::kNoFarFieldDomain: return "no_far_field_domain";
  }
  return "unknown";
}

const char* DeltaStarMethodName(DeltaStarMethod method) {
  switch (method) {
    case DeltaStarMethod::kNone: return "none";
    case DeltaStarMethod::kProfile: return "profile";
    case DeltaStarMethod::kAtRoot: return "at_root";
    case DeltaStarMethod::kNearTip: return "near_tip";
  }
  return "unknown";
}

namespace {

// Mode-I LEFM opening r behind a sharp tip: 8 K sqrt(r / 2 pi) / E', K^2 = E' J.
double NearTipOpening(double r, double J, double effective_modulus) {
  return r > 0 ? std::sqrt(32 * r * J / (std::numbers::pi * effective_modulus)) : 0.0;
}

// Stage 4 where the fitted profile cannot reach the root (the header): the
// tip at or behind the root -> 0; past it -> the near-tip opening with the
// frame's J_ff (the field fit's where ok). u from the tip's u_r (half the
// spread over r -+ u_r), J_ff's and the model allowance.
void NearTipDeltaStar(double root_m, double u_root_m, const FrameJOptions& options,
                      FrameJ* out) {
  const bool fit_ok = out->fit.status == FieldFitJStatus::kOk && out->fit.J > 0;
  const double J = fit_ok ? out->fit.J : out->status == FrameJStatus::kOk ? out->J_ff : NAN;
  const double u_J = fit_ok ? out->fit.J_uncertainty : 0.005 * out->J_ff_spread_percent * J;
  const double E = options.effective_modulus;
  if (root_m <= 0 && !(E > 0 && J > 0)) {  // no E' or J: 0 without an uncertainty
    out->delta_star_ok = true;
    out->delta_star_method = DeltaStarMethod::kAtRoot;
    return;
  }
  if (!(E > 0)) {
    out->delta_star_why = fmt::format(
        "the tip is {:.3g} mm past the root, closer than the fitted opening profile reaches; "
        "the near-tip delta* needs the plate's effective modulus (FrameJOptions::"
        "effective_modulus, set from --scene)",
        root_m * 1e3);
    return;
  }
  if (!(J > 0)) {
    out->delta_star_why = fmt::format(
        "the tip is {:.3g} mm past the root, closer than the fitted opening profile reaches, "
        "and the frame has no J_ff for the near-tip delta*",
        root_m * 1e3);
    return;
  }
  const double d = NearTipOpening(root_m, J, E);
  const double spread = 0.5 * (NearTipOpening(root_m + u_root_m, J, E) -
                               NearTipOpening(root_m - u_root_m, J, E));
  out->delta_star_ok = true;
  out->delta_star = d;
  out->delta_star_uncertainty =
      std::sqrt(spread * spread + std::pow(0.5 * d * u_J / J, 2) +
                std::pow(kNearTipModelRelative * d, 2));
  out->delta_star_method = root_m > 0 ? DeltaStarMethod::kNearTip : DeltaStarMethod::kAtRoot;
}

// The field with the crack band behind the tip (and one band width ahead)
// marked kCrackBand: subsets there straddle the faces.
DisplacementField WithCrackBand(const DisplacementField& field, double tip_x, double tip_y,
                                double c, double s, double band) {
  DisplacementField f = field;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const double ex = f.x[i] - tip_x, ey = f.y[i] - tip_y;
    const double along = c * ex + s * ey, normal = -s * ex + c * ey;
    if (std::abs(normal) < band && along < band && f.status[i] == PointStatus::kOk)
      f.status[i] = PointStatus::kCrackBand;
  }
  return f;
}

}  // namespace

FrameJ ComputeFrameJ(const DisplacementField& field, double tip_x_px, double tip_y_px,
                     double tip_s_px, double line_dx, double line_dy, double band_half_width_px,
                     double scale_m_per_px, double offset_m, const FrameJOptions& options,
                     double tip_uncertainty_px) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid J options: " + why);
  FrameJ out;
  const double length = std::hypot(line_dx, line_dy);
  if (!(length > 0)) {
    out.status = FrameJStatus::kNoTip;
    out.why = "no crack line";
    return out;
  }
  if (field.nx < 3 || field.ny < 3) {
    out.status = FrameJStatus::kNoTip;
    out.why = "the field is not a grid: the J integral needs points on a square lattice "
              "(an export's x, y on equal steps in both directions, as DIC grids are)";
    return out;
  }
  const double c = line_dx / length, s = line_dy / length;
  const double step = field.x[1] - field.x[0];
  // Stage 1: the notch root along the line (px); a tip behind it reads as
  // no growth yet (root at the tip).
  const double s_root = (options.notch_length_m - offset_m) / scale_m_per_px;
  const double root_px = std::max(0.0, tip_s_px - s_root);
  out.root_distance_m = root_px * scale_m_per_px;
  // Stage 2: domains in grid points, centred on the zone's midpoint, from
  // half the zone plus the margin to the valid points' bounding box.
  const double half = 0.5 * root_px / step;
  const double cx = tip_x_px - c * 0.5 * root_px, cy = tip_y_px - s * 0.5 * root_px;
  const FieldExtent box = ValidExtent(field);
  const double reach = std::min({cx - box.x0, box.x1 - cx, cy - box.y0, box.y1 - cy}) / step - 1;
  const double r_in0 = half + std::max(options.margin_points, band_half_width_px / step + 1);
  const int n = options.far_field_domains;
  const double room = std::max(reach - r_in0, 4.0);  // too little: the domains leave the field
  JIntegralOptions jo = options.integral;
  jo.metres_per_unit = scale_m_per_px;
  jo.domain_units = DomainUnits::kGridPoints;
  jo.domains.clear();
  const double gap = room / (2.0 * n);
  for (int k = 0; k < n; ++k)
    jo.domains.push_back({DomainKind::kFarField, r_in0 + k * gap, r_in0 + room - (n - 1 - k) * gap,
                          -half});
  // delta*'s stretch: opening_half_length behind the root (the notch side,
  // where the opening is smooth), and ahead of it, toward the tip, only
  // opening_ahead_fraction of the zone (at least 2 points): nearer the tip
  // the opening, smoothed by subsets about as long as a young zone, bends
  // down and the quadratic read the root low (-5 to -9 % on 2-5 mm zones
  // with 0.9 of the zone on both sides; tests/dic/j_integral_test.cpp).
  const double root_points = root_px / step;
  jo.opening_ahead_length = std::clamp(options.opening_ahead_fraction * root_points, 2.0,
                                       options.integral.opening_half_length);
  CrackGeometry crack{tip_x_px, tip_y_px, c, s, root_px};
  // Stage 3: the integral and delta* (dic/j_integral.hpp).
  const DisplacementField banded = WithCrackBand(
      WithoutRigidRotation(field, &out.rigid_rotation_rad), tip_x_px, tip_y_px, c, s,
      band_half_width_px);
  // The field-wide fit first: a uniform dilatation it shows (stress-free,
  // FieldFitJResult::dilatation) is taken out of the field the domains read.
  if (options.field_fit)
    out.fit = FitFarFieldJ(banded, cx, cy, c, s, (r_in0 + options.fit_margin_points) * step,
                           options.elastic, scale_m_per_px, options.fit);
  DisplacementField undilated;
  if (out.fit.dilatation_removed) {
    undilated = banded;
    for (std::size_t i = 0; i < undilated.size(); ++i) {
      undilated.u[i] -= out.fit.dilatation * (undilated.x[i] - cx);
      undilated.v[i] -= out.fit.dilatation * (undilated.y[i] - cy);
    }
  }
  JIntegralResult r;
  try {
    r = ComputeJIntegral(out.fit.dilatation_removed ? undilated : banded, crack, options.elastic,
                         jo);
  } catch (const Error& e) {
    if (e.kind() == ErrorKind::kUsage) throw;
    out.status = FrameJStatus::kNoFarFieldDomain;
    out.why = e.message();
    return out;
  }
  out.domains = static_cast<int>(r.domains.size());
  out.domains_ok = r.far_field_ok;
  if (r.far_field_ok > 0) {
    out.status = FrameJStatus::kOk;
    out.J_ff = r.j_ff;
    out.J_ff_spread_percent = r.j_ff_spread_percent;
  } else {
    out.status = FrameJStatus::kNoFarFieldDomain;
    for (const DomainResult& d : r.domains)
      out.why += fmt::format("{}r {:.0f}-{:.0f} pt: {}", out.why.empty() ? "" : "; ", d.spec.r_in,
                             d.spec.r_out, DomainStatusName(d.status));
  }
  // Stage 4: delta*, from the profile where its stretch fits between the
  // notch and the tip, else at or near the tip (NearTipDeltaStar).
  if (root_px <= jo.opening_ahead_length * step) {
    NearTipDeltaStar((tip_s_px - s_root) * scale_m_per_px, tip_uncertainty_px * scale_m_per_px,
                     options, &out);
  } else if (r.root_opening.ok) {
    out.delta_star_ok = true;
    out.delta_star = r.root_opening.delta;
    out.delta_star_uncertainty = r.root_opening.delta_std;
    out.delta_star_method = DeltaStarMethod::kProfile;
  } else {
    out.delta_star_why = r.root_opening.why;
  }
  return out;
}

}  // namespace bridgefit::dic
