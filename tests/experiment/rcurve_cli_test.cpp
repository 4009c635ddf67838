// `bridgefit rcurve` end to end on the real DCB record: the JSON contract of
// issue #6, the HDF5 output, and clear errors (exit 1 input, exit 2 usage).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../cli/cli_helpers.hpp"
#include "bridgefit/io/hdf5.hpp"

namespace {

using bridgefit::testing::RunCli;

const std::string kData = std::string(BRIDGEFIT_TEST_DATA_DIR) + "/experiment/DCB-01_Toughness.csv";
const std::string kSpecimen =
    "--type dcb --width 25mm --height 2.7mm --length 123mm --modulus 19.3GPa ";
const std::string kColumns =
    "--columns time=Time,displacement=Disp,load=Force,crack_length=CrackExt ";
const std::string kUnits = "--units time=s,displacement=mm,load=N,crack_length=mm ";

TEST(RcurveCli, JsonContractAndHdf5Output) {
  const auto dir = std::filesystem::temp_directory_path() / ("bf_rcurve_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto h5 = dir / "rcurve.h5";
  const auto csv = dir / "rcurve.csv";
  const auto r = RunCli("rcurve '" + kData + "' " + kSpecimen + kColumns + kUnits +
                        "--method mbt --json --out '" + h5.string() + "' --csv '" + csv.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("method"), "mbt");
  const auto& points = j.at("points");
  ASSERT_GT(points.size(), 300u);
  for (const char* key : {"crack_length_m", "crack_growth_m", "R_J_per_m2", "R_uncertainty_J_per_m2"})
    EXPECT_TRUE(points[0].contains(key)) << key;
  // Rising R curve of the data: about 0.3 kJ/m^2 at initiation, about 1 kJ/m^2 late.
  EXPECT_NEAR(j.at("initiation_R_J_per_m2").get<double>(), 270.0, 30.0);
  EXPECT_NEAR(points.back().at("R_J_per_m2").get<double>(), 1000.0, 60.0);
  EXPECT_EQ(j.at("points_used").get<int>(), static_cast<int>(points.size()));
  int dropped = 0;
  for (const auto& d : j.at("points_dropped")) {
    EXPECT_FALSE(d.at("reason").get<std::string>().empty());
    dropped += d.at("count").get<int>();
  }
  // Every row read is either used or dropped with a reason.
  EXPECT_EQ(dropped + j.at("points_used").get<int>(), j.at("rows_read").get<int>());

  const bridgefit::io::H5Reader file(h5);
  std::string units;
  const std::vector<double> R = file.ReadVector("/rcurve/R", &units);
  EXPECT_EQ(units, "J/m^2");
  ASSERT_EQ(R.size(), points.size());
  EXPECT_DOUBLE_EQ(R.back(), points.back().at("R_J_per_m2").get<double>());
  EXPECT_TRUE(file.Exists("/experiment/load"));
  std::ifstream text(csv);
  std::string header;
  std::getline(text, header);
  EXPECT_EQ(header.rfind("crack_length [mm], R [J/m^2], R_uncertainty [J/m^2]", 0), 0u) << header;
  std::filesystem::remove_all(dir);
}

TEST(RcurveCli, ClearErrors) {
  // Unknown method: usage error.
  auto r = RunCli("rcurve '" + kData + "' " + kSpecimen + kColumns + kUnits + "--method area");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("energy, mbt"), std::string::npos) << r.err;
  // No specimen at all: usage error.
  r = RunCli("rcurve '" + kData + "' " + kColumns + kUnits);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  // Missing crack-length column for a method that needs it: input error naming it.
  r = RunCli("rcurve '" + kData + "' " + kSpecimen +
             "--columns time=Time,displacement=Disp,load=Force,crack_length=Crack "
             "--units time=s,displacement=mm,load=N --method mbt");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("crack"), std::string::npos) << r.err;
  // Crack lengths declared in metres (they are mm): longer than the specimen.
  r = RunCli("rcurve '" + kData + "' " + kSpecimen + kColumns +
             "--units time=s,displacement=mm,load=N,crack_length=m --method mbt");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("unit"), std::string::npos) << r.err;
  // Load-block sizes without the large-displacement correction: usage error.
  r = RunCli("rcurve '" + kData + "' " + kSpecimen + kColumns + kUnits +
             "--method cc --block-offset 5mm");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--large-displacement"), std::string::npos) << r.err;
  // The correction is for the DCB beam methods only.
  r = RunCli("rcurve '" + kData + "' " + kSpecimen + kColumns + kUnits +
             "--method energy --large-displacement");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  // Crack lengths from images: a file that is not a DIC CSV (no image column).
  r = RunCli("rcurve '" + kData + "' " + kSpecimen + kColumns + kUnits + "--crack-length-from '" +
             kData + "'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("image"), std::string::npos) << r.err;
  // The record names no images: nothing to match the frames to.
  const std::string frames = (std::filesystem::temp_directory_path() / "bf_rcurve_frames.csv").string();
  { std::ofstream(frames) << "frame, image, crack_length [mm]\n1, a.png, 40\n2, b.png, 45\n"; }
  r = RunCli("rcurve '" + kData + "' " + kSpecimen + kColumns + kUnits + "--crack-length-from '" +
             frames + "'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("names no images"), std::string::npos) << r.err;
  std::filesystem::remove(frames);
}

// D5528's F/N corrections from the command line: reported in `figures`
// (d/a reaches 0.30 on DCB-01, F >= 0.973 with t = 0) and they change R.
TEST(RcurveCli, LargeDisplacementOption) {
  const std::string base =
      "rcurve '" + kData + "' " + kSpecimen + kColumns + kUnits + "--method cc --json ";
  const auto plain = RunCli(base);
  const auto corrected =
      RunCli(base + "--large-displacement --block-offset 0mm --block-half-length 0mm");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(corrected.exit_code, 0) << corrected.err;
  const nlohmann::json p = nlohmann::json::parse(plain.out);
  const nlohmann::json c = nlohmann::json::parse(corrected.out);
  EXPECT_FALSE(p.at("figures").contains("d5528_F_min"));
  EXPECT_NEAR(c.at("figures").at("d5528_F_min").get<double>(), 0.9728, 5e-4);
  EXPECT_NEAR(c.at("figures").at("d5528_N_min").get<double>(), 0.9767, 5e-4);
  // 2.7103 before issue 15, when the record was cut at its first displacement
  // "unloading" (338 propagation rows, now 343: docs/RCURVE_METHODS.md).
  EXPECT_NEAR(c.at("figures").at("cc_n").get<double>(), 2.7126, 5e-4);
  ASSERT_EQ(p.at("points").size(), c.at("points").size());
  const double last_plain = p.at("points").back().at("R_J_per_m2").get<double>();
  const double last_corrected = c.at("points").back().at("R_J_per_m2").get<double>();
  EXPECT_GT(last_corrected / last_plain - 1.0, 0.001);  // n rises with the C/N fit
}

}  // namespace
