// `bridgefit campaign`: many specimens of one material (issue 19).
//   bridgefit campaign data_samples/dcb_campaign/campaign.toml --out campaign_out [--jobs 2]
//   mpirun -n 4 bridgefit campaign campaign.toml --out campaign_out   (docs/MPI.md)
// Flags -> campaign::RunCampaign -> printing; the manifest format is in
// docs/FORMATS.md, the statistics and outlier rule in docs/CAMPAIGN.md.

#include <iostream>
#include <optional>

#include <fmt/format.h>

#include "bridgefit/campaign/campaign.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/io/campaign_manifest.hpp"
#include "bridgefit/parallel/communicator.hpp"
#include "command.hpp"

namespace bridgefit::cli {
namespace {

nlohmann::json ResultJson(const campaign::CampaignResult& r, const std::string& out_dir) {
  nlohmann::json specimens = nlohmann::json::array();
  for (const campaign::SpecimenOutcome& s : r.specimens) {
    nlohmann::json j = {{"name", s.name}, {"record", s.request.input_path},
                        {"ran", s.ran()}, {"ok", s.ok()}, {"wall_s", s.wall_s}, {"rank", s.rank},
                        {"error", s.error}, {"notes", s.notes},
                        {"images", s.dic ? nlohmann::json(s.dic->folder.string())
                                         : nlohmann::json(nullptr)}};
    if (s.ran()) {
      const inverse::FitSummary& f = s.run->summary;
      j["converged"] = f.converged;
      j["bridging_detected"] = f.bridging_detected;
      j["law"] = f.law;
      j["parameters_si"] = {{"sigma_c_Pa", EstimateJson(f.sigma_c)},
                            {"J_B_J_per_m2", EstimateJson(f.J_B)},
                            {"delta_c_m", EstimateJson(f.delta_c)},
                            {"J_tip_c_J_per_m2", EstimateJson(f.J_tip_c)}};
    }
    specimens.push_back(j);
  }
  nlohmann::json statistics = nlohmann::json::array();
  for (const campaign::ParameterStatistics& p : r.statistics)
    statistics.push_back({{"parameter", p.parameter}, {"unit", p.unit}, {"values", p.values},
                          {"bounds", p.bounds}, {"mean", NumberOrNull(p.mean * p.scale)},
                          {"sd", NumberOrNull(p.sd * p.scale)}, {"cv", NumberOrNull(p.cv)},
                          {"median", NumberOrNull(p.median * p.scale)},
                          {"campaign_lower_bound", NumberOrNull(p.campaign_lower_bound * p.scale)},
                          {"bound_from", p.bound_from}, {"outliers", p.outliers},
                          {"note", p.note}});
  nlohmann::json joint;
  if (r.joint) {
    const inverse::FitSummary& f = r.joint->summary;
    const inverse::ConsistencyTest& t = r.joint->consistency;
    joint = {{"specimens", r.joint->specimens},
             {"parameters_si", {{"sigma_c_Pa", EstimateJson(f.sigma_c)},
                                {"J_B_J_per_m2", EstimateJson(f.J_B)},
                                {"delta_c_m", EstimateJson(f.delta_c)},
                                {"J_tip_c_J_per_m2", EstimateJson(f.J_tip_c)}}},
             {"verdict", f.verdict},
             {"model_error", r.joint->model_error.Summary()},
             {"model_error_warning", r.joint->model_error.warning},
             {"likelihood_ratio", NumberOrNull(t.statistic)},
             {"degrees_of_freedom", t.degrees_of_freedom},
             {"p_value", NumberOrNull(t.p_value)},
             {"consistent", t.consistent()},
             {"consistency", t.Summary()},
             {"flagged", r.joint->flagged},
             {"p_value_without_flagged",
              r.joint->summary_without_flagged
                  ? NumberOrNull(r.joint->consistency_without_flagged.p_value)
                  : nlohmann::json()},
             {"wall_s", r.joint->wall_s}};
    // The parameters shared; each specimen's own values of the others (SI);
    // who carries each shared one, by the stated rule.
    nlohmann::json shared = nlohmann::json::array(), own = nlohmann::json::array(),
                   carriers = nlohmann::json::object();
    for (int i = 0; i < inverse::kParameterCount; ++i)
      if (r.joint->shared[i]) shared.push_back(inverse::ParameterName(i));
    for (const pipeline::OwnParameterValue& v : r.joint->own_values)
      own.push_back({{"specimen", v.specimen}, {"parameter", inverse::ParameterName(v.parameter)},
                     {"unit", v.parameter == inverse::kSigmaC ? "Pa" : "J/m^2"},
                     {"value", NumberOrNull(v.value)}, {"ci95_low", NumberOrNull(v.ci95_low)},
                     {"ci95_high", NumberOrNull(v.ci95_high)},
                     {"conditional_ci95_low", NumberOrNull(v.conditional_ci95_low)},
                     {"conditional_ci95_high", NumberOrNull(v.conditional_ci95_high)}});
    for (const pipeline::ParameterCarriers& c : r.joint->carriers)
      carriers[inverse::ParameterName(c.parameter)] = {{"specimens", c.specimens},
                                                       {"reasons", c.reasons}};
    joint["shared"] = shared;
    joint["own_values_si"] = own;
    joint["carriers"] = carriers;
    joint["carrier_rule"] = pipeline::kCarrierRule;
  } else if (!r.joint_error.empty()) {
    joint = {{"error", r.joint_error}};
  }
  return {{"command", "campaign"}, {"manifest", r.manifest.path.string()}, {"joint", joint},
          {"name", r.manifest.name}, {"out", out_dir}, {"jobs", r.jobs}, {"ranks", r.ranks},
          {"wall_s", r.wall_s}, {"failed", r.Failed()}, {"specimens", specimens},
          {"statistics", statistics}};
}

class CampaignCommand final : public Command {
 public:
  const char* name() const override { return "campaign"; }
  const char* description() const override {
    return "Fit many specimens of one material from a manifest: per-specimen fits and the "
           "campaign's statistics (docs/CAMPAIGN.md)";
  }
  void Register(CLI::App& sub) override {
    sub.add_option("manifest", manifest_, "Campaign manifest (TOML, docs/FORMATS.md)")
        ->required();
    sub.add_option("--out", out_,
                   "Output folder: summary.csv, statistics.csv, specimens/NAME.h5, campaign.h5, "
                   "report/index.html")
        ->required();
    sub.add_option("--jobs", jobs_, "Specimens fitted at once (0: the machine's cores)")
        ->default_val(0)
        ->check(CLI::NonNegativeNumber);
    sub.add_flag("--joint", joint_,
                 "Also fit one law to every converged specimen at once, with a likelihood-ratio "
                 "test of whether one law describes them all (joint.csv)");
    sub.add_option("--joint-parameters", joint_parameters_,
                   "The parameters the joint fit shares, e.g. sigma_c,J_B (the others each "
                   "specimen's own); over the manifest's joint key; default all")
        ->delimiter(',');
  }

  int Run(const CommonOptions& common) override {
    const std::unique_ptr<parallel::Communicator> comm = parallel::MakeWorldCommunicator();
    campaign::CampaignOptions options;
    options.jobs = jobs_;
    options.joint = joint_;
    if (!joint_parameters_.empty()) {
      try {
        options.joint_parameters = inverse::ParseSharedParameters(joint_parameters_);
      } catch (const Error& e) {
        throw Error(ErrorKind::kUsage, e.message(),
                    {.field = "--joint-parameters", .value = e.context().value,
                     .expected = e.context().expected});
      }
    }
    const std::string prefix = comm->size() > 1 ? fmt::format("rank {}: ", comm->rank()) : "";
    if (!common.quiet)
      // One write per line: the ranks' lines are not cut into each other.
      options.progress = [prefix](const std::string& line) { std::cerr << prefix + line + "\n"; };
    const campaign::RankedCampaign ranked =
        campaign::RunCampaignOnRanks(manifest_, options, *comm);
    if (ranked.quiet_exit) return *ranked.quiet_exit;
    const campaign::CampaignResult& result = *ranked.result;
    if (!result.complete) return 0;  // rank 0 writes and reports
    campaign::WriteCampaignOutputs(result, out_);
    if (common.json) {
      PrintJson(ResultJson(result, out_));
    } else {
      std::cout << result.BriefReport() << "  written: " << out_ << "/summary.csv, "
                << out_ << "/statistics.csv, " << out_ << "/specimens/, " << out_
                << "/campaign.h5, " << out_ << "/report/index.html\n";
    }
    for (const campaign::SpecimenOutcome& s : result.specimens)
      if (!s.ok())
        std::cerr << "warning: specimen '" << s.name << "' "
                  << (s.ran() ? "did not converge" : "failed: " + s.error) << "\n";
    return result.Failed() == 0 ? 0 : 1;
  }

 private:
  std::string manifest_, out_;
  int jobs_ = 0;
  bool joint_ = false;
  std::vector<std::string> joint_parameters_;
};

}  // namespace

std::unique_ptr<Command> MakeCampaignCommand() { return std::make_unique<CampaignCommand>(); }

}  // namespace bridgefit::cli
