#include "bridgefit/io/scene_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "bridgefit/core/error.hpp"

namespace bridgefit::io {
namespace {

const std::string kScenes = std::string(BRIDGEFIT_TEST_DATA_DIR) + "/scenes/";

TEST(Scene, ReadsTheIssueExample) {
  const Scene scene = ReadSceneFile(kScenes + "ct_mdf.toml");
  EXPECT_EQ(scene.specimen.type, SpecimenType::kCT);
  EXPECT_DOUBLE_EQ(scene.specimen.width, 0.1);
  EXPECT_DOUBLE_EQ(scene.specimen.height, 0.12);
  EXPECT_DOUBLE_EQ(scene.specimen.thickness, 12.7e-3);
  EXPECT_DOUBLE_EQ(scene.specimen.notch, 0.03);
  EXPECT_DOUBLE_EQ(scene.material.E, 3e9);
  EXPECT_DOUBLE_EQ(scene.material.nu, 0.3);
  EXPECT_DOUBLE_EQ(scene.material.density, 609.0);
  ASSERT_TRUE(scene.fracture.has_value());
  EXPECT_DOUBLE_EQ(scene.fracture->J_tip_c, 2210.0);
  ASSERT_TRUE(scene.bridging.has_value());
  EXPECT_EQ(scene.bridging->shape.family, laws::LawFamily::kLinear);
  EXPECT_DOUBLE_EQ(scene.bridging->scales.sigma_c, 0.45e6);
  EXPECT_DOUBLE_EQ(scene.bridging->scales.J_B, 500.0);
  EXPECT_NEAR(scene.bridging->scales.delta_c, 2 * 500.0 / 0.45e6, 1e-15);
  EXPECT_DOUBLE_EQ(*scene.run.max_crack_length, 0.08);
  EXPECT_TRUE(scene.run.grow);
}

TEST(Scene, ReadsOrthotropicDcbWithNPerMmToughness) {
  const Scene scene = ReadSceneFile(kScenes + "dcb_composite.toml");
  EXPECT_EQ(scene.specimen.type, SpecimenType::kDCB);
  EXPECT_TRUE(scene.material.orthotropic);
  EXPECT_DOUBLE_EQ(scene.material.E1, 19.3e9);
  EXPECT_DOUBLE_EQ(scene.material.G13, 3e9);  // defaults to G12
  EXPECT_DOUBLE_EQ(scene.fracture->J_tip_c, 350.0);
  EXPECT_DOUBLE_EQ(scene.bridging->scales.J_B, 600.0);
  EXPECT_DOUBLE_EQ(scene.specimen.CrackFrontWidth(), 25e-3);
}

TEST(Scene, TableLawRelativeToSceneFile) {
  const Scene scene = ReadSceneFile(kScenes + "ct_table_law.toml");
  EXPECT_EQ(scene.bridging->shape.family, laws::LawFamily::kTable);
  EXPECT_DOUBLE_EQ(scene.bridging->scales.sigma_c, 1.0e6);
  EXPECT_DOUBLE_EQ(scene.bridging->scales.delta_c, 2.0e-3);
  EXPECT_DOUBLE_EQ(scene.specimen.height, 0.06);  // default 1.2 W
}

constexpr const char* kGood = R"([specimen]
type = "ct"
width = "100 mm"
thickness = "12.7 mm"
notch = "30 mm"
[material]
E = "3 GPa"
nu = 0.3
)";

// Parses `text`; returns the error message (or fails when none is thrown).
std::string ErrorOf(const std::string& text) {
  try {
    ParseScene(text, "bad.toml");
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kInput);
    return e.what();
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return "";
}

void ExpectContains(const std::string& message, const std::vector<std::string>& parts) {
  for (const auto& part : parts) EXPECT_NE(message.find(part), std::string::npos)
      << "'" << part << "' not in: " << message;
}

TEST(Scene, GoodMinimalSceneParses) { EXPECT_NO_THROW(ParseScene(kGood, "good.toml")); }

TEST(Scene, BadScenesNameFileLineKeyAndExpectation) {
  std::string s = kGood;
  // 1. missing key
  ExpectContains(ErrorOf(std::string(kGood).replace(s.find("notch"), 16, "")),
                 {"bad.toml", "specimen.notch", "missing required key", "length"});
  // 2. wrong unit
  ExpectContains(ErrorOf(std::string(kGood).replace(s.find("\"3 GPa\""), 7, "\"3 mm\"")),
                 {"bad.toml:7", "material.E", "wrong unit", "MPa"});
  // 3. bare number
  ExpectContains(ErrorOf(std::string(kGood).replace(s.find("\"12.7 mm\""), 9, "12.7")),
                 {"bad.toml:4", "specimen.thickness", "bare number needs a unit", "mm"});
  // 4. negative thickness
  ExpectContains(ErrorOf(std::string(kGood).replace(s.find("\"12.7 mm\""), 9, "\"-12.7 mm\"")),
                 {"specimen.thickness", "must be positive", "-12.7 mm"});
  // 5. notch longer than the specimen
  ExpectContains(ErrorOf(std::string(kGood).replace(s.find("\"30 mm\""), 7, "\"130 mm\"")),
                 {"specimen.notch", "before the back edge", "W = 100 mm"});
  // 6. unknown key
  ExpectContains(ErrorOf(std::string(kGood) + "colour = \"red\"\n"),
                 {"bad.toml:9", "material.colour", "unknown key"});
  // 7. unknown section
  ExpectContains(ErrorOf(std::string(kGood) + "[solver]\nx = 1\n"),
                 {"bad.toml", "solver", "unknown section"});
  // 8. unknown specimen type
  ExpectContains(ErrorOf(std::string(kGood).replace(s.find("\"ct\""), 4, "\"sent\"")),
                 {"specimen.type", "unknown specimen type", "\"ct\" or \"dcb\""});
  // 9. law with delta_c <= 0
  ExpectContains(ErrorOf(std::string(kGood) +
                         "[bridging]\nlaw = \"linear\"\nsigma_c = \"1 MPa\"\ndelta_c = \"-1 mm\"\n"),
                 {"bad.toml", "delta_c", "must be positive"});
  // 10. law with only one scale
  ExpectContains(ErrorOf(std::string(kGood) + "[bridging]\nlaw = \"cubic\"\nsigma_c = \"1 MPa\"\n"),
                 {"bad.toml", "two of sigma_c, delta_c and J_B"});
  // 11. unknown law
  ExpectContains(ErrorOf(std::string(kGood) + "[bridging]\nlaw = \"quadratic\"\n"),
                 {"bad.toml:10", "law", "unknown bridging law", "linear, cubic"});
  // 12. Poisson's ratio out of range
  ExpectContains(ErrorOf(std::string(kGood).replace(s.find("nu = 0.3"), 8, "nu = 0.7")),
                 {"material.nu", "-1 < nu < 0.5"});
  // 13. not TOML at all
  ExpectContains(ErrorOf("[specimen\ntype = ct"), {"bad.toml:1", "not valid TOML"});
  // 14. max crack length beyond the back edge
  ExpectContains(ErrorOf(std::string(kGood) + "[run]\nmax_crack_length = \"120 mm\"\n"),
                 {"run.max_crack_length", "between the notch and the end"});
  // 15. missing [material]
  ExpectContains(ErrorOf("[specimen]\ntype = \"ct\"\nwidth = \"1 m\"\nthickness = \"1 cm\"\nnotch = \"3 cm\"\n"),
                 {"material", "missing required section"});
}

TEST(Scene, EmptyAndBinaryFiles) {
  const auto dir = std::filesystem::temp_directory_path() / "bf_scene_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "empty.toml") << "\n  \n";
  {
    std::ofstream garbage(dir / "garbage.toml", std::ios::binary);
    for (int i = 0; i < 512; ++i) garbage.put(static_cast<char>((i * 37) % 256));
  }
  try {
    ReadSceneFile(dir / "empty.toml");
    ADD_FAILURE();
  } catch (const Error& e) {
    ExpectContains(e.what(), {"empty.toml", "empty"});
  }
  try {
    ReadSceneFile(dir / "garbage.toml");
    ADD_FAILURE();
  } catch (const Error& e) {
    ExpectContains(e.what(), {"garbage.toml", "binary"});
  }
  try {
    ReadSceneFile(dir / "missing.toml");
    ADD_FAILURE();
  } catch (const Error& e) {
    ExpectContains(e.what(), {"missing.toml", "cannot open"});
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace bridgefit::io
