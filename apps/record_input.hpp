#pragma once
// Test records on the command line, shared by `bridgefit rcurve` and
// `bridgefit fit RECORD` (which reduces a record to an R curve in-process):
// reading a record file and writing a reduction's HDF5 groups.

#include <string>
#include <utility>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/experiment/rcurve.hpp"
#include "bridgefit/io/hdf5.hpp"

namespace bridgefit::cli {

// A record from CSV (units in the header or `units`, columns renamed by
// `columns`, e.g. "load=Force") or from the HDF5 group /experiment.
ExperimentRecord ReadRecordFile(const std::string& path, const std::string& columns,
                                const std::string& units);

// Rows that gave no R point: import cleaning (io), then the reduction's reasons.
std::vector<std::pair<std::string, int>> DroppedRowList(const ExperimentRecord& record,
                                                        const experiment::RCurveResult& result);

// /experiment (the record) and /rcurve (the reduction with its dropped rows,
// noise levels, figures and specimen), the layout of `bridgefit rcurve --out`.
void WriteReductionH5(io::H5Writer& file, const ExperimentRecord& record,
                      const experiment::RCurveResult& result,
                      const experiment::RCurveOptions& options, const std::string& scene_path);

}  // namespace bridgefit::cli
