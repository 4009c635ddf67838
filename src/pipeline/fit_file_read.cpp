// The reader of the fit file (/fit and its groups): what fit_file.cpp's
// WriteFitFile wrote, read back (one format, its writer and reader side
// by side in this module).
#include "bridgefit/pipeline/fit_file.hpp"

#include <cmath>
#include <fstream>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/hdf5.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/rcurve_file.hpp"
#include "fit_models.hpp"
#include "h5_read.hpp"

namespace bridgefit::pipeline {

// The reader of /fit (the report's view of it): what WriteFitFile wrote.
using detail::NumberAttr;
using detail::StringAttr;
using detail::VectorOrEmpty;

namespace {

const char* const kFitFileExpected =
    "a fit file from 'bridgefit fit --out FIT.h5' (or a campaign.h5 from 'bridgefit campaign')";

// One estimate as WriteEstimate wrote it (the report's and the design's
// reader); absent attributes stay NaN.
inverse::ParameterEstimate ReadEstimate(const io::H5Reader& r, const std::string& pg) {
  inverse::ParameterEstimate e;
  if (!r.Exists(pg)) return e;
  e.value = NumberAttr(r, pg, "value");
  e.ci95_low = NumberAttr(r, pg, "ci95_low");
  e.ci95_high = NumberAttr(r, pg, "ci95_high");
  e.lower_bound = NumberAttr(r, pg, "lower_bound");
  if (r.HasAttribute(pg, "model_bias")) {
    e.statistical_ci95_low = NumberAttr(r, pg, "statistical_ci95_low");
    e.statistical_ci95_high = NumberAttr(r, pg, "statistical_ci95_high");
    e.model_bias = NumberAttr(r, pg, "model_bias");
  }
  e.identified = NumberAttr(r, pg, "identified") == 1.0;
  e.fixed = NumberAttr(r, pg, "fixed") == 1.0;
  e.decided_by = StringAttr(r, pg, "decided_by");
  e.note = StringAttr(r, pg, "note");
  return e;
}

// /fit/law_shape as WriteLawShape wrote it; a file without it: the family's
// default shape (said in `note`), or an Error for a family whose shape is
// data. A table without its interpolation (written before it was stored)
// is read with straight segments, said in `note`.
laws::LawShape ReadLawShape(const io::H5Reader& r, const std::string& g, const std::string& file,
                            std::string* note) {
  const std::string lg = g + "/law_shape";
  const std::string family_name = r.Exists(lg) ? StringAttr(r, lg, "family") : StringAttr(r, g, "law");
  laws::LawFamily family;
  try {
    family = laws::ParseLawFamily(family_name);
  } catch (const Error&) {
    throw Error(ErrorKind::kInput, "the fit file names no law family this program knows",
                {.file = file, .field = g + "/law", .value = family_name, .expected = kFitFileExpected});
  }
  laws::LawShape shape;
  shape.family = family;
  if (r.Exists(lg)) {
    shape.peak_ratio = NumberAttr(r, lg, "peak_ratio");
    shape.alpha = NumberAttr(r, lg, "alpha");
    shape.d_points = VectorOrEmpty(r, lg + "/d_points");
    shape.s_points = VectorOrEmpty(r, lg + "/s_points");
    const std::string interpolation = StringAttr(r, lg, "interpolation");
    if (!interpolation.empty()) {
      try {
        shape.interpolation = laws::ParseTableInterpolation(interpolation);
      } catch (const Error& e) {
        throw Error(ErrorKind::kInput, e.message(),
                    {.file = file, .field = lg + " interpolation", .value = interpolation,
                     .expected = e.context().expected});
      }
    } else if (family == laws::LawFamily::kTable) {
      *note += "; the table law's interpolation is not in the file (written before it was "
               "stored): drawn with straight segments between its points";
    }
  } else if (std::optional<laws::LawShape> d = laws::DefaultShape(family)) {
    shape = *d;
    *note += "; the law's shape: the family's default (the file predates /fit/law_shape)";
  } else {
    throw Error(ErrorKind::kInput, "the fit file does not hold the shape of its law",
                {.file = file, .field = lg, .value = family_name,
                 .expected = "a fit file written with /fit/law_shape (refit it)"});
  }
  shape.Validate();
  return shape;
}

// A fitted shape's own parameters (/fit/law_shape, fitted_family set).
void ReadFittedShape(const io::H5Reader& r, const std::string& lg, report::FitView& f) {
  if (!r.Exists(lg)) return;
  f.fitted_shape = StringAttr(r, lg, "fitted_family");
  if (f.fitted_shape.empty()) return;
  f.shape_knots = static_cast<int>(NumberAttr(r, lg, "knots"));
  f.fitted_shape_note = StringAttr(r, lg, "note");
  if (!r.Exists(lg + "/parameter_names")) return;
  const std::vector<std::string> names = r.ReadStrings(lg + "/parameter_names");
  const std::vector<double> values = VectorOrEmpty(r, lg + "/parameter_values");
  const std::vector<double> errors = VectorOrEmpty(r, lg + "/parameter_standard_errors");
  const std::vector<double> pinned = VectorOrEmpty(r, lg + "/parameter_pinned");
  if (values.size() != names.size() || errors.size() != names.size() ||
      pinned.size() != names.size())
    return;
  for (size_t k = 0; k < names.size(); ++k)
    f.shape_parameters.push_back({names[k], values[k], errors[k], pinned[k] == 1.0});
}

}  // namespace

report::FitView ReadFitView(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path))
    throw Error(ErrorKind::kInput, "the fit file does not exist",
                {.file = path.string(), .expected = "an HDF5 file from 'bridgefit fit --out'"});
  const io::H5Reader r(path);
  if (!r.Exists("/fit"))
    throw Error(ErrorKind::kInput, "the file has no /fit group",
                {.file = path.string(), .field = "/fit",
                 .expected = "an HDF5 file from 'bridgefit fit --out'"});
  report::FitView f;
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
  try {
    f.shape = ReadLawShape(r, g, path.string(), &f.shape_note);
  } catch (const Error& e) {  // the report still draws the rest, and says why not the law
    f.shape_note += std::string("; ") + e.what();
  }
  if (!f.shape_note.empty()) f.shape_note.erase(0, 2);  // the leading "; "
  ReadFittedShape(r, g + "/law_shape", f);
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
    report::Estimate e;
    e.name = name;
    const std::string pg = g + "/parameters/" + name;
    if (r.Exists(pg)) {
      const inverse::ParameterEstimate read = ReadEstimate(r, pg);
      e.present = true;
      e.units = StringAttr(r, pg, "units");
      e.value = read.value;
      e.ci_low = read.ci95_low;
      e.ci_high = read.ci95_high;
      e.lower_bound = read.lower_bound;
      e.statistical_low = read.statistical_ci95_low;
      e.statistical_high = read.statistical_ci95_high;
      e.model_bias = read.model_bias;
      e.identified = read.identified;
      e.fixed = read.fixed;
      e.decided_by = read.decided_by;
      e.note = read.note;
    }
    f.estimates.push_back(e);
    const std::string prof = g + "/profiles/" + name;
    if (r.Exists(prof + "/value") && r.Exists(prof + "/chi2")) {
      report::Profile p{name, r.ReadVector(prof + "/value"), r.ReadVector(prof + "/chi2"),
                NumberAttr(r, prof, "chi2_threshold"), NumberAttr(r, prof, "flat") == 1.0};
      if (p.value.size() == p.chi2.size() && p.value.size() >= 2) f.profiles.push_back(p);
    }
  }
  return f;
}

// ---- the fitted law for `bridgefit design` (ReadFittedLaw) ----
namespace {

// /fit/scene (written since issue 19's design): specimen and material.
Scene ReadFitScene(const io::H5Reader& r, const std::string& sg, const std::string& file) {
  Scene scene;
  scene.source = file + ":" + sg;
  SpecimenSpec& s = scene.specimen;
  s.type = StringAttr(r, sg, "specimen") == "dcb" ? SpecimenType::kDCB : SpecimenType::kCT;
  s.width = NumberAttr(r, sg, "width_m");
  s.height = NumberAttr(r, sg, "height_m");
  s.thickness = NumberAttr(r, sg, "thickness_m");
  s.length = NumberAttr(r, sg, "length_m");
  s.notch = NumberAttr(r, sg, "notch_m");
  s.plane = StringAttr(r, sg, "plane") == "strain" ? PlaneCondition::kPlaneStrain
                                                   : PlaneCondition::kPlaneStress;
  MaterialSpec& m = scene.material;
  m.orthotropic = NumberAttr(r, sg, "orthotropic") == 1.0;
  m.E = NumberAttr(r, sg, "E_Pa");
  m.nu = NumberAttr(r, sg, "nu");
  m.E1 = NumberAttr(r, sg, "E1_Pa");
  m.E2 = NumberAttr(r, sg, "E2_Pa");
  m.G12 = NumberAttr(r, sg, "G12_Pa");
  m.nu12 = NumberAttr(r, sg, "nu12");
  m.G13 = NumberAttr(r, sg, "G13_Pa");
  m.angle = NumberAttr(r, sg, "angle_rad");
  m.density = NumberAttr(r, sg, "density_kg_per_m3");
  scene.Validate();
  return scene;
}

// A file written before /fit/scene: the scene file its `scene` attribute
// names, as given, then next to the fit file. Empty path: not found.
std::filesystem::path FindSceneFile(const std::string& named, const std::filesystem::path& file) {
  if (named.empty()) return {};
  const std::filesystem::path given(named);
  if (std::filesystem::exists(given)) return given;
  const std::filesystem::path beside = file.parent_path() / given.filename();
  return std::filesystem::exists(beside) ? beside : std::filesystem::path();
}

}  // namespace

bool IsHdf5File(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  char head[8] = {};
  in.read(head, 8);
  return in.gcount() == 8 && std::string(head, 8) == std::string("\x89HDF\r\n\x1a\n", 8);
}

FittedLaw ReadFittedLaw(const io::H5Reader& r, const std::filesystem::path& file,
                        const std::string& root) {
  const std::string g = root + "/fit", name = file.string();
  if (!r.Exists(g)) {
    const bool rcurve = r.Exists(root + "/rcurve") || r.Exists(root + "/experiment");
    throw Error(ErrorKind::kInput,
                rcurve ? "the file holds an R curve or a record but no fit: fit it first "
                         "('bridgefit fit FILE --out FIT.h5')"
                       : "the file has no fit",
                {.file = name, .field = g, .expected = kFitFileExpected});
  }
  FittedLaw law;
  law.source = name;
  law.group = g;
  const std::string pg = g + "/parameters/";
  law.sigma_c = ReadEstimate(r, pg + "sigma_c");
  law.J_B = ReadEstimate(r, pg + "J_B");
  law.delta_c = ReadEstimate(r, pg + "delta_c");
  law.J_tip_c = ReadEstimate(r, pg + "J_tip_c");
  const double jb = law.J_B.identified ? law.J_B.value : law.J_B.lower_bound;
  if (!(law.sigma_c.value > 0) || !(jb > 0) || !(law.J_tip_c.value > 0))
    throw Error(ErrorKind::kInput,
                "the fit file holds no fitted bridging law (sigma_c, J_B or its lower bound, "
                "J_tip,c)",
                {.file = name, .field = pg + "sigma_c, J_B, J_tip_c",
                 .value = StringAttr(r, g, "verdict"), .expected = kFitFileExpected});
  if (r.Exists(g + "/scene")) {
    law.scene = ReadFitScene(r, g + "/scene", name);
    law.note = "specimen and material from " + g + "/scene";
  } else {
    const std::string named = StringAttr(r, g, "scene");
    const std::filesystem::path scene_file = FindSceneFile(named, file);
    if (scene_file.empty())
      throw Error(ErrorKind::kInput,
                  "the fit file holds no specimen (/fit/scene) and its scene file is not found",
                  {.file = name, .field = g + "/scene", .value = named,
                   .expected = "a fit file written with /fit/scene, or its scene file in place"});
    law.scene = io::ReadSceneFile(scene_file);
    law.scene.bridging.reset();
    law.scene.fracture.reset();
    law.note = "specimen and material from the scene file " + scene_file.string() +
               " (the fit file predates /fit/scene)";
  }
  law.shape = ReadLawShape(r, g, name, &law.note);
  return law;
}

FittedLaw ReadFittedLaw(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path))
    throw Error(ErrorKind::kInput, "the fit file does not exist",
                {.file = path.string(), .expected = kFitFileExpected});
  if (!IsHdf5File(path))
    throw Error(ErrorKind::kInput, "not an HDF5 file",
                {.file = path.string(), .expected = kFitFileExpected});
  const io::H5Reader r(path);
  return ReadFittedLaw(r, path);
}

}  // namespace bridgefit::pipeline
