// Cubic B-spline prefilter (Unser 1991): causal + anticausal recursion with
// the pole z = sqrt(3) - 2 and mirror boundaries, separable in x and y.
#include "interpolation.hpp"

#include <algorithm>

namespace bridgefit::dic::detail {
namespace {

void Prefilter1D(double* c, int n) {
  if (n < 2) return;
  const double z = std::sqrt(3.0) - 2.0;
  const double lambda = (1.0 - z) * (1.0 - 1.0 / z);
  for (int k = 0; k < n; ++k) c[k] *= lambda;
  // Causal initial value, mirror boundary, truncated where z^k < 1e-10.
  const int horizon = std::min(n, 22);
  double zk = z, sum = c[0];
  for (int k = 1; k < horizon; ++k) {
    sum += zk * c[k];
    zk *= z;
  }
  c[0] = sum;
  for (int k = 1; k < n; ++k) c[k] += z * c[k - 1];
  c[n - 1] = (z / (z * z - 1.0)) * (c[n - 1] + z * c[n - 2]);
  for (int k = n - 2; k >= 0; --k) c[k] = z * (c[k + 1] - c[k]);
}

}  // namespace

InterpolatedImage::InterpolatedImage(const Image& image, Interpolation interpolation)
    : width(image.width), height(image.height), kind(interpolation) {
  coef.assign(image.pixels.begin(), image.pixels.end());
  if (kind != Interpolation::kBSpline3) return;
  std::vector<double> line(std::max(width, height));
  for (int y = 0; y < height; ++y) {
    float* row = coef.data() + static_cast<size_t>(y) * width;
    for (int x = 0; x < width; ++x) line[x] = row[x];
    Prefilter1D(line.data(), width);
    for (int x = 0; x < width; ++x) row[x] = static_cast<float>(line[x]);
  }
  for (int x = 0; x < width; ++x) {
    for (int y = 0; y < height; ++y) line[y] = coef[static_cast<size_t>(y) * width + x];
    Prefilter1D(line.data(), height);
    for (int y = 0; y < height; ++y) coef[static_cast<size_t>(y) * width + x] = static_cast<float>(line[y]);
  }
}

}  // namespace bridgefit::dic::detail
