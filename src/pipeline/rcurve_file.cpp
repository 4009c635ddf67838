#include "bridgefit/pipeline/rcurve_file.hpp"

#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/io/csv.hpp"

namespace bridgefit::pipeline {

bool IsHdf5Path(const std::string& path) {
  return path.size() > 3 && (path.ends_with(".h5") || path.ends_with(".hdf5"));
}

ExperimentRecord ReadRecordFile(const std::string& path, const std::string& columns,
                                const std::string& units) {
  if (path.ends_with(".h5") || path.ends_with(".hdf5")) {
    if (!columns.empty() || !units.empty())
      throw Error(ErrorKind::kUsage, "--columns/--units apply to CSV records only",
                  {.field = "--columns", .value = path});
    const io::H5Reader file(path);
    ExperimentRecord record = io::ReadExperimentH5(file, "/experiment");
    if (record.source.empty()) record.source = path;
    return record;
  }
  io::RecordColumns mapping;
  if (!columns.empty()) io::ApplyColumnMapping(columns, mapping);
  if (!units.empty()) io::ApplyUnitMapping(units, mapping);
  return io::ReadRecordCsv(path, mapping);
}

RCurve ReadRCurveFile(const std::string& path) {
  if (IsHdf5Path(path)) {
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

RCurveFileRecord ReadRCurveFileRecord(const std::string& path) {
  RCurveFileRecord out;
  if (!IsHdf5Path(path)) return out;
  const io::H5Reader reader(path);
  if (reader.Exists("/experiment/load")) out.record = io::ReadExperimentH5(reader, "/experiment");
  if (reader.Exists("/rcurve/figures") &&
      reader.HasAttribute("/rcurve/figures", "initial_compliance_m_per_N"))
    out.initial_compliance =
        reader.ReadNumberAttribute("/rcurve/figures", "initial_compliance_m_per_N");
  if (reader.Exists("/rcurve/dropped_reasons") && reader.Exists("/rcurve/dropped_counts")) {
    const std::vector<std::string> reasons = reader.ReadStrings("/rcurve/dropped_reasons");
    const std::vector<double> counts = reader.ReadVector("/rcurve/dropped_counts");
    for (std::size_t i = 0; i < std::min(reasons.size(), counts.size()); ++i)
      out.dropped_rows.emplace_back(reasons[i], static_cast<int>(std::lround(counts[i])));
  }
  if (reader.Exists("/rcurve/warnings"))
    for (const std::string& w : reader.ReadStrings("/rcurve/warnings"))
      if (w != "none") out.reduction_warnings.push_back(w);
  return out;
}

std::vector<std::pair<std::string, int>> DroppedRowList(const ExperimentRecord& record,
                                                        const experiment::RCurveResult& result) {
  std::vector<std::pair<std::string, int>> list;
  if (record.rows_dropped_nan > 0)
    list.emplace_back("missing value (NaN) in a used column, on import", record.rows_dropped_nan);
  if (record.rows_repeated > 0)
    list.emplace_back("exact repeat of the previous row, on import", record.rows_repeated);
  for (const experiment::DroppedRows& d : result.dropped) list.emplace_back(d.reason, d.count);
  return list;
}

void WriteDroppedRows(io::H5Writer& file, const std::vector<std::pair<std::string, int>>& dropped,
                      const std::vector<std::string>& warnings) {
  std::vector<std::string> reasons;
  std::vector<double> counts;
  for (const auto& [reason, count] : dropped) {
    reasons.push_back(reason);
    counts.push_back(count);
  }
  file.WriteStrings("/rcurve/dropped_reasons", reasons);
  file.WriteVector("/rcurve/dropped_counts", counts, "1", "rows dropped per reason");
  file.WriteStrings("/rcurve/warnings", warnings.empty() ? std::vector<std::string>{"none"} : warnings);
}

void WriteReductionH5(io::H5Writer& file, const ExperimentRecord& record,
                      const experiment::RCurveResult& result,
                      const experiment::RCurveOptions& options, const std::string& scene_path) {
  io::WriteRecordH5(file, record, "/experiment");
  io::WriteRecordH5(file, result.curve, "/rcurve");
  file.WriteVector("/rcurve/crack_growth", result.crack_growth, "m", "a - a0");
  file.WriteVector("/rcurve/load", result.load, "N", "load at the point (end row for energy)");
  file.WriteVector("/rcurve/displacement", result.displacement, "m", "load-point displacement");
  std::vector<double> rows(result.rows.begin(), result.rows.end());
  file.WriteVector("/rcurve/record_row", rows, "1", "0-based row of the cleaned record");
  WriteDroppedRows(file, DroppedRowList(record, result), result.warnings);
  file.WriteStrings("/rcurve/notes",
                    result.notes.empty() ? std::vector<std::string>{"none"} : result.notes);
  file.WriteAttribute("/rcurve", "points_used", static_cast<double>(result.points_used));
  file.WriteAttribute("/rcurve", "load_noise_N", result.load_noise);
  file.WriteAttribute("/rcurve", "displacement_noise_m", result.displacement_noise);
  file.WriteAttribute("/rcurve", "crack_length_noise_m", result.crack_length_noise);
  for (const auto& [key, value] : result.figures)
    file.WriteAttribute("/rcurve/figures", key, value);
  file.WriteAttribute("/rcurve", "specimen",
                      options.specimen.type == SpecimenType::kCT ? "ct" : "dcb");
  file.WriteAttribute("/rcurve", "specimen_width_m", options.specimen.width);
  file.WriteAttribute("/rcurve", "specimen_height_m", options.specimen.height);
  file.WriteAttribute("/rcurve", "specimen_thickness_m", options.specimen.thickness);
  file.WriteAttribute("/rcurve", "specimen_length_m", options.specimen.length);
  file.WriteAttribute("/rcurve", "crack_front_width_m", options.specimen.CrackFrontWidth());
  if (!scene_path.empty()) file.WriteAttribute("/rcurve", "scene", scene_path);
}

void WriteRCurveCsv(const std::string& path, const experiment::RCurveResult& result,
                  const experiment::RCurveOptions& options) {
  std::string text =
      "crack_length [mm], R [J/m^2], R_uncertainty [J/m^2], crack_growth [mm], load [N], "
      "displacement [mm], R_expanded_uncertainty [J/m^2]\n";
  // CSV R curves carry one standard uncertainty (what `fit` reads);
  // the expanded one (coverage factor k) is the last column.
  for (std::size_t i = 0; i < result.curve.size(); ++i)
    text += fmt::format("{:.8g}, {:.8g}, {:.8g}, {:.8g}, {:.8g}, {:.8g}, {:.8g}\n",
                        result.curve.crack_length[i] * 1e3, result.curve.R[i],
                        result.curve.R_uncertainty[i] / options.coverage_factor,
                        result.crack_growth[i] * 1e3, result.load[i],
                        result.displacement[i] * 1e3, result.curve.R_uncertainty[i]);
  WriteTextFileAtomic(path, text);
}

}  // namespace bridgefit::pipeline
