#include "bridgefit/scene/scene.hpp"

#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"

namespace bridgefit {
namespace {

void RequirePositive(const std::string& file, const char* field, double value, const char* unit,
                     double unit_scale) {
  if (!(std::isfinite(value) && value > 0.0))
    throw Error(ErrorKind::kInput, "must be positive",
                {.file = file, .field = field,
                 .value = fmt::format("{:g} {}", value / unit_scale, unit),
                 .expected = fmt::format("a value > 0 {}", unit)});
}

}  // namespace

void Scene::Validate() const {
  const SpecimenSpec& s = specimen;
  if (s.type == SpecimenType::kCT) {
    RequirePositive(source, "specimen.width", s.width, "mm", 1e-3);
    RequirePositive(source, "specimen.height", s.height, "mm", 1e-3);
    RequirePositive(source, "specimen.thickness", s.thickness, "mm", 1e-3);
    RequirePositive(source, "specimen.notch", s.notch, "mm", 1e-3);
    if (s.notch >= s.width)
      throw Error(ErrorKind::kInput, "the notch must end before the back edge",
                  {.file = source, .field = "specimen.notch",
                   .value = fmt::format("{:g} mm", s.notch * 1e3),
                   .expected = fmt::format("a0 < W = {:g} mm", s.width * 1e3)});
  } else {
    RequirePositive(source, "specimen.width", s.width, "mm", 1e-3);
    RequirePositive(source, "specimen.height", s.height, "mm", 1e-3);
    RequirePositive(source, "specimen.length", s.length, "mm", 1e-3);
    RequirePositive(source, "specimen.notch", s.notch, "mm", 1e-3);
    if (s.notch >= s.length)
      throw Error(ErrorKind::kInput, "the notch must be shorter than the specimen",
                  {.file = source, .field = "specimen.notch",
                   .value = fmt::format("{:g} mm", s.notch * 1e3),
                   .expected = fmt::format("a0 < L = {:g} mm", s.length * 1e3)});
  }
  const MaterialSpec& m = material;
  if (m.orthotropic) {
    RequirePositive(source, "material.E1", m.E1, "GPa", 1e9);
    RequirePositive(source, "material.E2", m.E2, "GPa", 1e9);
    RequirePositive(source, "material.G12", m.G12, "GPa", 1e9);
    // Positive-definite compliance: nu12^2 < E1 / E2.
    if (!(m.nu12 * m.nu12 < m.E1 / m.E2))
      throw Error(ErrorKind::kInput, "the orthotropic constants are not positive definite",
                  {.file = source, .field = "material.nu12", .value = fmt::format("{:g}", m.nu12),
                   .expected = fmt::format("|nu12| < sqrt(E1/E2) = {:g}", std::sqrt(m.E1 / m.E2))});
  } else {
    RequirePositive(source, "material.E", m.E, "GPa", 1e9);
    if (!(m.nu > -1.0 && m.nu < 0.5))
      throw Error(ErrorKind::kInput, "Poisson's ratio out of range",
                  {.file = source, .field = "material.nu", .value = fmt::format("{:g}", m.nu),
                   .expected = "-1 < nu < 0.5"});
  }
  if (!(m.density >= 0.0))
    throw Error(ErrorKind::kInput, "density must not be negative",
                {.file = source, .field = "material.density",
                 .value = fmt::format("{:g} kg/m^3", m.density)});
  if (fracture) RequirePositive(source, "fracture.J_tip_c", fracture->J_tip_c, "J/m^2", 1.0);
  if (bridging) {
    RequirePositive(source, "bridging.sigma_c", bridging->scales.sigma_c, "MPa", 1e6);
    RequirePositive(source, "bridging.delta_c", bridging->scales.delta_c, "mm", 1e-3);
    RequirePositive(source, "bridging.J_B", bridging->scales.J_B, "J/m^2", 1.0);
  }
  if (run.max_crack_length) {
    const double limit = s.type == SpecimenType::kCT ? s.width : s.length;
    if (!(*run.max_crack_length > s.notch && *run.max_crack_length < limit))
      throw Error(ErrorKind::kInput, "max_crack_length must lie between the notch and the end",
                  {.file = source, .field = "run.max_crack_length",
                   .value = fmt::format("{:g} mm", *run.max_crack_length * 1e3),
                   .expected = fmt::format("{:g} mm < a < {:g} mm", s.notch * 1e3, limit * 1e3)});
  }
  if (run.load_point_displacement)
    RequirePositive(source, "run.load_point_displacement", *run.load_point_displacement, "mm",
                    1e-3);
}

}  // namespace bridgefit
