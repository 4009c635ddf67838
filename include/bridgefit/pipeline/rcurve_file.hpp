#pragma once
// Test records and R curves on disk, the one owner of the layout that
// `bridgefit rcurve --out` writes and `bridgefit fit` / `report` read:
//   /experiment  the record (io::WriteRecordH5)
//   /rcurve      the reduction: R curve, its rows, dropped rows, noise
//                levels, /rcurve/figures and the specimen

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/experiment/rcurve.hpp"
#include "bridgefit/io/hdf5.hpp"

namespace bridgefit::pipeline {

bool IsHdf5Path(const std::string& path);  // .h5 or .hdf5

// A record from CSV (units in the header or `units`, columns renamed by
// `columns`, e.g. "load=Force") or from the HDF5 group /experiment.
ExperimentRecord ReadRecordFile(const std::string& path, const std::string& columns,
                                const std::string& units);

// An R curve from CSV ('crack_length [mm], R [J/m^2][, R_uncertainty [J/m^2]]')
// or from the /rcurve group of an rcurve.h5.
RCurve ReadRCurveFile(const std::string& path);

// What an rcurve.h5 holds besides the curve: the record behind it
// (/experiment, when present) and its initial compliance C0 [m/N]
// (/rcurve/figures; NaN when absent), the rows its reduction dropped by
// reason and its warnings (/rcurve/dropped_*, /rcurve/warnings). Nothing for a CSV.
struct RCurveFileRecord {
  std::optional<ExperimentRecord> record;
  double initial_compliance = NAN;
  std::vector<std::pair<std::string, int>> dropped_rows;
  std::vector<std::string> reduction_warnings;
};
RCurveFileRecord ReadRCurveFileRecord(const std::string& path);

// Rows that gave no R point: import cleaning (io), then the reduction's reasons.
std::vector<std::pair<std::string, int>> DroppedRowList(const ExperimentRecord& record,
                                                        const experiment::RCurveResult& result);

// /rcurve/dropped_reasons, /rcurve/dropped_counts (rows per reason) and
// /rcurve/warnings ("none" when there are none).
void WriteDroppedRows(io::H5Writer& file, const std::vector<std::pair<std::string, int>>& dropped,
                      const std::vector<std::string>& warnings);

// /experiment (the record) and /rcurve (the reduction with its dropped rows,
// noise levels, figures and specimen), the layout of `bridgefit rcurve --out`.
void WriteReductionH5(io::H5Writer& file, const ExperimentRecord& record,
                      const experiment::RCurveResult& result,
                      const experiment::RCurveOptions& options, const std::string& scene_path);

// `bridgefit rcurve --csv`: the R curve with one standard uncertainty (what
// ReadRCurveFile reads), crack growth, load, displacement and the expanded
// uncertainty (coverage factor k) last; lengths in mm. Atomic.
void WriteRCurveCsv(const std::string& path, const experiment::RCurveResult& result,
                    const experiment::RCurveOptions& options);

}  // namespace bridgefit::pipeline
