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
#include "bridgefit/io/hdf5.hpp"
#include "command.hpp"

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

nlohmann::json PathJson(const dic::FrameResult& f) {
  const dic::CrackLine& L = f.line_used;
  nlohmann::json j = {{"found", f.path.found},
                      {"line_px", {L.x0, L.y0, L.x1, L.y1}}};
  if (f.path.found) {
    j["angle_deg"] = f.path.angle_deg;
    j["points"] = f.path.inliers;
    j["rms_residual_px"] = f.path.rms_residual_px;
    j["cracked_length_px"] = f.path.cracked_length_px;
    j["line_max_offset_px"] = f.path.hint_max_offset_px;
    j["line_angle_deg"] = f.path.hint_angle_deg;
    j["disagrees_with_line"] = f.path.disagrees_with_hint;
  } else if (!f.path.why_not_found.empty()) {
    j["why_not_found"] = f.path.why_not_found;
  }
  return j;
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
    sub.add_flag("--no-incremental", no_incremental_,
                 "Never update the reference image along the sequence");
    sub.add_option("--out", out_, "Write results to this HDF5 file");
    sub.add_flag("--fields", fields_, "With --out: also store every displacement field");
    sub.add_option("--csv", csv_, "Write one row per frame to this CSV file");
  }

  int Run(const CommonOptions& common) override {
    dic::CrackSequenceOptions opt;
    const double m_per_px = ParseQuantity(scale_, Dimension::LengthPerPixel());
    BF_CHECK_INPUT(m_per_px > 0, "scale must be positive",
                   {.field = "--scale", .value = scale_, .expected = "e.g. '0.05mm/px'"});
    opt.scale_m_per_px = m_per_px;
    opt.offset_m = ParseQuantity(offset_, Dimension::Length());
    opt.has_line = !crack_line_.empty();
    opt.find_path = !fixed_line_;
    if (fixed_line_ && !opt.has_line)
      throw Error(ErrorKind::kUsage, "--fixed-line needs --crack-line",
                  {.field = "--fixed-line", .expected = "--crack-line x0,y0,x1,y1"});
    if (opt.has_line) {
      const auto line = ParseOptionNumbers(crack_line_, "--crack-line", 4);
      opt.tip.line = {line[0], line[1], line[2], line[3]};
      if (!(opt.tip.line.Length() > 1))
        throw Error(ErrorKind::kUsage, "crack line end points coincide",
                    {.field = "--crack-line", .value = crack_line_});
    }
    auto& c = opt.correlation;
    c.min_zncc = min_zncc_;
    c.seed_search_radius = search_;
    c.threads = threads_;
    c.incremental = !no_incremental_;
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
    opt.method = dic::ParseTipMethod(tip_method_);
    dic::SetGridDefaults(subset_, step_, &opt);
    opt.tip.threshold_floor_px = ParsePixelsOrLength(threshold_, m_per_px, "--threshold");
    if (fit_radius_ > 0) opt.tip.fit_radius_px = opt.tip.sqrt_window_px = fit_radius_;
    opt.path.min_jump_px = opt.tip.threshold_floor_px;
    opt.path.search_half_width_px = path_search_;
    opt.keep_fields = fields_ && !out_.empty();
    opt.show_progress = !common.quiet;
    std::string why;
    if (!opt.IsValid(&why)) throw Error(ErrorKind::kUsage, why);

    const auto paths = dic::ExpandImageArguments(images_);
    if (paths.size() < 2)
      throw Error(ErrorKind::kInput, "need at least two images (a reference and a deformed one)",
                  {.file = paths.front().string()});
    const dic::CrackSequenceResult result = dic::AnalyzeCrackSequence(paths, opt);

    if (!csv_.empty()) WriteCsv(result, m_per_px);
    if (!out_.empty()) WriteH5(result, opt);
    if (common.json) {
      nlohmann::json out;
      nlohmann::json frames = nlohmann::json::array();
      for (const auto& f : result.frames) {
        const bool t = f.has_length;
        frames.push_back({
            {"image", f.image},
            {"crack_length_m", t ? nlohmann::json(f.crack_length_m) : nlohmann::json()},
            {"crack_length_raw_m", t ? nlohmann::json(f.crack_length_raw_m) : nlohmann::json()},
            {"crack_length_uncertainty_m", t ? nlohmann::json(f.uncertainty_m) : nlohmann::json()},
            {"crack_length_px", t ? NumberOrNull(f.tip.tip.s_px) : nlohmann::json()},
            {"tip_x_px", t ? NumberOrNull(f.tip.tip.x_px) : nlohmann::json()},
            {"tip_y_px", t ? NumberOrNull(f.tip.tip.y_px) : nlohmann::json()},
            {"tip_method", t ? nlohmann::json(dic::TipMethodName(f.tip.method)) : nlohmann::json()},
            {"tip_williams_px", f.tip.williams.found ? NumberOrNull(f.tip.williams.s_px) : nlohmann::json()},
            {"tip_jump_px", f.tip.jump.found ? NumberOrNull(f.tip.jump.s_px) : nlohmann::json()},
            {"tip_sqrt_px", f.tip.sqrt_cod.found ? NumberOrNull(f.tip.sqrt_cod.s_px) : nlohmann::json()},
            {"methods_disagree", f.tip.methods_disagree},
            {"tip_at_edge", f.tip.tip_at_edge},
            {"flagged", f.flagged},
            {"flags", f.Flags()},
            {"path", PathJson(f)},
            {"k_over_2mu_sqrt_m", f.tip.williams.found
                                      ? NumberOrNull(f.tip.k_over_2mu_sqrt_px * std::sqrt(m_per_px))
                                      : nlohmann::json()},
            {"williams_residual_px", f.tip.williams.found ? NumberOrNull(f.tip.williams_residual_px)
                                                          : nlohmann::json()},
            {"jump_threshold_px", f.tip.threshold_px},
            {"valid_fraction", f.valid_fraction},
            {"mean_zncc", f.correlation.mean_zncc},
            {"reference_frame", f.correlation.reference_frame},
        });
      }
      out["frames"] = std::move(frames);
      out["points_per_frame"] = result.points;
      out["wall_s"] = result.wall_s;
      out["points_per_s"] = result.points_per_s;
      out["scale_m_per_px"] = m_per_px;
      out["offset_m"] = opt.offset_m;
      PrintJson(out);
    } else {
      std::cout << result.BriefReport() << "\n";
      std::cout << fmt::format("{:>5} {:>14} {:>10} {:>10} {:>9} {:>9} {:>9} {:>6}  {}\n", "frame",
                               "a [mm]", "+- [mm]", "a [px]", "tip_x", "tip_y", "method", "valid",
                               "image");
      for (size_t k = 0; k < result.frames.size(); ++k) {
        const auto& f = result.frames[k];
        if (f.has_length)
          std::cout << fmt::format("{:5} {:14.4f} {:10.4f} {:10.2f} {:9.2f} {:9.2f} {:>9} {:6.3f}{} {}\n",
                                   k, f.crack_length_m * 1e3, f.uncertainty_m * 1e3, f.tip.tip.s_px,
                                   f.tip.tip.x_px, f.tip.tip.y_px, dic::TipMethodName(f.tip.method),
                                   f.valid_fraction, f.flagged ? "*" : " ",
                                   f.image + (f.flagged ? "  [" + f.Flags() + "]" : ""));
        else
          std::cout << fmt::format("{:5} {:>14} {:>10} {:>10} {:>9} {:>9} {:>9} {:6.3f}  {}\n", k,
                                   "none", "", "", "", "", "", f.valid_fraction, f.image);
      }
      std::cout << "(* = flagged: the length may be wrong by more than its uncertainty)\n";
    }
    return 0;
  }

 private:
  void WriteCsv(const dic::CrackSequenceResult& r, double m_per_px) const {
    std::string text =
        "frame, image, crack_length [mm], crack_length_raw [mm], uncertainty [mm], crack_length "
        "[px], tip_x [px], tip_y [px], tip_method, tip_williams [px], tip_jump [px], tip_sqrt [px], "
        "methods_disagree, valid_fraction, mean_zncc, reference_frame, flags\n";
    auto num = [](bool ok, double v) { return ok && std::isfinite(v) ? fmt::format("{:.6g}", v) : std::string(); };
    for (size_t k = 0; k < r.frames.size(); ++k) {
      const auto& f = r.frames[k];
      const bool t = f.has_length;
      std::string image = f.image;
      if (image.find_first_of(",\"") != std::string::npos) {
        std::string q = "\"";
        for (char ch : image) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
        image = q + "\"";
      }
      text += fmt::format("{}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {:.4f}, {:.4f}, {}, {}\n", k,
                          image, num(t, f.crack_length_m * 1e3), num(t, f.crack_length_raw_m * 1e3),
                          num(t, f.uncertainty_m * 1e3), num(t, f.tip.tip.s_px),
                          num(t, f.tip.tip.x_px), num(t, f.tip.tip.y_px),
                          t ? dic::TipMethodName(f.tip.method) : "",
                          num(f.tip.williams.found, f.tip.williams.s_px),
                          num(f.tip.jump.found, f.tip.jump.s_px),
                          num(f.tip.sqrt_cod.found, f.tip.sqrt_cod.s_px),
                          f.tip.methods_disagree ? 1 : 0, f.valid_fraction,
                          f.correlation.mean_zncc, f.correlation.reference_frame, f.Flags());
    }
    (void)m_per_px;
    WriteTextFileAtomic(csv_, text);
  }

  void WriteH5(const dic::CrackSequenceResult& r, const dic::CrackSequenceOptions& opt) const {
    io::H5Writer h5(out_);
    const size_t n = r.frames.size();
    std::vector<double> a(n, NAN), a_raw(n, NAN), sig(n, NAN), tx(n, NAN), ty(n, NAN), vf(n),
        kk(n, NAN), res(n, NAN);
    std::vector<std::string> images, methods;
    for (size_t k = 0; k < n; ++k) {
      const auto& f = r.frames[k];
      images.push_back(f.image);
      methods.push_back(f.has_length ? dic::TipMethodName(f.tip.method) : "none");
      vf[k] = f.valid_fraction;
      if (f.has_length) {
        a[k] = f.crack_length_m;
        a_raw[k] = f.crack_length_raw_m;
        sig[k] = f.uncertainty_m;
        tx[k] = f.tip.tip.x_px;
        ty[k] = f.tip.tip.y_px;
      }
      if (f.tip.williams.found) {
        kk[k] = f.tip.k_over_2mu_sqrt_px * std::sqrt(opt.scale_m_per_px);
        res[k] = f.tip.williams_residual_px;
      }
    }
    h5.WriteStrings("/dic/images", images);
    h5.WriteStrings("/dic/tip_method", methods);
    h5.WriteVector("/dic/crack_length", a, "m", "monotone crack length (NaN: no opening)");
    h5.WriteVector("/dic/crack_length_raw", a_raw, "m", "per-frame crack length");
    h5.WriteVector("/dic/crack_length_uncertainty", sig, "m", "one standard deviation");
    h5.WriteVector("/dic/tip_x", tx, "px", "tip position, reference image");
    h5.WriteVector("/dic/tip_y", ty, "px", "tip position, reference image");
    h5.WriteVector("/dic/valid_fraction", vf, "1", "valid points / correlated points");
    h5.WriteVector("/dic/k_over_2mu", kk, "m^0.5", "Williams K_I / (2 mu)");
    h5.WriteVector("/dic/williams_residual", res, "px", "RMS residual of the field fit");
    std::vector<std::string> flags;
    std::vector<double> path(4 * n, NAN);
    for (size_t k = 0; k < n; ++k) {
      flags.push_back(r.frames[k].Flags());
      const auto& L = r.frames[k].line_used;
      if (k > 0 && (r.frames[k].path.found || opt.has_line)) {
        path[4 * k] = L.x0; path[4 * k + 1] = L.y0; path[4 * k + 2] = L.x1; path[4 * k + 3] = L.y1;
      }
    }
    h5.WriteStrings("/dic/flags", flags);
    h5.WriteMatrix("/dic/crack_path", n, 4, path, "px",
                   "line the length is measured along: x0, y0 (notch side), x1, y1");
    const auto& L = opt.tip.line;
    h5.WriteAttribute("/dic", "crack_line_px", fmt::format("{},{},{},{}", L.x0, L.y0, L.x1, L.y1));
    h5.WriteAttribute("/dic", "scale_m_per_px", opt.scale_m_per_px);
    h5.WriteAttribute("/dic", "offset_m", opt.offset_m);
    h5.WriteAttribute("/dic", "subset_px", static_cast<double>(opt.correlation.subset_size));
    h5.WriteAttribute("/dic", "step_px", static_cast<double>(opt.correlation.step));
    for (size_t k = 1; k < n; ++k) {
      const auto& f = r.frames[k];
      const std::string g = fmt::format("/dic/frame_{:04d}", k);
      h5.WriteVector(g + "/cod_s", f.tip.cod.s_px, "px", "station along the crack line");
      std::vector<double> open(f.tip.cod.opening_px), slide(f.tip.cod.sliding_px);
      for (size_t j = 0; j < open.size(); ++j)
        if (!f.tip.cod.valid[j]) open[j] = slide[j] = NAN;
      h5.WriteVector(g + "/cod_opening", open, "px", "normal displacement jump");
      h5.WriteVector(g + "/cod_sliding", slide, "px", "tangential displacement jump");
      if (!f.field.x.empty()) {
        const size_t rows = f.field.ny, cols = f.field.nx;
        std::vector<double> u(f.field.u), v(f.field.v), st(f.field.size());
        for (size_t i = 0; i < f.field.size(); ++i) {
          st[i] = static_cast<double>(f.field.status[i]);
          if (!f.field.ok(i)) u[i] = v[i] = NAN;
        }
        h5.WriteMatrix(g + "/x", rows, cols, f.field.x, "px");
        h5.WriteMatrix(g + "/y", rows, cols, f.field.y, "px");
        h5.WriteMatrix(g + "/u", rows, cols, u, "px");
        h5.WriteMatrix(g + "/v", rows, cols, v, "px");
        h5.WriteMatrix(g + "/zncc", rows, cols, f.field.zncc, "1");
        h5.WriteMatrix(g + "/status", rows, cols, st, "1",
                       "0 ok, 1 masked, 2 crack band, 3 out of image, 4 no convergence, 5 low "
                       "correlation, 6 unreached");
      }
    }
    h5.Commit();
  }

  std::vector<std::string> images_;
  std::string crack_line_, scale_, tip_method_, threshold_, offset_, roi_, shape_, interpolation_,
      out_, csv_;
  int subset_ = 31, step_ = 5, search_ = 40, threads_ = 0;
  double min_zncc_ = 0.8, fit_radius_ = 0;
  double path_search_ = 40;
  bool no_incremental_ = false, fields_ = false, fixed_line_ = false;
};

}  // namespace

std::unique_ptr<Command> MakeDicCommand() { return std::make_unique<DicCommand>(); }

}  // namespace bridgefit::cli
