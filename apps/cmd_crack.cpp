// `bridgefit crack`: crack length from displacement fields exported by other
// DIC software (plain CSV, GOM Aramis nodemap, DICe solution, DaVis vector
// text; one frame per file; Ncorr MAT files with all their frames), with the same path search, tip methods and
// per-frame output as `bridgefit dic`.
//   bridgefit crack nodemaps/ --crack-line 0,0,60,0 --offset 20mm --json
//   bridgefit crack "DICe_solution_*.txt" --scale 0.02mm/px --out crack.h5

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/dic/sequence.hpp"
#include "command.hpp"
#include "bridgefit/pipeline/crack_fields.hpp"
#include "bridgefit/pipeline/dic_file.hpp"
#include "dic_output.hpp"
#include "j_integral_flags.hpp"

namespace bridgefit::cli {
namespace {

class CrackCommand final : public Command {
 public:
  const char* name() const override { return "crack"; }
  const char* description() const override {
    return "Crack length from exported DIC displacement fields (CSV, Aramis, DICe, DaVis, Ncorr MAT)";
  }
  void Register(CLI::App& sub) override {
    sub.add_option("fields", files_,
                   "Field files: a folder (.txt/.csv/.dat/.mat), a glob or files; one frame per "
                   "text file, every frame of an Ncorr .mat; natural order")
        ->required();
    sub.add_option("--crack-line", crack_line_,
                   "Expected crack x0,y0,x1,y1 in the fields' coordinates (a hint for the path "
                   "found from the data)");
    sub.add_flag("--fixed-line", fixed_line_, "Take --crack-line as the crack (no path search)");
    sub.add_flag("--own-paths", own_paths_,
                 "Each frame's length along its own path (default: frames without a path of their "
                 "own, or whose unresolved path contradicts it, take the sequence's most precise path)");
    sub.add_option("--scale", scale_, "For fields in px: e.g. '0.05mm/px'");
    sub.add_option("--band", band_,
                   "Half width around the crack whose points are ignored, in the fields' unit "
                   "(default 1.5 point spacings; use half the subset size for DIC exports)");
    sub.add_option("--tip-method", tip_method_, "williams|jump|sqrt (preferred method)")
        ->default_val("williams");
    sub.add_option("--threshold", threshold_,
                   "Physical floor of the jump threshold, a length such as '0.001mm' (or px)")
        ->default_val("0.001mm");
    sub.add_option("--offset", offset_, "Added to the crack length, e.g. '12.5mm'")->default_val("0mm");
    sub.add_option("--fit-radius", fit_radius_, "Williams fit radius in the fields' unit");
    sub.add_option("--out", out_, "Write results to this HDF5 file");
    sub.add_option("--csv", csv_, "Write one row per frame to this CSV file");
    j_integral_.Add(&sub);
  }

  int Run(const CommonOptions& common) override {
    dic::CrackSequenceOptions opt;
    if (!scale_.empty()) {
      opt.scale_m_per_px = ParseQuantity(scale_, Dimension::LengthPerPixel());
      BF_CHECK_INPUT(opt.scale_m_per_px > 0, "scale must be positive",
                     {.field = "--scale", .value = scale_, .expected = "e.g. '0.05mm/px'"});
    }
    opt.offset_m = ParseQuantity(offset_, Dimension::Length());
    opt.has_line = !crack_line_.empty();
    opt.find_path = !fixed_line_;
    opt.sequence_path = !own_paths_;
    if (fixed_line_ && !opt.has_line)
      throw Error(ErrorKind::kUsage, "--fixed-line needs --crack-line", {.field = "--fixed-line"});
    if (opt.has_line) {
      const auto line = ParseOptionNumbers(crack_line_, "--crack-line", 4);
      opt.tip.line = {line[0], line[1], line[2], line[3]};
      if (!(opt.tip.line.Length() > 0))
        throw Error(ErrorKind::kUsage, "crack line end points coincide",
                    {.field = "--crack-line", .value = crack_line_});
    }
    opt.method = dic::ParseTipMethod(tip_method_);
    opt.show_progress = !common.quiet;
    opt.j_integral = j_integral_.Options();
    j_integral_.ApplyMaterial(&opt);
    pipeline::CrackFieldsRequest request{
        .fields = files_,
        .options = opt,
        .settings = {.band = band_, .fit_radius = fit_radius_, .threshold = threshold_}};
    const pipeline::CrackFieldsRun run = pipeline::RunCrackFields(request);
    if (!csv_.empty()) pipeline::WriteDicCsv(csv_, run.result);
    if (!out_.empty()) pipeline::WriteDicH5(out_, run.result, run.used);
    PrintDicResult(run.result, run.used, common.json, run.result.length_unit);
    return 0;
  }

 private:
  std::vector<std::string> files_;
  std::string crack_line_, scale_, tip_method_, threshold_, offset_, out_, csv_;
  double band_ = 0, fit_radius_ = 0;
  bool fixed_line_ = false, own_paths_ = false;
  JIntegralFlags j_integral_;  // --scene, --j-integral
};

}  // namespace

std::unique_ptr<Command> MakeCrackCommand() { return std::make_unique<CrackCommand>(); }

}  // namespace bridgefit::cli
