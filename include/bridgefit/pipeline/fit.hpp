#pragma once
// The fit workflow as one call (issue 16): a request value with IsValid and
// one run function returning everything the CLI prints or writes.
//
//   input (file or values) -> R curve (a record is reduced here, as
//   `bridgefit rcurve` would) -> forward models -> [compliance calibration
//   -> start fit] -> fit (one law, or every family by AICc; --model auto:
//   checked by MPM) -> the model's R at the data for a load-displacement fit
//
// The CLI (`bridgefit fit`), the benches and a batch runner call RunFit.
// Never throws for a failed forward run or a fit that did not converge (that
// is data, in the summary); throws bridgefit::Error for bad input (usage
// errors name the CLI option that sets the field).

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/experiment/rcurve.hpp"
#include "bridgefit/inverse/compliance_calibration.hpp"
#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/inverse/fit_shape.hpp"
#include "bridgefit/inverse/model_check.hpp"
#include "bridgefit/inverse/model_error.hpp"
#include "bridgefit/inverse/resolution.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/scene/scene.hpp"

namespace bridgefit::pipeline {

// The forward model: the cheapest that is accurate enough (README).
enum class ModelChoice {
  kReduced,   // the reduced model (docs/REDUCED.md)
  kAnalytic,  // small-scale bridging closed form
  kMpm,       // the MPM growth simulation
  kAuto,      // reduced fit, checked by MPM, corrected by space mapping
};
const char* ModelChoiceName(ModelChoice model);  // reduced | analytic | mpm | auto
ModelChoice ParseModelChoice(const std::string& name);

struct FitRequest {
  // The input: a file, told apart by its content (a CSV with crack_length
  // and R columns or an HDF5 with /rcurve is an R curve; a CSV with load and
  // displacement columns or an HDF5 with only /experiment is a record)...
  std::string input_path;
  std::string columns, units;  // CSV record: column and unit mapping (io::ApplyColumnMapping)
  // ...or values in memory (input_path empty): an R curve, or a record that
  // is reduced here; with both, the record is the one behind the R curve.
  std::optional<RCurve> rcurve;
  std::optional<ExperimentRecord> record;
  double record_initial_compliance = NAN;  // in-memory R curve: its record's C0 [m/N]
  // A record input's crack lengths measured on its images (a campaign
  // specimen's DIC): put into the record by experiment::CrackLengthFromFrames
  // (frames matched to rows by the record's image column) before the
  // reduction, as `rcurve --crack-length-from DIC.csv` does; what was done
  // goes into the reduction's notes. Empty: the record's own crack lengths.
  struct FrameCrackLengths {
    std::vector<std::string> image;   // each frame's image (file name)
    std::vector<double> crack_length;  // [m]; NaN: no length (the reference)
    std::string source;                // names them in notes and errors
  };
  std::optional<FrameCrackLengths> frame_crack_lengths;

  Scene scene;
  std::string scene_path;  // provenance in the fit file and errors

  ModelChoice model = ModelChoice::kReduced;
  // MPM cell [m], kMpm / kAuto; NaN: automatic (--mpm-cell auto): the
  // coarsest cell inside MPM's validity limits (2.5 mm at most, 8 cells
  // through a DCB arm, 10 over the data's growth); for kAuto then halved
  // while MPM's own error (from a solve at half the cell, order 1) is above
  // half the tolerance, at most `mpm_cell_halvings` times
  // (src/pipeline/fit_model_auto.cpp; an MPM run costs about 8x per halving).
  double mpm_cell = NAN;
  int mpm_cell_halvings = 3;
  double model_tolerance = 0.03;  // kAuto: relative R difference accepted
  // Reduced model element size [m]; NaN: automatic (--resolution auto,
  // inverse/resolution.hpp: the coarsest size whose predicted parameter
  // bias is below `resolution_bias_fraction` of each statistical
  // uncertainty, within the model's validity limits).
  double resolution = NAN;
  double resolution_bias_fraction = 0.3;
  // The reduced model's far-field element as a multiple of its default (CT
  // W/40, DCB h; models::ReducedOptions mesh.coarse_factor). The model error
  // refits once with half of it to see the far field's share, which
  // refining `resolution` does not change (docs/FIT.md, "The far field").
  double far_field = 1.0;

  bool compare_laws = false;  // every family, ranked by AICc
  // With compare_laws: the families whose shape is fitted too
  // (inverse/fit_shape.hpp), after the fixed-shape ones.
  std::vector<inverse::ShapeFamily> shape_families = {
      inverse::ShapeFamily::kBilinear, inverse::ShapeFamily::kTrilinear, inverse::ShapeFamily::kTable};
  inverse::ShapeFitOptions shape_fit;
  // A fitted-shape family alone (`--law bilinear|trilinear|table`, not with
  // compare_laws): its shape fitted with sigma_c, J_B and J_tip,c
  // (inverse/fit_shape.hpp; the table's N by AICc among
  // shape_fit.table_knots). Unset: the fixed-shape family `law`.
  std::optional<inverse::ShapeFamily> shape_law;
  laws::LawFamily law = laws::LawFamily::kLinear;
  // What the data's R is; nullopt: energy for an R curve, what its
  // reduction gives for a record. kAsData needs a record.
  std::optional<inverse::RKind> r_kind;
  inverse::FitTarget target = inverse::FitTarget::kRCurve;
  inverse::ComplianceCalibrationMode calibration = inverse::ComplianceCalibrationMode::kNone;
  inverse::FitOptions fit;
  // A record input's reduction (specimen and material come from the scene).
  experiment::RCurveOptions reduction;
  bool reduction_given = false;  // the caller set reduction options (an error for an R curve)

  // Every check that needs no input file; Check throws the Error RunFit
  // would, IsValid returns its text.
  void Check() const;
  bool IsValid(std::string* why) const;
};

// `--law` and a campaign manifest's `law` (the one home of the rule): compare
// (every family by AICc), a fitted-shape family (bilinear, trilinear, table:
// shape_law), or a fixed-shape family (linear, cubic, triangular,
// exponential: `law`). Sets compare_laws, shape_law and law. Throws
// Error(kUsage, field --law) naming the values. (A trilinear or table law
// held at the scene's points is FitRequest::law without shape_law.)
void SetFitLaw(const std::string& text, FitRequest& request);

// What the fit was given.
struct FitInput {
  std::string label;         // the path, or "(in memory)"
  bool from_record = false;  // reduced here
  RCurve curve;
  std::optional<ExperimentRecord> record;             // written as /experiment when known
  std::optional<experiment::RCurveResult> reduction;  // when from_record
  experiment::RCurveOptions reduction_options;
  // The record's initial compliance C0 [m/N] (the reduction's, or
  // /rcurve/figures of an rcurve.h5); NaN when unknown.
  double initial_compliance = NAN;
  // Record rows the R curve did not use, by reason, and the reduction's
  // warnings: the in-process reduction's, or an rcurve.h5's /rcurve/dropped_*
  // and /rcurve/warnings (issue 15: carried into the fit file and report).
  std::vector<std::pair<std::string, int>> dropped_rows;
  std::vector<std::string> reduction_warnings;
  std::string ReductionText() const;  // "energy method, reduced in-process from the record"
};

class ReducedModelCache;  // src/pipeline/fit_models.hpp

// The fitted shape's own parameters: a fitted-shape family fitted alone, or
// the comparison's winner when it is one (empty family: a fixed shape).
struct FittedShape {
  std::string family;  // "bilinear", "trilinear" or "table"; empty: none
  // d1, s1 / d1, d2, s0, s1, s2 / s(j/N), each with its Wald standard error
  // (the scale parameters free; inverse/fit_shape.hpp), in units of delta_c
  // (positions) and sigma_c (values).
  std::vector<inverse::ShapeParameter> parameters;
  int knots = 0;     // table: N (chosen by AICc among those tried)
  std::string note;  // how N was chosen, what was skipped
  bool fitted() const { return !family.empty(); }
};

struct FitRun {
  FitInput input;
  inverse::RKind r_kind = inverse::RKind::kEnergy;
  inverse::FitData data;                      // the R curve as fit data
  std::optional<inverse::FitData> load_data;  // a load-displacement fit's rows
  inverse::FitSummary summary;                // the fit (start fit and calibration counted in)
  laws::LawShape shape;                       // the law fitted (AICc's choice when comparing)
  FittedShape fitted_shape;                   // when that shape was fitted too
  std::vector<inverse::LawComparison> comparison;  // when comparing
  std::optional<inverse::FitSummary> start_fit;    // load-displacement fit: the R-curve fit
  inverse::ComplianceCalibrationResult calibration;
  bool model_checked = false;  // --model auto
  inverse::ModelCheckOptions check;
  inverse::ModelCheckResult model_check;
  double mpm_cell = NAN;  // [m], when an MPM model ran
  // --model auto: why the check cannot be trusted (the MPM run did not cover
  // the data, its cell is too coarse for the scene, a correction rejected
  // for MPM's own convergence); empty when none. Printed as a warning.
  std::string model_check_warning;
  // --model auto: max |R(cell / 2) / R(cell) - 1| of MPM at the final
  // parameters over the data (NaN when not computed: a given cell and no
  // correction).
  double mpm_convergence = NAN;
  // --model auto: MPM's own error at the check's crack lengths
  // (model_check.crack_length; R(cell) minus its converged R, order 1,
  // fit_model_auto.cpp), the corrected fit's model error; empty when not
  // computed.
  std::vector<double> mpm_error_R;  // [J/m^2]
  double mpm_error_from_cell = NAN;  // [m], the other cell of that estimate
  // --model auto with --mpm-cell auto: how the cell was chosen (the cells
  // tried, MPM's own error at each); empty for a given cell.
  std::string mpm_cell_choice;
  // Load-displacement fit: the model's R at the R curve's crack lengths.
  std::vector<double> load_fit_R;  // [J/m^2]
  double load_fit_R_rms = NAN;     // [J/m^2]
  std::string model_note;          // a sentence for the reader, or empty
  // The forward model's discretisation error, already in the summary's
  // intervals (issue 17; inverse/model_error.hpp).
  inverse::ModelErrorEstimate model_error;
  // The reduced model's element size used [m] (NaN without the reduced
  // model) and, when chosen automatically, how.
  double resolution = NAN;
  std::optional<inverse::ResolutionChoice> resolution_choice;
  // The reduced models built during this fit, shared by the resolution
  // chooser, the fit and the model error's coarser solves (RunFit sets it).
  std::shared_ptr<ReducedModelCache> reduced_models;

  // The rms R residual of the fit [J/m^2] (of the load fit's R curve for a
  // load-displacement fit).
  double RResidualRms() const;
  // The text `bridgefit fit` prints: law ranking, data, calibration, summary.
  std::string BriefReport() const;
};

// The input as the request names it (read, and reduced for a record).
FitInput ResolveFitInput(const FitRequest& request);

// R points measured below the scene's notch (crack lengths read short, by
// DIC or a gauge: a crack cannot be shorter than its notch, and the models
// start there) are fitted at the notch. A note says how many and by how
// much; a warning (input.reduction_warnings) where the largest shortfall
// exceeds twice the record's crack-length noise or 0.1 mm, whichever is
// larger (the crack lengths may then be offset).
void HoldAtNotch(double notch, FitInput& input, inverse::FitData& data);

FitRun RunFit(const FitRequest& request);

}  // namespace bridgefit::pipeline
