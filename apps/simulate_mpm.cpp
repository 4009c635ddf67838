// Placeholder until the MPM issue lands.
#include "simulate_mpm.hpp"

#include "bridgefit/core/error.hpp"

namespace bridgefit::cli {
void RegisterMpmOptions(CLI::App& sub, MpmCliOptions& options) {
  sub.add_option("--cell", options.cell, "MPM background cell size, e.g. '2.5 mm'");
  sub.add_option("--ppc", options.ppc, "MPM particles per cell per direction");
}
int RunMpmSimulation(const Scene&, const MpmCliOptions&, const std::string&, const std::string&,
                     const CommonOptions&) {
  throw Error(ErrorKind::kRuntime, "the MPM model is not available in this version yet");
}
}  // namespace bridgefit::cli
