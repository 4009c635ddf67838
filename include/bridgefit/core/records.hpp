#pragma once
// Plain value types passed between the stages of the data flow, in SI units.
// HDF5 layouts: docs/FORMATS.md (io::WriteRecordH5 / io::Read*H5).

#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace bridgefit {

// A load-displacement test record (one row per sample).
struct ExperimentRecord {
  std::string source;                 // provenance: file it came from
  std::vector<double> time;           // [s] (may be empty)
  std::vector<double> load;           // P [N]
  std::vector<double> displacement;   // load-point displacement [m]
  std::vector<double> crack_length;   // a [m], from the load line (may be empty; NaN: no reading)
  std::vector<std::string> images;    // image file per row (may be empty)
  std::map<std::string, std::string> metadata;  // specimen, material, notes

  // Cleaning done on import, reported, never silent.
  int rows_read = 0;
  int rows_dropped_nan = 0;   // rows with a NaN/empty value in a used column
  int rows_repeated = 0;      // exact repeats of the previous row

  std::size_t size() const { return load.size(); }
  bool has_crack_length() const { return !crack_length.empty(); }
  // Throws Error when column lengths differ or values are not finite (a
  // crack length may be NaN: not read in that row).
  void Validate() const;
};

// An R curve: resistance against crack length.
struct RCurve {
  std::string method;   // energy | mbt | cc | lefm | equivalent | model name
  std::string r_kind;   // "energy" (energy released) or "elastic-zone"
  std::string source;   // provenance
  std::vector<double> crack_length;   // a [m]
  std::vector<double> R;              // [J/m^2]
  std::vector<double> R_uncertainty;  // [J/m^2], empty when unknown
  // Coverage factor k of R_uncertainty: 1 = one standard uncertainty,
  // 2 = the expanded (about 95%) uncertainty `bridgefit rcurve` reports.
  double uncertainty_coverage = 1.0;
  double initial_crack_length = NAN;  // a0 [m]
  double initiation_R = NAN;          // [J/m^2]

  std::size_t size() const { return R.size(); }
  void Validate() const;
};

// One crack length of a forward simulation.
struct SimulationPoint {
  double crack_length = NAN;          // a [m]
  double R = NAN;                     // elastic-zone R (PHYSICS 3) [J/m^2]
  double R_energy = NAN;              // energy released per unit growth [J/m^2]
  double J_tip = NAN;                 // [J/m^2]
  double J_ff = NAN;                  // [J/m^2]
  double delta_root = NAN;            // COD at the notch root [m]
  double root_position = NAN;         // x of the notch root from the load line [m]
  double bridging_zone_length = NAN;  // a - x_root [m]
  double load = NAN;                  // P [N]
  double displacement = NAN;          // load-point displacement [m]
  double cmod = NAN;                  // crack-mouth opening [m]
};

enum class RunStatus { kOk, kNotConverged, kUnstable, kInvalidInput, kFailed };
const char* RunStatusName(RunStatus status);

// The result of a forward simulation with crack growth.
struct SimulationResult {
  std::string model;                  // "reduced", "mpm", "analytic"
  RunStatus status = RunStatus::kOk;
  std::string message;                // why it stopped
  std::vector<SimulationPoint> points;
  bool steady_state_reached = false;
  double steady_state_crack_length = NAN;  // [m], NaN when not reached
  double initiation_load = NAN;            // [N]
  double wall_s = 0.0;
  std::map<std::string, double> figures;   // model-specific numbers (SI)
  // Why its numbers may be off by more than the model's usual error (e.g. an
  // MPM cell too coarse for the specimen); printed, and in every output.
  std::vector<std::string> warnings;

  RCurve ToRCurve(bool energy_kind) const;
};

// R_energy per point from a load-displacement record: between successive
// points dU = int P dd - (P2 d2 - P1 d1)/2 (trapezoid), R = dU / (B da); a
// point gets the mean of the steps on either side (one step at the ends).
void FillEnergyR(std::vector<SimulationPoint>& points, double thickness);

// A point quantity at crack length a, linear between the points (ascending
// crack length); NaN outside their range.
double InterpolatePoints(const std::vector<SimulationPoint>& points, double a,
                         double SimulationPoint::*field);

// A test record along a simulation's path, as `bridgefit synth` writes it
// (no time, no noise): `loading_rows` rows of linear loading from the origin
// toward the first point (initiation, crack length a0), then `growth_rows`
// rows evenly spaced in point index from the first point to the last (linear
// between points). `nearest_point`, when given, receives the simulation point
// nearest each growth row. Needs two points and growth_rows >= 2.
ExperimentRecord RecordAlongPath(const SimulationResult& sim, int loading_rows, int growth_rows,
                                 std::vector<std::size_t>* nearest_point = nullptr);

}  // namespace bridgefit
