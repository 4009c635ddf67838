// The R-curve workflow (pipeline/rcurve.hpp): read, frames, reduce, write.
#include "bridgefit/pipeline/rcurve.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/pipeline/dic_file.hpp"
#include "bridgefit/pipeline/rcurve_file.hpp"

namespace bridgefit::pipeline {

bool RCurveRequest::IsValid(std::string* why) const { return options.IsValid(why); }

std::vector<std::pair<std::string, int>> RCurveRun::DroppedRows() const {
  return DroppedRowList(record, result);
}

std::string RCurveRun::BriefReport() const {
  std::string text = result.BriefReport() + "\n";
  for (const auto& [reason, count] : DroppedRows())
    if (reason.find("on import") != std::string::npos)
      text += fmt::format("  dropped {:5d}: {}\n", count, reason);
  text += fmt::format("{:>12} {:>12} {:>14} {:>14}\n", "a [mm]", "da [mm]", "R [J/m^2]",
                      "+- [J/m^2]");
  const RCurve& curve = result.curve;
  const std::size_t stride = std::max<std::size_t>(1, curve.size() / 25);
  for (std::size_t i = 0; i < curve.size(); ++i) {
    if (i % stride != 0 && i + 1 != curve.size()) continue;
    text += fmt::format("{:12.4f} {:12.4f} {:14.5g} {:14.3g}\n", curve.crack_length[i] * 1e3,
                        result.crack_growth[i] * 1e3, curve.R[i], curve.R_uncertainty[i]);
  }
  return text;
}

RCurveRun RunRCurve(const RCurveRequest& request) {
  std::string why;
  if (!request.IsValid(&why)) throw Error(ErrorKind::kUsage, why);
  RCurveRun run;
  run.options = request.options;
  run.record = ReadRecordFile(request.record_path, request.columns, request.units);
  std::vector<std::string> frame_notes;
  if (!request.crack_length_from.empty()) {
    // `bridgefit dic --csv`: one row per frame, its image and crack length.
    const DicCrackLengths frames = ReadDicCrackLengths(request.crack_length_from);
    frame_notes = frames.notes;
    run.record = experiment::CrackLengthFromFrames(run.record, frames.image, frames.crack_length,
                                                   request.crack_length_from, &frame_notes);
  }
  run.result = experiment::ComputeRCurve(run.record, run.options);
  run.result.notes.insert(run.result.notes.begin(), frame_notes.begin(), frame_notes.end());
  return run;
}

void WriteRCurveOutputs(const RCurveRequest& request, const RCurveRun& run,
                        const std::string& out_h5, const std::string& csv) {
  if (!out_h5.empty()) {
    io::H5Writer file(out_h5);
    WriteReductionH5(file, run.record, run.result, run.options, request.scene_path);
    file.Commit();
  }
  if (!csv.empty()) WriteRCurveCsv(csv, run.result, run.options);
}

}  // namespace bridgefit::pipeline
