// `bridgefit fit`: bridging-law parameters from a measured R curve, or from a
// load-displacement record with crack length reduced in-process (issue 7).
// The workflow is pipeline::RunFit; this file maps flags to a FitRequest and
// prints the run.
//   bridgefit fit rcurve.csv --scene scene.toml --law linear --json
//   bridgefit fit rcurve.h5 --scene scene.toml --fix J_tip_c=2210J/m^2 --out fit.h5
//   bridgefit fit data_samples/mdf_ct/record_exact.csv --scene data_samples/mdf_ct/scene.toml
//       --rcurve-method energy --out fit.h5 --report report

#include <iostream>
#include <sstream>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/fit.hpp"
#include "bridgefit/pipeline/report_file.hpp"
#include "command.hpp"
#include "fit_json.hpp"
#include "rcurve_flags.hpp"

namespace bridgefit::cli {
namespace {

int ParameterIndex(const std::string& name, const char* option) {
  for (int i = 0; i < inverse::kParameterCount; ++i)
    if (name == inverse::ParameterName(i)) return i;
  throw Error(ErrorKind::kUsage, "unknown parameter",
              {.field = option, .value = name, .expected = "sigma_c, J_B or J_tip_c"});
}

Dimension ParameterDimension(int index) {
  return index == inverse::kSigmaC ? Dimension::Stress() : Dimension::EnergyPerArea();
}

std::vector<std::pair<std::string, std::string>> SplitAssignments(const std::string& text,
                                                                  const char* option) {
  std::vector<std::pair<std::string, std::string>> out;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    const size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw Error(ErrorKind::kUsage, "malformed assignment",
                  {.field = option, .value = item, .expected = "name=value, e.g. J_tip_c=2210J/m^2"});
    out.emplace_back(item.substr(0, eq), item.substr(eq + 1));
  }
  return out;
}

// The `bridgefit rcurve` options that `bridgefit fit RECORD` takes.
struct ReductionFlags : RCurveFlags {
  std::string columns, units;
};


// An interval that cannot be trusted is said on stderr too, whatever the
// output format (the JSON carries it as interval_status / interval_reason).
void WarnUnreliableIntervals(const inverse::FitSummary& s, const std::string& law) {
  const std::pair<const char*, const inverse::ParameterEstimate*> estimates[] = {
      {"sigma_c", &s.sigma_c}, {"J_B", &s.J_B}, {"J_tip_c", &s.J_tip_c}};
  for (const auto& [name, e] : estimates) {
    if (e->fixed || e->interval_status == inverse::IntervalStatus::kReliable ||
        e->interval_status == inverse::IntervalStatus::kOpen)
      continue;
    std::cerr << "warning: fit (" << law << " law): " << name << " 95% interval "
              << inverse::IntervalStatusName(e->interval_status) << ": " << e->interval_reason
              << "\n";
  }
}

class FitCommand final : public Command {
 public:
  const char* name() const override { return "fit"; }
  const char* description() const override {
    return "Fit a bridging law (sigma_c, J_B, J_tip,c) to a measured R curve or test record";
  }
  void Register(CLI::App& sub) override {
    sub.add_option("input", input_,
                   "R curve (CSV 'crack_length [mm], R [J/m^2]' or rcurve.h5), or a test record "
                   "(CSV 'load [N], displacement [mm], crack_length [mm]' or record.h5)")
        ->required();
    sub.add_option("--scene", scene_, "Scene TOML: specimen and material")->required();
    sub.add_option("--model", model_,
                   "Forward model: reduced | analytic | mpm | auto (reduced fit, checked by MPM "
                   "and corrected by space mapping when they differ)")
        ->default_val("reduced");
    sub.add_option("--mpm-cell", mpm_cell_,
                   "MPM cell size for --model mpm|auto, or auto: the coarsest valid cell "
                   "(<= 2.5 mm, 8 through a DCB arm, 10 over the growth), halved for --model auto "
                   "while MPM's own error is above half --model-tolerance")
        ->default_val("auto");
    sub.add_option("--model-tolerance", model_tolerance_,
                   "--model auto: largest relative R difference between the reduced and MPM "
                   "models accepted without correction")
        ->default_val(0.03);
    sub.add_option("--law", law_,
                   "Law family: linear|cubic|triangular|exponential (shape held), "
                   "bilinear|trilinear|table (shape fitted too), or compare (every family by AICc)")
        ->default_val("linear");
    sub.add_option("--shape-families", shape_families_,
                   "--law compare: families whose shape is fitted too, comma-separated "
                   "bilinear,trilinear,table, or none")
        ->default_val("bilinear,trilinear,table");
    sub.add_option("--table-knots", table_knots_,
                   "--law table|compare: knot counts N the tabulated law tries (AICc chooses), "
                   "e.g. 3,4,5,6 or one count, 5")
        ->default_val("3,4,5,6");
    sub.add_option("--optimizer", optimizer_, "ceres-lm|bobyqa|neldermead|cobyla|direct|crs2")
        ->default_val("bobyqa");
    sub.add_option("--fix", fix_, "Fixed parameters, e.g. 'J_tip_c=2210J/m^2'");
    sub.add_option("--bounds", bounds_, "Bounds, e.g. 'sigma_c=0.05MPa..5MPa,J_B=1J/m^2..5kJ/m^2'");
    sub.add_option("--starts", starts_, "Latin-hypercube starts")->default_val(4);
    r_kind_option_ =
        sub.add_option("--r-kind", r_kind_,
                       "What the data holds: energy | elastic-zone | as-data (record input: the "
                       "model's own record reduced by the data's method); default energy, for a "
                       "record what its reduction gives");
    // A record input is reduced as `bridgefit rcurve RECORD --scene SCENE` would.
    reduction_options_ = {
        sub.add_option(
               "--rcurve-method", reduction_.method,
               "Record input: R-curve method energy|mbt|cc|lefm|equivalent (rcurve --method)")
            ->default_val("energy"),
        sub.add_option(
            "--rcurve-min-increment", reduction_.min_increment,
            "Record input, energy method: smallest crack increment (rcurve --min-increment)"),
        sub.add_option("--rcurve-max-crack-length", reduction_.max_crack_length,
                       "Record input: validity limit (rcurve --max-crack-length)"),
        sub.add_option("--rcurve-smooth", reduction_.smooth_rows,
                       "Record input, energy method: local quadratic fits over 2 N + 1 rows "
                       "(rcurve --smooth; 0: none)")
            ->default_val(0),
        sub.add_option(
            "--rcurve-load-noise", reduction_.load_noise,
            "Record input: load noise, 1 sigma (rcurve --load-noise; default estimated)"),
        sub.add_option("--rcurve-displacement-noise", reduction_.displacement_noise,
                       "Record input: displacement noise, 1 sigma (rcurve --displacement-noise)"),
        sub.add_option("--rcurve-crack-noise", reduction_.crack_noise,
                       "Record input: crack-length noise, 1 sigma (rcurve --crack-noise)"),
        sub.add_option("--columns", reduction_.columns,
                       "Record input: column mapping, e.g. load=Force,crack_length=CrackExt"),
        sub.add_option("--units", reduction_.units,
                       "Record input: unit mapping, e.g. displacement=mm,load=N")};
    sub.add_option("--fit-to", fit_to_,
                   "What the model is fitted to: r-curve (the R curve, or a record's reduction) | "
                   "load-displacement (a record's load at each displacement; started from the "
                   "R-curve fit; docs/FIT.md)")
        ->default_val("r-curve");
    sub.add_flag("--calibrate-compliance{initial}", calibrate_compliance_,
                 "--fit-to load-displacement: calibrate the model's compliance to the record's, "
                 "for real records whose E or machine compliance is not known (docs/FIT.md). "
                 "'initial' (the flag alone): the scene's moduli scaled to the initial slope, "
                 "refined on the whole record; '=crack': a modulus scale and a series compliance "
                 "fitted to the record's compliance at its measured crack lengths, alternated "
                 "with the law's fit")
        ->check(CLI::IsMember({"initial", "crack"}));
    sub.add_option("--resolution", resolution_,
                   "Reduced model element size, e.g. '0.5 mm', or auto (default): the coarsest "
                   "size whose predicted parameter bias is below 0.3 of each statistical "
                   "uncertainty (docs/FIT.md)")
        ->default_val("auto");
    sub.add_flag("--no-profile", no_profile_, "Skip the profile likelihood (faster)");
    sub.add_option("--out", out_h5_, "Write the fit to this HDF5 file");
    sub.add_option("--report", report_dir_, "Also write an HTML report into this folder");
  }

  int Run(const CommonOptions& common) override {
    const pipeline::FitRequest request = MakeRequest(common);
    const pipeline::FitRun run = pipeline::RunFit(request);
    // The in-process R curve's warnings (cleaning rules, a fallback start).
    if (run.input.reduction)
      for (const std::string& warning : run.input.reduction->warnings)
        std::cerr << "warning: " << warning << "\n";
    report::ReportOptions report_options;
    report_options.title = "bridgefit fit: " + input_;
    const auto written = pipeline::WriteFitOutputs(request, run, out_h5_, report_dir_, report_options);
    if (written && !common.quiet) std::cerr << "report: " << written->index_html.string() << "\n";
    if (run.model_error.status != inverse::ModelErrorStatus::kEstimated)
      std::cerr << "warning: fit: " << run.model_error.Summary() << "\n";
    if (!run.model_error.warning.empty())
      std::cerr << "warning: fit: " << run.model_error.warning << "\n";
    if (!run.model_check_warning.empty())
      std::cerr << "warning: fit: --model auto: " << run.model_check_warning << "\n";
    if (run.comparison.empty()) {
      WarnUnreliableIntervals(run.summary, run.summary.law);
    } else {
      for (const inverse::LawComparison& c : run.comparison) {
        WarnUnreliableIntervals(c.summary, c.law);
        if (std::isnan(c.aicc) && !c.note.empty())  // a family skipped: never a silent gap
          std::cerr << "warning: fit: --law compare: " << c.law << " " << c.note << "\n";
      }
    }
    if (common.json) {
      PrintJson(FitRunJson(run, input_));
    } else {
      std::cout << run.BriefReport();
      if (!out_h5_.empty()) std::cout << "  written: " << out_h5_ << "\n";
    }
    return run.summary.converged ? 0 : 1;
  }

 private:
  // Flags -> request; a malformed value is a usage error naming its flag.
  pipeline::FitRequest MakeRequest(const CommonOptions& common) const {
    pipeline::FitRequest request;
    request.input_path = input_;
    request.scene_path = scene_;
    request.scene = io::ReadSceneFile(scene_);
    request.columns = reduction_.columns;
    request.units = reduction_.units;
    for (const CLI::Option* option : reduction_options_)
      if (option->count() > 0) request.reduction_given = true;
    ApplyRCurveFlags(reduction_, "rcurve-", request.reduction);
    request.model = pipeline::ParseModelChoice(model_);
    if (model_ == "mpm" || model_ == "auto")
      request.mpm_cell = mpm_cell_ == "auto"
                             ? NAN
                             : ParseOptionQuantity(mpm_cell_, Dimension::Length(), "--mpm-cell");
    request.model_tolerance = model_tolerance_;
    if (!resolution_.empty() && resolution_ != "auto")
      request.resolution = ParseOptionQuantity(resolution_, Dimension::Length(), "--resolution");
    pipeline::SetFitLaw(law_, request);
    request.shape_families = ParseShapeFamilies(shape_families_);
    request.shape_fit.table_knots.clear();
    for (const std::string& item : SplitList(table_knots_)) {
      try {
        request.shape_fit.table_knots.push_back(std::stoi(item));
      } catch (const std::exception&) {
        throw Error(ErrorKind::kUsage, "malformed knot count",
                    {.field = "--table-knots", .value = item, .expected = "integers, e.g. 3,4,5,6"});
      }
    }
    if (r_kind_option_->count() > 0) request.r_kind = inverse::ParseRKind(r_kind_);
    request.target = inverse::ParseFitTarget(fit_to_);
    request.calibration = inverse::ParseComplianceCalibrationMode(calibrate_compliance_);
    request.fit = FitOptions(common);
    return request;
  }

  static std::vector<std::string> SplitList(const std::string& text) {
    std::vector<std::string> items;
    size_t start = 0;
    while (start <= text.size()) {
      const size_t comma = std::min(text.find(',', start), text.size());
      if (comma > start) items.push_back(text.substr(start, comma - start));
      start = comma + 1;
    }
    return items;
  }
  static std::vector<inverse::ShapeFamily> ParseShapeFamilies(const std::string& text) {
    std::vector<inverse::ShapeFamily> families;
    if (text == "none") return families;
    for (const std::string& item : SplitList(text)) {
      bool known = false;
      for (auto family : {inverse::ShapeFamily::kBilinear, inverse::ShapeFamily::kTrilinear,
                          inverse::ShapeFamily::kTable})
        if (item == inverse::ShapeFamilyName(family)) families.push_back(family), known = true;
      if (!known)
        throw Error(ErrorKind::kUsage, "unknown shape family",
                    {.field = "--shape-families", .value = item,
                     .expected = "bilinear, trilinear, table (comma-separated) or none"});
    }
    return families;
  }

  inverse::FitOptions FitOptions(const CommonOptions& common) const {
    inverse::FitOptions options;
    options.optimizer = inverse::ParseOptimizer(optimizer_);
    options.starts = starts_;
    options.profile_likelihood = !no_profile_;
    options.progress = !common.quiet;
    for (const auto& [key, value] : SplitAssignments(fix_, "--fix")) {
      const int index = ParameterIndex(key, "--fix");
      options.fixed[index] = true;
      options.fixed_value[index] = ParseOptionQuantity(value, ParameterDimension(index), "--fix");
    }
    for (const auto& [key, value] : SplitAssignments(bounds_, "--bounds")) {
      const int index = ParameterIndex(key, "--bounds");
      const size_t dots = value.find("..");
      if (dots == std::string::npos)
        throw Error(ErrorKind::kUsage, "malformed bounds",
                    {.field = "--bounds", .value = value, .expected = "low..high"});
      options.lower[index] =
          ParseOptionQuantity(value.substr(0, dots), ParameterDimension(index), "--bounds");
      options.upper[index] =
          ParseOptionQuantity(value.substr(dots + 2), ParameterDimension(index), "--bounds");
    }
    return options;
  }

  std::string shape_families_ = "bilinear,trilinear,table", table_knots_ = "3,4,5,6";
  std::string input_, scene_, model_, law_, optimizer_, fix_, bounds_, r_kind_, resolution_,
      out_h5_, report_dir_, mpm_cell_ = "auto", fit_to_ = "r-curve";
  double model_tolerance_ = 0.03;
  int starts_ = 4;
  bool no_profile_ = false;
  std::string calibrate_compliance_;  // "", "initial" or "crack"
  ReductionFlags reduction_;
  std::vector<CLI::Option*> reduction_options_;
  CLI::Option* r_kind_option_ = nullptr;
};

}  // namespace

std::unique_ptr<Command> MakeFitCommand() { return std::make_unique<FitCommand>(); }

}  // namespace bridgefit::cli
