// The bytes a rank sends rank 0 (src/campaign/outcome_wire.hpp). Oracle: a
// decoded outcome encodes to the same bytes (every field sent, doubles bit
// for bit, NaN included), the fields the campaign reads come back equal, and
// a truncated message or a rank's error is an Error naming the rank.
#include <gtest/gtest.h>

#include <cmath>

#include "../../src/campaign/outcome_wire.hpp"
#include "bridgefit/core/error.hpp"

namespace bridgefit::campaign {
namespace {

SpecimenOutcome Ran() {
  SpecimenOutcome s;
  s.name = "CT-2";
  s.wall_s = 1.25;
  s.rank = 1;
  s.fit_file = std::string("\x89HDF\r\n\x1a\n\0binary", 14);
  pipeline::FitRun& run = s.run.emplace();
  run.r_kind = inverse::RKind::kElasticZone;
  run.data.crack_length = {0.03, 0.031, 0.0325};
  run.data.R = {2200.0, 2400.5, 2600.25};
  run.resolution = 1e-3;
  run.shape = laws::MakeLinearShape();
  run.shape.d_points = {0.0, 0.5, 1.0};
  run.shape.interpolation = laws::TableInterpolation::kMonotoneCubic;
  run.model_note = "a note";
  inverse::FitSummary& f = run.summary;
  f.law = "linear";
  f.converged = true;
  f.chi2 = 0.1 + 0.2;  // not a short decimal
  f.sigma_c.value = 1.0e6 / 3.0;
  f.sigma_c.ci95_low = NAN;
  f.sigma_c.interval_status = inverse::IntervalStatus::kOpen;
  f.sigma_c.interval_reason = "flat to the box edge";
  f.J_B.lower_bound = 534.6;
  f.J_tip_c.value = 351.9;
  f.bounds.R_max = 886.5;
  f.starts.push_back({{1, 2, 3}, {4, 5, 6}, 0.5, 42, "xtol"});
  inverse::Profile p;
  p.parameter = 2;
  p.points.push_back({351.0, 0.2, true, {1, 2, 351.0}});
  p.status_reason = "smooth";
  f.profiles.push_back(p);
  f.fitted_R = {2210.0, NAN};
  f.best_parameters = {1e6, 500.0, 2210.0};
  run.load_data.emplace().load = {1.0, 2.0};
  run.calibration.modulus_factor = 1.0 / 3.0 + 1.0;
  run.calibration.series_compliance = 2e-7 / 3.0;
  return s;
}

std::vector<SpecimenOutcome> Empty() {
  std::vector<SpecimenOutcome> v(3);
  v[0].name = "CT-1", v[1].name = "CT-2", v[2].name = "bad";
  return v;
}

TEST(OutcomeWire, ADecodedOutcomeEncodesToTheSameBytes) {
  std::vector<SpecimenOutcome> sent = Empty();
  sent[1] = Ran();
  sent[2].error = "record bad.csv: not a number";
  sent[2].rank = 1;
  const std::string bytes = wire::EncodeOutcomes(sent, {1, 2});
  std::vector<SpecimenOutcome> got = Empty();
  wire::DecodeOutcomes(bytes, 1, got);
  EXPECT_EQ(wire::EncodeOutcomes(got, {1, 2}), bytes);
  EXPECT_FALSE(got[0].ran());  // not in the message
  ASSERT_TRUE(got[1].ran());
  const pipeline::FitRun& run = *got[1].run;
  EXPECT_EQ(got[1].fit_file, sent[1].fit_file);
  EXPECT_EQ(got[1].rank, 1);
  EXPECT_EQ(run.r_kind, inverse::RKind::kElasticZone);
  EXPECT_EQ(run.data.R, sent[1].run->data.R);
  EXPECT_EQ(run.summary.chi2, 0.1 + 0.2);
  EXPECT_EQ(run.summary.sigma_c.value, 1.0e6 / 3.0);
  EXPECT_TRUE(std::isnan(run.summary.sigma_c.ci95_low));
  EXPECT_EQ(run.summary.sigma_c.interval_status, inverse::IntervalStatus::kOpen);
  EXPECT_EQ(run.summary.J_B.lower_bound, 534.6);
  ASSERT_EQ(run.summary.profiles.size(), 1u);
  EXPECT_EQ(run.summary.profiles[0].points[0].parameters[2], 351.0);
  EXPECT_EQ(run.summary.starts[0].stop_reason, "xtol");
  EXPECT_EQ(run.shape.d_points, (std::vector<double>{0.0, 0.5, 1.0}));
  EXPECT_EQ(run.shape.interpolation, laws::TableInterpolation::kMonotoneCubic);
  ASSERT_TRUE(run.load_data.has_value());
  EXPECT_EQ(run.load_data->load, (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(run.calibration.modulus_factor, 1.0 / 3.0 + 1.0);  // the joint fit's nuisance start
  EXPECT_EQ(run.calibration.series_compliance, 2e-7 / 3.0);
  EXPECT_FALSE(got[2].ran());
  EXPECT_EQ(got[2].error, "record bad.csv: not a number");
}

TEST(OutcomeWire, ATruncatedMessageOrARanksErrorNamesTheRank) {
  std::vector<SpecimenOutcome> sent = Empty();
  sent[1] = Ran();
  const std::string bytes = wire::EncodeOutcomes(sent, {1});
  for (std::size_t cut : {std::size_t{3}, bytes.size() / 2, bytes.size() - 1}) {
    std::vector<SpecimenOutcome> got = Empty();
    try {
      wire::DecodeOutcomes(bytes.substr(0, cut), 2, got);
      ADD_FAILURE() << "no error for " << cut << " of " << bytes.size() << " bytes";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("rank 2"), std::string::npos) << e.what();
    }
  }
  std::vector<SpecimenOutcome> got = Empty();
  try {
    wire::DecodeOutcomes(wire::EncodeOutcomes(sent, {}, "no space left in /tmp"), 3, got);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("rank 3: no space left in /tmp"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace bridgefit::campaign
