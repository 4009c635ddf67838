// Printed output of `bridgefit dic` and `bridgefit crack`: one table or JSON
// object for both (the CSV and /dic files: pipeline/dic_file.hpp).
#include "dic_output.hpp"

#include <cmath>
#include <numbers>
#include <iostream>

#include <fmt/format.h>

#include "command.hpp"

namespace bridgefit::cli {
namespace {

nlohmann::json PathJson(const dic::FrameResult& f) {
  const dic::CrackLine& L = f.line_used;
  nlohmann::json j = {{"found", f.path.found}, {"line_px", {L.x0, L.y0, L.x1, L.y1}}};
  // line_px is the sequence's path where this frame's own (below) was not
  // resolved: the frame (index in "frames") whose path it is.
  j["from_frame"] = f.path_from_frame >= 0 ? nlohmann::json(f.path_from_frame) : nlohmann::json();
  if (f.path.found) {
    j["angle_deg"] = f.path.angle_deg;
    j["points"] = f.path.inliers;
    j["rms_residual_px"] = f.path.rms_residual_px;
    j["cracked_length_px"] = f.path.cracked_length_px;
    j["line_max_offset_px"] = f.path.hint_max_offset_px;
    j["line_angle_deg"] = f.path.hint_angle_deg;
    j["disagrees_with_line"] = f.path.disagrees_with_hint;
    j["rms_all_points_px"] = f.path.line_rms_all_px;  // fit quality of the straight path
    // The path's standard error at its ends (null: too few independent
    // points for one), and whether the angle is the line's, not measured.
    j["line_se_px"] = f.path.line_se_fitted ? nlohmann::json(f.path.line_se_px) : nlohmann::json();
    j["angle_from_line"] = f.path.angle_from_hint;
    j["curvature_per_px"] = f.path.curvature_per_px;
    j["curvature_se_per_px"] = f.path.curvature_se_per_px;
    j["curved"] = f.path.curved;
    if (f.path.curved) {
      j["polyline_px"] = nlohmann::json::array();
      for (size_t k = 0; k < f.path.polyline_x.size(); ++k)
        j["polyline_px"].push_back({f.path.polyline_x[k], f.path.polyline_y[k]});
      j["polyline_rms_px"] = f.path.polyline_rms_px;
    }
  } else if (!f.path.why_not_found.empty()) {
    j["why_not_found"] = f.path.why_not_found;
  }
  return j;
}

// J_ff and delta* of a frame: numbers only where their status is ok.
nlohmann::json FrameJJson(const dic::FrameJ& j) {
  const bool ok = j.status == dic::FrameJStatus::kOk;
  nlohmann::json out = {
      {"status", dic::FrameJStatusName(j.status)},
      {"J_ff_J_per_m2", ok ? NumberOrNull(j.J_ff) : nlohmann::json()},
      {"J_ff_spread_percent", ok ? NumberOrNull(j.J_ff_spread_percent) : nlohmann::json()},
      {"domains_ok", j.domains_ok},
      {"domains", j.domains},
      {"delta_star_m", j.delta_star_ok ? NumberOrNull(j.delta_star) : nlohmann::json()},
      {"delta_star_uncertainty_m",
       j.delta_star_ok ? NumberOrNull(j.delta_star_uncertainty) : nlohmann::json()},
      {"delta_star_method", dic::DeltaStarMethodName(j.delta_star_method)},
      {"root_distance_m", j.root_distance_m},
      {"rigid_rotation_deg", j.rigid_rotation_rad * 180.0 / std::numbers::pi},
      {"resampled", j.resampled}};
  if (!j.why.empty()) out["why"] = j.why;
  const bool fit_ok = j.fit.status == dic::FieldFitJStatus::kOk;
  out["field_fit"] = {
      {"status", dic::FieldFitJStatusName(j.fit.status)},
      {"J_ff_J_per_m2", fit_ok ? NumberOrNull(j.fit.J) : nlohmann::json()},
      {"J_ff_uncertainty_J_per_m2", fit_ok ? NumberOrNull(j.fit.J_uncertainty) : nlohmann::json()},
      {"residual_rms_m", NumberOrNull(j.fit.residual_rms_m)},
      {"points", j.fit.points},
      {"terms", j.fit.terms},
      {"dilatation", NumberOrNull(j.fit.dilatation)},
      {"dilatation_standard_error", NumberOrNull(j.fit.dilatation_se)},
      {"dilatation_removed", j.fit.dilatation_removed}};
  if (!j.fit.why.empty()) out["field_fit"]["why"] = j.fit.why;
  if (!j.delta_star_ok && !j.delta_star_why.empty()) out["delta_star_why"] = j.delta_star_why;
  return out;
}

}  // namespace

void PrintDicResult(const dic::CrackSequenceResult& result, const dic::CrackSequenceOptions& opt,
                    bool json, const std::string& field_unit) {
  const double m_per_px = opt.scale_m_per_px;
  if (json) {
    nlohmann::json out;
    nlohmann::json frames = nlohmann::json::array();
    for (const auto& f : result.frames) {
      const bool t = f.has_length;
      frames.push_back({
          {"image", f.image},
          {"crack_length_m", t ? nlohmann::json(f.crack_length_m) : nlohmann::json()},
          {"crack_length_raw_m", t ? nlohmann::json(f.crack_length_raw_m) : nlohmann::json()},
          {"crack_length_uncertainty_m", t ? nlohmann::json(f.uncertainty_m) : nlohmann::json()},
          {"crack_length_px", t ? NumberOrNull(f.tip.tip.s_px) : nlohmann::json()},
          {"tip_x_px", t ? NumberOrNull(f.tip.tip.x_px) : nlohmann::json()},
          {"tip_y_px", t ? NumberOrNull(f.tip.tip.y_px) : nlohmann::json()},
          {"tip_method", t ? nlohmann::json(dic::TipMethodName(f.tip.method)) : nlohmann::json()},
          {"tip_williams_px",
           f.tip.williams.found ? NumberOrNull(f.tip.williams.s_px) : nlohmann::json()},
          {"tip_jump_px", f.tip.jump.found ? NumberOrNull(f.tip.jump.s_px) : nlohmann::json()},
          {"tip_sqrt_px",
           f.tip.sqrt_cod.found ? NumberOrNull(f.tip.sqrt_cod.s_px) : nlohmann::json()},
          {"methods_disagree", f.tip.methods_disagree},
          {"tip_at_edge", f.tip.tip_at_edge},
          {"closed_lead_px", f.tip.opening_detected ? NumberOrNull(f.tip.closed_lead_px)
                                                    : nlohmann::json()},
          {"opening_detached", f.tip.opening_detached},
          {"flagged", f.flagged},
          {"flags", f.Flags()},
          {"path", PathJson(f)},
          {"k_over_2mu_sqrt_m", f.tip.williams.found
                                    ? NumberOrNull(f.tip.k_over_2mu_sqrt_px * std::sqrt(m_per_px))
                                    : nlohmann::json()},
          {"williams_residual_px",
           f.tip.williams.found ? NumberOrNull(f.tip.williams_residual_px) : nlohmann::json()},
          {"williams_clear_radius_px",
           f.tip.williams_window ? NumberOrNull(f.tip.williams_clear_radius_px) : nlohmann::json()},
          {"williams_hidden_points",
           f.tip.williams_window ? nlohmann::json(f.tip.williams_hidden_points) : nlohmann::json()},
          {"williams_points",
           f.tip.williams_window ? nlohmann::json(f.tip.williams_points) : nlohmann::json()},
          {"williams_shift_px",
           f.tip.williams.found ? NumberOrNull(f.tip.williams_shift_px) : nlohmann::json()},
          {"williams_unstable", f.tip.williams_unstable},
          {"williams_closing_shift_px",
           f.tip.williams.found ? NumberOrNull(f.tip.williams_closing_shift_px) : nlohmann::json()},
          {"williams_closing_shift_small_px",
           f.tip.williams.found ? NumberOrNull(f.tip.williams_closing_shift_small_px)
                                : nlohmann::json()},
          {"rigid_rotation_deg", f.rigid_rotation_rad * 180.0 / std::numbers::pi},
          {"williams_rotation_deg", f.tip.williams.found
                                        ? NumberOrNull(f.tip.williams_rotation_rad * 180.0 / std::numbers::pi)
                                        : nlohmann::json()},
          {"williams_window_shift_px",
           f.tip.williams.found ? NumberOrNull(f.tip.williams_window_shift_px) : nlohmann::json()},
          {"williams_window_share_px",
           f.tip.williams.found ? NumberOrNull(f.tip.williams_window_share_px) : nlohmann::json()},
          {"jump_threshold_px", f.tip.threshold_px},
          {"valid_fraction", f.valid_fraction},
          {"mean_zncc", f.correlation.mean_zncc},
          {"reference_frame", f.correlation.reference_frame},
          {"correlated_points", f.correlation.points},
          {"solves", f.correlation.solves},
          {"correlation_s", f.correlation.wall_s},
      });
      if (result.j_integral) frames.back()["j_integral"] = FrameJJson(f.j);
    }
    out["frames"] = std::move(frames);
    out["points_per_frame"] = result.points;
    out["mean_correlated_points"] = result.mean_correlated_points;
    out["wall_s"] = result.wall_s;
    out["points_per_s"] = result.points_per_s;
    out["sequence_path_frame"] =
        result.sequence_path_frame >= 0 ? nlohmann::json(result.sequence_path_frame) : nlohmann::json();
    out["fields_not_kept"] = result.fields_not_kept;
    // The *_px values are in the images' pixels, or for `crack` in the
    // fields' own coordinate unit (e.g. mm): said here, not guessed.
    out["length_unit"] = field_unit;
    out["scale_m_per_px"] = m_per_px;
    out["offset_m"] = opt.offset_m;
    PrintJson(out);
  } else {
    std::cout << result.BriefReport() << "\n";
    std::cout << fmt::format("{:>5} {:>14} {:>10} {:>10} {:>9} {:>9} {:>9} {:>6}  {}\n", "frame",
                             "a [mm]", "+- [mm]", "a [" + field_unit + "]", "tip_x", "tip_y",
                             "method", "valid", "image");
    if (field_unit != "px")
      std::cout << fmt::format("(a, tip_x and tip_y in the fields' unit, {})\n", field_unit);
    for (size_t k = 0; k < result.frames.size(); ++k) {
      const auto& f = result.frames[k];
      if (f.has_length)
        std::cout << fmt::format(
            "{:5} {:14.4f} {:10.4f} {:10.2f} {:9.2f} {:9.2f} {:>9} {:6.3f}{} {}\n", k,
            f.crack_length_m * 1e3, f.uncertainty_m * 1e3, f.tip.tip.s_px, f.tip.tip.x_px,
            f.tip.tip.y_px, dic::TipMethodName(f.tip.method), f.valid_fraction,
            f.flagged ? "*" : " ", f.image + (f.flagged ? "  [" + f.Flags() + "]" : ""));
      else
        std::cout << fmt::format("{:5} {:>14} {:>10} {:>10} {:>9} {:>9} {:>9} {:6.3f}  {}\n", k,
                                 "none", "", "", "", "", "", f.valid_fraction, f.image);
    }
    std::cout << "(* = flagged: the length may be wrong by more than its uncertainty)\n";
    if (result.j_integral) {
      std::cout << fmt::format("{:>5} {:>14} {:>10} {:>14} {:>12} {:>14} {:>10}  {}\n", "frame",
                               "J_ff [J/m^2]", "spread [%]", "delta* [mm]", "+- [mm]",
                               "J_fit [J/m^2]", "+- [J/m^2]", "status");
      for (size_t k = 0; k < result.frames.size(); ++k) {
        const dic::FrameJ& j = result.frames[k].j;
        const bool ok = j.status == dic::FrameJStatus::kOk;
        const bool fit_ok = j.fit.status == dic::FieldFitJStatus::kOk;
        std::cout << fmt::format(
            "{:5} {:>14} {:>10} {:>14} {:>12} {:>14} {:>10}  {}{}{}{}\n", k,
            ok ? fmt::format("{:.5g}", j.J_ff) : "-",
            ok ? fmt::format("{:.2f}", j.J_ff_spread_percent) : "-",
            j.delta_star_ok ? fmt::format("{:.5g}", j.delta_star * 1e3) : "-",
            j.delta_star_ok ? fmt::format("{:.2g}", j.delta_star_uncertainty * 1e3) : "-",
            fit_ok ? fmt::format("{:.5g}", j.fit.J) : "-",
            fit_ok ? fmt::format("{:.2g}", j.fit.J_uncertainty) : "-",
            dic::FrameJStatusName(j.status), j.why.empty() ? "" : " (" + j.why + ")",
            j.delta_star_method == dic::DeltaStarMethod::kNearTip
                ? " (delta*: near-tip opening, tip just past the root)"
                : "",
            fit_ok || j.fit.status == dic::FieldFitJStatus::kNotRequested
                ? ""
                : fmt::format(" (fit: {}{})", dic::FieldFitJStatusName(j.fit.status),
                              j.fit.why.empty() ? "" : ", " + j.fit.why));
      }
    }
  }
}

}  // namespace bridgefit::cli
