// `bridgefit fit --law compare` with the fitted-shape families (issue 21):
// every family named with its k, AICc and weight; a family with too many
// parameters for the data is skipped with a warning, never a number; the
// flags that choose them. The fits themselves: tests/inverse/fit_shape_test.cpp.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../inverse/shape_data.hpp"
#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "cli_helpers.hpp"

namespace bridgefit {
namespace {

using testing::RunCli;

const std::string kSample = std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/mdf_ct/";
// The noisy record reduced in-process: 8 R points.
const std::string kFit = "fit '" + kSample + "record.csv' --scene '" + kSample +
                         "scene.toml' --law compare --resolution 1mm --no-profile --json --quiet";

TEST(FitCompare, EveryFamilyWithItsCountAndWeight) {
  const auto r = RunCli(kFit);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const nlohmann::json& rows = j["law_comparison"];
  ASSERT_EQ(rows.size(), 7u);
  const char* laws[] = {"linear",   "cubic",     "triangular", "exponential",
                        "bilinear", "trilinear", "table"};
  double weights = 0.0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const nlohmann::json& row = rows[i];
    EXPECT_EQ(row["law"], laws[i]);
    EXPECT_TRUE(row["weight"].is_number()) << row.dump();
    weights += row["weight"].get<double>();
    if (row["law"] == "trilinear") {  // 7 parameters need 9 points
      EXPECT_TRUE(row["aicc"].is_null());
      EXPECT_TRUE(row["parameters"].is_null());
      EXPECT_EQ(row["weight"].get<double>(), 0.0);
      EXPECT_NE(
          row["note"].get<std::string>().find("8 data points are too few for its 7 parameters"),
          std::string::npos)
          << row["note"];
    } else {
      EXPECT_TRUE(row["aicc"].is_number()) << row.dump();
      EXPECT_TRUE(row["parameters"].is_number()) << row.dump();
    }
  }
  EXPECT_NEAR(weights, 1.0, 1e-12);
  EXPECT_NE(r.err.find("warning: fit: --law compare: trilinear skipped"), std::string::npos)
      << r.err;
  EXPECT_NE(rows[6]["note"].get<std::string>().find("skipped: table N = 5"), std::string::npos)
      << rows[6]["note"];
}

TEST(FitCompare, FlagsChooseTheShapeFamilies) {
  const auto none = RunCli(kFit + " --shape-families none");
  ASSERT_EQ(none.exit_code, 0) << none.err;
  EXPECT_EQ(nlohmann::json::parse(none.out)["law_comparison"].size(), 4u);
  const auto bad = RunCli(kFit + " --shape-families quadratic");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--shape-families"), std::string::npos) << bad.err;
  const auto knots = RunCli(kFit + " --table-knots 1");
  EXPECT_EQ(knots.exit_code, 2);
  EXPECT_NE(knots.err.find("table_knots"), std::string::npos) << knots.err;
}

// `fit --law table` alone on an R curve it can carry: the analytic model's
// R of a cubic law (60 points, 0.5% noise, tests/inverse/shape_data.hpp)
// written as CSV with a scene, fitted with `--model analytic`, written to a
// fit file, then `report` on it: the JSON carries the shape (its knots and
// their Wald intervals), the report draws that shape (its law table, break
// points and shape parameters), not a linear stand-in. A table the data
// cannot carry, and one knot, are errors naming the flag.
TEST(FitCompare, TableAloneThenItsReport) {
  const std::string dir = ::testing::TempDir() + "bf_fit_table_" + std::to_string(::getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  {
    std::ofstream(dir + "/scene.toml")
        << "[specimen]\ntype = \"ct\"\nwidth = \"200 mm\"\nthickness = \"10 mm\"\n"
           "notch = \"30 mm\"\n[material]\nE = \"1 GPa\"\nnu = 0.3\n";
  }
  const auto model = inverse::MakeAnalyticForwardModel(io::ReadSceneFile(dir + "/scene.toml"));
  const inverse::FitData data = inverse::testing::MakeShapeData(
      *model, 0.03, laws::MakeCubicShape(), {1.0e6, 500.0, 2210.0}, 0.11, 60, 0.005, 7);
  {
    std::ofstream csv(dir + "/rc.csv");
    csv << "crack_length [mm], R [J/m^2], R_uncertainty [J/m^2]\n";
    csv.precision(17);
    for (size_t i = 0; i < data.size(); ++i)
      csv << data.crack_length[i] * 1e3 << ", " << data.R[i] << ", " << data.R_uncertainty[i]
          << "\n";
  }
  const std::string alone = "fit '" + dir + "/rc.csv' --scene '" + dir +
                            "/scene.toml' --model analytic --law table --no-profile --quiet";
  const auto r = RunCli(alone + " --json --out '" + dir + "/fit.h5'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["law"], "table");
  EXPECT_TRUE(j["law_comparison"].empty());
  EXPECT_TRUE(j["bridging_detected"].get<bool>());
  const nlohmann::json& shape = j["law_shape"];
  EXPECT_EQ(shape["family"], "table");
  EXPECT_EQ(shape["fitted_family"], "table");
  EXPECT_EQ(shape["interpolation"], "monotone-cubic");
  const int knots = shape["knots"].get<int>();
  EXPECT_GE(knots, 3);
  EXPECT_LE(knots, 6);
  ASSERT_EQ(shape["points"].size(), static_cast<size_t>(knots + 1));
  ASSERT_EQ(shape["shape_parameters"].size(), static_cast<size_t>(knots));
  for (const nlohmann::json& p : shape["shape_parameters"])
    if (!p["pinned"].get<bool>()) {
      ASSERT_TRUE(p["standard_error"].is_number()) << p.dump();
      EXPECT_NEAR(p["wald_ci95_high"].get<double>() - p["value"].get<double>(),
                  1.96 * p["standard_error"].get<double>(), 1e-12);
    }
  EXPECT_TRUE(j["sigma_c_Pa"]["ci95_low"].is_number());
  EXPECT_EQ(j["sigma_c_Pa"]["interval_status"], "reliable");

  const auto report = RunCli("report '" + dir + "/fit.h5' --out '" + dir + "/report' --quiet");
  ASSERT_EQ(report.exit_code, 0) << report.err;
  std::ifstream page(dir + "/report/index.html");
  const std::string html((std::istreambuf_iterator<char>(page)), {});
  EXPECT_NE(html.find("id=\"law_shape\""), std::string::npos);
  EXPECT_NE(html.find("id=\"shape_parameters\""), std::string::npos);
  EXPECT_EQ(html.find("drawn with the linear shape"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir + "/report/law_points.dat"));

  const auto one = RunCli(alone + " --table-knots 1");
  EXPECT_EQ(one.exit_code, 2);
  EXPECT_NE(one.err.find("--table-knots"), std::string::npos) << one.err;
  {
    std::ofstream few(dir + "/few.csv");
    few << "crack_length [mm], R [J/m^2]\n31,2300\n33,2450\n36,2550\n40,2650\n45,2700\n50,2710\n";
  }
  const auto too_few = RunCli("fit '" + dir + "/few.csv' --scene '" + dir +
                              "/scene.toml' --model analytic --law table --no-profile --quiet");
  EXPECT_EQ(too_few.exit_code, 1);
  EXPECT_NE(too_few.err.find("--law"), std::string::npos) << too_few.err;
  EXPECT_NE(too_few.err.find("too few"), std::string::npos) << too_few.err;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace bridgefit
