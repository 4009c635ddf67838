// `bridgefit design`: the specimen size that would identify J_B and delta_c
// (issue 19; docs/CAMPAIGN.md "Design").
//   bridgefit design data_samples/mdf_ct/scene.toml --sigma-c 1MPa --jb 500J/m^2 --size 50mm:200mm:25mm
// Flags -> campaign::RunDesign -> printing.

#include <iostream>

#include "bridgefit/campaign/design.hpp"
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
           "(reduced model over similar specimens of the scene's shape)";
  }
  void Register(CLI::App& sub) override {
    sub.add_option("scene", scene_, "Scene (TOML) with the shape, material, [fracture] and [bridging]")
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
  }

  int Run(const CommonOptions& common) override {
    campaign::DesignRequest request;
    request.scene = io::ReadSceneFile(scene_);
    const auto parts = Split(size_);
    request.sizes = campaign::SizeGrid(ParseOptionQuantity(parts[0], Dimension::Length(), "--size"),
                                       ParseOptionQuantity(parts[1], Dimension::Length(), "--size"),
                                       ParseOptionQuantity(parts[2], Dimension::Length(), "--size"),
                                       "--size");
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

  std::string scene_, size_, sigma_c_, J_B_;
  double resolution_fraction_ = 0.0;
  int r_points_ = 20;
};

}  // namespace

std::unique_ptr<Command> MakeDesignCommand() { return std::make_unique<DesignCommand>(); }

}  // namespace bridgefit::cli
