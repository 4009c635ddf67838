// Record types <-> HDF5 groups; the layout is documented in docs/FORMATS.md.
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/hdf5.hpp"

namespace bridgefit::io {
namespace {

// SimulationPoint columns: name, member, unit, description.
struct PointColumn {
  const char* name;
  double SimulationPoint::*member;
  const char* units;
  const char* description;
};
constexpr PointColumn kPointColumns[] = {
    {"crack_length", &SimulationPoint::crack_length, "m", "crack length a from the load line"},
    {"R", &SimulationPoint::R, "J/m^2", "elastic-zone R (PHYSICS 3)"},
    {"R_energy", &SimulationPoint::R_energy, "J/m^2", "energy released per unit growth"},
    {"J_tip", &SimulationPoint::J_tip, "J/m^2", "crack-tip energy release rate"},
    {"J_ff", &SimulationPoint::J_ff, "J/m^2", "far-field J"},
    {"delta_root", &SimulationPoint::delta_root, "m", "COD at the notch root"},
    {"root_position", &SimulationPoint::root_position, "m", "notch-root x from the load line"},
    {"bridging_zone_length", &SimulationPoint::bridging_zone_length, "m", "a - x_root"},
    {"load", &SimulationPoint::load, "N", "load P"},
    {"displacement", &SimulationPoint::displacement, "m", "load-point displacement"},
    {"cmod", &SimulationPoint::cmod, "m", "crack-mouth opening"},
};

double AttributeOr(const H5Reader& file, const std::string& group, const std::string& key,
                   double fallback) {
  return file.HasAttribute(group, key) ? file.ReadNumberAttribute(group, key) : fallback;
}

// A row count: an integer from 0 to INT_MAX, checked before the conversion
// (a file with rows_read = 1e300 or NaN is refused, not cast).
int CountOr(const H5Reader& file, const std::string& group, const std::string& key) {
  if (!file.HasAttribute(group, key)) return 0;
  return static_cast<int>(
      file.ReadIntegerAttribute(group, key, 0, std::numeric_limits<int>::max()));
}

}  // namespace

void WriteRecordH5(H5Writer& file, const ExperimentRecord& record, const std::string& group) {
  file.WriteAttribute(group, "kind", "experiment");
  file.WriteAttribute(group, "source", record.source);
  file.WriteAttribute(group, "rows_read", record.rows_read);
  file.WriteAttribute(group, "rows_dropped_nan", record.rows_dropped_nan);
  file.WriteAttribute(group, "rows_repeated", record.rows_repeated);
  file.WriteVector(group + "/load", record.load, "N", "load P");
  file.WriteVector(group + "/displacement", record.displacement, "m", "load-point displacement");
  if (!record.time.empty()) file.WriteVector(group + "/time", record.time, "s", "test time");
  if (!record.crack_length.empty())
    file.WriteVector(group + "/crack_length", record.crack_length, "m",
                     "crack length a from the load line");
  if (!record.images.empty()) file.WriteStrings(group + "/images", record.images);
  for (const auto& [key, value] : record.metadata)
    file.WriteAttribute(group + "/metadata", key, value);
}

ExperimentRecord ReadExperimentH5(const H5Reader& file, const std::string& group) {
  ExperimentRecord record;
  record.source = file.ReadStringAttribute(group, "source");
  record.rows_read = CountOr(file, group, "rows_read");
  record.rows_dropped_nan = CountOr(file, group, "rows_dropped_nan");
  record.rows_repeated = CountOr(file, group, "rows_repeated");
  record.load = file.ReadVector(group + "/load");
  record.displacement = file.ReadVector(group + "/displacement");
  if (file.Exists(group + "/time")) record.time = file.ReadVector(group + "/time");
  if (file.Exists(group + "/crack_length"))
    record.crack_length = file.ReadVector(group + "/crack_length");
  if (file.Exists(group + "/images")) record.images = file.ReadStrings(group + "/images");
  // The metadata keys the library writes and reads back.
  for (const char* key : {"columns", "crack_length"})
    if (file.Exists(group + "/metadata") && file.HasAttribute(group + "/metadata", key))
      record.metadata[key] = file.ReadStringAttribute(group + "/metadata", key);
  record.Validate();
  return record;
}

void WriteRecordH5(H5Writer& file, const RCurve& curve, const std::string& group) {
  file.WriteAttribute(group, "kind", "rcurve");
  file.WriteAttribute(group, "method", curve.method);
  file.WriteAttribute(group, "r_kind", curve.r_kind);
  file.WriteAttribute(group, "source", curve.source);
  file.WriteAttribute(group, "initial_crack_length_m", curve.initial_crack_length);
  file.WriteAttribute(group, "initiation_R_J_per_m2", curve.initiation_R);
  file.WriteVector(group + "/crack_length", curve.crack_length, "m", "crack length a");
  file.WriteVector(group + "/R", curve.R, "J/m^2", "crack growth resistance");
  if (!curve.R_uncertainty.empty()) {
    file.WriteVector(group + "/R_uncertainty", curve.R_uncertainty, "J/m^2",
                     fmt::format("uncertainty of R, coverage factor k = {:g}",
                                 curve.uncertainty_coverage));
    file.WriteAttribute(group, "coverage_factor", curve.uncertainty_coverage);
  }
}

RCurve ReadRCurveH5(const H5Reader& file, const std::string& group) {
  RCurve curve;
  curve.method = file.ReadStringAttribute(group, "method");
  curve.r_kind = file.ReadStringAttribute(group, "r_kind");
  curve.source = file.ReadStringAttribute(group, "source");
  curve.initial_crack_length = AttributeOr(file, group, "initial_crack_length_m", NAN);
  curve.initiation_R = AttributeOr(file, group, "initiation_R_J_per_m2", NAN);
  curve.crack_length = file.ReadVector(group + "/crack_length");
  curve.R = file.ReadVector(group + "/R");
  if (file.Exists(group + "/R_uncertainty")) {
    curve.R_uncertainty = file.ReadVector(group + "/R_uncertainty");
    curve.uncertainty_coverage = AttributeOr(file, group, "coverage_factor", 1.0);
  }
  curve.Validate();
  return curve;
}

void WriteRecordH5(H5Writer& file, const SimulationResult& result, const std::string& group) {
  file.WriteAttribute(group, "kind", "simulation");
  file.WriteAttribute(group, "model", result.model);
  file.WriteAttribute(group, "status", RunStatusName(result.status));
  file.WriteAttribute(group, "message", result.message);
  file.WriteAttribute(group, "steady_state_reached", result.steady_state_reached ? 1.0 : 0.0);
  file.WriteAttribute(group, "steady_state_crack_length_m", result.steady_state_crack_length);
  file.WriteAttribute(group, "initiation_load_N", result.initiation_load);
  file.WriteAttribute(group, "wall_s", result.wall_s);
  for (const PointColumn& column : kPointColumns) {
    std::vector<double> values;
    values.reserve(result.points.size());
    for (const SimulationPoint& p : result.points) values.push_back(p.*column.member);
    file.WriteVector(group + "/" + column.name, values, column.units, column.description);
  }
  for (const auto& [key, value] : result.figures) file.WriteAttribute(group + "/figures", key, value);
}

SimulationResult ReadSimulationH5(const H5Reader& file, const std::string& group) {
  SimulationResult result;
  result.model = file.ReadStringAttribute(group, "model");
  const std::string status = file.ReadStringAttribute(group, "status");
  for (RunStatus s : {RunStatus::kOk, RunStatus::kNotConverged, RunStatus::kUnstable,
                      RunStatus::kInvalidInput, RunStatus::kFailed})
    if (status == RunStatusName(s)) result.status = s;
  result.message = file.ReadStringAttribute(group, "message");
  result.steady_state_reached = AttributeOr(file, group, "steady_state_reached", 0.0) != 0.0;
  result.steady_state_crack_length = AttributeOr(file, group, "steady_state_crack_length_m", NAN);
  result.initiation_load = AttributeOr(file, group, "initiation_load_N", NAN);
  result.wall_s = AttributeOr(file, group, "wall_s", 0.0);
  const std::vector<double> first = file.ReadVector(group + "/crack_length");
  result.points.resize(first.size());
  for (const PointColumn& column : kPointColumns) {
    const std::vector<double> values = file.ReadVector(group + "/" + column.name);
    if (values.size() != first.size())
      throw Error(ErrorKind::kInput, "dataset length differs from crack_length",
                  {.field = group + "/" + column.name});
    for (size_t i = 0; i < values.size(); ++i) result.points[i].*column.member = values[i];
  }
  return result;
}

}  // namespace bridgefit::io
