// The rcurve, law and simulate workflows as calls (issue 16), without the
// binary. Oracles: the law table against the linear law's closed form
// (R = J_tip,c + sigma_c delta / 2, the CLI test's oracle); the R-curve run
// equals experiment::ComputeRCurve on the same record and its files read back
// to the same curve; the simulation CSV read back equals the points; every
// CSV is written by its one writer and read by io::ReadCsvTable; the MPM runs
// equal mpm::SimulateGrowth and write their HDF5 + XDMF and history.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/pipeline/dic_file.hpp"
#include "bridgefit/pipeline/law.hpp"
#include "bridgefit/pipeline/rcurve.hpp"
#include "bridgefit/pipeline/rcurve_file.hpp"
#include "bridgefit/pipeline/simulate.hpp"
#include "bridgefit/pipeline/simulation_file.hpp"

namespace bridgefit::pipeline {
namespace {

namespace fs = std::filesystem;
const fs::path kSample = fs::path(BRIDGEFIT_SOURCE_DIR) / "data_samples" / "mdf_ct";

struct WorkDir {
  fs::path path = fs::temp_directory_path() / ("bf_workflows_" + std::to_string(::getpid()));
  WorkDir() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~WorkDir() { fs::remove_all(path); }
};

std::string FirstLine(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

LawRequest LinearLaw(int points) {
  LawRequest request;
  request.shape = laws::MakeLinearShape();
  request.scales = laws::CompleteScales(request.shape, {0.45e6, NAN, 500.0});
  request.J_tip_c = 2210.0;
  request.points = points;
  return request;
}

TEST(LawWorkflow, LinearLawTableMatchesItsClosedForm) {
  const LawRun run = RunLaw(LinearLaw(101));
  const double delta_c = 2 * 500.0 / 0.45e6;
  ASSERT_EQ(run.points.size(), 101u);
  EXPECT_EQ(run.points.front().delta, 0.0);
  EXPECT_NEAR(run.points.back().delta, delta_c, 1e-15);
  EXPECT_DOUBLE_EQ(run.points.front().sigma, 0.45e6);
  EXPECT_NEAR(run.points.back().sigma, 0.0, 1e-6);
  for (const LawPoint& p : run.points) {
    EXPECT_NEAR(p.R, 2210.0 + 0.5 * 0.45e6 * p.delta, 1e-6);
    EXPECT_GE(p.J_ff, p.R - 1e-9);
  }
  EXPECT_NEAR(run.points.back().R, 2710.0, 1e-9);  // J_tip,c + J_B at delta_c
}

TEST(LawWorkflow, CsvReadsBackAndReportNamesUnits) {
  WorkDir dir;
  const LawRun run = RunLaw(LinearLaw(5));
  const fs::path csv = dir.path / "law.csv";
  WriteLawCsv(csv.string(), run);
  EXPECT_EQ(FirstLine(csv), "delta [m], sigma [Pa], R [J/m^2], J_ff [J/m^2]");
  const io::CsvTable table = io::ReadCsvTable(csv);
  ASSERT_EQ(table.rows(), 5u);
  const auto R = table.ColumnSi("R", Dimension::EnergyPerArea());
  const auto delta = table.ColumnSi("delta", Dimension::Length());
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_NEAR(R[i], run.points[i].R, 1e-9 * run.points[i].R);
    EXPECT_NEAR(delta[i], run.points[i].delta, 1e-18 + 1e-9 * run.points[i].delta);
  }
  const std::string text = run.BriefReport();
  EXPECT_EQ(text.rfind("law linear: sigma_c = 0.45 MPa", 0), 0u) << text;
  EXPECT_NE(text.find("steady-state R = 2710 J/m^2"), std::string::npos) << text;
  EXPECT_NE(text.find("delta [mm]"), std::string::npos);
}

TEST(LawWorkflow, InvalidRequestIsAUsageError) {
  LawRequest request = LinearLaw(1);
  std::string why;
  EXPECT_FALSE(request.IsValid(&why));
  EXPECT_NE(why.find("2 points"), std::string::npos) << why;
  try {
    RunLaw(request);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kUsage);
  }
}

RCurveRequest SampleRCurveRequest() {
  RCurveRequest request;
  request.record_path = (kSample / "record.csv").string();
  request.scene_path = (kSample / "scene.toml").string();
  const Scene scene = io::ReadSceneFile(request.scene_path);
  request.options.specimen = scene.specimen;
  request.options.material = scene.material;
  return request;
}

TEST(RCurveWorkflow, RunEqualsTheReductionAndItsFilesReadBack) {
  const RCurveRequest request = SampleRCurveRequest();
  const RCurveRun run = RunRCurve(request);
  const ExperimentRecord record = ReadRecordFile(request.record_path, "", "");
  const experiment::RCurveResult direct = experiment::ComputeRCurve(record, request.options);
  ASSERT_GT(run.result.curve.size(), 3u);
  ASSERT_EQ(run.result.curve.size(), direct.curve.size());
  for (std::size_t i = 0; i < direct.curve.size(); ++i) {
    EXPECT_EQ(run.result.curve.crack_length[i], direct.curve.crack_length[i]);
    EXPECT_EQ(run.result.curve.R[i], direct.curve.R[i]);
  }
  EXPECT_EQ(run.DroppedRows(), DroppedRowList(record, direct));

  WorkDir dir;
  const fs::path h5 = dir.path / "rcurve.h5", csv = dir.path / "rcurve.csv";
  WriteRCurveOutputs(request, run, h5.string(), csv.string());
  for (const fs::path& file : {h5, csv}) {
    const RCurve back = ReadRCurveFile(file.string());
    ASSERT_EQ(back.size(), run.result.curve.size()) << file;
    for (std::size_t i = 0; i < back.size(); ++i) {
      EXPECT_NEAR(back.crack_length[i], run.result.curve.crack_length[i], 1e-9) << file;
      EXPECT_NEAR(back.R[i], run.result.curve.R[i], 1e-6 * run.result.curve.R[i]) << file;
    }
  }
  const RCurveFileRecord stored = ReadRCurveFileRecord(h5.string());
  EXPECT_EQ(stored.dropped_rows, run.DroppedRows());

  const std::string text = run.BriefReport();
  EXPECT_EQ(text.rfind(run.result.BriefReport() + "\n", 0), 0u);
  EXPECT_NE(text.find("      a [mm]      da [mm]      R [J/m^2]     +- [J/m^2]\n"),
            std::string::npos)
      << text;
}

// `rcurve --crack-length-from dic.csv`: a frame whose flags put its length
// in doubt (here 5 mm for about 39 mm, tip_at_edge) is left out and the rows
// around it are interpolated between its neighbours; a frame flagged only
// path_disagrees_with_line (the given line was off, the length is measured
// on the path found) keeps its length. Oracle: the record's rows at the
// frames hold the DIC lengths, the left-out row lies between its neighbours.
TEST(RCurveWorkflow, DicFramesWithADoubtfulLengthAreLeftOutWithANote) {
  WorkDir dir;
  dic::CrackSequenceResult dic_run;
  for (int k = 0; k <= 9; ++k) {
    dic::FrameResult f;
    f.image = (kSample / "images" / fmt::format("frame_{:02d}.png", k)).string();
    if (k > 0) {
      f.has_length = true;
      f.crack_length_m = f.crack_length_raw_m = (30.0 + 4.5 * k) * 1e-3;
      f.uncertainty_m = 0.2e-3;
    }
    dic_run.frames.push_back(f);
  }
  dic_run.frames[3].crack_length_m = dic_run.frames[3].crack_length_raw_m = 5e-3;
  dic_run.frames[3].tip.tip_at_edge = true;
  dic_run.frames[5].path_disagrees_with_hint = true;
  const fs::path csv = dir.path / "dic.csv";
  WriteDicCsv(csv.string(), dic_run);

  const DicCrackLengths read = ReadDicCrackLengths(csv.string());
  EXPECT_TRUE(std::isnan(read.crack_length[3]));
  EXPECT_NEAR(read.crack_length[5], 52.5e-3, 1e-8);
  ASSERT_EQ(read.notes.size(), 1u);
  EXPECT_NE(read.notes[0].find("frame_03.png (tip_at_edge)"), std::string::npos) << read.notes[0];
  EXPECT_EQ(read.notes[0].find("frame_05"), std::string::npos) << read.notes[0];

  // Fewer than two lengths without a doubt: all stay, with a warning.
  DicCrackLengths few{{"a.png", "b.png", "c.png"}, {30e-3, 31e-3, 29e-3}, {}};
  LeaveOutDoubtfulLengths({"", "tip_at_edge", "methods_disagree"}, few);
  EXPECT_DOUBLE_EQ(few.crack_length[1], 31e-3);
  EXPECT_DOUBLE_EQ(few.crack_length[2], 29e-3);
  ASSERT_EQ(few.notes.size(), 1u);
  EXPECT_EQ(few.notes[0].rfind("warning: 2 DIC frame(s)", 0), 0u) << few.notes[0];

  RCurveRequest request = SampleRCurveRequest();
  request.crack_length_from = csv.string();
  const RCurveRun run = RunRCurve(request);
  const ExperimentRecord& record = run.record;
  auto row_of = [&](int frame) {
    for (std::size_t r = 0; r < record.images.size(); ++r)
      if (record.images[r].find(fmt::format("frame_{:02d}", frame)) != std::string::npos) return r;
    return record.images.size();
  };
  ASSERT_LT(row_of(4), record.size());
  EXPECT_NEAR(record.crack_length[row_of(2)], 39.0e-3, 1e-8);
  EXPECT_NEAR(record.crack_length[row_of(5)], 52.5e-3, 1e-8);
  const double left_out = record.crack_length[row_of(3)];
  EXPECT_GT(left_out, 39.0e-3);
  EXPECT_LT(left_out, 48.0e-3);
  bool noted = false;
  for (const std::string& n : run.result.notes)
    noted = noted || n.find("frame_03.png") != std::string::npos;
  EXPECT_TRUE(noted) << "the R curve's notes do not name the left-out frame";
}

TEST(RCurveWorkflow, InvalidOptionsAreRefusedBeforeTheRecordIsRead) {
  RCurveRequest request = SampleRCurveRequest();
  request.record_path = "/nonexistent/record.csv";
  request.options.coverage_factor = -1.0;
  std::string why;
  ASSERT_FALSE(request.IsValid(&why));
  try {
    RunRCurve(request);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kUsage) << e.what();
  }
}

TEST(SimulateWorkflow, ReducedRunAndItsCsvReadBack) {
  const Scene scene = io::ReadSceneFile(kSample / "scene.toml");
  models::ReducedOptions options;
  options.mesh.resolution = 1e-3;
  options.progress = false;
  const ReducedSimulation run = SimulateReduced(scene, options, "");
  ASSERT_EQ(run.result.status, RunStatus::kOk) << run.result.message;
  EXPECT_NEAR(run.resolution, 1e-3, 1e-12);
  EXPECT_GT(run.elements, 0);
  EXPECT_FALSE(run.cache_hit);
  EXPECT_EQ(run.result.figures.at("model_cache_hit"), 0.0);

  WorkDir dir;
  const fs::path csv = dir.path / "sim.csv";
  WriteSimulationCsv(csv.string(), run.result);
  const io::CsvTable table = io::ReadCsvTable(csv);
  ASSERT_EQ(table.rows(), run.result.points.size());
  const auto a = table.ColumnSi("crack_length", Dimension::Length());
  const auto R = table.ColumnSi("R", Dimension::EnergyPerArea());
  const auto load = table.ColumnSi("load", Dimension::Force());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a[i], run.result.points[i].crack_length, 1e-12);
    EXPECT_NEAR(R[i], run.result.points[i].R, 1e-8 * std::abs(run.result.points[i].R));
    EXPECT_NEAR(load[i], run.result.points[i].load, 1e-8 * std::abs(run.result.points[i].load));
  }
  const std::string text = run.BriefReport();
  EXPECT_EQ(text.rfind("model reduced (ok): ", 0), 0u) << text;
  EXPECT_NE(text.find(SimulationTable(run.result)), std::string::npos);
}

TEST(SimulateWorkflow, ReducedModelNeedsFractureAndGrowth) {
  Scene scene = io::ReadSceneFile(kSample / "scene.toml");
  scene.run.grow = false;
  try {
    SimulateReduced(scene, {}, "");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kInput);
    EXPECT_EQ(e.context().field, "run.grow");
  }
}

TEST(SimulateWorkflow, MpmGrowthIsTheGrowthSimulationOfTheScene) {
  const Scene scene =
      io::ReadSceneFile(fs::path(BRIDGEFIT_SOURCE_DIR) / "tests" / "data" / "scenes" / "ct_mdf.toml");
  mpm::GrowthOptions options;
  options.cell = 5e-3;
  options.threads = 1;
  const mpm::GrowthResult run = SimulateMpmGrowth(scene, options);
  const std::optional<laws::BridgingLaw> law =
      scene.bridging ? std::optional<laws::BridgingLaw>(scene.bridging->Law()) : std::nullopt;
  const mpm::GrowthResult direct =
      mpm::SimulateGrowth(scene, law ? &*law : nullptr, scene.fracture->J_tip_c, options);
  ASSERT_EQ(run.result.status, RunStatus::kOk) << run.result.message;
  ASSERT_EQ(run.result.points.size(), direct.result.points.size());
  for (std::size_t i = 0; i < direct.result.points.size(); ++i)
    EXPECT_EQ(run.result.points[i].R, direct.result.points[i].R) << i;
  const std::string text = MpmGrowthBriefReport(run);
  EXPECT_EQ(text.rfind("model mpm (ok), quasi-static ", 0), 0u) << text;
  EXPECT_NE(text.find(SimulationTable(run.result)), std::string::npos);
}

TEST(SimulateWorkflow, MpmStationaryRunWritesItsFilesAndHistory) {
  const Scene scene = io::ReadSceneFile(fs::path(BRIDGEFIT_SOURCE_DIR) / "tests" / "data" /
                                        "mpm" / "ct_stationary.toml");
  mpm::SolverOptions options;
  options.threads = 1;
  options.target_displacement = *scene.run.load_point_displacement;
  WorkDir dir;
  const fs::path h5 = dir.path / "run.h5";
  const MpmStationaryRun run = SimulateMpmStationary(scene, 5e-3, 2, options, h5.string());
  ASSERT_EQ(run.summary.status, RunStatus::kOk) << run.summary.message;
  EXPECT_TRUE(fs::exists(h5));
  EXPECT_TRUE(fs::exists(run.xdmf_path)) << run.xdmf_path;
  EXPECT_EQ(run.contour_cells, options.contour_cells);
  EXPECT_FALSE(run.description.empty());
  ASSERT_FALSE(run.summary.history.empty());
  // The history CSV: one row per sample, one J column per contour.
  const fs::path csv = dir.path / "history.csv";
  WriteMpmHistoryCsv(csv.string(), run.summary, run.contour_cells);
  const io::CsvTable table = io::ReadCsvTable(csv);
  EXPECT_EQ(table.rows(), run.summary.history.size());
  EXPECT_EQ(table.names.size(), 6 + run.contour_cells.size());
}

TEST(SimulateWorkflow, MpmHistoryCsvNamesEachContour) {
  mpm::Summary summary;
  mpm::HistorySample sample;
  sample.time = 1e-3;
  sample.load = 10.0;
  sample.J = {1.5, 2.5};
  summary.history.push_back(sample);
  const std::string text = MpmHistoryCsv(summary, {3, 5});
  std::istringstream in(text);
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  EXPECT_EQ(header,
            "time_s,load_N,displacement_m,load_line_cod_m,kinetic_J,strain_J,"
            "J_3cells_J_per_m2,J_5cells_J_per_m2");
  EXPECT_EQ(row.rfind("0.001,10,", 0), 0u) << row;
  EXPECT_TRUE(row.ends_with(",1.5,2.5")) << row;
}

}  // namespace
}  // namespace bridgefit::pipeline
