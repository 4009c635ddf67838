// /lawfree, the one owner (pipeline/law_free.hpp): written by `bridgefit
// lawfree --out`, read back by the report and the tests.
#include <cmath>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/pipeline/law_free.hpp"
#include "h5_read.hpp"

namespace bridgefit::pipeline {
namespace {

constexpr const char* kFarFieldGroup = "/lawfree/far_field_j";
constexpr const char* kRCurveGroup = "/lawfree/elastic_zone_r";

std::vector<std::string> OrNone(const std::vector<std::string>& v) {
  return v.empty() ? std::vector<std::string>{"none"} : v;
}
std::vector<std::string> FromNone(std::vector<std::string> v) {
  if (v.size() == 1 && v[0] == "none") v.clear();
  return v;
}

void WriteRoute(io::H5Writer& h5, const std::string& g, const laws::LawFreeResult& r,
                const std::vector<double>& opening, const std::vector<double>& value,
                const std::vector<double>& uncertainty) {
  h5.WriteVector(g + "/delta", r.delta, "m", "opening (from the onset of growth)");
  h5.WriteVector(g + "/sigma", r.sigma, "Pa", "bridging traction, clipped at 0");
  h5.WriteVector(g + "/sigma_standard_error", r.sigma_standard_error, "Pa");
  h5.WriteVector(g + "/sigma_lower", r.sigma_lower, "Pa", "band: sigma - z se, unclipped");
  h5.WriteVector(g + "/sigma_upper", r.sigma_upper, "Pa", "band: sigma + z se");
  std::vector<double> resolved(r.resolved.begin(), r.resolved.end());
  h5.WriteVector(g + "/resolved", resolved, "1",
                 "1: the band's half-width is at most resolved_fraction x the peak sigma");
  h5.WriteVector(g + "/J_tip_c", {r.J_tip_c}, "J/m^2", "crack-tip toughness");
  h5.WriteVector(g + "/J_tip_c_standard_error", {r.J_tip_c_standard_error}, "J/m^2");
  h5.WriteVector(g + "/J_B", {r.J_B.value}, "J/m^2",
                 "bridging toughness: a value when J_B_identified, else a one-sided 95 % lower "
                 "bound");
  h5.WriteVector(g + "/J_B_standard_error", {r.J_B.standard_error}, "J/m^2");
  h5.WriteVector(g + "/delta_c", {r.delta_c.value}, "m",
                 "critical opening: a value when delta_c_identified, else a lower bound");
  h5.WriteVector(g + "/null_space_slope_min", {r.null_space_slope_min}, "Pa/m",
                 "R route, not identified: sigma + C delta with C >= this");
  h5.WriteVector(g + "/sample_opening", opening, "m", "delta* (J route) or delta_root (R route)");
  h5.WriteVector(g + "/sample_value", value, "J/m^2", "J_ff (J route) or R (R route)");
  h5.WriteVector(g + "/sample_uncertainty", uncertainty, "J/m^2", "one standard uncertainty");
  h5.WriteStrings(g + "/notes", OrNone(r.notes));
  h5.WriteAttribute(g, "identified", r.identified ? 1.0 : 0.0);
  h5.WriteAttribute(g, "J_B_identified", r.J_B.identified ? 1.0 : 0.0);
  h5.WriteAttribute(g, "delta_c_identified", r.delta_c.identified ? 1.0 : 0.0);
  h5.WriteAttribute(g, "J_tip_c_given", r.J_tip_c_given ? 1.0 : 0.0);
  h5.WriteAttribute(g, "onset_index", static_cast<double>(r.onset_index));
  h5.WriteAttribute(g, "onset_detected", r.onset_detected ? 1.0 : 0.0);
  h5.WriteAttribute(g, "points_used", static_cast<double>(r.points_used));
  h5.WriteAttribute(g, "plateau_points", static_cast<double>(r.plateau_points));
  h5.WriteAttribute(g, "penalty", r.penalty);
  h5.WriteAttribute(g, "effective_dof", r.effective_dof);
  h5.WriteAttribute(g, "chi2", r.chi2);
  h5.WriteAttribute(g, "noise_scale", r.noise_scale);
  h5.WriteAttribute(g, "resolved_fraction", r.resolved_fraction);
  h5.WriteAttribute(g, "run_s", r.run_seconds);
}

double Scalar(const io::H5Reader& r, const std::string& path) {
  const std::vector<double> v = detail::VectorOrEmpty(r, path);
  return v.empty() ? NAN : v[0];
}

laws::LawFreeResult ReadRoute(const io::H5Reader& r, const std::string& file, const std::string& g,
                              laws::LawFreeRoute route, std::vector<double>* opening,
                              std::vector<double>* value, std::vector<double>* uncertainty) {
  laws::LawFreeResult out;
  out.route = route;
  out.delta = r.ReadVector(g + "/delta");
  out.sigma = r.ReadVector(g + "/sigma");
  out.sigma_standard_error = detail::VectorOrEmpty(r, g + "/sigma_standard_error");
  out.sigma_lower = detail::VectorOrEmpty(r, g + "/sigma_lower");
  out.sigma_upper = detail::VectorOrEmpty(r, g + "/sigma_upper");
  out.J_tip_c = Scalar(r, g + "/J_tip_c");
  out.J_tip_c_standard_error = Scalar(r, g + "/J_tip_c_standard_error");
  out.J_B.value = Scalar(r, g + "/J_B");
  out.J_B.standard_error = Scalar(r, g + "/J_B_standard_error");
  out.delta_c.value = Scalar(r, g + "/delta_c");
  out.null_space_slope_min = Scalar(r, g + "/null_space_slope_min");
  *opening = detail::VectorOrEmpty(r, g + "/sample_opening");
  *value = detail::VectorOrEmpty(r, g + "/sample_value");
  *uncertainty = detail::VectorOrEmpty(r, g + "/sample_uncertainty");
  if (r.Exists(g + "/notes")) out.notes = FromNone(r.ReadStrings(g + "/notes"));
  auto flag = [&](const char* key) { return detail::NumberAttr(r, g, key) == 1.0; };
  out.identified = flag("identified");
  out.J_B.identified = flag("J_B_identified");
  out.delta_c.identified = flag("delta_c_identified");
  out.J_tip_c_given = flag("J_tip_c_given");
  out.onset_detected = flag("onset_detected");
  // `resolved` follows from the band, the route and `identified` (the one
  // rule, laws::MarkResolved), at the file's fraction (files before
  // 2026-12-05 hold none: the default).
  const double fraction = detail::NumberAttr(r, g, "resolved_fraction");
  laws::MarkResolved(std::isfinite(fraction) ? fraction : laws::LawFreeOptions{}.resolved_fraction,
                     out);
  auto integer = [&](const char* key) {
    const double v = detail::NumberAttr(r, g, key);
    return std::isfinite(v) ? static_cast<int>(v) : 0;
  };
  out.onset_index = integer("onset_index");
  out.points_used = integer("points_used");
  out.plateau_points = integer("plateau_points");
  out.penalty = detail::NumberAttr(r, g, "penalty");
  out.effective_dof = detail::NumberAttr(r, g, "effective_dof");
  out.chi2 = detail::NumberAttr(r, g, "chi2");
  out.noise_scale = detail::NumberAttr(r, g, "noise_scale");
  out.run_seconds = detail::NumberAttr(r, g, "run_s");
  const size_t n = out.delta.size();
  if (out.sigma.size() != n)
    throw Error(ErrorKind::kInput, "sigma and delta differ in length",
                {.file = file, .field = g + "/sigma",
                 .value = std::to_string(out.sigma.size()), .expected = std::to_string(n)});
  return out;
}

}  // namespace

void WriteLawFreeH5(const std::filesystem::path& path, const LawFreeRun& run) {
  io::H5Writer h5(path);
  h5.WriteStrings("/lawfree/notes", OrNone(run.notes));
  h5.WriteAttribute("/lawfree", "dic_file", run.dic_file);
  h5.WriteAttribute("/lawfree", "rcurve_file", run.rcurve_file);
  h5.WriteAttribute("/lawfree", "frames", static_cast<double>(run.frames));
  h5.WriteAttribute("/lawfree", "run_s", run.wall_s);
  if (run.far_field) {
    WriteRoute(h5, kFarFieldGroup, *run.far_field, run.j_samples.opening, run.j_samples.J_ff,
               run.j_samples.uncertainty);
    if (!run.j_samples.opening_uncertainty.empty())
      h5.WriteVector(std::string(kFarFieldGroup) + "/sample_opening_uncertainty",
                     run.j_samples.opening_uncertainty, "m",
                     "one standard uncertainty of delta* (effective variance)");
  }
  if (run.r_curve)
    WriteRoute(h5, kRCurveGroup, *run.r_curve, run.r_samples.opening, run.r_samples.R,
               run.r_samples.uncertainty);
  h5.Commit();
}

LawFreeRun ReadLawFreeH5(const std::filesystem::path& path) {
  const io::H5Reader r(path);
  if (!r.Exists("/lawfree/notes"))
    throw Error(ErrorKind::kInput, "the file holds no law-free result",
                {.file = path.string(), .field = "/lawfree",
                 .expected = "an HDF5 file from 'bridgefit lawfree --out'"});
  LawFreeRun run;
  run.notes = FromNone(r.ReadStrings("/lawfree/notes"));
  run.dic_file = detail::StringAttr(r, "/lawfree", "dic_file");
  run.rcurve_file = detail::StringAttr(r, "/lawfree", "rcurve_file");
  const double frames = detail::NumberAttr(r, "/lawfree", "frames");
  run.frames = std::isfinite(frames) ? static_cast<int>(frames) : 0;
  run.wall_s = detail::NumberAttr(r, "/lawfree", "run_s");
  if (r.Exists(std::string(kFarFieldGroup) + "/sigma"))
    run.far_field = ReadRoute(r, path.string(), kFarFieldGroup, laws::LawFreeRoute::kFarFieldJ,
                              &run.j_samples.opening, &run.j_samples.J_ff,
                              &run.j_samples.uncertainty);
  run.j_samples.opening_uncertainty =
      detail::VectorOrEmpty(r, std::string(kFarFieldGroup) + "/sample_opening_uncertainty");
  if (r.Exists(std::string(kRCurveGroup) + "/sigma"))
    run.r_curve = ReadRoute(r, path.string(), kRCurveGroup, laws::LawFreeRoute::kElasticZoneR,
                            &run.r_samples.opening, &run.r_samples.R, &run.r_samples.uncertainty);
  return run;
}

report::LawFreeView ReadLawFreeView(const std::filesystem::path& path) {
  const LawFreeRun run = ReadLawFreeH5(path);
  report::LawFreeView view;
  view.file = path;
  auto add = [&](const char* route, const std::optional<laws::LawFreeResult>& r) {
    if (!r) return;
    view.curves.push_back({route, r->delta, r->sigma, r->sigma_lower, r->sigma_upper, r->identified,
                           r->resolved, r->resolved_fraction});
  };
  add("J_ff(delta*)", run.far_field);
  add("R(delta_root)", run.r_curve);
  return view;
}

}  // namespace bridgefit::pipeline
