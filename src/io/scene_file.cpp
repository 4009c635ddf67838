#include "bridgefit/io/scene_file.hpp"

#include <fstream>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/input_limits.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/io/csv.hpp"
#include "toml_section.hpp"

namespace bridgefit::io {
namespace {

using detail::LineOf;
using detail::Section;

double ParseAngle(const Section& section, const char* key) {
  if (!section.has(key)) return 0.0;
  std::string text = section.String(key, "0 deg");
  double value = 0.0;
  char unit[16] = {0};
  if (std::sscanf(text.c_str(), "%lf %15s", &value, unit) != 2 ||
      (std::string(unit) != "deg" && std::string(unit) != "rad"))
    throw Error(ErrorKind::kInput, "an angle needs a unit",
                {.file = section.Context(key).file, .line = section.Context(key).line,
                 .field = section.Context(key).field, .value = text,
                 .expected = "an angle such as '30 deg' or '0.5 rad'"});
  return std::string(unit) == "deg" ? value * std::numbers::pi / 180.0 : value;
}

// The document: valid TOML with only the known sections.
toml::table ParseRoot(std::string_view text, const std::string& source_name) {
  toml::table root;
  try {
    root = toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    throw Error(ErrorKind::kInput, std::string("not valid TOML: ") + std::string(e.description()),
                {.file = source_name, .line = static_cast<int>(e.source().begin.line),
                 .expected = "a scene in TOML (see docs/FORMATS.md)"});
  }
  const std::set<std::string> sections = {"specimen", "material", "fracture", "bridging", "run"};
  for (auto&& [key, value] : root) {
    if (!sections.count(std::string(key.str())))
      throw Error(ErrorKind::kInput, "unknown section or key",
                  {.file = source_name, .line = LineOf(value), .field = std::string(key.str()),
                   .expected = "one of [specimen], [material], [fracture], [bridging], [run]"});
  }
  return root;
}

// [specimen]: CT (W, B, optional height) or DCB (b, h, L), notch, plane.
SpecimenSpec ParseSpecimen(const toml::table& root, const std::string& source_name) {
  const Section specimen(root, source_name, "specimen",
                         {"type", "width", "height", "thickness", "length", "notch", "plane"});
  if (!specimen.present())
    throw Error(ErrorKind::kInput, "missing required section",
                {.file = source_name, .field = "specimen", .expected = "a [specimen] table"});
  const std::string type = specimen.String("type", "", true);
  SpecimenSpec s;
  if (type == "ct") {
    s.type = SpecimenType::kCT;
    s.width = specimen.Quantity("width", Dimension::Length());
    s.height = specimen.OptionalQuantity("height", Dimension::Length()).value_or(1.2 * s.width);
    s.thickness = specimen.Quantity("thickness", Dimension::Length());
    if (specimen.has("length"))
      throw Error(ErrorKind::kInput, "a CT specimen has no 'length' (its total width is 1.25 W)",
                  specimen.Context("length", "no length key for type = \"ct\""));
  } else if (type == "dcb") {
    s.type = SpecimenType::kDCB;
    s.width = specimen.Quantity("width", Dimension::Length());
    s.height = specimen.Quantity("height", Dimension::Length());
    s.length = specimen.Quantity("length", Dimension::Length());
    s.thickness = specimen.OptionalQuantity("thickness", Dimension::Length()).value_or(2.0 * s.height);
  } else {
    ErrorContext c = specimen.Context("type", "\"ct\" or \"dcb\"");
    c.value = type;
    throw Error(ErrorKind::kInput, "unknown specimen type", c);
  }
  s.notch = specimen.Quantity("notch", Dimension::Length());
  const std::string plane = specimen.String("plane", "stress");
  if (plane == "stress") {
    s.plane = PlaneCondition::kPlaneStress;
  } else if (plane == "strain") {
    s.plane = PlaneCondition::kPlaneStrain;
  } else {
    ErrorContext c = specimen.Context("plane", "\"stress\" or \"strain\"");
    c.value = plane;
    throw Error(ErrorKind::kInput, "unknown plane condition", c);
  }
  return s;
}

// [material]: isotropic (E, nu) or orthotropic (E1, E2, G12, nu12, angle).
MaterialSpec ParseMaterial(const toml::table& root, const std::string& source_name) {
  const Section material(root, source_name, "material",
                         {"E", "nu", "E1", "E2", "G12", "nu12", "G13", "angle", "density"});
  if (!material.present())
    throw Error(ErrorKind::kInput, "missing required section",
                {.file = source_name, .field = "material", .expected = "a [material] table"});
  MaterialSpec m;
  m.orthotropic = material.has("E1") || material.has("E2") || material.has("G12");
  if (m.orthotropic) {
    if (material.has("E") || material.has("nu"))
      throw Error(ErrorKind::kInput, "give either E and nu (isotropic) or E1, E2, G12, nu12",
                  material.Context(material.has("E") ? "E" : "nu", "not both kinds"));
    m.E1 = material.Quantity("E1", Dimension::Stress());
    m.E2 = material.Quantity("E2", Dimension::Stress());
    m.G12 = material.Quantity("G12", Dimension::Stress());
    m.nu12 = material.Number("nu12", 0.0, true);
    m.G13 = material.OptionalQuantity("G13", Dimension::Stress()).value_or(m.G12);
    m.angle = ParseAngle(material, "angle");
  } else {
    m.E = material.Quantity("E", Dimension::Stress());
    m.nu = material.Number("nu", 0.0, true);
    m.G13 = material.OptionalQuantity("G13", Dimension::Stress()).value_or(m.E / (2.0 * (1.0 + m.nu)));
  }
  m.density = material.OptionalQuantity("density", Dimension::Density()).value_or(0.0);
  return m;
}

// [bridging]: a law family with its shape options and two of its scales.
std::optional<BridgingSpec> ParseBridging(const toml::table& root, const std::string& source_name) {
  const Section bridging(root, source_name, "bridging",
                         {"law", "sigma_c", "J_B", "delta_c", "peak_ratio", "alpha", "trilinear",
                          "table"});
  if (!bridging.present()) return std::nullopt;
  BridgingSpec b;
  const std::string law = bridging.String("law", "linear");
  laws::LawFamily family;
  try {
    family = laws::ParseLawFamily(law);
  } catch (const Error& e) {
    throw e.WithContext(bridging.Context("law"));
  }
  laws::LawScales given{
      bridging.OptionalQuantity("sigma_c", Dimension::Stress()).value_or(NAN),
      bridging.OptionalQuantity("delta_c", Dimension::Length()).value_or(NAN),
      bridging.OptionalQuantity("J_B", Dimension::EnergyPerArea()).value_or(NAN)};
  try {
    laws::ShapeSpec spec{.family = family};
    if (family == laws::LawFamily::kTriangular)
      spec.peak_ratio = bridging.Number("peak_ratio", laws::kDefaultPeakRatio);
    if (family == laws::LawFamily::kExponential)
      spec.alpha = bridging.Number("alpha", laws::kDefaultExponentialAlpha);
    if (family == laws::LawFamily::kTrilinear) spec.trilinear = bridging.Numbers("trilinear", 5);
    if (family == laws::LawFamily::kTable) {
      std::filesystem::path table = bridging.String("table", "", true);
      if (table.is_relative()) table = std::filesystem::path(source_name).parent_path() / table;
      b.table_file = table.string();
      // A table is small: refused at its own limit (a scene naming
      // /dev/zero would otherwise read until memory runs out).
      const CsvTable csv = ReadCsvTable(table, CsvKind::kLawTable);
      spec.table_delta = csv.ColumnSi("delta", Dimension::Length());
      spec.table_sigma = csv.ColumnSi("sigma", Dimension::Stress());
    }
    b.shape = laws::MakeShape(spec, &given);
    b.scales = laws::CompleteScales(b.shape, given);
  } catch (const Error& e) {
    ErrorContext c = bridging.Context(e.context().field.empty() ? "law" : e.context().field.c_str());
    throw e.WithContext(c);
  }
  return b;
}

}  // namespace

Scene ParseScene(std::string_view text, const std::string& source_name) {
  const toml::table root = ParseRoot(text, source_name);
  Scene scene;
  scene.source = source_name;
  scene.specimen = ParseSpecimen(root, source_name);
  scene.material = ParseMaterial(root, source_name);

  const Section fracture(root, source_name, "fracture", {"J_tip_c"});
  if (fracture.present()) scene.fracture = FractureSpec{fracture.Quantity("J_tip_c", Dimension::EnergyPerArea())};
  scene.bridging = ParseBridging(root, source_name);

  const Section run(root, source_name, "run", {"max_crack_length", "grow", "load_point_displacement"});
  scene.run.max_crack_length = run.OptionalQuantity("max_crack_length", Dimension::Length());
  scene.run.grow = run.Bool("grow", true);
  scene.run.load_point_displacement = run.OptionalQuantity("load_point_displacement", Dimension::Length());

  scene.Validate();
  return scene;
}

Scene ReadSceneFile(const std::filesystem::path& path) {
  const std::string text = detail::ReadTomlText(path, "scene file");
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw Error(ErrorKind::kInput, "the scene file is empty",
                {.file = path.string(), .expected = "a scene with [specimen] and [material]"});
  return ParseScene(text, path.string());
}

}  // namespace bridgefit::io
