// The fit's local optimizers and starts (fit_impl.hpp).
#include <ceres/ceres.h>
#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "fit_impl.hpp"

namespace bridgefit::inverse::fit_internal {
namespace {

// Ceres functor: residuals of the free box coordinates (numeric derivatives).
struct CeresResiduals {
  const Objective* objective;
  int pinned = -1;
  double pinned_value = 0.0;
  bool operator()(double const* const* x, double* residuals) const {
    return objective->Residuals(objective->Expand(x[0], pinned, pinned_value), residuals);
  }
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
}  // namespace

LocalResult MinimizeNlopt(const Objective& objective, Optimizer optimizer, std::vector<double> x_full,
                          int max_evaluations, int pinned, double pinned_value, double xtol) {
  // A pinned coordinate is left out of the search (the optimizer works on
  // the others only: a dead dimension costs a derivative-free method
  // evaluations for nothing) and put back into the result.
  // `pinned` is a parameter index; `skip` its place among the free coordinates.
  const int n_full = static_cast<int>(x_full.size());
  const std::vector<int>& free = objective.free();
  const int skip = pinned < 0 ? -1
                              : static_cast<int>(std::find(free.begin(), free.end(), pinned) -
                                                 free.begin());
  std::vector<double> x0;
  for (int i = 0; i < n_full; ++i)
    if (i != skip) x0.push_back(x_full[i]);
  const int n = static_cast<int>(x0.size());
  LocalResult result;
  const int before = objective.evaluations();
  struct Context {
    const Objective* objective;
    int pinned, skip;
    double pinned_value;
    std::vector<double> full;  // scratch: the searched coordinates with the pinned one
  } context{&objective, pinned, skip, pinned_value, x_full};
  auto f = [](unsigned, const double* x, double*, void* data) -> double {
    auto* c = static_cast<Context*>(data);
    for (int i = 0, j = 0; i < static_cast<int>(c->full.size()); ++i)
      if (i != c->skip) c->full[i] = x[j++];
    return c->objective->Chi2(c->objective->Expand(c->full.data(), c->pinned, c->pinned_value));
  };
  if (n == 0) {
    result.x = x_full;
    result.chi2 = f(0, nullptr, nullptr, &context);
    result.converged = true;
    result.stop_reason = "nothing to search";
    result.evaluations = objective.evaluations() - before;
    return result;
  }
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
  constexpr double kInitialStep = 0.05;
  if (optimizer == Optimizer::kBobyqa || optimizer == Optimizer::kNelderMead ||
      optimizer == Optimizer::kCobyla)
    opt.set_initial_step(std::vector<double>(n, kInitialStep));
  // BOBYQA moves a start that lies closer to a bound than its first step
  // onto the bound or a step inside (Powell's rule), so its answer can be
  // worse than the start itself (a restart from a profile point at J_tip,c
  // 0.018 box: chi^2 1694 in, 806307 out, validation #192). The start's
  // chi^2 is then a candidate, and where it beats the search the search is
  // repeated from it with each first step no longer than the distance to
  // the nearer bound (NLopt rescales by the steps: the start then stays).
  const std::vector<double> start = x0;
  bool moved = false;
  if (optimizer == Optimizer::kBobyqa)
    for (double x : x0) moved = moved || (x > 0.0 && x < kInitialStep) || (x < 1.0 && x > 1.0 - kInitialStep);
  const double start_chi2 = moved ? f(0, start.data(), nullptr, &context) : kFailedCost;
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
  if (start_chi2 < value) {
    std::vector<double> steps(n), again = start;
    for (int i = 0; i < n; ++i)
      steps[i] = start[i] > 0.0 && start[i] < 1.0
                     ? std::clamp(std::min(start[i], 1.0 - start[i]), 1e-4, kInitialStep)
                     : kInitialStep;
    opt.set_initial_step(steps);
    opt.set_maxeval(std::max(1, max_evaluations - (objective.evaluations() - before)));
    double again_value = kFailedCost;
    std::string again_reason;
    bool again_converged = false;
    try {
      const nlopt::result r = opt.optimize(again, again_value);
      again_reason = NloptReason(r);
      again_converged = r == nlopt::SUCCESS || r == nlopt::FTOL_REACHED ||
                        r == nlopt::XTOL_REACHED || r == nlopt::STOPVAL_REACHED;
    } catch (const std::exception& e) {
      again_reason = std::string("nlopt stopped: ") + e.what();
    }
    const bool better = again_value <= start_chi2;
    x0 = better ? again : start;
    value = better ? again_value : start_chi2;
    result.converged = better && again_converged;
    result.stop_reason = (better ? again_reason : std::string("the start kept")) +
                         " (the first search moved its start onto worse ground: searched again "
                         "with steps within the bounds)";
  }
  result.x = x_full;
  for (int i = 0, j = 0; i < n_full; ++i)
    if (i != skip) result.x[i] = x0[j++];
  result.chi2 = value;
  result.evaluations = objective.evaluations() - before;
  return result;
}

namespace {

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

}  // namespace

LocalResult MinimizeLocal(const Objective& objective, Optimizer optimizer,
                          const std::vector<double>& x0, int max_evaluations, int pinned,
                          double pinned_value) {
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
}  // namespace bridgefit::inverse::fit_internal
