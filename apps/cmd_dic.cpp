// `bridgefit dic`: crack length from a DIC image sequence (PHYSICS 9).
//   bridgefit dic frames/ --crack-line 235,580,780,580 --scale 0.05mm/px
//   bridgefit dic "img_*.png" --crack-line 20,100,300,100 --scale 0.05mm/px --subset 31
//       --step 5 --tip-method williams --threshold 0.02px --offset 10mm --out crack.h5 --json

#include <cmath>
#include <iostream>
#include <sstream>

#include <fmt/format.h>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/dic/image.hpp"
#include "bridgefit/dic/sequence.hpp"
#include "bridgefit/dic/settings.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "command.hpp"
#include "bridgefit/pipeline/dic_file.hpp"
#include "dic_output.hpp"
#include "j_integral_flags.hpp"

namespace bridgefit::cli {
namespace {


// "0.02px" -> px; a length ("0.001 mm") is converted with the scale.
double ParsePixelsOrLength(const std::string& text, double m_per_px, const char* option) {
  try {
    return ParseQuantity(text, Dimension::Pixel());
  } catch (const Error&) {
  }
  try {
    return ParseQuantity(text, Dimension::Length()) / m_per_px;
  } catch (const Error& e) {
    throw Error(ErrorKind::kUsage, "expected pixels or a length",
                {.field = option, .value = text, .expected = "e.g. '0.02px' or '0.001mm'"});
  }
}

class DicCommand final : public Command {
 public:
  const char* name() const override { return "dic"; }
  const char* description() const override {
    return "Crack length from a DIC image sequence (subset correlation + crack-tip tracking)";
  }
  void Register(CLI::App& sub) override {
    sub.add_option("images", images_,
                   "Images: a folder, a glob or files (natural order; the first is the reference)")
        ->required();
    sub.add_option("--crack-line", crack_line_,
                   "Expected crack x0,y0,x1,y1 in reference pixels, from the notch into the "
                   "material: a hint (start point and direction) for the path found from the data; "
                   "without it the path is searched along x and y and lengths run from the field "
                   "edge on the notch side");
    sub.add_flag("--fixed-line", fixed_line_,
                 "Take --crack-line as the crack itself (no path search; crack band on the line)");
    sub.add_flag("--own-paths", own_paths_,
                 "Each frame's length along its own path (default: frames without a path of their "
                 "own, or whose unresolved path contradicts it, take the sequence's most precise path)");
    sub.add_option("--path-search", path_search_,
                   "Path search half width across the given line, px")
        ->default_val(40);
    sub.add_option("--scale", scale_, "Image scale, e.g. '0.05mm/px'")->required();
    sub.add_option("--subset", subset_, "Subset size in px (odd)")->default_val(31);
    sub.add_option("--step", step_, "Grid step in px")->default_val(5);
    sub.add_option("--tip-method", tip_method_, "williams|jump|sqrt (preferred method)")
        ->default_val("williams");
    sub.add_option("--threshold", threshold_,
                   "Physical floor of the jump threshold, e.g. '0.02px' or '0.001mm'")
        ->default_val("0.02px");
    sub.add_option("--offset", offset_, "Added to the crack length, e.g. '12.5mm'")
        ->default_val("0mm");
    sub.add_option("--fit-radius", fit_radius_, "Williams fit radius in px (default 5 subsets)");
    sub.add_option("--roi", roi_, "Region of interest x0,y0,x1,y1 in px");
    sub.add_option("--shape", shape_, "Subset shape function: first|second")->default_val("first");
    sub.add_option("--interpolation", interpolation_, "bspline|keys")->default_val("bspline");
    sub.add_option("--min-zncc", min_zncc_, "Minimum ZNCC of a valid point")->default_val(0.8);
    sub.add_option("--search", search_, "Seed search radius in px")->default_val(40);
    sub.add_option("--threads", threads_, "OpenMP threads (0 = all)")->default_val(0);
    sub.add_flag("--full-field", full_field_,
                 "Correlate every grid point (default: only the crack band, which follows the tip)");
    sub.add_flag("--no-incremental", no_incremental_,
                 "Never update the reference image along the sequence");
    sub.add_option("--out", out_, "Write results to this HDF5 file");
    sub.add_flag("--fields", fields_, "With --out: also store every displacement field");
    sub.add_option("--csv", csv_, "Write one row per frame to this CSV file");
    j_integral_.Add(&sub);
  }

  int Run(const CommonOptions& common) override {
    // A scale given the other way round (px/mm) is the usual slip: say which
    // option and the inverse value that was probably meant.
    double m_per_px = NAN;
    try {
      m_per_px = ParseQuantity(scale_, Dimension::LengthPerPixel());
    } catch (const Error& e) {
      std::string hint = "a length per pixel, e.g. '0.05mm/px'";
      const std::size_t slash = scale_.find('/');
      if (slash != std::string::npos) {
        const std::string left = scale_.substr(0, slash), right = scale_.substr(slash + 1);
        try {
          // "6.667px/mm": px over a length; 1 / (6.667 px/mm) = 0.15 mm/px.
          const double px = ParseQuantity(left, Dimension::Pixel());
          const double per = ParseQuantity("1" + right, Dimension::Length());
          if (px > 0 && per > 0)
            hint = fmt::format("a length per pixel; '{}' reads as pixels per length: did you mean "
                               "'--scale {:.6g}mm/px'?",
                               scale_, per / px * 1e3);
        } catch (const Error&) {
        }
      }
      throw Error(ErrorKind::kUsage, "the image scale is not a length per pixel (" + e.message() + ")",
                  {.field = "--scale", .value = scale_, .expected = hint});
    }
    BF_CHECK_INPUT(m_per_px > 0, "scale must be positive",
                   {.field = "--scale", .value = scale_, .expected = "e.g. '0.05mm/px'"});
    dic::DicSettings settings;
    settings.scale_m_per_px = m_per_px;
    settings.offset_m = ParseQuantity(offset_, Dimension::Length());
    settings.fixed_line = fixed_line_;
    settings.own_paths = own_paths_;
    if (fixed_line_ && crack_line_.empty())
      throw Error(ErrorKind::kUsage, "--fixed-line needs --crack-line",
                  {.field = "--fixed-line", .expected = "--crack-line x0,y0,x1,y1"});
    if (!crack_line_.empty()) {
      const auto line = ParseOptionNumbers(crack_line_, "--crack-line", 4);
      settings.crack_line = dic::CrackLine{line[0], line[1], line[2], line[3]};
      if (!(settings.crack_line->Length() > 1))
        throw Error(ErrorKind::kUsage, "crack line end points coincide",
                    {.field = "--crack-line", .value = crack_line_});
    }
    settings.subset_px = subset_;
    settings.step_px = step_;
    settings.tip_method = tip_method_;
    settings.threshold_px = ParsePixelsOrLength(threshold_, m_per_px, "--threshold");
    settings.fit_radius_px = fit_radius_;
    settings.path_search_px = path_search_;
    settings.min_zncc = min_zncc_;
    settings.seed_search_px = search_;
    settings.threads = threads_;
    settings.show_progress = !common.quiet;
    dic::CrackSequenceOptions opt = dic::MakeSequenceOptions(settings);
    auto& c = opt.correlation;
    c.incremental = !no_incremental_;
    opt.full_field = full_field_;
    if (shape_ == "second") c.shape = dic::ShapeFunction::kSecondOrder;
    else if (shape_ != "first")
      throw Error(ErrorKind::kUsage, "unknown shape function",
                  {.field = "--shape", .value = shape_, .expected = "first or second"});
    if (interpolation_ == "keys") c.interpolation = dic::Interpolation::kBicubicKeys;
    else if (interpolation_ != "bspline")
      throw Error(ErrorKind::kUsage, "unknown interpolation",
                  {.field = "--interpolation", .value = interpolation_, .expected = "bspline or keys"});
    if (!roi_.empty()) {
      const auto r = ParseOptionNumbers(roi_, "--roi", 4);
      c.roi_x0 = static_cast<int>(r[0]);
      c.roi_y0 = static_cast<int>(r[1]);
      c.roi_x1 = static_cast<int>(r[2]);
      c.roi_y1 = static_cast<int>(r[3]);
    }
    opt.keep_fields = fields_ && !out_.empty();
    opt.j_integral = j_integral_.Options();
    j_integral_.ApplyMaterial(&opt);
    std::string why;
    if (!opt.IsValid(&why)) throw Error(ErrorKind::kUsage, why);

    const auto paths = dic::ExpandImageArguments(images_);
    if (paths.size() < 2)
      throw Error(ErrorKind::kInput, "need at least two images (a reference and a deformed one)",
                  {.file = paths.front().string()});
    const dic::CrackSequenceResult result = dic::AnalyzeCrackSequence(paths, opt);

    if (!csv_.empty()) pipeline::WriteDicCsv(csv_, result);
    if (!out_.empty()) pipeline::WriteDicH5(out_, result, opt);
    PrintDicResult(result, opt, common.json);
    return 0;
  }

 private:
  std::vector<std::string> images_;
  std::string crack_line_, scale_, tip_method_, threshold_, offset_, roi_, shape_, interpolation_,
      out_, csv_;
  int subset_ = 31, step_ = 5, search_ = 40, threads_ = 0;
  double min_zncc_ = 0.8, fit_radius_ = 0;
  double path_search_ = 40;
  bool full_field_ = false;
  bool no_incremental_ = false, fields_ = false, fixed_line_ = false, own_paths_ = false;
  JIntegralFlags j_integral_;  // --scene, --j-integral
};

}  // namespace

std::unique_ptr<Command> MakeDicCommand() { return std::make_unique<DicCommand>(); }

}  // namespace bridgefit::cli
