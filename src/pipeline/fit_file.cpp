#include "bridgefit/pipeline/fit_file.hpp"

#include <cmath>
#include <fstream>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/rcurve_file.hpp"
#include "fit_models.hpp"
#include "h5_read.hpp"

namespace bridgefit::pipeline {
namespace {

void WriteEstimate(io::H5Writer& file, const std::string& group,
                   const inverse::ParameterEstimate& e, const std::string& units) {
  file.WriteAttribute(group, "units", units);
  file.WriteAttribute(group, "value", e.value);
  file.WriteAttribute(group, "ci95_low", e.ci95_low);
  file.WriteAttribute(group, "ci95_high", e.ci95_high);
  file.WriteAttribute(group, "lower_bound", e.lower_bound);
  file.WriteAttribute(group, "identified", e.identified ? 1.0 : 0.0);
  file.WriteAttribute(group, "fixed", e.fixed ? 1.0 : 0.0);
  file.WriteAttribute(group, "decided_by", e.decided_by);
  file.WriteAttribute(group, "note", e.note);
  file.WriteAttribute(group, "interval_status", inverse::IntervalStatusName(e.interval_status));
  file.WriteAttribute(group, "interval_reason", e.interval_reason);
  // Issue 17: ci95_* are the total interval; its parts.
  file.WriteAttribute(group, "statistical_ci95_low", e.statistical_ci95_low);
  file.WriteAttribute(group, "statistical_ci95_high", e.statistical_ci95_high);
  file.WriteAttribute(group, "model_bias", e.model_bias);
}

// The forward model's discretisation error (inverse/model_error.hpp).
void WriteModelError(io::H5Writer& file, const std::string& g, const FitRun& run) {
  const inverse::ModelErrorEstimate& m = run.model_error;
  const std::string me = g + "/model_error";
  file.WriteAttribute(me, "status", inverse::ModelErrorStatusName(m.status));
  file.WriteAttribute(me, "reason", m.reason);
  file.WriteAttribute(me, "summary", m.Summary());
  file.WriteAttribute(me, "quantity", m.quantity);
  file.WriteAttribute(me, "resolution_m", m.resolution);
  file.WriteAttribute(me, "coarse_resolution_m", m.coarse_resolution);
  file.WriteAttribute(me, "coarser_resolution_m", m.coarser_resolution);
  file.WriteAttribute(me, "observed_order", m.observed_order);
  file.WriteAttribute(me, "order_used", m.order_used);
  file.WriteAttribute(me, "safety_factor", m.safety_factor);
  file.WriteAttribute(me, "output_bias_rms", m.output_bias_rms);
  file.WriteAttribute(me, "output_bias_max", m.output_bias_max);
  file.WriteAttribute(me, "output_bias_max_relative", m.output_bias_max_relative);
  file.WriteAttribute(me, "output_bias_noise_rms", m.output_bias_noise_rms);
  file.WriteAttribute(me, "output_bias_noise_max", m.output_bias_noise_max);
  file.WriteAttribute(me, "warning", m.warning);
  for (int i = 0; i < inverse::kParameterCount; ++i)
    file.WriteAttribute(me, std::string("bias_") + inverse::ParameterName(i), m.parameter_bias[i]);
  file.WriteAttribute(me, "wall_s", m.wall_s);
  file.WriteAttribute(g, "resolution_m", run.resolution);
  if (run.resolution_choice) {
    file.WriteAttribute(g, "resolution_auto_reason", run.resolution_choice->reason);
    file.WriteAttribute(g, "resolution_auto_wall_s", run.resolution_choice->wall_s);
  }
  if (!m.output_bias.empty())
    file.WriteVector(me + "/output_bias", m.output_bias, m.quantity == "load" ? "N" : "J/m^2",
                     "predicted bias of the model's prediction at each data point used");
}

void WriteSummaryAttributes(io::H5Writer& file, const std::string& g, const FitRequest& request,
                            const FitRun& run) {
  const inverse::FitSummary& s = run.summary;
  file.WriteAttribute(g, "kind", "fit");
  file.WriteAttribute(g, "scene", request.scene_path);
  file.WriteAttribute(g, "input", run.input.label);
  file.WriteAttribute(g, "input_kind", run.input.from_record ? "record" : "rcurve");
  file.WriteAttribute(g, "rcurve_method", run.input.curve.method);
  file.WriteAttribute(g, "data_reduction", run.input.ReductionText());
  file.WriteAttribute(g, "model", s.model);
  file.WriteAttribute(g, "optimizer", s.optimizer);
  file.WriteAttribute(g, "law", s.law);
  file.WriteAttribute(g, "r_kind", inverse::RKindName(run.r_kind));
  file.WriteAttribute(g, "verdict", s.verdict);
  file.WriteAttribute(g, "stop_reason", s.stop_reason);
  file.WriteAttribute(g, "evaluations", s.evaluations);
  file.WriteAttribute(g, "failed_evaluations", s.failed_evaluations);
  file.WriteAttribute(g, "wall_s", s.wall_s);
  file.WriteAttribute(g, "converged", s.converged ? 1.0 : 0.0);
  file.WriteAttribute(g, "steady_state_reached", s.steady_state_reached ? 1.0 : 0.0);
  file.WriteAttribute(g, "bridging_detected", s.bridging_detected ? 1.0 : 0.0);
  file.WriteAttribute(g, "reduced_chi2", s.reduced_chi2);
  file.WriteAttribute(g, "residual_autocorrelation", s.residual_autocorrelation);
  file.WriteAttribute(g, "interval_inflation", s.interval_inflation);
  file.WriteAttribute(g, "fit_to", inverse::FitTargetName(s.target));
}

void WriteCalibration(io::H5Writer& file, const std::string& g, const FitRun& run) {
  const inverse::ComplianceCalibrationResult& c = run.calibration;
  if (!c.calibrated()) return;
  file.WriteAttribute(g, "modulus_factor", c.modulus_factor);
  file.WriteAttribute(g, "modulus_factor_initial_slope", c.initial_slope_factor);
  file.WriteAttribute(g, "model_initial_compliance_m_per_N", c.model_initial_compliance);
  file.WriteAttribute(g, "record_initial_compliance_m_per_N", run.input.initial_compliance);
  file.WriteAttribute(g, "compliance_calibration", inverse::ComplianceCalibrationModeName(c.mode));
  file.WriteAttribute(g, "series_compliance_m_per_N", c.series_compliance);
  if (c.along_crack) {
    file.WriteAttribute(g, "compliance_rms_relative", c.along_crack->fit.rms_relative);
    file.WriteAttribute(g, "compliance_rows", c.along_crack->fit.rows);
    file.WriteAttribute(g, "compliance_rounds", c.along_crack->rounds);
  }
}

// The data and the model's fit to it: a load-displacement fit's rows, or the
// R curve's points.
void WriteFittedData(io::H5Writer& file, const std::string& g, const FitRun& run) {
  const inverse::FitSummary& s = run.summary;
  file.WriteVector(g + "/crack_length", run.data.crack_length, "m", "data crack length");
  file.WriteVector(g + "/R", run.data.R, "J/m^2", "data R");
  if (run.load_data) {
    // The R curve shown with a load-displacement fit: the model's R at the
    // data's crack lengths; the fit itself under /fit/load_displacement.
    file.WriteAttribute(g, "rms_residual_J_per_m2", run.load_fit_R_rms);
    file.WriteAttribute(g, "rms_residual_N", s.rms_residual);
    if (!run.load_fit_R.empty()) {
      file.WriteVector(g + "/fitted_crack_length", run.data.crack_length, "m", "data crack length");
      file.WriteVector(g + "/fitted_R", run.load_fit_R, "J/m^2", "model R at the fitted parameters");
    }
    const std::string ld = g + "/load_displacement";
    file.WriteVector(ld + "/displacement", s.fitted_displacement, "m", "record rows used");
    file.WriteVector(ld + "/load", s.fitted_record_load, "N", "record load");
    file.WriteVector(ld + "/fitted_load", s.fitted_load, "N", "model load");
    file.WriteVector(ld + "/fitted_crack_length", s.fitted_crack_length, "m",
                     "model crack length at each row");
    file.WriteVector(ld + "/outlier_displacement", s.outlier_crack_lengths, "m", "removed rows");
    file.WriteVector(ld + "/outlier_load", s.outlier_R, "N", "removed rows");
  } else {
    file.WriteAttribute(g, "rms_residual_J_per_m2", s.rms_residual);
    file.WriteVector(g + "/outlier_crack_length", s.outlier_crack_lengths, "m", "removed points");
    file.WriteVector(g + "/outlier_R", s.outlier_R, "J/m^2", "removed points");
    file.WriteAttribute(g, "misfit_points", static_cast<double>(s.misfit.points));
    if (s.misfit.points > 0) {
      file.WriteAttribute(g, "misfit_crack_length_from_m", s.misfit.crack_length_from);
      file.WriteAttribute(g, "misfit_crack_length_to_m", s.misfit.crack_length_to);
      file.WriteAttribute(g, "misfit_largest_robust_sd", s.misfit.largest_sd);
      file.WriteAttribute(g, "misfit", s.misfit.Describe());
    }
    file.WriteVector(g + "/fitted_crack_length", s.fitted_crack_length, "m", "points used");
    if (!s.fitted_R.empty()) file.WriteVector(g + "/fitted_R", s.fitted_R, "J/m^2", "model R");
  }
  if (!s.fitted_delta_root.empty())
    file.WriteVector(g + "/fitted_delta_root", s.fitted_delta_root, "m", "model notch-root COD");
}

void WriteModelCheck(io::H5Writer& file, const std::string& g, const FitRun& run) {
  if (!run.model_checked) return;
  const inverse::ModelCheckResult& m = run.model_check;
  const std::string mc = g + "/model_check";
  file.WriteAttribute(mc, "outcome", m.outcome);
  file.WriteAttribute(mc, "cheap_model", m.cheap_model);
  file.WriteAttribute(mc, "accurate_model", m.accurate_model);
  file.WriteAttribute(mc, "mpm_cell_m", run.mpm_cell);
  file.WriteAttribute(mc, "tolerance", run.check.tolerance);
  file.WriteAttribute(mc, "corrected", m.corrected ? 1.0 : 0.0);
  file.WriteAttribute(mc, "corrections", static_cast<double>(m.corrections));
  file.WriteAttribute(mc, "accurate_runs", static_cast<double>(m.accurate_runs));
  file.WriteAttribute(mc, "cheap_fit_s", m.cheap_fit_s);
  file.WriteAttribute(mc, "accurate_s", m.accurate_s);
  file.WriteAttribute(mc, "correction_fit_s", m.correction_fit_s);
  file.WriteAttribute(mc, "discrepancy_at_cheap_optimum", m.discrepancy_at_cheap_optimum);
  file.WriteAttribute(mc, "discrepancy_final", m.discrepancy_final);
  file.WriteAttribute(mc, "mpm_convergence", run.mpm_convergence);
  file.WriteAttribute(mc, "warning", run.model_check_warning);
  file.WriteAttribute(mc, "mpm_cell_choice", run.mpm_cell_choice);
  if (!m.crack_length.empty()) {
    file.WriteVector(mc + "/crack_length", m.crack_length, "m", "data crack length");
    file.WriteVector(mc + "/R_cheap", m.R_cheap, "J/m^2", "reduced model R");
    file.WriteVector(mc + "/R_accurate", m.R_accurate, "J/m^2", "MPM R");
  }
}

void WriteProfiles(io::H5Writer& file, const std::string& g, const inverse::FitSummary& s) {
  for (const inverse::Profile& p : s.profiles) {
    std::vector<double> values, chi2;
    for (const auto& point : p.points) {
      if (!point.ok) continue;
      values.push_back(point.value);
      chi2.push_back(point.chi2);
    }
    const std::string pg = g + "/profiles/" + inverse::ParameterName(p.parameter);
    file.WriteVector(pg + "/value", values, p.parameter == inverse::kSigmaC ? "Pa" : "J/m^2");
    file.WriteVector(pg + "/chi2", chi2, "1", "best chi^2 with the others re-optimized");
    file.WriteAttribute(pg, "chi2_threshold", p.chi2_threshold);
    file.WriteAttribute(pg, "flat", p.flat ? 1.0 : 0.0);
    file.WriteAttribute(pg, "status", inverse::IntervalStatusName(p.status));
    file.WriteAttribute(pg, "status_reason", p.status_reason);
    file.WriteAttribute(pg, "resolves", p.resolves);
  }
}

// The specimen and material the fit's model used (the scene after a
// campaign's per-specimen sizes and the compliance calibration), so that
// `bridgefit design` needs no scene file.
void WriteFitScene(io::H5Writer& file, const std::string& g, const Scene& scene) {
  const std::string sg = g + "/scene";
  const SpecimenSpec& s = scene.specimen;
  file.WriteAttribute(sg, "specimen", s.type == SpecimenType::kCT ? "ct" : "dcb");
  file.WriteAttribute(sg, "width_m", s.width);
  file.WriteAttribute(sg, "height_m", s.height);
  file.WriteAttribute(sg, "thickness_m", s.thickness);
  file.WriteAttribute(sg, "length_m", s.length);
  file.WriteAttribute(sg, "notch_m", s.notch);
  file.WriteAttribute(sg, "plane", s.plane == PlaneCondition::kPlaneStrain ? "strain" : "stress");
  const MaterialSpec& m = scene.material;
  file.WriteAttribute(sg, "orthotropic", m.orthotropic ? 1.0 : 0.0);
  file.WriteAttribute(sg, "E_Pa", m.E);
  file.WriteAttribute(sg, "nu", m.nu);
  file.WriteAttribute(sg, "E1_Pa", m.E1);
  file.WriteAttribute(sg, "E2_Pa", m.E2);
  file.WriteAttribute(sg, "G12_Pa", m.G12);
  file.WriteAttribute(sg, "nu12", m.nu12);
  file.WriteAttribute(sg, "G13_Pa", m.G13);
  file.WriteAttribute(sg, "angle_rad", m.angle);
  file.WriteAttribute(sg, "density_kg_per_m3", m.density);
}

// The law fitted (/fit/law_shape, docs/FORMATS.md): its normalized shape
// s(d) as laws::LawShape holds it (family, parameters, break points and the
// interpolation between them), the break points at the fitted scales, and
// a fitted shape's own parameters with their Wald standard errors.
void WriteLawShape(io::H5Writer& file, const std::string& g, const FitRun& run) {
  const laws::LawShape& shape = run.shape;
  const std::string lg = g + "/law_shape";
  file.WriteAttribute(lg, "family", std::string(laws::LawFamilyName(shape.family)));
  file.WriteAttribute(lg, "peak_ratio", shape.peak_ratio);
  file.WriteAttribute(lg, "alpha", shape.alpha);
  file.WriteAttribute(lg, "interpolation",
                      std::string(laws::TableInterpolationName(shape.interpolation)));
  if (!shape.d_points.empty()) {
    file.WriteVector(lg + "/d_points", shape.d_points, "1", "delta / delta_c of the break points");
    file.WriteVector(lg + "/s_points", shape.s_points, "1", "sigma / sigma_c at the break points");
    const double sigma_c = run.summary.sigma_c.value, delta_c = run.summary.delta_c.value;
    if (std::isfinite(sigma_c) && std::isfinite(delta_c)) {
      std::vector<double> delta, sigma;
      for (size_t k = 0; k < shape.d_points.size(); ++k) {
        delta.push_back(shape.d_points[k] * delta_c);
        sigma.push_back(shape.s_points[k] * sigma_c);
      }
      file.WriteVector(lg + "/delta_points", delta, "m", "break points' opening at the fitted delta_c");
      file.WriteVector(lg + "/sigma_points", sigma, "Pa", "break points' stress at the fitted sigma_c");
    }
  }
  const FittedShape& f = run.fitted_shape;
  file.WriteAttribute(lg, "fitted_family", f.family);
  if (!f.fitted()) return;
  file.WriteAttribute(lg, "knots", static_cast<double>(f.knots));
  file.WriteAttribute(lg, "note", f.note);
  std::vector<std::string> names;
  std::vector<double> values, errors, pinned;
  for (const inverse::ShapeParameter& p : f.parameters) {
    names.push_back(p.name);
    values.push_back(p.value);
    errors.push_back(p.standard_error);
    pinned.push_back(p.pinned ? 1.0 : 0.0);
  }
  file.WriteStrings(lg + "/parameter_names", names);
  file.WriteVector(lg + "/parameter_values", values, "1",
                   "d: delta / delta_c; s: sigma / sigma_c");
  file.WriteVector(lg + "/parameter_standard_errors", errors, "1",
                   "Wald standard errors, the scale parameters free (NaN: pinned or singular)");
  file.WriteVector(lg + "/parameter_pinned", pinned, "1", "1: the peak knot, sigma_c by definition");
}

}  // namespace

void WriteFitFile(const std::string& path, const FitRequest& request, const FitRun& run) {
  io::H5Writer file(path);
  const FitInput& input = run.input;
  if (input.reduction) {
    WriteReductionH5(file, *input.record, *input.reduction, input.reduction_options,
                     request.scene_path);
  } else {
    io::WriteRecordH5(file, input.curve, "/rcurve");
    if (input.record) io::WriteRecordH5(file, *input.record, "/experiment");
    if (!input.dropped_rows.empty())  // from an rcurve.h5
      WriteDroppedRows(file, input.dropped_rows, input.reduction_warnings);
  }
  const std::string g = "/fit";
  WriteSummaryAttributes(file, g, request, run);
  WriteCalibration(file, g, run);
  WriteFittedData(file, g, run);
  WriteEstimate(file, g + "/parameters/sigma_c", run.summary.sigma_c, "Pa");
  WriteEstimate(file, g + "/parameters/J_B", run.summary.J_B, "J/m^2");
  WriteEstimate(file, g + "/parameters/delta_c", run.summary.delta_c, "m");
  WriteEstimate(file, g + "/parameters/J_tip_c", run.summary.J_tip_c, "J/m^2");
  // The moduli as the fit's model used them (calibrated: times modulus_factor).
  WriteFitScene(file, g, run.calibration.calibrated()
                             ? ScaledModuli(request.scene, run.calibration.modulus_factor)
                             : request.scene);
  WriteLawShape(file, g, run);
  WriteModelCheck(file, g, run);
  WriteModelError(file, g, run);
  WriteProfiles(file, g, run.summary);
  file.Commit();
}

}  // namespace bridgefit::pipeline
