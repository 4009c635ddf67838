#include "bridgefit/core/error.hpp"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "bridgefit/core/atomic_file.hpp"

namespace bridgefit {
namespace {

TEST(Error, MessageNamesFileLineFieldValueExpected) {
  const Error e("must be positive", {.file = "scene.toml", .line = 4, .field = "specimen.thickness",
                                     .value = "-1 mm", .expected = "a value > 0 mm"});
  EXPECT_STREQ(e.what(),
               "scene.toml:4: field 'specimen.thickness': must be positive (got '-1 mm'); "
               "expected a value > 0 mm.");
  EXPECT_EQ(e.kind(), ErrorKind::kInput);
}

TEST(Error, WithContextFillsOnlyMissingFields) {
  const Error inner(ErrorKind::kInput, "wrong unit", {.value = "3 mm"});
  const Error outer = inner.WithContext({.file = "a.toml", .line = 2, .field = "E", .value = "x"});
  EXPECT_EQ(outer.context().file, "a.toml");
  EXPECT_EQ(outer.context().value, "3 mm");
  EXPECT_EQ(outer.kind(), ErrorKind::kInput);
}

TEST(AtomicOutput, NoFileUnlessCommitted) {
  const auto dir = std::filesystem::temp_directory_path() / "bf_atomic_test";
  std::filesystem::create_directories(dir);
  const auto target = dir / "out.txt";
  std::filesystem::remove(target);
  {
    AtomicOutput output(target);
    std::ofstream(output.temporary_path()) << "half";
    // destroyed without Commit: a failed run
  }
  EXPECT_FALSE(std::filesystem::exists(target));
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  WriteTextFileAtomic(target, "whole");
  std::ifstream in(target);
  std::string text;
  in >> text;
  EXPECT_EQ(text, "whole");
  EXPECT_THROW(AtomicOutput(dir / "missing_folder" / "x.txt"), Error);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace bridgefit
