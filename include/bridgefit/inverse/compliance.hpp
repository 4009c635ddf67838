#pragma once
// A model's elastic compliance calibrated to a test record along the
// measured crack: the record's compliance C_i = d_i / P_i at its crack
// lengths a_i against the model's C_m(a),
//
//   C_i ~ s C_m(a_i) + C_s,
//
// s the compliance scale (the model's moduli are multiplied by 1 / s) and
// C_s a compliance in series at the load point (load train, hinges, the
// arms' roots beyond what the model resolves). Least squares on the relative
// residuals (s C_m(a_i) + C_s) / C_i - 1, closed form (two unknowns).
//
// One value of the initial compliance fixes one factor only; the crack
// lengths give the compliance's whole course, which on a real DCB differs
// from an isotropic beam's (docs/FIT.md "Compliance along the crack").

#include <cmath>
#include <string>
#include <vector>

namespace bridgefit::inverse {

// A model's load-point compliance against crack length (ascending a).
struct ComplianceCurve {
  std::vector<double> crack_length;  // [m]
  std::vector<double> compliance;    // [m/N]
  // Linear interpolation; NaN outside the curve's range.
  double At(double crack_length) const;
};

struct ComplianceFitOptions {
  bool fit_series = true;  // false: C_s = 0, the scale alone
  int min_rows = 5;
  // A compliance in series (load train, hinges) cannot be negative: below
  // this bound C_s is held at it and the scale refitted (series_at_bound).
  double min_series_compliance = 0.0;  // [m/N]
  bool IsValid(std::string* why) const;
};

struct ComplianceFit {
  double scale = NAN;              // s
  double series_compliance = NAN;  // C_s [m/N]
  double rms_relative = NAN;       // rms of (s C_m + C_s) / C_i - 1
  bool series_at_bound = false;    // the free fit asked for C_s below the bound
  double series_unconstrained = NAN;  // what the free fit asked for [m/N]
  int rows = 0;                    // record rows inside the model curve's range
  double crack_min = NAN, crack_max = NAN;  // [m], of those rows
  std::string Summary() const;
};

// Throws Error (kInput, naming `source`) when fewer than options.min_rows
// rows fall inside the model curve or the fit is not physical (s <= 0).
ComplianceFit FitComplianceAlongCrack(const ComplianceCurve& model,
                                      const std::vector<double>& crack_length,
                                      const std::vector<double>& compliance,
                                      const ComplianceFitOptions& options,
                                      const std::string& source);

}  // namespace bridgefit::inverse
