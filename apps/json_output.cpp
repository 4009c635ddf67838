// The --json objects of `rcurve`, `law` and `simulate` (json_output.hpp).
#include "json_output.hpp"

#include <cmath>

#include "command.hpp"

namespace bridgefit::cli {

nlohmann::json RCurveRunJson(const pipeline::RCurveRun& run) {
  const ExperimentRecord& record = run.record;
  const experiment::RCurveResult& result = run.result;
  nlohmann::json out;
  out["method"] = result.curve.method;
  out["r_kind"] = result.curve.r_kind;
  out["source"] = record.source;
  out["specimen"] = run.options.specimen.type == SpecimenType::kCT ? "ct" : "dcb";
  nlohmann::json points = nlohmann::json::array();
  for (std::size_t i = 0; i < result.curve.size(); ++i)
    points.push_back({{"crack_length_m", result.curve.crack_length[i]},
                      {"crack_growth_m", result.crack_growth[i]},
                      {"R_J_per_m2", result.curve.R[i]},
                      {"R_uncertainty_J_per_m2", NumberOrNull(result.curve.R_uncertainty[i])},
                      {"load_N", result.load[i]},
                      {"record_row", result.rows[i]},
                      {"displacement_m", result.displacement[i]}});
  out["points"] = std::move(points);
  out["initial_crack_length_m"] = NumberOrNull(result.curve.initial_crack_length);
  out["initiation_R_J_per_m2"] = NumberOrNull(result.curve.initiation_R);
  const experiment::Initiation& init = result.initiation;
  out["initiation"] = {{"initial_compliance_m_per_N", NumberOrNull(init.initial_compliance)},
                       {"nonlinearity_row", init.nonlinearity_row},
                       {"offset_row", init.offset_row},
                       {"max_load_row", init.max_load_row},
                       {"visual_row", init.visual_row},
                       {"R_nonlinearity_J_per_m2", NumberOrNull(init.R_nonlinearity)},
                       {"R_offset_J_per_m2", NumberOrNull(init.R_offset)}};
  out["points_used"] = result.points_used;
  nlohmann::json dropped = nlohmann::json::array();
  int total = 0;
  for (const auto& [reason, count] : run.DroppedRows()) {
    dropped.push_back({{"reason", reason}, {"count", count}});
    total += count;
  }
  out["points_dropped"] = std::move(dropped);
  out["points_dropped_total"] = total;
  out["rows_read"] = record.rows_read > 0 ? record.rows_read : static_cast<int>(record.size());
  out["noise"] = {{"load_N", result.load_noise},
                  {"displacement_m", result.displacement_noise},
                  {"crack_length_m", result.crack_length_noise},
                  {"coverage_factor", run.options.coverage_factor}};
  nlohmann::json figures = nlohmann::json::object();
  for (const auto& [key, value] : result.figures) figures[key] = NumberOrNull(value);
  out["figures"] = std::move(figures);
  out["notes"] = result.notes;
  out["warnings"] = result.warnings;
  out["wall_s"] = result.wall_s;
  return out;
}

nlohmann::json LawRunJson(const pipeline::LawRun& run) {
  nlohmann::json out;
  out["law"] = std::string(laws::LawFamilyName(run.shape.family));
  out["sigma_c_Pa"] = run.scales.sigma_c;
  out["delta_c_m"] = run.scales.delta_c;
  out["J_B_J_per_m2"] = run.scales.J_B;
  out["J_tip_c_J_per_m2"] = run.J_tip_c;
  out["shape_area"] = run.shape.Area();
  nlohmann::json points = nlohmann::json::array();
  for (const pipeline::LawPoint& p : run.points)
    points.push_back({{"delta_m", p.delta}, {"sigma_Pa", p.sigma}, {"R_J_per_m2", p.R},
                      {"J_ff_J_per_m2", p.J_ff}});
  out["points"] = std::move(points);
  return out;
}

nlohmann::json SimulationJson(const SimulationResult& result) {
  nlohmann::json out;
  out["model"] = result.model;
  out["status"] = RunStatusName(result.status);
  out["message"] = result.message;
  out["warnings"] = result.warnings;
  out["wall_s"] = result.wall_s;
  out["steady_state_reached"] = result.steady_state_reached;
  out["steady_state_crack_length_m"] = NumberOrNull(result.steady_state_crack_length);
  out["initiation_load_N"] = NumberOrNull(result.initiation_load);
  nlohmann::json figures = nlohmann::json::object();
  for (const auto& [key, value] : result.figures) figures[key] = NumberOrNull(value);
  out["figures"] = figures;
  nlohmann::json points = nlohmann::json::array();
  for (const SimulationPoint& p : result.points)
    points.push_back({{"crack_length_m", NumberOrNull(p.crack_length)},
                      {"R_J_per_m2", NumberOrNull(p.R)},
                      {"R_energy_J_per_m2", NumberOrNull(p.R_energy)},
                      {"J_tip_J_per_m2", NumberOrNull(p.J_tip)},
                      {"J_ff_J_per_m2", NumberOrNull(p.J_ff)},
                      {"delta_root_m", NumberOrNull(p.delta_root)},
                      {"root_position_m", NumberOrNull(p.root_position)},
                      {"bridging_zone_length_m", NumberOrNull(p.bridging_zone_length)},
                      {"load_N", NumberOrNull(p.load)},
                      {"displacement_m", NumberOrNull(p.displacement)},
                      {"cmod_m", NumberOrNull(p.cmod)}});
  out["points"] = std::move(points);
  return out;
}

nlohmann::json MpmGrowthJson(const mpm::GrowthResult& g) {
  nlohmann::json out = SimulationJson(g.result);
  out["solver"] = "quasi-static (implicit MPM)";
  out["symmetry"] = g.half ? "half" : "full";
  out["cell_m"] = g.cell;
  out["increment_m"] = g.increment;
  out["particles"] = g.particles;
  out["dofs"] = g.dofs;
  // One static solve per crack length: no time steps to count.
  out["particle_steps_per_s"] = nullptr;
  out["contour_cells"] = g.contour_cells;
  nlohmann::json per_point = nlohmann::json::array();
  for (const std::vector<double>& contours : g.J_tip_contours) {
    nlohmann::json row = nlohmann::json::array();
    for (double j : contours) row.push_back(NumberOrNull(j));
    per_point.push_back(row);
  }
  out["J_tip_contours_J_per_m2"] = per_point;
  nlohmann::json stages = nlohmann::json::object();
  for (const auto& [name, seconds] : g.stage_seconds) stages[name] = seconds;
  out["stage_seconds"] = stages;
  return out;
}

nlohmann::json MpmStationaryJson(const pipeline::MpmStationaryRun& run, const std::string& out) {
  const mpm::Summary& s = run.summary;
  const int main_contour = 0;
  nlohmann::json history = nlohmann::json::array();
  for (const auto& h : s.history)
    history.push_back({{"time_s", h.time},
                       {"load_N", NumberOrNull(h.load)},
                       {"displacement_m", h.displacement},
                       {"load_line_cod_m", NumberOrNull(h.load_line_cod)},
                       {"J_J_per_m2", NumberOrNull(h.J.empty() ? NAN : h.J[main_contour])}});
  nlohmann::json contours = nlohmann::json::array();
  for (const auto& j : s.final_J)
    contours.push_back({{"half_cells", j.half_cells}, {"J_J_per_m2", NumberOrNull(j.J)}});
  return {{"model", "mpm"},
          {"status", RunStatusName(s.status)},
          {"message", s.message},
          {"description", run.description},
          {"wall_s", s.wall_s},
          {"steps", s.steps},
          {"particles", s.particles},
          {"threads", s.threads},
          {"dt_s", s.dt},
          {"particle_steps_per_s", s.particle_steps_per_s},
          {"max_kinetic_to_strain_energy", s.max_kinetic_to_strain},
          {"final_load_N", NumberOrNull(s.final_load)},
          {"final_displacement_m", s.final_displacement},
          {"final_J", contours},
          {"out", out},
          {"history", history}};
}

namespace {
nlohmann::json LawFreeResultJson(const laws::LawFreeResult& r) {
  auto estimate = [](const laws::LawFreeEstimate& e) {
    return nlohmann::json{{"value", NumberOrNull(e.value)},
                          {"standard_error", NumberOrNull(e.standard_error)},
                          {"identified", e.identified},
                          {"kind", e.identified ? "value" : "lower_bound"}};
  };
  return {{"delta_m", r.delta},
          {"sigma_Pa", r.sigma},
          {"sigma_standard_error_Pa", r.sigma_standard_error},
          {"sigma_lower_Pa", r.sigma_lower},
          {"sigma_upper_Pa", r.sigma_upper},
          {"resolved", std::vector<bool>(r.resolved.begin(), r.resolved.end())},
          {"resolved_fraction", r.resolved_fraction},
          {"J_tip_c_J_per_m2", NumberOrNull(r.J_tip_c)},
          {"J_tip_c_standard_error_J_per_m2", NumberOrNull(r.J_tip_c_standard_error)},
          {"J_tip_c_given", r.J_tip_c_given},
          {"J_B_J_per_m2", estimate(r.J_B)},
          {"delta_c_m", estimate(r.delta_c)},
          {"identified", r.identified},
          {"null_space_slope_min_Pa_per_m", NumberOrNull(r.null_space_slope_min)},
          {"points_used", r.points_used},
          {"onset_index", r.onset_index},
          {"penalty", NumberOrNull(r.penalty)},
          {"effective_dof", NumberOrNull(r.effective_dof)},
          {"noise_scale", NumberOrNull(r.noise_scale)},
          {"notes", r.notes}};
}
}  // namespace

nlohmann::json LawFreeRunJson(const pipeline::LawFreeRun& run) {
  nlohmann::json out = {{"dic_file", run.dic_file},
                        {"rcurve_file", run.rcurve_file},
                        {"frames", run.frames},
                        {"notes", run.notes},
                        {"wall_s", run.wall_s}};
  out["far_field_j"] = run.far_field ? LawFreeResultJson(*run.far_field) : nlohmann::json();
  out["elastic_zone_r"] = run.r_curve ? LawFreeResultJson(*run.r_curve) : nlohmann::json();
  return out;
}

}  // namespace bridgefit::cli
