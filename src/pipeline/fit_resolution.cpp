// --resolution auto: the reduced model's element size chosen from the
// predicted parameter bias (issue 17; include/bridgefit/inverse/resolution.hpp),
// and the fit at that size: halved where the law is not resolved there, or
// where the answer's own model error shows in the data.

#include <algorithm>
#include <cmath>
#include <exception>
#include <map>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
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

// The fit at the size --resolution auto chose. Where the law is refused as
// unresolved at that size (it reaches steady state within a few of the
// model's crack-length steps: every forward run of the fit, or of the
// compliance calibration's, failed so; validation #241, a CT whose law
// does it in 2.8 mm, at 0.695 mm elements), the size is halved, down to
// half the ladder's finest. Returns the sizes given up, for the choice's
// reason ("" for none); a refusal that halving cannot mend is rethrown.
std::string FitAtChosenSize(FitRequest& request, const FitRun& chosen, FitRun& run) {
  std::string given_up;
  while (true) {
    std::string why;
    std::exception_ptr thrown;
    try {
      FitAtResolution(request, run);
      if (!std::isnan(run.summary.best_parameters[inverse::kJTipC]))
        return given_up;  // a fit with an optimum (NaN: every forward run failed)
      why = run.summary.stop_reason;
    } catch (const Error& e) {
      why = e.what();
      thrown = std::current_exception();
    }
    const bool unresolved = why.find(inverse::kNotResolvedAtThisResolution) != std::string::npos;
    const bool can_halve =
        chosen.resolution_choice &&
        0.5 * request.resolution >= 0.5 * chosen.resolution_choice->finest * (1.0 - 1e-9);
    if (!unresolved || !can_halve) {
      if (thrown) std::rethrow_exception(thrown);
      return given_up;
    }
    given_up += fmt::format("{}{:.3g} mm", given_up.empty() ? "" : ", ", request.resolution * 1e3);
    request.resolution /= 2.0;
    run = chosen;
  }
}

// --resolution auto chose the size at the pilot's parameters; where the
// answer's own model error is visible in the data (the warning), or the
// model does not follow a run of R points (FitSummary::misfit: a rise
// shorter than its elements), the fit is repeated at half the size, down
// to half the ladder's finest (one rung beyond it: the ladder halves from
// its coarsest, so its last rung may sit up to twice above the finest).
void RefineWhereTheErrorShows(FitRequest& request, const FitRun& chosen, FitRun& run) {
  // The reason for the next halving, empty for none.
  const auto why_refine = [&]() -> std::string {
    const double h = request.resolution, floor = 0.5 * run.resolution_choice->finest;
    const bool biased = !run.model_error.warning.empty();
    const bool misfit = run.summary.misfit.points > 0;
    if ((!biased && !misfit) || 0.5 * h < floor * (1.0 - 1e-9)) return "";
    return misfit ? fmt::format("{:.3g} mm ({} R points in runs off the model)", h * 1e3,
                                run.summary.misfit.points)
                  : fmt::format("{:.3g} mm (predicted data bias {:.2g} noise sd rms)", h * 1e3,
                                run.model_error.output_bias_noise_rms);
  };
  double spent_s = 0.0;
  int spent_runs = 0;
  std::string refined, failed;
  while (run.resolution_choice) {
    const std::string why = why_refine();
    if (why.empty()) break;
    // Each attempt's summary holds the choice's own time once.
    spent_s += run.summary.wall_s - run.resolution_choice->wall_s;
    spent_runs += run.summary.evaluations - run.resolution_choice->runs;
    refined += (refined.empty() ? "" : ", ") + why;
    FitRequest finer = request;
    finer.resolution /= 2.0;
    FitRun attempt = chosen;
    const std::array<double, inverse::kParameterCount> answer = run.summary.best_parameters;
    try {
      FitAtResolution(finer, attempt, &answer);
    } catch (const Error& e) {  // the coarser fit stands, with its warning
      failed = fmt::format("; the fit at {:.3g} mm failed ({}): the {:.3g} mm fit is kept",
                           finer.resolution * 1e3, e.what(), request.resolution * 1e3);
      spent_s -= run.summary.wall_s - run.resolution_choice->wall_s;
      spent_runs -= run.summary.evaluations - run.resolution_choice->runs;
      break;
    }
    request = std::move(finer);
    run = std::move(attempt);
  }
  if (!refined.empty()) {
    run.resolution_choice->reason +=
        fmt::format("; after the fit the model's error showed in the data at {}", refined) +
        (failed.empty() ? fmt::format(": refined to {:.3g} mm", request.resolution * 1e3) : failed);
    run.summary.wall_s += spent_s;
    run.summary.evaluations += spent_runs;
  }
}

}  // namespace bridgefit::pipeline
