// Output of `bridgefit dic` and `bridgefit crack`: one table, JSON object,
// CSV and HDF5 layout for both (docs/DIC.md).
#include "dic_output.hpp"

#include <cmath>
#include <iostream>

#include <fmt/format.h>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "command.hpp"

namespace bridgefit::cli {
namespace {

nlohmann::json PathJson(const dic::FrameResult& f) {
  const dic::CrackLine& L = f.line_used;
  nlohmann::json j = {{"found", f.path.found}, {"line_px", {L.x0, L.y0, L.x1, L.y1}}};
  if (f.path.found) {
    j["angle_deg"] = f.path.angle_deg;
    j["points"] = f.path.inliers;
    j["rms_residual_px"] = f.path.rms_residual_px;
    j["cracked_length_px"] = f.path.cracked_length_px;
    j["line_max_offset_px"] = f.path.hint_max_offset_px;
    j["line_angle_deg"] = f.path.hint_angle_deg;
    j["disagrees_with_line"] = f.path.disagrees_with_hint;
    j["rms_all_points_px"] = f.path.line_rms_all_px;  // fit quality of the straight path
    j["curved"] = f.path.curved;
    if (f.path.curved) {
      j["polyline_px"] = nlohmann::json::array();
      for (size_t k = 0; k < f.path.polyline_x.size(); ++k)
        j["polyline_px"].push_back({f.path.polyline_x[k], f.path.polyline_y[k]});
      j["polyline_rms_px"] = f.path.polyline_rms_px;
    }
  } else if (!f.path.why_not_found.empty()) {
    j["why_not_found"] = f.path.why_not_found;
  }
  return j;
}

}  // namespace

void PrintDicResult(const dic::CrackSequenceResult& result, const dic::CrackSequenceOptions& opt,
                    bool json, const std::string& field_unit) {
  const double m_per_px = opt.scale_m_per_px;
  if (json) {
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
          {"tip_williams_px",
           f.tip.williams.found ? NumberOrNull(f.tip.williams.s_px) : nlohmann::json()},
          {"tip_jump_px", f.tip.jump.found ? NumberOrNull(f.tip.jump.s_px) : nlohmann::json()},
          {"tip_sqrt_px",
           f.tip.sqrt_cod.found ? NumberOrNull(f.tip.sqrt_cod.s_px) : nlohmann::json()},
          {"methods_disagree", f.tip.methods_disagree},
          {"tip_at_edge", f.tip.tip_at_edge},
          {"flagged", f.flagged},
          {"flags", f.Flags()},
          {"path", PathJson(f)},
          {"k_over_2mu_sqrt_m", f.tip.williams.found
                                    ? NumberOrNull(f.tip.k_over_2mu_sqrt_px * std::sqrt(m_per_px))
                                    : nlohmann::json()},
          {"williams_residual_px",
           f.tip.williams.found ? NumberOrNull(f.tip.williams_residual_px) : nlohmann::json()},
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
        std::cout << fmt::format(
            "{:5} {:14.4f} {:10.4f} {:10.2f} {:9.2f} {:9.2f} {:>9} {:6.3f}{} {}\n", k,
            f.crack_length_m * 1e3, f.uncertainty_m * 1e3, f.tip.tip.s_px, f.tip.tip.x_px,
            f.tip.tip.y_px, dic::TipMethodName(f.tip.method), f.valid_fraction,
            f.flagged ? "*" : " ", f.image + (f.flagged ? "  [" + f.Flags() + "]" : ""));
      else
        std::cout << fmt::format("{:5} {:>14} {:>10} {:>10} {:>9} {:>9} {:>9} {:6.3f}  {}\n", k,
                                 "none", "", "", "", "", "", f.valid_fraction, f.image);
    }
    std::cout << "(* = flagged: the length may be wrong by more than its uncertainty)\n";
  }
}

void WriteDicCsv(const std::string& path, const dic::CrackSequenceResult& r) {
  std::string text =
      "frame, image, crack_length [mm], crack_length_raw [mm], uncertainty [mm], crack_length "
      "[px], tip_x [px], tip_y [px], tip_method, tip_williams [px], tip_jump [px], tip_sqrt [px], "
      "methods_disagree, valid_fraction, mean_zncc, reference_frame, flags\n";
  auto num = [](bool ok, double v) {
    return ok && std::isfinite(v) ? fmt::format("{:.6g}", v) : std::string();
  };
  for (size_t k = 0; k < r.frames.size(); ++k) {
    const auto& f = r.frames[k];
    const bool t = f.has_length;
    std::string image = f.image;
    if (image.find_first_of(",\"") != std::string::npos) {
      std::string q = "\"";
      for (char ch : image) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
      image = q + "\"";
    }
    text += fmt::format(
        "{}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {:.4f}, {:.4f}, {}, {}\n", k, image,
        num(t, f.crack_length_m * 1e3), num(t, f.crack_length_raw_m * 1e3),
        num(t, f.uncertainty_m * 1e3), num(t, f.tip.tip.s_px), num(t, f.tip.tip.x_px),
        num(t, f.tip.tip.y_px), t ? dic::TipMethodName(f.tip.method) : "",
        num(f.tip.williams.found, f.tip.williams.s_px), num(f.tip.jump.found, f.tip.jump.s_px),
        num(f.tip.sqrt_cod.found, f.tip.sqrt_cod.s_px), f.tip.methods_disagree ? 1 : 0,
        f.valid_fraction, f.correlation.mean_zncc, f.correlation.reference_frame, f.Flags());
  }
  WriteTextFileAtomic(path, text);
}

void WriteDicH5(const std::string& file, const dic::CrackSequenceResult& r,
                const dic::CrackSequenceOptions& opt) {
  io::H5Writer h5(file);
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
      path[4 * k] = L.x0;
      path[4 * k + 1] = L.y0;
      path[4 * k + 2] = L.x1;
      path[4 * k + 3] = L.y1;
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
  // The field-fit window (Williams fit radius around the tip, crack band excluded): the report draws it.
  h5.WriteAttribute("/dic", "fit_radius_px", opt.tip.fit_radius_px);
  h5.WriteAttribute("/dic", "band_half_width_px", opt.tip.band_half_width_px);
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

}  // namespace bridgefit::cli
