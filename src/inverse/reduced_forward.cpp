#include "bridgefit/inverse/reduced_forward.hpp"

#include "bridgefit/specimen/calibrations.hpp"

namespace bridgefit::inverse {

std::unique_ptr<SimulationForwardModel> MakeReducedForwardModel(
    const Scene& scene, const models::ReducedOptions& options) {
  return MakeReducedForwardModel(std::make_shared<const models::ReducedModel>(scene, options.mesh),
                                 options);
}

std::unique_ptr<SimulationForwardModel> MakeReducedForwardModel(
    std::shared_ptr<const models::ReducedModel> model, const models::ReducedOptions& options) {
  return std::make_unique<SimulationForwardModel>(
      "reduced", [model, options](const laws::BridgingLaw* law, double J_tip_c) {
        return model->Run(law, J_tip_c, options);
      });
}

std::unique_ptr<AnalyticForwardModel> MakeAnalyticForwardModel(const Scene& scene) {
  return std::make_unique<AnalyticForwardModel>(
      specimen::EffectiveModulus(scene.material, scene.specimen.plane), scene.specimen.notch);
}

}  // namespace bridgefit::inverse
