// `bridgefit crack`: crack length from displacement fields exported by other
// DIC software (plain CSV, GOM Aramis nodemap, DICe solution, DaVis vector
// text; one frame per file; Ncorr MAT files with all their frames), with the same path search, tip methods and
// per-frame output as `bridgefit dic`.
//   bridgefit crack nodemaps/ --crack-line 0,0,60,0 --offset 20mm --json
//   bridgefit crack "DICe_solution_*.txt" --scale 0.02mm/px --out crack.h5

#include <cmath>
#include <filesystem>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/dic/fields.hpp"
#include "bridgefit/dic/sequence.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "command.hpp"
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
    const auto files = dic::ExpandFieldArguments(files_);
    // Ncorr v7.3 files are HDF5: each is read in a child first, with matio
    // as NcorrFile reads it (its attribute reads take libhdf5 paths the
    // generic walk does not), including files a folder or glob names
    // (fuzz_ncorr: libhdf5 crashes in H5HG_read on corrupt ones).
    // MAT v5 files too: a 584-byte header made matio allocate 2.6 GB and
    // run for minutes. The child gets 10 s plus 1 s per 10 MB of file.
    for (const auto& file : files)
      if (dic::IsMatFile(file)) {
        std::error_code ec;
        const double mb = static_cast<double>(std::filesystem::file_size(file, ec)) / 1e6;
        io::CheckH5FileInChildProcess(file, 10.0 + (ec ? 0.0 : mb / 10.0),
                                      [&file] { dic::ReadEveryNcorrFrame(file); });
      }
    // The unit of the fields decides how the threshold and radius read.
    dic::FieldFile first;
    std::string first_name;
    dic::FieldFrames(files).Next(&first, &first_name);
    const double m_per_unit = first.IsPixels() ? opt.scale_m_per_px : first.m_per_unit;
    if (!(m_per_unit > 0))
      throw Error(ErrorKind::kUsage, "the fields are in px: a scale is needed",
                  {.file = first_name, .field = "--scale", .expected = "e.g. '0.05mm/px'"});
    const double spacing = dic::PointSpacing(first.field);
    BF_CHECK_INPUT(spacing > 0, "cannot tell the point spacing", {.file = first_name});
    dic::SetFieldDefaults(spacing, band_ > 0 ? band_ : 1.5 * spacing, &opt);
    if (fit_radius_ > 0) opt.tip.fit_radius_px = opt.tip.sqrt_window_px = fit_radius_;
    try {
      opt.tip.threshold_floor_px = ParseQuantity(threshold_, Dimension::Length()) / m_per_unit;
    } catch (const Error&) {
      if (!first.IsPixels()) throw;
      opt.tip.threshold_floor_px = ParseQuantity(threshold_, Dimension::Pixel());
    }
    opt.path.min_jump_px = opt.tip.threshold_floor_px;
    opt.j_integral = j_integral_.Options();
    const dic::CrackSequenceResult result =
        dic::AnalyzeCrackFields(files, opt, /*auto_defaults=*/false);
    dic::CrackSequenceOptions used = opt;
    used.scale_m_per_px = m_per_unit;
    if (!csv_.empty()) pipeline::WriteDicCsv(csv_, result);
    if (!out_.empty()) pipeline::WriteDicH5(out_, result, used);
    PrintDicResult(result, used, common.json, first.unit);
    return 0;
  }

 private:
  std::vector<std::string> files_;
  std::string crack_line_, scale_, tip_method_, threshold_, offset_, out_, csv_;
  double band_ = 0, fit_radius_ = 0;
  bool fixed_line_ = false;
  JIntegralFlags j_integral_;  // --scene, --j-integral
};

}  // namespace

std::unique_ptr<Command> MakeCrackCommand() { return std::make_unique<CrackCommand>(); }

}  // namespace bridgefit::cli
