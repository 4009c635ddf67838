#pragma once
// HDF5 cache of crack-plane models, keyed by geometry, material and
// resolution (CrackPlaneModel::key), so a fit pays for the finite-element
// solve once. Layout: group /crack_plane (docs/REDUCED.md).

#include <filesystem>
#include <memory>
#include <string>

#include "bridgefit/specimen/crack_plane.hpp"

namespace bridgefit::models {

// `inputs`: the scene and mesh values the model was built from (checked on a
// cache read, so a hash collision cannot return a wrong model).
void WriteCrackPlaneModel(const std::filesystem::path& path, const specimen::CrackPlaneModel& m,
                          const std::string& inputs = "");
// Throws Error when the file is not a crack-plane model.
specimen::CrackPlaneModel ReadCrackPlaneModel(const std::filesystem::path& path);

struct CacheOutcome {
  bool hit = false;
  std::filesystem::path file;  // empty when no cache directory was given
};

// Reads the model of `scene` from `cache_dir` when a file with the same key
// is there, else builds it and stores it (atomically). An empty `cache_dir`
// only builds.
// The inputs that define a crack-plane model (specimen, material, mesh with
// its defaults resolved) as text at `digits` significant digits: the cache
// file's key (9) and the in-memory model cache's (17).
std::string CrackPlaneInputs(const Scene& scene, const specimen::CrackPlaneOptions& mesh,
                             int digits);

std::shared_ptr<const specimen::CrackPlaneModel> LoadOrBuildCrackPlaneModel(
    const Scene& scene, const specimen::CrackPlaneOptions& mesh,
    const std::filesystem::path& cache_dir, CacheOutcome* outcome = nullptr);

}  // namespace bridgefit::models
