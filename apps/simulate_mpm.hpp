#pragma once
// The MPM branch of `bridgefit simulate` (cmd_simulate.cpp calls these).

#include <CLI/CLI.hpp>
#include <string>

#include "bridgefit/scene/scene.hpp"
#include "command.hpp"

namespace bridgefit::cli {

struct MpmCliOptions {
  std::string cell = "2.5 mm";  // background cell size, with unit
  int ppc = 2;                  // particles per cell per direction
  int threads = 0;              // 0: OpenMP default
  int fields_every = 0;         // write particle fields every N steps (0: never)
  std::string shape = "gimp";   // gimp | linear
  std::string scheme = "usl";   // usf | usl | usavg
  double cfl = 0.5;
  bool half = false;            // growth: half-specimen model
  bool full = false;            // growth: full explicit-crack model
  std::string increment;        // growth: tip increment with unit (default one cell)
  std::vector<int> contours = {3};  // growth: J contour half sizes [cells]
};

// Adds the MPM-only options to the `simulate` subcommand.
void RegisterMpmOptions(CLI::App& sub, MpmCliOptions& options);
// Runs the scene with the MPM solver; writes `out_h5`/`csv` if non-empty.
int RunMpmSimulation(const Scene& scene, const MpmCliOptions& options,
                     const std::string& out_h5, const std::string& csv,
                     const CommonOptions& common);

}  // namespace bridgefit::cli
