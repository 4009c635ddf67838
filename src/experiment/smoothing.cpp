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

}  // namespace bridgefit::experiment
