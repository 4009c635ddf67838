// Replays tests/fuzz/regressions through the real readers (and the CLI for
// HDF5): every input that once crashed, hit undefined behaviour or read
// without limit must now end in a clean bridgefit::Error.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../cli/cli_helpers.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/dic/fields.hpp"
#include "bridgefit/dic/image.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "h5_inputs.hpp"

namespace bridgefit {
namespace {

namespace fs = std::filesystem;
const fs::path kRegressions = BRIDGEFIT_REGRESSIONS_DIR;

std::vector<fs::path> FilesIn(const std::string& kind) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(kRegressions / kind))
    if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

std::string Slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The message of the Error `read` throws; a failure when it throws nothing.
template <class F>
std::string ErrorOf(F&& read, const fs::path& input) {
  try {
    read();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for " << input;
  return "";
}

TEST(FuzzRegressions, UnitsAreRefusedNamingTheValue) {
  const auto files = FilesIn("units");
  ASSERT_GE(files.size(), 3u);
  for (const fs::path& file : files) {
    const std::string text = Slurp(file);
    const std::string m = ErrorOf([&] { ParseQuantity(text, Dimension::Length()); }, file);
    EXPECT_NE(m.find(text), std::string::npos) << file << ": " << m;
  }
}

TEST(FuzzRegressions, WrappedUnitOnTheCommandLineExitsTwoNamingIt) {
  const std::string unit = Slurp(kRegressions / "units/wrapped_exponents.txt");
  const auto r = testing::RunCli("law --law linear --sigma-c '1 MPa' --delta-c '" + unit +
                                 "' --jtip '1 N/mm'");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("m^2147483647*m^2147483647*m^3"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--delta-c"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("exponent out of range"), std::string::npos) << r.err;
}

TEST(FuzzRegressions, SceneWithWrappedWidthIsRefusedNamingTheField) {
  const fs::path file = kRegressions / "scene/width_wrapped_unit.toml";
  const std::string m = ErrorOf([&] { io::ReadSceneFile(file); }, file);
  EXPECT_NE(m.find("specimen.width"), std::string::npos) << m;
  EXPECT_NE(m.find("exponent out of range"), std::string::npos) << m;
}

TEST(FuzzRegressions, TableLawFromDevZeroStopsAtItsSizeLimit) {
  const fs::path file = kRegressions / "scene/table_dev_zero.toml";
  const std::string m = ErrorOf([&] { io::ReadSceneFile(file); }, file);
  EXPECT_NE(m.find("/dev/zero"), std::string::npos) << m;
  EXPECT_NE(m.find("BRIDGEFIT_MAX_TABLE_BYTES"), std::string::npos) << m;
}

TEST(FuzzRegressions, CsvRecordsAreRefused) {
  for (const fs::path& file : FilesIn("csv")) {
    const std::string m = ErrorOf([&] { io::ReadRecordCsv(file, io::RecordColumns{}); }, file);
    EXPECT_FALSE(m.empty()) << file;
  }
}

TEST(FuzzRegressions, ImagesAreRefused) {
  for (const fs::path& file : FilesIn("image")) {
    const std::string m = ErrorOf([&] { dic::ReadImage(file); }, file);
    EXPECT_FALSE(m.empty()) << file;
  }
}

// Ncorr MAT files the fuzzer made, read as `bridgefit crack` reads them (a
// v7.3 file, HDF5, in a child first): an Error naming the file, never a
// crash. Two findings: a v5 struct whose field table matio left null (a SEGV
// in Mat_VarGetStructFieldByName), and a v7.3 file on which libhdf5's
// H5HG_read copies overlapping gigabyte ranges (in-process only).
TEST(FuzzRegressions, NcorrFilesAreRefused) {
  const auto files = FilesIn("ncorr");
  ASSERT_GE(files.size(), 2u);
  for (const fs::path& file : files) {
    const std::string m = ErrorOf(
        [&] {
          if (dic::IsMatFile(file))
            io::CheckH5FileInChildProcess(file, 5.0, [&file] { dic::ReadEveryNcorrFrame(file); });
          const dic::NcorrFile ncorr(file);
          for (std::size_t k = 0; k < ncorr.Frames(); ++k) (void)ncorr.Frame(k);
        },
        file);
    EXPECT_NE(m.find(file.filename().string()), std::string::npos) << m;
  }
}

// The CLI on a folder of them (a folder or glob names files that main's
// own check of the command line does not see): exit 1 with a message.
TEST(FuzzRegressions, NcorrFolderExitsOneFromCrack) {
  const fs::path dir = fs::temp_directory_path() / ("bf_fuzz_ncorr_" + std::to_string(getpid()));
  for (const fs::path& file : FilesIn("ncorr")) {
    SCOPED_TRACE(file.string());
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::copy_file(file, dir / "run.mat");
    const auto r = testing::RunCli("crack '" + dir.string() + "' --scale 0.1mm/px --quiet");
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("error:"), std::string::npos) << r.err;
  }
  fs::remove_all(dir);
}

// In-process, after the child-process check, through every HDF5 reader: a
// corrupt file is an Error (or some kinds read and others refuse), never a
// crash. Every file here must be refused as a test record.
// Field exports are valid data here (both read), but once made PointSpacing
// cast a 3e14 bucket count to int (subsets on one line: zero area) or divide
// an overflowing span: the spacing must come out finite and, for the DICe
// column of subsets 10 px apart, exactly 10 px.
TEST(FuzzRegressions, FieldExportsGiveAFiniteNodeSpacing) {
  const auto files = FilesIn("fields");
  ASSERT_GE(files.size(), 2u);
  for (const fs::path& file : files) {
    try {
      const dic::FieldFile f = dic::ReadFieldText(Slurp(file), file.string());
      const double spacing = dic::PointSpacing(f.field);
      EXPECT_TRUE(std::isfinite(spacing) && spacing >= 0) << file << ": " << spacing;
      if (file.filename() == "dice_subsets_on_one_line.txt") {
        EXPECT_DOUBLE_EQ(spacing, 10.0);
      }
    } catch (const Error&) {  // a clean refusal is fine too
    }
  }
}

TEST(FuzzRegressions, Hdf5FilesReadAsEveryKindWithoutCrashing) {
  const auto files = FilesIn("h5");
  ASSERT_GE(files.size(), 8u);
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.string());
    try {
      (void)fuzz::ReadAsEveryH5Input(file, true);
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::kInput) << e.what();
    }
  }
}

// The CLI: each corrupt file given to rcurve, fit and report exits 1 with a
// message, none with a signal, and writes no output.
TEST(FuzzRegressions, Hdf5FilesExitOneFromEveryCommand) {
  const fs::path out = fs::temp_directory_path() / ("bf_fuzz_regressions_" + std::to_string(getpid()));
  fs::create_directories(out);
  const std::string scene = std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/mdf_ct/scene.toml";
  for (const fs::path& file : FilesIn("h5")) {
    SCOPED_TRACE(file.string());
    const std::string in = "'" + file.string() + "'";
    for (const std::string& args :
         {"rcurve " + in + " --scene '" + scene + "' --out '" + (out / "r.h5").string() + "'",
          "fit " + in + " --scene '" + scene + "' --out '" + (out / "f.h5").string() + "'",
          "report " + in + " --out '" + (out / "report").string() + "'"}) {
      const auto r = testing::RunCli(args + " --quiet");
      EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.err;
      EXPECT_NE(r.err.find("error:"), std::string::npos) << args << "\n" << r.err;
    }
    EXPECT_FALSE(fs::exists(out / "r.h5"));
    EXPECT_FALSE(fs::exists(out / "f.h5"));
  }
  fs::remove_all(out);
}

}  // namespace
}  // namespace bridgefit
