// What a report shows, read from files (the report itself takes values).
#include "bridgefit/pipeline/report_file.hpp"

#include <unistd.h>

#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/dic_file.hpp"
#include "bridgefit/pipeline/law_free.hpp"
#include "bridgefit/pipeline/fit_file.hpp"
#include "bridgefit/pipeline/rcurve_file.hpp"

namespace bridgefit::pipeline {
namespace {

report::ReferenceView ReadReference(const report::ReferenceColumn& ref) {
  if (ref.csv.empty() || ref.column.empty())
    throw Error(ErrorKind::kUsage, "a reference column needs both the CSV and the column name",
                {.field = "--reference, --reference-csv", .value = ref.csv.string() + " " + ref.column});
  const io::CsvTable t = io::ReadCsvTable(ref.csv);
  auto unit_of = [&](const std::string& header) {
    const auto it = ref.units.find(header);
    return it == ref.units.end() ? std::string() : it->second;
  };
  if (t.Find(ref.column) < 0)
    throw Error(ErrorKind::kInput, "the reference column is not in the CSV",
                {.file = ref.csv.string(), .field = ref.column, .expected = "a header of the file"});
  if (t.Find(ref.crack_length_column) < 0)
    throw Error(ErrorKind::kInput, "the reference CSV has no crack-length column",
                {.file = ref.csv.string(), .field = ref.crack_length_column,
                 .expected = "a crack-length header (map it with --columns crack_length=NAME)"});
  report::ReferenceView v;
  v.file = ref.csv;
  v.column = ref.column;
  v.label = ref.column;
  v.unit_text = unit_of(ref.column);
  if (v.unit_text.empty()) v.unit_text = t.units[t.Find(ref.column)];
  const std::vector<double> a =
      t.ColumnSi(ref.crack_length_column, Dimension::Length(), unit_of(ref.crack_length_column));
  const std::vector<double> g = t.ColumnSi(ref.column, Dimension::EnergyPerArea(), unit_of(ref.column));
  for (size_t i = 0; i < a.size() && i < g.size(); ++i)
    if (std::isfinite(a[i]) && std::isfinite(g[i])) {
      v.crack_length.push_back(a[i]);
      v.value.push_back(g[i]);
    }
  if (v.value.empty())
    throw Error(ErrorKind::kInput, "the reference column has no row with a finite value and crack length",
                {.file = ref.csv.string(), .field = ref.column});
  return v;
}

report::TruthView ReadTruth(const std::filesystem::path& scene_file) {
  report::TruthView t;
  const Scene scene = io::ReadSceneFile(scene_file);
  t.present = true;
  if (scene.fracture) t.J_tip_c = scene.fracture->J_tip_c;
  if (scene.bridging) {
    t.shape = scene.bridging->shape;
    t.sigma_c = scene.bridging->scales.sigma_c;
    t.delta_c = scene.bridging->scales.delta_c;
    t.J_B = scene.bridging->Law().BridgingToughness();
  } else {
    t.sigma_c = t.delta_c = t.J_B = 0.0;  // no bridging in the truth
  }
  return t;
}

}  // namespace

report::ReportInput ReadReportInput(const std::filesystem::path& fit_h5,
                                    const report::ReportOptions& options) {
  report::ReportInput in;
  in.fit_path = fit_h5;
  in.fit = ReadFitView(fit_h5);
  // The record rows the R curve did not use, by reason, and the reduction's
  // warnings (/rcurve of `rcurve --out` and of a fit file; issue 15).
  const RCurveFileRecord behind = ReadRCurveFileRecord(fit_h5.string());
  for (const auto& [reason, count] : behind.dropped_rows)
    in.notes.push_back(fmt::format("R curve: {} record rows not used: {}", count, reason));
  for (const std::string& warning : behind.reduction_warnings)
    in.notes.push_back("R curve warning: " + warning);
  // The record: --record, else the fit file itself when it carries /experiment.
  std::filesystem::path record_h5 = options.record_h5;
  if (record_h5.empty() && io::H5Reader(fit_h5).Exists("/experiment/load")) record_h5 = fit_h5;
  if (!record_h5.empty()) {
    const io::H5Reader r(record_h5);
    in.record = io::ReadExperimentH5(r, "/experiment");
    in.record_from_images = in.record->metadata.count("crack_length") > 0;  // rcurve --crack-length-from
  }
  if (!options.dic_csv.empty() || !options.dic_h5.empty())
    in.dic = ReadDicView(options.dic_csv, options.dic_h5, options.images_dir, in.notes);
  if (!options.lawfree_h5.empty()) in.law_free = ReadLawFreeView(options.lawfree_h5);
  if (options.reference.enabled()) in.reference = ReadReference(options.reference);
  if (!options.truth_scene.empty()) in.truth = ReadTruth(options.truth_scene);
  return in;
}

report::ReportSummary WriteFitReport(const std::filesystem::path& fit_h5,
                                     const std::filesystem::path& out_dir,
                                     const report::ReportOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, why, {.field = "report options"});
  if (out_dir.empty()) throw Error(ErrorKind::kUsage, "the output folder is empty", {.field = "--out"});
  Stopwatch watch;
  const report::ReportInput input = ReadReportInput(fit_h5, options);
  report::ReportSummary summary = report::WriteFitReport(input, out_dir, options);
  summary.wall_s = watch.Seconds();
  return summary;
}

std::optional<report::ReportSummary> WriteFitOutputs(const FitRequest& request, const FitRun& run,
                                                     const std::string& fit_h5,
                                                     const std::filesystem::path& report_dir,
                                                     const report::ReportOptions& options) {
  // The report reads the fit file: without one named it goes to a temporary file.
  const std::string fit_file =
      !fit_h5.empty() ? fit_h5
      : report_dir.empty()
          ? std::string()
          : (std::filesystem::temp_directory_path() /
             ("bridgefit-fit-" + std::to_string(::getpid()) + ".h5")).string();
  if (!fit_file.empty()) WriteFitFile(fit_file, request, run);
  if (report_dir.empty()) return std::nullopt;
  try {
    report::ReportSummary written = WriteFitReport(fit_file, report_dir, options);
    if (fit_h5.empty()) std::filesystem::remove(fit_file);
    return written;
  } catch (...) {
    if (fit_h5.empty()) std::filesystem::remove(fit_file);
    throw;
  }
}

}  // namespace bridgefit::pipeline
