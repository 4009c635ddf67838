#include "bridgefit/inverse/fit.hpp"

#include <ceres/ceres.h>
#include <nlopt.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"

namespace bridgefit::inverse {
namespace {

constexpr double kFailedCost = 1e30;  // chi^2 of a failed forward run (infeasible)

// sigma_c and J_B span decades: their box coordinate is logarithmic.
bool IsLogScale(int index) { return index == kSigmaC || index == kJB; }

double FromBox(int index, double x, const FitOptions& o) {
  const double lo = o.lower[index], hi = o.upper[index];
  x = std::clamp(x, 0.0, 1.0);
  return IsLogScale(index) ? lo * std::pow(hi / lo, x) : lo + x * (hi - lo);
}
// The inverse of FromBox, clamped to the box.
double ToBox(int index, double value, const FitOptions& o) {
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

// Ceres functor: residuals of the free box coordinates (numeric derivatives).
struct CeresResiduals {
  const Objective* objective;
  int pinned = -1;
  double pinned_value = 0.0;
  bool operator()(double const* const* x, double* residuals) const {
    return objective->Residuals(objective->Expand(x[0], pinned, pinned_value), residuals);
  }
};

struct LocalResult {
  std::vector<double> x;
  double chi2 = kFailedCost;
  int evaluations = 0;
  std::string stop_reason;
  bool converged = false;
};

std::string NloptReason(nlopt::result r) {
  switch (r) {
    case nlopt::SUCCESS: return "success";
    case nlopt::STOPVAL_REACHED: return "stop value reached";
    case nlopt::FTOL_REACHED: return "function tolerance reached";
    case nlopt::XTOL_REACHED: return "parameter tolerance reached";
    case nlopt::MAXEVAL_REACHED: return "evaluation limit reached";
    case nlopt::MAXTIME_REACHED: return "time limit reached";
    default: return "failed (" + std::to_string(static_cast<int>(r)) + ")";
  }
}

nlopt::algorithm NloptAlgorithm(Optimizer o) {
  switch (o) {
    case Optimizer::kBobyqa: return nlopt::LN_BOBYQA;
    case Optimizer::kNelderMead: return nlopt::LN_NELDERMEAD;
    case Optimizer::kCobyla: return nlopt::LN_COBYLA;
    case Optimizer::kDirect: return nlopt::GN_DIRECT_L;
    case Optimizer::kCrs2: return nlopt::GN_CRS2_LM;
    case Optimizer::kCeresLm: break;
  }
  return nlopt::LN_BOBYQA;
}

// Minimizes chi^2 over the free box coordinates (one of them may be pinned).
LocalResult MinimizeNlopt(const Objective& objective, Optimizer optimizer, std::vector<double> x0,
                          int max_evaluations, int pinned = -1, double pinned_value = 0.0,
                          double xtol = 0.0) {
  const int n = static_cast<int>(x0.size());
  LocalResult result;
  const int before = objective.evaluations();
  struct Context {
    const Objective* objective;
    int pinned;
    double pinned_value;
  } context{&objective, pinned, pinned_value};
  auto f = [](unsigned, const double* x, double*, void* data) -> double {
    const auto* c = static_cast<const Context*>(data);
    return c->objective->Chi2(c->objective->Expand(x, c->pinned, c->pinned_value));
  };
  // CRS2 (and MLSL-like methods) draw random points: seed NLopt's generator
  // so a fit is reproducible.
  if (optimizer == Optimizer::kCrs2) nlopt::srand(objective.options().seed);
  nlopt::opt opt(NloptAlgorithm(optimizer), static_cast<unsigned>(n));
  opt.set_lower_bounds(std::vector<double>(n, 0.0));
  opt.set_upper_bounds(std::vector<double>(n, 1.0));
  opt.set_min_objective(f, &context);
  const bool global = optimizer == Optimizer::kDirect || optimizer == Optimizer::kCrs2;
  if (!global) {  // a global search runs to its budget
    opt.set_xtol_rel(xtol > 0.0 ? xtol : objective.options().relative_tolerance);
    opt.set_ftol_rel(1e-10);
  }
  opt.set_maxeval(max_evaluations);
  if (optimizer == Optimizer::kBobyqa || optimizer == Optimizer::kNelderMead ||
      optimizer == Optimizer::kCobyla)
    opt.set_initial_step(std::vector<double>(n, 0.05));
  double value = kFailedCost;
  try {
    const nlopt::result r = opt.optimize(x0, value);
    result.stop_reason = NloptReason(r);
    result.converged = r == nlopt::SUCCESS || r == nlopt::FTOL_REACHED ||
                       r == nlopt::XTOL_REACHED || r == nlopt::STOPVAL_REACHED ||
                       (global && r == nlopt::MAXEVAL_REACHED);
  } catch (const std::exception& e) {
    result.stop_reason = std::string("nlopt stopped: ") + e.what();
  }
  result.x = x0;
  result.chi2 = value;
  result.evaluations = objective.evaluations() - before;
  return result;
}

LocalResult MinimizeCeres(const Objective& objective, std::vector<double> x0, int max_evaluations,
                          int pinned = -1, double pinned_value = 0.0) {
  const int n = static_cast<int>(x0.size());
  const int m = static_cast<int>(objective.data().size());
  LocalResult result;
  const int before = objective.evaluations();
  // Forward differences: n + 1 forward runs per Jacobian instead of 2 n + 1.
  auto* cost = new ceres::DynamicNumericDiffCostFunction<CeresResiduals, ceres::FORWARD>(
      new CeresResiduals{&objective, pinned, pinned_value});
  cost->AddParameterBlock(n);
  cost->SetNumResiduals(m);
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, x0.data());
  for (int i = 0; i < n; ++i) {
    problem.SetParameterLowerBound(x0.data(), i, 0.0);
    problem.SetParameterUpperBound(x0.data(), i, 1.0);
  }
  ceres::Solver::Options options;
  options.minimizer_type = ceres::TRUST_REGION;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = std::max(5, max_evaluations / (n + 2));
  // The forward models solve to ~1e-10: tighter tolerances only add runs.
  options.function_tolerance = 1e-9;
  options.parameter_tolerance = std::max(objective.options().relative_tolerance, 1e-7);
  options.gradient_tolerance = 1e-14;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  result.x = x0;
  result.chi2 = 2.0 * summary.final_cost;
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.stop_reason = summary.message;
  if (summary.termination_type == ceres::FAILURE || !std::isfinite(result.chi2))
    result.chi2 = kFailedCost;
  result.evaluations = objective.evaluations() - before;
  return result;
}

LocalResult MinimizeLocal(const Objective& objective, Optimizer optimizer,
                          const std::vector<double>& x0, int max_evaluations, int pinned = -1,
                          double pinned_value = 0.0) {
  if (optimizer == Optimizer::kCeresLm)
    return MinimizeCeres(objective, x0, max_evaluations, pinned, pinned_value);
  if (optimizer == Optimizer::kDirect || optimizer == Optimizer::kCrs2) {
    // Global search, then a local polish from its best point.
    LocalResult global = MinimizeNlopt(objective, optimizer, x0, max_evaluations, pinned, pinned_value);
    LocalResult polish =
        MinimizeNlopt(objective, Optimizer::kBobyqa, global.x, max_evaluations / 2, pinned, pinned_value);
    polish.evaluations += global.evaluations;
    polish.stop_reason = "global: " + global.stop_reason + "; polish: " + polish.stop_reason;
    return polish.chi2 <= global.chi2 ? polish : global;
  }
  return MinimizeNlopt(objective, optimizer, x0, max_evaluations, pinned, pinned_value);
}

// Latin-hypercube design in the unit box.
std::vector<std::vector<double>> LatinHypercube(int points, int dims, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::vector<double>> design(points, std::vector<double>(dims));
  for (int d = 0; d < dims; ++d) {
    std::vector<int> strata(points);
    std::iota(strata.begin(), strata.end(), 0);
    std::shuffle(strata.begin(), strata.end(), rng);
    for (int p = 0; p < points; ++p) design[p][d] = (strata[p] + unit(rng)) / points;
  }
  return design;
}

// Jacobian d r_i / d p_j of the physical free parameters (central differences).
bool PhysicalJacobian(const Objective& objective, const std::vector<double>& full,
                      Eigen::MatrixXd* jacobian) {
  const auto& free = objective.free();
  const int m = static_cast<int>(objective.data().size());
  jacobian->resize(m, static_cast<int>(free.size()));
  std::vector<double> plus(m), minus(m);
  for (size_t k = 0; k < free.size(); ++k) {
    const int j = free[k];
    const double h = 1e-4 * std::max(std::abs(full[j]), 1e-12);
    std::vector<double> p = full, q = full;
    p[j] += h;
    q[j] -= h;
    if (!objective.Residuals(p, plus.data()) || !objective.Residuals(q, minus.data())) return false;
    for (int i = 0; i < m; ++i) (*jacobian)(i, static_cast<int>(k)) = (plus[i] - minus[i]) / (2 * h);
  }
  return true;
}

// Sets full[index] to the best of 9 evenly spaced box points (chi^2 with the
// other parameters as they are in `full`).
void ScanBox(const Objective& objective, int index, std::vector<double>& full) {
  double best_chi2 = kFailedCost, best_value = full[index];
  for (int i = 0; i <= 8; ++i) {
    full[index] = FromBox(index, (i + 0.5) / 9.0, objective.options());
    const double chi2 = objective.Chi2(full);
    if (chi2 < best_chi2) best_chi2 = chi2, best_value = full[index];
  }
  full[index] = best_value;
}

// A first start read off the data: J_tip,c from the first points, J_B from
// the rise, and sigma_c from a coarse scan of the box (a few evaluations).
std::vector<double> DataInformedStart(const Objective& objective) {
  const FitData& data = objective.data();
  const FitOptions& o = objective.options();
  std::vector<double> full = objective.Expand(std::vector<double>(objective.free().size(), 0.5).data());
  if (data.target == FitTarget::kLoad) {
    // No R to read: J_tip,c and J_B from FitOptions::initial (an R-curve fit),
    // else J_tip,c from a scan of the box without bridging and J_B a fifth of it.
    if (!o.fixed[kJTipC] && std::isfinite(o.initial[kJTipC])) {
      full[kJTipC] = std::clamp(o.initial[kJTipC], o.lower[kJTipC], o.upper[kJTipC]);
    } else if (!o.fixed[kJTipC]) {
      std::vector<double> flat = full;
      flat[kJB] = 0.0;
      ScanBox(objective, kJTipC, flat);
      full[kJTipC] = flat[kJTipC];
    }
    if (!o.fixed[kJB])
      full[kJB] = std::clamp(std::isfinite(o.initial[kJB]) ? o.initial[kJB] : 0.2 * full[kJTipC],
                             o.lower[kJB], o.upper[kJB]);
  } else {
    const size_t head = std::min<size_t>(3, data.R.size());
    const double J_tip = *std::min_element(data.R.begin(), data.R.begin() + head);
    const double rise = *std::max_element(data.R.begin(), data.R.end()) - J_tip;
    if (!o.fixed[kJTipC]) full[kJTipC] = std::clamp(J_tip, o.lower[kJTipC], o.upper[kJTipC]);
    if (!o.fixed[kJB]) full[kJB] = std::clamp(std::max(rise, 0.05 * J_tip), o.lower[kJB], o.upper[kJB]);
  }
  const bool sigma_c_given = data.target == FitTarget::kLoad && std::isfinite(o.initial[kSigmaC]);
  if (!o.fixed[kSigmaC] && sigma_c_given)
    full[kSigmaC] = std::clamp(o.initial[kSigmaC], o.lower[kSigmaC], o.upper[kSigmaC]);
  else if (!o.fixed[kSigmaC])
    ScanBox(objective, kSigmaC, full);
  std::vector<double> x;
  for (int index : objective.free()) x.push_back(ToBox(index, full[index], o));
  return x;
}

ParameterEstimate& EstimateOf(FitSummary& s, int index) {
  return index == kSigmaC ? s.sigma_c : index == kJB ? s.J_B : s.J_tip_c;
}

}  // namespace

const char* ParameterName(int index) {
  static constexpr const char* kNames[] = {"sigma_c", "J_B", "J_tip_c"};
  return kNames[index];
}

const char* OptimizerName(Optimizer optimizer) {
  switch (optimizer) {
    case Optimizer::kCeresLm: return "ceres-lm";
    case Optimizer::kBobyqa: return "bobyqa";
    case Optimizer::kNelderMead: return "neldermead";
    case Optimizer::kCobyla: return "cobyla";
    case Optimizer::kDirect: return "direct";
    case Optimizer::kCrs2: return "crs2";
  }
  return "unknown";
}

Optimizer ParseOptimizer(const std::string& name) {
  for (Optimizer o : {Optimizer::kCeresLm, Optimizer::kBobyqa, Optimizer::kNelderMead,
                      Optimizer::kCobyla, Optimizer::kDirect, Optimizer::kCrs2})
    if (name == OptimizerName(o)) return o;
  throw Error(ErrorKind::kUsage, "unknown optimizer",
              {.field = "--optimizer", .value = name,
               .expected = "ceres-lm, bobyqa, neldermead, cobyla, direct or crs2"});
}

bool FitOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (starts < 1) return fail("starts must be >= 1");
  if (max_evaluations < 10) return fail("max_evaluations must be >= 10");
  if (threads < 0) return fail("threads must be >= 0");
  if (!(min_bridging_fraction >= 0.0 && min_bridging_fraction < 1.0))
    return fail("min_bridging_fraction must be in [0, 1)");
  for (int i = 0; i < kParameterCount; ++i) {
    if (fixed[i]) {
      if (!(fixed_value[i] >= 0.0) || !std::isfinite(fixed_value[i]))
        return fail(std::string("fixed ") + ParameterName(i) + " must be finite and >= 0");
      continue;
    }
    if (!(lower[i] > 0.0 && upper[i] > lower[i] && std::isfinite(upper[i])))
      return fail(std::string("bounds of ") + ParameterName(i) + " must satisfy 0 < low < high");
  }
  if (std::count(fixed.begin(), fixed.end(), false) == 0) return fail("every parameter is fixed");
  return true;
}

FitData FitData::FromRCurve(const RCurve& curve, RKind kind) {
  FitData data;
  data.crack_length = curve.crack_length;
  data.R = curve.R;
  // The fit weights by one standard uncertainty.
  BF_CHECK_INPUT(curve.uncertainty_coverage > 0.0, "the R uncertainty's coverage factor must be > 0",
                 {.field = "coverage_factor"});
  for (double u : curve.R_uncertainty) data.R_uncertainty.push_back(u / curve.uncertainty_coverage);
  data.kind = kind;
  {
    // An equivalent crack length from a noisy compliance is not monotone:
    // order the points by it (an R curve is R(a); the model's curve is
    // compared the same way).
    std::vector<std::size_t> order(data.R.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return data.crack_length[a] < data.crack_length[b];
    });
    FitData sorted;
    sorted.kind = kind;
    for (std::size_t i : order) {
      sorted.crack_length.push_back(data.crack_length[i]);
      sorted.R.push_back(data.R[i]);
      if (!data.R_uncertainty.empty()) sorted.R_uncertainty.push_back(data.R_uncertainty[i]);
    }
    data = std::move(sorted);
  }
  data.Validate();
  return data;
}

const char* FitTargetName(FitTarget target) {
  return target == FitTarget::kLoad ? "load-displacement" : "r-curve";
}

FitTarget ParseFitTarget(const std::string& name) {
  if (name == "r-curve") return FitTarget::kRCurve;
  if (name == "load-displacement") return FitTarget::kLoad;
  throw Error(ErrorKind::kUsage, "unknown fit target",
              {.field = "--fit-to", .value = name, .expected = "r-curve or load-displacement"});
}

FitData FitData::FromRecord(const ExperimentRecord& record, double load_noise,
                            double displacement_noise) {
  BF_CHECK_INPUT(load_noise >= 0.0 && displacement_noise >= 0.0,
                 "record noise must be >= 0", {.file = record.source, .field = "noise"});
  FitData data;
  data.target = FitTarget::kLoad;
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < record.size(); ++i)
    if (record.displacement[i] > 0.0) rows.push_back(i);
  for (std::size_t i : rows) {
    data.displacement.push_back(record.displacement[i]);
    data.load.push_back(record.load[i]);
  }
  if (load_noise > 0.0 || displacement_noise > 0.0) {
    constexpr int kHalf = 3;
    const int n = static_cast<int>(rows.size());
    for (int i = 0; i < n; ++i) {
      // Least-squares slope dP/dd over rows i - 3 .. i + 3.
      double sd = 0, sp = 0, sdd = 0, sdp = 0;
      int count = 0;
      for (int j = std::max(0, i - kHalf); j <= std::min(n - 1, i + kHalf); ++j, ++count) {
        sd += data.displacement[j];
        sp += data.load[j];
        sdd += data.displacement[j] * data.displacement[j];
        sdp += data.displacement[j] * data.load[j];
      }
      const double denominator = count * sdd - sd * sd;
      const double slope = denominator > 0.0 ? (count * sdp - sd * sp) / denominator : 0.0;
      data.load_uncertainty.push_back(
          std::hypot(load_noise, slope * displacement_noise));
    }
  }
  data.Validate();
  return data;
}

FitData FitData::Subset(const std::vector<int>& keep) const {
  FitData out;
  out.target = target;
  out.kind = kind;
  auto pick = [&keep](const std::vector<double>& from, std::vector<double>& to) {
    if (from.empty()) return;
    for (int i : keep) to.push_back(from[i]);
  };
  pick(crack_length, out.crack_length);
  pick(R, out.R);
  pick(R_uncertainty, out.R_uncertainty);
  pick(displacement, out.displacement);
  pick(load, out.load);
  pick(load_uncertainty, out.load_uncertainty);
  return out;
}

namespace {
// One series of a fit's data: values against an axis, optional uncertainties.
void ValidateSeries(const char* axis_name, const std::vector<double>& axis, const char* name,
                    const std::vector<double>& values, const std::vector<double>& uncertainty,
                    bool axis_ascending) {
  BF_CHECK_INPUT(values.size() >= 4, fmt::format("a fit needs at least four {} values", name),
                 {.field = name, .value = std::to_string(values.size()) + " points"});
  BF_CHECK_INPUT(axis.size() == values.size(),
                 fmt::format("{} and {} differ in length", axis_name, name));
  BF_CHECK_INPUT(uncertainty.empty() || uncertainty.size() == values.size(),
                 fmt::format("the {} uncertainties and {} differ in length", name, name));
  for (size_t i = 0; i < values.size(); ++i) {
    BF_CHECK_INPUT(std::isfinite(values[i]) && std::isfinite(axis[i]), "fit data must be finite",
                   {.field = "row " + std::to_string(i + 1)});
    if (axis_ascending && i > 0)
      BF_CHECK_INPUT(axis[i] >= axis[i - 1],
                     fmt::format("the {} of the data must not decrease", axis_name),
                     {.field = axis_name, .value = std::to_string(axis[i])});
    if (!uncertainty.empty())
      BF_CHECK_INPUT(uncertainty[i] > 0.0, "uncertainties must be positive",
                     {.field = std::string(name) + "_uncertainty",
                      .value = std::to_string(uncertainty[i])});
  }
}
}  // namespace

void FitData::Validate() const {
  if (target == FitTarget::kLoad)
    ValidateSeries("displacement", displacement, "load", load, load_uncertainty, false);
  else
    ValidateSeries("crack_length", crack_length, "R", R, R_uncertainty, true);
}

std::string FitSummary::BriefReport() const {
  auto line = [](const char* name, const ParameterEstimate& e, double scale, const char* unit) {
    if (e.fixed) return fmt::format("  {:<8} = {:.4g} {} (fixed)\n", name, e.value / scale, unit);
    if (std::isfinite(e.value))
      return fmt::format("  {:<8} = {:.4g} {} [95% CI {:.4g} .. {:.4g}]{}\n", name, e.value / scale,
                         unit, e.ci95_low / scale, e.ci95_high / scale,
                         e.identified ? "" : " (not identifiable)");
    if (std::isfinite(e.lower_bound))
      return fmt::format("  {:<8} >= {:.4g} {} (lower bound: {})\n", name, e.lower_bound / scale,
                         unit, e.note);
    return fmt::format("  {:<8}   not identifiable: {}\n", name, e.note);
  };
  std::string out = fmt::format(
      "fit ({} law, {} model, {}, {}): {} evaluations ({} failed), {:.2f} s, {}; rms residual "
      "{:.4g} {}\n  {}\n",
      law, model, optimizer, FitTargetName(target), evaluations, failed_evaluations, wall_s,
      converged ? "converged" : "NOT converged (" + stop_reason + ")", rms_residual,
      target == FitTarget::kLoad ? "N" : "J/m^2", verdict);
  if (reduced_chi2 > 1.5 && std::isfinite(reduced_chi2))
    out += fmt::format("  reduced chi^2 {:.3g}: the data scatter more than their uncertainties say; "
                       "intervals widened by it\n", reduced_chi2);
  out += line("sigma_c", sigma_c, 1e6, "MPa");
  out += line("J_B", J_B, 1.0, "J/m^2");
  out += line("delta_c", delta_c, 1e-3, "mm");
  out += line("J_tip_c", J_tip_c, 1.0, "J/m^2");
  return out;
}

FitSummary FitBridgingLaw(const ForwardModel& model, const laws::LawShape& shape,
                          const FitData& data, const FitOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid fit options: " + why);
  data.Validate();
  const Stopwatch clock;
  const Objective objective(model, shape, data, options);
  const std::vector<int>& free = objective.free();
  const int n_free = static_cast<int>(free.size());
  const int m = static_cast<int>(data.size());
  const bool weighted = data.weighted();
  const bool load_fit = data.target == FitTarget::kLoad;

  FitSummary s;
  s.target = data.target;
  s.model = model.Name();
  s.optimizer = OptimizerName(options.optimizer);
  s.law = std::string(laws::LawFamilyName(shape.family));
  s.data_points = m;
  Progress progress("fit", static_cast<size_t>(options.starts), options.progress);

  // 1. Multi-start local searches from a Latin-hypercube design.
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
  LocalResult best;
  for (int k = 0; k < starts; ++k) {
    const int budget = global ? options.max_evaluations * options.starts : options.max_evaluations;
    LocalResult r = MinimizeLocal(objective, options.optimizer, design[k], budget);
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
    progress.Update(static_cast<size_t>(k + 1));
  }
  progress.Finish();
  s.converged = best.converged && best.chi2 < kFailedCost;
  s.stop_reason = best.stop_reason;
  if (best.chi2 >= kFailedCost) {
    s.evaluations = objective.evaluations();
    s.failed_evaluations = objective.failures();
    s.wall_s = clock.Seconds();
    s.converged = false;
    s.stop_reason = "every forward run failed: " + objective.last_failure();
    s.verdict = "fit failed: no parameter set gave a valid forward run";
    return s;
  }

  std::vector<double> full = objective.Expand(best.x.data());
  for (int i = 0; i < kParameterCount; ++i) s.best_parameters[i] = full[i];
  std::vector<double> residuals(m);
  ForwardPrediction prediction;
  objective.Residuals(full, residuals.data(), &prediction);

  // Outliers: residuals beyond the threshold in robust standard deviations.
  if (options.outlier_threshold > 0.0) {
    std::vector<double> magnitude(m);
    for (int i = 0; i < m; ++i) magnitude[i] = std::abs(residuals[i]);
    std::vector<double> sorted = magnitude;
    std::nth_element(sorted.begin(), sorted.begin() + m / 2, sorted.end());
    const double robust_sd = 1.4826 * sorted[m / 2];
    const double limit = options.outlier_threshold * std::max(robust_sd, weighted ? 1.0 : 1e-300);
    std::vector<int> keep;
    std::vector<double> removed_a, removed_R;
    for (int i = 0; i < m; ++i) {
      if (magnitude[i] <= limit) {
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
  }
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
  double sum_sq = 0.0;
  for (int i = 0; i < m; ++i) sum_sq += std::pow(model_values[i] - values[i], 2);
  s.rms_residual = std::sqrt(sum_sq / m);
  // Without reported uncertainties the noise scale comes from the residuals.
  const int dof = std::max(1, m - n_free);
  // With reported uncertainties a reduced chi^2 above 1 says they miss part
  // of the scatter (model error, an effect the model lacks, as on a real
  // record): the intervals and tests are widened by it (Birge ratio), never
  // narrowed below what the uncertainties give.
  s.reduced_chi2 = best.chi2 / dof;
  const double scale2 = weighted ? std::max(1.0, s.reduced_chi2) : std::max(s.reduced_chi2, 1e-300);

  // 2. Covariance from the Jacobian: C = s^2 (J^T J)^-1.
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

  // 3. Profile likelihood per free parameter: the others re-optimized. The
  //    95% interval edges are found by stepping out from the optimum in the
  //    box coordinate until Delta chi^2 > threshold, then bisecting.
  const double threshold = 3.84 * scale2;
  {
    // The profiles are independent: they run side by side, each with its
    // own objective (and counters), and are applied in parameter order.
    struct ProfileRun {
      int k = 0;
      Profile profile;
      double x_low = 0.0, x_high = 0.0;
      int evaluations = 0, failures = 0;
    };
    std::vector<ProfileRun> runs;
    for (int k = 0; k < n_free; ++k) {
      // J_B's profile decides identifiability (steady state in the window):
      // it always runs; the others only when asked for.
      if (!options.profile_likelihood && free[k] != kJB) continue;
      runs.push_back({.k = k});
    }
    // Without full profiles only J_B's upper side is needed (the steady-state
    // decision); its lower limit then stays the Jacobian one.
    const bool lower_side = options.profile_likelihood;
    const int profile_threads = options.threads > 0 ? options.threads : 2;
#pragma omp parallel for num_threads(profile_threads) schedule(dynamic) \
    if (runs.size() > 1 && profile_threads > 1)
    for (std::size_t q = 0; q < runs.size(); ++q) {
      ProfileRun& run = runs[q];
      const int k = run.k;
      const int index = free[k];
      const Objective local(model, shape, data, options);
      Profile& profile = run.profile;
      profile.parameter = index;
      profile.chi2_threshold = threshold;
      // Each re-optimization starts from the nearest point already solved
      // inside the interval (warm start; the step-out moves away from it).
      std::vector<double> warm = best.x;
      auto profile_chi2 = [&](double x) {
        const double value = FromBox(index, x, options);
        double chi2 = kFailedCost;
        std::vector<double> at = full;
        at[index] = value;
        if (n_free == 1) {
          chi2 = local.Chi2(at);
        } else {
          // The pinned coordinate stays in the vector; its value is overridden.
          const LocalResult r =
              MinimizeNlopt(local, Optimizer::kBobyqa, warm, 80, index, value, 1e-4);
          chi2 = r.chi2;
          at = local.Expand(r.x.data(), index, value);
          if (chi2 < kFailedCost && chi2 - best.chi2 <= threshold) warm = r.x;
        }
        profile.points.push_back({value, chi2, chi2 < kFailedCost, {at[0], at[1], at[2]}});
        return chi2;
      };
      const auto inside = [&](double chi2) {
        return chi2 < kFailedCost && chi2 - best.chi2 <= threshold;
      };
      // Returns the box coordinate of the edge on one side, or NaN when the
      // profile stays inside up to the end of the box (flat on that side).
      auto edge = [&](double direction) -> double {
        warm = best.x;
        double in = best.x[k], step = 0.004;
        while (true) {
          const double out = std::clamp(in + direction * step, 0.0, 1.0);
          if (out == in) return NAN;  // reached the box edge while inside
          if (!inside(profile_chi2(out))) {
            double lo = in, hi = out;
            for (int b = 0; b < 5; ++b) {
              const double mid = 0.5 * (lo + hi);
              (inside(profile_chi2(mid)) ? lo : hi) = mid;
            }
            return lo;
          }
          in = out;
          step *= 2.0;
        }
      };
      run.x_low = lower_side ? edge(-1.0) : 0.0;
      run.x_high = edge(+1.0);
      profile.points.push_back({full[index], best.chi2, true, {full[0], full[1], full[2]}});
      std::sort(profile.points.begin(), profile.points.end(),
                [](const ProfilePoint& a, const ProfilePoint& b) { return a.value < b.value; });
      run.evaluations = local.evaluations();
      run.failures = local.failures();
    }
    for (ProfileRun& run : runs) {
      const int index = free[run.k];
      const double x_low = run.x_low, x_high = run.x_high;
      Profile& profile = run.profile;
      objective.AddCounts(run.evaluations, run.failures);
      ParameterEstimate& e = EstimateOf(s, index);
      if (lower_side) e.ci95_low = std::isnan(x_low) ? NAN : FromBox(index, x_low, options);
      e.ci95_high = std::isnan(x_high) ? NAN : FromBox(index, x_high, options);
      profile.flat = std::isnan(x_low) || std::isnan(x_high);
      if (profile.flat) {
        e.identified = false;
        e.note = fmt::format(
            "profile likelihood flat {} over the range explored ({:.4g} .. {:.4g})",
            std::isnan(x_low) && std::isnan(x_high) ? "on both sides"
            : std::isnan(x_high)                    ? "above the optimum"
                                                    : "below the optimum",
            options.lower[index], options.upper[index]);
      } else {
        e.identified = true;
        e.note = lower_side ? "CI from the profile likelihood"
                            : "CI: Jacobian below, profile likelihood above";
      }
      s.profiles.push_back(std::move(profile));
    }
  }

  // 4. Bridging detected? Likelihood ratio of the flat model R = J_tip,c.
  if (!options.fixed[kJB]) {
    std::vector<double> flat = full;
    flat[kJB] = 0.0;
    double flat_chi2 = kFailedCost;
    // Best constant: the weighted mean of R (sum of weights sw kept for its
    // interval). A load-displacement record: J_tip,c re-optimized alone.
    double sw = 0.0, swr = 0.0;
    bool flat_converged = true;  // the weighted mean is closed-form
    std::string flat_stop_reason = "closed form";
    if (load_fit) {
      if (!options.fixed[kJTipC]) {
        FitOptions only_tip = options;
        only_tip.fixed = {true, true, false};
        only_tip.fixed_value = {full[kSigmaC], 0.0, 0.0};
        const Objective tip_only(model, shape, data, only_tip);
        // From the better of the bridged optimum's J_tip,c and the given start's.
        std::vector<double> x0{ToBox(kJTipC, full[kJTipC], options)};
        if (std::isfinite(options.initial[kJTipC])) {
          const std::vector<double> other{ToBox(kJTipC, options.initial[kJTipC], options)};
          if (tip_only.Chi2(tip_only.Expand(other.data())) < tip_only.Chi2(tip_only.Expand(x0.data())))
            x0 = other;
        }
        const LocalResult r = MinimizeNlopt(tip_only, Optimizer::kNelderMead, x0, 80);
        objective.AddCounts(tip_only.evaluations(), tip_only.failures());
        flat = tip_only.Expand(r.x.data());
        flat_converged = r.converged;
        flat_stop_reason = r.stop_reason;
        // One-parameter curvature for the interval: sw = d2chi2/dJ^2 / 2.
        const double J = flat[kJTipC], h = 1e-3 * J;
        std::vector<double> up = flat, down = flat;
        up[kJTipC] = J + h;
        down[kJTipC] = J - h;
        const double c0 = objective.Chi2(flat), cp = objective.Chi2(up), cm = objective.Chi2(down);
        sw = (cp - 2 * c0 + cm) / (2 * h * h);
      }
    } else {
      for (int i = 0; i < m; ++i) {
        const double w = weighted ? 1.0 / std::pow(data.R_uncertainty[i], 2) : 1.0;
        sw += w;
        swr += w * data.R[i];
      }
      if (!options.fixed[kJTipC]) flat[kJTipC] = swr / sw;
    }
    flat_chi2 = objective.Chi2(flat);
    const double statistic = (flat_chi2 - best.chi2) / scale2;
    // Bridging below the models' own R accuracy is not reported either: the
    // smaller of J_B and the rise of the fitted R inside the data window (a
    // weak, long zone may hold a large J_B yet add little R before the end).
    const std::vector<double>& fitted_R = load_fit ? prediction.R_physical : prediction.R;
    double rise = 0.0;
    for (double r : fitted_R) rise = std::max(rise, r - full[kJTipC]);
    const double bridging_seen = std::min(full[kJB], rise);
    const bool below_resolution =
        flat_chi2 < kFailedCost && bridging_seen < options.min_bridging_fraction * full[kJTipC];
    if ((flat_chi2 < kFailedCost && statistic < 5.99) || below_resolution) {
      s.bridging_detected = false;
      s.verdict =
          statistic < 0.0
              ? fmt::format("no bridging detected: a flat R curve fits better than the best "
                            "bridged law found (chi^2 {:.4g} against {:.4g})",
                            flat_chi2, best.chi2)
          : statistic < 5.99
              ? fmt::format("no bridging detected: a flat R curve fits as well (likelihood-ratio "
                            "statistic {:.2f} < 5.99, 2 parameters at 95%)", statistic)
              : fmt::format("no bridging detected: the best law adds {:.3g} J/m^2 to R in the "
                            "data (J_B = {:.3g} J/m^2), below {:g}% of J_tip,c, the forward "
                            "models' R accuracy (likelihood-ratio statistic {:.2f})",
                            bridging_seen, full[kJB], 100 * options.min_bridging_fraction,
                            statistic);
      // The answer is the flat model: its convergence is the fit's.
      s.converged = flat_converged;
      s.stop_reason = "flat model (J_B = 0): " + flat_stop_reason;
      s.J_B = {.value = 0.0, .identified = true,
               .decided_by = statistic < 5.99 ? "likelihood-ratio test" : "model R accuracy",
               .note = "J_B consistent with 0"};
      s.sigma_c = {.decided_by = "likelihood-ratio test", .note = "no bridging detected"};
      s.delta_c = {.decided_by = "likelihood-ratio test", .note = "no bridging detected"};
      if (!options.fixed[kJTipC]) {
        const double flat_reduced = flat_chi2 / std::max(1, m - 1);
        const double flat_scale2 = weighted ? std::max(1.0, flat_reduced) : flat_reduced;
        const double sd = sw > 0.0 ? std::sqrt(flat_scale2 / sw) : NAN;
        s.J_tip_c = {.value = flat[kJTipC], .ci95_low = flat[kJTipC] - 1.96 * sd,
                     .ci95_high = flat[kJTipC] + 1.96 * sd, .identified = std::isfinite(sd),
                     .decided_by = load_fit ? "load-displacement fit without bridging"
                                            : "weighted mean (flat R curve)",
                     .note = "no bridging"};
      }
      s.rms_residual = 0.0;
      if (load_fit) {
        std::vector<double> r(m);
        ForwardPrediction at_flat;
        objective.Residuals(flat, r.data(), &at_flat);
        s.fitted_crack_length = at_flat.crack_length_physical;
        s.fitted_R = at_flat.R_physical;
        s.fitted_load = at_flat.load;
        for (int i = 0; i < m && i < static_cast<int>(at_flat.load.size()); ++i)
          s.rms_residual += std::pow(at_flat.load[i] - data.load[i], 2);
      } else {
        s.fitted_R.assign(m, flat[kJTipC]);
        for (int i = 0; i < m; ++i) s.rms_residual += std::pow(flat[kJTipC] - data.R[i], 2);
      }
      s.rms_residual = std::sqrt(s.rms_residual / m);
      s.chi2 = flat_chi2;
      s.evaluations = objective.evaluations();
      s.failed_evaluations = objective.failures();
      s.wall_s = clock.Seconds();
      return s;
    }
  }

  // 5. Steady state in the data? The fitted model must reach it inside the
  //    data window, with the J_B profile bounded above.
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
    if (p.steady_state_reached)
      for (double a : axis) past += a >= p.steady_state_crack_length;
    return p.steady_state_reached && past >= 3;
  };
  bool reached = reaches_in_window(prediction);
  if (reached && jb_profile) {
    if (jb_profile->flat && std::isnan(s.J_B.ci95_high)) reached = false;
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
    // The fitted (smoothed) R at a_max; with as-data the model's own R there.
    const double R_max = physical ? prediction.R_physical[last] : prediction.R[last];
    const double J_tip = full[kJTipC];
    s.bounds = laws::BoundsFromTruncatedCurve(R_max, J_tip, prediction.delta_root[last], a_max);
    const std::string evidence = fmt::format(
        "steady state not reached by a = {:.4g} mm: J_B >= R_max - J_tip,c = {:.4g} - {:.4g}",
        a_max * 1e3, R_max, J_tip);
    s.J_B = {.lower_bound = s.bounds.J_B_lower, .identified = false,
             .decided_by = "PHYSICS 7 bound from the fitted R at the last point", .note = evidence};
    s.delta_c = {.lower_bound = s.bounds.delta_c_lower, .identified = false,
                 .decided_by = "PHYSICS 7 bound: fitted notch-root COD at the last point",
                 .note = fmt::format("delta_c >= delta_root({:.4g} mm) = {:.4g} mm", a_max * 1e3,
                                     s.bounds.delta_c_lower * 1e3)};
    s.verdict = fmt::format(
        "steady state not reached within the data (a <= {:.4g} mm): sigma_c estimated from the "
        "rising R curve; J_B and delta_c are lower bounds (PHYSICS 7)", a_max * 1e3);
  } else {
    s.verdict = s.steady_state_reached
                    ? fmt::format("steady state reached at a = {:.4g} mm: all parameters estimated",
                                  s.steady_state_crack_length * 1e3)
                    : "J_B fixed by the user";
  }
  s.evaluations = objective.evaluations();
  s.failed_evaluations = objective.failures();
  s.wall_s = clock.Seconds();
  return s;
}

std::vector<LawComparison> CompareLawFamilies(const ForwardModel& model,
                                              const std::vector<laws::LawShape>& shapes,
                                              const FitData& data, const FitOptions& options) {
  std::vector<LawComparison> out;
  for (const laws::LawShape& shape : shapes) {
    LawComparison c;
    c.law = std::string(laws::LawFamilyName(shape.family));
    c.summary = FitBridgingLaw(model, shape, data, options);
    out.push_back(std::move(c));
  }
  const bool weighted = data.weighted();
  double scale2 = 1.0;
  if (!weighted) {
    double best = INFINITY;
    for (const auto& c : out)
      if (c.summary.converged) best = std::min(best, c.summary.chi2 / std::max(1, c.summary.data_points - 3));
    scale2 = std::isfinite(best) && best > 0 ? best : 1.0;
  }
  double best_aicc = INFINITY;
  for (auto& c : out) {
    if (!c.summary.converged) continue;
    const int k = c.summary.bridging_detected
                      ? static_cast<int>(std::count(options.fixed.begin(), options.fixed.end(), false))
                      : (options.fixed[kJTipC] ? 0 : 1);
    const int n = c.summary.data_points;
    c.aicc = c.summary.chi2 / scale2 + 2.0 * k + (n - k - 1 > 0 ? 2.0 * k * (k + 1) / (n - k - 1) : 0.0);
    best_aicc = std::min(best_aicc, c.aicc);
  }
  for (auto& c : out) c.delta_aicc = c.aicc - best_aicc;
  return out;
}

}  // namespace bridgefit::inverse
