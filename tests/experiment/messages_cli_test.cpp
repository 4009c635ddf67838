// The messages of issue 15's "What was seen", end to end through the CLI:
// each names the file, the field, the stage and the way out (the text is
// checked), exit 1 for bad input and 2 for bad usage; and the cleaning's
// counts and warnings reach the JSON and stderr.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "../cli/cli_helpers.hpp"

namespace {

using bridgefit::testing::RunCli;
namespace fs = std::filesystem;

const std::string kDcb = std::string(BRIDGEFIT_TEST_DATA_DIR) + "/experiment/DCB-01_Toughness.csv";
const std::string kScene = std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/dcb_composite/scene.toml";
const std::string kMap =
    " --columns time=Time,displacement=Disp,load=Force,crack_length=CrackExt"
    " --units time=s,displacement=mm,load=N,crack_length=mm ";

fs::path TempDir() {
  const fs::path dir = fs::temp_directory_path() / ("bf_msg15_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

// A small DCB-like record: linear loading, then growth (or none).
std::string WriteRecord(const fs::path& path, bool grows, bool loading_rows, int nan_rows) {
  std::ofstream out(path);
  out << "time [s], load [N], displacement [mm], crack_length [mm]\n";
  int row = 0;
  auto line = [&](double P, double d, double a, bool nan_a) {
    out << row++ << ", " << P << ", " << d << ", ";
    if (nan_a) out << "NaN\n";
    else out << a << "\n";
  };
  const int first = loading_rows ? 1 : 9;  // without: only loads near the peak
  for (int i = first; i <= 10; ++i) line(6.0 * i, 0.2 * i, 37.64, false);
  for (int i = 1; i <= 40; ++i) {
    const double a = grows ? 37.64 + 1.5 * i : 37.64;
    line(60.0 - 0.5 * i, 2.0 + 0.3 * i, a, i > 40 - nan_rows);
  }
  return path.string();
}

void ExpectMentions(const std::string& text, std::initializer_list<const char*> words) {
  for (const char* w : words) EXPECT_NE(text.find(w), std::string::npos) << "'" << w << "' in: " << text;
}

TEST(Issue15Messages, CrackLengthNeverGrowsNamesStageAndWayOut) {
  const std::string file = WriteRecord(TempDir() / "flat.csv", false, true, 0);
  const auto r = RunCli("rcurve '" + file + "' --scene '" + kScene + "' --method mbt");
  EXPECT_EQ(r.exit_code, 1);
  ExpectMentions(r.err, {"flat.csv", "field 'crack_length'", "stage 'initiation'",
                         "never grows beyond its noise", "way out", "--crack-noise"});
}

TEST(Issue15Messages, TooFewLoadingRowsNamesStageAndWayOut) {
  const std::string file = WriteRecord(TempDir() / "noload.csv", true, false, 0);
  const auto r = RunCli("rcurve '" + file + "' --scene '" + kScene + "' --method mbt");
  EXPECT_EQ(r.exit_code, 1);
  ExpectMentions(r.err, {"noload.csv", "field 'load'", "stage 'initiation'",
                         "too few loading rows", "kept after cleaning", "way out"});
}

TEST(Issue15Messages, TooFewRowsAfterCleaningListsTheRules) {
  // Two loading rows with a reading, 40 growth rows without one.
  const std::string file = WriteRecord(TempDir() / "nan.csv", true, false, 40);
  const auto r = RunCli("rcurve '" + file + "' --scene '" + kScene + "' --method mbt");
  EXPECT_EQ(r.exit_code, 1);
  ExpectMentions(r.err, {"nan.csv", "stage 'cleaning'", "too few rows left after cleaning",
                         "40 no crack length (NaN)", "--method equivalent", "way out"});
}

// The in-process energy R curve of `fit` with too few points: the file, the
// field R, the stage and the way out (it was "field 'R': a fit needs at least
// four R values (got '3 points')").
TEST(Issue15Messages, FitNamesTheInProcessRCurve) {
  const auto r = RunCli("fit '" + kDcb + "' --scene '" + kScene + "'" + kMap +
                        "--rcurve-min-increment 20mm --law linear");
  EXPECT_EQ(r.exit_code, 1);
  ExpectMentions(r.err, {"DCB-01_Toughness.csv", "field 'R'", "in-process R curve",
                         "energy method", "gave 3 R points", "--rcurve-method mbt"});
}

TEST(Issue15Messages, ModelAutoWithLoadFitRefusedFirst) {
  // A missing input file would be reported first if the check came late.
  const auto r = RunCli("fit /nonexistent.csv --scene '" + kScene +
                        "' --fit-to load-displacement --model auto");
  EXPECT_EQ(r.exit_code, 2);
  ExpectMentions(r.err, {"--model", "auto", "load-displacement"});
}

TEST(Issue15Messages, ScaleGivenAsPixelsPerLengthSuggestsTheInverse) {
  const auto r = RunCli("dic '" + std::string(BRIDGEFIT_SOURCE_DIR) +
                        "/data_samples/mdf_ct/images' --crack-line 0,0,10,0 --scale 6.667px/mm");
  EXPECT_EQ(r.exit_code, 2);
  ExpectMentions(r.err, {"--scale", "6.667px/mm", "0.149993mm/px"});
}

// A real glitch and an injected cycle: counted by rule in the JSON, and a
// rule over 5% warns on stderr naming its option.
TEST(Issue15Messages, CleaningCountsInJsonAndWarnsOnStderr) {
  const fs::path dir = TempDir();
  std::ifstream in(kDcb);
  std::ofstream out(dir / "cycle.csv");
  std::string line;
  int row = 0;
  while (std::getline(in, line)) {
    out << line << "\n";
    if (++row == 200) {  // after row 199: a 40-row unload-reload at the same crack length
      std::stringstream cells(line);
      std::string t, d, P, a;
      std::getline(cells, t, ','), std::getline(cells, d, ','), std::getline(cells, P, ',');
      std::getline(cells, a, ',');
      for (int s = 1; s <= 40; ++s) {
        const double f = s <= 20 ? s / 20.0 : (40 - s) / 20.0;
        out << t << "," << std::stod(d) * (1 - 0.9 * f) << "," << std::stod(P) * (1 - 0.9 * f)
            << "," << a << ",NaN\n";
      }
    }
  }
  out.close();
  const auto r = RunCli("rcurve '" + (dir / "cycle.csv").string() + "' --scene '" + kScene + "'" +
                        kMap + "--method mbt --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  int cycle = 0, glitch = 0, total = 0;
  for (const auto& d : j.at("points_dropped")) {
    const std::string reason = d.at("reason");
    if (reason.find("unload-reload") != std::string::npos) cycle += d.at("count").get<int>();
    if (reason.find("glitch") != std::string::npos) glitch += d.at("count").get<int>();
    total += d.at("count").get<int>();
  }
  EXPECT_GE(cycle, 38);
  EXPECT_LE(cycle, 40);
  EXPECT_EQ(glitch, 1);  // DCB-01's own spike at row 372
  EXPECT_EQ(total + j.at("points_used").get<int>(), j.at("rows_read").get<int>());
  // 40 of 416 rows (9.6%): the rule warns, naming its option.
  ExpectMentions(r.err, {"warning", "unload-reload cycle", "--reversal-tolerance"});
  EXPECT_FALSE(j.at("warnings").empty());
}

}  // namespace
