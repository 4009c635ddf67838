#pragma once
// Run output of the MPM solver: history and particle fields in one HDF5 file
// (layout below, every dataset with a `units` attribute) and an XDMF file
// next to it that ParaView opens as a time series of point clouds.
//
//   /mpm                     attributes: model, cell_m, ppc, shape, scheme, status, ...
//   /mpm/history/{time_s, load_N, displacement_m, load_line_cod_m, kinetic_J,
//                 strain_J, external_work_J, damping_per_s, J_<k>cells_J_per_m2}
//   /mpm/fields/step_NNNNNNNN/{position (N x 2) m, ux, uy m, vx, vy m/s,
//                 sxx, syy, sxy Pa, strain_energy_density J/m^3}  attribute time_s

#include <filesystem>
#include <memory>

#include "bridgefit/mpm/solver.hpp"

namespace bridgefit::mpm {

// False when the library was built without bf_io (RunWriter then throws).
bool RunOutputAvailable();

class RunWriter {
 public:
  // The HDF5 file appears (atomically) at `h5_path` on Finish; the XDMF file
  // at the same path with extension .xdmf.
  explicit RunWriter(const std::filesystem::path& h5_path);
  ~RunWriter();
  RunWriter(const RunWriter&) = delete;
  RunWriter& operator=(const RunWriter&) = delete;

  // Use as the solver's fields callback.
  void AddFields(long step, double time, const ParticleFields& fields);
  void Finish(const Summary& summary, const Model& model, const SolverOptions& options);
  std::filesystem::path xdmf_path() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bridgefit::mpm
