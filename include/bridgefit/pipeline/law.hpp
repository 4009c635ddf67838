#pragma once
// A bridging law and its elastic-zone R curve as a table (issue 16),
// `bridgefit law` (PHYSICS 2-3):
//
//   delta_i = delta_c i / (points - 1),  i = 0 .. points - 1
//   sigma(delta_i), R(delta_i) = J_tip,c + W(delta_i) (laws::ElasticZoneR),
//   J_ff(delta_i) (laws::FarFieldJ)
//
// WriteLawCsv is the one writer of the law CSV ('delta [m], sigma [Pa],
// R [J/m^2], J_ff [J/m^2]'); io::ReadCsvTable reads it back.

#include <cmath>
#include <string>
#include <vector>

#include "bridgefit/laws/law.hpp"

namespace bridgefit::pipeline {

struct LawRequest {
  laws::LawShape shape;
  laws::LawScales scales;  // complete (laws::CompleteScales)
  double J_tip_c = NAN;    // [J/m^2], > 0
  int points = 101;        // openings from 0 to delta_c inclusive, >= 2

  bool IsValid(std::string* why) const;
};

struct LawPoint {
  double delta = NAN;  // opening [m]
  double sigma = NAN;  // traction [Pa]
  double R = NAN;      // elastic-zone R at this root opening [J/m^2]
  double J_ff = NAN;   // far-field J [J/m^2]
};

struct LawRun {
  laws::LawShape shape;
  laws::LawScales scales;
  double J_tip_c = NAN;
  std::vector<LawPoint> points;

  // The text `bridgefit law` prints: the law's scales and steady-state R,
  // then the table (about 20 rows, the last always).
  std::string BriefReport() const;
};

// Throws Error(kUsage) for an invalid request.
LawRun RunLaw(const LawRequest& request);

// The points as CSV (SI, units in the header), atomic.
void WriteLawCsv(const std::string& path, const LawRun& run);

}  // namespace bridgefit::pipeline
