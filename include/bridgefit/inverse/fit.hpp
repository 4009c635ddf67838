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

namespace bridgefit::parallel {
class Communicator;
}

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
  // A load-displacement fit takes each finite value on its own (sigma_c NaN:
  // a scan of the box at the given J_tip,c and J_B).
  std::array<double, kParameterCount> initial = {NAN, NAN, NAN};
  // Profile-likelihood intervals for every free parameter. J_B's profile
  // runs regardless: it decides whether steady state was reached.
  bool profile_likelihood = true;
  // Points whose residual exceeds `outlier_threshold` robust standard
  // deviations (1.4826 x median |residual|) after a first fit are removed
  // (at most a fifth of the data), listed in the summary, and the fit is
  // repeated without them. 0 disables the check. In an R-curve fit, two or
  // more such points in a row on the same side of the model are not
  // outliers but a misfit (FitSummary::misfit): they stay in the fit.
  double outlier_threshold = 5.0;
  // Bridging that adds less than this fraction of J_tip,c to R (the smaller
  // of the fitted J_B and the fitted R's rise inside the data window) is
  // reported as no bridging even when statistically significant: it is
  // below the forward models' R accuracy (reduced model: flat R within 0.5%
  // without bridging, MPM within 0.4%; docs/REDUCED.md, docs/MPM.md), so a
  // fit to a long record can find it in the model's own discretisation
  // error (docs/FIT.md).
  double min_bridging_fraction = 0.01;
  unsigned seed = 12345;          // Latin-hypercube design
  int threads = 0;                // profiles side by side (0: two OpenMP threads, 1: serial)
  bool progress = false;
  // Ranks of one job sharing this fit's profiles (a campaign's joint fit
  // under MPI, docs/MPI.md): profile q runs on rank q mod N, on `threads`
  // there, and every rank gets them all. Every rank must make the same fit
  // at the same time (collective). Null or one rank: this process alone. The
  // result does not depend on it, bit for bit.
  parallel::Communicator* ranks = nullptr;

  bool IsValid(std::string* why) const;
};

// What a fit compares the model with: an R curve (R against crack length), or
// the test record itself (load against load-point displacement, docs/FIT.md
// "Fitting the load-displacement record").
enum class FitTarget { kRCurve, kLoad };
const char* FitTargetName(FitTarget target);  // "r-curve", "load-displacement"
FitTarget ParseFitTarget(const std::string& name);

// The data of a fit.
struct FitData {
  FitTarget target = FitTarget::kRCurve;
  // kRCurve: R against crack length, with optional uncertainties.
  std::vector<double> crack_length;   // [m]
  std::vector<double> R;              // [J/m^2]
  std::vector<double> R_uncertainty;  // [J/m^2], empty: equal weights, scale from residuals
  RKind kind = RKind::kEnergy;
  // kLoad: the record's rows in test order.
  std::vector<double> displacement;      // load-point displacement [m]
  std::vector<double> load;              // [N]
  std::vector<double> load_uncertainty;  // [N], one sigma; empty: equal weights, scale from residuals
  static FitData FromRCurve(const RCurve& curve, RKind kind);
  // The rows of `record` with a displacement above zero. Each row's
  // uncertainty combines the load noise with the displacement noise carried
  // through the record's local slope: u^2 = u_P^2 + (dP/dd u_d)^2, the slope
  // from a straight line through the row and its neighbours (+-3 rows).
  // Both noises zero: equal weights, scale from the residuals.
  static FitData FromRecord(const ExperimentRecord& record, double load_noise,
                            double displacement_noise);
  std::size_t size() const { return target == FitTarget::kLoad ? load.size() : R.size(); }
  bool weighted() const {
    return target == FitTarget::kLoad ? !load_uncertainty.empty() : !R_uncertainty.empty();
  }
  // The rows `keep` (indices into this data, ascending).
  FitData Subset(const std::vector<int>& keep) const;
  void Validate() const;
};

// How far a printed 95% interval can be trusted (docs/FIT.md "Profiles you
// can trust"). Anything but kReliable comes with a reason and a warning; an
// end that cannot be trusted is printed as NaN (open), never at the optimum.
enum class IntervalStatus {
  kReliable,             // a smooth profile crossing the threshold (or the Jacobian)
  kOpen,                 // the profile stays under the threshold to the box edge (flat)
  kEndsOnBound,          // the optimum sits on the box edge: the box, not the data, ends it
  kUnreliableZeroWidth,  // an end at the optimum even after finer bisection and re-solves
  kUnreliableNonSmooth,  // chi^2 jumps, or the profile is not monotone, or finds a lower chi^2
  kUnreliableMisfit,     // the model does not follow a run of data points (FitSummary::misfit)
};
// "reliable", "open", "ends_on_bound", "unreliable_zero_width", "unreliable_non_smooth",
// "unreliable_misfit"
const char* IntervalStatusName(IntervalStatus status);

struct ParameterEstimate {
  double value = NAN;        // NaN when only a bound is known
  double ci95_low = NAN;
  double ci95_high = NAN;
  double lower_bound = NAN;  // set when not identifiable from a truncated curve
  bool identified = false;
  bool fixed = false;
  std::string decided_by;    // e.g. "ceres-lm + reduced", "PHYSICS 7 bound"
  std::string note;
  IntervalStatus interval_status = IntervalStatus::kReliable;
  std::string interval_reason;  // empty when reliable: why the interval cannot be trusted
  // With the model error applied (model_error.hpp): ci95_low/high are the
  // total interval, these the noise's alone, and model_bias the predicted
  // discretisation bias of `value` (estimate minus the converged model's).
  // NaN when no model error was applied.
  double statistical_ci95_low = NAN;
  double statistical_ci95_high = NAN;
  double model_bias = NAN;
  bool interval_reliable() const { return interval_status == IntervalStatus::kReliable; }
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
  // The worse of the two sides' checks, with its reason (empty when reliable).
  IntervalStatus status = IntervalStatus::kReliable;
  std::string status_reason;
  int resolves = 0;              // profile points re-solved with more starts
};

// R points that lie beyond the outlier threshold two or more in a row on
// the same side of the model: not gross errors but data the model cannot
// follow (a rise shorter than its elements, a law that does not fit). They
// stay in the fit and every estimated interval is marked kUnreliableMisfit
// (docs/FIT.md "A run of misfit points").
struct MisfitRun {
  int points = 0;                  // points in such runs; 0: none
  double crack_length_from = NAN;  // the runs' first and last crack length [m]
  double crack_length_to = NAN;
  double largest_sd = NAN;         // the largest |residual| among them [robust SD]
  int side = 0;                    // +1 the data above the model, -1 below, 0 both
  std::string Describe() const;    // one phrase for the verdict and the warnings
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
  FitTarget target = FitTarget::kRCurve;
  double rms_residual = NAN;      // [J/m^2] (R-curve fit) or [N] (load-displacement fit)
  double chi2 = NAN;
  // chi^2 / (points - free parameters) at the optimum; with reported
  // uncertainties the intervals are widened by it when it exceeds 1.
  double reduced_chi2 = NAN;
  // Lag-1 autocorrelation of the (weighted) residuals in data order, and the
  // factor (1 + rho) / (1 - rho) on s^2 where it is significant (1 where
  // not; docs/FIT.md "Correlated residuals").
  double residual_autocorrelation = NAN;
  double interval_inflation = 1.0;
  // s^2 of the intervals and tests: the Birge ratio (weighted data) or the
  // residual variance (unweighted) x interval_inflation.
  double noise_scale2 = NAN;
  int data_points = 0;
  bool bridging_detected = true;
  std::string verdict;            // one sentence for the report
  ParameterEstimate sigma_c, J_B, delta_c, J_tip_c;
  laws::TruncationBounds bounds;  // evidence when steady state was not reached
  std::vector<StartResult> starts;
  // Removed points: crack length [m] and R [J/m^2] of an R-curve fit, or
  // displacement [m] and load [N] of a load-displacement fit.
  std::vector<double> outlier_crack_lengths;
  std::vector<double> outlier_R;
  MisfitRun misfit;  // R-curve fit: runs of points the model does not follow
  std::vector<Profile> profiles;
  // R-curve fit: the data points used (outliers removed) [m] and the model's
  // R there [J/m^2]. Load-displacement fit: the model's physical crack
  // length and elastic-zone R at each row used.
  std::vector<double> fitted_crack_length;
  std::vector<double> fitted_R;
  std::vector<double> fitted_delta_root;
  // Load-displacement fit: the rows used [m], their measured load and the
  // model's load there [N].
  std::vector<double> fitted_displacement;
  std::vector<double> fitted_record_load;
  std::vector<double> fitted_load;
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
// A fitted shape's parameter (inverse/fit_shape.hpp).
struct ShapeParameter {
  std::string name;  // "d1", "s1", "s(0.25)" (table knot at d = 0.25)
  double value = NAN;
  double standard_error = NAN;  // Wald, the scale parameters free; NaN: singular
  bool pinned = false;          // the table's peak knot (= 1 by definition, not a parameter)
};
struct LawComparison {
  std::string law;
  FitSummary summary;
  double aicc = NAN;
  double delta_aicc = NAN;  // against the best family
  laws::LawShape shape;       // the law fitted (a fitted-shape family: its optimum)
  double parameters = NAN;    // k in AICc (the penalised table: effective, fit_shape.hpp)
  double weight = NAN;        // Akaike weight exp(-delta/2) / sum over the families (0: no AICc)
  double noise_scale2 = NAN;  // s^2 of the AICc
  std::string note;           // a skipped family's reason; a fitted shape's parameters
  std::vector<ShapeParameter> shape_parameters;  // a fitted-shape family's
};
// delta_aicc against the smallest finite AICc, and the Akaike weights.
void RankByAicc(std::vector<LawComparison>& comparison);
std::vector<LawComparison> CompareLawFamilies(const ForwardModel& model,
                                              const std::vector<laws::LawShape>& shapes,
                                              const FitData& data, const FitOptions& options);

}  // namespace bridgefit::inverse
