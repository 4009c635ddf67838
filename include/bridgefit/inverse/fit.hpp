#pragma once
// Fitting a bridging law to a measured R curve (issue 7): NLopt and Ceres
// optimizers, multi-start, identifiability, bounds and uncertainty.

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "bridgefit/core/records.hpp"
#include "bridgefit/inverse/forward_model.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/laws/rcurve_theory.hpp"

namespace bridgefit::inverse {

// Parameter order inside the fitter.
enum ParameterIndex { kSigmaC = 0, kJB = 1, kJTipC = 2 };
constexpr int kParameterCount = 3;
const char* ParameterName(int index);  // "sigma_c", "J_B", "J_tip_c"

enum class Optimizer { kCeresLm, kBobyqa, kNelderMead, kCobyla, kDirect, kCrs2 };
const char* OptimizerName(Optimizer optimizer);
Optimizer ParseOptimizer(const std::string& name);

struct FitOptions {
  Optimizer optimizer = Optimizer::kBobyqa;  // fastest reliable one in docs/FIT.md
  int starts = 4;                 // Latin-hypercube multi-start points
  int max_evaluations = 600;      // per local run
  double relative_tolerance = 1e-6;  // on the box coordinates
  // Box [low, high] of each parameter (SI); a fixed parameter ignores it.
  std::array<double, kParameterCount> lower = {0.02e6, 1.0, 50.0};
  std::array<double, kParameterCount> upper = {20e6, 20000.0, 20000.0};
  std::array<bool, kParameterCount> fixed = {false, false, false};
  std::array<double, kParameterCount> fixed_value = {0.0, 0.0, 0.0};
  // First start (physical values, SI) for the free parameters; NaN: read
  // one off the data (J_tip,c from the first points, J_B from the rise).
  std::array<double, kParameterCount> initial = {NAN, NAN, NAN};
  // Profile-likelihood intervals for every free parameter. J_B's profile
  // runs regardless: it decides whether steady state was reached.
  bool profile_likelihood = true;
  // Points whose residual exceeds `outlier_threshold` robust standard
  // deviations (1.4826 x median |residual|) after a first fit are removed
  // (at most a fifth of the data), listed in the summary, and the fit is
  // repeated without them. 0 disables the check.
  double outlier_threshold = 5.0;
  unsigned seed = 12345;          // Latin-hypercube design
  int threads = 0;                // profiles side by side (0: two OpenMP threads, 1: serial)
  bool progress = false;

  bool IsValid(std::string* why) const;
};

// The data of a fit: R against crack length, with optional uncertainties.
struct FitData {
  std::vector<double> crack_length;   // [m]
  std::vector<double> R;              // [J/m^2]
  std::vector<double> R_uncertainty;  // [J/m^2], empty: equal weights, scale from residuals
  RKind kind = RKind::kEnergy;
  static FitData FromRCurve(const RCurve& curve, RKind kind);
  void Validate() const;
};

struct ParameterEstimate {
  double value = NAN;        // NaN when only a bound is known
  double ci95_low = NAN;
  double ci95_high = NAN;
  double lower_bound = NAN;  // set when not identifiable from a truncated curve
  bool identified = false;
  bool fixed = false;
  std::string decided_by;    // e.g. "ceres-lm + reduced", "PHYSICS 7 bound"
  std::string note;
};

struct ProfilePoint {
  double value;  // parameter value (SI)
  double chi2;   // best chi^2 with the other parameters re-optimized
  bool ok;
  std::array<double, 3> parameters;  // the full (sigma_c, J_B, J_tip_c) there
};
struct Profile {
  int parameter = 0;
  std::vector<ProfilePoint> points;
  double chi2_threshold = 3.84;  // Delta chi^2 of a 95% interval (scaled when weights unknown)
  bool flat = false;             // never rises past the threshold on one side
};

struct StartResult {
  std::array<double, kParameterCount> start{};
  std::array<double, kParameterCount> end{};
  double cost = NAN;
  int evaluations = 0;
  std::string stop_reason;
};

struct FitSummary {
  std::string model;
  std::string optimizer;
  std::string law;
  int evaluations = 0;
  int failed_evaluations = 0;     // forward runs that reported a failure
  double wall_s = 0.0;
  bool converged = false;
  std::string stop_reason;
  bool steady_state_reached = false;
  double steady_state_crack_length = NAN;
  double rms_residual = NAN;      // [J/m^2]
  double chi2 = NAN;
  int data_points = 0;
  bool bridging_detected = true;
  std::string verdict;            // one sentence for the report
  ParameterEstimate sigma_c, J_B, delta_c, J_tip_c;
  laws::TruncationBounds bounds;  // evidence when steady state was not reached
  std::vector<StartResult> starts;
  std::vector<double> outlier_crack_lengths;  // removed points [m]
  std::vector<double> outlier_R;              // their R [J/m^2]
  std::vector<Profile> profiles;
  std::vector<double> fitted_crack_length;  // the data points used (outliers removed) [m]
  std::vector<double> fitted_R;   // model R there [J/m^2]
  std::vector<double> fitted_delta_root;
  // The full parameter vector (sigma_c, J_B, J_tip_c) at the chi^2 minimum
  // [SI], also when only bounds are reported (NaN when the fit failed).
  std::array<double, kParameterCount> best_parameters = {NAN, NAN, NAN};

  std::string BriefReport() const;
};

// Fits `shape`'s parameters to `data` with `model`. Never throws for a
// failed forward run (counted and reported); throws Error for invalid
// options or data.
FitSummary FitBridgingLaw(const ForwardModel& model, const laws::LawShape& shape,
                          const FitData& data, const FitOptions& options);

// Law families compared by Akaike's information criterion with the small-
// sample correction: AICc = chi2 / s^2 + 2k + 2k(k+1)/(n-k-1), s^2 = 1 with
// reported uncertainties (else the best family's reduced chi^2).
struct LawComparison {
  std::string law;
  FitSummary summary;
  double aicc = NAN;
  double delta_aicc = NAN;  // against the best family
};
std::vector<LawComparison> CompareLawFamilies(const ForwardModel& model,
                                              const std::vector<laws::LawShape>& shapes,
                                              const FitData& data, const FitOptions& options);

}  // namespace bridgefit::inverse
