// Crack band: only the grid points the crack needs are correlated (a strip
// along the line for the path search and the COD profile, a disk around the
// last tip for the Williams window), the band follows the tip, and the crack
// lengths are those of the full field.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <gtest/gtest.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/image.hpp"
#include "bridgefit/dic/sequence.hpp"

namespace bridgefit::dic {
namespace {
namespace fs = std::filesystem;

const fs::path kFrames = fs::path(BRIDGEFIT_SOURCE_DIR) / "data_samples" / "mdf_ct" / "images";

TEST(CrackBand, StripAndDiskGeometry) {
  DisplacementField g;
  for (int y = 0; y <= 100; ++y)
    for (int x = 0; x <= 100; ++x) {
      g.x.push_back(x);
      g.y.push_back(y);
    }
  const CrackLine line{10, 50, 90, 50};
  // Tip known at (60, 50): strip |y - 50| <= 5 from x = 5 on, disk r <= 20.
  const std::vector<char> on = CrackBandPoints(g, line, true, 60, 50, 5, 20);
  size_t count = 0, expected = 0;
  for (size_t i = 0; i < g.size(); ++i) {
    const bool strip = g.x[i] >= 5 && std::abs(g.y[i] - 50) <= 5;
    const bool disk = (g.x[i] - 60) * (g.x[i] - 60) + (g.y[i] - 50) * (g.y[i] - 50) <= 400;
    expected += strip || disk ? 1 : 0;
    count += on[i] ? 1 : 0;
    EXPECT_EQ(on[i] != 0, strip || disk) << g.x[i] << "," << g.y[i];
  }
  EXPECT_EQ(count, expected);
  // Tip unknown: the strip is as wide as the disk.
  const std::vector<char> wide = CrackBandPoints(g, line, false, 0, 0, 5, 20);
  for (size_t i = 0; i < g.size(); ++i)
    EXPECT_EQ(wide[i] != 0, g.x[i] >= -10 && std::abs(g.y[i] - 50) <= 20);
}

TEST(CrackBand, InactivePointsAreMaskedAndCostNothing) {
  CorrelationOptions c;
  c.subset_size = 31;
  c.step = 10;
  const Image ref = ReadImage(kFrames / "frame_00.png");
  Correlator full(c, ref), half(c, ref);
  std::vector<char> active(half.Grid().size(), 0);
  size_t on = 0;
  for (size_t i = 0; i < active.size(); ++i)
    if (half.Grid().y[i] < 120) active[i] = 1, on += half.Grid().status[i] == PointStatus::kUnreached;
  half.SetActive(active);
  const Image frame = ReadImage(kFrames / "frame_03.png");
  CorrelationSummary sf, sh;
  const DisplacementField a = full.Next(frame, &sf);
  const DisplacementField b = half.Next(frame, &sh);
  EXPECT_EQ(sh.points, on);
  EXPECT_LT(sh.points, sf.points);
  for (size_t i = 0; i < b.size(); ++i) {
    if (!active[i]) {
      EXPECT_EQ(b.status[i], PointStatus::kMasked);
    } else if (a.ok(i) && b.ok(i)) {
      // Same point, other neighbours' guesses: equal within the IC-GN stop
      // criterion (convergence_px = 1e-3).
      EXPECT_NEAR(a.u[i], b.u[i], 2e-3);
      EXPECT_NEAR(a.v[i], b.v[i], 2e-3);
    }
  }
  EXPECT_THROW(half.SetActive(std::vector<char>(3, 1)), Error);
}

// The MDF sample frames (400 x 300 px, crack on y = 150): the band run gives
// the full field's lengths with fewer points correlated.
TEST(CrackBand, SameLengthsAsTheFullField) {
  std::vector<fs::path> images;
  for (int k : {0, 2, 4, 6, 8, 9}) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%02d.png", k);
    images.push_back(kFrames / name);
  }
  CrackSequenceOptions o;
  SetGridDefaults(31, 5, &o);
  o.scale_m_per_px = 0.15e-3;
  o.offset_m = 20e-3;
  o.show_progress = false;
  o.tip.line = {0, 150, 399, 150};
  // A smaller Williams window and path search than the defaults, so the band
  // is smaller than this small image.
  o.tip.fit_radius_px = o.tip.sqrt_window_px = 60;
  o.path.search_half_width_px = 20;
  for (bool line : {true, false}) {
    SCOPED_TRACE(line ? "line given" : "no line");
    o.has_line = line;
    CrackSequenceOptions f = o;
    f.full_field = true;
    const CrackSequenceResult band = AnalyzeCrackSequence(images, o);
    const CrackSequenceResult full = AnalyzeCrackSequence(images, f);
    std::printf("%s: band %.0f points per frame, full %.0f (%s)\n", line ? "line" : "no line",
                band.mean_correlated_points, full.mean_correlated_points, band.BriefReport().c_str());
    EXPECT_LT(band.mean_correlated_points, 0.85 * full.mean_correlated_points);
    ASSERT_EQ(band.frames.size(), full.frames.size());
    for (size_t k = 1; k < band.frames.size(); ++k) {
      const FrameResult& b = band.frames[k];
      const FrameResult& a = full.frames[k];
      ASSERT_EQ(b.has_length, a.has_length) << b.image;
      if (!a.has_length) continue;
      EXPECT_NEAR(b.crack_length_raw_m * 1e3, a.crack_length_raw_m * 1e3, 0.1) << b.image;
      // The first growth step (10 mm = 67 px here) may exceed the initial
      // margin of 4 grid steps and is flagged; then the margin is twice the
      // largest step seen.
      if (k >= 3) EXPECT_FALSE(b.tip_beyond_band) << b.image;
      std::printf("  %s: band %.3f mm, full %.3f mm, points %zu / %zu\n", b.image.c_str(),
                  b.crack_length_raw_m * 1e3, a.crack_length_raw_m * 1e3, b.correlation.points,
                  a.correlation.points);
    }
  }
}

}  // namespace
}  // namespace bridgefit::dic
