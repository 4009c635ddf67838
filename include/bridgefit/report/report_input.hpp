#pragma once
// What a report shows, as values (issue 16: the report opens no HDF5, CSV or
// TOML file itself). pipeline/report_file.hpp reads them: /fit with its one
// reader (pipeline/fit_file.hpp), the record (/experiment), the DIC output
// (pipeline/dic_file.hpp), a reference column and a truth scene.

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/laws/law.hpp"

namespace bridgefit::report {

// A view of a fit (+ optional record, DIC, reference, truth).

struct Estimate {
  std::string name, units;
  double value = NAN, ci_low = NAN, ci_high = NAN, lower_bound = NAN;
  // Issue 17: ci_* are the total interval (statistical + model bias); the
  // profile's own crossings are the statistical ends (NaN in older files).
  double statistical_low = NAN, statistical_high = NAN, model_bias = NAN;
  double ProfileLow() const { return std::isfinite(model_bias) ? statistical_low : ci_low; }
  double ProfileHigh() const { return std::isfinite(model_bias) ? statistical_high : ci_high; }
  bool present = false, identified = false, fixed = false;
  std::string decided_by, note;
};

struct Profile {
  std::string name;
  std::vector<double> value, chi2;  // SI value, best chi^2 with the others re-optimized
  double threshold = NAN;           // Delta chi^2 of the 95% interval (3.84 s^2)
  bool flat = false;                // stays under the threshold to the box edge on a side
};

struct FitView {
  std::string source;  // file name, for the page
  std::string model, optimizer, law, verdict, r_kind, scene, stop_reason, fit_to;
  double converged = NAN, steady = NAN, bridging = NAN, rms = NAN, rms_load = NAN, wall_s = NAN;
  double evaluations = NAN, reduced_chi2 = NAN;
  std::vector<double> a, R, fit_a, fit_R, out_a, out_R;
  // A load-displacement fit: rows used, their load and the model's load.
  std::vector<double> fit_d, fit_P, data_P, out_d, out_P;
  std::vector<Estimate> estimates;  // sigma_c, J_B, delta_c, J_tip_c
  std::vector<Profile> profiles;
  // The law's shape (/fit/law_shape; a file without it: the family's
  // default); nullopt when the file holds none for a family whose shape is
  // data (the report then draws no law, said in shape_note).
  std::optional<laws::LawShape> shape;
  std::string shape_note;  // a fallback taken reading the shape
  // A fitted shape's own parameters (bilinear, trilinear, table; empty
  // fitted_shape: a fixed shape): d in delta_c, s in sigma_c, with their
  // Wald standard errors (NaN: the pinned peak, or singular).
  struct ShapeParameter {
    std::string name;
    double value = NAN, standard_error = NAN;
    bool pinned = false;
  };
  std::string fitted_shape;
  int shape_knots = 0;  // table: N
  std::string fitted_shape_note;
  std::vector<ShapeParameter> shape_parameters;
  const Estimate* Find(const std::string& name) const {
    for (const Estimate& e : estimates)
      if (e.name == name && e.present) return &e;
    return nullptr;
  }
};

// One DIC frame as `bridgefit dic` wrote it (CSV and/or HDF5).
struct DicFrame {
  std::string image;            // as recorded
  std::filesystem::path image_file;          // resolved on disk (empty when not found)
  double crack_length = NAN;    // [m]
  double tip_x = NAN, tip_y = NAN;  // [px], reference image
  std::string tip_method;       // "" or "none" when no tip
  double valid_fraction = NAN;
  bool methods_disagree = false;
  double tip_williams_s = NAN, tip_jump_s = NAN, tip_sqrt_s = NAN;  // [px] along the line, per method
  std::vector<double> cod_s, cod_opening;  // [px] along the crack line
  // A path found by DIC (optional, later versions): points in px.
  std::vector<double> path_x, path_y;
  std::string flag;             // why the frame is doubtful ("" = fine)
};

struct DicView {
  std::filesystem::path csv, h5;
  std::vector<DicFrame> frames;
  bool has_line = false;
  double line[4] = {NAN, NAN, NAN, NAN};  // x0,y0,x1,y1 [px]
  double scale_m_per_px = NAN, offset_m = NAN, fit_radius_px = NAN, subset_px = NAN;
  std::vector<double> path_x, path_y;     // a crack path for the whole sequence, if given
  bool has_geometry() const { return !h5.empty(); }
};

struct ReferenceView {
  std::string label, column, unit_text;  // e.g. G_I, N/mm
  std::filesystem::path file;
  std::vector<double> crack_length, value;  // [m], [J/m^2] (rows with both finite)
};

// A law-free sigma(delta) (bridgefit lawfree --out, /lawfree): per route the
// curve with its band, drawn over the fitted law.
struct LawFreeView {
  struct Curve {
    std::string route;  // "J_ff(delta*)" or "R(delta_root)"
    std::vector<double> delta, sigma, lower, upper;  // [m], [Pa]
    bool identified = false;  // false: J_B, delta_c bounds only (R route: sigma + C delta)
    // Per node: the band is within +-resolved_fraction of the peak (drawn thick).
    std::vector<char> resolved;
    double resolved_fraction = 0.10;
  };
  std::filesystem::path file;
  std::vector<Curve> curves;
};

struct TruthView {
  bool present = false;
  std::optional<laws::LawShape> shape;  // the true law's shape (bridging in the scene)
  double sigma_c = NAN, delta_c = NAN, J_B = NAN, J_tip_c = NAN;
};

struct ReportInput {
  std::filesystem::path fit_path;  // the fit file the view was read from (the page names it)
  FitView fit;
  std::optional<ExperimentRecord> record;
  bool record_from_images = false;  // its crack length came from DIC (rcurve --crack-length-from)
  std::optional<DicView> dic;
  std::optional<ReferenceView> reference;
  std::optional<LawFreeView> law_free;
  TruthView truth;
  std::vector<std::string> notes;  // what could not be read, and why
};

}  // namespace bridgefit::report
