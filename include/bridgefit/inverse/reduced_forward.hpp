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

}  // namespace bridgefit::inverse
