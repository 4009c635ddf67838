#pragma once
// The bridging law without assuming its shape, as a workflow (issue 21,
// PHYSICS section 10): `bridgefit lawfree`.
//
//   dic.h5 (bridgefit dic/crack --scene S --j-integral --out)
//     -> J_ff(delta*) per frame      -> laws::LawFromFarFieldJ   (eq. 1)
//   rcurve.h5 (R per crack length) + delta* per frame, matched by crack length
//     -> R(delta_root)               -> laws::LawFromRCurve      (eq. 3)
//   -> LawFreeRun -> /lawfree (WriteLawFreeH5 / ReadLawFreeH5, the one owner)
//
// Frames whose J or delta* has a status other than ok are skipped with a
// note; so are R points outside the crack lengths the frames cover (delta*
// is interpolated linearly in crack length between frames, never
// extrapolated). J_ff per frame is the field-wide fit's (dic/j_fit.hpp) where
// its status is ok (its standard uncertainty, at least `j_fit_relative_floor`
// of J_ff), else the domains' (with a note) - `j_source` chooses; the
// domains' uncertainty is half their contour spread, at least
// `j_relative_floor` of J_ff (one domain has no spread); R's is the
// file's R_uncertainty over its coverage factor, or `r_relative_floor` of
// the median R when the file has none (both routes choose their penalty by
// GCV, which does not trust the stated scale, and widen the band when the
// data scatter more than stated).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bridgefit/dic/crack.hpp"
#include "bridgefit/dic/frame_j.hpp"
#include "bridgefit/laws/law_free.hpp"
#include "bridgefit/report/report_input.hpp"
#include "bridgefit/scene/scene.hpp"

namespace bridgefit::pipeline {

// The per-frame J options for `bridgefit dic/crack --scene S --j-integral`:
// the scene's elastic constants (plane stress; an isotropic plane-strain
// scene as the equivalent plane-stress pair E / (1 - nu^2), nu / (1 - nu))
// and its notch as the notch root's crack length. Throws Error(kInput)
// naming the scene for an orthotropic plane-strain scene.
dic::FrameJOptions FrameJOptionsFromScene(const Scene& scene);
// The tip fit's material for `bridgefit dic/crack --scene S` (with or
// without --j-integral): an orthotropic plate's in-plane compliances
// (plane stress or the plane-strain reduced ones; axis 1 along the crack)
// for Lekhnitskii's series, else kappa from nu. Throws Error(kInput)
// naming the scene for a rotated orthotropic material.
void TipMaterialFromScene(const Scene& scene, dic::CrackTipOptions* tip);

struct LawFreeRequest {
  std::filesystem::path dic_file;     // dic.h5 with J_ff and delta* per frame
  std::filesystem::path rcurve_file;  // optional: rcurve.h5 or R-curve CSV (the R route)
  bool far_field_route = true;        // false: the R route only
  std::optional<double> J_tip_c;      // R route: given [J/m^2]; absent: fitted
  // J route: delta* at the onset [m]. Absent: the onset frame is the last
  // of the leading frames whose delta* is zero within 2 of its standard
  // uncertainties (a zero after growth began: skipped, a warning; dic writes
  // delta* = 0 while the tip is at or behind the notch root, the near-tip
  // opening with the tip's uncertainty just past it), the
  // frames before it are left out (a note); without such a frame the onset
  // is detected from J_ff's shape, with a warning note.
  std::optional<double> onset_opening;
  enum class JSource { kFieldFit, kDomains };
  JSource j_source = JSource::kFieldFit;
  double j_relative_floor = 0.01;
  double j_fit_relative_floor = 0.0025;
  double r_relative_floor = 0.02;
  laws::LawFreeOptions options;
  // Files given, a route asked for, floors > 0, options valid.
  bool IsValid(std::string* why) const;
};

struct LawFreeRun {
  std::string dic_file, rcurve_file;
  int frames = 0;                              // in the DIC file
  std::optional<laws::LawFreeResult> far_field;  // the J_ff(delta*) route
  std::optional<laws::LawFreeResult> r_curve;    // the R(delta_root) route
  laws::FarFieldJSamples j_samples;            // what the J route was given
  laws::RCurveSamples r_samples;               // what the R route was given
  std::vector<std::string> notes;              // skipped frames / points, failed routes
  double wall_s = 0;
  std::string BriefReport() const;  // with units
};

struct DicJSeries;  // pipeline/dic_file.hpp

// The J route's samples from a DIC series as RunLawFree assembles them
// (docs/LAW_FREE.md "What each route needs": the onset frame and its
// range, flagged frames, near-tip openings, the J source and floors);
// what was left out and assumed goes to `notes`. bench/lawfree_split feeds
// it series with true J or delta* swapped in.
laws::FarFieldJSamples FarFieldJSamplesOf(const DicJSeries& series, const LawFreeRequest& request,
                                          std::vector<std::string>& notes);

// Throws Error(kUsage) for an invalid request, Error(kInput) naming the file
// and field for unreadable input (a dic.h5 without J: rerun dic with
// --j-integral) and when no requested route could run (each route's own
// failure is otherwise a note).
LawFreeRun RunLawFree(const LawFreeRequest& request);

// /lawfree: attributes dic_file, rcurve_file, frames; /lawfree/notes; per
// route a group far_field_j or elastic_zone_r with delta [m], sigma,
// sigma_standard_error, sigma_lower, sigma_upper [Pa], J_tip_c,
// J_tip_c_standard_error, J_B, J_B_standard_error [J/m^2], delta_c [m],
// null_space_slope_min [Pa/m] (1-element datasets with units), the flags
// identified, J_B_identified, delta_c_identified, J_tip_c_given (0/1
// attributes), the fit's figures, its notes and the samples it used
// (sample_opening [m], sample_value, sample_uncertainty [J/m^2]). Atomic.
void WriteLawFreeH5(const std::filesystem::path& path, const LawFreeRun& run);
// Throws Error(kInput) naming the file when it holds no /lawfree.
LawFreeRun ReadLawFreeH5(const std::filesystem::path& path);
// The report's view of /lawfree (ReadLawFreeH5, curves only).
report::LawFreeView ReadLawFreeView(const std::filesystem::path& path);

}  // namespace bridgefit::pipeline
