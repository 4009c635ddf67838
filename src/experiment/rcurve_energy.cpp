// The energy method (PHYSICS 8): dU = int P dd - (P_j d_j - P_i d_i)/2 between
// the ends of each crack increment, R = dU / (B da); optionally on local
// quadratic fits of the growth rows (ASTM E647 incremental polynomial).
// Stages: balance values (measured or smoothed) -> increments resolvable
// against the crack-length noise -> one R point per increment.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "rcurve_stages.hpp"

namespace bridgefit::experiment::detail {
namespace {

// The values entering the balance from row `start` on: the rows as measured
// (displacement taken relative to d0, the elastic unloading), or (h > 0)
// local quadratic fits against time over the growth rows [start, m - 1] only,
// so no window straddles the initiation kink.
struct BalanceValues {
  int start = 0;
  int h = 0;  // smoothing half window (0: measured rows)
  std::vector<double> P, d, a;
  std::vector<LocalWeights> fit_weights;  // per row from start (h > 0)
};

// Smoothed values: P, d, a at row k = sum_q w_q(k) (row value)_q over the window.
BalanceValues MeasuredOrSmoothedValues(const Prepared& p, int start, RCurveResult& result) {
  const RCurveOptions& options = *p.options;
  const ExperimentRecord& record = *p.record;
  const Rows& w = p.w;
  const int m = static_cast<int>(w.size());
  const int h = options.smoothing_half_window;
  std::vector<double> ds(m);
  for (int k = 0; k < m; ++k) ds[k] = w.d[k] - p.lin.intercept;  // elastic unloading to d0
  BalanceValues v;
  v.start = start;
  v.h = h;
  v.P = w.P, v.d = ds, v.a = w.a;
  if (h <= 0) return v;
  std::vector<double> x(m);
  bool time_increases = !record.time.empty();
  for (int k = 0; k < m; ++k) {
    x[k] = time_increases ? record.time[w.row[k]] : k;
    if (k > start && !(x[k] > x[k - 1])) time_increases = false;
  }
  if (!time_increases)
    for (int k = 0; k < m; ++k) x[k] = k;
  double hat_sum = 0.0;
  for (int k = start; k < m; ++k) {
    LocalWeights lw = LocalQuadraticWeights(x, start, m - 1, k, h);
    double P = 0.0, d = 0.0, a = 0.0, hat = 0.0;
    for (std::size_t q = 0; q < lw.weights.size(); ++q) {
      const int r = lw.first_row + static_cast<int>(q);
      P += lw.weights[q] * w.P[r];
      d += lw.weights[q] * ds[r];
      a += lw.weights[q] * w.a_raw[r];
      hat += lw.weights[q] * lw.weights[q];
    }
    v.P[k] = P, v.d[k] = d, v.a[k] = a;
    hat_sum += std::sqrt(hat);
    v.fit_weights.push_back(std::move(lw));
  }
  const double noise_factor = hat_sum / (m - start);  // mean sqrt(sum w^2)
  result.figures["energy_smoothing_half_window_rows"] = h;
  result.figures["energy_smoothed_crack_noise_m"] = noise_factor * p.sigma_a;
  result.notes.push_back(fmt::format(
      "energy method on local quadratic fits of load, displacement and crack length against {} "
      "over {} rows (ASTM E647 incremental polynomial); crack-length noise {} per row, {} "
      "after the fits; every increment spans at least one window",
      time_increases ? "time" : "row number", 2 * h + 1, Mm(p.sigma_a),
      Mm(noise_factor * p.sigma_a)));
  return v;
}

// Standard deviation of a[j] - a[i] over sigma_a: sqrt 2 for raw rows, the
// norm of the difference of the two fits' weights when smoothed.
class IncrementNoise {
 public:
  IncrementNoise(const BalanceValues& v, int m) : v_(v), dense_(v.h > 0 ? m : 0, 0.0) {}
  double operator()(int i, int j) {
    if (v_.h <= 0) return std::sqrt(2.0);
    const LocalWeights& wi = v_.fit_weights[i - v_.start];
    const LocalWeights& wj = v_.fit_weights[j - v_.start];
    for (std::size_t q = 0; q < wj.weights.size(); ++q) dense_[wj.first_row + q] += wj.weights[q];
    for (std::size_t q = 0; q < wi.weights.size(); ++q) dense_[wi.first_row + q] -= wi.weights[q];
    double ss = 0.0;
    const int lo = std::min(wi.first_row, wj.first_row);
    const int hi = std::max(wi.first_row + static_cast<int>(wi.weights.size()),
                            wj.first_row + static_cast<int>(wj.weights.size()));
    for (int r = lo; r < hi; ++r) ss += dense_[r] * dense_[r], dense_[r] = 0.0;
    return std::sqrt(ss);
  }

 private:
  const BalanceValues& v_;
  std::vector<double> dense_;
};

// Increments [i, j]: each the shortest run with da >= da_min (smoothed:
// da >= max(min_crack_increment, increment_resolution x its own noise) and at
// least one window of rows); rows left over at the end join the last one.
std::vector<std::pair<int, int>> CrackIncrements(const Prepared& p, const BalanceValues& v,
                                                 double da_min, IncrementNoise& noise,
                                                 RCurveResult& result) {
  const RCurveOptions& options = *p.options;
  const int m = static_cast<int>(p.w.size());
  const int h = v.h;
  const std::vector<double>& a = v.a;
  auto resolvable = [&](int i, int j) {
    const double da = a[j] - a[i];
    if (h <= 0) return da >= da_min;
    return j - i >= 2 * h + 1 && da >= options.min_crack_increment &&
           da >= options.increment_resolution * p.sigma_a * noise(i, j);
  };
  std::vector<std::pair<int, int>> increments;
  for (int i = v.start;;) {
    int j = i + 1;
    while (j < m && !resolvable(i, j)) ++j;
    if (j >= m) break;
    increments.emplace_back(i, j);
    i = j;
  }
  if (!increments.empty() && increments.back().second < m - 1 &&
      a[m - 1] > a[increments.back().second]) {
    result.notes.push_back(fmt::format("the last {} rows (growth {}) joined the last increment",
                                       m - 1 - increments.back().second,
                                       Mm(a[m - 1] - a[increments.back().second])));
    increments.back().second = m - 1;
  }
  return increments;
}

// Var(dU) from linear sensitivities of dU to every P_k and d_k of the
// increment [i, j] (smoothed: carried back to the measured rows through the
// fits' weights; gP, gd are zeroed scratch of m rows, left zeroed).
double EnergyVariance(const Prepared& p, const BalanceValues& v, int i, int j,
                      std::vector<double>& gP, std::vector<double>& gd) {
  const std::vector<double>& P_e = v.P;
  const std::vector<double>& d_e = v.d;
  const double sigma_P = p.sigma_P, sigma_d = p.sigma_d;
  const int m = static_cast<int>(p.w.size());
  double var = 0.0;
  for (int k = i; k <= j; ++k) {
    const double dprev = k > i ? d_e[k] - d_e[k - 1] : 0.0;
    const double dnext = k < j ? d_e[k + 1] - d_e[k] : 0.0;
    double sP = 0.5 * (dprev + dnext);
    const double Pprev = k > i ? P_e[k - 1] : P_e[k];
    const double Pnext = k < j ? P_e[k + 1] : P_e[k];
    double sd = (k > i ? 0.5 * (Pprev + P_e[k]) : 0.0) - (k < j ? 0.5 * (P_e[k] + Pnext) : 0.0);
    if (k == j) sP -= 0.5 * d_e[k], sd -= 0.5 * P_e[k];
    if (k == i) sP += 0.5 * d_e[k], sd += 0.5 * P_e[k];
    if (v.h <= 0) {
      var += sP * sP * sigma_P * sigma_P + sd * sd * sigma_d * sigma_d;
      continue;
    }
    const LocalWeights& lw = v.fit_weights[k - v.start];
    for (std::size_t q = 0; q < lw.weights.size(); ++q) {
      gP[lw.first_row + q] += sP * lw.weights[q];
      gd[lw.first_row + q] += sd * lw.weights[q];
    }
  }
  if (v.h > 0)
    for (int r = v.start; r < m; ++r) {
      var += gP[r] * gP[r] * sigma_P * sigma_P + gd[r] * gd[r] * sigma_d * sigma_d;
      gP[r] = gd[r] = 0.0;
    }
  return var;
}

}  // namespace

void EnergyMethod(const Prepared& p, RCurveResult& result) {
  const RCurveOptions& options = *p.options;
  const Rows& w = p.w;
  const int m = static_cast<int>(w.size());
  const double B = p.B, a0 = p.a0;
  // The increment is set by the crack readings' own scatter about a smooth
  // monotone fit (p.sigma_a_increment); the uncertainty keeps sigma_a, which
  // on a DCB also holds the compliance-law residual (lagging tracking).
  const double da_min = std::max(options.min_crack_increment,
                                 options.increment_resolution * std::sqrt(2.0) * p.sigma_a_increment);
  const int start = std::max(0, p.first_growth - 1);
  AddDropped(result, "before initiation (no crack growth yet)", start);
  const BalanceValues v = MeasuredOrSmoothedValues(p, start, result);
  IncrementNoise noise(v, m);
  result.figures["energy_min_increment_m"] = v.h > 0 ? options.min_crack_increment : da_min;
  const std::vector<std::pair<int, int>> increments = CrackIncrements(p, v, da_min, noise, result);

  std::vector<double> gP(v.h > 0 ? m : 0, 0.0), gd(v.h > 0 ? m : 0, 0.0);
  int last_end = start;
  for (const auto& [i, j] : increments) {
    const double da = v.a[j] - v.a[i];
    const double R = EnergyReleased(v.P, v.d, i, j) / (B * da);
    const double var = EnergyVariance(p, v, i, j, gP, gd);
    const double rel_da = noise(i, j) * p.sigma_a / da;
    const double u = std::sqrt(var / (B * da * B * da) + R * R * rel_da * rel_da);
    result.curve.crack_length.push_back(0.5 * (v.a[i] + v.a[j]));
    result.curve.R.push_back(R);
    result.curve.R_uncertainty.push_back(options.coverage_factor * u);
    result.crack_growth.push_back(0.5 * (v.a[i] + v.a[j]) - a0);
    result.load.push_back(w.P[j]);
    result.displacement.push_back(w.d[j]);
    result.rows.push_back(w.row[j]);
    last_end = j;
  }
  result.points_used = result.curve.size() > 0 ? last_end - start + 1 : 0;
  AddDropped(result, "tail without crack growth after the last increment",
             result.curve.size() > 0 ? m - 1 - last_end : m - start);
  if (result.curve.size() == 0) {
    const EnergyIncrementLimit limit = EnergyIncrementLimitOf(options, da_min);
    const std::string increment =
        limit == EnergyIncrementLimit::kAsked ? "--min-increment smaller, "
        : limit == EnergyIncrementLimit::kScatter
            ? "--smooth N (local fits over 2 N + 1 rows; the crack readings' scatter sets this "
              "increment), "
            : "";
    throw Error(ErrorKind::kInput, "no crack increment is resolvable against the crack-length noise",
                {.file = p.src, .field = "crack_length", .value = Mm(w.a.back() - a0),
                 .expected = fmt::format(
                     "growth >= {} (R curve stage: energy method); way out: {}--crack-noise, "
                     "or --method mbt|cc (DCB) / lefm (CT)",
                     Mm(da_min), increment)});
  }
  result.curve.initiation_R = result.curve.R.front();
}

}  // namespace bridgefit::experiment::detail
