#pragma once
// A campaign manifest (issue 19; format: docs/FORMATS.md "Campaign manifest"):
// the shared scene and fit choices in [campaign], then one [[specimen]] table
// per test. Paths are relative to the manifest's folder. Unknown keys,
// missing files, duplicate names and bare numbers where a unit is needed are
// errors naming the manifest, the line and the key - all found here, before
// any work starts. The fit choices stay text (as on the `fit` command line);
// the campaign module turns them into requests, naming the line they came
// from (`lines`).

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bridgefit/scene/scene.hpp"

namespace bridgefit::io {

// The record-reading and fit choices a specimen may set for itself; empty
// text means "the campaign's".
struct ManifestChoices {
  std::string columns, units;  // record column and unit mapping, e.g. "load=Force"
  std::string rcurve_method;   // energy | mbt | cc | lefm | equivalent
  std::string fit_to;          // r-curve | load-displacement
  std::string calibrate_compliance;  // "" | initial | crack
};

// A specimen's crack lengths measured by DIC on its images ([specimen.dic]
// table; docs/FORMATS.md): the folder and `bridgefit dic`'s settings, units
// checked here (px or SI); defaults as `dic`'s. Whether the folder holds
// images and the settings make valid options is checked by the campaign
// (campaign::BuildDicRequests), before any work.
struct ManifestDic {
  std::filesystem::path images;  // the folder (exists; relative to the manifest)
  double scale_m_per_px = 0;     // scale, e.g. "0.15 mm/px"
  double offset_m = 0;           // offset, e.g. "20 mm"
  std::optional<std::array<double, 4>> crack_line;  // x0, y0, x1, y1 [px]
  bool fixed_line = false;
  int subset_px = 31, step_px = 5;
  std::string tip_method = "williams";
  double threshold_px = 0.02;  // a length is converted with the scale
  double path_search_px = 40;
};

struct ManifestSpecimen {
  std::string name;
  int line = 0;                      // the line of its [[specimen]] header
  std::filesystem::path record;      // the record or R curve (CSV or HDF5)
  std::filesystem::path scene_path;  // its own scene, or the campaign's
  Scene scene;                       // read, the specimen's sizes applied, validated
  ManifestChoices choices;
  std::optional<ManifestDic> dic;    // [specimen.dic]: DIC on its images
  std::map<std::string, int> lines;  // key -> manifest line ("dic.scale" for [specimen.dic])
};

struct CampaignManifest {
  std::filesystem::path path;
  std::string name;                  // [campaign] name (default: the file's stem)
  std::filesystem::path scene_path;  // the shared scene
  std::string law = "linear";        // as `fit --law` (pipeline::SetFitLaw): a family or "compare"
  std::string model = "reduced";     // reduced | analytic
  std::optional<double> resolution;  // reduced model element size [m]
  bool profile = true;               // profile-likelihood intervals
  // The law parameters the joint fit (--joint) shares, as written (names
  // checked by the campaign, naming lines["joint"]); absent: all.
  std::optional<std::vector<std::string>> joint;
  ManifestChoices choices;           // defaults: energy R curve, r-curve fit
  std::vector<ManifestSpecimen> specimens;
  std::map<std::string, int> lines;  // [campaign] key -> line
};

CampaignManifest ReadCampaignManifest(const std::filesystem::path& path);
// `path` names the manifest in messages and anchors relative paths.
CampaignManifest ParseCampaignManifest(std::string_view text, const std::filesystem::path& path);

}  // namespace bridgefit::io
