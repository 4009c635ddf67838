#include "fit_models.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/models/crack_plane_cache.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/mpm/growth.hpp"
#include "bridgefit/specimen/calibrations.hpp"
#include "bridgefit/specimen/crack_plane.hpp"

namespace bridgefit::pipeline {

Scene ScaledModuli(const Scene& scene, double factor) {
  Scene scaled = scene;
  for (double* modulus : {&scaled.material.E, &scaled.material.E1, &scaled.material.E2,
                          &scaled.material.G12, &scaled.material.G13})
    *modulus *= factor;
  return scaled;
}

inverse::SimulationForwardModel::Reducer ModelRecordReducer(const FitInput& input) {
  experiment::RCurveOptions options = input.reduction_options;
  // The data's compliance calibration, not the model record's own: a
  // calibration error of the data then cancels (RCurveOptions::given_*).
  // Issue 17, validation #269 (DCB, MBT, noise-free record at the model's
  // own size): the model record's own Delta put its R 3.3 J/m^2 above the
  // data's at the truth, and J_tip,c came out 872.5 for 876.3 J/m^2.
  if (input.reduction) {
    auto figure = [&](const char* name) {
      const auto it = input.reduction->figures.find(name);
      return it == input.reduction->figures.end() ? NAN : it->second;
    };
    if (options.method == experiment::RMethod::kMbt) options.given_mbt_delta = figure("mbt_delta_m");
    if (options.method == experiment::RMethod::kComplianceCalibration)
      options.given_cc_exponent = figure("cc_n");
  }
  options.load_noise = 1e-3;            // [N]: the model has none; small, not zero
  options.displacement_noise = 1e-9;    // [m]
  options.crack_length_noise = 1e-6;    // [m]
  options.smoothing_half_window = 0;
  return [options](const SimulationResult& sim) {
    constexpr int kLoading = 20;
    inverse::SimulationForwardModel::Reduced out;
    if (sim.points.size() < 2) return out;
    // The model's path as a record (core's RecordAlongPath), one growth row
    // per model point, rows numbered as time.
    const int points = static_cast<int>(sim.points.size());
    ExperimentRecord record = RecordAlongPath(sim, kLoading, points);
    record.source = "model record (" + sim.model + ")";
    for (std::size_t row = 0; row < record.size(); ++row) record.time.push_back(static_cast<double>(row));
    // The initiation point with its crack grown by 1 um, so the reduction
    // has a point at initiation (the data's first growth rows).
    record.crack_length[kLoading] += 1e-6;
    const experiment::RCurveResult r = experiment::ComputeRCurve(record, options);
    for (std::size_t i = 0; i < r.curve.size(); ++i) {
      out.crack_length.push_back(r.curve.crack_length[i]);
      out.R.push_back(r.curve.R[i]);
      out.point.push_back(std::max(0, r.rows[i] - kLoading));
    }
    return out;
  };
}

namespace {

// The crack length a record reaches at its largest displacement when its
// crack readings stop before it (a NaN tail, a camera that ran out): the
// measured growth per unit displacement over the last fifth of the measured
// displacement range, extrapolated (linearly: under displacement control the
// crack grows as a concave function of the displacement, so this errs long,
// the safe side for a model that must follow the record). NaN: no readings.
double CrackAtLastDisplacement(const ExperimentRecord& record) {
  std::vector<std::size_t> measured;
  double d_max = -INFINITY;
  for (std::size_t i = 0; i < record.size(); ++i) {
    if (!std::isfinite(record.displacement[i])) continue;
    d_max = std::max(d_max, record.displacement[i]);
    if (std::isfinite(record.crack_length[i])) measured.push_back(i);
  }
  if (measured.size() < 2) return NAN;
  double d_last = -INFINITY, d_first = INFINITY, a_last = -INFINITY;
  for (std::size_t i : measured) {
    d_first = std::min(d_first, record.displacement[i]);
    if (record.displacement[i] > d_last) d_last = record.displacement[i];
    a_last = std::max(a_last, record.crack_length[i]);
  }
  if (!(d_max > d_last)) return a_last;
  const double from = d_last - 0.2 * (d_last - d_first);
  double n = 0, sd = 0, sa = 0, sdd = 0, sda = 0;
  for (std::size_t i : measured) {
    const double d = record.displacement[i], a = record.crack_length[i];
    if (d < from) continue;
    n += 1, sd += d, sa += a, sdd += d * d, sda += d * a;
  }
  const double denominator = n * sdd - sd * sd;
  const double slope = n >= 2 && denominator > 0.0 ? (n * sda - sd * sa) / denominator : 0.0;
  return a_last + std::max(slope, 0.0) * (d_max - d_last);
}

// The longest crack the scene's specimen model takes at element size h: 0.95
// W (CT, the calibrations' range) or L - 2 h (DCB).
double ModelCrackLimit(const SpecimenSpec& specimen, double h) {
  return specimen.type == SpecimenType::kCT ? specimen::kCtMaxRelativeCrack * specimen.width
                                            : specimen.length - 2.0 * h;
}

}  // namespace

std::shared_ptr<const models::ReducedModel> ReducedModelCache::Get(
    const Scene& scene, const specimen::CrackPlaneOptions& mesh) {
  const std::string key = models::CrackPlaneInputs(scene, mesh, 17);
  std::lock_guard<std::mutex> lock(mutex_);
  auto& model = models_[key];
  if (!model) model = std::make_shared<const models::ReducedModel>(scene, mesh);
  return model;
}

FitModels::FitModels(const FitRequest& request, const FitInput& input,
                     const inverse::FitData& data, bool load_fit, inverse::RKind kind,
                     ReducedModelCache* cache)
    : request_(request), input_(input), kind_(kind), cache_(cache) {
  // The models must grow past the data: its crack lengths, and for a record
  // the measured ones (an equivalent crack length trails them).
  data_end_ = *std::max_element(data.crack_length.begin(), data.crack_length.end());
  if (input.record && input.record->has_crack_length()) {
    for (double a : input.record->crack_length)
      if (std::isfinite(a)) data_end_ = std::max(data_end_, a);
    // A load fit follows the record to its last row, crack readings or not
    // (issue 15: with the last 55 readings missing, a model that stopped at
    // the last reading failed for every law weaker than the data's, and the
    // fit settled on a tough law 40x above the clean record's chi^2).
    const double reached = CrackAtLastDisplacement(*input.record);
    if (load_fit && std::isfinite(reached)) data_end_ = std::max(data_end_, reached);
  }
  // A load-displacement fit follows the model to the record's last
  // displacement, which a tougher trial law reaches with a shorter crack and
  // a weaker one with a longer crack: a tenth of the growth beyond.
  if (load_fit) data_end_ += 0.1 * std::max(data_end_ - request.scene.specimen.notch, 0.0);
}

void FitModels::Build(double modulus_factor, double series_compliance) {
  const Scene model_scene = ScaledModuli(request_.scene, modulus_factor);
  const ModelChoice choice = request_.model;
  if (choice == ModelChoice::kAnalytic) {
    model_ = inverse::MakeAnalyticForwardModel(model_scene);
    return;
  }
  modulus_factor_ = modulus_factor;
  series_compliance_ = series_compliance;
  if (choice != ModelChoice::kMpm) {
    resolution_ = std::isfinite(request_.resolution)
                      ? request_.resolution
                      : specimen::DefaultResolution(model_scene.specimen);
    model_ = MakeReduced(model_scene, resolution_, 2e-3, request_.far_field);
  }
  if (choice == ModelChoice::kMpm || choice == ModelChoice::kAuto) {
    const double cell = std::isfinite(request_.mpm_cell)
                            ? request_.mpm_cell
                            : CoarsestMpmCell(request_.scene.specimen, data_end_);
    auto accurate = MpmAt(cell);
    if (choice == ModelChoice::kMpm) model_ = std::move(accurate);
    else accurate_ = std::move(accurate);
    mpm_cell_ = cell;
  }
}

void FitModels::UseMpmCell(double cell) {
  accurate_ = MpmAt(cell);
  mpm_cell_ = cell;
}

std::unique_ptr<inverse::ForwardModel> FitModels::MpmAt(double cell) const {
  const Scene model_scene = ScaledModuli(request_.scene, modulus_factor_);
  mpm::GrowthOptions growth;
  growth.cell = cell;
  growth.max_crack_length = data_end_ + 2.0 * growth.cell;
  std::string why;
  if (!growth.IsValid(&why))
    throw Error(ErrorKind::kUsage, "invalid MPM options: " + why, {.field = "--mpm-cell"});
  auto mpm = std::make_unique<inverse::SimulationForwardModel>(
      "mpm", [model_scene, growth](const laws::BridgingLaw* law, double J_tip_c) {
        return mpm::SimulateGrowth(model_scene, law, J_tip_c, growth).result;
      });
  if (kind_ == inverse::RKind::kAsData) mpm->SetReducer(ModelRecordReducer(input_));
  mpm->SetSeriesCompliance(series_compliance_);
  return mpm;
}

std::unique_ptr<inverse::SimulationForwardModel> FitModels::MakeReduced(
    const Scene& scene, double resolution, double margin, double far_field) const {
  models::ReducedOptions reduced;
  reduced.mesh.resolution = resolution;
  reduced.mesh.coarse_factor = far_field;
  // Past the data, but inside what the specimen's model takes (a record's
  // crack near the back edge, or one extrapolated past it).
  reduced.mesh.max_crack_length =
      std::max(std::min(data_end_ + margin, ModelCrackLimit(scene.specimen, resolution)),
               scene.run.max_crack_length.value_or(0.0));
  // Shared only with the request's own moduli: a compliance calibration
  // tries many modulus factors, each once.
  auto simulation = cache_ && modulus_factor_ == 1.0
                        ? inverse::MakeReducedForwardModel(cache_->Get(scene, reduced.mesh), reduced)
                        : inverse::MakeReducedForwardModel(scene, reduced);
  if (kind_ == inverse::RKind::kAsData)
    simulation->SetReducer(ModelRecordReducer(input_));
  simulation->SetSeriesCompliance(series_compliance_);
  return simulation;
}

std::unique_ptr<inverse::ForwardModel> FitModels::ReducedAt(double resolution,
                                                           double far_field) const {
  // --model auto: its reduced model (the MPM check is accurate()).
  if (request_.model != ModelChoice::kReduced && request_.model != ModelChoice::kAuto)
    return nullptr;
  const Scene scene = ScaledModuli(request_.scene, modulus_factor_);
  // Past the data by two elements (a coarse mesh's last node rounds down by
  // up to one element), else by the fine model's 2 mm.
  for (double margin : {std::max(2e-3, 2.0 * resolution), 2e-3}) {
    try {
      return MakeReduced(scene, resolution, margin, far_field > 0.0 ? far_field : request_.far_field);
    } catch (const Error&) {
    }
  }
  return nullptr;  // the geometry does not take this element size
}

}  // namespace bridgefit::pipeline
