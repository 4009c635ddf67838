// The campaign manifest reader (format: docs/FORMATS.md "Campaign manifest").
#include "bridgefit/io/campaign_manifest.hpp"

#include <cmath>
#include <iterator>
#include <set>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/input_limits.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "toml_section.hpp"

namespace bridgefit::io {
namespace {

namespace fs = std::filesystem;
using detail::LineOf;
using detail::Section;

const char* const kChoiceKeys[] = {"columns", "units", "rcurve_method", "fit_to",
                                   "calibrate_compliance"};
// Specimen sizes a [[specimen]] may set over its scene's [specimen] values.
const char* const kSizeKeys[] = {"width", "height", "thickness", "length", "notch"};

void RecordLine(const Section& section, const char* key, std::map<std::string, int>* lines) {
  if (section.has(key)) (*lines)[key] = section.Context(key).line;
}

ManifestChoices ReadChoices(const Section& section, std::map<std::string, int>* lines) {
  ManifestChoices c;
  c.columns = section.String("columns", "");
  c.units = section.String("units", "");
  c.rcurve_method = section.String("rcurve_method", "");
  c.fit_to = section.String("fit_to", "");
  c.calibrate_compliance = section.String("calibrate_compliance", "");
  for (const char* key : kChoiceKeys) RecordLine(section, key, lines);
  return c;
}

// A path key, relative to the manifest's folder, that must name a file.
fs::path ExistingFile(const Section& section, const char* key, const fs::path& base,
                      const std::string& expected) {
  const std::string text = section.String(key, "", /*required=*/true);
  const fs::path path = fs::path(text).is_absolute() ? fs::path(text) : base / text;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    ErrorContext context = section.Context(key, expected);
    context.value = path.string();
    throw Error(ErrorKind::kInput, "file not found", context);
  }
  return path;
}

Scene ReadSpecimenScene(const fs::path& scene_path, const Section& section) {
  Scene scene;
  try {
    scene = ReadSceneFile(scene_path);
  } catch (const Error& e) {
    throw Error(ErrorKind::kInput,
                fmt::format("the scene of {} cannot be read: {}", section.name(), e.what()),
                section.Context("scene", "a scene file (docs/FORMATS.md)"));
  }
  SpecimenSpec& s = scene.specimen;
  double* const targets[] = {&s.width, &s.height, &s.thickness, &s.length, &s.notch};
  for (int i = 0; i < 5; ++i)
    if (section.has(kSizeKeys[i])) *targets[i] = section.Quantity(kSizeKeys[i], Dimension::Length());
  try {
    scene.Validate();
  } catch (const Error& e) {
    throw Error(ErrorKind::kInput,
                fmt::format("{} with its sizes is not a valid scene: {}", section.name(), e.what()),
                section.Context("name"));
  }
  return scene;
}

// A path key, relative to the manifest's folder, that must name a folder.
fs::path ExistingFolder(const Section& section, const char* key, const fs::path& base,
                        const std::string& expected) {
  const std::string text = section.String(key, "", /*required=*/true);
  const fs::path path = fs::path(text).is_absolute() ? fs::path(text) : base / text;
  std::error_code ec;
  if (!fs::is_directory(path, ec)) {
    ErrorContext context = section.Context(key, expected);
    context.value = path.string();
    throw Error(ErrorKind::kInput, "folder not found", context);
  }
  return path;
}

ErrorContext WithValue(ErrorContext context, const std::string& value) {
  context.value = value;
  return context;
}

// A whole number of pixels, e.g. "31 px".
int WholePixels(const Section& section, const char* key, int fallback) {
  if (!section.has(key)) return fallback;
  const double v = section.Quantity(key, Dimension::Pixel());
  if (!(v >= 1 && v <= 10000 && v == std::floor(v)))
    throw Error(ErrorKind::kInput, "must be a whole number of pixels",
                WithValue(section.Context(key, "e.g. \"31 px\""), fmt::format("{:g} px", v)));
  return static_cast<int>(v);
}

// [specimen.dic]: the images and `bridgefit dic`'s settings.
ManifestDic ReadDic(const toml::node& node, const Section& specimen, const fs::path& base,
                    std::map<std::string, int>* lines) {
  static const char* const kKeys[] = {"images", "scale",  "offset",     "crack_line", "fixed_line",
                                      "subset", "step",   "tip_method", "threshold",  "path_search"};
  const toml::table* table = node.as_table();
  if (!table)
    throw Error(ErrorKind::kInput, "must be a [specimen.dic] table",
                specimen.Context("dic", "a table of the specimen's DIC settings"));
  const Section section(table, specimen.file(), specimen.name() + ".dic",
                        std::set<std::string>(std::begin(kKeys), std::end(kKeys)));
  ManifestDic d;
  d.images = ExistingFolder(section, "images", base,
                            "the folder of the specimen's images, relative to the manifest");
  d.scale_m_per_px = section.Quantity("scale", Dimension::LengthPerPixel());
  if (!(d.scale_m_per_px > 0))
    throw Error(ErrorKind::kInput, "the image scale must be positive",
                section.Context("scale", "a length per pixel, e.g. \"0.15 mm/px\""));
  d.offset_m = section.OptionalQuantity("offset", Dimension::Length()).value_or(0.0);
  if (section.has("crack_line")) {
    const toml::node* line = table->get("crack_line");
    const toml::array* array = line->as_array();
    const std::string expected = "four pixel positions x0, y0, x1, y1, e.g. "
                                 "[\"0 px\", \"150 px\", \"399 px\", \"150 px\"]";
    if (!array || array->size() != 4)
      throw Error(ErrorKind::kInput, "wrong value", section.Context("crack_line", expected));
    std::array<double, 4> xy{};
    for (std::size_t k = 0; k < 4; ++k) {
      const auto text = (*array)[k].value<std::string>();
      if (!text)
        throw Error(ErrorKind::kInput, "each position needs its unit (px)",
                    section.Context("crack_line", expected));
      try {
        xy[k] = ParseQuantity(*text, Dimension::Pixel());
      } catch (const Error& e) {
        throw e.WithContext(section.Context("crack_line", expected));
      }
    }
    d.crack_line = xy;
  }
  d.fixed_line = section.Bool("fixed_line", false);
  d.subset_px = WholePixels(section, "subset", d.subset_px);
  d.step_px = WholePixels(section, "step", d.step_px);
  d.tip_method = section.String("tip_method", d.tip_method);
  if (section.has("threshold")) {
    const std::string text = section.String("threshold", "");
    try {
      d.threshold_px = ParseQuantity(text, Dimension::Pixel());
    } catch (const Error&) {
      try {
        d.threshold_px = ParseQuantity(text, Dimension::Length()) / d.scale_m_per_px;
      } catch (const Error&) {
        throw Error(ErrorKind::kInput, "expected pixels or a length",
                    WithValue(section.Context("threshold", "e.g. \"0.02 px\" or \"0.003 mm\""),
                              text));
      }
    }
  }
  d.path_search_px = section.OptionalQuantity("path_search", Dimension::Pixel()).value_or(40.0);
  (*lines)["dic"] = section.line();
  for (const char* key : kKeys)
    if (section.has(key)) (*lines)[std::string("dic.") + key] = section.Context(key).line;
  return d;
}

ManifestSpecimen ReadSpecimen(const toml::table& table, const std::string& file, int index,
                              const fs::path& base, const CampaignManifest& campaign) {
  std::set<std::string> allowed = {"name", "record", "scene", "dic"};
  for (const char* key : kChoiceKeys) allowed.insert(key);
  for (const char* key : kSizeKeys) allowed.insert(key);
  const Section section(&table, file, fmt::format("specimen[{}]", index + 1), allowed);
  ManifestSpecimen sp;
  sp.line = LineOf(table);
  sp.name = section.String("name", "", /*required=*/true);
  if (sp.name.empty() || sp.name.find_first_of("/\\\"\n") != std::string::npos)
    throw Error(ErrorKind::kInput, "bad specimen name",
                section.Context("name", "a non-empty name without / \\ \" or line breaks "
                                        "(it names the specimen's outputs)"));
  for (const char* key : {"name", "record", "scene"}) RecordLine(section, key, &sp.lines);
  for (const char* key : kSizeKeys) RecordLine(section, key, &sp.lines);
  sp.record = ExistingFile(section, "record", base,
                           "a record or R curve (CSV or HDF5), relative to the manifest");
  sp.scene_path = section.has("scene")
                      ? ExistingFile(section, "scene", base, "a scene file, relative to the manifest")
                      : campaign.scene_path;
  if (sp.scene_path.empty())
    section.Missing("scene", "a scene here or in [campaign] (scene = \"scene.toml\")");
  sp.scene = ReadSpecimenScene(sp.scene_path, section);
  sp.choices = ReadChoices(section, &sp.lines);
  if (const toml::node* dic = table.get("dic")) sp.dic = ReadDic(*dic, section, base, &sp.lines);
  return sp;
}

}  // namespace

CampaignManifest ParseCampaignManifest(std::string_view text, const fs::path& path) {
  const std::string file = path.string();
  toml::table root;
  try {
    root = toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    throw Error(ErrorKind::kInput, std::string("not valid TOML: ") + std::string(e.description()),
                {.file = file, .line = static_cast<int>(e.source().begin.line),
                 .expected = "a campaign manifest in TOML (docs/FORMATS.md)"});
  }
  for (auto&& [key, value] : root)
    if (key.str() != "campaign" && key.str() != "specimen")
      throw Error(ErrorKind::kInput, "unknown section or key",
                  {.file = file, .line = LineOf(value), .field = std::string(key.str()),
                   .expected = "[campaign] and [[specimen]] tables"});
  const fs::path base = path.has_parent_path() ? path.parent_path() : fs::path(".");

  CampaignManifest m;
  m.path = path;
  std::set<std::string> allowed = {"name", "scene", "law", "model", "resolution", "profile", "joint"};
  for (const char* key : kChoiceKeys) allowed.insert(key);
  const Section campaign(root, file, "campaign", allowed);
  m.name = campaign.String("name", path.stem().string());
  if (campaign.has("scene"))
    m.scene_path = ExistingFile(campaign, "scene", base, "a scene file, relative to the manifest");
  m.law = campaign.String("law", m.law);
  m.model = campaign.String("model", m.model);
  if (campaign.has("resolution")) m.resolution = campaign.Quantity("resolution", Dimension::Length());
  m.profile = campaign.Bool("profile", true);
  if (campaign.has("joint")) m.joint = campaign.Strings("joint");
  for (const char* key : {"name", "scene", "law", "model", "resolution", "profile", "joint"})
    RecordLine(campaign, key, &m.lines);
  m.choices = ReadChoices(campaign, &m.lines);

  const toml::node* specimens = root.get("specimen");
  const toml::array* array = specimens ? specimens->as_array() : nullptr;
  if (!array || array->empty())
    throw Error(ErrorKind::kInput, "no specimens",
                {.file = file, .line = specimens ? LineOf(*specimens) : 0, .field = "specimen",
                 .expected = "one [[specimen]] table per test, each with name and record"});
  std::map<std::string, int> first_line;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::table* table = (*array)[i].as_table();
    if (!table)
      throw Error(ErrorKind::kInput, "must be a [[specimen]] table",
                  {.file = file, .line = LineOf((*array)[i]), .field = "specimen"});
    ManifestSpecimen sp = ReadSpecimen(*table, file, static_cast<int>(i), base, m);
    const auto [it, inserted] = first_line.emplace(sp.name, sp.lines["name"]);
    if (!inserted)
      throw Error(ErrorKind::kInput, "duplicate specimen name",
                  {.file = file, .line = sp.lines["name"], .field = "specimen.name", .value = sp.name,
                   .expected = fmt::format("a name not used before (line {} has it)", it->second)});
    m.specimens.push_back(std::move(sp));
  }
  return m;
}

CampaignManifest ReadCampaignManifest(const fs::path& path) {
  return ParseCampaignManifest(detail::ReadTomlText(path, "campaign manifest"), path);
}

}  // namespace bridgefit::io
