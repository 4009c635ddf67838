// The report's input: the only part of src/report that opens files. Reads the
// fit file (/fit, layout in docs/FORMATS.md) into a FitView, and the optional
// record, DIC output (CSV and/or HDF5), reference column and truth scene.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/io/csv.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "report_impl.hpp"

namespace bridgefit::report::detail {
namespace {

std::string StringAttr(const io::H5Reader& r, const std::string& object, const std::string& key) {
  return r.HasAttribute(object, key) ? r.ReadStringAttribute(object, key) : std::string();
}
double NumberAttr(const io::H5Reader& r, const std::string& object, const std::string& key) {
  return r.HasAttribute(object, key) ? r.ReadNumberAttribute(object, key) : NAN;
}
std::vector<double> VectorOrEmpty(const io::H5Reader& r, const std::string& path) {
  return r.Exists(path) ? r.ReadVector(path) : std::vector<double>();
}

// /fit of a `bridgefit fit --out` file.
FitView ReadFit(const fs::path& path) {
  if (!fs::exists(path))
    throw Error(ErrorKind::kInput, "the fit file does not exist",
                {.file = path.string(), .expected = "an HDF5 file from 'bridgefit fit --out'"});
  const io::H5Reader r(path);
  if (!r.Exists("/fit"))
    throw Error(ErrorKind::kInput, "the file has no /fit group",
                {.file = path.string(), .field = "/fit",
                 .expected = "an HDF5 file from 'bridgefit fit --out'"});
  FitView f;
  f.source = path.filename().string();
  const std::string g = "/fit";
  f.model = StringAttr(r, g, "model");
  f.optimizer = StringAttr(r, g, "optimizer");
  f.law = StringAttr(r, g, "law");
  f.verdict = StringAttr(r, g, "verdict");
  f.r_kind = StringAttr(r, g, "r_kind");
  f.scene = StringAttr(r, g, "scene");
  f.stop_reason = StringAttr(r, g, "stop_reason");
  f.converged = NumberAttr(r, g, "converged");
  f.steady = NumberAttr(r, g, "steady_state_reached");
  f.bridging = NumberAttr(r, g, "bridging_detected");
  f.rms = NumberAttr(r, g, "rms_residual_J_per_m2");
  f.reduced_chi2 = NumberAttr(r, g, "reduced_chi2");
  f.fit_to = StringAttr(r, g, "fit_to");
  if (r.Exists(g + "/load_displacement")) {
    const std::string ld = g + "/load_displacement";
    f.rms_load = NumberAttr(r, g, "rms_residual_N");
    f.fit_d = VectorOrEmpty(r, ld + "/displacement");
    f.data_P = VectorOrEmpty(r, ld + "/load");
    f.fit_P = VectorOrEmpty(r, ld + "/fitted_load");
    f.out_d = VectorOrEmpty(r, ld + "/outlier_displacement");
    f.out_P = VectorOrEmpty(r, ld + "/outlier_load");
    if (f.fit_P.size() != f.fit_d.size() || f.data_P.size() != f.fit_d.size()) f.fit_P.clear();
  }
  f.wall_s = NumberAttr(r, g, "wall_s");
  f.evaluations = NumberAttr(r, g, "evaluations");
  f.a = VectorOrEmpty(r, g + "/crack_length");
  f.R = VectorOrEmpty(r, g + "/R");
  if (f.a.empty() && r.Exists("/rcurve/crack_length")) {
    f.a = r.ReadVector("/rcurve/crack_length");
    f.R = VectorOrEmpty(r, "/rcurve/R");
  }
  if (f.a.empty() || f.a.size() != f.R.size())
    throw Error(ErrorKind::kInput, "the fit file holds no R curve",
                {.file = path.string(), .field = "/fit/crack_length, /fit/R"});
  f.fit_a = VectorOrEmpty(r, g + "/fitted_crack_length");
  f.fit_R = VectorOrEmpty(r, g + "/fitted_R");
  if (f.fit_R.size() != f.fit_a.size()) f.fit_R.clear();
  f.out_a = VectorOrEmpty(r, g + "/outlier_crack_length");
  f.out_R = VectorOrEmpty(r, g + "/outlier_R");
  for (const char* name : {"sigma_c", "J_B", "delta_c", "J_tip_c"}) {
    Estimate e;
    e.name = name;
    const std::string pg = g + "/parameters/" + name;
    if (r.Exists(pg)) {
      e.present = true;
      e.units = StringAttr(r, pg, "units");
      e.value = NumberAttr(r, pg, "value");
      e.ci_low = NumberAttr(r, pg, "ci95_low");
      e.ci_high = NumberAttr(r, pg, "ci95_high");
      e.lower_bound = NumberAttr(r, pg, "lower_bound");
      if (r.HasAttribute(pg, "model_bias")) {
        e.statistical_low = NumberAttr(r, pg, "statistical_ci95_low");
        e.statistical_high = NumberAttr(r, pg, "statistical_ci95_high");
        e.model_bias = NumberAttr(r, pg, "model_bias");
      }
      e.identified = NumberAttr(r, pg, "identified") == 1.0;
      e.fixed = NumberAttr(r, pg, "fixed") == 1.0;
      e.decided_by = StringAttr(r, pg, "decided_by");
      e.note = StringAttr(r, pg, "note");
    }
    f.estimates.push_back(e);
    const std::string prof = g + "/profiles/" + name;
    if (r.Exists(prof + "/value") && r.Exists(prof + "/chi2")) {
      Profile p{name, r.ReadVector(prof + "/value"), r.ReadVector(prof + "/chi2"),
                NumberAttr(r, prof, "chi2_threshold"), NumberAttr(r, prof, "flat") == 1.0};
      if (p.value.size() == p.chi2.size() && p.value.size() >= 2) f.profiles.push_back(p);
    }
  }
  return f;
}

// The first existing of: the path as recorded, relative to the DIC file's
// folder, the file name in `images_dir`, the file name next to the DIC file.
fs::path ResolveImage(const std::string& recorded, const fs::path& dic_file, const fs::path& images_dir) {
  if (recorded.empty()) return {};
  const fs::path p(recorded);
  std::vector<fs::path> candidates{p};
  if (p.is_relative()) candidates.push_back(dic_file.parent_path() / p);
  if (!images_dir.empty()) candidates.push_back(images_dir / p.filename());
  candidates.push_back(dic_file.parent_path() / p.filename());
  for (const fs::path& c : candidates) {
    std::error_code ec;
    if (fs::is_regular_file(c, ec)) return c;
  }
  return {};
}

// bridgefit dic --csv: one row per frame.
void ReadDicCsv(const fs::path& path, DicView& dic, std::vector<std::string>& notes) {
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
    DicFrame& f = dic.frames[k];
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
void ReadDicH5(const fs::path& path, DicView& dic) {
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
    DicFrame& f = dic.frames[k];
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
std::string FrameFlag(const DicFrame& f, size_t k) {
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

DicView ReadDic(const ReportOptions& options, std::vector<std::string>& notes) {
  DicView dic;
  dic.csv = options.dic_csv;
  dic.h5 = options.dic_h5;
  if (!dic.h5.empty()) {
    if (!fs::exists(dic.h5))
      throw Error(ErrorKind::kInput, "the DIC file does not exist",
                  {.file = dic.h5.string(), .field = "--dic",
                   .expected = "an HDF5 file from 'bridgefit dic --out'"});
    ReadDicH5(dic.h5, dic);
  }
  if (!dic.csv.empty()) ReadDicCsv(dic.csv, dic, notes);
  const fs::path anchor = dic.h5.empty() ? dic.csv : dic.h5;
  int missing = 0;
  for (size_t k = 0; k < dic.frames.size(); ++k) {
    DicFrame& f = dic.frames[k];
    f.image_file = ResolveImage(f.image, anchor, options.images_dir);
    missing += f.image_file.empty();
    f.flag = FrameFlag(f, k);
  }
  if (dic.has_geometry() && missing > 0)
    notes.push_back(fmt::format("{} of {} DIC images not found (recorded paths, next to {}{}): "
                                "those frames are not drawn",
                                missing, dic.frames.size(), anchor.parent_path().string(),
                                options.images_dir.empty() ? "; give --images DIR" : ", --images"));
  return dic;
}

ReferenceView ReadReference(const ReferenceColumn& ref) {
  if (ref.csv.empty() || ref.column.empty())
    throw Error(ErrorKind::kUsage, "a reference column needs both the CSV and the column name",
                {.field = "--reference, --reference-csv", .value = ref.csv.string() + " " + ref.column});
  const io::CsvTable t = io::ReadCsvTable(ref.csv);
  auto unit_of = [&](const std::string& header) {
    const auto it = ref.units.find(header);
    return it == ref.units.end() ? std::string() : it->second;
  };
  if (t.Find(ref.column) < 0)
    throw Error(ErrorKind::kInput, "the reference column is not in the CSV",
                {.file = ref.csv.string(), .field = ref.column, .expected = "a header of the file"});
  if (t.Find(ref.crack_length_column) < 0)
    throw Error(ErrorKind::kInput, "the reference CSV has no crack-length column",
                {.file = ref.csv.string(), .field = ref.crack_length_column,
                 .expected = "a crack-length header (map it with --columns crack_length=NAME)"});
  ReferenceView v;
  v.file = ref.csv;
  v.column = ref.column;
  v.label = ref.column;
  v.unit_text = unit_of(ref.column);
  if (v.unit_text.empty()) v.unit_text = t.units[t.Find(ref.column)];
  const std::vector<double> a =
      t.ColumnSi(ref.crack_length_column, Dimension::Length(), unit_of(ref.crack_length_column));
  const std::vector<double> g = t.ColumnSi(ref.column, Dimension::EnergyPerArea(), unit_of(ref.column));
  for (size_t i = 0; i < a.size() && i < g.size(); ++i)
    if (std::isfinite(a[i]) && std::isfinite(g[i])) {
      v.crack_length.push_back(a[i]);
      v.value.push_back(g[i]);
    }
  if (v.value.empty())
    throw Error(ErrorKind::kInput, "the reference column has no row with a finite value and crack length",
                {.file = ref.csv.string(), .field = ref.column});
  return v;
}

TruthView ReadTruth(const fs::path& scene_file) {
  TruthView t;
  const Scene scene = io::ReadSceneFile(scene_file);
  t.present = true;
  if (scene.fracture) t.J_tip_c = scene.fracture->J_tip_c;
  if (scene.bridging) {
    t.shape = scene.bridging->shape;
    t.sigma_c = scene.bridging->scales.sigma_c;
    t.delta_c = scene.bridging->scales.delta_c;
    t.J_B = scene.bridging->Law().BridgingToughness();
  } else {
    t.sigma_c = t.delta_c = t.J_B = 0.0;  // no bridging in the truth
  }
  return t;
}

}  // namespace

ReportInput ReadReportInput(const fs::path& fit_h5, const ReportOptions& options) {
  ReportInput in;
  in.fit = ReadFit(fit_h5);
  // The record: --record, else the fit file itself when it carries /experiment.
  fs::path record_h5 = options.record_h5;
  if (record_h5.empty() && io::H5Reader(fit_h5).Exists("/experiment/load")) record_h5 = fit_h5;
  if (!record_h5.empty()) {
    const io::H5Reader r(record_h5);
    in.record = io::ReadExperimentH5(r, "/experiment");
    in.record_from_images = in.record->metadata.count("crack_length") > 0;  // rcurve --crack-length-from
  }
  if (!options.dic_csv.empty() || !options.dic_h5.empty()) in.dic = ReadDic(options, in.notes);
  if (options.reference.enabled()) in.reference = ReadReference(options.reference);
  if (!options.truth_scene.empty()) in.truth = ReadTruth(options.truth_scene);
  return in;
}

}  // namespace bridgefit::report::detail
