// `bridgefit simulate --model reduced`: the JSON contract of issue 3 and
// clear errors for bad scenes.

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace {

struct CliRun {
  int exit_code = -1;
  std::string out, err;
};

CliRun RunBridgefit(const std::string& args) {
  const auto err_file = std::filesystem::temp_directory_path() /
                        ("bf_simulate_test_" + std::to_string(::testing::UnitTest::GetInstance()
                                                                  ->random_seed()) + ".err");
  const std::string command = std::string(BRIDGEFIT_CLI) + " " + args + " 2>" + err_file.string();
  CliRun run;
  FILE* pipe = popen(command.c_str(), "r");
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.out.append(buffer.data(), n);
  const int status = pclose(pipe);
  run.exit_code = WEXITSTATUS(status);
  std::ifstream in(err_file);
  std::stringstream text;
  text << in.rdbuf();
  run.err = text.str();
  std::filesystem::remove(err_file);
  return run;
}

const std::string kData = std::string(BRIDGEFIT_TEST_DATA_DIR) + "/models/";

TEST(SimulateCli, ReducedJsonHasTheDocumentedKeys) {
  const CliRun r = RunBridgefit("simulate " + kData + "ct_linear_1mpa.toml --model reduced "
                       "--resolution '1 mm' --json --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["model"], "reduced");
  EXPECT_GT(j["wall_s"].get<double>(), 0.0);
  ASSERT_TRUE(j["steady_state_reached"].get<bool>());
  EXPECT_NEAR(j["steady_state_crack_length_m"].get<double>(), 0.071, 0.002);
  EXPECT_GT(j["initiation_load_N"].get<double>(), 1000.0);
  const auto& points = j["points"];
  ASSERT_EQ(points.size(), 51u);  // 30 .. 80 mm every 1 mm
  for (const char* key : {"crack_length_m", "R_J_per_m2", "R_energy_J_per_m2", "J_tip_J_per_m2",
                          "J_ff_J_per_m2", "delta_root_m", "root_position_m", "load_N",
                          "displacement_m"})
    EXPECT_TRUE(points[10].contains(key)) << key;
  EXPECT_NEAR(points.back()["R_J_per_m2"].get<double>(), 2710.0, 1e-6);
  EXPECT_NEAR(points[0]["J_tip_J_per_m2"].get<double>(), 2210.0, 1e-6);
}

TEST(SimulateCli, BadScenesGiveClearErrors) {
  CliRun r = RunBridgefit("simulate " + kData + "ct_shallow_notch.toml --json");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(r.err.find("a0/W"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("specimen.notch"), std::string::npos) << r.err;
  r = RunBridgefit("simulate " + kData + "ct_linear_1mpa.toml --resolution 1");
  EXPECT_EQ(r.exit_code, 2) << r.err;  // a bare number: usage error
  EXPECT_NE(r.err.find("--resolution"), std::string::npos) << r.err;
}

}  // namespace
