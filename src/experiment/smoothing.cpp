// Building blocks of the R-curve reduction: isotonic regression, robust
// noise estimates, energy released between two rows.
#include <algorithm>
#include <cmath>
#include <vector>

#include "bridgefit/core/error.hpp"
#include "bridgefit/experiment/rcurve.hpp"

namespace bridgefit::experiment {

std::vector<double> IsotonicIncreasing(const std::vector<double>& values) {
  // Pool adjacent violators: blocks of (mean, count), merged while decreasing.
  std::vector<double> mean;
  std::vector<int> count;
  mean.reserve(values.size());
  count.reserve(values.size());
  for (double v : values) {
    mean.push_back(v);
    count.push_back(1);
    while (mean.size() > 1 && mean[mean.size() - 2] > mean.back()) {
      const std::size_t k = mean.size() - 1;
      const int n = count[k - 1] + count[k];
      mean[k - 1] = (mean[k - 1] * count[k - 1] + mean[k] * count[k]) / n;
      count[k - 1] = n;
      mean.pop_back();
      count.pop_back();
    }
  }
  std::vector<double> out;
  out.reserve(values.size());
  for (std::size_t b = 0; b < mean.size(); ++b) out.insert(out.end(), count[b], mean[b]);
  return out;
}

namespace {
double Median(std::vector<double> v) {
  if (v.empty()) return NAN;
  const std::size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + m, v.end());
  double med = v[m];
  if (v.size() % 2 == 0) {
    std::nth_element(v.begin(), v.begin() + m - 1, v.end());
    med = 0.5 * (med + v[m - 1]);
  }
  return med;
}
}  // namespace

double RobustNoiseSigma(const std::vector<double>& values) {
  if (values.size() < 5) return 0.0;
  std::vector<double> second;
  second.reserve(values.size() - 2);
  for (std::size_t i = 1; i + 1 < values.size(); ++i)
    second.push_back(values[i + 1] - 2.0 * values[i] + values[i - 1]);
  const double med = Median(second);
  for (double& s : second) s = std::abs(s - med);
  // Var(x[i+1] - 2x[i] + x[i-1]) = 6 sigma^2 for white noise.
  return 1.4826 * Median(second) / std::sqrt(6.0);
}

double ScatterAboutMovingAverage(const std::vector<double>& x, int half_window) {
  const int n = static_cast<int>(x.size());
  if (n < 2 * half_window + 2) return 0.0;
  std::vector<double> residual;
  residual.reserve(n);
  double sum = 0.0;
  for (int k = 0; k < 2 * half_window + 1; ++k) sum += x[k];
  const int width = 2 * half_window + 1;
  for (int i = half_window; i + half_window < n; ++i) {
    if (i > half_window) sum += x[i + half_window] - x[i - half_window - 1];
    residual.push_back(x[i] - sum / width);
  }
  // RMS, not MAD: stick-slip jumps of a tracked crack are heavy-tailed and
  // must count. Var(x_i - mean of its window) = sigma^2 (1 - 1/width).
  double ss = 0.0;
  for (double r : residual) ss += r * r;
  return std::sqrt(ss / residual.size() / (1.0 - 1.0 / width));
}

double EnergyReleased(const std::vector<double>& load, const std::vector<double>& d, int i,
                      int j) {
  BF_DEBUG_ASSERT(i >= 0 && j < static_cast<int>(load.size()) && i < j);
  double work = 0.0;
  for (int k = i; k < j; ++k) work += 0.5 * (load[k] + load[k + 1]) * (d[k + 1] - d[k]);
  return work - 0.5 * (load[j] * d[j] - load[i] * d[i]);
}

LocalWeights LocalQuadraticWeights(const std::vector<double>& x, int first, int last, int row,
                                   int half_window) {
  BF_DEBUG_ASSERT(first <= row && row <= last && last < static_cast<int>(x.size()));
  int lo = row - half_window, hi = row + half_window;
  if (lo < first) hi += first - lo, lo = first;
  if (hi > last) lo -= hi - last, hi = last;
  lo = std::max(lo, first);
  LocalWeights out;
  out.first_row = lo;
  const int n = hi - lo + 1;
  // Abscissa centred on the row and scaled to [-1, 1] for conditioning.
  double scale = 0.0;
  for (int m = lo; m <= hi; ++m) scale = std::max(scale, std::abs(x[m] - x[row]));
  std::vector<double> t(n, 0.0);
  if (scale > 0)
    for (int m = lo; m <= hi; ++m) t[m - lo] = (x[m] - x[row]) / scale;
  // Value at t = 0 of the least-squares polynomial: weights_m = phi(t_m)^T M^-1 e0,
  // M = sum phi phi^T, phi = (1, t, t^2); degree lowered while M is singular.
  for (int degree = std::min(2, n - 1); degree >= 0; --degree) {
    const int p = degree + 1;
    double M[3][4] = {};
    for (double tm : t) {
      const double phi[3] = {1.0, tm, tm * tm};
      for (int r = 0; r < p; ++r)
        for (int c = 0; c < p; ++c) M[r][c] += phi[r] * phi[c];
    }
    M[0][p] = 1.0;  // right-hand side e0
    bool singular = false;
    for (int c = 0; c < p && !singular; ++c) {
      int pivot = c;
      for (int r = c + 1; r < p; ++r)
        if (std::abs(M[r][c]) > std::abs(M[pivot][c])) pivot = r;
      if (!(std::abs(M[pivot][c]) > 1e-10 * n)) singular = true;
      if (singular) break;
      for (int k = 0; k <= p; ++k) std::swap(M[c][k], M[pivot][k]);
      for (int r = 0; r < p; ++r) {
        if (r == c) continue;
        const double f = M[r][c] / M[c][c];
        for (int k = c; k <= p; ++k) M[r][k] -= f * M[c][k];
      }
    }
    if (singular) continue;
    double coef[3] = {};
    for (int r = 0; r < p; ++r) coef[r] = M[r][p] / M[r][r];
    out.weights.resize(n);
    for (int m = 0; m < n; ++m)
      out.weights[m] = coef[0] + (p > 1 ? coef[1] * t[m] : 0.0) + (p > 2 ? coef[2] * t[m] * t[m] : 0.0);
    return out;
  }
  out.weights.assign(n, 1.0 / n);
  return out;
}

}  // namespace bridgefit::experiment
