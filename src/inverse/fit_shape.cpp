// The joint search of a law's shape and its scale parameters (fit_shape.hpp
// equations (1) and (2)), and the fit with the shape held that gives the
// intervals, steady state and bounds.
#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "fit_impl.hpp"
#include "fit_shape_impl.hpp"

namespace bridgefit::inverse::shape_internal {

using namespace fit_internal;

namespace {

// The cost (1) of box coordinates x = (free scale parameters, positions, values).
class JointObjective {
 public:
  JointObjective(const ForwardModel& model, const FitData& data, const FitOptions& options,
                 const ShapeLayout& layout, double lambda)
      : model_(model),
        data_(data),
        options_(options),
        layout_(layout),
        lambda_(lambda),
        free_(FreeScaleParameters(options)) {}

  int dims() const { return static_cast<int>(free_.size()) + layout_.dims(); }
  int evaluations() const { return evaluations_; }
  const std::vector<int>& free() const { return free_; }
  const FitOptions& options() const { return options_; }

  // Scale parameters, positions and values of box coordinates.
  void Decode(const double* x, std::array<double, kParameterCount>* main, std::vector<double>* d,
              std::vector<double>* v) const {
    for (int i = 0; i < kParameterCount; ++i) (*main)[i] = options_.fixed_value[i];
    const int n_main = static_cast<int>(free_.size());
    for (int k = 0; k < n_main; ++k) (*main)[free_[k]] = FromBox(free_[k], x[k], options_);
    *d = layout_.PositionsFromBox(x + n_main);
    v->assign(x + n_main + layout_.positions(), x + dims());
  }
  // Weighted residuals of a law; false when the shape or the run fails.
  bool Residuals(const std::array<double, kParameterCount>& main, const laws::LawShape& shape,
                 double* r) const {
    ++evaluations_;
    const Objective objective(model_, shape, data_, options_);
    return objective.Residuals(std::vector<double>(main.begin(), main.end()), r);
  }
  // chi^2 of the data (NaN on failure) and the cost (1).
  double Cost(const double* x, double* chi2_out = nullptr) const {
    std::array<double, kParameterCount> main{};
    std::vector<double> d, v;
    Decode(x, &main, &d, &v);
    laws::LawShape shape;
    if (!layout_.Build(d, v, &shape)) return kFailedCost;
    std::vector<double> r(data_.size());
    if (!Residuals(main, shape, r.data())) return kFailedCost;
    double chi2 = 0.0;
    for (double e : r) chi2 += e * e;
    if (chi2_out) *chi2_out = chi2;
    return chi2 + lambda_ * layout_.Roughness(shape);
  }

 private:
  const ForwardModel& model_;
  const FitData& data_;
  const FitOptions& options_;
  const ShapeLayout& layout_;
  double lambda_;
  std::vector<int> free_;
  mutable int evaluations_ = 0;
};

struct LocalRun {
  std::vector<double> x;
  double cost = kFailedCost;
  bool converged = false;
  std::string stop_reason;
};

// BOBYQA over the unit box from x0.
LocalRun Bobyqa(const JointObjective& f, std::vector<double> x0, int max_evaluations) {
  const int n = f.dims();
  nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(n));
  opt.set_lower_bounds(std::vector<double>(n, 0.0));
  opt.set_upper_bounds(std::vector<double>(n, 1.0));
  auto cost = [](unsigned, const double* x, double*, void* data) -> double {
    return static_cast<const JointObjective*>(data)->Cost(x);
  };
  opt.set_min_objective(cost, const_cast<JointObjective*>(&f));
  opt.set_xtol_rel(f.options().relative_tolerance);
  opt.set_ftol_rel(1e-10);
  opt.set_maxeval(max_evaluations);
  std::vector<double> step(n, 0.1);
  for (size_t k = 0; k < f.free().size(); ++k) step[k] = 0.05;
  opt.set_initial_step(step);
  for (double& v : x0) v = std::clamp(v, 0.0, 1.0);
  LocalRun run;
  try {
    const nlopt::result r = opt.optimize(x0, run.cost);
    run.converged = r == nlopt::SUCCESS || r == nlopt::FTOL_REACHED || r == nlopt::XTOL_REACHED;
    run.stop_reason = run.converged ? "tolerance reached"
                      : r == nlopt::MAXEVAL_REACHED
                          ? "evaluation limit reached"
                          : "nlopt result " + std::to_string(static_cast<int>(r));
  } catch (const std::exception& e) {
    run.stop_reason = std::string("nlopt stopped: ") + e.what();
  }
  run.x = x0;
  return run;
}

// Starts: each converged seed's optimum with its shape projected, then a
// Latin-hypercube design.
std::vector<std::vector<double>> Starts(const JointObjective& f, const ShapeLayout& layout,
                                        const std::vector<LawComparison>& all_seeds, int from_seeds,
                                        int random, unsigned seed) {
  std::vector<const LawComparison*> seeds;
  for (const LawComparison& s : all_seeds)
    if (s.summary.converged && std::isfinite(s.summary.best_parameters[kSigmaC]))
      seeds.push_back(&s);
  std::stable_sort(seeds.begin(), seeds.end(),
                   [](const auto* a, const auto* b) { return a->summary.chi2 < b->summary.chi2; });
  if (static_cast<int>(seeds.size()) > from_seeds) seeds.resize(from_seeds);
  std::vector<std::vector<double>> starts;
  for (const LawComparison* seed_fit : seeds) {
    const LawComparison& s = *seed_fit;
    std::vector<double> x;
    for (int i : f.free()) x.push_back(ToBox(i, s.summary.best_parameters[i], f.options()));
    const std::vector<double> shape = layout.Project(s.shape);
    x.insert(x.end(), shape.begin(), shape.end());
    starts.push_back(std::move(x));
  }
  for (auto& x : LatinHypercube(random, f.dims(), seed)) starts.push_back(std::move(x));
  return starts;
}

// The Wald coordinates (free scale parameters, positions, values but the
// pinned one) and back.
struct WaldMap {
  const ShapeLayout& layout;
  const std::vector<int>& free;
  int pinned;
  std::vector<double> Pack(const JointResult& j) const {
    std::vector<double> w;
    for (int i : free) w.push_back(j.main[i]);
    w.insert(w.end(), j.positions.begin(), j.positions.end());
    for (int k = 0; k < static_cast<int>(j.values.size()); ++k)
      if (k != pinned) w.push_back(j.values[k]);
    return w;
  }
  bool Unpack(const std::vector<double>& w, std::array<double, kParameterCount> main,
              std::array<double, kParameterCount>* main_out, laws::LawShape* shape) const {
    size_t c = 0;
    for (int i : free) main[i] = w[c++];
    std::vector<double> d(w.begin() + c, w.begin() + c + layout.positions());
    c += layout.positions();
    std::vector<double> v;
    for (int k = 0; k < layout.values(); ++k) v.push_back(k == pinned ? 1.0 : w[c++]);
    for (double value : v)
      if (value > 1.0) return false;  // the peak knot must stay the peak
    *main_out = main;
    return layout.Build(d, v, shape);
  }
};

// Jacobian of the residuals in the Wald coordinates (central differences,
// one-sided at a bound), the penalty's rows sqrt(lambda) D, and from them
// k_eff (2) and (J^T J + lambda D^T D)^-1. False when a run fails.
bool Information(const JointObjective& f, const FitData& data, JointResult& j) {
  const WaldMap map{j.layout, f.free(), j.pinned};
  const std::vector<double> w0 = map.Pack(j);
  const int p = static_cast<int>(w0.size());
  const int m = static_cast<int>(data.size());
  const int n_main = static_cast<int>(f.free().size());
  Eigen::MatrixXd jac(m, p);
  std::vector<double> plus(m), minus(m);
  for (int c = 0; c < p; ++c) {
    const double h = c < n_main ? 1e-4 * std::max(std::abs(w0[c]), 1e-12) : 1e-4;
    std::vector<double> wp = w0, wm = w0;
    wp[c] += h;
    wm[c] -= h;
    std::array<double, kParameterCount> main{};
    laws::LawShape shape;
    const bool up = map.Unpack(wp, j.main, &main, &shape) && f.Residuals(main, shape, plus.data());
    const bool down =
        map.Unpack(wm, j.main, &main, &shape) && f.Residuals(main, shape, minus.data());
    if (!up && !down) return false;
    std::vector<double> centre(m);
    if (!up || !down) {
      map.Unpack(w0, j.main, &main, &shape);
      if (!f.Residuals(main, shape, centre.data())) return false;
    }
    for (int i = 0; i < m; ++i)
      jac(i, c) = up && down ? (plus[i] - minus[i]) / (2 * h)
                  : up       ? (plus[i] - centre[i]) / h
                             : (centre[i] - minus[i]) / h;
  }
  const Eigen::MatrixXd jtj = jac.transpose() * jac;
  Eigen::MatrixXd penalty = Eigen::MatrixXd::Zero(p, p);
  if (j.layout.family == ShapeFamily::kTable && j.lambda > 0.0) {
    // Rows of D over the knots s_0 .. s_(N-1) (s_N = 0), columns: the
    // unpinned knots' Wald coordinates.
    const int n = j.layout.knots;
    const int first_value = n_main + j.layout.positions();
    Eigen::MatrixXd d = Eigen::MatrixXd::Zero(std::max(0, n - 1), p);
    for (int row = 0; row + 1 < n; ++row)
      for (int k : {row, row + 1, row + 2}) {
        if (k >= n || k == j.pinned) continue;
        const int col = first_value + (k < j.pinned || j.pinned < 0 ? k : k - 1);
        d(row, col) += k == row + 1 ? -2.0 : 1.0;
      }
    penalty = j.lambda * d.transpose() * d;
  }
  // Conditioned on the unit-diagonal scaling (sigma_c in Pa, knots ~1).
  const Eigen::MatrixXd a = jtj + penalty;
  const Eigen::VectorXd scale = a.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd a_unit = scale.asDiagonal() * a * scale.asDiagonal();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a_unit);
  const double cond = svd.singularValues()(0) / std::max(svd.singularValues()(p - 1), 1e-300);
  if (cond >= 1e12) return false;
  j.inverse_information = scale.asDiagonal() * a_unit.inverse() * scale.asDiagonal();
  j.effective_parameters = (j.inverse_information * jtj).trace();
  return true;
}

}  // namespace

std::vector<int> FreeScaleParameters(const FitOptions& options) {
  std::vector<int> free;
  for (int i = 0; i < kParameterCount; ++i)
    if (!options.fixed[i]) free.push_back(i);
  return free;
}

JointResult RunJoint(const ForwardModel& model, const ShapeLayout& layout, const FitData& data,
                     const FitOptions& options, const ShapeFitOptions& shape_options,
                     const std::vector<LawComparison>& seeds, double scale2) {
  JointResult j;
  j.layout = layout;
  j.lambda = layout.family == ShapeFamily::kTable ? shape_options.smoothness * scale2 : 0.0;
  j.nominal_parameters = static_cast<int>(FreeScaleParameters(options).size()) + layout.counted();
  const JointObjective f(model, data, options, j.layout, j.lambda);
  LocalRun best;
  for (const auto& x0 : Starts(f, j.layout, seeds, shape_options.seed_starts,
                               shape_options.random_starts, options.seed)) {
    LocalRun run = Bobyqa(f, x0, shape_options.max_evaluations);
    if (run.cost < best.cost) best = std::move(run);
  }
  j.evaluations = f.evaluations();
  j.converged = best.converged;
  j.stop_reason = best.stop_reason;
  if (best.cost >= kFailedCost) {
    j.stop_reason = "every forward run of the shape search failed";
    return j;
  }
  std::vector<double> d, v;
  f.Decode(best.x.data(), &j.main, &d, &v);
  j.positions = d;
  if (layout.normalised()) {  // the redundant scale of the knots: peak knot = 1
    const double peak = *std::max_element(v.begin(), v.end());
    for (double& value : v) value /= peak;
    j.pinned = static_cast<int>(std::max_element(v.begin(), v.end()) - v.begin());
    v[j.pinned] = 1.0;
  }
  j.values = v;
  j.layout.Build(j.positions, j.values, &j.shape);
  j.roughness = j.layout.Roughness(j.shape);
  double chi2 = NAN;
  f.Cost(best.x.data(), &chi2);
  j.chi2 = chi2;
  j.ok = true;
  if (!Information(f, data, j)) {
    j.inverse_information.resize(0, 0);
    j.effective_parameters = j.nominal_parameters;
  }
  j.evaluations = f.evaluations();
  return j;
}

namespace {

// The hull of an estimate's interval and value -+ 1.96 sd (an open or
// untrusted end stays NaN); true when it widened.
bool Widen(ParameterEstimate& e, double sd) {
  if (!std::isfinite(sd) || !std::isfinite(e.value)) return false;
  bool widened = false;
  if (std::isfinite(e.ci95_low) && e.value - 1.96 * sd < e.ci95_low) {
    e.ci95_low = e.value - 1.96 * sd;
    widened = true;
  }
  if (std::isfinite(e.ci95_high) && e.value + 1.96 * sd > e.ci95_high) {
    e.ci95_high = e.value + 1.96 * sd;
    widened = true;
  }
  return widened;
}

// Wald standard error of delta_c = J_B / (k sigma_c), k the shape's area,
// by the delta method over the Wald coordinates (no model runs).
double DeltaCError(const JointResult& j, const WaldMap& map, const std::vector<double>& w0,
                   const Eigen::MatrixXd& cov) {
  auto delta_c = [&](const std::vector<double>& w) {
    std::array<double, kParameterCount> main{};
    laws::LawShape shape;
    if (!map.Unpack(w, j.main, &main, &shape)) return double(NAN);
    return main[kJB] / (shape.Area() * main[kSigmaC]);
  };
  const int p = static_cast<int>(w0.size());
  Eigen::VectorXd g(p);
  const double centre = delta_c(w0);
  for (int c = 0; c < p; ++c) {
    const double h = 1e-6 * std::max(std::abs(w0[c]), 1e-3);
    std::vector<double> wp = w0, wm = w0;
    wp[c] += h;
    wm[c] -= h;
    const double up = delta_c(wp), down = delta_c(wm);
    g(c) = std::isfinite(up) && std::isfinite(down) ? (up - down) / (2 * h)
           : std::isfinite(up)                      ? (up - centre) / h
                                                    : (centre - down) / h;
  }
  return std::sqrt(g.dot(cov * g));
}

}  // namespace

ShapeFit FinishShapeFit(const ForwardModel& model, const FitData& data, const FitOptions& options,
                        const JointResult& j) {
  ShapeFit out;
  out.family = j.layout.family;
  out.law = ShapeFamilyName(out.family);
  out.knots = j.layout.family == ShapeFamily::kTable ? j.layout.knots : 0;
  out.penalty = j.lambda;
  out.roughness = j.roughness;
  out.evaluations = j.evaluations;
  out.parameters = j.nominal_parameters;
  out.effective_parameters = j.effective_parameters;
  if (!j.ok) {
    out.skip_reason = j.stop_reason;
    return out;
  }
  out.fitted = true;
  out.shape = j.shape;
  // The shape held: profiles, steady state, bounds and the no-bridging test
  // of the fixed-shape fit, started at the joint optimum.
  FitOptions held = options;
  held.outlier_threshold = 0.0;
  for (int i = 0; i < kParameterCount; ++i)
    if (!options.fixed[i]) held.initial[i] = j.main[i];
  FitSummary& s = out.summary;
  s = FitBridgingLaw(model, j.shape, data, held);
  s.law = out.law;
  s.evaluations += j.evaluations;

  const std::vector<int> free = FreeScaleParameters(options);
  const WaldMap map{j.layout, free, j.pinned};
  const std::vector<double> w0 = map.Pack(j);
  const std::vector<std::string> names = j.layout.Names();
  const int n = static_cast<int>(data.size());
  const bool have_cov = j.inverse_information.rows() == static_cast<int>(w0.size());
  double s2 = j.chi2 / std::max(1.0, n - j.effective_parameters);
  s2 = (data.weighted() ? std::max(1.0, s2) : s2) * s.interval_inflation;
  const Eigen::MatrixXd cov = have_cov ? Eigen::MatrixXd(s2 * j.inverse_information)
                                       : Eigen::MatrixXd::Constant(w0.size(), w0.size(), NAN);
  // Shape parameters: positions, then knot values (the pinned peak has none).
  const int n_main = static_cast<int>(free.size());
  for (int k = 0, c = n_main; k < j.layout.dims(); ++k) {
    ShapeParameter p{.name = names[k]};
    const int value_index = k - j.layout.positions();
    p.value = value_index < 0 ? j.positions[k] : j.values[value_index];
    p.pinned = value_index == j.pinned && value_index >= 0;
    if (!p.pinned) p.standard_error = std::sqrt(cov(c, c)), ++c;
    out.shape_parameters.push_back(p);
  }
  if (!s.bridging_detected) {
    out.note = "no bridging detected: the shape parameters mean nothing";
    return out;
  }
  if (!j.converged)  // said in the verdict too: the shape's optimum may not be reached
    s.verdict += "; the shape search stopped before converging (" + j.stop_reason + ")";
  std::vector<std::string> widened;
  for (int k = 0; k < n_main; ++k) {
    ParameterEstimate& e = EstimateOf(s, free[k]);
    if (!e.identified) continue;  // a bound or an open profile: left as the held-shape fit says
    if (Widen(e, std::sqrt(cov(k, k)))) widened.push_back(ParameterName(free[k]));
    e.note += fmt::format("; with the shape free (Wald, {} parameters) -+{:.4g}",
                          j.nominal_parameters, 1.96 * std::sqrt(cov(k, k)));
  }
  if (s.delta_c.identified && !options.fixed[kJB] && !options.fixed[kSigmaC] && have_cov &&
      Widen(s.delta_c, DeltaCError(j, map, w0, cov)))
    widened.push_back("delta_c");
  s.verdict += fmt::format(
      "; {} shape fitted with the scale parameters ({} parameters{})", out.law,
      j.nominal_parameters,
      j.lambda > 0.0 ? fmt::format(", {:.2f} effective", j.effective_parameters) : std::string());
  if (!widened.empty())
    s.verdict += "; intervals widened for the shape's uncertainty: " +
                 fmt::format("{}", fmt::join(widened, ", "));
  std::vector<std::string> notes;
  if (!j.converged) notes.push_back("shape search: " + j.stop_reason + " (its best point kept)");
  if (!have_cov) notes.push_back("shape parameters' covariance singular: no Wald errors");
  out.note = fmt::format("{}", fmt::join(notes, "; "));
  return out;
}

double Aicc(double chi2_over_s2, double k, int n) {
  if (!(n - k - 1 > 0)) return NAN;
  return chi2_over_s2 + 2.0 * k + 2.0 * k * (k + 1) / (n - k - 1);
}

std::string TooFewPoints(int points, int k, const std::string& what) {
  // AICc and a residual noise scale need n - k >= 2.
  if (points >= k + 2) return "";
  return fmt::format("{}: {} data points are too few for its {} parameters (at least {} needed)",
                     what, points, k, k + 2);
}

}  // namespace bridgefit::inverse::shape_internal
