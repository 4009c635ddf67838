// The fit's input: told apart by content, read, and a record reduced to an R
// curve with the same library call and defaults as `bridgefit rcurve RECORD
// --scene SCENE --method M` (docs/FIT.md).

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/pipeline/fit.hpp"
#include "bridgefit/pipeline/rcurve_file.hpp"

namespace bridgefit::pipeline {
namespace {

// Which an input holds, by its content: a CSV with `crack_length` and `R`
// columns, or an HDF5 with /rcurve, is an R curve; a CSV with load and
// displacement columns, or an HDF5 with only /experiment, is a record.
bool InputIsRecord(const std::string& path, const std::string& column_mapping) {
  if (IsHdf5Path(path)) {
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
  if (!column_mapping.empty()) io::ApplyColumnMapping(column_mapping, columns);
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

// An R-curve input: the curve, and from an rcurve.h5 the record behind it
// and its initial compliance.
void ReadRCurveInput(const FitRequest& request, FitInput& input) {
  if (request.reduction_given)
    throw Error(ErrorKind::kUsage, "the R-curve reduction options apply to a record only",
                {.file = request.input_path,
                 .field = "--rcurve-method, --rcurve-min-increment, --rcurve-max-crack-length, "
                          "--rcurve-smooth, --rcurve-*-noise, --columns, --units",
                 .expected = "a load-displacement record as input, or none of these options"});
  if (request.frame_crack_lengths)
    throw Error(ErrorKind::kUsage, "crack lengths from image frames apply to a record only",
                {.file = request.input_path.empty() ? "(in memory)" : request.input_path,
                 .field = "crack lengths from " + request.frame_crack_lengths->source,
                 .expected = "a load-displacement record with an image column as input"});
  if (request.input_path.empty()) {
    input.curve = *request.rcurve;
    input.record = request.record;
    input.initial_compliance = request.record_initial_compliance;
    return;
  }
  const std::string& path = request.input_path;
  input.curve = ReadRCurveFile(path);
  RCurveFileRecord behind = ReadRCurveFileRecord(path);
  input.record = std::move(behind.record);
  input.initial_compliance = behind.initial_compliance;
  input.dropped_rows = std::move(behind.dropped_rows);
  input.reduction_warnings = std::move(behind.reduction_warnings);
}

// Only the compliance-based reductions infer the crack length (CT lefm and
// equivalent: docs/RCURVE_METHODS.md); the others need it measured.
bool MethodNeedsCrackLength(experiment::RMethod method, SpecimenType specimen) {
  return method != experiment::RMethod::kEquivalentCrack &&
         !(method == experiment::RMethod::kLefm && specimen == SpecimenType::kCT);
}

// ---- issue 15: the in-process R curve names itself and falls back ----
// A fit needs at least four R values. The energy method on a visually
// tracked crack may give fewer (or none); a load-displacement fit only uses
// the R curve for its start, so it starts from the point-wise method of the
// specimen instead (DCB: mbt; CT: lefm, with the compliance's crack length
// when there are no readings) and says so. Any other failure names the file,
// the stage (the in-process R curve) and the way out.
constexpr std::size_t kFitMinPoints = 4;

experiment::RMethod FallbackMethod(SpecimenType type) {
  return type == SpecimenType::kDCB ? experiment::RMethod::kMbt : experiment::RMethod::kLefm;
}

// The way out for too few energy increments, by what set the increment
// (experiment::EnergyIncrementLimitOf, the one rule); empty for another
// method or a smoothed run.
std::string IncrementWayOut(const experiment::RCurveOptions& options,
                            const experiment::RCurveResult& result) {
  if (options.method != experiment::RMethod::kEnergy) return {};
  const auto used = result.figures.find("energy_min_increment_m");
  switch (experiment::EnergyIncrementLimitOf(options,
                                             used == result.figures.end() ? 0.0 : used->second)) {
    case experiment::EnergyIncrementLimit::kAsked:
      return "a smaller --rcurve-min-increment";
    case experiment::EnergyIncrementLimit::kScatter:
      return "--rcurve-smooth N (the crack readings' scatter sets the increment, which a smaller "
             "--rcurve-min-increment cannot lower; local fits over 2 N + 1 rows do)";
    case experiment::EnergyIncrementLimit::kSmoothed:
      break;
  }
  return {};
}

std::string WayOut(SpecimenType type, const std::string& increment) {
  const std::string method = type == SpecimenType::kDCB ? "--rcurve-method mbt (or cc)"
                                                        : "--rcurve-method lefm (or equivalent)";
  return method + ", " + (increment.empty() ? "" : increment + ", ") +
         "or --fit-to load-displacement";
}

experiment::RCurveResult ReduceInProcess(const FitRequest& request, const FitInput& input,
                                         experiment::RCurveOptions& options) {
  const SpecimenType type = request.scene.specimen.type;
  const std::string stage =
      fmt::format("the in-process R curve of `fit` ({} method, --rcurve-method)",
                  experiment::RMethodName(options.method));
  const bool may_fall_back = request.target == inverse::FitTarget::kLoad &&
                             options.method == experiment::RMethod::kEnergy;
  std::string why_not;
  try {
    experiment::RCurveResult result = experiment::ComputeRCurve(*input.record, options);
    if (result.curve.size() >= kFitMinPoints) return result;
    why_not = fmt::format("gave {} R points", result.curve.size());
    if (!may_fall_back)
      throw Error(ErrorKind::kInput,
                  fmt::format("{} gave {} R points; a fit needs at least {}", stage,
                              result.curve.size(), kFitMinPoints),
                  {.file = input.label,
                   .field = "R",
                   .value = fmt::format("{} points, increment {:.3g} mm", result.curve.size(),
                                        1e3 * result.figures["energy_min_increment_m"]),
                   .expected = ">= 4 R points; way out: " +
                               WayOut(type, IncrementWayOut(options, result))});
  } catch (const Error& e) {
    if (!may_fall_back || !why_not.empty()) {
      if (e.kind() != ErrorKind::kInput || std::string(e.what()).find(stage) != std::string::npos)
        throw;
      throw Error(e.kind(), stage + ": " + e.message(), e.context())
          .WithContext({.expected = "way out: " + WayOut(type, "")});
    }
    why_not = e.message();
  }
  options.method = FallbackMethod(type);
  if (type == SpecimenType::kCT && !input.record->has_crack_length())
    options.method = experiment::RMethod::kEquivalentCrack;
  experiment::RCurveResult result;
  try {
    result = experiment::ComputeRCurve(*input.record, options);
  } catch (const Error& e) {
    throw Error(e.kind(),
                fmt::format("{} failed ({}), and so did the {} R curve that would start the "
                            "load fit: {}",
                            stage, why_not, experiment::RMethodName(options.method), e.message()),
                e.context());
  }
  const std::string said = fmt::format(
      "the energy R curve {} (fewer than {}): the load-displacement fit starts from the {} R "
      "curve instead",
      why_not, kFitMinPoints, experiment::RMethodName(options.method));
  result.notes.insert(result.notes.begin(), said);
  result.warnings.insert(result.warnings.begin(), input.label + ": " + said);
  return result;
}

// A record input, reduced here.
void ReduceRecordInput(const FitRequest& request, FitInput& input) {
  experiment::RCurveOptions& options = input.reduction_options;
  options = request.reduction;
  options.specimen = request.scene.specimen;
  options.material = request.scene.material;
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid R-curve options: " + why);
  input.record = request.input_path.empty()
                     ? *request.record
                     : ReadRecordFile(request.input_path, request.columns, request.units);
  std::vector<std::string> frame_notes;
  if (const auto& frames = request.frame_crack_lengths)
    input.record = experiment::CrackLengthFromFrames(*input.record, frames->image,
                                                     frames->crack_length, frames->source,
                                                     &frame_notes);
  if (MethodNeedsCrackLength(options.method, request.scene.specimen.type) &&
      !input.record->has_crack_length()) {
    io::RecordColumns columns;
    if (!request.columns.empty()) io::ApplyColumnMapping(request.columns, columns);
    throw Error(ErrorKind::kInput,
                fmt::format("the record has no crack-length column, which the {} method needs",
                            experiment::RMethodName(options.method)),
                {.file = input.label,
                 .field = columns.crack_length,
                 .expected = "a column 'crack_length [mm]' (another header: --columns "
                             "crack_length=HEADER), an R curve as input, or --rcurve-method "
                             "equivalent (crack length from the compliance)"});
  }
  input.reduction = ReduceInProcess(request, input, options);
  input.reduction->notes.insert(input.reduction->notes.begin(), frame_notes.begin(),
                                frame_notes.end());
  input.curve = input.reduction->curve;
  input.initial_compliance = input.reduction->initiation.initial_compliance;
  input.dropped_rows = DroppedRowList(*input.record, *input.reduction);
  input.reduction_warnings = input.reduction->warnings;
}

}  // namespace

std::string FitInput::ReductionText() const {
  return from_record ? fmt::format("{} method, reduced in-process from the record", curve.method)
                     : fmt::format("R curve read from the input ({})", curve.method);
}

FitInput ResolveFitInput(const FitRequest& request) {
  FitInput input;
  input.label = request.input_path.empty() ? std::string("(in memory)") : request.input_path;
  if (request.input_path.empty()) {
    BF_CHECK_INPUT(request.rcurve || request.record, "the fit request names no input",
                   {.field = "input", .expected = "a path, an R curve or a record"});
    input.from_record = !request.rcurve;
  } else {
    input.from_record = InputIsRecord(request.input_path, request.columns);
  }
  if (input.from_record) ReduceRecordInput(request, input);
  else ReadRCurveInput(request, input);
  return input;
}

void HoldAtNotch(double notch, FitInput& input, inverse::FitData& data) {
  if (!(notch > 0.0)) return;
  int below = 0;
  double worst = 0.0;
  for (double& a : data.crack_length) {
    if (!(a < notch)) continue;
    ++below, worst = std::max(worst, notch - a);
    a = notch;
  }
  if (below == 0) return;
  double noise = NAN;
  if (input.reduction) {
    const auto it = input.reduction->figures.find("crack_length_noise_m");
    if (it != input.reduction->figures.end()) noise = it->second;
  }
  const double tolerance = std::max(1e-4, std::isfinite(noise) ? 2.0 * noise : 0.0);
  const std::string said = fmt::format(
      "{} R point{} measured up to {:.3g} mm below the notch (a0 = {:.4g} mm) fitted at the "
      "notch (a crack cannot be shorter than its notch)",
      below, below == 1 ? "" : "s", worst * 1e3, notch * 1e3);
  if (worst > tolerance)
    input.reduction_warnings.push_back(fmt::format(
        "{}: more than {:.2g} mm short, so the crack lengths may be offset; check the scene's "
        "notch, the crack-length column's zero or the DIC crack line",
        said, tolerance * 1e3));
  else if (input.reduction)
    input.reduction->notes.push_back(said);
}

}  // namespace bridgefit::pipeline
