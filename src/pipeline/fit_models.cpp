#include "fit_models.hpp"

#include <algorithm>
#include <cmath>

#include "bridgefit/core/error.hpp"
#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/mpm/growth.hpp"
#include "bridgefit/specimen/crack_plane.hpp"

namespace bridgefit::pipeline {

Scene ScaledModuli(const Scene& scene, double factor) {
  Scene scaled = scene;
  for (double* modulus : {&scaled.material.E, &scaled.material.E1, &scaled.material.E2,
                          &scaled.material.G12, &scaled.material.G13})
    *modulus *= factor;
  return scaled;
}

inverse::SimulationForwardModel::Reducer ModelRecordReducer(
    const experiment::RCurveOptions& data_options) {
  experiment::RCurveOptions options = data_options;
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

FitModels::FitModels(const FitRequest& request, const FitInput& input,
                     const inverse::FitData& data, bool load_fit, inverse::RKind kind)
    : request_(request), input_(input), kind_(kind) {
  // The models must grow past the data: its crack lengths, and for a record
  // the measured ones (an equivalent crack length trails them).
  data_end_ = *std::max_element(data.crack_length.begin(), data.crack_length.end());
  if (input.record && input.record->has_crack_length())
    for (double a : input.record->crack_length)
      if (std::isfinite(a)) data_end_ = std::max(data_end_, a);
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
    model_ = MakeReduced(model_scene, resolution_, 2e-3);
  }
  if (choice == ModelChoice::kMpm || choice == ModelChoice::kAuto) {
    mpm::GrowthOptions growth;
    growth.cell = request_.mpm_cell;
    growth.max_crack_length = data_end_ + 2.0 * growth.cell;
    std::string why;
    if (!growth.IsValid(&why))
      throw Error(ErrorKind::kUsage, "invalid MPM options: " + why, {.field = "--mpm-cell"});
    auto accurate = std::make_unique<inverse::SimulationForwardModel>(
        "mpm", [model_scene, growth](const laws::BridgingLaw* law, double J_tip_c) {
          return mpm::SimulateGrowth(model_scene, law, J_tip_c, growth).result;
        });
    if (kind_ == inverse::RKind::kAsData)
      accurate->SetReducer(ModelRecordReducer(input_.reduction_options));
    accurate->SetSeriesCompliance(series_compliance);
    if (choice == ModelChoice::kMpm) model_ = std::move(accurate);
    else accurate_ = std::move(accurate);
    mpm_cell_ = growth.cell;
  }
}

std::unique_ptr<inverse::SimulationForwardModel> FitModels::MakeReduced(const Scene& scene,
                                                                        double resolution,
                                                                        double margin) const {
  models::ReducedOptions reduced;
  reduced.mesh.resolution = resolution;
  reduced.mesh.max_crack_length =
      std::max(data_end_ + margin, scene.run.max_crack_length.value_or(0.0));
  auto simulation = inverse::MakeReducedForwardModel(scene, reduced);
  if (kind_ == inverse::RKind::kAsData)
    simulation->SetReducer(ModelRecordReducer(input_.reduction_options));
  simulation->SetSeriesCompliance(series_compliance_);
  return simulation;
}

std::unique_ptr<inverse::ForwardModel> FitModels::ReducedAt(double resolution) const {
  if (request_.model != ModelChoice::kReduced) return nullptr;
  const Scene scene = ScaledModuli(request_.scene, modulus_factor_);
  // Past the data by two elements (a coarse mesh's last node rounds down by
  // up to one element), else by the fine model's 2 mm.
  for (double margin : {std::max(2e-3, 2.0 * resolution), 2e-3}) {
    try {
      return MakeReduced(scene, resolution, margin);
    } catch (const Error&) {
    }
  }
  return nullptr;  // the geometry does not take this element size
}

}  // namespace bridgefit::pipeline
