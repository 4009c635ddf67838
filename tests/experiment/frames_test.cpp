// Crack lengths measured on images put into a record (CrackLengthFromFrames),
// against hand-computed values on a six-row record.
#include <gtest/gtest.h>

#include <cmath>

#include "bridgefit/core/error.hpp"
#include "bridgefit/experiment/rcurve.hpp"

namespace bridgefit::experiment {
namespace {

// Rows at t = 0, 1, 2, 4, 5, 6 s; images at rows 0 (reference), 1, 3 and 4.
ExperimentRecord SixRows() {
  ExperimentRecord r;
  r.source = "six rows";
  r.time = {0, 1, 2, 4, 5, 6};
  r.load = {0, 10, 20, 30, 25, 20};
  r.displacement = {0, 1e-4, 2e-4, 3e-4, 4e-4, 5e-4};
  r.images = {"img/f0.png", "img/f1.png", "", "img/f3.png", "img/f4.png", ""};
  return r;
}

TEST(CrackLengthFromFrames, InterpolatesInTimeBetweenFrames) {
  std::vector<std::string> notes;
  // DIC order need not be the record's; folders differ; the reference has no crack.
  const ExperimentRecord out = CrackLengthFromFrames(
      SixRows(), {"/data/f3.png", "f0.png", "other/f1.png", "f4.png"}, {0.040, NAN, 0.030, 0.046},
      "dic.csv", &notes);
  // Row 0: before the first frame with a crack (f1): its 30 mm. Row 2 (t = 2)
  // between f1 (t = 1, 30 mm) and f3 (t = 4, 40 mm): 30 + 10/3 mm. Row 5: after
  // the last frame, removed.
  ASSERT_EQ(out.size(), 5u);
  EXPECT_DOUBLE_EQ(out.crack_length[0], 0.030);
  EXPECT_DOUBLE_EQ(out.crack_length[1], 0.030);
  EXPECT_NEAR(out.crack_length[2], 0.030 + 0.010 / 3.0, 1e-15);
  EXPECT_DOUBLE_EQ(out.crack_length[3], 0.040);
  EXPECT_DOUBLE_EQ(out.crack_length[4], 0.046);
  EXPECT_EQ(out.load.size(), 5u);
  EXPECT_EQ(out.time.size(), 5u);
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_NE(notes[0].find("3 frames"), std::string::npos) << notes[0];
  EXPECT_NE(notes[1].find("1 rows after the last frame"), std::string::npos) << notes[1];
}

TEST(CrackLengthFromFrames, WithoutTimeInterpolatesByRow) {
  ExperimentRecord r = SixRows();
  r.time.clear();
  const ExperimentRecord out =
      CrackLengthFromFrames(r, {"f1.png", "f3.png"}, {0.030, 0.040}, "dic.csv", nullptr);
  EXPECT_NEAR(out.crack_length[2], 0.035, 1e-15);  // row 2 halfway between rows 1 and 3
}

TEST(CrackLengthFromFrames, ClearErrors) {
  // One matching frame only.
  try {
    CrackLengthFromFrames(SixRows(), {"f1.png", "zz.png"}, {0.03, 0.04}, "dic.csv", nullptr);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kInput);
    EXPECT_NE(std::string(e.what()).find("dic.csv"), std::string::npos) << e.what();
  }
  // A record without an image column.
  ExperimentRecord r = SixRows();
  r.images.clear();
  EXPECT_THROW(CrackLengthFromFrames(r, {"f1.png", "f3.png"}, {0.03, 0.04}, "dic.csv", nullptr),
               Error);
}

}  // namespace
}  // namespace bridgefit::experiment
