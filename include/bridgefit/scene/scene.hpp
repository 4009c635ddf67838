#pragma once
// A test scene: specimen, material, fracture, bridging law and run limits.
// Plain value types in SI units; read from TOML by io::ReadSceneFile.

#include <optional>
#include <string>

#include "bridgefit/laws/law.hpp"

namespace bridgefit {

enum class SpecimenType { kCT, kDCB };
enum class PlaneCondition { kPlaneStress, kPlaneStrain };

struct SpecimenSpec {
  SpecimenType type = SpecimenType::kCT;
  // CT: W, load line to back edge. DCB: b, the specimen width (out of plane).
  double width = 0.0;
  // CT: total height (default 1.2 W). DCB: h, the thickness of one arm.
  double height = 0.0;
  // CT: B, the out-of-plane thickness. DCB: unused (b is `width`).
  double thickness = 0.0;
  // DCB: total length L. CT: unused (total width is 1.25 W).
  double length = 0.0;
  // a0: initial crack length measured from the load line.
  double notch = 0.0;
  PlaneCondition plane = PlaneCondition::kPlaneStress;

  // Out-of-plane thickness carried by the crack front: B (CT) or b (DCB).
  double CrackFrontWidth() const { return type == SpecimenType::kCT ? thickness : width; }
};

struct MaterialSpec {
  bool orthotropic = false;
  double E = 0.0;    // isotropic Young's modulus [Pa]
  double nu = 0.0;   // isotropic Poisson's ratio
  double E1 = 0.0;   // orthotropic: along the crack (x) [Pa]
  double E2 = 0.0;   // orthotropic: across the crack (y) [Pa]
  double G12 = 0.0;  // in-plane shear modulus [Pa]
  double nu12 = 0.0;
  double G13 = 0.0;  // transverse shear modulus, DCB beam theory [Pa] (0: use G12)
  double angle = 0.0;  // material axis 1 from the crack direction [rad]
  double density = 0.0;  // [kg/m^3]

  // Modulus along the crack direction (E, or E1).
  double AxialModulus() const { return orthotropic ? E1 : E; }
};

struct FractureSpec {
  double J_tip_c = 0.0;  // crack-tip toughness [J/m^2]
};

struct BridgingSpec {
  laws::LawShape shape;
  laws::LawScales scales;  // completed: all three of sigma_c, delta_c, J_B
  std::string table_file;  // for law = "table": the CSV it came from

  laws::BridgingLaw Law() const { return {&shape, scales.sigma_c, scales.delta_c}; }
};

struct RunSpec {
  std::optional<double> max_crack_length;  // [m], from the load line
  bool grow = true;                        // crack growth when [fracture] is present
  std::optional<double> load_point_displacement;  // target for stationary runs [m]
};

struct Scene {
  std::string source;  // file it was read from (for messages)
  SpecimenSpec specimen;
  MaterialSpec material;
  std::optional<FractureSpec> fracture;
  std::optional<BridgingSpec> bridging;
  RunSpec run;

  // Physical checks (positive sizes, notch inside the valid range, ...).
  // Throws Error naming the scene file and the field.
  void Validate() const;
};

}  // namespace bridgefit
