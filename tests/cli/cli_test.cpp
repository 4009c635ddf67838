// The `bridgefit` CLI contract: exit codes, --json, errors on stderr.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli_helpers.hpp"

namespace bridgefit {
namespace {

using testing::RunCli;

TEST(Cli, VersionAndHelp) {
  auto r = RunCli("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("bridgefit 0."), std::string::npos);
  r = RunCli("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("law"), std::string::npos);
  r = RunCli("law --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--sigma-c"), std::string::npos);
  EXPECT_NE(r.out.find("--json"), std::string::npos);
}

TEST(Cli, UsageErrorsExitTwo) {
  EXPECT_EQ(RunCli("").exit_code, 2);
  EXPECT_EQ(RunCli("frobnicate").exit_code, 2);
  EXPECT_EQ(RunCli("law --no-such-option").exit_code, 2);
  const auto r = RunCli("law --sigma-c 0.45 --jb '500 J/m^2' --jtip '2210 J/m^2' --json");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;  // nothing on stdout on error, even with --json
  EXPECT_NE(r.err.find("--sigma-c"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("needs a unit"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("MPa"), std::string::npos) << r.err;
}

TEST(Cli, LawJsonHasTheDocumentedKeys) {
  const auto r = RunCli(
      "law --law linear --sigma-c '0.45 MPa' --jb '500 J/m^2' --jtip '2210 J/m^2' --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);  // exactly one JSON object
  EXPECT_EQ(j["law"], "linear");
  EXPECT_DOUBLE_EQ(j["sigma_c_Pa"].get<double>(), 0.45e6);
  EXPECT_DOUBLE_EQ(j["J_B_J_per_m2"].get<double>(), 500.0);
  EXPECT_DOUBLE_EQ(j["J_tip_c_J_per_m2"].get<double>(), 2210.0);
  const double delta_c = j["delta_c_m"].get<double>();
  EXPECT_NEAR(delta_c, 2 * 500.0 / 0.45e6, 1e-15);
  const auto& points = j["points"];
  ASSERT_EQ(points.size(), 101u);
  EXPECT_EQ(points[0]["delta_m"].get<double>(), 0.0);
  EXPECT_NEAR(points[100]["delta_m"].get<double>(), delta_c, 1e-15);
  for (const auto& p : points) {
    const double delta = p["delta_m"].get<double>();
    // Linear softening: R = J_tip,c + sigma_c delta / 2 up to delta_c.
    EXPECT_NEAR(p["R_J_per_m2"].get<double>(), 2210.0 + 0.5 * 0.45e6 * delta, 1e-6);
    EXPECT_GE(p["J_ff_J_per_m2"].get<double>(), p["R_J_per_m2"].get<double>() - 1e-9);
    EXPECT_TRUE(p.contains("sigma_Pa"));
  }
  EXPECT_NEAR(points[100]["R_J_per_m2"].get<double>(), 2710.0, 1e-9);
}

TEST(Cli, LawAcceptsAnyTwoScalesAndWritesCsv) {
  const auto csv = std::filesystem::temp_directory_path() / "bf_cli_law.csv";
  std::filesystem::remove(csv);
  const auto r = RunCli("law --law cubic --sigma-c 1MPa --delta-c 2mm --jtip 1N/mm --points 5 --csv '" +
                        csv.string() + "' --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["J_B_J_per_m2"].get<double>(), 9.0 / 16.0 * 1e6 * 2e-3, 1e-9);
  EXPECT_EQ(j["points"].size(), 5u);
  ASSERT_TRUE(std::filesystem::exists(csv));
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "delta [m], sigma [Pa], R [J/m^2], J_ff [J/m^2]");
  std::filesystem::remove(csv);
}

TEST(Cli, CsvIntoMissingFolderFailsWithoutOutput) {
  const auto r = RunCli(
      "law --sigma-c 1MPa --jb 500J/m^2 --jtip 2210J/m^2 --csv /nonexistent_dir/out.csv");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("/nonexistent_dir/out.csv"), std::string::npos) << r.err;
}

TEST(Cli, HumanReadableOutputCarriesUnits) {
  const auto r = RunCli("law --law exponential --alpha 2 --sigma-c 1MPa --jb 500J/m^2 --jtip 2210J/m^2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("delta [mm]"), std::string::npos);
  EXPECT_NE(r.out.find("R [J/m^2]"), std::string::npos);
}

}  // namespace
}  // namespace bridgefit
