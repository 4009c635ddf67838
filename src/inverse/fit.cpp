#include "bridgefit/inverse/fit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <random>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/parallel/communicator.hpp"
#include "fit_impl.hpp"
#include "fit_shape_impl.hpp"

namespace bridgefit::inverse {

using namespace fit_internal;

namespace {

// Restarts of the local search from a profile point below the optimum.
constexpr int kProfileRestarts = 2;

// A profile's ends and checks into its parameter's estimate: an end that
// cannot be trusted is NaN (open), never the optimum itself.
void ApplyProfile(const ProfileRun& run, bool lower_side, const FitOptions& options,
                  ParameterEstimate& e) {
  const Profile& profile = run.profile;
  const int index = profile.parameter;
  auto end = [&](const ProfileEdge& edge) {
    return std::isnan(edge.x) ? NAN : FromBox(index, edge.x, options);
  };
  if (lower_side) e.ci95_low = end(run.low);
  e.ci95_high = end(run.high);
  e.interval_status = profile.status;
  e.interval_reason = profile.status_reason;
  const bool open_low = lower_side && run.low.status == IntervalStatus::kOpen;
  const bool open_high = run.high.status == IntervalStatus::kOpen;
  if (profile.status == IntervalStatus::kOpen) {
    e.identified = false;
    e.note = fmt::format("profile likelihood flat {} over the range explored ({:.4g} .. {:.4g})",
                         open_low && open_high ? "on both sides"
                         : open_high           ? "above the optimum"
                                               : "below the optimum",
                         options.lower[index], options.upper[index]);
    e.interval_reason = e.note;
  } else if (profile.status == IntervalStatus::kEndsOnBound) {
    e.identified = false;
    e.note = "interval ends on the box edge: " + profile.status_reason;
  } else if (profile.status != IntervalStatus::kReliable) {
    // The value is still the best fit found; its interval is not trusted.
    e.identified = !open_low && !open_high;
    e.note = "interval unreliable (" + std::string(IntervalStatusName(profile.status)) +
             "): " + profile.status_reason;
    if (std::isfinite(e.ci95_low) || std::isfinite(e.ci95_high))
      e.note = (lower_side ? "CI from the profile likelihood, "
                           : "CI: Jacobian below, profile likelihood above, ") + e.note;
  } else {
    e.identified = true;
    e.note = lower_side ? "CI from the profile likelihood"
                        : "CI: Jacobian below, profile likelihood above";
  }
}

// Stage 1: multi-start local searches from a Latin-hypercube design (one
// start for the global optimizers); every start into s.starts, the lowest
// (the first of equals) returned.
LocalResult MultiStartSearch(const FitContext& c, FitSummary& s) {
  const FitOptions& options = c.options;
  const Objective& objective = c.objective;
  const std::vector<int>& free = c.free;
  const int n_free = c.n_free;
  const bool load_fit = c.load_fit;
  Progress progress("fit", static_cast<size_t>(options.starts), options.progress);
  const bool global = options.optimizer == Optimizer::kDirect || options.optimizer == Optimizer::kCrs2;
  const int starts = global ? 1 : options.starts;
  auto design = LatinHypercube(starts, n_free, options.seed);
  if (global) design[0].assign(n_free, 0.5);
  else design[0] = DataInformedStart(objective);
  if (!load_fit && std::isfinite(options.initial[free[0]])) {
    for (int i = 0; i < n_free; ++i) {
      design[0][i] = ToBox(free[i], options.initial[free[i]], options);
    }
  }
  // The starts are independent: over ranks (options.ranks), start k on
  // rank k mod N, then every rank gets every start.
  parallel::Communicator* ranks =
      options.ranks && options.ranks->size() > 1 ? options.ranks : nullptr;
  std::vector<StartRun> runs(starts);
  for (int k = 0; k < starts; ++k) {
    if (ranks && ranks->OwnerOf(k) != ranks->rank()) continue;
    const int budget = global ? options.max_evaluations * options.starts : options.max_evaluations;
    const int evaluations = objective.evaluations(), failures = objective.failures();
    runs[k].result = MinimizeLocal(objective, options.optimizer, design[k], budget);
    runs[k].evaluations = objective.evaluations() - evaluations;
    runs[k].failures = objective.failures() - failures;
    if (runs[k].failures > 0) runs[k].last_failure = objective.last_failure();
    progress.Update(static_cast<size_t>(k + 1));
  }
  if (ranks) ShareStartRuns(*ranks, runs, objective);
  LocalResult best;
  for (int k = 0; k < starts; ++k) {
    const LocalResult& r = runs[k].result;
    StartResult start;
    for (int i = 0; i < n_free; ++i) {
      start.start[free[i]] = FromBox(free[i], design[k][i], options);
      start.end[free[i]] = FromBox(free[i], r.x[i], options);
    }
    start.cost = r.chi2;
    start.evaluations = r.evaluations;
    start.stop_reason = r.stop_reason;
    s.starts.push_back(start);
    if (r.chi2 < best.chi2) best = r;
  }
  progress.Finish();
  return best;
}

// Stage 2: residuals beyond the threshold in robust standard deviations are
// outliers; with at most a fifth of the points among them, the fit is re-run
// without them (its summary lists them). In an R-curve fit, outliers two or
// more in a row on the same side of the model are a misfit, not gross
// errors: they stay, and `misfit` describes them. nullopt: no refit.
std::optional<FitSummary> RefitWithoutOutliers(const FitContext& c, const std::vector<double>& residuals,
                                               const Stopwatch& clock, MisfitRun& misfit) {
  if (!(c.options.outlier_threshold > 0.0)) return std::nullopt;  // the check is off
  const ForwardModel& model = c.model;
  const laws::LawShape& shape = c.shape;
  const FitData& data = c.data;
  const FitOptions& options = c.options;
  const Objective& objective = c.objective;
  const int m = c.m;
  const bool weighted = c.weighted;
  const bool load_fit = c.load_fit;
  std::vector<double> magnitude(m);
  for (int i = 0; i < m; ++i) magnitude[i] = std::abs(residuals[i]);
  std::vector<double> sorted = magnitude;
  std::nth_element(sorted.begin(), sorted.begin() + m / 2, sorted.end());
  const double robust_sd = 1.4826 * sorted[m / 2];
  const double limit = options.outlier_threshold * std::max(robust_sd, weighted ? 1.0 : 1e-300);
  const auto beyond = [&](int i) { return i >= 0 && i < m && magnitude[i] > limit; };
  const auto same_side = [&](int i, int j) { return (residuals[i] > 0) == (residuals[j] > 0); };
  std::vector<int> keep;
  std::vector<double> removed_a, removed_R;
  for (int i = 0; i < m; ++i) {
    const bool in_run = !load_fit && beyond(i) &&
                        ((beyond(i - 1) && same_side(i - 1, i)) || (beyond(i + 1) && same_side(i, i + 1)));
    if (in_run) {
      const int side = residuals[i] > 0 ? -1 : +1;  // r = model - data
      misfit.side = misfit.points == 0 || misfit.side == side ? side : 0;
      ++misfit.points;
      misfit.crack_length_from = std::fmin(misfit.crack_length_from, data.crack_length[i]);
      misfit.crack_length_to = std::fmax(misfit.crack_length_to, data.crack_length[i]);
      misfit.largest_sd = std::fmax(misfit.largest_sd, magnitude[i] / std::max(robust_sd, 1e-300));
    }
    if (magnitude[i] <= limit || in_run) {
      keep.push_back(i);
    } else if (load_fit) {
      removed_a.push_back(data.displacement[i]);
      removed_R.push_back(data.load[i]);
    } else {
      removed_a.push_back(data.crack_length[i]);
      removed_R.push_back(data.R[i]);
    }
  }
  if (!removed_a.empty() && removed_a.size() * 5 <= static_cast<size_t>(m)) {
    FitOptions again = options;
    again.outlier_threshold = 0.0;
    FitSummary refit = FitBridgingLaw(model, shape, data.Subset(keep), again);
    refit.outlier_crack_lengths = removed_a;
    refit.outlier_R = removed_R;
    refit.evaluations += objective.evaluations();
    refit.failed_evaluations += objective.failures();
    refit.wall_s = clock.Seconds();
    refit.verdict += fmt::format("; {} outlier(s) removed (residual > {:g} robust SD)",
                                 removed_a.size(), options.outlier_threshold);
    return refit;
  }
  return std::nullopt;
}

// A run of misfit points (stage 2) into the summary: the verdict says so and
// every estimated interval is marked unreliable with the reason.
void MarkMisfit(const MisfitRun& misfit, FitSummary& s) {
  if (misfit.points == 0) return;
  s.misfit = misfit;
  const std::string why = misfit.Describe();
  s.verdict += "; " + why;
  for (ParameterEstimate* e : {&s.sigma_c, &s.J_B, &s.delta_c, &s.J_tip_c}) {
    if (e->fixed || !std::isfinite(e->value) || e->interval_status != IntervalStatus::kReliable) continue;
    e->interval_status = IntervalStatus::kUnreliableMisfit;
    e->interval_reason = why;
    e->note += (e->note.empty() ? "" : "; ") + std::string("interval unreliable (") +
               IntervalStatusName(e->interval_status) + ")";
  }
}

// sum r_i r_(i+1) / sum r_i^2; NaN for fewer than 3 values or all zero.
double LagOneAutocorrelation(const std::vector<double>& r) {
  if (r.size() < 3) return NAN;
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    den += r[i] * r[i];
    if (i + 1 < r.size()) num += r[i] * r[i + 1];
  }
  return den > 0.0 ? num / den : NAN;
}

constexpr double kOneSided95 = 1.645;  // standard normal quantile

// Stage 3: the optimum's curves and residuals into the summary. Returns the
// noise scale s^2 of the intervals and tests.
double RecordOptimum(const FitContext& c, const LocalResult& best, const ForwardPrediction& prediction,
                     FitSummary& s) {
  const FitData& data = c.data;
  const int n_free = c.n_free;
  const int m = c.m;
  const bool weighted = c.weighted;
  const bool load_fit = c.load_fit;
  s.chi2 = best.chi2;
  s.fitted_crack_length = load_fit ? prediction.crack_length_physical : data.crack_length;
  s.fitted_R = load_fit ? prediction.R_physical : prediction.R;
  s.fitted_delta_root = prediction.delta_root;
  if (load_fit) {
    s.fitted_displacement = data.displacement;
    s.fitted_record_load = data.load;
    s.fitted_load = prediction.load;
  }
  const std::vector<double>& values = load_fit ? data.load : data.R;
  const std::vector<double>& model_values = load_fit ? prediction.load : prediction.R;
  const std::vector<double>& u = load_fit ? data.load_uncertainty : data.R_uncertainty;
  double sum_sq = 0.0;
  std::vector<double> scaled(m);
  for (int i = 0; i < m; ++i) {
    sum_sq += std::pow(model_values[i] - values[i], 2);
    scaled[i] = (model_values[i] - values[i]) / (weighted ? u[i] : 1.0);
  }
  s.rms_residual = std::sqrt(sum_sq / m);
  // Without reported uncertainties the noise scale comes from the residuals.
  const int dof = std::max(1, m - n_free);
  // With reported uncertainties a reduced chi^2 above 1 says they miss part
  // of the scatter (model error, an effect the model lacks, as on a real
  // record): the intervals and tests are widened by it (Birge ratio), never
  // narrowed below what the uncertainties give.
  s.reduced_chi2 = best.chi2 / dof;
  const double birge = weighted ? std::max(1.0, s.reduced_chi2) : std::max(s.reduced_chi2, 1e-300);
  // Residuals in data order (crack length, or the record's rows) that run
  // in long same-sign stretches carry fewer independent pieces than points:
  // errors shared by neighbours (a smoothed record, overlapping increments)
  // or a smooth misfit the model cannot follow. An AR(1) sequence with
  // lag-1 correlation rho has the variance of a mean, and so of each
  // estimate, (1 + rho) / (1 - rho) times the independent one; s^2 is
  // multiplied by that where rho is significant (> 2 / sqrt(m), the 95%
  // limit of an uncorrelated sequence's), the effective number of points
  // kept >= free parameters + 2.
  s.residual_autocorrelation = LagOneAutocorrelation(scaled);
  s.interval_inflation = 1.0;
  const double rho = s.residual_autocorrelation;
  if (std::isfinite(rho) && rho > 2.0 / std::sqrt(static_cast<double>(m)) && m > n_free + 2)
    s.interval_inflation = std::min((1.0 + rho) / std::max(1.0 - rho, 1e-12),
                                    static_cast<double>(m) / (n_free + 2));
  s.noise_scale2 = birge * s.interval_inflation;
  return s.noise_scale2;
}

// Stage 4: covariance from the Jacobian, C = s^2 (J^T J)^-1: every
// parameter's value and a first interval.
Eigen::MatrixXd JacobianIntervals(const FitContext& c, const std::vector<double>& full,
                                  double scale2, FitSummary& s) {
  const FitOptions& options = c.options;
  const Objective& objective = c.objective;
  const std::vector<int>& free = c.free;
  const int n_free = c.n_free;
  Eigen::MatrixXd jacobian;
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Constant(n_free, n_free, NAN);
  if (PhysicalJacobian(objective, full, &jacobian)) {
    const Eigen::MatrixXd jtj = jacobian.transpose() * jacobian;
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(jtj);
    const double cond = svd.singularValues()(0) / std::max(svd.singularValues()(n_free - 1), 1e-300);
    if (cond < 1e12) covariance = scale2 * jtj.inverse();
  }
  for (int i = 0; i < kParameterCount; ++i) {
    ParameterEstimate& e = EstimateOf(s, i);
    e.value = full[i];
    e.fixed = options.fixed[i];
    e.decided_by = e.fixed ? "fixed by the user" : s.optimizer + " + " + s.model;
  }
  for (int k = 0; k < n_free; ++k) {
    ParameterEstimate& e = EstimateOf(s, free[k]);
    const double sd = std::sqrt(covariance(k, k));
    e.ci95_low = e.value - 1.96 * sd;
    e.ci95_high = e.value + 1.96 * sd;
    e.identified = std::isfinite(sd);
    e.note = std::isfinite(sd) ? "CI from the Jacobian covariance" : "singular Jacobian";
  }
  return covariance;
}

// Stage 5: profile likelihood per free parameter, the others re-optimized:
// the 95% interval edges are found by stepping out from the optimum in the
// box coordinate until Delta chi^2 > threshold, then bisecting.
void ProfileIntervals(const FitContext& c, const LocalResult& best, const std::vector<double>& full,
                      double threshold, const Eigen::MatrixXd& covariance, FitSummary& s) {
  const ForwardModel& model = c.model;
  const laws::LawShape& shape = c.shape;
  const FitData& data = c.data;
  const FitOptions& options = c.options;
  const Objective& objective = c.objective;
  const std::vector<int>& free = c.free;
  const int n_free = c.n_free;
  // J_B's profile decides identifiability (steady state in the window):
  // it always runs; the others only when asked for. Without full profiles
  // only J_B's upper side is needed; its lower limit stays the Jacobian one.
  std::vector<int> ks;
  for (int k = 0; k < n_free; ++k)
    if (options.profile_likelihood || free[k] == kJB) ks.push_back(k);
  const bool lower_side = options.profile_likelihood;
  std::vector<ProfileRun> runs =
      RunProfiles(model, shape, data, options, ks, best, full, threshold, lower_side, &covariance);
  for (ProfileRun& run : runs) {
    objective.AddCounts(run.evaluations, run.failures);
    ApplyProfile(run, lower_side, options, EstimateOf(s, free[run.k]));
    s.profiles.push_back(std::move(run.profile));
  }
}

// Stage 7: steady state in the data? The fitted model must reach it inside
// the data window, with the J_B profile bounded above; delta_c from J_B and
// sigma_c, and the PHYSICS 7 bounds when it is not reached.
void SteadyStateAndBounds(const FitContext& c, const LocalResult& best, const std::vector<double>& full,
                          const ForwardPrediction& prediction, double threshold,
                          const Eigen::MatrixXd& covariance, FitSummary& s) {
  const laws::LawShape& shape = c.shape;
  const FitData& data = c.data;
  const FitOptions& options = c.options;
  const Objective& objective = c.objective;
  const int m = c.m;
  // The data's axis may be an equivalent crack length (R kind as-data): the
  // model's physical crack length and R behind each point then decide.
  // A record's last row need not hold its longest crack (an unloading tail):
  // the bounds are read at the row whose model crack is the longest.
  const bool physical = !prediction.crack_length_physical.empty();
  const std::size_t last =
      physical ? static_cast<std::size_t>(std::max_element(prediction.crack_length_physical.begin(),
                                                           prediction.crack_length_physical.end()) -
                                          prediction.crack_length_physical.begin())
               : data.crack_length.size() - 1;
  const double a_max = physical ? prediction.crack_length_physical[last] : data.crack_length[last];
  const Profile* jb_profile = nullptr;
  for (const auto& p : s.profiles)
    if (p.parameter == kJB) jb_profile = &p;
  // Steady state is established by the data only when every statistically
  // acceptable parameter set reaches it inside the window: check the best
  // fit and the largest J_B inside the profile's 95% region.
  auto reaches_in_window = [&](const ForwardPrediction& p) {
    int past = 0;
    const std::vector<double>& axis = p.crack_length_physical.empty() ? data.crack_length
                                                                      : p.crack_length_physical;
    if (!p.past_steady_state.empty())
      past = static_cast<int>(std::count(p.past_steady_state.begin(), p.past_steady_state.end(), 1));
    else if (p.steady_state_reached)
      for (double a : axis) past += a >= p.steady_state_crack_length;
    return p.steady_state_reached && past >= 3;
  };
  bool reached = reaches_in_window(prediction);
  if (reached && jb_profile) {
    if (std::isnan(s.J_B.ci95_high)) reached = false;  // flat, or an end not trusted
    const ProfilePoint* largest = nullptr;
    for (const auto& point : jb_profile->points)
      if (point.ok && point.chi2 - best.chi2 <= threshold && (!largest || point.value > largest->value))
        largest = &point;
    if (reached && largest) {
      std::vector<double> r(m);
      ForwardPrediction edge;
      const std::vector<double> at(largest->parameters.begin(), largest->parameters.end());
      if (objective.Residuals(at, r.data(), &edge)) reached = reaches_in_window(edge);
    }
  }
  s.steady_state_reached = reached;
  s.steady_state_crack_length = s.steady_state_reached ? prediction.steady_state_crack_length : NAN;

  const double k_area = shape.Area();
  if (full[kSigmaC] > 0 && full[kJB] > 0) s.delta_c.value = full[kJB] / (k_area * full[kSigmaC]);
  s.delta_c.decided_by = s.J_B.decided_by;
  if (!options.fixed[kJB] && !options.fixed[kSigmaC] && s.J_B.identified && s.sigma_c.identified &&
      std::isfinite(s.J_B.ci95_low) && std::isfinite(s.J_B.ci95_high)) {
    // delta_c = J_B / (k sigma_c): the extremes of the two intervals (conservative).
    s.delta_c.ci95_low = s.J_B.ci95_low / (k_area * s.sigma_c.ci95_high);
    s.delta_c.ci95_high = s.J_B.ci95_high / (k_area * s.sigma_c.ci95_low);
    s.delta_c.identified = true;
    s.delta_c.note = "from J_B / (k sigma_c), interval from the extremes of both";
  }

  if (!s.steady_state_reached && !options.fixed[kJB]) {
    // PHYSICS 7: bounds from the last valid point, never point values.
    const double J_tip = full[kJTipC];
    // R_max as the elastic-zone R (BridgingRise: an energy R also holds the
    // back-face effects and can exceed J_tip,c + J_B).
    const double R_max = J_tip + BridgingRise(c.objective, full, prediction, last);
    s.bounds = laws::BoundsFromTruncatedCurve(R_max, J_tip, prediction.delta_root[last], a_max);
    // The fitted R_max and J_tip,c carry the noise: a bound read off them
    // can lie above the truth (issue 19's W = 50 mm CT: 824 and 1118 against
    // J_B = 500 J/m^2). Each bound is lowered to the lesser of its one-sided
    // 95% lower confidence limit (1.645 standard uncertainties, delta
    // method) and its least value over the laws the profiles accept (the
    // linearisation misses a curved region: 585 against 500 on its own).
    BoundUncertainty u = TruncationBoundUncertainty(c.objective, full, covariance, last);
    ProfileBoundMinimum(c.objective, s.profiles, best.chi2, threshold, last, &u);
    const double J_B_linear = std::isfinite(u.J_B_sd) ? s.bounds.J_B_lower - kOneSided95 * u.J_B_sd : NAN;
    const double delta_c_linear =
        std::isfinite(u.delta_c_sd) ? s.bounds.delta_c_lower - kOneSided95 * u.delta_c_sd : NAN;
    std::string lowered = " (not lowered by its uncertainty: no finite covariance or profile)";
    if (std::isfinite(J_B_linear) || std::isfinite(u.J_B_profile_min)) {
      const double J_B_low = std::fmin(J_B_linear, u.J_B_profile_min);
      lowered = fmt::format(", lowered to {:.4g} for its uncertainty (one-sided 95%: the lesser of "
                            "1.645 standard uncertainties below and the profiles' least)",
                            std::max(0.0, J_B_low));
      s.bounds.J_B_lower = std::max(0.0, std::fmin(s.bounds.J_B_lower, J_B_low));
    }
    if (std::isfinite(delta_c_linear) || std::isfinite(u.delta_c_profile_min))
      s.bounds.delta_c_lower = std::max(
          0.0, std::fmin(s.bounds.delta_c_lower, std::fmin(delta_c_linear, u.delta_c_profile_min)));
    const std::string evidence = fmt::format(
        "steady state not reached by a = {:.4g} mm: J_B >= R_max - J_tip,c = {:.4g} - {:.4g}{}",
        a_max * 1e3, R_max, J_tip, lowered);
    s.J_B = {.lower_bound = s.bounds.J_B_lower, .identified = false,
             .decided_by = "PHYSICS 7 bound from the fitted R at the last point", .note = evidence};
    s.delta_c = {.lower_bound = s.bounds.delta_c_lower, .identified = false,
                 .decided_by = "PHYSICS 7 bound: fitted notch-root COD at the last point",
                 .note = fmt::format("delta_c >= delta_root({:.4g} mm) = {:.4g} mm at the fit{}",
                                     a_max * 1e3, prediction.delta_root[last] * 1e3,
                                     s.bounds.delta_c_lower < prediction.delta_root[last]
                                         ? fmt::format(", lowered to {:.4g} mm for its uncertainty "
                                                       "(one-sided 95%)",
                                                       s.bounds.delta_c_lower * 1e3)
                                         : "")};
    s.verdict = fmt::format(
        "steady state not reached within the data (a <= {:.4g} mm): sigma_c estimated from the "
        "rising R curve; J_B and delta_c are lower bounds (PHYSICS 7)", a_max * 1e3);
  } else {
    s.verdict = s.steady_state_reached
                    ? fmt::format("steady state reached at a = {:.4g} mm: all parameters estimated",
                                  s.steady_state_crack_length * 1e3)
                    : "J_B fixed by the user";
  }
}

}  // namespace

FitSummary FitBridgingLaw(const ForwardModel& model, const laws::LawShape& shape,
                          const FitData& data, const FitOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid fit options: " + why);
  data.Validate();
  const Stopwatch clock;
  const Objective objective(model, shape, data, options);
  const FitContext c{model, shape, data, options, objective, objective.free(),
                     static_cast<int>(objective.free().size()), static_cast<int>(data.size()),
                     data.weighted(), data.target == FitTarget::kLoad};

  FitSummary s;
  s.target = data.target;
  s.model = model.Name();
  s.optimizer = OptimizerName(options.optimizer);
  s.law = std::string(laws::LawFamilyName(shape.family));
  s.data_points = c.m;
  auto finish = [&]() {
    s.evaluations = objective.evaluations();
    s.failed_evaluations = objective.failures();
    s.wall_s = clock.Seconds();
    return s;
  };

  LocalResult best = MultiStartSearch(c, s);
  s.converged = best.converged && best.chi2 < kFailedCost;
  s.stop_reason = best.stop_reason;
  if (best.chi2 >= kFailedCost) {
    s.converged = false;
    s.stop_reason = "every forward run failed: " + objective.last_failure();
    s.verdict = "fit failed: no parameter set gave a valid forward run";
    return finish();
  }
  // Stages 2-6 from the optimum; again from a restart's better one.
  std::vector<ProfilePoint> earlier;  // the profile points of the rounds before
  for (int round = 0;; ++round) {
    const std::vector<double> full = objective.Expand(best.x.data());
    for (int i = 0; i < kParameterCount; ++i) s.best_parameters[i] = full[i];
    std::vector<double> residuals(c.m);
    ForwardPrediction prediction;
    objective.Residuals(full, residuals.data(), &prediction);

    MisfitRun misfit;
    if (std::optional<FitSummary> refit = RefitWithoutOutliers(c, residuals, clock, misfit)) {
      MarkMisfit(misfit, *refit);
      return *refit;
    }
    s.sigma_c = s.J_B = s.delta_c = s.J_tip_c = ParameterEstimate{};
    s.profiles.clear();
    const double scale2 = RecordOptimum(c, best, prediction, s);
    const Eigen::MatrixXd covariance = JacobianIntervals(c, full, scale2, s);
    const double threshold = 3.84 * scale2;
    ProfileIntervals(c, best, full, threshold, covariance, s);
    if (round < kProfileRestarts) {
      if (std::optional<LocalResult> better = RestartFromProfiles(c, best, threshold, s)) {
        for (const Profile& profile : s.profiles)
          earlier.insert(earlier.end(), profile.points.begin(), profile.points.end());
        best = *better;
        s.converged = best.converged;
        s.stop_reason = best.stop_reason + " (after a restart from a profile point)";
        continue;
      }
    }
    WidenToEarlierPoints(c, earlier, best.chi2, threshold, s);
    if (!RecordNoBridging(c, best, full, prediction, scale2, s))
      SteadyStateAndBounds(c, best, full, prediction, threshold, covariance, s);
    MarkMisfit(misfit, s);
    return finish();
  }
}

std::vector<LawComparison> CompareLawFamilies(const ForwardModel& model,
                                              const std::vector<laws::LawShape>& shapes,
                                              const FitData& data, const FitOptions& options) {
  std::vector<LawComparison> out;
  for (const laws::LawShape& shape : shapes) {
    LawComparison c;
    c.law = std::string(laws::LawFamilyName(shape.family));
    c.shape = shape;
    c.summary = FitBridgingLaw(model, shape, data, options);
    out.push_back(std::move(c));
  }
  const double scale2 = shape_internal::SeedScale(data, out);
  for (auto& c : out) {
    c.noise_scale2 = scale2;
    if (!c.summary.converged) continue;
    const int k = c.summary.bridging_detected
                      ? static_cast<int>(std::count(options.fixed.begin(), options.fixed.end(), false))
                      : (options.fixed[kJTipC] ? 0 : 1);
    const int n = c.summary.data_points;
    c.parameters = k;
    // Too few points for the small-sample term: AIC alone (as always for these families).
    c.aicc = n - k - 1 > 0 ? shape_internal::Aicc(c.summary.chi2 / scale2, k, n)
                           : c.summary.chi2 / scale2 + 2.0 * k;
  }
  RankByAicc(out);
  return out;
}

}  // namespace bridgefit::inverse
