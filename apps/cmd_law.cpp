// `bridgefit law`: evaluates a bridging law and its R curve (PHYSICS 2-3).
// Flags (or a scene) -> pipeline::LawRequest -> pipeline::RunLaw -> printing.
//   bridgefit law --law linear --sigma-c "0.45 MPa" --jb "500 J/m^2" --jtip "2210 J/m^2"
//   bridgefit law --law cubic --sigma-c 1MPa --delta-c 2mm --jtip 2210J/m^2 --json

#include <cmath>
#include <iostream>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/pipeline/law.hpp"
#include "command.hpp"
#include "json_output.hpp"

namespace bridgefit::cli {
namespace {

class LawCommand final : public Command {
 public:
  const char* name() const override { return "law"; }
  const char* description() const override {
    return "Evaluate a bridging law sigma(delta) and its elastic-zone R curve";
  }
  void Register(CLI::App& sub) override {
    sub.add_option("--law", law_, "linear|cubic|triangular|trilinear|exponential|table")
        ->default_val("linear");
    sub.add_option("--sigma-c", sigma_c_, "Peak bridging stress, e.g. '0.45 MPa'");
    sub.add_option("--jb", J_B_, "Bridging toughness J_B, e.g. '500 J/m^2'");
    sub.add_option("--delta-c", delta_c_, "Critical opening, e.g. '2.57 mm'");
    sub.add_option("--jtip", J_tip_c_, "Crack-tip toughness J_tip,c, e.g. '2210 J/m^2'");
    sub.add_option("--scene", scene_,
                   "Take the law and J_tip,c from a scene file ([bridging], [fracture])")
        ->check(CLI::ExistingFile);
    sub.add_option("--peak-ratio", peak_ratio_,
                   "triangular: opening at the peak as a fraction of delta_c (u_e/delta_c)")
        ->default_val(laws::kDefaultPeakRatio);
    sub.add_option("--alpha", alpha_, "exponential: decay constant, s = exp(-alpha d)")
        ->default_val(laws::kDefaultExponentialAlpha);
    sub.add_option("--trilinear", trilinear_,
                   "trilinear: 's0,d1,s1,d2,s2' (fractions of sigma_c and delta_c)");
    sub.add_option("--table", table_,
                   "table: CSV with header 'delta [mm], sigma [MPa]' (any units)");
    sub.add_option("--points", points_, "Number of openings from 0 to delta_c inclusive")
        ->default_val(101)
        ->check(CLI::Range(2, 1000000));
    sub.add_option("--csv", csv_, "Also write the points to this CSV file");
  }

  int Run(const CommonOptions& common) override {
    laws::LawShape shape;
    laws::LawScales scales;
    double J_tip_c = ParseOptionQuantity(J_tip_c_, Dimension::EnergyPerArea(), "--jtip");
    if (!scene_.empty()) {
      const Scene scene = io::ReadSceneFile(scene_);
      if (!scene.bridging)
        throw Error(ErrorKind::kInput, "the scene has no bridging law",
                    {.file = scene_, .field = "bridging", .expected = "a [bridging] table"});
      shape = scene.bridging->shape;
      scales = scene.bridging->scales;
      if (!std::isfinite(J_tip_c)) {
        if (!scene.fracture)
          throw Error(ErrorKind::kInput, "the scene has no crack-tip toughness",
                      {.file = scene_, .field = "fracture.J_tip_c",
                       .expected = "a [fracture] table, or --jtip"});
        J_tip_c = scene.fracture->J_tip_c;
      }
    } else {
      LawFromOptions(shape, scales);
    }
    if (!(J_tip_c > 0.0))
      throw Error(ErrorKind::kUsage, "J_tip,c must be given and positive",
                  {.field = "--jtip", .value = J_tip_c_,
                   .expected = "a value > 0 such as '2210 J/m^2' (or --scene)"});
    pipeline::LawRequest request;
    request.shape = shape;
    request.scales = scales;
    request.J_tip_c = J_tip_c;
    request.points = points_;
    const pipeline::LawRun run = pipeline::RunLaw(request);
    if (!csv_.empty()) pipeline::WriteLawCsv(csv_, run);
    if (common.json) {
      PrintJson(LawRunJson(run));
    } else {
      std::cout << run.BriefReport();
    }
    return 0;
  }

 private:
  // Builds the law from --law, --sigma-c, --jb, --delta-c and shape options.
  void LawFromOptions(laws::LawShape& shape, laws::LawScales& scales) const {
    laws::LawFamily family;
    try {
      family = laws::ParseLawFamily(law_);
    } catch (const Error& e) {
      throw Error(ErrorKind::kUsage, e.message(), ErrorContext{.field = "--law", .value = law_, .expected = e.context().expected});
    }
    laws::LawScales given{ParseOptionQuantity(sigma_c_, Dimension::Stress(), "--sigma-c"),
                          ParseOptionQuantity(delta_c_, Dimension::Length(), "--delta-c"),
                          ParseOptionQuantity(J_B_, Dimension::EnergyPerArea(), "--jb")};
    laws::ShapeSpec spec{.family = family, .peak_ratio = peak_ratio_, .alpha = alpha_};
    try {
      if (family == laws::LawFamily::kTrilinear) {
        if (trilinear_.empty())
          throw Error(ErrorKind::kUsage, "the trilinear law needs its break points",
                      {.field = "--trilinear", .expected = "'s0,d1,s1,d2,s2'"});
        spec.trilinear = ParseOptionNumbers(trilinear_, "--trilinear", 5);
      }
      if (family == laws::LawFamily::kTable) {
        if (table_.empty())
          throw Error(ErrorKind::kUsage, "the table law needs --table FILE",
                      {.field = "--table", .expected = "a CSV with columns delta and sigma"});
        const io::CsvTable table = io::ReadCsvTable(table_);
        spec.table_delta = table.ColumnSi("delta", Dimension::Length());
        spec.table_sigma = table.ColumnSi("sigma", Dimension::Stress());
      }
      shape = laws::MakeShape(spec, &given);
    } catch (const Error& e) {
      // Shape parameters come from options (usage); a table file's content is data.
      if (e.kind() != ErrorKind::kInput || family == laws::LawFamily::kTable) throw;
      throw Error(ErrorKind::kUsage, e.message(), e.context());
    }
    try {
      scales = laws::CompleteScales(shape, given);
    } catch (const Error& e) {  // the scales come from options: a usage error
      throw Error(ErrorKind::kUsage, e.message(), e.context());
    }
  }

  std::string scene_;
  std::string law_, sigma_c_, J_B_, delta_c_, J_tip_c_, trilinear_, table_, csv_;
  double peak_ratio_ = laws::kDefaultPeakRatio;
  double alpha_ = laws::kDefaultExponentialAlpha;
  int points_ = 101;
};

}  // namespace

std::unique_ptr<Command> MakeLawCommand() { return std::make_unique<LawCommand>(); }

}  // namespace bridgefit::cli
