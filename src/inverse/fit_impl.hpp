#pragma once
// Private to src/inverse: the fit's objective in box coordinates and the
// local optimizers behind FitBridgingLaw (fit.cpp); fit_optimize.cpp
// implements them.

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/inverse/model_error.hpp"

namespace bridgefit::inverse::fit_internal {

inline constexpr double kFailedCost = 1e30;  // chi^2 of a failed forward run (infeasible)
// A profile point whose chi^2 lies this far below the optimum's found a
// better minimum (the fit stopped in a local one): one rule for the
// profile's shape check and the fit's restart from that point.
inline double BelowOptimumTolerance(double threshold, double optimum_chi2) {
  return std::max(0.1 * threshold, 1e-9 * optimum_chi2);
}

// sigma_c and J_B span decades: their box coordinate is logarithmic.
inline bool IsLogScale(int index) { return index == kSigmaC || index == kJB; }

inline double FromBox(int index, double x, const FitOptions& o) {
  const double lo = o.lower[index], hi = o.upper[index];
  x = std::clamp(x, 0.0, 1.0);
  return IsLogScale(index) ? lo * std::pow(hi / lo, x) : lo + x * (hi - lo);
}
// The inverse of FromBox, clamped to the box.
inline double ToBox(int index, double value, const FitOptions& o) {
  const double lo = o.lower[index], hi = o.upper[index];
  const double v = std::clamp(value, lo, hi);
  return IsLogScale(index) ? std::log(v / lo) / std::log(hi / lo) : (v - lo) / (hi - lo);
}

// The objective: weighted residuals of the model against the data.
class Objective {
 public:
  Objective(const ForwardModel& model, const laws::LawShape& shape, const FitData& data,
            const FitOptions& options)
      : model_(model), shape_(shape), data_(data), options_(options) {
    for (int i = 0; i < kParameterCount; ++i)
      if (!options.fixed[i]) free_.push_back(i);
  }

  const std::vector<int>& free() const { return free_; }
  const laws::LawShape& shape() const { return shape_; }
  int evaluations() const { return evaluations_; }
  int failures() const { return failures_; }
  // Counts of evaluations made on copies of this objective (parallel profiles).
  void AddCounts(int evaluations, int failures) const {
    evaluations_ += evaluations;
    failures_ += failures;
  }

  LawParameters Parameters(const std::vector<double>& full) const {
    return {full[kSigmaC], full[kJB], full[kJTipC]};
  }
  // Full physical parameter vector from the free box coordinates; `pinned`
  // overrides one free parameter (profile likelihood).
  std::vector<double> Expand(const double* x, int pinned = -1, double pinned_value = 0.0) const {
    std::vector<double> full(kParameterCount);
    for (int i = 0; i < kParameterCount; ++i) full[i] = options_.fixed_value[i];
    for (size_t k = 0; k < free_.size(); ++k) full[free_[k]] = FromBox(free_[k], x[k], options_);
    if (pinned >= 0) full[pinned] = pinned_value;
    return full;
  }

  // Residuals r_i = (R_model - R_i) / u_i, or (P_model - P_i) / u_i for a
  // load-displacement fit. False when the forward run failed.
  bool Residuals(const std::vector<double>& full, double* residuals,
                 ForwardPrediction* prediction = nullptr) const {
    ++evaluations_;
    const bool load = data_.target == FitTarget::kLoad;
    ForwardPrediction p =
        load ? model_.PredictLoad(shape_, Parameters(full), data_.displacement)
             : model_.Predict(shape_, Parameters(full), data_.crack_length, data_.kind);
    const std::vector<double>& model_values = load ? p.load : p.R;
    const std::vector<double>& values = load ? data_.load : data_.R;
    const std::vector<double>& uncertainty = load ? data_.load_uncertainty : data_.R_uncertainty;
    if (!p.ok() || model_values.size() != values.size()) {
      ++failures_;
      last_failure_ = p.message;
      return false;
    }
    for (size_t i = 0; i < values.size(); ++i) {
      const double u = uncertainty.empty() ? 1.0 : uncertainty[i];
      residuals[i] = (model_values[i] - values[i]) / u;
      if (!std::isfinite(residuals[i])) {
        ++failures_;
        last_failure_ = load ? "non-finite model load" : "non-finite model R";
        return false;
      }
    }
    if (prediction) *prediction = std::move(p);
    return true;
  }

  double Chi2(const std::vector<double>& full) const {
    std::vector<double> r(data_.size());
    if (!Residuals(full, r.data())) return kFailedCost;
    double sum = 0.0;
    for (double v : r) sum += v * v;
    return sum;
  }

  const std::string& last_failure() const { return last_failure_; }
  // The last failure of evaluations made on another rank.
  void SetLastFailure(const std::string& message) const { last_failure_ = message; }
  const FitData& data() const { return data_; }
  const FitOptions& options() const { return options_; }

 private:
  const ForwardModel& model_;
  const laws::LawShape& shape_;
  const FitData& data_;
  const FitOptions& options_;
  std::vector<int> free_;
  mutable int evaluations_ = 0;
  mutable int failures_ = 0;
  mutable std::string last_failure_;
};

struct LocalResult {
  std::vector<double> x;
  double chi2 = kFailedCost;
  int evaluations = 0;
  std::string stop_reason;
  bool converged = false;
};

// Minimizes chi^2 over the free box coordinates (one of them may be pinned)
// with an NLopt algorithm.
LocalResult MinimizeNlopt(const Objective& objective, Optimizer optimizer, std::vector<double> x0,
                          int max_evaluations, int pinned = -1, double pinned_value = 0.0,
                          double xtol = 0.0);
// The optimizer of the options: Ceres LM, an NLopt local one, or a global
// NLopt search polished by BOBYQA.
LocalResult MinimizeLocal(const Objective& objective, Optimizer optimizer,
                          const std::vector<double>& x0, int max_evaluations, int pinned = -1,
                          double pinned_value = 0.0);
// Latin-hypercube design in the unit box.
std::vector<std::vector<double>> LatinHypercube(int points, int dims, unsigned seed);
// Jacobian d r_i / d p_j of the physical free parameters (central differences).
bool PhysicalJacobian(const Objective& objective, const std::vector<double>& full,
                      Eigen::MatrixXd* jacobian);
// Sets full[index] to the best of 9 evenly spaced box points.
void ScanBox(const Objective& objective, int index, std::vector<double>& full);
// What the stages of one fit share.
struct FitContext {
  const ForwardModel& model;
  const laws::LawShape& shape;
  const FitData& data;
  const FitOptions& options;
  const Objective& objective;
  const std::vector<int>& free;  // the free parameters' indices
  int n_free, m;                 // free parameters, data points
  bool weighted, load_fit;
};

inline ParameterEstimate& EstimateOf(FitSummary& s, int index) {
  return index == kSigmaC ? s.sigma_c : index == kJB ? s.J_B : s.J_tip_c;
}

// The restart stage of FitBridgingLaw (fit_restart.cpp). A profile point
// below the optimum means the search stopped in a local minimum: a full
// local search from that point's parameters (listed among the starts);
// nullopt when none is lower or the search does not beat the optimum.
std::optional<LocalResult> RestartFromProfiles(const FitContext& c, const LocalResult& best,
                                               double threshold, FitSummary& s);
// After a restart: the earlier rounds' profile points within the threshold
// of the new optimum widen the intervals that do not reach them (marked
// non-smooth).
void WidenToEarlierPoints(const FitContext& c, const std::vector<ProfilePoint>& earlier,
                          double optimum_chi2, double threshold, FitSummary& s);

// Stage 6 of FitBridgingLaw (fit_flat.cpp): the flat R curve (J_B = 0)
// against the bridged optimum; true when no bridging is reported (the
// summary then holds the flat answer).
bool RecordNoBridging(const FitContext& c, const LocalResult& best, const std::vector<double>& full,
                      const ForwardPrediction& prediction, double scale2, FitSummary& s);

// PHYSICS 7's R_max - J_tip,c at the data point `last` for parameters p:
// the model's elastic-zone rise W(delta_root) where the data's R is an
// energy R (R_energy also holds the specimen's back-face effects and can
// exceed J_tip,c + J_B: the reduced model's W = 50 mm CT, sigma_c 1 MPa,
// J_B 500 J/m^2, has R_energy - J_tip,c = 856 J/m^2 at a = 0.91 W), else the
// model's R (elastic-zone, or the physical R behind an as-data point) - J_tip,c.
double BridgingRise(const Objective& objective, const std::vector<double>& p,
                    const ForwardPrediction& prediction, std::size_t last);
// Standard uncertainties of the PHYSICS 7 bounds' quantities at the
// optimum `full`: R(a_last) - J_tip,c and delta_root(a_last) at the data
// point `last` (the model's physical R there when it has one), by the delta
// method from the free parameters' covariance (central differences, 2 x free
// model runs). NaN when the covariance is not finite or a run fails.
struct BoundUncertainty {
  double J_B_sd = NAN;      // [J/m^2]
  double delta_c_sd = NAN;  // [m]
  // The least of each quantity over the profiles' points inside the 95%
  // region (statistically acceptable laws; NaN without such points).
  double J_B_profile_min = NAN;      // [J/m^2]
  double delta_c_profile_min = NAN;  // [m]
};
BoundUncertainty TruncationBoundUncertainty(const Objective& objective,
                                            const std::vector<double>& full,
                                            const Eigen::MatrixXd& covariance, std::size_t last);
// Fills the *_profile_min fields from the profiles' points with chi^2 within
// `threshold` of `best_chi2` (one model run each).
void ProfileBoundMinimum(const Objective& objective, const std::vector<Profile>& profiles,
                         double best_chi2, double threshold, std::size_t last,
                         BoundUncertainty* out);
// A first start read off the data (box coordinates of the free parameters).
std::vector<double> DataInformedStart(const Objective& objective);

// One end of a profile-likelihood interval (fit_profile.cpp): its box
// coordinate (NaN: open or not trustworthy) and how far it can be trusted.
struct ProfileEdge {
  double x = NAN;
  IntervalStatus status = IntervalStatus::kReliable;
  std::string reason;  // empty when reliable
};
// The profile of one free parameter (index k into the free ones) with the
// others re-optimized, and the ends of its 95% interval.
struct ProfileRun {
  int k = 0;
  Profile profile;
  ProfileEdge low, high;
  int evaluations = 0, failures = 0;
};
// One local search of the multi-start stage and what it cost the objective.
struct StartRun {
  LocalResult result;
  int evaluations = 0, failures = 0;
  std::string last_failure;  // the objective's after this search, when it failed at all
};
// A fit's work over the ranks of a job (fit_ranks.cpp, FitOptions::ranks).
// Throws Error (kInternal, on that rank) when a rank's optimum, full vector
// or threshold differs from rank 0's in any bit (the dealt profiles would not
// fit together).
void CheckSameOptimum(parallel::Communicator& ranks, const LocalResult& best,
                      const std::vector<double>& full, double threshold);
// Each rank's own runs (those of index q with OwnerOf(q) == its rank) to
// every rank, into `runs` (same length on every rank).
void ShareProfileRuns(parallel::Communicator& ranks, std::vector<ProfileRun>& runs);
// The same for the multi-start searches; the others' evaluations, failures
// and last failure are added to `objective` in start order, as if it had
// made them.
void ShareStartRuns(parallel::Communicator& ranks, std::vector<StartRun>& runs,
                    const Objective& objective);
// Profiles of the free parameters `ks` (side by side; over options.ranks
// when set, each rank running its share), at the optimum `best`
// (box coordinates; `full` its physical vector), with the interval threshold
// Delta chi^2 = `threshold`; `lower_side` false: only the upper ends.
// `covariance`: the Jacobian covariance of the free parameters (physical;
// may be null), which seeds each end's search and each point's start.
std::vector<ProfileRun> RunProfiles(const ForwardModel& model, const laws::LawShape& shape,
                                    const FitData& data, const FitOptions& options,
                                    const std::vector<int>& ks, const LocalResult& best,
                                    const std::vector<double>& full, double threshold,
                                    bool lower_side, const Eigen::MatrixXd* covariance = nullptr);


// The order of convergence from two successive differences (fine: r h to
// h, coarse: r^2 h to r h; any common scaling), the order used (at most
// the model's asymptotic one) and the Richardson denominator r^p - 1
// (model_error.cpp). `problem`: why the coarse difference is missing.
struct OrderChoice {
  bool observed = false;
  bool no_difference = false;  // the coarser solve agrees with the fine one
  double observed_order = NAN;
  double order = NAN;
  double denominator = 1.0;
  std::string problem;
};
OrderChoice ChooseOrder(const std::vector<double>& fine, const std::vector<double>& coarse,
                        const std::string& problem, const ModelErrorOptions& options);
// The rows a fit kept (its outliers left out), model_error.cpp.
FitData RowsUsed(const FitData& data, const FitSummary& fit);
// The parameters a fit's answer rests on (`at`, SI) and which the data
// decided (the free ones of the returned options): every free one with
// bridging; without, J_tip,c of a load-displacement fit only.
FitOptions AnswerParameters(const FitOptions& options, const FitSummary& fit,
                            std::array<double, kParameterCount>* at);
// The model's prediction at the data (R or load); empty when the run failed
// (the message in `why`), model_error.cpp.
std::vector<double> PredictAt(const ForwardModel& model, const laws::LawShape& shape,
                              const LawParameters& p, const FitData& data, std::string* why);
// rms and largest |bias_i| / (u_i s), s^2 = `scale2` (u = 1 where the data
// carry no uncertainties): a predicted output bias in noise standard
// deviations (with the data's own uncertainties, s = 1), model_error.cpp.
std::array<double, 2> NoiseRelative(const std::vector<double>& bias, const FitData& data,
                                    double scale2);

}  // namespace bridgefit::inverse::fit_internal
