// `bridgefit design`: the specimen size that would identify J_B and delta_c
// (issue 19; docs/CAMPAIGN.md "Design").
//   bridgefit design data_samples/mdf_ct/scene.toml --sigma-c 1MPa --jb 500J/m^2 --size 50mm:200mm:25mm
//   bridgefit design fit.h5 --size 50mm:300mm:25mm --chart design_chart
// Flags -> campaign::RunDesign (a scene) or campaign::RunFitDesign (a fit
// file or campaign.h5, told apart from a scene by its .toml name) -> printing.

#include <filesystem>
#include <iostream>

#include "bridgefit/campaign/design.hpp"
#include "bridgefit/campaign/design_fit.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/laws/law.hpp"
#include "command.hpp"

namespace bridgefit::cli {
namespace {

class DesignCommand final : public Command {
 public:
  const char* name() const override { return "design"; }
  const char* description() const override {
    return "Which specimen size reaches steady state early enough to identify J_B and delta_c "
           "(reduced model over similar specimens of the scene's or the fit's shape)";
  }
  void Register(CLI::App& sub) override {
    sub.add_option("scene", scene_,
                   "Scene (TOML) with the shape, material, [fracture] and [bridging]; or a fit "
                   "file (bridgefit fit --out) or campaign.h5: its law (bound and 95% region), "
                   "specimen and material")
        ->required()
        ->check(CLI::ExistingFile);
    sub.add_option("--size", size_,
                   "Sizes FROM:TO:STEP (CT: W; DCB: L, the arm height and a0 scaled with it), "
                   "e.g. 50mm:200mm:25mm")
        ->required();
    sub.add_option("--sigma-c", sigma_c_, "Override the scene's sigma_c, e.g. '1 MPa'");
    sub.add_option("--jb", J_B_, "Override the scene's J_B, e.g. '500 J/m^2'");
    sub.add_option("--resolution-fraction", resolution_fraction_,
                   "Element size / characteristic size (CT W, DCB h); 0: the model's default")
        ->default_val(0.0);
    sub.add_option("--r-points", r_points_, "R points a test gives over its growth window")
        ->default_val(20);
    sub.add_option("--specimen", specimen_, "Fit file: the specimen to design (ct|dcb), the fit's own")
        ->check(CLI::IsMember({"ct", "dcb"}));
    sub.add_option("--shape-scene", shape_scene_,
                   "Fit file: design this scene's specimen and material instead of the fit's")
        ->check(CLI::ExistingFile);
    sub.add_option("--grid", grid_, "Fit file: region points per parameter (2..9)")->default_val(3);
    sub.add_option("--jb-cap", jb_cap_,
                   "Fit file: where J_B is only a lower bound, the region's upper end as a "
                   "multiple of the bound")
        ->default_val(2.0);
    sub.add_option("--sigma-c-span", sigma_c_span_,
                   "Fit file: where sigma_c's 95% interval is open or reaches 0, the region's "
                   "end as the value divided or multiplied by this")
        ->default_val(2.0);
    sub.add_option("--chart", chart_, "Fit file: folder for the onset-against-size chart (onset.png)");
  }

  int Run(const CommonOptions& common) override {
    if (std::filesystem::path(scene_).extension() != ".toml") return RunFit(common);
    if (!specimen_.empty() || !shape_scene_.empty() || !chart_.empty())
      throw Error(ErrorKind::kUsage, "--specimen, --shape-scene and --chart take a fit file",
                  {.file = scene_, .expected = "a fit file (bridgefit fit --out) or campaign.h5"});
    campaign::DesignRequest request;
    request.scene = io::ReadSceneFile(scene_);
    request.sizes = Sizes();
    if (!sigma_c_.empty() || !J_B_.empty()) {
      if (!request.scene.bridging)
        throw Error(ErrorKind::kInput, "the scene has no bridging law to override",
                    {.file = scene_, .field = "bridging", .expected = "a [bridging] table"});
      laws::LawScales given = request.scene.bridging->scales;
      if (!sigma_c_.empty())
        given.sigma_c = ParseOptionQuantity(sigma_c_, Dimension::Stress(), "--sigma-c");
      if (!J_B_.empty()) given.J_B = ParseOptionQuantity(J_B_, Dimension::EnergyPerArea(), "--jb");
      given.delta_c = NAN;  // follows from the other two
      request.scene.bridging->scales = laws::CompleteScales(request.scene.bridging->shape, given);
    }
    request.resolution_fraction = resolution_fraction_;
    request.r_points = r_points_;
    std::string why;
    if (!request.IsValid(&why))
      throw Error(ErrorKind::kInput, why, {.file = scene_, .expected = "a scene with [fracture] and [bridging]"});
    const campaign::DesignResult result = campaign::RunDesign(request);
    if (const std::string w = result.Warning(); !w.empty()) std::cerr << "warning: design: " << w << "\n";
    if (common.json) {
      nlohmann::json sizes = nlohmann::json::array();
      for (const campaign::DesignSize& d : result.sizes)
        sizes.push_back({{"size_m", d.size}, {"notch_m", d.notch}, {"window_end_m", d.window_end},
                         {"steady_state_reached", d.reached}, {"onset_m", NumberOrNull(d.onset)},
                         {"points_past_onset", d.points_past}, {"identifies", d.identifies},
                         {"status", RunStatusName(d.status)}, {"message", d.message}});
      PrintJson({{"command", "design"}, {"scene", scene_}, {"sizes", sizes},
                 {"sizes_unknown_below_smallest", result.UnknownBelowSmallest()},
                 {"warning", result.Warning()},
                 {"smallest_identifying_size_m",
                  result.smallest >= 0 ? nlohmann::json(result.sizes[result.smallest].size)
                                       : nlohmann::json(nullptr)}});
    } else {
      std::cout << "design for " << scene_ << " (reduced model, similar specimens):\n"
                << result.BriefReport();
    }
    return 0;
  }

 private:
  std::vector<double> Sizes() const {
    const auto parts = Split(size_);
    return campaign::SizeGrid(ParseOptionQuantity(parts[0], Dimension::Length(), "--size"),
                              ParseOptionQuantity(parts[1], Dimension::Length(), "--size"),
                              ParseOptionQuantity(parts[2], Dimension::Length(), "--size"), "--size");
  }

  // The fit-file route: the law's bound and region from the file.
  int RunFit(const CommonOptions& common) {
    if (!sigma_c_.empty() || !J_B_.empty())
      throw Error(ErrorKind::kUsage, "--sigma-c and --jb override a scene's law, not a fit's",
                  {.file = scene_, .expected = "a scene (.toml) with --sigma-c / --jb"});
    campaign::FitDesignRequest request;
    request.law = campaign::ReadDesignLaw(scene_);
    if (!specimen_.empty())
      request.specimen = specimen_ == "dcb" ? SpecimenType::kDCB : SpecimenType::kCT;
    if (!shape_scene_.empty()) request.scene = io::ReadSceneFile(shape_scene_);
    request.sizes = Sizes();
    request.grid = grid_;
    request.jb_cap_factor = jb_cap_;
    request.sigma_c_span = sigma_c_span_;
    request.resolution_fraction = resolution_fraction_;
    request.r_points = r_points_;
    std::string why;
    if (!request.IsValid(&why))
      throw Error(ErrorKind::kInput, why, {.file = scene_, .expected = "a fit with sigma_c and J_B (or its bound)"});
    const campaign::FitDesignResult result = campaign::RunFitDesign(request);
    std::string chart;
    if (!chart_.empty())
      chart = report::WriteDesignChart(campaign::DesignChartOf(result), chart_).string();
    if (const std::string w = result.Warning(); !w.empty()) std::cerr << "warning: design: " << w << "\n";
    if (common.json) {
      PrintJson(FitDesignJson(result, chart));
    } else {
      std::cout << "design from " << scene_ << " (reduced model, similar specimens):\n"
                << result.BriefReport();
      if (!chart.empty()) std::cout << "  chart: " << chart << "\n";
    }
    return 0;
  }

  static nlohmann::json LawJson(const campaign::RegionLaw& law) {
    return {{"sigma_c_Pa", law.sigma_c}, {"J_B_J_per_m2", law.J_B}, {"delta_c_m", law.delta_c}};
  }

  nlohmann::json FitDesignJson(const campaign::FitDesignResult& r, const std::string& chart) const {
    nlohmann::json region = nlohmann::json::array(), sizes = nlohmann::json::array();
    for (const campaign::RegionLaw& law : r.region) region.push_back(LawJson(law));
    for (const campaign::FitDesignSize& s : r.sizes)
      sizes.push_back({{"size_m", s.size}, {"notch_m", s.notch}, {"window_end_m", s.window_end},
                       {"bound_onset_m", NumberOrNull(s.bound_onset)},
                       {"bound_identifies", s.bound_identifies},
                       {"worst_onset_m", NumberOrNull(s.worst_onset)},
                       {"worst_law", s.worst_law >= 0 ? LawJson(r.region[s.worst_law]) : nlohmann::json(nullptr)},
                       {"region_earliest_onset_m", NumberOrNull(s.min_onset)},
                       {"region_reached", s.region_reached}, {"region_identify", s.region_identify},
                       {"region_unknown", s.region_unknown}});
    const auto size_or_null = [&r](int i) {
      return i >= 0 ? nlohmann::json(r.sizes[i].size) : nlohmann::json(nullptr);
    };
    return {{"command", "design"}, {"input", scene_}, {"law_from", r.note},
            {"specimen", r.specimen == SpecimenType::kCT ? "ct" : "dcb"},
            {"bound_law", LawJson(r.bound)}, {"bound_law_text", r.bound_text},
            {"region_text", r.region_text}, {"region_laws", region},
            {"jb_cap_factor", jb_cap_}, {"sigma_c_span", sigma_c_span_}, {"sizes", sizes},
            {"smallest_size_bound_law_m", size_or_null(r.smallest_bound)},
            {"smallest_size_whole_region_m", size_or_null(r.smallest_region)},
            {"warning", r.Warning()}, {"chart", chart.empty() ? nlohmann::json(nullptr) : nlohmann::json(chart)},
            {"wall_s", r.wall_s}};
  }

  std::vector<std::string> Split(const std::string& text) const {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (std::size_t colon; (colon = text.find(':', start)) != std::string::npos; start = colon + 1)
      parts.push_back(text.substr(start, colon - start));
    parts.push_back(text.substr(start));
    if (parts.size() != 3)
      throw Error(ErrorKind::kUsage, "bad size range",
                  {.field = "--size", .value = text, .expected = "FROM:TO:STEP, e.g. 50mm:200mm:25mm"});
    return parts;
  }

  std::string scene_, size_, sigma_c_, J_B_, specimen_, shape_scene_, chart_;
  double resolution_fraction_ = 0.0, jb_cap_ = 2.0, sigma_c_span_ = 2.0;
  int r_points_ = 20, grid_ = 3;
};

}  // namespace

std::unique_ptr<Command> MakeDesignCommand() { return std::make_unique<DesignCommand>(); }

}  // namespace bridgefit::cli
