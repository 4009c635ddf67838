#pragma once
// The R-curve workflow as one call (issue 16), `bridgefit rcurve`:
//
//   record file -> [crack lengths from the DIC frames] -> reduction
//   (experiment::ComputeRCurve) -> result; WriteRCurveOutputs writes it
//   (pipeline/rcurve_file.hpp owns the layouts)
//
// Throws bridgefit::Error: kUsage for invalid reduction options (checked
// before any file is read), kInput for a record that cannot be read.

#include <string>
#include <utility>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/experiment/rcurve.hpp"

namespace bridgefit::pipeline {

struct RCurveRequest {
  std::string record_path;     // CSV (units in the header or `units`) or HDF5 /experiment
  std::string columns, units;  // CSV: column and unit mapping (io::ApplyColumnMapping)
  // Crack lengths measured on the record's images: the CSV of `bridgefit
  // dic --csv`, matched by the record's image column (empty: none).
  std::string crack_length_from;
  experiment::RCurveOptions options;  // specimen, material and reduction
  std::string scene_path;             // provenance, written in /rcurve

  bool IsValid(std::string* why) const;  // the reduction options' checks
};

struct RCurveRun {
  ExperimentRecord record;  // as reduced (with the frames' crack lengths)
  experiment::RCurveResult result;
  experiment::RCurveOptions options;

  // Rows that gave no R point: import cleaning, then the reduction's reasons.
  std::vector<std::pair<std::string, int>> DroppedRows() const;
  // The text `bridgefit rcurve` prints: the result's brief report, the rows
  // dropped on import and the curve (at most about 25 rows, the last always).
  std::string BriefReport() const;
};

RCurveRun RunRCurve(const RCurveRequest& request);

// `--out` (/experiment + /rcurve) and `--csv` (the R curve); an empty path
// is not written.
void WriteRCurveOutputs(const RCurveRequest& request, const RCurveRun& run,
                        const std::string& out_h5, const std::string& csv);

}  // namespace bridgefit::pipeline
