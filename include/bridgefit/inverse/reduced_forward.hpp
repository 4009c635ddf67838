#pragma once
// The reduced forward model behind the fit's ForwardModel interface (the app,
// tests and benches all fit with it).

#include <memory>

#include "bridgefit/inverse/forward_model.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/scene/scene.hpp"

namespace bridgefit::inverse {

// Builds the scene's crack-plane model at options.mesh (throws Error on bad
// input) and wraps ReducedModel::Run with `options` as a model named "reduced".
std::unique_ptr<SimulationForwardModel> MakeReducedForwardModel(
    const Scene& scene, const models::ReducedOptions& options);
// The same around a model already built (options.mesh is not used).
std::unique_ptr<SimulationForwardModel> MakeReducedForwardModel(
    std::shared_ptr<const models::ReducedModel> model, const models::ReducedOptions& options);

// The analytic model of a scene: E' = specimen::EffectiveModulus (the one
// effective modulus the reduced model, synth and the R-curve reductions use;
// Sih-Paris-Irwin for an orthotropic material), a0 = the notch.
std::unique_ptr<AnalyticForwardModel> MakeAnalyticForwardModel(const Scene& scene);

}  // namespace bridgefit::inverse
