// The files of `bridgefit simulate` (pipeline/simulation_file.hpp).
#include "bridgefit/pipeline/simulation_file.hpp"

#include <fmt/format.h>

#include "bridgefit/core/atomic_file.hpp"
#include "bridgefit/io/hdf5.hpp"

namespace bridgefit::pipeline {

std::string SimulationCsv(const SimulationResult& result) {
  std::string text =
      "crack_length [m], R [J/m^2], R_energy [J/m^2], J_tip [J/m^2], J_ff [J/m^2], "
      "delta_root [m], root_position [m], bridging_zone_length [m], load [N], "
      "displacement [m], cmod [m]\n";
  for (const SimulationPoint& p : result.points)
    text += fmt::format("{:.10g}, {:.10g}, {:.10g}, {:.10g}, {:.10g}, {:.10g}, {:.10g}, {:.10g}, "
                        "{:.10g}, {:.10g}, {:.10g}\n",
                        p.crack_length, p.R, p.R_energy, p.J_tip, p.J_ff, p.delta_root,
                        p.root_position, p.bridging_zone_length, p.load, p.displacement, p.cmod);
  return text;
}

void WriteSimulationCsv(const std::string& path, const SimulationResult& result) {
  WriteTextFileAtomic(path, SimulationCsv(result));
}

void WriteSimulationH5(const std::string& path, const SimulationResult& result,
                       const Scene& scene) {
  io::H5Writer file(path);
  io::WriteRecordH5(file, result);
  file.WriteAttribute("/simulation", "scene", scene.source);
  std::string warnings;  // one per line, empty when none
  for (const std::string& w : result.warnings) warnings += (warnings.empty() ? "" : "\n") + w;
  file.WriteAttribute("/simulation", "warnings", warnings);
  file.Commit();
}

std::string MpmHistoryCsv(const mpm::Summary& summary, const std::vector<int>& contour_cells) {
  std::string text = "time_s,load_N,displacement_m,load_line_cod_m,kinetic_J,strain_J";
  for (int k : contour_cells) text += fmt::format(",J_{}cells_J_per_m2", k);
  text += "\n";
  for (const auto& h : summary.history) {
    text += fmt::format("{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}", h.time, h.load,
                        h.displacement, h.load_line_cod, h.kinetic, h.strain);
    for (double j : h.J) text += fmt::format(",{:.9g}", j);
    text += "\n";
  }
  return text;
}

void WriteMpmHistoryCsv(const std::string& path, const mpm::Summary& summary,
                        const std::vector<int>& contour_cells) {
  WriteTextFileAtomic(path, MpmHistoryCsv(summary, contour_cells));
}

}  // namespace bridgefit::pipeline
