// The messages of issue 15's "What was seen", end to end through the CLI:
// each names the file, the field, the stage and the way out (the text is
// checked), exit 1 for bad input and 2 for bad usage; and the cleaning's
// counts and warnings reach the JSON and stderr.
// bridgefit headers first: <signal.h> (via gtest) defines a macro si_value.
#include "bridgefit/io/hdf5.hpp"

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

// DCB-01 with a 40-row unload-reload after row 199 at the same crack length.
std::string WriteCycleRecord(const fs::path& dir) {
  std::ifstream in(kDcb);
  std::ofstream out(dir / "cycle.csv");
  std::string line;
  int row = 0;
  while (std::getline(in, line)) {
    out << line << "\n";
    if (++row == 200) {
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
  return (dir / "cycle.csv").string();
}

// Rows by reason, and the count of those whose reason holds `word`.
int CountWith(const nlohmann::json& dropped, const std::string& word, int* total) {
  int c = 0;
  for (const auto& d : dropped) {
    const std::string reason = d.at("reason");
    if (reason.find(word) != std::string::npos) c += d.at("count").get<int>();
    if (total) *total += d.at("count").get<int>();
  }
  return c;
}

// `simulate --model mpm` without a density: the quasi-static growth run
// needs none (docs/FORMATS.md lists it as optional); it said "density must be
// positive (got '0')".
TEST(Issue15Messages, MpmGrowthRunsWithoutDensity) {
  const fs::path scene = TempDir() / "no_density.toml";
  std::ifstream in(std::string(BRIDGEFIT_SOURCE_DIR) + "/tests/data/scenes/ct_mdf.toml");
  std::ofstream out(scene);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("density", 0) != 0) out << line << "\n";
  out.close();
  const auto r = RunCli("simulate '" + scene.string() + "' --model mpm --cell '5 mm' --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("density"), std::string::npos) << r.err;
  EXPECT_FALSE(nlohmann::json::parse(r.out).at("points").empty());
}

// A real glitch and an injected cycle: counted by rule in the JSON, and a
// rule over 5% warns on stderr naming its option.
TEST(Issue15Messages, CleaningCountsInJsonAndWarnsOnStderr) {
  const std::string file = WriteCycleRecord(TempDir());
  const auto r = RunCli("rcurve '" + file + "' --scene '" + kScene + "'" + kMap + "--method mbt --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  int total = 0;
  const int cycle = CountWith(j.at("points_dropped"), "unload-reload", &total);
  EXPECT_GE(cycle, 38);
  EXPECT_LE(cycle, 40);
  EXPECT_EQ(CountWith(j.at("points_dropped"), "glitch", nullptr), 1);  // DCB-01's own spike at row 372
  EXPECT_EQ(total + j.at("points_used").get<int>(), j.at("rows_read").get<int>());
  // 40 of 416 rows (9.6%): the rule warns, naming its option.
  ExpectMentions(r.err, {"warning", "unload-reload cycle", "--reversal-tolerance"});
  EXPECT_FALSE(j.at("warnings").empty());
}

// The same counts reach every output of `fit` on a record (JSON, HDF5 and
// the report's notes), and of the README chain (rcurve --out, then fit of
// that file). The analytic model keeps it quick: the counts do not depend on it.
TEST(Issue15Messages, DroppedRowsByReasonInFitJsonHdf5AndReport) {
  const fs::path dir = TempDir();
  const std::string file = WriteCycleRecord(dir);
  const std::string common = " --scene '" + kScene + "' --model analytic --law linear --no-profile --json";
  const auto direct = RunCli("fit '" + file + "'" + kMap + "--rcurve-method mbt" + common + " --out '" +
                             (dir / "fit.h5").string() + "' --report '" + (dir / "report").string() + "'");
  ASSERT_EQ(direct.exit_code, 0) << direct.err;
  const nlohmann::json data = nlohmann::json::parse(direct.out).at("data");
  int total = 0;
  const int cycle = CountWith(data.at("points_dropped"), "unload-reload", &total);
  EXPECT_GE(cycle, 38);
  EXPECT_LE(cycle, 40);
  EXPECT_EQ(total, data.at("points_dropped_total").get<int>());
  EXPECT_EQ(total + data.at("points_used").get<int>(), data.at("rows_read").get<int>());
  // The text output says it too.
  const auto text = RunCli("fit '" + file + "'" + kMap + "--rcurve-method mbt --scene '" + kScene +
                           "' --model analytic --law linear --no-profile");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  ExpectMentions(text.out, {"record rows giving no R point", "unload-reload cycle"});

  // README chain: the counts travel through rcurve.h5 into the fit file.
  const std::string rc = (dir / "rc.h5").string();
  ASSERT_EQ(RunCli("rcurve '" + file + "' --scene '" + kScene + "'" + kMap + "--method mbt --out '" + rc + "'")
                .exit_code,
            0);
  const auto chain = RunCli("fit '" + rc + "'" + common + " --out '" + (dir / "fit2.h5").string() +
                            "' --report '" + (dir / "report2").string() + "'");
  ASSERT_EQ(chain.exit_code, 0) << chain.err;
  int chain_total = 0;
  EXPECT_EQ(CountWith(nlohmann::json::parse(chain.out).at("data").at("points_dropped"), "unload-reload",
                      &chain_total),
            cycle);
  EXPECT_EQ(chain_total, total);

  for (const char* run : {"", "2"}) {
    // HDF5: the counts read back by reason.
    const bridgefit::io::H5Reader h5((dir / ("fit" + std::string(run) + ".h5")).string());
    const std::vector<std::string> reasons = h5.ReadStrings("/rcurve/dropped_reasons");
    const std::vector<double> counts = h5.ReadVector("/rcurve/dropped_counts");
    ASSERT_EQ(reasons.size(), counts.size());
    double h5_total = 0.0, h5_cycle = 0.0;
    for (std::size_t i = 0; i < reasons.size(); ++i) {
      h5_total += counts[i];
      if (reasons[i].find("unload-reload") != std::string::npos) h5_cycle += counts[i];
    }
    EXPECT_EQ(h5_total, total) << "run " << run;
    EXPECT_EQ(h5_cycle, cycle) << "run " << run;
    // The report's notes list each reason with its count.
    std::ifstream page(dir / ("report" + std::string(run)) / "index.html");
    std::stringstream html;
    html << page.rdbuf();
    ExpectMentions(html.str(), {"record rows not used: unload-reload cycle", "R curve: 1 record rows not used: glitch"});
    EXPECT_NE(html.str().find("R curve: " + std::to_string(cycle) + " record rows not used: unload-reload"),
              std::string::npos)
        << "run " << run;
  }
}

}  // namespace
