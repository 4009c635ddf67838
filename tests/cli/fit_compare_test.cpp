// `bridgefit fit --law compare` with the fitted-shape families (issue 21):
// every family named with its k, AICc and weight; a family with too many
// parameters for the data is skipped with a warning, never a number; the
// flags that choose them. The fits themselves: tests/inverse/fit_shape_test.cpp.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace bridgefit
