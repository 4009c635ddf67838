// Built when bf_io is absent: the writer reports that output is unavailable.
#include "bridgefit/core/error.hpp"
#include "bridgefit/mpm/output.hpp"

namespace bridgefit::mpm {
bool RunOutputAvailable() { return false; }
struct RunWriter::Impl {};
RunWriter::RunWriter(const std::filesystem::path&) {
  throw Error(ErrorKind::kRuntime, "this build has no HDF5 output (bf_io missing)");
}
RunWriter::~RunWriter() = default;
void RunWriter::AddFields(long, double, const ParticleFields&) {}
void RunWriter::Finish(const Summary&, const Model&, const SolverOptions&) {}
std::filesystem::path RunWriter::xdmf_path() const { return {}; }
}  // namespace bridgefit::mpm
