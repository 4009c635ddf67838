// The numerical pieces of the law-free routes (law_free.hpp): input checks,
// the hat-function basis, the penalised least squares with its lambda
// search, and the plateau and onset tests.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "bridgefit/core/error.hpp"
#include "law_free_impl.hpp"

namespace bridgefit::laws::law_free_detail {
namespace {

std::string Indexed(const std::string& name, size_t i) {
  return name + "[" + std::to_string(i) + "]";
}

void CheckFinite(const std::vector<double>& values, const std::string& name) {
  for (size_t i = 0; i < values.size(); ++i)
    BF_CHECK_INPUT(std::isfinite(values[i]), "samples must be finite",
                   {.field = Indexed(name, i),
                    .value = std::to_string(values[i]),
                    .expected = "a finite number"});
}

// Weighted straight line through samples [i0, i1]: slope and chi^2.
struct Line {
  double slope = 0.0, chi2 = 0.0;
};
Line FitLine(const Samples& s, int i0, int i1) {
  double sw = 0.0, swx = 0.0, swy = 0.0;
  for (int i = i0; i <= i1; ++i) {
    const double w = 1.0 / (s.u[i] * s.u[i]);
    sw += w, swx += w * s.x[i], swy += w * s.y[i];
  }
  const double mx = swx / sw, my = swy / sw;
  double sxx = 0.0, sxy = 0.0;
  for (int i = i0; i <= i1; ++i) {
    const double w = 1.0 / (s.u[i] * s.u[i]);
    sxx += w * (s.x[i] - mx) * (s.x[i] - mx);
    sxy += w * (s.x[i] - mx) * (s.y[i] - my);
  }
  Line line;
  line.slope = sxx > 0.0 ? sxy / sxx : 0.0;
  for (int i = i0; i <= i1; ++i) {
    const double r = (s.y[i] - my - line.slope * (s.x[i] - mx)) / s.u[i];
    line.chi2 += r * r;
  }
  return line;
}

// Flatness of the tail [p, n): the weighted straight line's slope is within
// z standard errors of zero, the standard error scaled up by the line's own
// scatter when the samples scatter more than their stated u.
struct TailTest {
  bool flat = false;  // the slope is not significantly different from zero
  double mean = 0.0, mean_se = 0.0;
  double slope = 0.0, slope_se = 0.0;
};
TailTest TestTail(const Samples& s, int p, double z) {
  const int n = static_cast<int>(s.x.size());
  double sw = 0.0, swx = 0.0, swy = 0.0;
  for (int i = p; i < n; ++i) {
    const double w = 1.0 / (s.u[i] * s.u[i]);
    sw += w, swx += w * s.x[i], swy += w * s.y[i];
  }
  const double mx = swx / sw, my = swy / sw;
  double sxx = 0.0, sxy = 0.0, chi2_mean = 0.0;
  for (int i = p; i < n; ++i) {
    const double w = 1.0 / (s.u[i] * s.u[i]);
    sxx += w * (s.x[i] - mx) * (s.x[i] - mx);
    sxy += w * (s.x[i] - mx) * (s.y[i] - my);
    chi2_mean += w * (s.y[i] - my) * (s.y[i] - my);
  }
  const double slope = sxy / sxx;
  const double chi2_line = std::max(0.0, chi2_mean - slope * slope * sxx);
  const int count = n - p;
  const double scatter = std::sqrt(std::max(1.0, chi2_line / (count - 2)));
  TailTest t;
  t.slope = slope;
  t.slope_se = scatter / std::sqrt(sxx);
  t.flat = std::abs(slope) <= z * t.slope_se;
  t.mean = my;
  t.mean_se = std::sqrt(std::max(1.0, chi2_mean / (count - 1)) / sw);
  return t;
}

// One point of the lambda search.
struct StepFit {
  bool ok = false;
  double log10_relative = 0.0, lambda = 0.0, score = 0.0, chi2 = 0.0, trace_h = 0.0;
  Eigen::VectorXd x;
};

// The usable step with the lowest score among those `admit` accepts (the
// first of equal ones); -1 when none.
template <class Admit>
int BestStep(const std::vector<StepFit>& steps, Admit admit) {
  int best = -1;
  for (int k = 0; k < static_cast<int>(steps.size()); ++k)
    if (steps[k].ok && admit(steps[k]) && (best < 0 || steps[k].score < steps[best].score)) best = k;
  return best;
}

// Wahba's posterior covariance s^2 (A^T A + lambda P)^-1 of a step, with
// s^2 = max(1, chi^2 / (n - tr H)) (returned in *scale2).
Eigen::MatrixXd PosteriorCovariance(const Eigen::MatrixXd& AtA, const Eigen::MatrixXd& P,
                                    const StepFit& step, double n, double* scale2) {
  *scale2 = std::max(1.0, step.chi2 / (n - step.trace_h));
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(AtA + step.lambda * P);
  return *scale2 * ldlt.solve(Eigen::MatrixXd::Identity(AtA.rows(), AtA.cols()));
}

// At the null-space end of the penalty (the criterion's best fit has no
// curvature: sigma linear), the Bayesian band is the line's own
// uncertainty, which holds only if the law is linear; a curved law the data
// do not resolve falls out of it (an exponential law on a 48-frame synth
// run: 5 nodes missed; over 30 % of delta_c, GCV jumps to lambda ~ 1e5 on
// half the seeds and the line's band covers 76 % of the nodes). The band
// then allows for the best curved alternative, the criterion's best fit
// with tr H >= dim(null space) + 0.5: covariance = its own + d d^T, d the
// step from the line to it.
void AllowForUnresolvedCurvature(const Eigen::MatrixXd& AtA, const Eigen::MatrixXd& P, double n,
                                 const std::vector<StepFit>& steps, PenalisedFit* fit) {
  const int null_dim = static_cast<int>(P.cols()) - Eigen::FullPivLU<Eigen::MatrixXd>(P).rank();
  if (!(fit->trace_h < null_dim + 0.5)) return;
  const int alt = BestStep(steps, [&](const StepFit& s) { return s.trace_h >= null_dim + 0.5; });
  if (alt < 0) return;
  double scale2 = 1.0;
  const Eigen::VectorXd d = steps[alt].x - fit->x;
  fit->covariance = PosteriorCovariance(AtA, P, steps[alt], n, &scale2) + d * d.transpose();
  fit->null_space_allowance_dof = steps[alt].trace_h;
}

}  // namespace

Samples CheckAndSort(const std::vector<double>& opening, const std::vector<double>& value,
                     const std::vector<double>& uncertainty, const std::string& opening_name,
                     const std::string& value_name, int min_points) {
  BF_CHECK_INPUT(
      value.size() == opening.size(), "every opening needs one value",
      {.field = value_name,
       .value = std::to_string(value.size()) + " values",
       .expected = std::to_string(opening.size()) + " (as many as " + opening_name + ")"});
  BF_CHECK_INPUT(
      uncertainty.size() == opening.size(), "every value needs one uncertainty",
      {.field = "uncertainty",
       .value = std::to_string(uncertainty.size()) + " values",
       .expected = std::to_string(opening.size()) + " (as many as " + opening_name + ")"});
  BF_CHECK_INPUT(static_cast<int>(opening.size()) >= min_points,
                 "too few samples to read a bridging law from",
                 {.field = opening_name,
                  .value = std::to_string(opening.size()) + " samples",
                  .expected = "at least " + std::to_string(min_points) + " samples"});
  CheckFinite(opening, opening_name);
  CheckFinite(value, value_name);
  CheckFinite(uncertainty, "uncertainty");
  for (size_t i = 0; i < uncertainty.size(); ++i)
    BF_CHECK_INPUT(uncertainty[i] > 0.0, "standard uncertainties must be positive",
                   {.field = Indexed("uncertainty", i),
                    .value = std::to_string(uncertainty[i]),
                    .expected = "u > 0 (same unit as " + value_name + ")"});
  Samples s;
  s.order.resize(opening.size());
  std::iota(s.order.begin(), s.order.end(), 0);
  std::stable_sort(s.order.begin(), s.order.end(),
                   [&](int a, int b) { return opening[a] < opening[b]; });
  for (size_t k = 0; k < s.order.size(); ++k) {
    const int i = s.order[k];
    if (k > 0)
      BF_CHECK_INPUT(opening[i] > s.x.back(),
                     "openings must be distinct (strictly increasing "
                     "once sorted)",
                     {.field = Indexed(opening_name, i),
                      .value = std::to_string(opening[i]),
                      .expected = "an opening different from every other sample's"});
    s.x.push_back(opening[i]);
    s.y.push_back(value[i]);
    s.u.push_back(uncertainty[i]);
  }
  return s;
}

Grid MakeGrid(double x_max, int node_count) {
  Grid g;
  g.h = x_max / (node_count - 1);
  for (int j = 0; j < node_count; ++j) g.nodes.push_back(j * g.h);
  g.nodes.back() = x_max;
  return g;
}

Eigen::RowVectorXd HatIntegrals(const Grid& grid, double x) {
  const int m = static_cast<int>(grid.nodes.size());
  Eigen::RowVectorXd a = Eigen::RowVectorXd::Zero(m);
  const double h = grid.h;
  for (int k = 0; k + 1 < m; ++k) {
    const double x0 = grid.nodes[k];
    if (x <= x0) break;
    // Interval [x0, x0 + h]: int phi_k = h (t - t^2/2), int phi_{k+1} = h t^2 / 2.
    const double t = std::min(1.0, (x - x0) / h);
    a[k] += h * (t - 0.5 * t * t);
    a[k + 1] += h * 0.5 * t * t;
  }
  return a;
}

Eigen::RowVectorXd HatValues(const Grid& grid, double x) {
  const int m = static_cast<int>(grid.nodes.size());
  Eigen::RowVectorXd v = Eigen::RowVectorXd::Zero(m);
  const int k = std::clamp(static_cast<int>(std::floor(x / grid.h)), 0, m - 2);
  const double t = std::clamp((x - grid.nodes[k]) / grid.h, 0.0, 1.0);
  v[k] = 1.0 - t;
  v[k + 1] = t;
  return v;
}

Eigen::MatrixXd SecondDifferences(int node_count) {
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(std::max(0, node_count - 2), node_count);
  for (int j = 1; j + 1 < node_count; ++j) {
    d(j - 1, j - 1) = 1.0;
    d(j - 1, j) = -2.0;
    d(j - 1, j + 1) = 1.0;
  }
  return d;
}

RCurveSystem MakeRCurveSystem(const Samples& s, const Grid& grid, std::optional<double> J_tip_c,
                              double sigma_end) {
  RCurveSystem sys;
  const int n = static_cast<int>(s.x.size()), m = static_cast<int>(grid.nodes.size());
  sys.offset = J_tip_c ? 0 : 1;
  sys.free_nodes = m - 1;
  sys.A = Eigen::MatrixXd::Zero(n, sys.offset + sys.free_nodes);
  sys.b.resize(n);
  for (int i = 0; i < n; ++i) {
    const Eigen::RowVectorXd row =
        HatIntegrals(grid, s.x[i]) - 0.5 * s.x[i] * HatValues(grid, s.x[i]);
    if (sys.offset) sys.A(i, 0) = 1.0 / s.u[i];
    sys.A.block(i, sys.offset, 1, sys.free_nodes) = row.head(sys.free_nodes) / s.u[i];
    sys.b[i] = (s.y[i] - J_tip_c.value_or(0.0) - sigma_end * row.sum()) / s.u[i];
  }
  const Eigen::MatrixXd D = SecondDifferences(m).leftCols(sys.free_nodes);
  const int k = sys.offset + sys.free_nodes;
  sys.P = Eigen::MatrixXd::Zero(k, k);
  sys.P.bottomRightCorner(sys.free_nodes, sys.free_nodes) = D.transpose() * D;
  return sys;
}

PenalisedFit SolvePenalised(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                            const Eigen::MatrixXd& P, PenaltyRule rule, double gcv_gamma) {
  const Eigen::MatrixXd AtA = A.transpose() * A;
  const Eigen::VectorXd Atb = A.transpose() * b;
  const double n = static_cast<double>(A.rows());
  const double base = AtA.trace() / std::max(P.trace(), std::numeric_limits<double>::min());
  // log10(lambda / base) from -10 to 6 in steps of 0.1.
  constexpr int kSteps = 161;
  constexpr double kFirst = -10.0, kStep = 0.1;
  std::vector<StepFit> steps(kSteps);
  for (int step = 0; step < kSteps; ++step) {
    const double t = kFirst + kStep * step;
    const double lambda = base * std::pow(10.0, t);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(AtA + lambda * P);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) continue;
    const Eigen::VectorXd x = ldlt.solve(Atb);
    const double chi2 = (b - A * x).squaredNorm();
    const double trace_h = ldlt.solve(AtA).trace();
    if (!std::isfinite(chi2) || !std::isfinite(trace_h) || n - gcv_gamma * trace_h < 1.0) continue;
    double score = 0.0;
    switch (rule) {
      case PenaltyRule::kGeneralisedCrossValidation:
        score = n * chi2 / ((n - gcv_gamma * trace_h) * (n - gcv_gamma * trace_h));
        break;
      case PenaltyRule::kUnbiasedRisk:
        score = chi2 + 2.0 * trace_h;
        break;
      case PenaltyRule::kDiscrepancy:
        // The largest lambda with chi^2 <= n; when none reaches it (u
        // understated), the smallest lambda. t lies in [-10, 6].
        score = chi2 <= n ? -t : 1e6 + t;
        break;
    }
    steps[step] = {.ok = true, .log10_relative = t, .lambda = lambda, .score = score,
                   .chi2 = chi2, .trace_h = trace_h, .x = x};
  }
  const int best_step = BestStep(steps, [](const StepFit&) { return true; });
  if (best_step < 0)
    throw Error(ErrorKind::kRuntime, "the penalised least squares found no usable penalty",
                {.expected = "samples that determine sigma on the grid"});
  const StepFit& chosen = steps[best_step];
  PenalisedFit best;
  best.x = chosen.x;
  best.lambda = chosen.lambda;
  best.log10_relative = chosen.log10_relative;
  best.chi2 = chosen.chi2;
  best.trace_h = chosen.trace_h;
  best.at_search_edge = best_step == 0 || best_step == kSteps - 1;
  double scale2 = 1.0;
  best.covariance = PosteriorCovariance(AtA, P, chosen, n, &scale2);
  best.noise_scale = std::sqrt(scale2);
  AllowForUnresolvedCurvature(AtA, P, n, steps, &best);
  return best;
}

PenaltySolution SolveAtPenalty(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                               const Eigen::MatrixXd& P, double lambda, double noise_scale) {
  const Eigen::MatrixXd H = A.transpose() * A + lambda * P;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
  PenaltySolution out;
  out.x = ldlt.solve(A.transpose() * b);
  out.variance = noise_scale * noise_scale *
                 ldlt.solve(Eigen::MatrixXd::Identity(H.rows(), H.cols())).diagonal();
  return out;
}

Plateau FindPlateau(const Samples& s, int first, const LawFreeOptions& options) {
  const int n = static_cast<int>(s.x.size());
  const double range = s.x[n - 1] - s.x[first];
  Plateau plateau;
  for (int p = n - options.plateau_min_points; p >= first; --p) {
    if (s.x[n - 1] - s.x[p] < options.plateau_span * range) continue;
    const TailTest t = TestTail(s, p, options.plateau_z);
    if (!t.flat) continue;
    // Not significantly rising is not enough (noisy data never are): the
    // rise the tail still allows over its span, at plateau_z standard
    // errors, must be a small part of the curve's rise to the plateau, or
    // the noise, not the law, made it flat (an equivalence test).
    const double allowed = (std::abs(t.slope) + options.plateau_z * t.slope_se) *
                           (s.x[n - 1] - s.x[p]);
    const double rise = t.mean - s.y[first];
    if (!(rise > 0.0 && allowed <= options.plateau_rise_fraction * rise)) continue;
    plateau.found = true;
    plateau.start = p;
    plateau.mean = t.mean;
    plateau.mean_se = t.mean_se;
  }
  return plateau;
}

int DetectOnset(const Samples& s, const LawFreeOptions& options, std::string* note) {
  const int n = static_cast<int>(s.x.size());
  const int w = options.onset_window;
  if (n < w + 3) {
    *note =
        "too few samples to look for the onset of growth; the first sample is taken as "
        "the onset";
    return 0;
  }
  // The onset is the kink where the steep pre-growth rise of J_ff (J_tip
  // rising at nearly fixed delta*) gives way to the bridging slope sigma:
  // the sample k where the line through [k - w, k] is steepest compared with
  // the next step k -> k + 1. The next step alone, not a window, so that a
  // window straddling the kink cannot blur it.
  int best_k = -1;
  double best_contrast = -std::numeric_limits<double>::infinity();
  for (int k = 1; k + w < n; ++k) {
    const double next = (s.y[k + 1] - s.y[k]) / (s.x[k + 1] - s.x[k]);
    const double contrast = FitLine(s, std::max(0, k - w), k).slope - next;
    if (contrast > best_contrast) best_contrast = contrast, best_k = k;
  }
  const double pre = FitLine(s, std::max(0, best_k - w), best_k).slope;
  double post_max = 0.0;
  for (int j = best_k; j + w < n; ++j) post_max = std::max(post_max, FitLine(s, j, j + w).slope);
  if (pre > options.onset_kink_ratio * post_max) return best_k;
  *note =
      "no kink in J_ff(delta*) marks the onset of growth (the steepest pre-onset slope is "
      "not " +
      std::to_string(options.onset_kink_ratio) +
      " times the later ones); the first sample is taken as the onset";
  return 0;
}

}  // namespace bridgefit::laws::law_free_detail
