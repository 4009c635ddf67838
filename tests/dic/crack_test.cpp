// Crack tip location: exact LEFM fields (no images) and synthetic cracked
// speckle images with known tips.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <gtest/gtest.h>

#include "bridgefit/dic/crack.hpp"
#include "bridgefit/dic/speckle.hpp"

namespace bridgefit::dic {
namespace {

// A displacement field sampled exactly from `motion` on a grid, with the
// crack band marked as the correlator would.
DisplacementField SampleField(const ModeICrackField& motion, int w, int h, int step,
                              double band_half) {
  DisplacementField f;
  f.nx = w / step;
  f.ny = h / step;
  for (int iy = 0; iy < f.ny; ++iy)
    for (int ix = 0; ix < f.nx; ++ix) {
      const double x = ix * step, y = iy * step;
      double u, v;
      motion(x, y, &u, &v);
      f.x.push_back(x);
      f.y.push_back(y);
      f.u.push_back(u);
      f.v.push_back(v);
      f.zncc.push_back(1);
      f.iterations.push_back(1);
      f.status.push_back(std::abs(y - motion.tip_y) <= band_half ? PointStatus::kCrackBand
                                                                  : PointStatus::kOk);
    }
  const size_t n = f.x.size();
  f.dudx.assign(n, 0);
  f.dudy.assign(n, 0);
  f.dvdx.assign(n, 0);
  f.dvdy.assign(n, 0);
  return f;
}

TEST(CrackTip, WilliamsFitRecoversExactLefmTipAndK) {
  // The Williams basis (n = 1 mode I) must reproduce the textbook K field
  // used by the generator, so the fit finds the tip and K_I/(2 mu) exactly.
  ModeICrackField motion;
  motion.tip_x = 143.3;
  motion.tip_y = 100;
  motion.k_over_2mu = 0.05;
  motion.translation_x = 0.4;
  motion.translation_y = -0.7;
  motion.rotation = 2e-4;
  const DisplacementField f = SampleField(motion, 300, 200, 4, 12);
  CrackTipOptions o;
  o.line = {20, 100, 290, 100};
  o.station_spacing_px = 4;
  o.band_half_width_px = 12;
  o.side_depth_px = 10;
  const CrackTipResult r = LocateCrackTip(f, o, TipMethod::kWilliams);
  ASSERT_TRUE(r.opening_detected);
  ASSERT_TRUE(r.williams.found);
  EXPECT_EQ(r.method, TipMethod::kWilliams);
  EXPECT_NEAR(r.williams.s_px, 123.3, 0.05);
  EXPECT_NEAR(r.tip.x_px, 143.3, 0.05);
  EXPECT_NEAR(r.k_over_2mu_sqrt_px, 0.05, 0.0005);
  EXPECT_LT(r.williams_residual_px, 1e-4);
  // COD profile behind the tip: (kappa + 1) A sqrt(2 r / pi), extrapolated
  // from the band edges; a few px behind the tip within 3%.
  for (size_t k = 0; k < r.cod.s_px.size(); ++k) {
    const double rr = 123.3 - r.cod.s_px[k];
    if (!r.cod.valid[k] || rr < 40) continue;
    EXPECT_NEAR(r.cod.opening_px[k], motion.OpeningAt(rr), 0.03 * motion.OpeningAt(rr))
        << "s = " << r.cod.s_px[k];
  }
  // The jump threshold runs ahead of the tip (documented bias), never behind
  // by more than one station.
  EXPECT_GT(r.jump.s_px, 123.3 - 4);
}

// The Williams window reads the continuum only (crack_williams.cpp): a hole
// (a cluster of failed points) 50 px above the tip ends the window at its
// nearest point, and the ok points beside a failed pair (a cluster too small
// to cut the window), given a wrong motion, are left out: the exact field's
// tip is still found exactly.
// A rigid rotation of the whole field (a specimen turning in its grips)
// is no part of the crack: the series' rigid columns hold it to first order
// only, and its second-order part, an equibiaxial contraction of
// (1 - cos theta) r, pulled the tip (an LEFM field in mm turned by 1 / 2 / 3
// degrees: +0.28 / +1.2 mm / no Williams tip). Oracle: the exact field,
// noise 0.01 px, turned exactly (deformed positions) by 0-8 degrees about a
// point far from the tip: the tip within 0.3 px of the truth, the
// unturned run's tip within 0.1 px, the rotation recovered.
TEST(CrackTip, WilliamsTipIsBlindToARigidRotation) {
  ModeICrackField motion;
  motion.tip_x = 143.3;
  motion.tip_y = 100;
  motion.k_over_2mu = 0.05;
  CrackTipOptions o;
  o.line = {20, 100, 290, 100};
  o.station_spacing_px = 4;
  o.band_half_width_px = 12;
  o.side_depth_px = 10;
  double unturned = 0;
  for (double degrees : {0.0, 1.0, 3.0, 8.0}) {
    SCOPED_TRACE(degrees);
    const double theta = degrees * std::numbers::pi / 180;
    DisplacementField f = SampleField(motion, 300, 200, 4, 12);
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 0.01);
    for (size_t i = 0; i < f.size(); ++i) {
      // Turn the deformed position about (-50, 300) px, then add noise.
      const double X = f.x[i] + f.u[i] + 50, Y = f.y[i] + f.v[i] - 300;
      f.u[i] = std::cos(theta) * X - std::sin(theta) * Y - 50 - f.x[i] + noise(rng);
      f.v[i] = std::sin(theta) * X + std::cos(theta) * Y + 300 - f.y[i] + noise(rng);
    }
    const CrackTipResult r = LocateCrackTip(f, o, TipMethod::kWilliams);
    ASSERT_TRUE(r.williams.found);
    EXPECT_EQ(r.method, TipMethod::kWilliams);
    EXPECT_NEAR(r.williams.s_px, 123.3, 0.3);
    if (degrees == 0) unturned = r.williams.s_px;
    EXPECT_NEAR(r.williams.s_px, unturned, 0.1);
    if (degrees > 0) EXPECT_NEAR(r.williams_rotation_rad, theta, 1e-3);
    EXPECT_FALSE(r.methods_disagree);
    std::printf("turned %.0f deg: Williams tip %.3f px (truth 123.3) +- %.3f, rotation %.4f rad\n",
                degrees, r.williams.s_px, r.williams.uncertainty_px, r.williams_rotation_rad);
  }
}

TEST(CrackTip, WilliamsWindowReadsTheContinuumOnly) {
  ModeICrackField motion;
  motion.tip_x = 143.3;
  motion.tip_y = 100;
  motion.k_over_2mu = 0.05;
  DisplacementField f = SampleField(motion, 300, 200, 4, 12);
  CrackTipOptions o;
  o.line = {20, 100, 290, 100};
  o.station_spacing_px = 4;
  o.band_half_width_px = 12;
  o.side_depth_px = 10;
  const double hole_x = 132, hole_y = 40;
  for (size_t i = 0; i < f.size(); ++i)
    if (std::hypot(f.x[i] - hole_x, f.y[i] - hole_y) <= 10) f.status[i] = PointStatus::kLowCorrelation;
  // Its grid neighbours correlated to something else.
  for (size_t i = 0; i < f.size(); ++i) {
    const int ix = static_cast<int>(i % f.nx), iy = static_cast<int>(i / f.nx);
    bool beside = false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int jx = ix + dx, jy = iy + dy;
        if (jx >= 0 && jy >= 0 && jx < f.nx && jy < f.ny &&
            f.status[static_cast<size_t>(jy) * f.nx + jx] == PointStatus::kLowCorrelation)
          beside = true;
      }
    if (beside && f.ok(i)) f.u[i] += 3;
  }
  // A failed pair 30 px below the tip, its neighbours moved by 2 px.
  for (size_t i = 0; i < f.size(); ++i) {
    const double dx = f.x[i] - 148, dy = f.y[i] - 132;
    if ((dx == 0 || dx == 4) && dy == 0) f.status[i] = PointStatus::kNoConvergence;
    else if (dx >= -4 && dx <= 8 && std::abs(dy) <= 4) f.v[i] += 2;
  }
  const CrackTipResult r = LocateCrackTip(f, o, TipMethod::kWilliams);
  ASSERT_TRUE(r.williams.found);
  double cx, cy;
  o.line.FromLocal(r.williams_centre_s_px, 0, &cx, &cy);
  double nearest = 1e300;
  for (size_t i = 0; i < f.size(); ++i)
    if (f.status[i] == PointStatus::kLowCorrelation)
      nearest = std::min(nearest, std::hypot(f.x[i] - cx, f.y[i] - cy));
  EXPECT_NEAR(r.williams_clear_radius_px, nearest, 1e-9);
  EXPECT_LT(r.williams_clear_radius_px, o.fit_radius_px);
  EXPECT_FALSE(r.williams_window_short);
  EXPECT_EQ(r.method, TipMethod::kWilliams);
  EXPECT_FALSE(r.williams_unstable);
  EXPECT_NEAR(r.williams.s_px, 123.3, 0.05);
  EXPECT_LT(r.williams_residual_px, 1e-4);  // no moved point was read
}

// A Williams tip that moves when the window shrinks by one station is
// flagged and not used: points in the window's outer ring (one station
// wide, above the crack) carry a wrong motion, so the tip depends on
// whether they are read.
TEST(CrackTip, WilliamsTipSensitiveToTheWindowIsNotTheLength) {
  ModeICrackField motion;
  motion.tip_x = 143.3;
  motion.tip_y = 100;
  motion.k_over_2mu = 0.05;
  DisplacementField f = SampleField(motion, 300, 200, 4, 12);
  CrackTipOptions o;
  o.line = {20, 100, 290, 100};
  o.station_spacing_px = 4;
  o.band_half_width_px = 12;
  o.side_depth_px = 10;
  const CrackTipResult clean = LocateCrackTip(f, o, TipMethod::kWilliams);
  ASSERT_TRUE(clean.williams.found);
  EXPECT_FALSE(clean.williams_unstable);
  EXPECT_LT(std::abs(clean.williams_shift_px), 0.05);
  double cx, cy;
  o.line.FromLocal(clean.williams_centre_s_px, 0, &cx, &cy);
  for (size_t i = 0; i < f.size(); ++i) {
    const double d = std::hypot(f.x[i] - cx, f.y[i] - cy);
    if (d >= o.fit_radius_px - o.station_spacing_px && d < o.fit_radius_px && f.y[i] < 100 &&
        f.x[i] < cx)
      f.v[i] += 3;
  }
  const CrackTipResult r = LocateCrackTip(f, o, TipMethod::kWilliams);
  std::printf("Williams %.2f (shift %.2f, +- %.2f), sqrt %.2f, method %s\n", r.williams.s_px,
              r.williams_shift_px, r.williams.uncertainty_px, r.sqrt_cod.s_px,
              TipMethodName(r.method));
  EXPECT_TRUE(r.williams_unstable);
  EXPECT_NE(r.method, TipMethod::kWilliams);
}

// The shadow rule (crack_williams.cpp, Shadow): a failed cluster hides only
// what lies behind it as seen from the window's centre; the rest of the disk
// is read. The tests share the exact field of the hole test above (tip at
// s = 123.3 px, fit radius 80 px, step 4 px).
struct ShadowCase {
  ModeICrackField motion;
  DisplacementField f;
  CrackTipOptions o;
  ShadowCase() {
    motion.tip_x = 143.3;
    motion.tip_y = 100;
    motion.k_over_2mu = 0.05;
    f = SampleField(motion, 300, 200, 4, 12);
    o.line = {20, 100, 290, 100};
    o.station_spacing_px = 4;
    o.band_half_width_px = 12;
    o.side_depth_px = 10;
  }
  // Failed points where `in` holds; their ok grid neighbours moved by 2 px
  // (as subsets straddling a failure correlate to something else).
  template <class In>
  void Fail(In in) {
    for (size_t i = 0; i < f.size(); ++i)
      if (in(f.x[i], f.y[i]) && f.status[i] == PointStatus::kOk) f.status[i] = PointStatus::kNoConvergence;
    for (size_t i = 0; i < f.size(); ++i) {
      if (!f.ok(i)) continue;
      const int ix = static_cast<int>(i % f.nx), iy = static_cast<int>(i / f.nx);
      bool beside = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int jx = ix + dx, jy = iy + dy;
          if (jx >= 0 && jy >= 0 && jx < f.nx && jy < f.ny &&
              f.status[static_cast<size_t>(jy) * f.nx + jx] == PointStatus::kNoConvergence)
            beside = true;
        }
      if (beside) f.v[i] += 2;
    }
  }
};

// A 3 x 3 failed cluster 30 px from the tip, below the crack ahead of it:
// the old rule cut the whole window to 30 px (< half the fit radius: no
// Williams tip); the shadow rule hides the sector behind it and keeps the tip.
TEST(CrackTip, SmallFailedClusterHidesOnlyItsShadow) {
  ShadowCase c;
  c.Fail([](double x, double y) { return x >= 152 && x <= 160 && y >= 124 && y <= 132; });
  const CrackTipResult r = LocateCrackTip(c.f, c.o, TipMethod::kWilliams);
  std::printf("Williams %.3f +- %.3f, clear radius %.1f, %d points, %d hidden, residual %.2g\n",
              r.williams.s_px, r.williams.uncertainty_px, r.williams_clear_radius_px,
              r.williams_points, r.williams_hidden_points, r.williams_residual_px);
  EXPECT_LT(r.williams_clear_radius_px, c.o.min_fit_radius_fraction * c.o.fit_radius_px);
  EXPECT_GT(r.williams_hidden_points, 0);
  EXPECT_FALSE(r.williams_window_short);
  EXPECT_FALSE(r.williams_unstable);
  ASSERT_EQ(r.method, TipMethod::kWilliams);
  EXPECT_NEAR(r.williams.s_px, 123.3, 0.5);
  EXPECT_LT(r.williams_residual_px, 1e-4);  // no moved neighbour read
}

// The same on a crack tilted by 10 degrees, with noise (0.01 px, fixed seed)
// on every displacement: the shadow and the quadrants are taken in the
// line's frame, the tip stays within 0.5 px.
TEST(CrackTip, SmallFailedClusterOnATiltedNoisyCrack) {
  ModeICrackField motion;
  const double a = 10.0 * std::numbers::pi / 180.0;
  motion.direction_x = std::cos(a);
  motion.direction_y = std::sin(a);
  motion.tip_x = 150;
  motion.tip_y = 110;
  motion.k_over_2mu = 0.05;
  DisplacementField f = SampleField(motion, 300, 220, 4, -1);  // no band yet
  CrackTipOptions o;
  const double back = 130;  // the line starts 130 px behind the tip
  o.line = {motion.tip_x - back * std::cos(a), motion.tip_y - back * std::sin(a),
            motion.tip_x + 140 * std::cos(a), motion.tip_y + 140 * std::sin(a)};
  o.station_spacing_px = 4;
  o.band_half_width_px = 12;
  o.side_depth_px = 10;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (size_t i = 0; i < f.size(); ++i) {
    double s, n;
    o.line.ToLocal(f.x[i], f.y[i], &s, &n);
    if (std::abs(n) <= 12) f.status[i] = PointStatus::kCrackBand;
    f.u[i] += noise(rng);
    f.v[i] += noise(rng);
  }
  // 3 x 3 failed points centred 28 px ahead of the tip, 22 px off the line.
  double cx, cy;
  o.line.FromLocal(back + 28, 22, &cx, &cy);
  for (size_t i = 0; i < f.size(); ++i)
    if (std::abs(f.x[i] - cx) <= 4.01 && std::abs(f.y[i] - cy) <= 4.01 && f.ok(i))
      f.status[i] = PointStatus::kLowCorrelation;
  const CrackTipResult r = LocateCrackTip(f, o, TipMethod::kWilliams);
  std::printf("Williams %.3f +- %.3f (truth %.1f), clear radius %.1f, %d points, %d hidden\n",
              r.williams.s_px, r.williams.uncertainty_px, back, r.williams_clear_radius_px,
              r.williams_points, r.williams_hidden_points);
  EXPECT_LT(r.williams_clear_radius_px, o.min_fit_radius_fraction * o.fit_radius_px);
  EXPECT_GT(r.williams_hidden_points, 0);
  EXPECT_FALSE(r.williams_window_short);
  ASSERT_EQ(r.method, TipMethod::kWilliams);
  EXPECT_NEAR(r.williams.s_px, back, 0.5);
}

// A grip: a block above the crack behind the tip moves rigidly by (4, -5) px,
// its edge failed. Its interior correlates (ok points, no failed neighbour)
// but lies behind the failed edge: hidden, not read. Read whole (no
// clusters), it pulls the fit off the field.
TEST(CrackTip, GripBehindItsFailedEdgeIsHidden) {
  ShadowCase c;
  auto inside = [](double x, double y) { return x >= 60 && x <= 112 && y >= 12 && y <= 64; };
  for (size_t i = 0; i < c.f.size(); ++i)
    if (inside(c.f.x[i], c.f.y[i])) {
      c.f.u[i] += 4;
      c.f.v[i] -= 5;
    }
  c.Fail([&](double x, double y) {
    return inside(x, y) && !(x >= 68 && x <= 104 && y >= 20 && y <= 56);  // edge, 2 points wide
  });
  const CrackTipResult r = LocateCrackTip(c.f, c.o, TipMethod::kWilliams);
  CrackTipOptions whole = c.o;
  whole.min_failed_cluster = 1 << 30;
  const CrackTipResult u = LocateCrackTip(c.f, whole, TipMethod::kWilliams);
  std::printf("Williams %.3f (residual %.2g, %d hidden); block read: %.3f (residual %.2g)\n",
              r.williams.s_px, r.williams_residual_px, r.williams_hidden_points, u.williams.s_px,
              u.williams_residual_px);
  EXPECT_GT(r.williams_hidden_points, 0);
  EXPECT_FALSE(r.williams_window_short);
  ASSERT_EQ(r.method, TipMethod::kWilliams);
  EXPECT_NEAR(r.williams.s_px, 123.3, 0.05);
  EXPECT_LT(r.williams_residual_px, 1e-4);  // no block point read
  EXPECT_GT(u.williams_residual_px, 0.01);  // the block is in the window
}

// Too one-sided: a failed wall 16-20 px above the line from x = 96 px on
// (behind the window's centre) hides the whole upper quadrant ahead of the
// centre; below the line the window is whole. No Williams tip
// (williams_window_short), the length from sqrt/jump. (A wall from x = 136
// px on, 9 px ahead of the centre, leaves a 30 degree sector ahead above,
// about 105 points out to the fit radius, more than the 48 of that quadrant
// of the disk of half the radius: not short, and the tip is exact there.)
TEST(CrackTip, WindowHiddenAboveAheadIsShort) {
  ShadowCase c;
  c.Fail([](double x, double y) { return x >= 96 && y >= 80 && y <= 84; });
  const CrackTipResult r = LocateCrackTip(c.f, c.o, TipMethod::kWilliams);
  std::printf("short %d, centre %.1f, %d points, %d hidden, method %s\n", r.williams_window_short, r.williams_centre_s_px,
              r.williams_points, r.williams_hidden_points, TipMethodName(r.method));
  EXPECT_TRUE(r.williams_window_short);
  EXPECT_FALSE(r.williams.found);
  EXPECT_NE(r.method, TipMethod::kWilliams);
}

// A failed ring all round the centre: the window is the disk inside it, short
// exactly when the ring is closer than half the fit radius (the old rule).
TEST(CrackTip, FailedRingAllRoundShortBelowHalfTheRadius) {
  double cx, cy;
  {
    const ShadowCase clean;
    const CrackTipResult r = LocateCrackTip(clean.f, clean.o, TipMethod::kWilliams);
    clean.o.line.FromLocal(r.williams_centre_s_px, 0, &cx, &cy);
  }
  for (const double ring : {30.0, 38.0, 44.0, 52.0, 60.0}) {
    ShadowCase c;
    c.Fail([&](double x, double y) {
      const double d = std::hypot(x - cx, y - cy);
      return d >= ring && d <= ring + 6;
    });
    const CrackTipResult r = LocateCrackTip(c.f, c.o, TipMethod::kWilliams);
    std::printf("ring %.0f px: short %d, clear radius %.1f, Williams %.3f\n", ring,
                r.williams_window_short, r.williams_clear_radius_px, r.williams.s_px);
    // The disk inside the ring, against the disk of half the fit radius
    // (40 px): short when the ring is closer; not short when it is two grid
    // steps farther (the ring's inner neighbours are no continuum, the
    // lattice counts differ by a step); in between either.
    const double half = c.o.min_fit_radius_fraction * c.o.fit_radius_px;
    if (r.williams_clear_radius_px >= half && r.williams_clear_radius_px < half + 8) continue;
    const bool short_expected = r.williams_clear_radius_px < half;
    EXPECT_EQ(r.williams_window_short, short_expected) << ring;
    if (!short_expected) {
      ASSERT_EQ(r.method, TipMethod::kWilliams);
      EXPECT_NEAR(r.williams.s_px, 123.3, 0.05);
    }
  }
}

TEST(CrackTip, NoOpeningGivesNoTip) {
  ModeICrackField motion;
  motion.k_over_2mu = 0;  // rigid motion only
  motion.translation_x = 1.5;
  motion.tip_y = 100;
  const DisplacementField f = SampleField(motion, 300, 200, 4, 12);
  CrackTipOptions o;
  o.line = {20, 100, 290, 100};
  o.station_spacing_px = 4;
  o.band_half_width_px = 12;
  const CrackTipResult r = LocateCrackTip(f, o, TipMethod::kWilliams);
  EXPECT_FALSE(r.opening_detected);
  EXPECT_FALSE(r.tip.found);
}

TEST(CrackTip, MonotoneRegressionPoolsViolators) {
  const std::vector<double> a{1, 3, 2, 4, 0, 5};
  const std::vector<double> s(6, 1.0);
  std::vector<char> valid(6, 1);
  valid[4] = 0;  // skipped, returned unchanged
  const auto m = MonotoneNonDecreasing(a, s, valid);
  EXPECT_DOUBLE_EQ(m[0], 1);
  EXPECT_DOUBLE_EQ(m[1], 2.5);
  EXPECT_DOUBLE_EQ(m[2], 2.5);
  EXPECT_DOUBLE_EQ(m[3], 4);
  EXPECT_DOUBLE_EQ(m[4], 0);
  EXPECT_DOUBLE_EQ(m[5], 5);
}

// Acceptance: synthetic cracked images, tip growing over 10 frames; the
// field fit finds the tip within 1 px on average; the length is monotone.
TEST(CrackTip, SyntheticCrackedSequence) {
  SpeckleOptions speckle;
  speckle.width = 320;
  speckle.height = 200;
  speckle.speckle_radius_px = 2.0;
  speckle.noise_std = 0.005;
  const SpeckleRenderer renderer(speckle);
  const Image ref = renderer.RenderReference(100);
  CorrelationOptions opt;
  opt.subset_size = 21;
  opt.step = 4;
  opt.has_crack = true;
  opt.crack = {20, 100, 300, 100};
  Correlator correlator(opt, ref);
  CrackTipOptions tip_opt;
  tip_opt.line = opt.crack;
  tip_opt.station_spacing_px = opt.step;
  tip_opt.band_half_width_px = opt.subset_size / 2 + 1;
  tip_opt.side_depth_px = 2.5 * opt.step;
  const double mm_per_px = 0.05;
  double sum_err[3] = {0, 0, 0};
  int found[3] = {0, 0, 0};
  std::vector<double> lengths, sigmas;
  std::vector<char> valid;
  int disagree = 0;
  for (int k = 0; k < 10; ++k) {
    ModeICrackField motion;
    motion.tip_x = 120 + 10.3 * k;
    motion.tip_y = 100;
    motion.k_over_2mu = 0.04 + 0.002 * k;
    motion.translation_x = 0.2 * k;
    motion.translation_y = -0.1 * k;
    motion.rotation = 1e-4 * k;
    const Image def = renderer.Render(motion, 200 + k);
    CorrelationSummary summary;
    const DisplacementField f = correlator.Next(def, &summary);
    const CrackTipResult r = LocateCrackTip(f, tip_opt, TipMethod::kWilliams);
    ASSERT_TRUE(r.opening_detected) << "frame " << k;
    const double s_true = motion.tip_x - 20;
    const TipEstimate* t[3] = {&r.williams, &r.jump, &r.sqrt_cod};
    for (int m = 0; m < 3; ++m)
      if (t[m]->found) {
        sum_err[m] += std::abs(t[m]->s_px - s_true);
        ++found[m];
      }
    std::printf("frame %d: true %.2f williams %.2f (+-%.2f, K/2mu %.4f) jump %.2f sqrt %.2f  %s\n", k,
                s_true, r.williams.s_px, r.williams.uncertainty_px, r.k_over_2mu_sqrt_px,
                r.jump.s_px, r.sqrt_cod.s_px, summary.BriefReport().c_str());
    // Never a confident wrong tip: within 2 sigma (sigma at least one
    // station / sqrt(12), as the sequence states it) or flagged.
    const double sigma = std::max(r.tip.uncertainty_px, tip_opt.station_spacing_px / std::sqrt(12.0));
    EXPECT_TRUE(std::abs(r.tip.s_px - s_true) <= 2 * sigma || r.methods_disagree || r.tip_at_edge)
        << "frame " << k << ": error " << r.tip.s_px - s_true << " px, sigma " << sigma;
    disagree += r.methods_disagree ? 1 : 0;
    lengths.push_back(r.tip.s_px * mm_per_px);
    sigmas.push_back(std::max(r.tip.uncertainty_px, 0.05) * mm_per_px);
    valid.push_back(r.tip.found ? 1 : 0);
  }
  EXPECT_EQ(found[0], 10);
  // The methods agree within their uncertainties here (Williams 0.3 px,
  // sqrt 0.5 px, jump ahead by less than the band): no frame is flagged.
  EXPECT_EQ(disagree, 0);
  const double mean_williams = sum_err[0] / std::max(found[0], 1);
  EXPECT_LT(mean_williams, 1.0);
  const char* names[3] = {"williams", "jump", "sqrt"};
  for (int m = 0; m < 3; ++m) {
    const double e = found[m] ? sum_err[m] / found[m] : NAN;
    std::printf("%s: mean |error| %.3f px = %.4f mm over %d frames\n", names[m], e, e * mm_per_px,
                found[m]);
    RecordProperty(std::string(names[m]) + "_mean_error_px", std::to_string(e));
  }
  const auto mono = MonotoneNonDecreasing(lengths, sigmas, valid);
  for (size_t k = 1; k < mono.size(); ++k) EXPECT_GE(mono[k], mono[k - 1]);
  // The monotone fit moves no frame by more than the tip tolerance.
  for (size_t k = 0; k < mono.size(); ++k) EXPECT_NEAR(mono[k], lengths[k], 1.0 * mm_per_px);
}

}  // namespace
}  // namespace bridgefit::dic
