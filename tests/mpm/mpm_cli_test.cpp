// `bridgefit simulate SCENE --model mpm`: the JSON contract, the HDF5 +
// XDMF output, and agreement with the library run it wraps.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/mpm/growth.hpp"
#include "bridgefit/mpm/solver.hpp"

namespace bridgefit::mpm {
namespace {

std::string RunCommand(const std::string& command, int* exit_code) {
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return out;
  std::array<char, 4096> buffer;
  while (fgets(buffer.data(), buffer.size(), pipe)) out += buffer.data();
  const int status = pclose(pipe);
  *exit_code = WEXITSTATUS(status);
  return out;
}

TEST(MpmCli, JsonHdf5AndXdmfMatchTheLibraryRun) {
  const std::string scene = std::string(BRIDGEFIT_TEST_DATA_DIR) + "/mpm/ct_stationary.toml";
  const auto dir = std::filesystem::temp_directory_path() / "bf_mpm_cli_test";
  std::filesystem::create_directories(dir);
  const auto h5 = dir / "run.h5";
  std::filesystem::remove(h5);
  int code = -1;
  const std::string out = RunCommand(std::string(BRIDGEFIT_CLI) + " simulate " + scene +
                                         " --model mpm --cell '5 mm' --threads 1 --json --out " +
                                         h5.string() + " --fields-every 1000 2>/dev/null",
                                     &code);
  ASSERT_EQ(code, 0) << out;
  const nlohmann::json j = nlohmann::json::parse(out);
  for (const char* key : {"model", "wall_s", "steps", "particles", "particle_steps_per_s",
                          "max_kinetic_to_strain_energy", "history"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["model"], "mpm");
  ASSERT_FALSE(j["history"].empty());
  for (const char* key : {"time_s", "load_N", "displacement_m", "J_J_per_m2"})
    EXPECT_TRUE(j["history"][0].contains(key)) << key;

  // The same run through the library.
  const Scene s = io::ReadSceneFile(scene);
  SolverOptions opt;
  opt.threads = 1;
  opt.target_displacement = *s.run.load_point_displacement;
  const Summary lib = Solver(BuildSpecimenModel(s, 0.005, 2), opt).Run();
  EXPECT_EQ(j["steps"].get<long>(), lib.steps);
  EXPECT_EQ(j["particles"].get<std::size_t>(), lib.particles);
  const auto& last = j["history"].back();
  EXPECT_NEAR(last["load_N"].get<double>() / lib.final_load, 1.0, 1e-12);
  EXPECT_NEAR(last["J_J_per_m2"].get<double>() / lib.final_J[0].J, 1.0, 1e-12);

  // HDF5 history and fields, and an XDMF that points into it.
  io::H5Reader reader(h5);
  std::string units;
  const auto load = reader.ReadVector("/mpm/history/load_N", &units);
  EXPECT_EQ(units, "N");
  EXPECT_EQ(load.size(), j["history"].size());
  EXPECT_TRUE(reader.Exists("/mpm/fields/step_00001000/sxx"));
  const auto xdmf = std::filesystem::path(h5).replace_extension(".xdmf");
  std::ifstream in(xdmf);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("run.h5:/mpm/fields/step_00001000/position"), std::string::npos);
  EXPECT_NE(text.str().find("Polyvertex"), std::string::npos);
}

TEST(MpmCli, GrowthSceneGivesThePointsOfTheLibraryRun) {
  const std::string scene = std::string(BRIDGEFIT_SOURCE_DIR) + "/tests/data/scenes/ct_mdf.toml";
  int code = -1;
  const std::string out = RunCommand(std::string(BRIDGEFIT_CLI) + " simulate " + scene +
                                         " --model mpm --cell '5 mm' --json 2>/dev/null",
                                     &code);
  ASSERT_EQ(code, 0) << out;
  const nlohmann::json j = nlohmann::json::parse(out);
  EXPECT_EQ(j["model"], "mpm");
  EXPECT_EQ(j["symmetry"], "half");
  for (const char* key : {"steady_state_reached", "steady_state_crack_length_m", "wall_s",
                          "particle_steps_per_s", "particles", "dofs", "J_tip_contours_J_per_m2"})
    EXPECT_TRUE(j.contains(key)) << key;
  const Scene s = io::ReadSceneFile(scene);
  const laws::BridgingLaw law = s.bridging->Law();
  GrowthOptions opt;
  opt.cell = 0.005;
  const GrowthResult lib = SimulateGrowth(s, &law, s.fracture->J_tip_c, opt);
  ASSERT_EQ(j["points"].size(), lib.result.points.size());
  for (std::size_t i = 0; i < lib.result.points.size(); ++i) {
    const auto& p = j["points"][i];
    for (const char* key : {"crack_length_m", "R_J_per_m2", "R_energy_J_per_m2", "J_tip_J_per_m2",
                            "J_ff_J_per_m2", "delta_root_m", "root_position_m", "load_N",
                            "displacement_m"})
      ASSERT_TRUE(p.contains(key)) << key;
    EXPECT_NEAR(p["R_J_per_m2"].get<double>(), lib.result.points[i].R, 1e-6);
    EXPECT_NEAR(p["load_N"].get<double>(), lib.result.points[i].load, 1e-6);
  }
}

TEST(MpmCli, ContradictoryGrowthOptionsAreUsageErrors) {
  const std::string growth = std::string(BRIDGEFIT_SOURCE_DIR) + "/tests/data/scenes/ct_mdf.toml";
  const std::string stationary =
      std::string(BRIDGEFIT_SOURCE_DIR) + "/tests/data/mpm/ct_stationary.toml";
  for (const std::string& args :
       {growth + " --model mpm --half --full", growth + " --model mpm --fields-every 10",
        stationary + " --model mpm --half"}) {
    int code = -1;
    const std::string out =
        RunCommand(std::string(BRIDGEFIT_CLI) + " simulate " + args + " --json 2>/dev/null", &code);
    EXPECT_EQ(code, 2) << args;
    EXPECT_TRUE(out.empty()) << args << ": " << out;
  }
}

}  // namespace
}  // namespace bridgefit::mpm
