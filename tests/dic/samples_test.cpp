// DIC Challenge Samples 14 and 15 (exact fields known) and the real
// 2D_ALDIC fracture sequence (cropped copies in tests/data/dic).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <gtest/gtest.h>
#include <sstream>

#include "bridgefit/dic/correlation.hpp"
#include "bridgefit/dic/sequence.hpp"

namespace bridgefit::dic {
namespace {

const std::string kData = std::string(BRIDGEFIT_TEST_DATA_DIR) + "/dic/";

std::vector<std::vector<double>> ReadNumericCsv(const std::string& path, int skip_rows) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::vector<std::vector<double>> rows;
  std::string line;
  for (int i = 0; i < skip_rows; ++i) std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream s(line);
    std::string item;
    while (std::getline(s, item, ',')) row.push_back(std::stod(item));
    if (!row.empty()) rows.push_back(row);
  }
  return rows;
}

// Acceptance: Sample 14 L1, 31x31 first-order subsets, RMS(u - exact) <=
// 0.015 px over rows 250..330 (published first-order result: 0.012 px).
TEST(DicChallenge, Sample14L1) {
  const Image ref = ReadImage(kData + "sample14/Sample14 Reference rows230-349.png");
  const Image def = ReadImage(kData + "sample14/Sample 14 L1 Amp0.1 rows230-349.png");
  const auto exact = ReadNumericCsv(kData + "sample14/Sample14Exact.csv", 1);
  ASSERT_EQ(exact.size(), 2048u);
  CorrelationOptions opt;
  opt.subset_size = 31;
  opt.step = 8;
  opt.roi_y0 = 20;  // rows 250..330 of the full image
  opt.roi_y1 = 101;
  CorrelationSummary summary;
  const DisplacementField f = CorrelatePair(ref, def, opt, &summary);
  double sum2 = 0, sum2_v = 0;
  size_t n = 0;
  for (size_t i = 0; i < f.size(); ++i) {
    ASSERT_TRUE(f.ok(i)) << f.x[i] << "," << f.y[i] << " " << PointStatusName(f.status[i]);
    const double e = f.u[i] - exact[static_cast<size_t>(f.x[i])][1];
    sum2 += e * e;
    sum2_v += f.v[i] * f.v[i];
    ++n;
  }
  const double rms = std::sqrt(sum2 / n), rms_v = std::sqrt(sum2_v / n);
  std::printf("Sample 14 L1: %zu points, RMS(u - exact) = %.4f px, RMS(v) = %.4f px; %s\n", n, rms,
              rms_v, summary.BriefReport().c_str());
  RecordProperty("rms_u_px", std::to_string(rms));
  EXPECT_LE(rms, 0.015);
  EXPECT_LE(rms_v, 0.015);
}

// Sample 15 exact profile: command.csv gives v at the DEFORMED row y (DICe
// compares at the current position). A material point at reference row Y
// has v_L(Y) = v(Y + v_L(Y)); solved by fixed-point iteration (|dv/dy| < 1).
std::vector<double> LagrangianProfile(const std::vector<std::vector<double>>& command, int column) {
  const int rows = static_cast<int>(command.size());
  auto at = [&](double y) {
    y = std::clamp(y, 0.0, rows - 1.0);
    const int y0 = std::min(static_cast<int>(y), rows - 2);
    const double t = y - y0;
    return (1 - t) * command[y0][column] + t * command[y0 + 1][column];
  };
  std::vector<double> v(rows);
  for (int Y = 0; Y < rows; ++Y) {
    double x = command[Y][column];
    for (int it = 0; it < 100; ++it) x = at(Y + x);
    v[Y] = x;
  }
  return v;
}

// Sample 15: v(Y) must follow the exact staircase on the plateaus; the steps
// are smeared over about one subset. Reports RMS overall and by distance
// from the steep parts.
TEST(DicChallenge, Sample15Staircase) {
  const auto command = ReadNumericCsv(kData + "sample15/command.csv", 0);
  ASSERT_GE(command.size(), 999u);
  const Image ref = ReadImage(kData + "sample15/Reference_cols900-1099.png");
  struct Case { const char* file; int column; };
  for (const Case c : {Case{"P200_K50_N2_cols900-1099.png", 1}, Case{"P200_K400_N2_cols900-1099.png", 8}}) {
    const std::vector<double> exact = LagrangianProfile(command, c.column);
    const Image def = ReadImage(kData + "sample15/" + c.file);
    CorrelationOptions opt;
    opt.subset_size = 35;
    opt.step = 5;
    opt.roi_x0 = 90;  // one column of points near x = 1000 of the full image
    opt.roi_x1 = 111;
    const DisplacementField f = CorrelatePair(ref, def, opt);
    // Steep rows: |dv/dy| > 0.02 px/px in the exact profile.
    std::vector<int> steep;
    for (size_t y = 1; y + 1 < exact.size(); ++y)
      if (std::abs(exact[y + 1] - exact[y - 1]) / 2 > 0.02)
        steep.push_back(static_cast<int>(y));
    double all2 = 0, near2 = 0, far2 = 0, far_max = 0;
    size_t n_all = 0, n_near = 0, n_far = 0, failed = 0;
    for (size_t i = 0; i < f.size(); ++i) {
      const int y = static_cast<int>(f.y[i]);
      if (y >= static_cast<int>(exact.size())) continue;
      // Near the top the image moves by up to 9.6 px: subsets leave it.
      const bool inside = y + exact[y] - opt.subset_size / 2 >= 1;
      if (!f.ok(i)) {
        if (inside || f.status[i] != PointStatus::kOutOfImage) ++failed;
        continue;
      }
      const double e = f.v[i] - exact[y];
      int dist = 1 << 20;
      for (int s : steep) dist = std::min(dist, std::abs(s - y));
      all2 += e * e;
      ++n_all;
      if (dist > opt.subset_size / 2 + 2) {
        far2 += e * e;
        far_max = std::max(far_max, std::abs(e));
        ++n_far;
      } else {
        near2 += e * e;
        ++n_near;
      }
    }
    const double rms_all = std::sqrt(all2 / std::max<size_t>(n_all, 1));
    const double rms_far = std::sqrt(far2 / std::max<size_t>(n_far, 1));
    const double rms_near = std::sqrt(near2 / std::max<size_t>(n_near, 1));
    std::printf("Sample 15 %s: RMS(v - exact) all %.4f px (%zu points, %zu failed); "
                "within half a subset of a steep part %.4f px (%zu); elsewhere %.4f px, max %.4f (%zu)\n",
                c.file, rms_all, n_all, failed, rms_near, n_near, rms_far, far_max, n_far);
    EXPECT_EQ(failed, 0u);
    ASSERT_GT(n_far, 10u);
    EXPECT_LT(rms_far, 0.02) << c.file;
    // Smearing: where the profile is steep the subset average departs from
    // the exact value.
    EXPECT_GT(rms_near, rms_far);
  }
}

// The real fracture sequence correlates end to end (incremental mode as
// needed) and gives a crack length that grows monotonically.
TEST(RealSequence, AldicFracHeter) {
  std::vector<std::filesystem::path> frames;
  for (const char* f : {"img_0000 .png", "img_0240 .png", "img_0420 .png", "img_0570 .png"})
    frames.push_back(kData + "aldic_frac_heter/" + f);
  CrackSequenceOptions opt;
  opt.correlation.subset_size = 31;
  opt.correlation.step = 8;
  opt.correlation.roi_x0 = 42;  // unspeckled notch and grip lie left of this
  opt.tip.line = {15, 182, 470, 182};
  opt.tip.station_spacing_px = 8;
  opt.tip.band_half_width_px = 16;
  opt.tip.side_depth_px = 20;
  opt.tip.fit_radius_px = 155;
  opt.tip.sqrt_window_px = 155;
  opt.scale_m_per_px = 1e-5;
  opt.show_progress = false;
  opt.keep_fields = true;
  const CrackSequenceResult r = AnalyzeCrackSequence(frames, opt);
  ASSERT_EQ(r.frames.size(), 4u);
  double last = -1;
  for (size_t k = 1; k < r.frames.size(); ++k) {
    const FrameResult& f = r.frames[k];
    std::printf("%s: valid %.3f, ZNCC %.4f, ref %d, tip %s: williams %.1f jump %.1f sqrt %.1f px, "
                "a = %.1f px (monotone)\n",
                f.image.c_str(), f.valid_fraction, f.correlation.mean_zncc,
                f.correlation.reference_frame, f.has_length ? TipMethodName(f.tip.method) : "none",
                f.tip.williams.s_px, f.tip.jump.s_px, f.tip.sqrt_cod.s_px,
                f.crack_length_m / opt.scale_m_per_px);
    // The specimen moves up by about 56 px: points near the top of the crop
    // leave the image. Away from the notch and the grip boundary (x >= 100)
    // and from the rows that leave the image (y >= 80) every point must
    // correlate; near them (sheared subsets, the opened gap, the image edge)
    // a few may fail.
    size_t used = 0, good = 0, used_far = 0, good_far = 0;
    int hist[7] = {0, 0, 0, 0, 0, 0, 0};
    for (size_t i = 0; i < f.field.size(); ++i) {
      const PointStatus st = f.field.status[i];
      ++hist[static_cast<int>(st)];
      if (st == PointStatus::kMasked || st == PointStatus::kCrackBand ||
          st == PointStatus::kOutOfImage)
        continue;
      ++used;
      good += f.field.ok(i) ? 1 : 0;
      if (f.field.x[i] >= 100 && f.field.y[i] >= 80) {
        ++used_far;
        good_far += f.field.ok(i) ? 1 : 0;
      }
    }
    std::printf("  status counts ok %d, band %d, out %d, no-conv %d, low-zncc %d, unreached %d\n",
                hist[0], hist[2], hist[3], hist[4], hist[5], hist[6]);
    EXPECT_GT(static_cast<double>(good) / used, 0.93) << f.image;
    EXPECT_GT(static_cast<double>(good_far) / used_far, 0.99) << f.image;
    ASSERT_TRUE(f.has_length) << f.image;
    EXPECT_GE(f.crack_length_m, last);
    last = f.crack_length_m;
  }
  // The last frame's crack has visibly opened into the speckle: tip well
  // past the notch tip, and before x = 100 px of the crop (no jump beyond,
  // as in the 2D_ALDIC peer result).
  const FrameResult& f = r.frames.back();
  EXPECT_GT(f.tip.tip.x_px, 30);
  EXPECT_LT(f.tip.tip.x_px, 100);
  // Opening near the notch is several pixels (the gap is visible).
  double max_open = 0;
  for (size_t k = 0; k < f.tip.cod.s_px.size(); ++k)
    if (f.tip.cod.valid[k]) max_open = std::max(max_open, f.tip.cod.opening_px[k]);
  for (size_t k = 0; k < f.tip.cod.s_px.size(); ++k)
    std::printf("%.0f:%.3f ", f.tip.cod.s_px[k], f.tip.cod.valid[k] ? f.tip.cod.opening_px[k] : NAN);
  std::printf("\n");
  EXPECT_GT(max_open, 1.0);
}

// The crack line given 18 px apart (y = 582 and 600 in the full frame, the
// crack found at about 593): on the early frames the opening is too small
// for a path of their own (none found, or one found 30 px off on scattered
// points), so each read along its own line and the two disagreed (full
// sequence, documented ROI: 4 of 10 frames within 2 px). The path the most
// open frame finds is the sequence's: every frame agrees within 2 px, and
// the path is reported. Runtime: about 10 s.
TEST(RealSequence, AldicFracHeterLineAt582Or600) {
  std::vector<std::filesystem::path> frames;
  for (const char* f : {"img_0000 .png", "img_0240 .png", "img_0420 .png", "img_0570 .png"})
    frames.push_back(kData + "aldic_frac_heter/" + f);
  auto run = [&](double line_y, bool sequence_path) {
    CrackSequenceOptions opt;
    SetGridDefaults(31, 6, &opt);
    opt.correlation.roi_x0 = 42;  // unspeckled notch and grip lie left of this
    opt.tip.line = {15, line_y, 470, line_y};
    opt.scale_m_per_px = 1e-5;
    opt.show_progress = false;
    opt.sequence_path = sequence_path;
    return AnalyzeCrackSequence(frames, opt);
  };
  const double lines[2] = {182, 200};
  int differ_own = 0;
  std::vector<CrackSequenceResult> along;
  for (double y : lines) along.push_back(run(y, true));
  std::vector<CrackSequenceResult> own;
  for (double y : lines) own.push_back(run(y, false));
  for (int l = 0; l < 2; ++l) {
    ASSERT_EQ(along[l].frames.size(), 4u);
    ASSERT_GE(along[l].sequence_path_frame, 1) << "line y = " << lines[l];
    const FrameResult& source = along[l].frames[along[l].sequence_path_frame];
    EXPECT_TRUE(source.path.found);
    std::printf("line y = %.0f: the sequence's path from frame %d, y = %.2f .. %.2f px\n", lines[l],
                along[l].sequence_path_frame, source.line_used.y0, source.line_used.y1);
  }
  for (size_t k = 1; k < 4; ++k) {
    const FrameResult &a = along[0].frames[k], &b = along[1].frames[k];
    const FrameResult &ao = own[0].frames[k], &bo = own[1].frames[k];
    auto px = [](const FrameResult& f) { return f.has_length ? f.tip.tip.s_px : NAN; };
    std::printf("%s: along the sequence path %.2f / %.2f px (y %.1f / %.1f), own %.2f / %.2f px%s%s\n",
                a.image.c_str(), px(a), px(b), a.line_used.y0, b.line_used.y0, px(ao), px(bo),
                ao.path_not_found ? " (own path not found on 582)" : "",
                bo.path_not_found ? " (own path not found on 600)" : "");
    EXPECT_EQ(a.has_length, b.has_length) << a.image;
    if (a.has_length && b.has_length) EXPECT_NEAR(a.tip.tip.s_px, b.tip.tip.s_px, 2.0) << a.image;
    differ_own += ao.has_length != bo.has_length ||
                          (ao.has_length && std::abs(ao.tip.tip.s_px - bo.tip.tip.s_px) > 2.0)
                      ? 1
                      : 0;
  }
  EXPECT_GT(differ_own, 0) << "the lines agree on their own paths: the case tests nothing";
}

}  // namespace
}  // namespace bridgefit::dic
