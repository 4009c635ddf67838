// `fit --law compare` reported wall_s of 1-3 s for commands that took 4-17 s
// (issue 15): the time was the best family's fit only. The run's wall_s must
// cover the whole comparison: at least the sum of the families' own times,
// and at most the time measured around the call.
#include "bridgefit/core/progress.hpp"
#include "bridgefit/experiment/rcurve.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/fit.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace bridgefit::pipeline {
namespace {

TEST(CompareWallTime, CoversEveryFamily) {
  io::RecordColumns columns;
  io::ApplyColumnMapping("time=Time,displacement=Disp,load=Force,crack_length=CrackExt", columns);
  io::ApplyUnitMapping("time=s,displacement=mm,load=N,crack_length=mm", columns);
  FitRequest request;
  request.record =
      io::ReadRecordCsv(std::string(BRIDGEFIT_TEST_DATA_DIR) + "/experiment/DCB-01_Toughness.csv", columns);
  request.scene_path = std::string(BRIDGEFIT_SOURCE_DIR) + "/data_samples/dcb_composite/scene.toml";
  request.scene = io::ReadSceneFile(request.scene_path);
  request.model = ModelChoice::kAnalytic;  // quick: the time bookkeeping does not depend on the model
  request.compare_laws = true;
  request.fit.profile_likelihood = false;
  request.shape_fit.table_knots = {3, 4};  // the fitted-shape families too, kept short
  request.reduction.method = experiment::RMethod::kMbt;
  request.reduction_given = true;
  const Stopwatch watch;
  const FitRun run = RunFit(request);
  const double outside = watch.Seconds();
  ASSERT_GE(run.comparison.size(), 3u);
  double families = 0.0;
  for (const auto& c : run.comparison) families += c.summary.wall_s;
  EXPECT_GE(run.summary.wall_s, families);
  EXPECT_LE(run.summary.wall_s, outside);
  for (const auto& c : run.comparison) std::printf("  %s %.3f s, %d evaluations\n", c.law.c_str(), c.summary.wall_s, c.summary.evaluations);
  std::printf("compare: %zu families, wall_s %.3f s, families' sum %.3f s, around the call %.3f s\n",
              run.comparison.size(), run.summary.wall_s, families, outside);
}

}  // namespace
}  // namespace bridgefit::pipeline
