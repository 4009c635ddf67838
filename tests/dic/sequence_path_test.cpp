// The sequence's crack path (issue 18): a crack path is a material line, so
// frames whose own path is missing or off (not resolved, and apart from the
// sequence's most precise path by more than their uncertainties) take that
// path, and the lengths do not depend on the line given. Exported fields
// (CSV, mm, 1 mm nodes, 0.5 um noise) of an LEFM crack growing from the
// field's edge, 1.5 to 36.5 mm, with a fault on the first three frames: a
// second discontinuity (4 um across a line wandering 6 mm above the crack,
// a paint layer or a facet row slipping) that is stronger there than the
// crack, so those frames' own paths run along it. Lines given on the crack
// and 4 mm above and below it. Measured: the 6.5 mm frame read 7.67-7.91 mm
// along its own path (+-2.5-4.4 mm), 4.97-5.19 mm (+-1.4-2.0 mm, two of
// three seeds flagged) along the sequence's, the same on every line; the
// slip stays in the field the tip is fitted to. The real sequence's case is
// RealSequence.AldicFracHeterLineAt582Or600. Runtime: about 2 s.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "bridgefit/dic/fields.hpp"
#include "bridgefit/dic/sequence.hpp"
#include "bridgefit/dic/speckle.hpp"

namespace bridgefit::dic {
namespace {
namespace fs = std::filesystem;

constexpr int kFrames = 8;
constexpr double kCrackY = 0.5;  // mm, between node rows

double TrueTip(int k) { return -8.5 + 1.5 * k + 0.5 * k * k; }  // mm; field and crack from x = -10 mm

// Frame k: the mode I field of a tip at TrueTip(k), its K rising with the
// frame (opening 10 mm behind the tip from ~3 um to ~40 um), white noise
// `noise_mm` on u and v.
FieldFile GrowingCrackFrame(int k, double noise_mm, bool slip, std::mt19937_64* rng) {
  ModeICrackField m;
  m.tip_x = TrueTip(k);
  m.tip_y = kCrackY;
  m.k_over_2mu = 0.001 * (1 + 0.5 * k);
  m.translation_x = 0.01 * k;
  m.translation_y = -0.005 * k;
  std::normal_distribution<double> noise(0.0, noise_mm);
  FieldFile f;
  f.unit = "mm";
  f.m_per_unit = 1e-3;
  DisplacementField& d = f.field;
  for (int iy = -25; iy <= 25; ++iy)
    for (int ix = -10; ix <= 70; ++ix) {
      double u, v;
      m(ix, iy, &u, &v);
      // A second discontinuity on the early frames (a paint layer or a
      // facet row slipping: 4 um across a wandering line 6 mm above the
      // crack, over the first 20 mm), stronger there than the crack.
      if (slip && k <= 2 && ix < 10 && iy > kCrackY + 6 + 2 * std::sin(ix / 3.0)) v += 0.004;
      d.x.push_back(ix);
      d.y.push_back(iy);
      d.u.push_back(u + noise(*rng));
      d.v.push_back(v + noise(*rng));
      d.zncc.push_back(1);
      d.iterations.push_back(0);
      d.status.push_back(PointStatus::kOk);
    }
  d.nx = 81;
  d.ny = 51;
  return f;
}

std::vector<fs::path> WriteSequence(const fs::path& dir, double noise_mm, std::uint64_t seed,
                                    bool slip = true) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::mt19937_64 rng(seed);
  std::vector<fs::path> files;
  for (int k = 0; k < kFrames; ++k) {
    files.push_back(dir / ("frame_" + std::to_string(k) + ".csv"));
    WriteFieldFile(files.back(), GrowingCrackFrame(k, noise_mm, slip, &rng), FieldFormat::kCsv);
  }
  return files;
}

CrackSequenceResult Locate(const std::vector<fs::path>& files, double line_y, bool sequence_path) {
  CrackSequenceOptions o;
  o.show_progress = false;
  o.tip.threshold_floor_px = 0.001;  // mm
  o.path.min_jump_px = 0.001;
  o.tip.line = {-10, line_y, 70, line_y};
  o.sequence_path = sequence_path;
  return AnalyzeCrackFields(files, o);
}

// Whatever the line given, the same reading (to 0.05 mm).
void ExpectSameReading(const FrameResult& on, const FrameResult& off, const std::string& where) {
  EXPECT_EQ(on.has_length, off.has_length) << where;
  if (on.has_length && off.has_length)
    EXPECT_NEAR(on.crack_length_raw_m, off.crack_length_raw_m, 0.05e-3) << where;
}

// Never a confident wrong length: right within twice its uncertainty, or
// in doubt.
void ExpectRightOrInDoubt(const FrameResult& f, double truth_m, const std::string& where) {
  if (f.has_length && !f.LengthDoubtful())
    EXPECT_LT(std::abs(f.crack_length_raw_m - truth_m), 2 * f.uncertainty_m) << where;
}

TEST(SequencePath, LengthsDoNotDependOnTheLineWhereEarlyFramesCannotResolveThePath) {
  const fs::path dir = fs::temp_directory_path() / ("bf_seqpath_" + std::to_string(::getpid()));
  const double lines[3] = {kCrackY, kCrackY + 4, kCrackY - 4};
  int differ_without = 0, frames_compared = 0, taken = 0;
  auto mm = [](const FrameResult& f) {
    if (!f.has_length) return std::string("none");
    return fmt::format("{:.3f}+-{:.3f}{}", f.crack_length_raw_m * 1e3, f.uncertainty_m * 1e3,
                       f.LengthDoubtful() ? "*" : "");
  };
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const std::vector<fs::path> files = WriteSequence(dir, 0.0005, seed);
    std::vector<CrackSequenceResult> along, own;
    for (double y : lines) {
      along.push_back(Locate(files, y, true));
      own.push_back(Locate(files, y, false));
      ASSERT_EQ(along.back().frames.size(), static_cast<size_t>(kFrames));
      EXPECT_GE(along.back().sequence_path_frame, 0);
    }
    for (int k = 0; k < kFrames; ++k) {
      const FrameResult& on = along[0].frames[k];
      std::printf("seed %d frame %d truth %.2f mm: along the sequence path %s / %s / %s (line on, +4, -4 mm),"
                  " own %s / %s / %s (* in doubt)\n",
                  static_cast<int>(seed), k, TrueTip(k) + 10, mm(on).c_str(), mm(along[1].frames[k]).c_str(),
                  mm(along[2].frames[k]).c_str(), mm(own[0].frames[k]).c_str(), mm(own[1].frames[k]).c_str(),
                  mm(own[2].frames[k]).c_str());
      taken += on.path_from_frame >= 0 ? 1 : 0;
      bool own_differ = false;
      const std::string where = fmt::format("seed {} frame {}", seed, k);
      for (int l = 1; l < 3; ++l) {
        ExpectSameReading(on, along[l].frames[k], fmt::format("{} line {}", where, l));
        const FrameResult &a = own[l].frames[k], &b = along[l].frames[k];
        own_differ = own_differ || a.has_length != b.has_length ||
                     (a.has_length && std::abs(a.crack_length_raw_m - b.crack_length_raw_m) > 0.05e-3);
      }
      ExpectRightOrInDoubt(on, (TrueTip(k) + 10) * 1e-3, where);
      ++frames_compared;
      differ_without += own_differ ? 1 : 0;
    }
  }
  fs::remove_all(dir);
  std::printf("frames along the sequence path: %d of %d, their reading changed on %d\n", taken,
              frames_compared, differ_without);
  EXPECT_GT(differ_without, 0) << "every frame resolves its own path: the case tests nothing";
}

// The same growing crack without the slip: the first frames' own paths,
// found from a few points of a 3-4 um opening, are not resolved (standard
// error 2-5 mm at their ends) yet lie within their uncertainty of the
// sequence's, and along them no opening passes the threshold; along the
// sequence's path the 3.5 mm frame reads 3.47-3.88 mm (seeds 1, 3, 4, 6;
// none on every one of them before). Such frames take the reading along the
// sequence's path (ReadsBetterAlongSequencePath), the same whatever the
// line, right within twice its uncertainty or flagged. Runtime: about 3 s.
TEST(SequencePath, AnUnresolvedPathWithoutAnOpeningReadsAlongTheSequencesPath) {
  const fs::path dir = fs::temp_directory_path() / ("bf_seqpath2_" + std::to_string(::getpid()));
  int without_own = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const std::vector<fs::path> files = WriteSequence(dir, 0.0005, seed, false);
    std::vector<CrackSequenceResult> along;
    for (double y : {kCrackY, kCrackY + 4, kCrackY - 4}) along.push_back(Locate(files, y, true));
    const CrackSequenceResult own = Locate(files, kCrackY, false);
    for (int k = 1; k < kFrames; ++k) {
      const FrameResult &a = along[0].frames[k], &o = own.frames[k];
      const double truth = (TrueTip(k) + 10) * 1e-3;
      if (o.path.found && !o.has_length && a.has_length) {
        ++without_own;
        std::printf("seed %d frame %d (%.1f mm): own path se %.2f mm, no length; %.3f +- %.3f mm along the "
                    "sequence's path%s\n",
                    static_cast<int>(seed), k, truth * 1e3, o.path.line_se_px,
                    a.crack_length_raw_m * 1e3, a.uncertainty_m * 1e3,
                    a.LengthDoubtful() ? (" (" + a.Flags() + ")").c_str() : "");
        EXPECT_EQ(a.path_from_frame, along[0].sequence_path_frame) << "seed " << seed << " frame " << k;
      }
      const std::string where = fmt::format("seed {} frame {}", seed, k);
      for (int l = 1; l < 3; ++l)
        ExpectSameReading(a, along[l].frames[k], fmt::format("{} line {}", where, l));
      ExpectRightOrInDoubt(a, truth, where);
    }
  }
  fs::remove_all(dir);
  EXPECT_GE(without_own, 2) << "no frame's own path lacked an opening: the case tests nothing";
}

}  // namespace
}  // namespace bridgefit::dic
