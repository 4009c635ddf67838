// `bridgefit rcurve`: R curve from a load-displacement(-crack length) record
// (module experiment, docs/RCURVE_METHODS.md).
//   bridgefit rcurve data_samples/dcb_composite/DCB-01_Toughness.csv
//       --scene data_samples/dcb_composite/scene.toml --method mbt
//       --columns time=Time,displacement=Disp,load=Force,crack_length=CrackExt
//       --units time=s,displacement=mm,load=N,crack_length=mm --out rcurve.h5 --json
//   bridgefit rcurve record.h5 --type ct --width 100mm --thickness 12.7mm --notch 30mm
//       --modulus 3GPa --method energy --csv rcurve.csv

#include <cmath>
#include <iostream>
#include <string>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/units.hpp"
#include "bridgefit/experiment/rcurve.hpp"
#include "bridgefit/io/scene_file.hpp"
#include "bridgefit/pipeline/rcurve.hpp"
#include "command.hpp"
#include "json_output.hpp"
#include "rcurve_flags.hpp"

namespace bridgefit::cli {
namespace {

class RcurveCommand final : public Command {
 public:
  const char* name() const override { return "rcurve"; }
  const char* description() const override {
    return "R curve from a test record (energy, DCB beam/compliance, CT LEFM, equivalent crack)";
  }
  void Register(CLI::App& sub) override {
    sub.add_option("record", record_, "Test record: CSV (units in the header or --units) or HDF5")
        ->required();
    sub.add_option("--scene", scene_, "Scene TOML with [specimen] and [material]");
    sub.add_option("--method", flags_.method, "energy|mbt|cc|lefm|equivalent")->default_val("energy");
    sub.add_option("--columns", columns_,
                   "Column mapping, e.g. time=Time,displacement=Disp,load=Force,crack_length=CrackExt");
    sub.add_option("--units", units_, "Unit mapping, e.g. displacement=mm,load=N,crack_length=mm");
    sub.add_option("--out", out_, "Write the record and the R curve to this HDF5 file");
    sub.add_option("--csv", csv_, "Write the R curve to this CSV file");
    sub.add_option("--crack-length-from", crack_from_,
                   "Crack lengths measured on the record's images: the CSV of `bridgefit dic "
                   "--csv`, matched by the record's image column, linear in time between frames");
    // Specimen options (without --scene, or overriding it).
    sub.add_option("--type", type_, "Specimen type: ct|dcb");
    sub.add_option("--width", width_, "CT: W; DCB: b (e.g. '25 mm')");
    sub.add_option("--height", height_, "DCB: arm thickness h; CT: total height");
    sub.add_option("--thickness", thickness_, "CT: thickness B");
    sub.add_option("--length", length_, "DCB: total length L");
    sub.add_option("--notch", notch_, "Initial crack length a0 from the load line");
    sub.add_option("--modulus", modulus_, "Young's modulus E (along the crack), e.g. '19.3 GPa'");
    sub.add_option("--nu", nu_, "Poisson's ratio");
    sub.add_option("--g13", g13_, "DCB transverse shear modulus G13 (orthotropic scenes)");
    sub.add_option("--plane", plane_, "stress|strain (CT LEFM)");
    // Reduction settings.
    sub.add_option("--load-noise", flags_.load_noise, "Load noise, 1 sigma (default: estimated)");
    sub.add_option("--displacement-noise", flags_.displacement_noise, "Displacement noise, 1 sigma");
    sub.add_option("--crack-noise", flags_.crack_noise, "Crack-length noise, 1 sigma");
    sub.add_option("--min-increment", flags_.min_increment, "Energy method: smallest crack increment");
    sub.add_option("--smooth", flags_.smooth_rows,
                   "Energy method: local quadratic fits over 2 N + 1 rows before the balance (0: none)")
        ->default_val(0);
    sub.add_option("--max-crack-length", flags_.max_crack_length, "Validity limit (default CT 0.9 W, DCB L - 4h)");
    sub.add_flag("--large-displacement", large_displacement_,
                 "DCB mbt/cc: ASTM D5528 large-displacement (F) and load-block (N) corrections");
    sub.add_option("--block-offset", block_offset_,
                   "With --large-displacement: t, loading-pin centre to arm mid-plane (default 0)");
    sub.add_option("--block-half-length", block_half_length_,
                   "With --large-displacement: L', loading-pin centre to block edge (default 0)");
    sub.add_option("--coverage", coverage_, "Coverage factor of the reported uncertainty")
        ->default_val(2.0);
    // Record cleaning (docs/RCURVE_METHODS.md, "Cleaning"): tolerances of the named rules.
    sub.add_option("--reversal-tolerance", cleaning_.reversal_tolerance,
                   "Displacement drop below its running maximum that starts an unload-reload "
                   "cycle, in noise sigmas (less is jitter)")
        ->default_val(cleaning_.reversal_tolerance);
    sub.add_option("--glitch-tolerance", cleaning_.glitch_tolerance,
                   "Single-row spike in load or displacement dropped as a glitch, in noise sigmas")
        ->default_val(cleaning_.glitch_tolerance);
    sub.add_option("--preload-fraction", cleaning_.preload_fraction,
                   "Leading rows with load below this fraction of the maximum are the preload")
        ->default_val(cleaning_.preload_fraction);
    sub.add_option("--failure-fraction", cleaning_.failure_fraction,
                   "Trailing rows after the last load above this fraction of the maximum are after "
                   "final failure")
        ->default_val(cleaning_.failure_fraction);
  }

  int Run(const CommonOptions& common) override {
    experiment::RCurveOptions options;
    ApplyRCurveFlags(flags_, "", options);
    if (!scene_.empty()) {
      const Scene scene = io::ReadSceneFile(scene_);
      options.specimen = scene.specimen;
      options.material = scene.material;
    } else if (type_.empty()) {
      throw Error(ErrorKind::kUsage, "the specimen is not given",
                  {.field = "--scene", .expected = "--scene SCENE.toml or --type ct|dcb with sizes"});
    }
    ApplySpecimenOptions(options);
    options.coverage_factor = coverage_;
    options.cleaning = cleaning_;
    options.large_displacement_correction = large_displacement_;
    if (!block_offset_.empty())
      options.load_block_offset = ParseOptionQuantity(block_offset_, Dimension::Length(), "--block-offset");
    if (!block_half_length_.empty())
      options.load_block_half_length =
          ParseOptionQuantity(block_half_length_, Dimension::Length(), "--block-half-length");
    if ((!block_offset_.empty() || !block_half_length_.empty()) && !large_displacement_)
      throw Error(ErrorKind::kUsage,
                  "the load-block sizes only act with the large-displacement correction",
                  {.field = "--block-offset/--block-half-length",
                   .expected = "--large-displacement"});
    pipeline::RCurveRequest request;
    request.record_path = record_;
    request.columns = columns_;
    request.units = units_;
    request.crack_length_from = crack_from_;
    request.options = options;
    request.scene_path = scene_;
    const pipeline::RCurveRun run = pipeline::RunRCurve(request);
    for (const std::string& warning : run.result.warnings)
      std::cerr << "warning: " << warning << "\n";
    pipeline::WriteRCurveOutputs(request, run, out_, csv_);
    if (common.json) {
      nlohmann::json out = RCurveRunJson(run);
      if (!out_.empty()) out["out"] = out_;
      if (!csv_.empty()) out["csv"] = csv_;
      PrintJson(out);
    } else {
      std::cout << run.BriefReport();
    }
    return 0;
  }

 private:
  void ApplySpecimenOptions(experiment::RCurveOptions& o) const {
    if (!type_.empty()) {
      if (type_ == "ct" || type_ == "CT") o.specimen.type = SpecimenType::kCT;
      else if (type_ == "dcb" || type_ == "DCB") o.specimen.type = SpecimenType::kDCB;
      else
        throw Error(ErrorKind::kUsage, "unknown specimen type",
                    {.field = "--type", .value = type_, .expected = "ct or dcb"});
    }
    auto set = [](double& target, const std::string& text, const char* option) {
      const double v = ParseOptionQuantity(text, Dimension::Length(), option);
      if (std::isfinite(v)) target = v;
    };
    set(o.specimen.width, width_, "--width");
    set(o.specimen.height, height_, "--height");
    set(o.specimen.thickness, thickness_, "--thickness");
    set(o.specimen.length, length_, "--length");
    set(o.specimen.notch, notch_, "--notch");
    const double E = ParseOptionQuantity(modulus_, Dimension::Stress(), "--modulus");
    if (std::isfinite(E)) {
      if (o.material.orthotropic) o.material.E1 = E;
      else o.material.E = E;
    }
    if (std::isfinite(nu_)) o.material.nu = nu_;
    const double G13 = ParseOptionQuantity(g13_, Dimension::Stress(), "--g13");
    if (std::isfinite(G13)) o.material.G13 = G13;
    if (!plane_.empty()) {
      if (plane_ == "stress") o.specimen.plane = PlaneCondition::kPlaneStress;
      else if (plane_ == "strain") o.specimen.plane = PlaneCondition::kPlaneStrain;
      else
        throw Error(ErrorKind::kUsage, "unknown plane condition",
                    {.field = "--plane", .value = plane_, .expected = "stress or strain"});
    }
  }

  std::string record_, scene_, columns_, units_, out_, csv_, crack_from_;
  std::string type_, width_, height_, thickness_, length_, notch_, modulus_, g13_, plane_;
  std::string block_offset_, block_half_length_;
  bool large_displacement_ = false;
  double nu_ = NAN;
  double coverage_ = 2.0;
  RCurveFlags flags_;
  experiment::CleaningOptions cleaning_;
};

}  // namespace

std::unique_ptr<Command> MakeRcurveCommand() { return std::make_unique<RcurveCommand>(); }

}  // namespace bridgefit::cli
