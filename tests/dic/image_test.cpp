// Image I/O and argument expansion (folders, globs, natural order, spaces).
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/image.hpp"
#include "bridgefit/dic/speckle.hpp"

namespace bridgefit::dic {
namespace {
namespace fs = std::filesystem;

fs::path TempDir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("bf_dic_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

TEST(Image, NaturalOrder) {
  EXPECT_TRUE(NaturalLess("img2.png", "img10.png"));
  EXPECT_FALSE(NaturalLess("img10.png", "img2.png"));
  EXPECT_TRUE(NaturalLess("img_0060 .png", "img_0120 .png"));
  EXPECT_TRUE(NaturalLess("a 9.tif", "a 10.tif"));
  EXPECT_FALSE(NaturalLess("same", "same"));
}

TEST(Image, SixteenBitRoundTripAndFolderExpansion) {
  const fs::path dir = TempDir("io");
  SpeckleOptions o;
  o.width = 40;
  o.height = 30;
  o.bit_depth = 16;
  const Image img = SpeckleRenderer(o).RenderReference(1);
  for (const char* name : {"frame 10.png", "frame 2.png", "frame 1.png"})
    WriteImage(dir / name, img, 16);
  std::ofstream(dir / "notes.txt") << "not an image";
  const Image back = ReadImage(dir / "frame 2.png");
  ASSERT_EQ(back.width, 40);
  ASSERT_EQ(back.height, 30);
  EXPECT_EQ(back.bit_depth, 16);
  for (size_t i = 0; i < img.pixels.size(); ++i) ASSERT_EQ(back.pixels[i], img.pixels[i]);
  const auto files = ExpandImageArguments({dir.string()});
  ASSERT_EQ(files.size(), 3u);
  EXPECT_EQ(files[0].filename(), "frame 1.png");
  EXPECT_EQ(files[1].filename(), "frame 2.png");
  EXPECT_EQ(files[2].filename(), "frame 10.png");
  const auto globbed = ExpandImageArguments({(dir / "frame 1*.png").string()});
  ASSERT_EQ(globbed.size(), 2u);
  EXPECT_EQ(globbed[1].filename(), "frame 10.png");
  fs::remove_all(dir);
}

TEST(Image, BadInputsGiveClearErrors) {
  const fs::path dir = TempDir("bad");
  std::ofstream(dir / "broken.png") << "this is not a PNG";
  try {
    ReadImage(dir / "broken.png");
    FAIL() << "unreadable image accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("broken.png"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadImage(dir / "missing.png"), Error);
  // A PNG cut short (issue 15): libpng's own "libpng error" line joins the
  // message instead of leaking onto stderr before it.
  Image small;
  small.width = small.height = 64;
  small.pixels.assign(64 * 64, 0.0f);
  for (int i = 0; i < 64 * 64; ++i) small.pixels[i] = static_cast<float>((i * 37) % 251);
  WriteImage(dir / "whole.png", small, 8);
  const auto size = fs::file_size(dir / "whole.png");
  fs::copy_file(dir / "whole.png", dir / "cut.png");
  fs::resize_file(dir / "cut.png", size / 2);
  ::testing::internal::CaptureStderr();
  std::string message;
  try {
    ReadImage(dir / "cut.png");
  } catch (const Error& e) {
    message = e.what();
  }
  const std::string leaked = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(message.find("cut.png"), std::string::npos) << message;
  EXPECT_EQ(leaked.find("libpng"), std::string::npos) << leaked;
  const fs::path empty = dir / "empty";
  fs::create_directories(empty);
  try {
    ExpandImageArguments({empty.string()});
    FAIL() << "empty folder accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no image"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ExpandImageArguments({(dir / "*.tif").string()}), Error);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace bridgefit::dic
