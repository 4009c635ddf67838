#include "bridgefit/models/crack_plane_cache.hpp"

#include <functional>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/io/hdf5.hpp"

namespace bridgefit::models {

namespace {
constexpr const char* kGroup = "/crack_plane";
}

void WriteCrackPlaneModel(const std::filesystem::path& path, const specimen::CrackPlaneModel& m,
                          const std::string& inputs) {
  io::H5Writer file(path);
  const std::string g = kGroup;
  file.WriteAttribute(g, "kind", "crack_plane_model");
  file.WriteAttribute(g, "inputs", inputs);
  file.WriteAttribute(g, "key", m.key);
  file.WriteAttribute(g, "load_kind", m.load_kind);
  file.WriteAttribute(g, "resolution_m", m.resolution);
  file.WriteAttribute(g, "notch_m", m.notch);
  file.WriteAttribute(g, "thickness_m", m.thickness);
  file.WriteAttribute(g, "effective_modulus_Pa", m.effective_modulus);
  file.WriteAttribute(g, "load_compliance_m2_per_N", m.load_compliance);
  file.WriteAttribute(g, "mouth_compliance_m2_per_N", m.mouth_compliance);
  file.WriteAttribute(g, "gauge_compliance_m2_per_N", m.gauge_compliance);
  file.WriteAttribute(g, "gauge_x_m", m.gauge_x);
  file.WriteAttribute(g, "elements", m.elements);
  file.WriteAttribute(g, "dofs", m.dofs);
  file.WriteAttribute(g, "build_s", m.build_s);
  const size_t n = m.node_x.size();
  file.WriteVector(g + "/node_x", m.node_x, "m", "retained crack-plane node positions");
  file.WriteMatrix(g + "/stiffness", n, n, m.stiffness, "N/m^2",
                   "condensed stiffness per unit thickness (symmetric)");
  file.WriteVector(g + "/load", m.load, "1", "nodal force per unit load p = P/B");
  file.WriteVector(g + "/load_coupling", m.load_coupling, "1", "Delta = c0 p + q.u");
  file.WriteVector(g + "/mouth_coupling", m.mouth_coupling, "1", "u_mouth = m0 p + qm.u");
  file.WriteVector(g + "/gauge_coupling", m.gauge_coupling, "1", "u_gauge = gc p + qg.u");
  file.Commit();
}

specimen::CrackPlaneModel ReadCrackPlaneModel(const std::filesystem::path& path) {
  io::H5Reader file(path);
  const std::string g = kGroup;
  if (!file.Exists(g) || file.ReadStringAttribute(g, "kind") != "crack_plane_model")
    throw Error(ErrorKind::kInput, "not a crack-plane model file",
                {.file = path.string(), .field = g});
  specimen::CrackPlaneModel m;
  m.key = file.ReadStringAttribute(g, "key");
  m.load_kind = file.ReadStringAttribute(g, "load_kind");
  m.resolution = file.ReadNumberAttribute(g, "resolution_m");
  m.notch = file.ReadNumberAttribute(g, "notch_m");
  m.thickness = file.ReadNumberAttribute(g, "thickness_m");
  m.effective_modulus = file.ReadNumberAttribute(g, "effective_modulus_Pa");
  m.load_compliance = file.ReadNumberAttribute(g, "load_compliance_m2_per_N");
  m.mouth_compliance = file.ReadNumberAttribute(g, "mouth_compliance_m2_per_N");
  m.gauge_compliance = file.ReadNumberAttribute(g, "gauge_compliance_m2_per_N");
  m.gauge_x = file.ReadNumberAttribute(g, "gauge_x_m");
  m.elements = static_cast<int>(file.ReadIntegerAttribute(g, "elements", 0, 1 << 30));
  m.dofs = static_cast<int>(file.ReadIntegerAttribute(g, "dofs", 0, 1 << 30));
  m.build_s = file.ReadNumberAttribute(g, "build_s");
  m.node_x = file.ReadVector(g + "/node_x");
  m.stiffness = file.ReadVector(g + "/stiffness");
  m.load = file.ReadVector(g + "/load");
  m.load_coupling = file.ReadVector(g + "/load_coupling");
  m.mouth_coupling = file.ReadVector(g + "/mouth_coupling");
  m.gauge_coupling = file.ReadVector(g + "/gauge_coupling");
  const size_t n = m.node_x.size();
  if (n < 3 || m.stiffness.size() != n * n || m.load.size() != n || m.load_coupling.size() != n ||
      m.mouth_coupling.size() != n || m.gauge_coupling.size() != n)
    throw Error(ErrorKind::kInput, "crack-plane model datasets have inconsistent sizes",
                {.file = path.string(), .field = g});
  return m;
}

std::string CrackPlaneInputs(const Scene& scene, const specimen::CrackPlaneOptions& mesh,
                             int digits) {
  const SpecimenSpec& s = scene.specimen;
  const MaterialSpec& m = scene.material;
  const auto g = [digits](double v) { return fmt::format("{:.{}g}", v, digits); };
  return fmt::format(
      "{} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {}", static_cast<int>(s.type),
      static_cast<int>(s.plane), g(s.width), g(s.height), g(s.thickness), g(s.length), g(s.notch),
      m.orthotropic, g(m.angle), g(m.E), g(m.nu), g(m.E1), g(m.E2), g(m.G12), g(m.nu12),
      g(mesh.resolution > 0 ? mesh.resolution : specimen::DefaultResolution(s)),
      g(mesh.max_crack_length > 0 ? mesh.max_crack_length : specimen::DefaultMaxCrackLength(scene)),
      g(mesh.grading), g(mesh.coarse_factor));
}

std::shared_ptr<const specimen::CrackPlaneModel> LoadOrBuildCrackPlaneModel(
    const Scene& scene, const specimen::CrackPlaneOptions& mesh,
    const std::filesystem::path& cache_dir, CacheOutcome* outcome) {
  if (outcome) *outcome = {};
  if (cache_dir.empty())
    return std::make_shared<const specimen::CrackPlaneModel>(
        specimen::BuildCrackPlaneModel(scene, mesh));
  // The key needs the mesh; building the key alone is cheap only after the
  // model, so the file name hashes the inputs that define the key.
  const std::string inputs = CrackPlaneInputs(scene, mesh, 9);
  const std::filesystem::path file =
      cache_dir / fmt::format("crack_plane_{:016x}.h5", std::hash<std::string>{}(inputs));
  if (outcome) outcome->file = file;
  if (std::filesystem::exists(file)) {
    try {
      auto cached = std::make_shared<specimen::CrackPlaneModel>(ReadCrackPlaneModel(file));
      if (io::H5Reader(file).ReadStringAttribute(kGroup, "inputs") == inputs) {
        if (outcome) outcome->hit = true;
        return cached;
      }
    } catch (const Error&) {
      // An unreadable cache entry is rebuilt and overwritten below.
    }
  }
  auto built = std::make_shared<specimen::CrackPlaneModel>(specimen::BuildCrackPlaneModel(scene, mesh));
  std::filesystem::create_directories(cache_dir);
  WriteCrackPlaneModel(file, *built, inputs);
  return built;
}

}  // namespace bridgefit::models
