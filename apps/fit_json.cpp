// `bridgefit fit --json` (fit_json.hpp): the fit run, its model error and
// each parameter estimate as JSON.
#include "fit_json.hpp"

#include <cmath>

#include "command.hpp"

namespace bridgefit::cli {

using inverse::FitSummary;

nlohmann::json ModelErrorJson(const inverse::ModelErrorEstimate& m) {
  nlohmann::json bias;
  for (int i = 0; i < inverse::kParameterCount; ++i)
    bias[inverse::ParameterName(i)] = NumberOrNull(m.parameter_bias[i]);
  return {{"status", inverse::ModelErrorStatusName(m.status)},
          {"reason", m.reason},
          {"summary", m.Summary()},
          {"quantity", m.quantity},
          {"resolution_m", NumberOrNull(m.resolution)},
          {"coarse_resolution_m", NumberOrNull(m.coarse_resolution)},
          {"coarser_resolution_m", NumberOrNull(m.coarser_resolution)},
          {"observed_order", NumberOrNull(m.observed_order)},
          {"order_used", NumberOrNull(m.order_used)},
          {"safety_factor", NumberOrNull(m.safety_factor)},
          {"output_bias_rms", NumberOrNull(m.output_bias_rms)},
          {"output_bias_max", NumberOrNull(m.output_bias_max)},
          {"output_bias_max_relative", NumberOrNull(m.output_bias_max_relative)},
          {"output_bias_noise_rms", NumberOrNull(m.output_bias_noise_rms)},
          {"output_bias_noise_max", NumberOrNull(m.output_bias_noise_max)},
          {"warning", m.warning},
          {"parameter_bias", bias},
          {"wall_s", m.wall_s}};
}

namespace {

// "model_check": --model auto's check and correction.
nlohmann::json ModelCheckJson(const pipeline::FitRun& run) {
  const inverse::ModelCheckResult& model_check = run.model_check;
  return {{"outcome", model_check.outcome},
          {"cheap_model", model_check.cheap_model},
          {"accurate_model", model_check.accurate_model},
          {"mpm_cell_m", run.mpm_cell},
          {"tolerance", run.check.tolerance},
          {"accurate_ok", model_check.accurate_ok},
          {"corrected", model_check.corrected},
          {"corrections", model_check.corrections},
          {"accurate_runs", model_check.accurate_runs},
          {"cheap_fit_s", model_check.cheap_fit_s},
          {"accurate_s", model_check.accurate_s},
          {"correction_fit_s", model_check.correction_fit_s},
          {"discrepancy_at_cheap_optimum", NumberOrNull(model_check.discrepancy_at_cheap_optimum)},
          {"discrepancy_final", NumberOrNull(model_check.discrepancy_final)},
          {"mpm_convergence", NumberOrNull(run.mpm_convergence)},
          {"warning", run.model_check_warning}};
}

// "data": what the fit was given (and how a record was reduced).
nlohmann::json DataJson(const pipeline::FitInput& input, const std::string& input_path) {
  nlohmann::json data_json = {{"path", input_path},
                              {"kind", input.from_record ? "record" : "rcurve"},
                              {"rcurve_method", input.curve.method},
                              {"reduced_in_process", input.from_record},
                              {"reduction", input.ReductionText()},
                              {"rcurve_points", input.curve.size()}};
  if (!input.dropped_rows.empty()) {  // issue 15: every record row by reason
    int dropped = 0;
    nlohmann::json by_reason = nlohmann::json::array();
    for (const auto& [reason, count] : input.dropped_rows) {
      dropped += count;
      by_reason.push_back({{"reason", reason}, {"count", count}});
    }
    data_json["points_dropped"] = std::move(by_reason);
    data_json["points_dropped_total"] = dropped;
  }
  if (input.reduction) {
    const experiment::RCurveResult& r = *input.reduction;
    data_json["record_rows"] = input.record->size();
    data_json["rows_read"] = input.record->rows_read > 0 ? input.record->rows_read
                                                         : static_cast<int>(input.record->size());
    data_json["points_used"] = r.points_used;
    data_json["min_crack_increment_m"] = input.reduction_options.min_crack_increment;
    data_json["max_crack_length_m"] = NumberOrNull(input.reduction_options.max_crack_length);
    data_json["notes"] = r.notes;
    data_json["warnings"] = r.warnings;
    data_json["reduction_wall_s"] = r.wall_s;
  }
  return data_json;
}

// "compliance_calibration" of a load-displacement fit (null when not calibrated).
nlohmann::json CalibrationJson(const pipeline::FitRun& run) {
  const inverse::ComplianceCalibrationResult& calibration = run.calibration;
  if (!calibration.calibrated()) return nlohmann::json();
  nlohmann::json along_crack;
  if (calibration.along_crack)
    along_crack = {{"rms_relative", calibration.along_crack->fit.rms_relative},
                   {"rows", calibration.along_crack->fit.rows},
                   {"crack_min_m", calibration.along_crack->fit.crack_min},
                   {"crack_max_m", calibration.along_crack->fit.crack_max},
                   {"rounds", calibration.along_crack->rounds}};
  return {{"mode", inverse::ComplianceCalibrationModeName(calibration.mode)},
          {"modulus_factor", calibration.modulus_factor},
          {"series_compliance_m_per_N", calibration.series_compliance},
          {"along_crack", along_crack},
          {"modulus_factor_initial_slope", NumberOrNull(calibration.initial_slope_factor)},
          {"refinement_fits", calibration.fits},
          {"refinement_wall_s", calibration.wall_s},
          {"model_initial_compliance_m_per_N", calibration.model_initial_compliance},
          {"record_initial_compliance_m_per_N", run.input.initial_compliance}};
}

// "resolution_auto": how --resolution auto chose the element size.
nlohmann::json ResolutionAutoJson(const inverse::ResolutionChoice& choice) {
  nlohmann::json levels = nlohmann::json::array();
  for (const inverse::ResolutionLevel& l : choice.levels)
    levels.push_back({{"resolution_m", l.resolution},
                      {"evaluated", l.evaluated},
                      {"status", inverse::ModelErrorStatusName(l.status)},
                      {"meets", l.meets},
                      {"bias", {NumberOrNull(l.bias[0]), NumberOrNull(l.bias[1]), NumberOrNull(l.bias[2])}},
                      {"sd", {NumberOrNull(l.sd[0]), NumberOrNull(l.sd[1]), NumberOrNull(l.sd[2])}},
                      {"output_bias_noise_rms", NumberOrNull(l.output_bias_noise_rms)},
                      {"note", l.note}});
  return {{"resolution_m", choice.resolution},
          {"finest_m", NumberOrNull(choice.finest)},
          {"criterion_met", choice.criterion_met},
          {"reason", choice.reason},
          {"wall_s", choice.wall_s},
          {"levels", std::move(levels)}};
}

// "starts", "outliers_removed" and "law_comparison": the optimiser's record.
void AddSearchJson(const pipeline::FitRun& run, nlohmann::json& out) {
  const FitSummary& s = run.summary;
  nlohmann::json starts = nlohmann::json::array();
  for (const inverse::StartResult& start : s.starts)
    starts.push_back({{"start", start.start}, {"end", start.end}, {"chi2", NumberOrNull(start.cost)},
                      {"evaluations", start.evaluations}, {"stop_reason", start.stop_reason}});
  out["starts"] = std::move(starts);
  nlohmann::json outliers = nlohmann::json::array();
  for (size_t i = 0; i < s.outlier_R.size(); ++i)
    outliers.push_back(run.load_data ? nlohmann::json{{"displacement_m", s.outlier_crack_lengths[i]},
                                                  {"load_N", s.outlier_R[i]}}
                                 : nlohmann::json{{"crack_length_m", s.outlier_crack_lengths[i]},
                                                  {"R_J_per_m2", s.outlier_R[i]}});
  out["outliers_removed"] = std::move(outliers);
  if (s.misfit.points > 0)
    out["misfit"] = {{"points", s.misfit.points},
                     {"crack_length_from_m", s.misfit.crack_length_from},
                     {"crack_length_to_m", s.misfit.crack_length_to},
                     {"largest_robust_sd", s.misfit.largest_sd},
                     {"side", s.misfit.side > 0 ? "above" : s.misfit.side < 0 ? "below" : "both"},
                     {"message", s.misfit.Describe()}};
  nlohmann::json families = nlohmann::json::array();
  for (const auto& c : run.comparison) {
    nlohmann::json shape = nlohmann::json::array();
    for (const auto& p : c.shape_parameters)
      shape.push_back({{"name", p.name}, {"value", NumberOrNull(p.value)},
                       {"standard_error", NumberOrNull(p.standard_error)}, {"pinned", p.pinned}});
    families.push_back({{"law", c.law}, {"parameters", NumberOrNull(c.parameters)},
                        {"aicc", NumberOrNull(c.aicc)}, {"delta_aicc", NumberOrNull(c.delta_aicc)},
                        {"weight", NumberOrNull(c.weight)}, {"chi2", NumberOrNull(c.summary.chi2)},
                        {"converged", c.summary.converged}, {"note", c.note},
                        {"shape_parameters", std::move(shape)}});
  }
  out["law_comparison"] = std::move(families);
}

}  // namespace

nlohmann::json FitRunJson(const pipeline::FitRun& run, const std::string& input_path) {
  const FitSummary& s = run.summary;
  nlohmann::json out;
  out["model"] = s.model;
  out["model_note"] = run.model_note;
  if (run.model_checked) out["model_check"] = ModelCheckJson(run);
  out["optimizer"] = s.optimizer;
  out["law"] = s.law;
  out["r_kind"] = inverse::RKindName(run.r_kind);
  out["data"] = DataJson(run.input, input_path);
  out["evaluations"] = s.evaluations;
  out["failed_evaluations"] = s.failed_evaluations;
  out["wall_s"] = s.wall_s;
  out["converged"] = s.converged;
  out["stop_reason"] = s.stop_reason;
  out["steady_state_reached"] = s.steady_state_reached;
  out["steady_state_crack_length_m"] = NumberOrNull(s.steady_state_crack_length);
  out["bridging_detected"] = s.bridging_detected;
  out["verdict"] = s.verdict;
  out["fit_to"] = inverse::FitTargetName(s.target);
  out["rms_residual_J_per_m2"] = NumberOrNull(run.RResidualRms());
  if (run.load_data) {
    out["rms_residual_N"] = NumberOrNull(s.rms_residual);
    out["start_from_r_curve_fit"] = {
        {"sigma_c_Pa", NumberOrNull(run.start_fit->best_parameters[inverse::kSigmaC])},
        {"J_B_J_per_m2", NumberOrNull(run.start_fit->best_parameters[inverse::kJB])},
        {"J_tip_c_J_per_m2", NumberOrNull(run.start_fit->best_parameters[inverse::kJTipC])},
        {"evaluations", run.start_fit->evaluations},
        {"wall_s", run.start_fit->wall_s}};
    out["load_noise_N"] = NumberOrNull(run.input.reduction ? run.input.reduction->load_noise : NAN);
    out["compliance_calibration"] = CalibrationJson(run);
  }
  out["data_points"] = s.data_points;
  out["reduced_chi2"] = NumberOrNull(s.reduced_chi2);
  out["residual_autocorrelation"] = NumberOrNull(s.residual_autocorrelation);
  out["interval_inflation"] = NumberOrNull(s.interval_inflation);
  out["model_error"] = ModelErrorJson(run.model_error);
  out["resolution_m"] = NumberOrNull(run.resolution);
  if (run.resolution_choice) out["resolution_auto"] = ResolutionAutoJson(*run.resolution_choice);
  out["sigma_c_Pa"] = EstimateJson(s.sigma_c);
  out["J_B_J_per_m2"] = EstimateJson(s.J_B);
  out["delta_c_m"] = EstimateJson(s.delta_c);
  out["J_tip_c_J_per_m2"] = EstimateJson(s.J_tip_c);
  AddSearchJson(run, out);
  out["parameter_order"] = {"sigma_c_Pa", "J_B_J_per_m2", "J_tip_c_J_per_m2"};
  return out;
}

nlohmann::json EstimateJson(const inverse::ParameterEstimate& e) {
  return {{"value", NumberOrNull(e.value)},
          {"ci95_low", NumberOrNull(e.ci95_low)},
          {"ci95_high", NumberOrNull(e.ci95_high)},
          {"lower_bound", NumberOrNull(e.lower_bound)},
          {"identified", e.identified},
          {"fixed", e.fixed},
          {"decided_by", e.decided_by},
          {"note", e.note},
          {"interval_status", inverse::IntervalStatusName(e.interval_status)},
          {"interval_reason", e.interval_reason},
          // issue 17: ci95_* are the total interval (statistical + model bias)
          {"statistical_ci95_low", NumberOrNull(e.statistical_ci95_low)},
          {"statistical_ci95_high", NumberOrNull(e.statistical_ci95_high)},
          {"model_bias", NumberOrNull(e.model_bias)}};
}

}  // namespace bridgefit::cli
