// The DIC output's one owner (`bridgefit dic`, `bridgefit crack`): the
// per-frame CSV and the HDF5 /dic group, written and read here (docs/DIC.md).
#include "bridgefit/pipeline/dic_file.hpp"

#include <cmath>
#include <cstdio>

#include <fmt/format.h>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/core/error.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "h5_read.hpp"

namespace bridgefit::pipeline {
namespace {

using detail::NumberAttr;
using detail::StringAttr;
using detail::VectorOrEmpty;

// The first existing of: the path as recorded, relative to the DIC file's
// folder, the file name in `images_dir`, the file name next to the DIC file.
std::filesystem::path ResolveImage(const std::string& recorded, const std::filesystem::path& dic_file, const std::filesystem::path& images_dir) {
  if (recorded.empty()) return {};
  const std::filesystem::path p(recorded);
  std::vector<std::filesystem::path> candidates{p};
  if (p.is_relative()) candidates.push_back(dic_file.parent_path() / p);
  if (!images_dir.empty()) candidates.push_back(images_dir / p.filename());
  candidates.push_back(dic_file.parent_path() / p.filename());
  for (const std::filesystem::path& c : candidates) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(c, ec)) return c;
  }
  return {};
}

// bridgefit dic --csv: one row per frame.
void ReadDicCsv(const std::filesystem::path& path, report::DicView& dic, std::vector<std::string>& notes) {
  const io::CsvTable t = io::ReadCsvTable(path);
  int col = -1;
  for (size_t i = 0; i < t.names.size(); ++i)
    if (t.names[i] == "crack_length" || (col < 0 && t.names[i].find("crack_length") != std::string::npos &&
                                         t.names[i].find("raw") == std::string::npos))
      col = static_cast<int>(i);
  if (col < 0) {
    notes.push_back("DIC CSV has no crack_length column: " + path.string());
    return;
  }
  const std::vector<double> a = t.ColumnSi(t.names[col], Dimension::Length());
  if (dic.frames.size() < a.size()) dic.frames.resize(a.size());
  auto numbers = [&](const char* name) {
    return t.Find(name) >= 0 ? t.columns[t.Find(name)] : std::vector<double>(a.size(), NAN);
  };
  const std::vector<double> tx = numbers("tip_x"), ty = numbers("tip_y"),
                            valid = numbers("valid_fraction"), disagree = numbers("methods_disagree"),
                            williams = numbers("tip_williams"), jump = numbers("tip_jump"), sqrt_cod = numbers("tip_sqrt");
  for (size_t k = 0; k < a.size(); ++k) {
    report::DicFrame& f = dic.frames[k];
    f.crack_length = a[k];
    if (t.Find("image") >= 0) f.image = t.TextColumn("image")[k];
    if (t.Find("tip_method") >= 0) f.tip_method = t.TextColumn("tip_method")[k];
    f.tip_x = tx[k];
    f.tip_y = ty[k];
    f.valid_fraction = valid[k];
    f.methods_disagree = disagree[k] == 1.0;
    f.tip_williams_s = williams[k];
    f.tip_jump_s = jump[k];
    f.tip_sqrt_s = sqrt_cod[k];
  }
}

// bridgefit dic --out: /dic with the crack line, tips and opening profiles.
// Tolerant of datasets a later version adds (a crack path: /dic/path_x,
// /dic/path_y for the sequence, /dic/frame_NNNN/path_x, path_y per frame).
void ReadDicH5(const std::filesystem::path& path, report::DicView& dic) {
  const io::H5Reader r(path);
  if (!r.Exists("/dic/images"))
    throw Error(ErrorKind::kInput, "the DIC file has no /dic/images",
                {.file = path.string(), .field = "/dic/images",
                 .expected = "an HDF5 file from 'bridgefit dic --out'"});
  const std::vector<std::string> images = r.ReadStrings("/dic/images");
  const size_t n = images.size();
  auto vec = [&](const std::string& name) {
    std::vector<double> v = VectorOrEmpty(r, "/dic/" + name);
    v.resize(n, NAN);
    return v;
  };
  const std::vector<double> a = vec("crack_length"), tx = vec("tip_x"), ty = vec("tip_y"),
                            vf = vec("valid_fraction");
  const std::vector<std::string> methods =
      r.Exists("/dic/tip_method") ? r.ReadStrings("/dic/tip_method") : std::vector<std::string>();
  if (dic.frames.size() < n) dic.frames.resize(n);
  for (size_t k = 0; k < n; ++k) {
    report::DicFrame& f = dic.frames[k];
    f.image = images[k];
    if (std::isfinite(a[k]) || !std::isfinite(f.crack_length)) f.crack_length = a[k];
    f.tip_x = tx[k];
    f.tip_y = ty[k];
    f.valid_fraction = vf[k];
    if (k < methods.size()) f.tip_method = methods[k];
    const std::string g = fmt::format("/dic/frame_{:04d}", k);
    f.cod_s = VectorOrEmpty(r, g + "/cod_s");
    f.cod_opening = VectorOrEmpty(r, g + "/cod_opening");
    if (f.cod_opening.size() != f.cod_s.size()) f.cod_opening.clear();
    f.path_x = VectorOrEmpty(r, g + "/path_x");
    f.path_y = VectorOrEmpty(r, g + "/path_y");
    if (f.path_x.size() != f.path_y.size()) f.path_x.clear(), f.path_y.clear();
  }
  const std::string line = StringAttr(r, "/dic", "crack_line_px");
  if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf", &dic.line[0], &dic.line[1], &dic.line[2],
                  &dic.line[3]) == 4)
    dic.has_line = true;
  dic.scale_m_per_px = NumberAttr(r, "/dic", "scale_m_per_px");
  dic.offset_m = NumberAttr(r, "/dic", "offset_m");
  dic.fit_radius_px = NumberAttr(r, "/dic", "fit_radius_px");
  dic.subset_px = NumberAttr(r, "/dic", "subset_px");
  dic.path_x = VectorOrEmpty(r, "/dic/path_x");
  dic.path_y = VectorOrEmpty(r, "/dic/path_y");
  if (dic.path_x.size() != dic.path_y.size()) dic.path_x.clear(), dic.path_y.clear();
}

// Why a frame is doubtful, "" when it is not (frame 0 is the reference).
std::string FrameFlag(const report::DicFrame& f, size_t k) {
  if (k == 0) return "";
  std::vector<std::string> why;
  if (!std::isfinite(f.crack_length) || f.tip_method == "none") why.push_back("no tip found");
  if (f.methods_disagree) {
    std::string each;
    for (const auto& [name, s] : {std::pair<const char*, double>{"williams", f.tip_williams_s},
                                  {"jump", f.tip_jump_s}, {"sqrt", f.tip_sqrt_s}})
      if (std::isfinite(s)) each += fmt::format("{}{} {:.1f}", each.empty() ? "" : ", ", name, s);
    why.push_back("tip methods disagree by more than one grid step" +
                  (each.empty() ? std::string() : " (" + each + " px along the line)"));
  }
  if (std::isfinite(f.valid_fraction) && f.valid_fraction < 0.8)
    why.push_back(fmt::format("{:.0f}% of the points correlated", 100 * f.valid_fraction));
  std::string text;
  for (const std::string& w : why) text += (text.empty() ? "" : "; ") + w;
  return text;
}


// "ok", or why delta* was not read ("no_tip" without a tip).
std::string DeltaStarStatus(const dic::FrameJ& j) {
  if (j.delta_star_ok) return "ok";
  if (j.status == dic::FrameJStatus::kNoTip || j.status == dic::FrameJStatus::kNotRequested)
    return dic::FrameJStatusName(j.status);
  return "failed: " + j.delta_star_why;
}

// The field-wide fit's status ("ok", "not_requested", or the status and why).
std::string FitStatus(const dic::FrameJ& j) {
  std::string s = dic::FieldFitJStatusName(j.fit.status);
  if (!j.fit.why.empty()) s += ": " + j.fit.why;
  return s;
}

// /dic/J_ff, J_ff_spread, J_domains_ok, J_status, J_ff_fit,
// J_ff_fit_uncertainty, J_fit_status, delta_star,
// delta_star_uncertainty, delta_star_status and the inputs as attributes.
void WriteDicJ(io::H5Writer& h5, const dic::CrackSequenceResult& r,
               const dic::CrackSequenceOptions& opt) {
  const size_t n = r.frames.size();
  std::vector<double> j(n, NAN), spread(n, NAN), ok(n, 0), delta(n, NAN), u(n, NAN), root(n, NAN);
  std::vector<double> jfit(n, NAN), jfit_u(n, NAN), dil(n, NAN), dil_u(n, NAN), dil_out(n, 0);
  std::vector<double> rotation(n, NAN);
  std::vector<std::string> status, delta_status, fit_status, delta_method;
  for (size_t k = 0; k < n; ++k) {
    const dic::FrameJ& f = r.frames[k].j;
    if (f.fit.status == dic::FieldFitJStatus::kOk) {
      jfit[k] = f.fit.J;
      jfit_u[k] = f.fit.J_uncertainty;
    }
    fit_status.push_back(FitStatus(f));
    if (f.fit.status != dic::FieldFitJStatus::kNotRequested &&
        f.fit.status != dic::FieldFitJStatus::kTooFewPoints) {
      dil[k] = f.fit.dilatation;
      dil_u[k] = f.fit.dilatation_se;
      dil_out[k] = f.fit.dilatation_removed ? 1 : 0;
    }
    if (f.status != dic::FrameJStatus::kNotRequested && f.status != dic::FrameJStatus::kNoTip)
      rotation[k] = f.rigid_rotation_rad;
    if (f.status == dic::FrameJStatus::kOk) {
      j[k] = f.J_ff;
      spread[k] = f.J_ff_spread_percent;
    }
    ok[k] = f.domains_ok;
    std::string s = dic::FrameJStatusName(f.status);
    if (!f.why.empty() && f.status != dic::FrameJStatus::kOk) s += ": " + f.why;
    status.push_back(s);
    if (f.delta_star_ok) {
      delta[k] = f.delta_star;
      u[k] = f.delta_star_uncertainty;
    }
    if (f.status != dic::FrameJStatus::kNoTip && f.status != dic::FrameJStatus::kNotRequested)
      root[k] = f.root_distance_m;
    delta_status.push_back(DeltaStarStatus(f));
    delta_method.push_back(dic::DeltaStarMethodName(f.delta_star_method));
  }
  h5.WriteVector("/dic/J_ff", j, "J/m^2", "far-field J, mean over the ok domains (NaN: see J_status)");
  h5.WriteVector("/dic/J_ff_spread", spread, "%", "(max - min) / mean over the ok far-field domains");
  h5.WriteVector("/dic/J_domains_ok", ok, "1", "far-field domains that gave a J");
  h5.WriteStrings("/dic/J_status", status);
  h5.WriteVector("/dic/J_ff_fit", jfit, "J/m^2",
                 "far-field J of the field-wide Williams fit (NaN: see J_fit_status)");
  h5.WriteVector("/dic/J_ff_fit_uncertainty", jfit_u, "J/m^2", "one standard deviation");
  h5.WriteStrings("/dic/J_fit_status", fit_status);
  h5.WriteVector("/dic/J_fit_dilatation", dil, "1",
                 "uniform dilatation of the field (stress-free: out-of-plane motion, thermal)");
  h5.WriteVector("/dic/J_fit_dilatation_uncertainty", dil_u, "1", "one standard deviation");
  h5.WriteVector("/dic/J_fit_dilatation_removed", dil_out, "1",
                 "1: beyond 3 standard deviations, taken out of J_ff and J_ff_fit");
  h5.WriteVector("/dic/J_rigid_rotation", rotation, "rad",
                 "the field's rigid rotation taken out before J (counter-clockwise)");
  h5.WriteVector("/dic/delta_star", delta, "m",
                 "opening at the initial notch root (NaN: see delta_star_status)");
  h5.WriteVector("/dic/delta_star_uncertainty", u, "m", "one standard deviation");
  h5.WriteVector("/dic/root_distance", root, "m", "tip to initial notch root along the line");
  h5.WriteStrings("/dic/delta_star_status", delta_status);
  // profile | at_root | near_tip (LEFM near-tip opening) | none (dic/frame_j.hpp)
  h5.WriteStrings("/dic/delta_star_method", delta_method);
  const dic::ElasticConstants& e = opt.j_integral.elastic;
  h5.WriteAttribute("/dic", "notch_length_m", opt.j_integral.notch_length_m);
  h5.WriteAttribute(
      "/dic", "j_elastic",
      e.kind == dic::ElasticConstants::Kind::kIsotropic
          ? fmt::format("isotropic E {:.6g} Pa, nu {:.4g}, plane stress", e.E, e.nu)
          : fmt::format("orthotropic E1 {:.6g} Pa, E2 {:.6g} Pa, G12 {:.6g} Pa, nu12 {:.4g}, "
                        "plane stress",
                        e.E1, e.E2, e.G12, e.nu12));
}

}  // namespace

void WriteDicCsv(const std::string& path, const dic::CrackSequenceResult& r) {
  std::string text =
      "frame, image, crack_length [mm], crack_length_raw [mm], uncertainty [mm], crack_length "
      "[px], tip_x [px], tip_y [px], tip_method, tip_williams [px], tip_jump [px], tip_sqrt [px], "
      "methods_disagree, valid_fraction, mean_zncc, reference_frame, flags";
  // With the J integral (issue 21): J_ff and delta* per frame, each with
  // its status (a number only where the status is ok).
  if (r.j_integral)
    text += ", J_ff [J/m^2], J_ff_spread [%], J_domains_ok, J_status, delta_star [mm], "
            "delta_star_uncertainty [mm], delta_star_status, J_ff_fit [J/m^2], "
            "J_ff_fit_uncertainty [J/m^2], J_fit_status, delta_star_method";
  text += "\n";
  auto num = [](bool ok, double v) {
    return ok && std::isfinite(v) ? fmt::format("{:.6g}", v) : std::string();
  };
  // The crack lengths exactly (the shortest text that reads back to the same
  // double): `rcurve --crack-length-from` gives what the DIC measured, and a
  // campaign's DIC specimen the single chain's fit (CampaignDic test).
  auto exact = [](bool ok, double v) {
    return ok && std::isfinite(v) ? fmt::format("{}", v) : std::string();
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
        exact(t, f.crack_length_m * 1e3), exact(t, f.crack_length_raw_m * 1e3),
        num(t, f.uncertainty_m * 1e3), num(t, f.tip.tip.s_px), num(t, f.tip.tip.x_px),
        num(t, f.tip.tip.y_px), t ? dic::TipMethodName(f.tip.method) : "",
        num(f.tip.williams.found, f.tip.williams.s_px), num(f.tip.jump.found, f.tip.jump.s_px),
        num(f.tip.sqrt_cod.found, f.tip.sqrt_cod.s_px), f.tip.methods_disagree ? 1 : 0,
        f.valid_fraction, f.correlation.mean_zncc, f.correlation.reference_frame, f.Flags());
    if (r.j_integral) {
      text.pop_back();
      const bool j_ok = f.j.status == dic::FrameJStatus::kOk;
      text += fmt::format(", {}, {}, {}, {}, {}, {}, {}\n", num(j_ok, f.j.J_ff),
                          num(j_ok, f.j.J_ff_spread_percent), f.j.domains_ok,
                          dic::FrameJStatusName(f.j.status), num(f.j.delta_star_ok, f.j.delta_star * 1e3),
                          num(f.j.delta_star_ok, f.j.delta_star_uncertainty * 1e3),
                          DeltaStarStatus(f.j));
      text.pop_back();
      const bool fit_ok = f.j.fit.status == dic::FieldFitJStatus::kOk;
      text += fmt::format(", {}, {}, {}, {}\n", num(fit_ok, f.j.fit.J),
                          num(fit_ok, f.j.fit.J_uncertainty),
                          dic::FieldFitJStatusName(f.j.fit.status),
                          dic::DeltaStarMethodName(f.j.delta_star_method));
    }
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
  if (r.j_integral) WriteDicJ(h5, r, opt);
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

DicCrackLengths ReadDicCrackLengths(const std::string& path) {
  const io::CsvTable frames = io::ReadCsvTable(path);
  for (const char* column : {"image", "crack_length"})
    if (frames.Find(column) < 0)
      throw Error(ErrorKind::kInput, "the crack-length file lacks a column",
                  {.file = path, .field = column,
                   .expected = "the CSV of `bridgefit dic --csv` (image, crack_length [mm])"});
  DicCrackLengths out{
      frames.TextColumn("image"), frames.ColumnSi("crack_length", Dimension::Length()), {}};
  if (frames.Find("flags") >= 0) LeaveOutDoubtfulLengths(frames.TextColumn("flags"), out);
  return out;
}

void LeaveOutDoubtfulLengths(const std::vector<std::string>& flags, DicCrackLengths& frames) {
  BF_CHECK_INPUT(flags.size() == frames.image.size(), "one flags entry per frame");
  std::string listed;
  std::vector<size_t> doubtful;
  int clean = 0;
  for (size_t k = 0; k < flags.size(); ++k) {
    if (!std::isfinite(frames.crack_length[k])) continue;
    if (!dic::FlagsDoubtLength(flags[k])) {
      ++clean;
      continue;
    }
    doubtful.push_back(k);
    listed += fmt::format("{}{} ({})", listed.empty() ? "" : ", ",
                          std::filesystem::path(frames.image[k]).filename().string(), flags[k]);
  }
  if (doubtful.empty()) return;
  // An R curve needs two lengths: with fewer left, the doubtful ones stay,
  // and the warning travels with the curve.
  if (clean < 2) {
    frames.notes.push_back(fmt::format(
        "warning: {} DIC frame(s) whose flags put the length in doubt are used for the crack "
        "lengths ({} without a doubt, fewer than 2): the R curve may be off by more than the "
        "lengths' uncertainty; check the crack line, the ROI and the flags ({}) in the DIC CSV",
        doubtful.size(), clean, listed));
    return;
  }
  for (size_t k : doubtful) frames.crack_length[k] = NAN;
  frames.notes.push_back(fmt::format(
      "{} DIC frame(s) left out of the crack lengths (their flags put the length in doubt; "
      "the R curve interpolates over them): {}",
      doubtful.size(), listed));
}

DicJSeries ReadDicJSeries(const std::filesystem::path& path) {
  const io::H5Reader r(path);
  if (!r.Exists("/dic/images"))
    throw Error(ErrorKind::kInput, "the DIC file has no /dic/images",
                {.file = path.string(), .field = "/dic/images",
                 .expected = "an HDF5 file from 'bridgefit dic --out' or 'bridgefit crack --out'"});
  for (const char* name : {"/dic/J_ff", "/dic/J_status", "/dic/delta_star", "/dic/delta_star_status"})
    if (!r.Exists(name))
      throw Error(ErrorKind::kInput, "the DIC file holds no J integral",
                  {.file = path.string(), .field = name,
                   .expected = "J_ff and delta* per frame: rerun 'bridgefit dic' (or 'crack') with "
                               "--scene S --j-integral --out"});
  DicJSeries s;
  s.image = r.ReadStrings("/dic/images");
  const size_t n = s.image.size();
  auto vec = [&](const std::string& name) {
    std::vector<double> v = VectorOrEmpty(r, "/dic/" + name);
    v.resize(n, NAN);
    return v;
  };
  s.crack_length = vec("crack_length");
  s.J_ff = vec("J_ff");
  s.J_ff_spread_percent = vec("J_ff_spread");
  s.delta_star = vec("delta_star");
  s.delta_star_uncertainty = vec("delta_star_uncertainty");
  s.J_status = r.ReadStrings("/dic/J_status");
  s.delta_star_status = r.ReadStrings("/dic/delta_star_status");
  s.J_status.resize(n, "missing");
  // The field-wide fit's J (files before 2026-12-03 have none: "missing").
  s.J_ff_fit = vec("J_ff_fit");
  s.J_ff_fit_uncertainty = vec("J_ff_fit_uncertainty");
  if (r.Exists("/dic/J_fit_status")) s.J_fit_status = r.ReadStrings("/dic/J_fit_status");
  s.J_fit_status.resize(n, "missing");
  // The dilatation taken out of J (files before 2026-12-05: NaN and 0).
  s.J_fit_dilatation = vec("J_fit_dilatation");
  s.J_fit_dilatation_uncertainty = vec("J_fit_dilatation_uncertainty");
  s.J_fit_dilatation_removed = VectorOrEmpty(r, "/dic/J_fit_dilatation_removed");
  s.J_fit_dilatation_removed.resize(n, 0);
  s.delta_star_status.resize(n, "missing");
  // How delta* was read (files before 2026-12-04 have none: "missing").
  if (r.Exists("/dic/delta_star_method")) s.delta_star_method = r.ReadStrings("/dic/delta_star_method");
  s.delta_star_method.resize(n, "missing");
  if (r.Exists("/dic/flags")) s.flags = r.ReadStrings("/dic/flags");
  s.flags.resize(n);
  s.notch_length = NumberAttr(r, "/dic", "notch_length_m");
  return s;
}

report::DicView ReadDicView(const std::filesystem::path& csv, const std::filesystem::path& h5,
                            const std::filesystem::path& images_dir, std::vector<std::string>& notes) {
  report::DicView dic;
  dic.csv = csv;
  dic.h5 = h5;
  if (!dic.h5.empty()) {
    if (!std::filesystem::exists(dic.h5))
      throw Error(ErrorKind::kInput, "the DIC file does not exist",
                  {.file = dic.h5.string(), .field = "--dic",
                   .expected = "an HDF5 file from 'bridgefit dic --out'"});
    ReadDicH5(dic.h5, dic);
  }
  if (!dic.csv.empty()) ReadDicCsv(dic.csv, dic, notes);
  const std::filesystem::path anchor = dic.h5.empty() ? dic.csv : dic.h5;
  int missing = 0;
  for (size_t k = 0; k < dic.frames.size(); ++k) {
    report::DicFrame& f = dic.frames[k];
    f.image_file = ResolveImage(f.image, anchor, images_dir);
    missing += f.image_file.empty();
    f.flag = FrameFlag(f, k);
  }
  if (dic.has_geometry() && missing > 0)
    notes.push_back(fmt::format("{} of {} DIC images not found (recorded paths, next to {}{}): "
                                "those frames are not drawn",
                                missing, dic.frames.size(), anchor.parent_path().string(),
                                images_dir.empty() ? "; give --images DIR" : ", --images"));
  return dic;
}

}  // namespace bridgefit::pipeline
