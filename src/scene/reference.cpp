#include "bridgefit/scene/reference.hpp"

namespace bridgefit {

Scene ReferenceCtScene(double notch) {
  Scene s;
  s.source = "reference CT scene";
  s.specimen.type = SpecimenType::kCT;
  s.specimen.width = 0.100;
  s.specimen.height = 0.120;
  s.specimen.thickness = 0.0127;
  s.specimen.notch = notch;
  s.specimen.plane = PlaneCondition::kPlaneStress;
  s.material.E = 3e9;
  s.material.nu = 0.3;
  s.material.density = 609.0;
  s.fracture = FractureSpec{2210.0};
  return s;
}

void AddLinearBridging(Scene& scene, double sigma_c, double J_B) {
  scene.bridging = BridgingSpec{laws::MakeLinearShape(), {sigma_c, 2.0 * J_B / sigma_c, J_B}, ""};
}

}  // namespace bridgefit
