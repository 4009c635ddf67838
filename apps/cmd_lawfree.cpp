// `bridgefit lawfree`: the bridging law without assuming its shape (issue 21,
// PHYSICS 10). Flags -> pipeline::LawFreeRequest -> pipeline::RunLawFree ->
// printing and /lawfree.
//   bridgefit dic images/ --scale 0.15mm/px --offset 20mm --scene S --j-integral --out dic.h5
//   bridgefit lawfree dic.h5 --out lawfree.h5
//   bridgefit lawfree dic.h5 --rcurve rcurve.h5 --jtip "2210 J/m^2" --json

#include <iostream>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/pipeline/law_free.hpp"
#include "command.hpp"
#include "json_output.hpp"

namespace bridgefit::cli {
namespace {

class LawFreeCommand final : public Command {
 public:
  const char* name() const override { return "lawfree"; }
  const char* description() const override {
    return "Bridging law sigma(delta) without a law family, from J_ff(delta*) and/or R(delta_root)";
  }
  void Register(CLI::App& sub) override {
    sub.add_option("dic", dic_,
                   "dic.h5 of `bridgefit dic` or `crack` with --scene S --j-integral")
        ->required();
    sub.add_option("--rcurve", rcurve_,
                   "R curve (rcurve.h5 or CSV, R per crack length): also the R(delta_root) route");
    sub.add_flag("--no-j-route", no_j_route_, "Only the R(delta_root) route");
    sub.add_option("--jtip", jtip_, "R route: J_tip,c given, e.g. '2210 J/m^2' (default: fitted)");
    sub.add_option(
        "--onset", onset_,
        "J route: delta* at the onset of growth, e.g. '0.01 mm' (default: the last frame with "
        "delta* = 0, else detected from J_ff's shape with a warning)");
    sub.add_option("--j-source", j_source_,
                   "J route: J_ff per frame from the field-wide fit ('fit', the domains' where "
                   "the fit failed) or the domain integral ('domains')")
        ->check(CLI::IsMember({"fit", "domains"}))
        ->default_val("fit");
    sub.add_option("--grid-points", grid_points_, "sigma nodes from 0 to the largest opening")
        ->default_val(41);
    sub.add_option("--out", out_, "Write /lawfree to this HDF5 file");
  }

  int Run(const CommonOptions& common) override {
    pipeline::LawFreeRequest request;
    request.dic_file = dic_;
    request.rcurve_file = rcurve_;
    request.far_field_route = !no_j_route_;
    if (!jtip_.empty())
      request.J_tip_c = ParseOptionQuantity(jtip_, Dimension::EnergyPerArea(), "--jtip");
    if (!onset_.empty())
      request.onset_opening = ParseOptionQuantity(onset_, Dimension::Length(), "--onset");
    request.options.grid_points = grid_points_;
    request.j_source = j_source_ == "domains" ? pipeline::LawFreeRequest::JSource::kDomains
                                              : pipeline::LawFreeRequest::JSource::kFieldFit;
    std::string why;
    if (!request.IsValid(&why)) throw Error(ErrorKind::kUsage, why);
    const pipeline::LawFreeRun run = pipeline::RunLawFree(request);
    if (!out_.empty()) pipeline::WriteLawFreeH5(out_, run);
    if (common.json) {
      nlohmann::json j = LawFreeRunJson(run);
      j["out"] = out_;
      PrintJson(j);
    } else {
      std::cout << run.BriefReport();
      if (!out_.empty()) std::cout << "wrote " << out_ << " (/lawfree)\n";
    }
    return 0;
  }

 private:
  std::string dic_, rcurve_, jtip_, onset_, out_, j_source_ = "fit";
  int grid_points_ = 41;
  bool no_j_route_ = false;
};

}  // namespace

std::unique_ptr<Command> MakeLawFreeCommand() { return std::make_unique<LawFreeCommand>(); }

}  // namespace bridgefit::cli
