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

// `fit --law table` alone on the same 8 R points, written to a fit file,
// then `report` on it: the JSON carries the shape (its knots and their
// Wald intervals), the report draws that shape (its law table and points),
// not a linear stand-in. A table the data cannot carry, and one knot, are
// errors naming the flag.
TEST(FitCompare, TableAloneThenItsReport) {
  const std::string dir = ::testing::TempDir() + "bf_fit_table_" + std::to_string(::getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string alone = "fit '" + kSample + "record.csv' --scene '" + kSample +
                            "scene.toml' --law table --resolution 1mm --no-profile --quiet";
  const auto r = RunCli(alone + " --json --out '" + dir + "/fit.h5'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["law"], "table");
  EXPECT_TRUE(j["law_comparison"].empty());
  const nlohmann::json& shape = j["law_shape"];
  EXPECT_EQ(shape["family"], "table");
  EXPECT_EQ(shape["fitted_family"], "table");
  EXPECT_EQ(shape["interpolation"], "monotone-cubic");
  const int knots = shape["knots"].get<int>();
  EXPECT_TRUE(knots == 3 || knots == 4) << knots;  // 8 points: N = 5, 6 skipped
  ASSERT_EQ(shape["points"].size(), static_cast<size_t>(knots + 1));
  ASSERT_EQ(shape["shape_parameters"].size(), static_cast<size_t>(knots));
  for (const nlohmann::json& p : shape["shape_parameters"])
    if (!p["pinned"].get<bool>() && p["standard_error"].is_number())
      EXPECT_NEAR(p["wald_ci95_high"].get<double>() - p["value"].get<double>(),
                  1.96 * p["standard_error"].get<double>(), 1e-12);
  EXPECT_TRUE(j["sigma_c_Pa"]["ci95_low"].is_number());
  EXPECT_FALSE(j["sigma_c_Pa"]["interval_status"].get<std::string>().empty());

  const auto report = RunCli("report '" + dir + "/fit.h5' --out '" + dir + "/report' --quiet");
  ASSERT_EQ(report.exit_code, 0) << report.err;
  std::ifstream page(dir + "/report/index.html");
  const std::string html((std::istreambuf_iterator<char>(page)), {});
  EXPECT_NE(html.find("id=\"law_shape\""), std::string::npos);
  EXPECT_NE(html.find("id=\"shape_parameters\""), std::string::npos);
  EXPECT_EQ(html.find("drawn with the linear shape"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir + "/report/law_points.dat"));
  std::filesystem::remove_all(dir);

  const auto one = RunCli(alone + " --table-knots 1");
  EXPECT_EQ(one.exit_code, 2);
  EXPECT_NE(one.err.find("--table-knots"), std::string::npos) << one.err;
  const auto too_many = RunCli(alone + " --table-knots 6");
  EXPECT_EQ(too_many.exit_code, 1);
  EXPECT_NE(too_many.err.find("--law"), std::string::npos) << too_many.err;
  EXPECT_NE(too_many.err.find("too few"), std::string::npos) << too_many.err;
}

}  // namespace
}  // namespace bridgefit
