#pragma once
// `--resolution auto` (issue 17): the coarsest element size of the reduced
// model whose predicted parameter bias is below a stated fraction of each
// parameter's statistical uncertainty, within the model's validity limits.
//
// A ladder h_k = coarsest / 2^k (k = 0, 1, ... down to `finest`). A quick
// pilot fit gives the parameters; at each size the fit is re-run locally
// from them (BOBYQA, no profiles) and the estimates p(h) give, from three
// successive sizes, Richardson's bias at h exactly as the model error does
// (model_error.hpp: order at most the model's asymptotic 1, F_s 3 where the
// order is not observed). The first size at which every identified
// parameter's |bias| <= fraction x its statistical standard uncertainty
// (Jacobian) and whose predicted bias of the data (R or load, the coarser
// model's prediction at the same parameters against this one's) is at most
// kOutputBiasNoiseLimit noise standard deviations rms wins; the finest is
// taken, with the reason, when none does. The second condition catches a
// model that cannot follow the data at all (a zone shorter than a few
// elements): its estimates can agree between sizes while the verdict
// (bridging detected) is wrong at every one of them.

#include <functional>
#include <string>
#include <vector>

#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/inverse/model_error.hpp"

namespace bridgefit::inverse {

struct ResolutionOptions {
  double bias_fraction = 0.3;  // of each parameter's statistical standard uncertainty
  double coarsest = NAN;       // [m], the model's validity limit (required)
  double finest = NAN;         // [m], the finest size tried (required)
  ModelErrorOptions error;     // refinement ratio (the ladder's), orders, safety factors
  bool IsValid(std::string* why) const;
};

struct ResolutionLevel {
  double resolution = NAN;  // [m]
  bool evaluated = false;   // the model ran and the local fit converged
  std::array<double, kParameterCount> estimate = {NAN, NAN, NAN};  // local refit (SI)
  std::array<double, kParameterCount> bias = {NAN, NAN, NAN};      // predicted at this size
  std::array<double, kParameterCount> sd = {NAN, NAN, NAN};        // statistical, Jacobian
  ModelErrorStatus status = ModelErrorStatus::kNotEstimated;
  double output_bias_noise_rms = NAN;  // the prediction's bias at the data, noise sd rms
  bool meets = false;
  std::string note;
};

struct ResolutionChoice {
  double resolution = NAN;  // [m], the chosen element size
  double finest = NAN;      // [m], the finest size the ladder allows
  bool criterion_met = false;
  std::string reason;       // a sentence: why this size
  std::vector<ResolutionLevel> levels;  // every size evaluated, coarse to fine
  int runs = 0;
  double wall_s = 0.0;
};

// A model at element size h [m], or null where the geometry does not take
// it; the caller owns (and may cache) the models.
using ModelAtResolution = std::function<const ForwardModel*(double resolution)>;

// Chooses the element size for fitting `shape` to `data` from the pilot fit
// `pilot` (any converged fit of the same data, e.g. at the coarsest size).
// Never throws for failed runs (they end the ladder with a reason).
ResolutionChoice ChooseResolution(const ModelAtResolution& model_at, const laws::LawShape& shape,
                                  const FitData& data, const FitOptions& options,
                                  const FitSummary& pilot, const ResolutionOptions& resolution);

}  // namespace bridgefit::inverse
