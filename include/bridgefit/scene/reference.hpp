#pragma once
// The reference compact-tension scene of the issues (PHYSICS 6): CT with
// W = 100 mm, H = 120 mm, B = 12.7 mm, a0 = 30 mm, plane stress, E = 3 GPa,
// nu = 0.3, MDF density 609 kg/m^3, J_tip,c = 2210 J/m^2, no bridging. Tests
// and benches build on it instead of spelling it out again.

#include "bridgefit/scene/scene.hpp"

namespace bridgefit {

Scene ReferenceCtScene(double notch = 0.030);

// Adds a linear-softening law with sigma_c [Pa] and J_B [J/m^2]
// (delta_c = 2 J_B / sigma_c).
void AddLinearBridging(Scene& scene, double sigma_c, double J_B);

}  // namespace bridgefit
