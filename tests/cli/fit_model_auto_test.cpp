// `bridgefit fit --model auto`: the CLI's job (issue 16): the model_check
// JSON and the --model-tolerance usage error. The check itself (the reduced
// fit checked with MPM at 2.5 mm, corrected by output space mapping beyond
// the tolerance) is tested as a library call: tests/pipeline/model_auto_test.cpp.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "cli_helpers.hpp"

namespace bridgefit {
namespace {

using testing::RunCli;

const std::string kSample = std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/mdf_ct/";
const std::string kFit = "fit '" + kSample + "record_exact.csv' --scene '" + kSample +
                         "scene.toml' --rcurve-load-noise 0.01N --rcurve-displacement-noise "
                         "0.01um --rcurve-crack-noise 0.001mm --law linear --resolution 1mm "
                         "--no-profile --json --quiet --model auto";

// The JSON of --model auto (the check's figures: tests/pipeline/model_auto_test.cpp).
TEST(FitModelAuto, TheJsonCarriesTheModelCheck) {
  const auto r = RunCli(kFit);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  const nlohmann::json& c = j["model_check"];
  ASSERT_TRUE(c.is_object());
  EXPECT_TRUE(c["outcome"].is_string());
  EXPECT_EQ(c["cheap_model"], "reduced");
  EXPECT_EQ(c["accurate_model"], "mpm");
  EXPECT_TRUE(c["accurate_ok"].is_boolean());
  EXPECT_TRUE(c["corrected"].is_boolean());
  EXPECT_TRUE(c["accurate_runs"].is_number_integer());
  EXPECT_TRUE(c["discrepancy_at_cheap_optimum"].is_number());
  EXPECT_TRUE(c["accurate_s"].is_number());
  EXPECT_DOUBLE_EQ(c["tolerance"].get<double>(), 0.03);
  EXPECT_DOUBLE_EQ(c["mpm_cell_m"].get<double>(), 2.5e-3);
  EXPECT_EQ(j["model"], "reduced");
}

TEST(FitModelAuto, AToleranceOutsideZeroToOneIsAUsageError) {
  const auto r = RunCli(kFit + " --model-tolerance 2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(r.err.find("--model-tolerance"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace bridgefit
