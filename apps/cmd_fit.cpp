// `bridgefit fit`: bridging-law parameters from a measured R curve, or from a
// load-displacement record with crack length reduced in-process (issue 7).
//   bridgefit fit rcurve.csv --scene scene.toml --law linear --json
//   bridgefit fit rcurve.h5 --scene scene.toml --fix J_tip_c=2210J/m^2 --out fit.h5
//   bridgefit fit data_samples/mdf_ct/record_exact.csv --scene data_samples/mdf_ct/scene.toml
//       --rcurve-method energy --out fit.h5 --report report

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <filesystem>
#include <functional>
#include <optional>
#include <sstream>
#include <unistd.h>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/experiment/rcurve.hpp"
#include "bridgefit/inverse/compliance.hpp"
#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/inverse/model_check.hpp"
#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/mpm/growth.hpp"
#include "bridgefit/report/report.hpp"
#include "command.hpp"
#include "record_input.hpp"

namespace bridgefit::cli {
namespace {

using inverse::FitSummary;
using inverse::ParameterEstimate;

int ParameterIndex(const std::string& name, const char* option) {
  for (int i = 0; i < inverse::kParameterCount; ++i)
    if (name == inverse::ParameterName(i)) return i;
  throw Error(ErrorKind::kUsage, "unknown parameter",
              {.field = option, .value = name, .expected = "sigma_c, J_B or J_tip_c"});
}

Dimension ParameterDimension(int index) {
  return index == inverse::kSigmaC ? Dimension::Stress() : Dimension::EnergyPerArea();
}

std::vector<std::pair<std::string, std::string>> SplitAssignments(const std::string& text,
                                                                  const char* option) {
  std::vector<std::pair<std::string, std::string>> out;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    const size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw Error(ErrorKind::kUsage, "malformed assignment",
                  {.field = option, .value = item, .expected = "name=value, e.g. J_tip_c=2210J/m^2"});
    out.emplace_back(item.substr(0, eq), item.substr(eq + 1));
  }
  return out;
}

bool IsHdf5(const std::string& path) {
  return path.size() > 3 && (path.ends_with(".h5") || path.ends_with(".hdf5"));
}

// R curve from CSV ('crack_length [mm], R [J/m^2][, R_uncertainty [J/m^2]]')
// or from the HDF5 written by `bridgefit rcurve`.
RCurve ReadRCurveInput(const std::string& path) {
  if (IsHdf5(path)) {
    const io::H5Reader reader(path);
    return io::ReadRCurveH5(reader);
  }
  const io::CsvTable table = io::ReadCsvTable(path);
  RCurve curve;
  curve.source = path;
  curve.method = "csv";
  curve.crack_length = table.ColumnSi("crack_length", Dimension::Length());
  curve.R = table.ColumnSi("R", Dimension::EnergyPerArea());
  if (table.Find("R_uncertainty") >= 0)
    curve.R_uncertainty = table.ColumnSi("R_uncertainty", Dimension::EnergyPerArea());
  for (size_t i = 0; i < curve.R.size(); ++i)
    if (!std::isfinite(curve.R[i]) || !std::isfinite(curve.crack_length[i]))
      throw Error(ErrorKind::kInput, "missing value in row " + std::to_string(i + 1),
                  {.file = path, .expected = "a crack length and an R in every row"});
  curve.Validate();
  return curve;
}

// What the fit was given: an R curve, or a load-displacement record that is
// reduced here with the same library call and defaults as
// `bridgefit rcurve RECORD --scene SCENE --method M` (docs/FIT.md).
struct FitInput {
  bool from_record = false;  // reduced in-process
  RCurve curve;
  std::optional<ExperimentRecord> record;             // stored as /experiment when known
  std::optional<experiment::RCurveResult> reduction;  // when from_record
  experiment::RCurveOptions reduction_options;
  // The record's initial compliance C0 [m/N] (slope of the reduction's line
  // d = d0 + C0 P, or /rcurve/figures of an rcurve.h5); NaN when unknown.
  double initial_compliance = NAN;
};

// The `bridgefit rcurve` options that `bridgefit fit RECORD` takes.
struct ReductionFlags {
  std::string method = "energy", min_increment, max_crack_length, columns, units;
  std::string load_noise, displacement_noise, crack_noise;
  int smooth_rows = 0;
  bool any_given = false;  // any of them on the command line
};

// Which an input holds, by its content: a CSV with `crack_length` and `R`
// columns, or an HDF5 with /rcurve, is an R curve; a CSV with load and
// displacement columns, or an HDF5 with only /experiment, is a record.
bool InputIsRecord(const std::string& path, const ReductionFlags& flags) {
  if (IsHdf5(path)) {
    const io::H5Reader reader(path);
    if (reader.Exists("/rcurve")) return false;
    if (reader.Exists("/experiment")) return true;
    throw Error(
        ErrorKind::kInput, "the HDF5 file holds neither an R curve nor a test record",
        {.file = path,
         .field = "/rcurve, /experiment",
         .expected = "the output of `bridgefit rcurve --out` (or a file with /experiment)"});
  }
  const io::CsvTable table = io::ReadCsvTable(path);
  if (table.Find("crack_length") >= 0 && table.Find("R") >= 0) return false;
  io::RecordColumns columns;
  if (!flags.columns.empty()) io::ApplyColumnMapping(flags.columns, columns);
  if (table.Find(columns.load) >= 0 && table.Find(columns.displacement) >= 0) return true;
  std::string header;
  for (const std::string& name : table.names) header += (header.empty() ? "" : ", ") + name;
  throw Error(
      ErrorKind::kInput, "the CSV is neither an R curve nor a load-displacement record",
      {.file = path,
       .line = 1,
       .field = "header",
       .value = header,
       .expected = "'crack_length [mm], R [J/m^2]' (R curve) or 'load [N], displacement [mm], "
                   "crack_length [mm]' (record; --columns renames)"});
}

FitInput ReadFitInput(const std::string& path, const Scene& scene, const ReductionFlags& flags) {
  FitInput input;
  input.from_record = InputIsRecord(path, flags);
  if (!input.from_record) {
    if (flags.any_given)
      throw Error(ErrorKind::kUsage, "the R-curve reduction options apply to a record only",
                  {.file = path,
                   .field = "--rcurve-method, --rcurve-min-increment, --rcurve-max-crack-length, "
                            "--rcurve-smooth, --rcurve-*-noise, --columns, --units",
                   .expected = "a load-displacement record as input, or none of these options"});
    input.curve = ReadRCurveInput(path);
    if (IsHdf5(path)) {
      const io::H5Reader reader(path);
      if (reader.Exists("/experiment/load")) input.record = io::ReadExperimentH5(reader, "/experiment");
      if (reader.Exists("/rcurve/figures") &&
          reader.HasAttribute("/rcurve/figures", "initial_compliance_m_per_N")) {
        input.initial_compliance =
            reader.ReadNumberAttribute("/rcurve/figures", "initial_compliance_m_per_N");
      }
    }
    return input;
  }
  experiment::RCurveOptions& options = input.reduction_options;
  try {
    options.method = experiment::ParseRMethod(flags.method);
  } catch (const Error& e) {
    throw Error(
        ErrorKind::kUsage, e.message(),
        {.field = "--rcurve-method", .value = flags.method, .expected = e.context().expected});
  }
  options.specimen = scene.specimen;
  options.material = scene.material;
  if (!flags.min_increment.empty())
    options.min_crack_increment =
        ParseOptionQuantity(flags.min_increment, Dimension::Length(), "--rcurve-min-increment");
  options.max_crack_length =
      ParseOptionQuantity(flags.max_crack_length, Dimension::Length(), "--rcurve-max-crack-length");
  options.smoothing_half_window = flags.smooth_rows;
  options.load_noise =
      ParseOptionQuantity(flags.load_noise, Dimension::Force(), "--rcurve-load-noise");
  options.displacement_noise = ParseOptionQuantity(flags.displacement_noise, Dimension::Length(),
                                                   "--rcurve-displacement-noise");
  options.crack_length_noise =
      ParseOptionQuantity(flags.crack_noise, Dimension::Length(), "--rcurve-crack-noise");
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid R-curve options: " + why);

  input.record = ReadRecordFile(path, flags.columns, flags.units);
  // Only the compliance-based reductions infer the crack length (CT lefm
  // and equivalent: docs/RCURVE_METHODS.md); the energy method needs it.
  const bool needs_crack_length =
      options.method != experiment::RMethod::kEquivalentCrack &&
      !(options.method == experiment::RMethod::kLefm && scene.specimen.type == SpecimenType::kCT);
  if (needs_crack_length && !input.record->has_crack_length()) {
    io::RecordColumns columns;
    if (!flags.columns.empty()) io::ApplyColumnMapping(flags.columns, columns);
    throw Error(ErrorKind::kInput,
                fmt::format("the record has no crack-length column, which the {} method needs",
                            experiment::RMethodName(options.method)),
                {.file = path,
                 .field = columns.crack_length,
                 .expected = "a column 'crack_length [mm]' (another header: --columns "
                             "crack_length=HEADER), an R curve as input, or --rcurve-method "
                             "equivalent (crack length from the compliance)"});
  }
  input.reduction = experiment::ComputeRCurve(*input.record, options);
  input.curve = input.reduction->curve;
  input.initial_compliance = input.reduction->initiation.initial_compliance;
  return input;
}

nlohmann::json EstimateJson(const ParameterEstimate& e) {
  return {{"value", NumberOrNull(e.value)},
          {"ci95_low", NumberOrNull(e.ci95_low)},
          {"ci95_high", NumberOrNull(e.ci95_high)},
          {"lower_bound", NumberOrNull(e.lower_bound)},
          {"identified", e.identified},
          {"fixed", e.fixed},
          {"decided_by", e.decided_by},
          {"note", e.note}};
}

void WriteEstimate(io::H5Writer& file, const std::string& group, const ParameterEstimate& e,
                   const std::string& units) {
  file.WriteAttribute(group, "units", units);
  file.WriteAttribute(group, "value", e.value);
  file.WriteAttribute(group, "ci95_low", e.ci95_low);
  file.WriteAttribute(group, "ci95_high", e.ci95_high);
  file.WriteAttribute(group, "lower_bound", e.lower_bound);
  file.WriteAttribute(group, "identified", e.identified ? 1.0 : 0.0);
  file.WriteAttribute(group, "fixed", e.fixed ? 1.0 : 0.0);
  file.WriteAttribute(group, "decided_by", e.decided_by);
  file.WriteAttribute(group, "note", e.note);
}

// R kind as-data: the model's points become a record (a linear loading branch
// to initiation, then one row per crack length) that is reduced with the
// data's own method and options, without noise.
inverse::SimulationForwardModel::Reducer ModelRecordReducer(const FitInput& input) {
  experiment::RCurveOptions options = input.reduction_options;
  options.load_noise = 1e-3;            // [N]: the model has none; small, not zero
  options.displacement_noise = 1e-9;    // [m]
  options.crack_length_noise = 1e-6;    // [m]
  options.smoothing_half_window = 0;
  return [options](const SimulationResult& sim) {
    constexpr int kLoading = 20;
    inverse::SimulationForwardModel::Reduced out;
    if (sim.points.empty()) return out;
    ExperimentRecord record;
    record.source = "model record (" + sim.model + ")";
    const SimulationPoint& first = sim.points.front();
    for (int i = 0; i < kLoading; ++i) {
      const double f = static_cast<double>(i) / kLoading;
      record.time.push_back(i);
      record.load.push_back(f * first.load);
      record.displacement.push_back(f * first.displacement);
      record.crack_length.push_back(first.crack_length);
    }
    // The initiation point with its crack grown by 1 um, so the reduction
    // has a point at initiation (the data's first growth rows).
    for (std::size_t k = 0; k < sim.points.size(); ++k) {
      record.time.push_back(kLoading + static_cast<double>(k));
      record.load.push_back(sim.points[k].load);
      record.displacement.push_back(sim.points[k].displacement);
      record.crack_length.push_back(sim.points[k].crack_length + (k == 0 ? 1e-6 : 0.0));
    }
    const experiment::RCurveResult r = experiment::ComputeRCurve(record, options);
    for (std::size_t i = 0; i < r.curve.size(); ++i) {
      out.crack_length.push_back(r.curve.crack_length[i]);
      out.R.push_back(r.curve.R[i]);
      out.point.push_back(std::max(0, r.rows[i] - kLoading));
    }
    return out;
  };
}

// The scene with every modulus scaled by `factor` (the compliance of an
// elastic model scales by 1 / factor).
Scene ScaledModuli(const Scene& scene, double factor) {
  Scene scaled = scene;
  for (double* modulus : {&scaled.material.E, &scaled.material.E1, &scaled.material.E2,
                          &scaled.material.G12, &scaled.material.G13})
    *modulus *= factor;
  return scaled;
}

// The law a fit ended at: its best parameters, or J_tip,c alone when it
// found no bridging.
inverse::LawParameters FittedLaw(const FitSummary& s) {
  return {.sigma_c = s.best_parameters[inverse::kSigmaC],
          .J_B = s.bridging_detected ? s.best_parameters[inverse::kJB] : 0.0,
          .J_tip_c = s.bridging_detected ? s.best_parameters[inverse::kJTipC] : s.J_tip_c.value};
}

// --calibrate-compliance=crack: the modulus factor f and the series
// compliance C_s that make the fitted model's compliance follow the record's
// at its measured crack lengths, alternated with the law's fit (the record's
// compliance at a crack is that of the bridged crack, so the law enters):
// quick load fit at (f, C_s) -> the model's specimen compliance
// (d - C_s P) / P against its crack length along the fitted path -> a scale
// s and C_s from the record's rows (FitComplianceAlongCrack) -> f / s and the
// new C_s (accelerated, below), until ln f and C_s / C_ref move by less than
// 1e-3 (C_ref: the median compliance of the rows used; at most 12 rounds).
struct AlongCrackCalibration {
  double modulus_factor = NAN, series_compliance = 0.0;
  inverse::ComplianceFit fit;
  int iterations = 0, fits = 0, evaluations = 0;
  double wall_s = 0.0;
  std::string note;
};

AlongCrackCalibration CalibrateAlongCrack(
    const ExperimentRecord& record, const Scene& scene, const laws::LawShape& shape,
    const inverse::FitData& load_data, inverse::FitOptions options, double modulus_factor,
    const std::function<const inverse::ForwardModel*(double factor, double series)>& rebuild) {
  // The record's rows on its loading path (up to the largest displacement)
  // with a crack measured beyond the notch and a load above a fifth of the peak.
  std::vector<double> d, a, C;
  const std::size_t last =
      std::max_element(record.displacement.begin(), record.displacement.end()) -
      record.displacement.begin();
  const double peak = *std::max_element(record.load.begin(), record.load.end());
  for (std::size_t i = 0; i <= last; ++i)
    if (std::isfinite(record.crack_length[i]) && record.crack_length[i] > scene.specimen.notch &&
        record.load[i] >= 0.2 * peak && record.displacement[i] > 0.0) {
      d.push_back(record.displacement[i]);
      a.push_back(record.crack_length[i]);
      C.push_back(record.displacement[i] / record.load[i]);
    }
  BF_CHECK_INPUT(C.size() >= 5,
                 fmt::format("{} rows with a crack beyond the notch on the loading path; the "
                             "compliance along the crack needs 5 or more", C.size()),
                 {.file = record.source, .field = "crack_length"});
  std::vector<double> sorted = C;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double reference = sorted[sorted.size() / 2];
  options.profile_likelihood = false;
  options.starts = 1;
  options.progress = false;
  AlongCrackCalibration out;
  out.modulus_factor = modulus_factor;
  constexpr int kMaxRounds = 12;
  std::array<double, 2> previous_F{}, previous_g{};
  for (int round = 0; round < kMaxRounds; ++round) {
    const inverse::ForwardModel* model = rebuild(out.modulus_factor, out.series_compliance);
    const FitSummary q = inverse::FitBridgingLaw(*model, shape, load_data, options);
    ++out.fits;
    out.evaluations += q.evaluations;
    out.wall_s += q.wall_s;
    const inverse::LawParameters at = FittedLaw(q);
    // A round's fit need not converge to move (f, C_s) on: the final fit
    // reports its own convergence.
    if (!std::isfinite(at.J_tip_c) || !std::isfinite(at.sigma_c))
      throw Error(ErrorKind::kRuntime,
                  "calibrating the compliance along the crack: the law's fit gave no parameters (" +
                      q.stop_reason + ")",
                  {.file = record.source, .field = "--calibrate-compliance", .value = "crack"});
    for (int i = 0; i < inverse::kParameterCount; ++i)
      if (std::isfinite(q.best_parameters[i])) options.initial[i] = q.best_parameters[i];
    if (!q.bridging_detected) options.initial[inverse::kJTipC] = q.J_tip_c.value;
    // The fitted model's specimen compliance along its own crack.
    const inverse::ForwardPrediction p = model->PredictLoad(shape, at, d);
    if (!p.ok())
      throw Error(ErrorKind::kRuntime,
                  "calibrating the compliance along the crack: the fitted model failed: " +
                      p.message, {.file = record.source, .field = "--calibrate-compliance"});
    std::vector<std::pair<double, double>> curve;
    for (std::size_t j = 0; j < d.size(); ++j)
      if (p.load[j] > 0.0 && p.crack_length_physical[j] > scene.specimen.notch)
        curve.emplace_back(p.crack_length_physical[j],
                           (d[j] - out.series_compliance * p.load[j]) / p.load[j]);
    std::sort(curve.begin(), curve.end());
    inverse::ComplianceCurve model_curve;
    for (const auto& [crack, compliance] : curve)
      if (model_curve.crack_length.empty() || crack > model_curve.crack_length.back()) {
        model_curve.crack_length.push_back(crack);
        model_curve.compliance.push_back(compliance);
      }
    out.fit = inverse::FitComplianceAlongCrack(model_curve, a, C, {}, record.source);
    // The fixed point x = (ln f, C_s / C_ref) -> g(x), the values this round's
    // compliance fit asks for. The law's refit moves the bridged compliance
    // against them (on the MDF record plain updates overshoot by 0.65-0.75 of
    // their step and oscillate), so the update is Anderson-accelerated (depth
    // one): x+ = g - theta (g - g_prev), theta = F.(F - F_prev) / |F - F_prev|^2
    // with F = g - x.
    const std::array<double, 2> x = {std::log(out.modulus_factor),
                                     out.series_compliance / reference};
    const std::array<double, 2> g = {x[0] - std::log(out.fit.scale),
                                     out.fit.series_compliance / reference};
    const std::array<double, 2> F = {g[0] - x[0], g[1] - x[1]};
    std::array<double, 2> next = g;
    if (round > 0) {
      const double d0 = F[0] - previous_F[0], d1 = F[1] - previous_F[1];
      const double norm = d0 * d0 + d1 * d1;
      if (norm > 0.0) {
        const double theta = (F[0] * d0 + F[1] * d1) / norm;
        for (int k = 0; k < 2; ++k) next[k] = g[k] - theta * (g[k] - previous_g[k]);
      }
    }
    previous_F = F, previous_g = g;
    out.modulus_factor = std::exp(x[0] + std::clamp(next[0] - x[0], -0.2, 0.2));
    out.series_compliance = next[1] * reference;
    out.iterations = round + 1;
    if (std::abs(F[0]) < 1e-3 && std::abs(F[1]) < 1e-3) {
      if (out.series_compliance < -0.01 * reference)
        out.note = fmt::format("compliance along the crack: the series compliance is negative "
                               "({:.3g} mm/N): the model is too compliant at long cracks for a "
                               "spring to explain; check the scene's moduli", 1e3 * out.series_compliance);
      return out;
    }
  }
  out.note = fmt::format("compliance along the crack: not settled after {} rounds (last scale {:.4f})",
                         kMaxRounds, out.fit.scale);
  return out;
}

class FitCommand final : public Command {
 public:
  const char* name() const override { return "fit"; }
  const char* description() const override {
    return "Fit a bridging law (sigma_c, J_B, J_tip,c) to a measured R curve or test record";
  }
  void Register(CLI::App& sub) override {
    sub.add_option("input", input_,
                   "R curve (CSV 'crack_length [mm], R [J/m^2]' or rcurve.h5), or a test record "
                   "(CSV 'load [N], displacement [mm], crack_length [mm]' or record.h5)")
        ->required();
    sub.add_option("--scene", scene_, "Scene TOML: specimen and material")->required();
    sub.add_option("--model", model_,
                   "Forward model: reduced | analytic | mpm | auto (reduced fit, checked by MPM "
                   "and corrected by space mapping when they differ)")
        ->default_val("reduced");
    sub.add_option("--mpm-cell", mpm_cell_, "MPM cell size for --model mpm|auto")
        ->default_val("2.5 mm");
    sub.add_option("--model-tolerance", model_tolerance_,
                   "--model auto: largest relative R difference between the reduced and MPM "
                   "models accepted without correction")
        ->default_val(0.03);
    sub.add_option("--law", law_, "Law family: linear|cubic|triangular|exponential|compare (AICc)")
        ->default_val("linear");
    sub.add_option("--optimizer", optimizer_, "ceres-lm|bobyqa|neldermead|cobyla|direct|crs2")
        ->default_val("bobyqa");
    sub.add_option("--fix", fix_, "Fixed parameters, e.g. 'J_tip_c=2210J/m^2'");
    sub.add_option("--bounds", bounds_, "Bounds, e.g. 'sigma_c=0.05MPa..5MPa,J_B=1J/m^2..5kJ/m^2'");
    sub.add_option("--starts", starts_, "Latin-hypercube starts")->default_val(4);
    r_kind_option_ =
        sub.add_option("--r-kind", r_kind_,
                       "What the data holds: energy | elastic-zone | as-data (record input: the "
                       "model's own record reduced by the data's method); default energy, for a "
                       "record what its reduction gives");
    // A record input is reduced as `bridgefit rcurve RECORD --scene SCENE` would.
    reduction_options_ = {
        sub.add_option(
               "--rcurve-method", reduction_.method,
               "Record input: R-curve method energy|mbt|cc|lefm|equivalent (rcurve --method)")
            ->default_val("energy"),
        sub.add_option(
            "--rcurve-min-increment", reduction_.min_increment,
            "Record input, energy method: smallest crack increment (rcurve --min-increment)"),
        sub.add_option("--rcurve-max-crack-length", reduction_.max_crack_length,
                       "Record input: validity limit (rcurve --max-crack-length)"),
        sub.add_option("--rcurve-smooth", reduction_.smooth_rows,
                       "Record input, energy method: local quadratic fits over 2 N + 1 rows "
                       "(rcurve --smooth; 0: none)")
            ->default_val(0),
        sub.add_option(
            "--rcurve-load-noise", reduction_.load_noise,
            "Record input: load noise, 1 sigma (rcurve --load-noise; default estimated)"),
        sub.add_option("--rcurve-displacement-noise", reduction_.displacement_noise,
                       "Record input: displacement noise, 1 sigma (rcurve --displacement-noise)"),
        sub.add_option("--rcurve-crack-noise", reduction_.crack_noise,
                       "Record input: crack-length noise, 1 sigma (rcurve --crack-noise)"),
        sub.add_option("--columns", reduction_.columns,
                       "Record input: column mapping, e.g. load=Force,crack_length=CrackExt"),
        sub.add_option("--units", reduction_.units,
                       "Record input: unit mapping, e.g. displacement=mm,load=N")};
    sub.add_option("--fit-to", fit_to_,
                   "What the model is fitted to: r-curve (the R curve, or a record's reduction) | "
                   "load-displacement (a record's load at each displacement; started from the "
                   "R-curve fit; docs/FIT.md)")
        ->default_val("r-curve");
    sub.add_flag("--calibrate-compliance{initial}", calibrate_compliance_,
                 "--fit-to load-displacement: calibrate the model's compliance to the record's, "
                 "for real records whose E or machine compliance is not known (docs/FIT.md). "
                 "'initial' (the flag alone): the scene's moduli scaled to the initial slope, "
                 "refined on the whole record; '=crack': a modulus scale and a series compliance "
                 "fitted to the record's compliance at its measured crack lengths, alternated "
                 "with the law's fit")
        ->check(CLI::IsMember({"initial", "crack"}));
    sub.add_option("--resolution", resolution_, "Reduced model element size, e.g. '0.5 mm'");
    sub.add_flag("--no-profile", no_profile_, "Skip the profile likelihood (faster)");
    sub.add_option("--out", out_h5_, "Write the fit to this HDF5 file");
    sub.add_option("--report", report_dir_, "Also write an HTML report into this folder");
  }

  int Run(const CommonOptions& common) override {
    const Scene scene = io::ReadSceneFile(scene_);
    for (const CLI::Option* option : reduction_options_)
      if (option->count() > 0) reduction_.any_given = true;
    const FitInput input = ReadFitInput(input_, scene, reduction_);
    const RCurve& curve = input.curve;
    // Like with like: a record's reduction says what its R is.
    // --r-kind as-data (record input): the model's own record is reduced by
    // the data's method (calibrations, equivalent crack lengths); docs/FIT.md
    // says how sensitive that is to the model's compliance.
    const std::string r_kind = r_kind_option_->count() > 0 ? r_kind_
                               : input.from_record         ? curve.r_kind
                                                           : std::string("energy");
    if (r_kind == "as-data" && !input.from_record)
      throw Error(ErrorKind::kUsage, "--r-kind as-data needs a record input (reduced here)",
                  {.field = "--r-kind", .value = r_kind,
                   .expected = "energy or elastic-zone for an R-curve input"});
    const inverse::RKind kind = inverse::ParseRKind(r_kind);
    const std::string reduction_text =
        input.from_record
            ? fmt::format("{} method, reduced in-process from the record", curve.method)
            : fmt::format("R curve read from the input ({})", curve.method);
    const inverse::FitData data = inverse::FitData::FromRCurve(curve, kind);
    // --fit-to load-displacement: the record's rows, weighted by its noise
    // (given, or estimated by the reduction).
    const inverse::FitTarget target = inverse::ParseFitTarget(fit_to_);
    const bool calibrate = !calibrate_compliance_.empty();
    const bool calibrate_along_crack = calibrate_compliance_ == "crack";
    if (calibrate && target != inverse::FitTarget::kLoad)
      throw Error(ErrorKind::kUsage, "compliance calibration is for a load-displacement fit",
                  {.field = "--calibrate-compliance", .value = calibrate_compliance_,
                   .expected = "together with --fit-to load-displacement"});
    if (calibrate_along_crack && !(input.record && input.record->has_crack_length()))
      throw Error(ErrorKind::kUsage, "calibrating the compliance along the crack needs measured "
                  "crack lengths in the record",
                  {.file = input_, .field = "--calibrate-compliance", .value = calibrate_compliance_,
                   .expected = "a record with a crack_length column (or use the flag alone: "
                               "the initial slope)"});
    if (calibrate_along_crack && model_ != "reduced")
      throw Error(ErrorKind::kUsage, "calibrating the compliance along the crack runs the reduced model",
                  {.field = "--model", .value = model_, .expected = "reduced"});
    std::optional<inverse::FitData> load_data;
    if (target == inverse::FitTarget::kLoad) {
      if (!input.record)
        throw Error(ErrorKind::kUsage, "a load-displacement fit needs the test record",
                    {.file = input_, .field = "--fit-to", .value = fit_to_,
                     .expected = "a record as input (CSV with load and displacement columns, or "
                                 "an HDF5 with /experiment)"});
      const double load_noise = input.reduction ? input.reduction->load_noise
                                                : experiment::RobustNoiseSigma(input.record->load);
      const double displacement_noise =
          input.reduction ? input.reduction->displacement_noise
                          : experiment::RobustNoiseSigma(input.record->displacement);
      load_data = inverse::FitData::FromRecord(*input.record, load_noise, displacement_noise);
    }
    const inverse::FitData& fit_data = load_data ? *load_data : data;

    // The law family, or "compare": every family, ranked by AICc.
    const bool compare = law_ == "compare";
    laws::LawShape shape;
    if (!compare) {
      const laws::LawFamily family = [&] {
        try {
          return laws::ParseLawFamily(law_);
        } catch (const Error& e) {
          throw Error(ErrorKind::kUsage, e.message(),
                      {.field = "--law", .value = law_, .expected = e.context().expected + " or compare"});
        }
      }();
      switch (family) {
        case laws::LawFamily::kLinear: shape = laws::MakeLinearShape(); break;
        case laws::LawFamily::kCubic: shape = laws::MakeCubicShape(); break;
        case laws::LawFamily::kTriangular: shape = laws::MakeTriangularShape(0.1); break;
        case laws::LawFamily::kExponential: shape = laws::MakeExponentialShape(3.0); break;
        default:
          if (scene.bridging && scene.bridging->shape.family == family) {
            shape = scene.bridging->shape;  // trilinear/table shape from the scene
          } else {
            throw Error(ErrorKind::kUsage, "this law family needs its shape from the scene",
                        {.field = "--law", .value = law_,
                         .expected = "a scene whose [bridging] has this law"});
          }
      }
    }

    inverse::FitOptions options;
    options.optimizer = inverse::ParseOptimizer(optimizer_);
    options.starts = starts_;
    options.profile_likelihood = !no_profile_;
    options.progress = !common.quiet;
    for (const auto& [key, value] : SplitAssignments(fix_, "--fix")) {
      const int index = ParameterIndex(key, "--fix");
      options.fixed[index] = true;
      options.fixed_value[index] = ParseOptionQuantity(value, ParameterDimension(index), "--fix");
    }
    for (const auto& [key, value] : SplitAssignments(bounds_, "--bounds")) {
      const int index = ParameterIndex(key, "--bounds");
      const size_t dots = value.find("..");
      if (dots == std::string::npos)
        throw Error(ErrorKind::kUsage, "malformed bounds",
                    {.field = "--bounds", .value = value, .expected = "low..high"});
      options.lower[index] =
          ParseOptionQuantity(value.substr(0, dots), ParameterDimension(index), "--bounds");
      options.upper[index] =
          ParseOptionQuantity(value.substr(dots + 2), ParameterDimension(index), "--bounds");
    }
    std::string why;
    if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid fit options: " + why);

    // The forward model: the cheapest that is accurate enough (README).
    std::unique_ptr<inverse::ForwardModel> model;
    std::unique_ptr<inverse::ForwardModel> mpm_model;  // --model auto: the check
    double mpm_cell_m = NAN;
    std::string model_note;
    const double plane_factor =
        scene.specimen.plane == PlaneCondition::kPlaneStrain && !scene.material.orthotropic
            ? 1.0 - scene.material.nu * scene.material.nu
            : 1.0;
    const double effective_modulus = scene.material.AxialModulus() / plane_factor;
    // A compliance in series with the specimen (--calibrate-compliance=crack).
    double series_compliance = 0.0;
    // Builds the forward models on `model_scene` (the scene, or with its
    // moduli scaled to the record's compliance), with `series_compliance`.
    auto build_models = [&](const Scene& model_scene) {
      if (model_ == "analytic") {
        model = std::make_unique<inverse::AnalyticForwardModel>(effective_modulus,
                                                                model_scene.specimen.notch);
      } else if (model_ == "reduced" || model_ == "auto" || model_ == "mpm") {
        // The models must grow past the data: its crack lengths, and for a
        // record the measured ones (an equivalent crack length trails them).
        double data_end = *std::max_element(data.crack_length.begin(), data.crack_length.end());
        if (input.record && input.record->has_crack_length())
          for (double a : input.record->crack_length)
            if (std::isfinite(a)) data_end = std::max(data_end, a);
        // A load-displacement fit follows the model to the record's last
        // displacement, which a tougher trial law reaches with a shorter crack
        // and a weaker one with a longer crack: a tenth of the growth beyond.
        if (load_data) data_end += 0.1 * std::max(data_end - model_scene.specimen.notch, 0.0);
        models::ReducedOptions reduced;
        if (!resolution_.empty())
          reduced.mesh.resolution = ParseOptionQuantity(resolution_, Dimension::Length(), "--resolution");
        reduced.mesh.max_crack_length = std::max(
            data_end + 2e-3, model_scene.run.max_crack_length.value_or(0.0));
        if (model_ != "mpm") {
          auto simulation = inverse::MakeReducedForwardModel(model_scene, reduced);
          if (kind == inverse::RKind::kAsData) simulation->SetReducer(ModelRecordReducer(input));
          simulation->SetSeriesCompliance(series_compliance);
          model = std::move(simulation);
        }
        if (model_ == "mpm" || model_ == "auto") {
          mpm::GrowthOptions growth;
          growth.cell = ParseOptionQuantity(mpm_cell_, Dimension::Length(), "--mpm-cell");
          growth.max_crack_length = data_end + 2.0 * growth.cell;
          std::string why;
          if (!growth.IsValid(&why))
            throw Error(ErrorKind::kUsage, "invalid MPM options: " + why, {.field = "--mpm-cell"});
          auto accurate = std::make_unique<inverse::SimulationForwardModel>(
              "mpm", [model_scene, growth](const laws::BridgingLaw* law, double J_tip_c) {
                return mpm::SimulateGrowth(model_scene, law, J_tip_c, growth).result;
              });
          if (kind == inverse::RKind::kAsData) accurate->SetReducer(ModelRecordReducer(input));
          accurate->SetSeriesCompliance(series_compliance);
          if (model_ == "mpm") model = std::move(accurate);
          else mpm_model = std::move(accurate);
          mpm_cell_m = growth.cell;
        }
      } else {
        throw Error(ErrorKind::kUsage, "unknown model",
                    {.field = "--model", .value = model_,
                     .expected = "reduced, analytic, mpm or auto"});
      }
    };
    build_models(scene);
    // --calibrate-compliance: the model's moduli are scaled so that its
    // compliance at a0 is the record's initial one (all moduli by one factor
    // scale an elastic model's compliance exactly), then (reduced model) the
    // factor is refined on the whole record below. For real records, whose E
    // or machine compliance is known to percents while a load-displacement
    // fit reads sigma_c from ~0.1% of the load (docs/FIT.md).
    double modulus_factor = NAN, model_compliance = NAN;
    if (calibrate && model_ != "analytic" && std::isfinite(input.initial_compliance)) {
      const double d_probe = 1e-3 * input.initial_compliance;  // on the linear branch
      const inverse::ForwardPrediction probe =
          model->PredictLoad(laws::MakeLinearShape(), {.sigma_c = 1e6, .J_B = 0.0, .J_tip_c = 1000.0},
                             {d_probe});
      if (!probe.ok() || probe.load.empty() || !(probe.load[0] > 0.0))
        throw Error(ErrorKind::kRuntime, "the model's initial compliance could not be computed: " +
                                             probe.message, {.file = scene_});
      model_compliance = d_probe / probe.load[0];
      modulus_factor = model_compliance / input.initial_compliance;
      build_models(ScaledModuli(scene, modulus_factor));
    }
    inverse::ModelCheckOptions check;
    check.tolerance = model_tolerance_;
    if (std::string why; !check.IsValid(&why))
      throw Error(ErrorKind::kUsage, why, {.field = "--model-tolerance",
                                           .value = fmt::format("{:g}", model_tolerance_),
                                           .expected = "a fraction in (0, 1), e.g. 0.03"});
    inverse::ModelCheckResult model_check;

    std::vector<inverse::LawComparison> comparison;
    FitSummary s;
    const std::vector<laws::LawShape> families = {
        laws::MakeLinearShape(), laws::MakeCubicShape(), laws::MakeTriangularShape(0.1),
        laws::MakeExponentialShape(3.0)};
    const laws::LawShape* used_shape = &shape;
    // A load-displacement fit starts where the R-curve fit (of the one law,
    // or the linear one when comparing) ends: quick, without profiles.
    const laws::LawShape& start_shape = compare ? families[0] : shape;
    std::optional<FitSummary> start_fit;
    if (load_data) {
      inverse::FitOptions first = options;
      first.profile_likelihood = false;
      first.progress = false;
      start_fit = inverse::FitBridgingLaw(*model, start_shape, data, first);
      if (start_fit->bridging_detected) {
        for (int i = 0; i < inverse::kParameterCount; ++i)
          if (std::isfinite(start_fit->best_parameters[i]))
            options.initial[i] = start_fit->best_parameters[i];
      } else if (std::isfinite(start_fit->J_tip_c.value)) {
        // A flat R curve: its J_tip,c, a little bridging, sigma_c scanned.
        options.initial[inverse::kJTipC] = start_fit->J_tip_c.value;
        options.initial[inverse::kJB] = 0.05 * start_fit->J_tip_c.value;
      }
    }
    // The initial slope of a record gives its compliance to about 1% (a few
    // noisy loading rows); the whole record holds it to about 0.1%: the
    // modulus factor minimising the load-displacement chi^2 (each with the
    // law re-fitted, no profiles) by golden section within +-4% of the
    // initial-slope value, then the fit below runs at that factor.
    double initial_slope_factor = NAN, refinement_s = 0.0;
    int factor_fits = 0, refinement_evaluations = 0;
    std::optional<AlongCrackCalibration> along_crack;
    if (calibrate_along_crack) {
      initial_slope_factor = modulus_factor;
      const AlongCrackCalibration& c = along_crack.emplace(CalibrateAlongCrack(
          *input.record, scene, start_shape, *load_data, options,
          std::isfinite(modulus_factor) ? modulus_factor : 1.0, [&](double factor, double series) {
            series_compliance = series;
            build_models(ScaledModuli(scene, factor));
            return model.get();
          }));
      modulus_factor = c.modulus_factor;
      series_compliance = c.series_compliance;
      factor_fits = c.fits;
      refinement_s = c.wall_s;
      refinement_evaluations = c.evaluations;
      if (!c.note.empty()) model_note = c.note;
      build_models(ScaledModuli(scene, modulus_factor));
    } else if (std::isfinite(modulus_factor) && model_ == "reduced") {
      initial_slope_factor = modulus_factor;
      inverse::FitOptions quick = options;
      quick.profile_likelihood = false;
      quick.starts = 1;
      quick.progress = false;
      auto chi2_at = [&](double factor) {
        build_models(ScaledModuli(scene, factor));
        ++factor_fits;
        const FitSummary q = inverse::FitBridgingLaw(*model, start_shape, *load_data, quick);
        refinement_s += q.wall_s;
        refinement_evaluations += q.evaluations;
        return q.converged ? q.chi2 : INFINITY;
      };
      constexpr double kGolden = 0.6180339887498949;
      double lo = std::log(0.96 * initial_slope_factor), hi = std::log(1.04 * initial_slope_factor);
      double x1 = hi - kGolden * (hi - lo), x2 = lo + kGolden * (hi - lo);
      double f1 = chi2_at(std::exp(x1)), f2 = chi2_at(std::exp(x2));
      while (hi - lo > 2e-4) {  // the factor to 0.01%
        if (f1 <= f2) {
          hi = x2, x2 = x1, f2 = f1;
          x1 = hi - kGolden * (hi - lo);
          f1 = chi2_at(std::exp(x1));
        } else {
          lo = x1, x1 = x2, f1 = f2;
          x2 = lo + kGolden * (hi - lo);
          f2 = chi2_at(std::exp(x2));
        }
      }
      modulus_factor = std::exp(0.5 * (lo + hi));
      if (std::abs(std::log(modulus_factor / initial_slope_factor)) > 0.039)
        model_note = "compliance: the refined modulus factor is at the edge of +-4% of the "
                     "initial slope's: check the record's first rows";
      build_models(ScaledModuli(scene, modulus_factor));
    }
    if (compare) {
      comparison = inverse::CompareLawFamilies(*model, families, fit_data, options);
      const auto best = std::min_element(
          comparison.begin(), comparison.end(), [](const auto& a, const auto& b) {
            return !std::isnan(a.aicc) && (std::isnan(b.aicc) || a.aicc < b.aicc);
          });
      s = best->summary;
      // The family AICc preferred (comparison follows families).
      used_shape = &families[best - comparison.begin()];
      if (mpm_model)
        s = inverse::FitWithModelCheck(*model, *mpm_model, *used_shape, fit_data, options, check,
                                       &model_check);
    } else if (mpm_model) {
      s = inverse::FitWithModelCheck(*model, *mpm_model, shape, fit_data, options, check,
                                     &model_check);
    } else {
      s = inverse::FitBridgingLaw(*model, shape, fit_data, options);
    }
    // A load-displacement fit's R curve: the model's R (of the data's kind)
    // at the R curve's crack lengths, for the report and the R residual.
    std::vector<double> load_fit_R;
    double load_fit_R_rms = NAN;
    if (start_fit) {
      s.evaluations += start_fit->evaluations + refinement_evaluations;
      s.failed_evaluations += start_fit->failed_evaluations;
      s.wall_s += start_fit->wall_s + refinement_s;
      const inverse::LawParameters at = FittedLaw(s);
      if (std::isfinite(at.sigma_c) && std::isfinite(at.J_tip_c)) {
        const inverse::ForwardPrediction p =
            model->Predict(*used_shape, at, data.crack_length, data.kind);
        if (p.ok() && p.R.size() == data.R.size()) {
          load_fit_R = p.R;
          double sum = 0.0;
          for (std::size_t i = 0; i < p.R.size(); ++i) sum += std::pow(p.R[i] - data.R[i], 2);
          load_fit_R_rms = std::sqrt(sum / p.R.size());
        }
      }
    }
    if (mpm_model) model_note = "auto: " + model_check.outcome;

    // The report reads the fit file: without --out it goes to a temporary file.
    const std::string fit_file =
        !out_h5_.empty() ? out_h5_
        : report_dir_.empty()
            ? std::string()
            : (std::filesystem::temp_directory_path() /
               ("bridgefit-fit-" + std::to_string(::getpid()) + ".h5")).string();
    if (!fit_file.empty()) {
      io::H5Writer file(fit_file);
      if (input.reduction) {
        WriteReductionH5(file, *input.record, *input.reduction, input.reduction_options, scene_);
      } else {
        WriteRecordH5(file, curve, "/rcurve");
        if (input.record) WriteRecordH5(file, *input.record, "/experiment");
      }
      const std::string g = "/fit";
      file.WriteAttribute(g, "kind", "fit");
      file.WriteAttribute(g, "scene", scene_);
      file.WriteAttribute(g, "input", input_);
      file.WriteAttribute(g, "input_kind", input.from_record ? "record" : "rcurve");
      file.WriteAttribute(g, "rcurve_method", curve.method);
      file.WriteAttribute(g, "data_reduction", reduction_text);
      file.WriteAttribute(g, "model", s.model);
      file.WriteAttribute(g, "optimizer", s.optimizer);
      file.WriteAttribute(g, "law", s.law);
      file.WriteAttribute(g, "r_kind", inverse::RKindName(kind));
      file.WriteAttribute(g, "verdict", s.verdict);
      file.WriteAttribute(g, "stop_reason", s.stop_reason);
      file.WriteAttribute(g, "evaluations", s.evaluations);
      file.WriteAttribute(g, "failed_evaluations", s.failed_evaluations);
      file.WriteAttribute(g, "wall_s", s.wall_s);
      file.WriteAttribute(g, "converged", s.converged ? 1.0 : 0.0);
      file.WriteAttribute(g, "steady_state_reached", s.steady_state_reached ? 1.0 : 0.0);
      file.WriteAttribute(g, "bridging_detected", s.bridging_detected ? 1.0 : 0.0);
      file.WriteAttribute(g, "reduced_chi2", s.reduced_chi2);
      file.WriteAttribute(g, "fit_to", inverse::FitTargetName(s.target));
      if (std::isfinite(modulus_factor)) {
        file.WriteAttribute(g, "modulus_factor", modulus_factor);
        file.WriteAttribute(g, "modulus_factor_initial_slope", initial_slope_factor);
        file.WriteAttribute(g, "model_initial_compliance_m_per_N", model_compliance);
        file.WriteAttribute(g, "record_initial_compliance_m_per_N", input.initial_compliance);
        file.WriteAttribute(g, "compliance_calibration", calibrate_compliance_);
        file.WriteAttribute(g, "series_compliance_m_per_N", series_compliance);
        if (along_crack) {
          file.WriteAttribute(g, "compliance_rms_relative", along_crack->fit.rms_relative);
          file.WriteAttribute(g, "compliance_rows", along_crack->fit.rows);
          file.WriteAttribute(g, "compliance_rounds", along_crack->iterations);
        }
      }
      file.WriteVector(g + "/crack_length", data.crack_length, "m", "data crack length");
      file.WriteVector(g + "/R", data.R, "J/m^2", "data R");
      if (load_data) {
        // The R curve shown with a load-displacement fit: the model's R at
        // the data's crack lengths; the fit itself under /fit/load_displacement.
        file.WriteAttribute(g, "rms_residual_J_per_m2", load_fit_R_rms);
        file.WriteAttribute(g, "rms_residual_N", s.rms_residual);
        if (!load_fit_R.empty()) {
          file.WriteVector(g + "/fitted_crack_length", data.crack_length, "m", "data crack length");
          file.WriteVector(g + "/fitted_R", load_fit_R, "J/m^2", "model R at the fitted parameters");
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
        file.WriteVector(g + "/fitted_crack_length", s.fitted_crack_length, "m", "points used");
        if (!s.fitted_R.empty()) file.WriteVector(g + "/fitted_R", s.fitted_R, "J/m^2", "model R");
      }
      if (!s.fitted_delta_root.empty())
        file.WriteVector(g + "/fitted_delta_root", s.fitted_delta_root, "m", "model notch-root COD");
      WriteEstimate(file, g + "/parameters/sigma_c", s.sigma_c, "Pa");
      WriteEstimate(file, g + "/parameters/J_B", s.J_B, "J/m^2");
      WriteEstimate(file, g + "/parameters/delta_c", s.delta_c, "m");
      WriteEstimate(file, g + "/parameters/J_tip_c", s.J_tip_c, "J/m^2");
      if (mpm_model) {
        const std::string mc = g + "/model_check";
        file.WriteAttribute(mc, "outcome", model_check.outcome);
        file.WriteAttribute(mc, "cheap_model", model_check.cheap_model);
        file.WriteAttribute(mc, "accurate_model", model_check.accurate_model);
        file.WriteAttribute(mc, "mpm_cell_m", mpm_cell_m);
        file.WriteAttribute(mc, "tolerance", check.tolerance);
        file.WriteAttribute(mc, "corrected", model_check.corrected ? 1.0 : 0.0);
        file.WriteAttribute(mc, "corrections", static_cast<double>(model_check.corrections));
        file.WriteAttribute(mc, "accurate_runs", static_cast<double>(model_check.accurate_runs));
        file.WriteAttribute(mc, "cheap_fit_s", model_check.cheap_fit_s);
        file.WriteAttribute(mc, "accurate_s", model_check.accurate_s);
        file.WriteAttribute(mc, "correction_fit_s", model_check.correction_fit_s);
        file.WriteAttribute(mc, "discrepancy_at_cheap_optimum",
                            model_check.discrepancy_at_cheap_optimum);
        file.WriteAttribute(mc, "discrepancy_final", model_check.discrepancy_final);
        if (!model_check.crack_length.empty()) {
          file.WriteVector(mc + "/crack_length", model_check.crack_length, "m", "data crack length");
          file.WriteVector(mc + "/R_cheap", model_check.R_cheap, "J/m^2", "reduced model R");
          file.WriteVector(mc + "/R_accurate", model_check.R_accurate, "J/m^2", "MPM R");
        }
      }
      for (const inverse::Profile& p : s.profiles) {
        std::vector<double> values, chi2;
        for (const auto& point : p.points) {
          if (!point.ok) continue;
          values.push_back(point.value);
          chi2.push_back(point.chi2);
        }
        const std::string name = inverse::ParameterName(p.parameter);
        const std::string pg = g + "/profiles/" + name;
        file.WriteVector(pg + "/value", values, p.parameter == inverse::kSigmaC ? "Pa" : "J/m^2");
        file.WriteVector(pg + "/chi2", chi2, "1", "best chi^2 with the others re-optimized");
        file.WriteAttribute(pg, "chi2_threshold", p.chi2_threshold);
        file.WriteAttribute(pg, "flat", p.flat ? 1.0 : 0.0);
      }
      file.Commit();
    }
    if (!report_dir_.empty()) {
      report::ReportOptions report_options;
      report_options.title = "bridgefit fit: " + input_;
      try {
        const report::ReportSummary written = report::WriteFitReport(fit_file, report_dir_, report_options);
        if (out_h5_.empty()) std::filesystem::remove(fit_file);
        if (!common.quiet) std::cerr << "report: " << written.index_html.string() << "\n";
      } catch (...) {
        if (out_h5_.empty()) std::filesystem::remove(fit_file);
        throw;
      }
    }

    if (common.json) {
      nlohmann::json out;
      out["model"] = s.model;
      out["model_note"] = model_note;
      if (mpm_model) {
        out["model_check"] = {
            {"outcome", model_check.outcome},
            {"cheap_model", model_check.cheap_model},
            {"accurate_model", model_check.accurate_model},
            {"mpm_cell_m", mpm_cell_m},
            {"tolerance", check.tolerance},
            {"accurate_ok", model_check.accurate_ok},
            {"corrected", model_check.corrected},
            {"corrections", model_check.corrections},
            {"accurate_runs", model_check.accurate_runs},
            {"cheap_fit_s", model_check.cheap_fit_s},
            {"accurate_s", model_check.accurate_s},
            {"correction_fit_s", model_check.correction_fit_s},
            {"discrepancy_at_cheap_optimum", NumberOrNull(model_check.discrepancy_at_cheap_optimum)},
            {"discrepancy_final", NumberOrNull(model_check.discrepancy_final)}};
      }
      out["optimizer"] = s.optimizer;
      out["law"] = s.law;
      out["r_kind"] = inverse::RKindName(kind);
      nlohmann::json data_json = {{"path", input_},
                                  {"kind", input.from_record ? "record" : "rcurve"},
                                  {"rcurve_method", curve.method},
                                  {"reduced_in_process", input.from_record},
                                  {"reduction", reduction_text},
                                  {"rcurve_points", curve.size()}};
      if (input.reduction) {
        const experiment::RCurveResult& r = *input.reduction;
        int dropped = 0;
        for (const auto& item : DroppedRowList(*input.record, r)) dropped += item.second;
        data_json["record_rows"] = input.record->size();
        data_json["points_dropped_total"] = dropped;
        data_json["min_crack_increment_m"] = input.reduction_options.min_crack_increment;
        data_json["max_crack_length_m"] = NumberOrNull(input.reduction_options.max_crack_length);
        data_json["notes"] = r.notes;
        data_json["reduction_wall_s"] = r.wall_s;
      }
      out["data"] = std::move(data_json);
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
      out["rms_residual_J_per_m2"] = NumberOrNull(load_data ? load_fit_R_rms : s.rms_residual);
      if (load_data) {
        out["rms_residual_N"] = NumberOrNull(s.rms_residual);
        out["start_from_r_curve_fit"] = {
            {"sigma_c_Pa", NumberOrNull(start_fit->best_parameters[inverse::kSigmaC])},
            {"J_B_J_per_m2", NumberOrNull(start_fit->best_parameters[inverse::kJB])},
            {"J_tip_c_J_per_m2", NumberOrNull(start_fit->best_parameters[inverse::kJTipC])},
            {"evaluations", start_fit->evaluations},
            {"wall_s", start_fit->wall_s}};
        out["load_noise_N"] = NumberOrNull(
            input.reduction ? input.reduction->load_noise : NAN);
        out["compliance_calibration"] =
            std::isfinite(modulus_factor)
                ? nlohmann::json{{"mode", calibrate_compliance_},
                                 {"modulus_factor", modulus_factor},
                                 {"series_compliance_m_per_N", series_compliance},
                                 {"along_crack",
                                  along_crack
                                      ? nlohmann::json{{"rms_relative", along_crack->fit.rms_relative},
                                                       {"rows", along_crack->fit.rows},
                                                       {"crack_min_m", along_crack->fit.crack_min},
                                                       {"crack_max_m", along_crack->fit.crack_max},
                                                       {"rounds", along_crack->iterations}}
                                      : nlohmann::json()},
                                 {"modulus_factor_initial_slope", NumberOrNull(initial_slope_factor)},
                                 {"refinement_fits", factor_fits},
                                 {"refinement_wall_s", refinement_s},
                                 {"model_initial_compliance_m_per_N", model_compliance},
                                 {"record_initial_compliance_m_per_N", input.initial_compliance}}
                : nlohmann::json();
      }
      out["data_points"] = s.data_points;
      out["reduced_chi2"] = NumberOrNull(s.reduced_chi2);
      out["sigma_c_Pa"] = EstimateJson(s.sigma_c);
      out["J_B_J_per_m2"] = EstimateJson(s.J_B);
      out["delta_c_m"] = EstimateJson(s.delta_c);
      out["J_tip_c_J_per_m2"] = EstimateJson(s.J_tip_c);
      nlohmann::json starts = nlohmann::json::array();
      for (const inverse::StartResult& start : s.starts)
        starts.push_back({{"start", start.start}, {"end", start.end}, {"chi2", NumberOrNull(start.cost)},
                          {"evaluations", start.evaluations}, {"stop_reason", start.stop_reason}});
      out["starts"] = std::move(starts);
      nlohmann::json outliers = nlohmann::json::array();
      for (size_t i = 0; i < s.outlier_R.size(); ++i)
        outliers.push_back(load_data ? nlohmann::json{{"displacement_m", s.outlier_crack_lengths[i]},
                                                      {"load_N", s.outlier_R[i]}}
                                     : nlohmann::json{{"crack_length_m", s.outlier_crack_lengths[i]},
                                                      {"R_J_per_m2", s.outlier_R[i]}});
      out["outliers_removed"] = std::move(outliers);
      nlohmann::json families = nlohmann::json::array();
      for (const auto& c : comparison)
        families.push_back({{"law", c.law}, {"aicc", NumberOrNull(c.aicc)},
                            {"delta_aicc", NumberOrNull(c.delta_aicc)},
                            {"chi2", NumberOrNull(c.summary.chi2)},
                            {"converged", c.summary.converged}});
      out["law_comparison"] = std::move(families);
      out["parameter_order"] = {"sigma_c_Pa", "J_B_J_per_m2", "J_tip_c_J_per_m2"};
      PrintJson(out);
    } else {
      if (!comparison.empty()) {
        std::cout << "law families by AICc (smaller is better):\n";
        for (const auto& c : comparison)
          std::cout << fmt::format("  {:<12} AICc {:10.2f}  delta {:7.2f}  chi2 {:10.2f}{}\n", c.law,
                                   c.aicc, c.delta_aicc, c.summary.chi2,
                                   c.summary.converged ? "" : "  (not converged)");
      }
      std::cout << "data: " << input_ << ": " << reduction_text << ", " << curve.size()
                << " R points";
      if (load_data)
        std::cout << fmt::format("; fitted to the record's {} load-displacement rows (started "
                                 "from the R-curve fit, {:.2f} s); R rms {:.4g} J/m^2",
                                 load_data->size(), start_fit->wall_s, load_fit_R_rms);
      std::cout << "\n";
      if (along_crack)
        std::cout << fmt::format(
            "compliance: the scene's moduli x {:.4f} and {:.4g} mm/N in series (initial slope: x "
            "{:.4f}); {} rounds of {} fits; {}\n",
            modulus_factor, 1e3 * series_compliance, initial_slope_factor,
            along_crack->iterations, factor_fits, along_crack->fit.Summary());
      else if (std::isfinite(modulus_factor))
        std::cout << fmt::format(
            "compliance: the scene's moduli x {:.4f} (initial slope: x {:.4f}, model {:.4g} m/N "
            "at a0, record {:.4g} m/N; refined on the record in {} fits)\n",
            modulus_factor, initial_slope_factor, model_compliance, input.initial_compliance,
            factor_fits);
      std::cout << s.BriefReport();
      if (!model_note.empty()) std::cout << "  " << model_note << "\n";
      if (!out_h5_.empty()) std::cout << "  written: " << out_h5_ << "\n";
    }
    return s.converged ? 0 : 1;
  }

 private:
  std::string input_, scene_, model_, law_, optimizer_, fix_, bounds_, r_kind_, resolution_,
      out_h5_, report_dir_, mpm_cell_ = "2.5 mm", fit_to_ = "r-curve";
  double model_tolerance_ = 0.03;
  int starts_ = 4;
  bool no_profile_ = false;
  std::string calibrate_compliance_;  // "", "initial" or "crack"
  ReductionFlags reduction_;
  std::vector<CLI::Option*> reduction_options_;
  CLI::Option* r_kind_option_ = nullptr;
};

}  // namespace

std::unique_ptr<Command> MakeFitCommand() { return std::make_unique<FitCommand>(); }

}  // namespace bridgefit::cli
