// --resolution auto: the reduced model's element size chosen from the
// predicted parameter bias (issue 17; include/bridgefit/inverse/resolution.hpp).

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "bridgefit/core/progress.hpp"
#include "bridgefit/specimen/crack_plane.hpp"
#include "fit_models.hpp"

namespace bridgefit::pipeline {
namespace {

// The model's validity limits on the element size: a CT needs W/50 (the
// pin hole and ligament resolved); a DCB arm at least 4 square elements
// through its thickness; both at least 10 elements over the data's growth.
double CoarsestResolution(const Scene& scene, double growth) {
  const SpecimenSpec& s = scene.specimen;
  const double geometry = s.type == SpecimenType::kCT ? s.width / 50.0 : s.height / 4.0;
  return growth > 0.0 ? std::min(geometry, growth / 10.0) : geometry;
}

}  // namespace

void ChooseAutoResolution(FitRequest& request, const laws::LawShape& shape, FitRun& run) {
  if (std::isfinite(request.resolution) || request.model != ModelChoice::kReduced) return;
  const Stopwatch clock;
  const double a_end = *std::max_element(run.data.crack_length.begin(), run.data.crack_length.end());
  inverse::ResolutionOptions options;
  options.bias_fraction = request.resolution_bias_fraction;
  options.coarsest = CoarsestResolution(request.scene, a_end - request.scene.specimen.notch);
  // The finest tried: the model's former default (CT W/200, DCB
  // min(h/4, L/400)), below which a fit costs seconds.
  options.finest = std::min(specimen::DefaultResolution(request.scene.specimen), options.coarsest);

  // A quick pilot fit (no profiles) at the coarsest size.
  FitRequest coarse = request;
  coarse.resolution = options.coarsest;
  FitModels models(coarse, run.input, run.data, run.load_data.has_value(), run.r_kind,
                   run.reduced_models.get());
  models.Build(1.0, 0.0);
  inverse::FitOptions quick = request.fit;
  quick.profile_likelihood = false;
  quick.progress = false;
  inverse::FitSummary pilot;
  if (run.load_data) {
    StartFromRCurveFit(models.model(), shape, run.data, quick);
    pilot = inverse::FitBridgingLaw(models.model(), shape, *run.load_data, quick);
  } else {
    pilot = inverse::FitBridgingLaw(models.model(), shape, run.data, quick);
  }
  std::map<double, std::unique_ptr<inverse::ForwardModel>> cache;
  const inverse::ModelAtResolution model_at = [&](double h) {
    std::unique_ptr<inverse::ForwardModel>& model = cache[h];
    if (!model) model = models.ReducedAt(h);
    return model.get();
  };
  inverse::ResolutionChoice choice;
  if (pilot.converged) {
    choice = inverse::ChooseResolution(model_at, shape, run.load_data ? *run.load_data : run.data,
                                       quick, pilot, options);
  } else {
    choice.resolution = options.finest;
    choice.reason = "the pilot fit at the coarsest size did not converge: the finest size taken";
  }
  choice.wall_s = clock.Seconds();
  choice.finest = options.finest;
  request.resolution = choice.resolution;
  run.resolution_choice = std::move(choice);
}

}  // namespace bridgefit::pipeline
