// Crack band: only the grid points the crack needs are correlated (a strip
// along the line for the path search and the COD profile, a disk around the
// last tip for the Williams window), the band follows the tip, and the crack
// lengths are those of the full field.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <gtest/gtest.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/image.hpp"
#include "bridgefit/dic/sequence.hpp"
#include "bridgefit/dic/speckle.hpp"

namespace bridgefit::dic {
namespace {
namespace fs = std::filesystem;

const fs::path kFrames = fs::path(BRIDGEFIT_SOURCE_DIR) / "data_samples" / "mdf_ct" / "images";

TEST(CrackBand, PointsAreWhatTheLocationReads) {
  DisplacementField g;
  for (int y = 0; y <= 100; ++y)
    for (int x = 0; x <= 100; ++x) {
      g.x.push_back(x);
      g.y.push_back(y);
    }
  CrackSequenceOptions o;
  o.path.search_half_width_px = 6;
  o.path.gap_px = 3;
  o.path.side_depth_px = 2;  // path scan: |n| <= 11
  o.path.station_spacing_px = 4;
  o.tip.band_half_width_px = 2;
  o.tip.side_depth_px = 3;  // COD: |n| <= 5
  o.tip.station_spacing_px = 4;
  o.tip.fit_radius_px = 15;
  o.correlation.step = 2;  // the window's points' grid neighbours: 1.5 steps more
  CrackBandReads reads;
  reads.scan = true;
  reads.scan_line = {20, 50, 80, 50};
  reads.cod = true;
  reads.cod_line = {20, 60, 80, 70};  // a path found off the line, tilted
  reads.window = true;
  reads.window_x = 60;
  reads.window_y = 30;
  reads.window_margin_px = 5;  // disk radius 15 + 5 + 3
  const std::vector<char> on = CrackBandPoints(g, o, reads);
  size_t count = 0;
  for (size_t i = 0; i < g.size(); ++i) {
    const double x = g.x[i], y = g.y[i];
    const bool scan = x >= 18 && x <= 82 && std::abs(y - 50) <= 11;
    // Distance from the tilted COD line and position along it.
    const double L = std::hypot(60, 10), tx = 60 / L, ty = 10 / L;
    const double s = (x - 20) * tx + (y - 60) * ty, n = -(x - 20) * ty + (y - 60) * tx;
    const bool cod = std::abs(n) <= 5 && s >= -4.04 && s <= L + 4.04;
    const bool disk = std::hypot(x - 60, y - 30) <= 23;
    EXPECT_EQ(on[i] != 0, scan || cod || disk) << x << "," << y;
    count += on[i] ? 1 : 0;
  }
  EXPECT_GT(count, 1500u);
  EXPECT_LT(count, 3500u);
  // Nothing read, nothing correlated.
  const std::vector<char> none = CrackBandPoints(g, o, CrackBandReads{});
  EXPECT_EQ(std::count(none.begin(), none.end(), 1), 0);
}

TEST(CrackBand, InactivePointsAreMaskedAndCostNothing) {
  CorrelationOptions c;
  c.subset_size = 31;
  c.step = 10;
  c.update_sample_stride = 4;  // the reference-update test's lattice
  const Image ref = ReadImage(kFrames / "frame_00.png");
  Correlator full(c, ref), half(c, ref);
  std::vector<char> active(half.Grid().size(), 0);
  size_t on = 0;
  const int nx = half.Grid().nx;
  for (size_t i = 0; i < active.size(); ++i) {
    if (half.Grid().y[i] < 120) active[i] = 1;
    // Active, or on the update test's lattice (every 4th point in x and y).
    const bool lattice = (i % nx) % 4 == 0 && (i / nx) % 4 == 0;
    on += (active[i] || lattice) && half.Grid().status[i] == PointStatus::kUnreached;
  }
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
      // Within 0.1 px (0.015 mm): the band holds every point the location reads.
      EXPECT_NEAR(b.crack_length_raw_m * 1e3, a.crack_length_raw_m * 1e3, 0.015) << b.image;
      // The band is completed after locating: no frame lacks a point it read.
      EXPECT_FALSE(b.tip_beyond_band) << b.image;
      std::printf("  %s: band %.3f mm, full %.3f mm, points %zu / %zu\n", b.image.c_str(),
                  b.crack_length_raw_m * 1e3, a.crack_length_raw_m * 1e3, b.correlation.points,
                  a.correlation.points);
    }
  }
}


// Synthetic LEFM crack (speckle generator) growing 30 px a frame: the band
// run reads the same points as the full field, so every frame's length is
// the full field's within 0.1 px, with far fewer points; and in both runs
// every length is within 2 sigma of the truth or the frame is flagged.
TEST(CrackBand, SyntheticSequenceMatchesTheFullField) {
  const fs::path dir = fs::temp_directory_path() / "bridgefit_crack_band_synthetic";
  fs::remove_all(dir);
  fs::create_directories(dir);
  SpeckleOptions so;
  so.width = 480;
  so.height = 320;
  so.seed = 11;
  const SpeckleRenderer renderer(so);
  std::vector<fs::path> images;
  std::vector<double> truth = {0};
  for (int k = 0; k < 7; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%02d.png", k);
    images.push_back(dir / name);
    if (k == 0) {
      WriteImage(images.back(), renderer.RenderReference(500), 8);
      continue;
    }
    ModeICrackField m;
    m.tip_x = 150 + 30.0 * (k - 1);
    m.tip_y = 160.5;
    m.k_over_2mu = 0.06;
    m.translation_x = 0.15 * k;
    m.translation_y = -0.1 * k;
    WriteImage(images.back(), renderer.Render(m, 500 + k), 8);
    truth.push_back(m.tip_x - 10);  // from the line's start at x = 10
  }
  CrackSequenceOptions o;
  SetGridDefaults(21, 5, &o);
  o.scale_m_per_px = 1e-5;
  o.show_progress = false;
  o.tip.line = {10, 160.5, 470, 160.5};
  o.tip.fit_radius_px = o.tip.sqrt_window_px = 60;
  o.path.search_half_width_px = 20;
  CrackSequenceOptions f = o;
  f.full_field = true;
  const CrackSequenceResult band = AnalyzeCrackSequence(images, o);
  const CrackSequenceResult full = AnalyzeCrackSequence(images, f);
  std::printf("band %.0f points per frame, full %.0f\n", band.mean_correlated_points,
              full.mean_correlated_points);
  EXPECT_LT(band.mean_correlated_points, 0.5 * full.mean_correlated_points);
  for (size_t k = 1; k < images.size(); ++k) {
    const FrameResult& b = band.frames[k];
    const FrameResult& a = full.frames[k];
    ASSERT_TRUE(b.has_length && a.has_length) << b.image;
    const double lb = b.crack_length_raw_m / o.scale_m_per_px, la = a.crack_length_raw_m / o.scale_m_per_px;
    std::printf("  frame %zu: truth %.2f, band %.3f (+-%.2f) %s, full %.3f %s, points %zu / %zu\n", k,
                truth[k], lb, b.uncertainty_m / o.scale_m_per_px, b.Flags().c_str(), la,
                a.Flags().c_str(), b.correlation.points, a.correlation.points);
    EXPECT_NEAR(lb, la, 0.1) << b.image;
    EXPECT_FALSE(b.tip_beyond_band) << b.image;
    for (const FrameResult* r : {&b, &a}) {
      const double err = r->crack_length_raw_m / o.scale_m_per_px - truth[k];
      EXPECT_TRUE(std::abs(err) <= 2 * r->uncertainty_m / o.scale_m_per_px || r->flagged)
          << r->image << ": error " << err << " px";
    }
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace bridgefit::dic
