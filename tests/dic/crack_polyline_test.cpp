// The crack path as a polyline where a straight line fits badly: a kinked
// crack (exact displacement jump across two segments) gives two segments
// meeting at the kink; a straight crack stays a line.
#include <cmath>
#include <numbers>
#include <gtest/gtest.h>

#include "bridgefit/dic/crack_path.hpp"
#include "exact_crack_field.hpp"

namespace bridgefit::dic {
namespace {

// Opening jump across the path y = y(x) falling as sqrt(200 - x) to zero at
// the tip x = 200 (so the notch is on the left), on a 2 px grid, with a rigid
// drift; `kink_deg` is the second segment's angle from x = 100 on.
DisplacementField Kinked(double kink_deg) {
  const double t = std::tan(kink_deg * std::numbers::pi / 180);
  auto path_y = [t](double x) { return 100.0 + (x > 100 ? (x - 100) * t : 0.0); };
  return test_fields::ExactOpeningField(path_y);  // tip at x = 200
}

CrackPathOptions Options() {
  CrackPathOptions o;
  o.station_spacing_px = 2;
  o.gap_px = 3;
  o.side_depth_px = 6;
  o.curved_rms_px = 2;
  return o;
}

TEST(CrackPolyline, KinkedCrackGivesTwoSegmentsMeetingAtTheKink) {
  const CrackPathResult r = FindCrackPath(Kinked(25), Options());
  ASSERT_TRUE(r.found) << r.why_not_found;
  EXPECT_TRUE(r.curved) << r.BriefReport();
  EXPECT_GT(r.line_rms_all_px, 2.0);
  ASSERT_EQ(r.polyline_x.size(), 3u) << r.BriefReport();
  EXPECT_NEAR(r.polyline_x[1], 100, 4) << r.BriefReport();
  EXPECT_NEAR(r.polyline_y[1], 100, 2) << r.BriefReport();
  // The last vertex on the kinked segment, near the tip.
  const double t = std::tan(25 * std::numbers::pi / 180);
  EXPECT_NEAR(r.polyline_y[2], 100 + (r.polyline_x[2] - 100) * t, 1.5);
  EXPECT_LT(r.polyline_rms_px, 1.0);
}

TEST(CrackPolyline, StraightCrackStaysALine) {
  const CrackPathResult r = FindCrackPath(Kinked(0), Options());
  ASSERT_TRUE(r.found) << r.why_not_found;
  EXPECT_FALSE(r.curved) << r.BriefReport();
  EXPECT_LT(r.line_rms_all_px, 1.0);
  EXPECT_TRUE(r.polyline_x.empty());
}

TEST(CrackPolyline, FitThroughPointsOfThreeSegments) {
  std::vector<double> x, y;
  for (int i = 0; i <= 60; ++i) {  // (0,0)-(20,0)-(40,10)-(60,10)
    const double xx = i;
    x.push_back(xx);
    y.push_back(xx <= 20 ? 0 : xx <= 40 ? (xx - 20) * 0.5 : 10);
  }
  std::vector<double> vx, vy;
  double rms;
  FitCrackPolyline(x, y, 1.0, 3, &vx, &vy, &rms);
  ASSERT_EQ(vx.size(), 4u);
  EXPECT_NEAR(vx[1], 20, 0.5);
  EXPECT_NEAR(vy[1], 0, 0.5);
  EXPECT_NEAR(vx[2], 40, 0.5);
  EXPECT_NEAR(vy[2], 10, 0.5);
  EXPECT_LT(rms, 0.3);
}

}  // namespace
}  // namespace bridgefit::dic
