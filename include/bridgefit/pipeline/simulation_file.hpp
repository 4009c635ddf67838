#pragma once
// The files of `bridgefit simulate`, their one writer (issue 16):
//   --out  HDF5 /simulation (io::WriteRecordH5) with the scene's path
//   --csv  the points, SI with units in the header
//          ('crack_length [m], R [J/m^2], R_energy [J/m^2], ...')
//   --csv  of a stationary MPM run: its history
//          ('time_s,load_N,...,J_<k>cells_J_per_m2' per J contour)
// io::ReadCsvTable reads the CSVs back. All written atomically.

#include <string>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/mpm/solver.hpp"
#include "bridgefit/scene/scene.hpp"

namespace bridgefit::pipeline {

std::string SimulationCsv(const SimulationResult& result);
void WriteSimulationCsv(const std::string& path, const SimulationResult& result);
void WriteSimulationH5(const std::string& path, const SimulationResult& result,
                       const Scene& scene);

std::string MpmHistoryCsv(const mpm::Summary& summary, const std::vector<int>& contour_cells);
void WriteMpmHistoryCsv(const std::string& path, const mpm::Summary& summary,
                        const std::vector<int>& contour_cells);

}  // namespace bridgefit::pipeline
