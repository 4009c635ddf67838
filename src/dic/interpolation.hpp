#pragma once
// Private: cubic B-spline coefficients (prefiltered once per image) and
// Keys bicubic, evaluated with value and gradient on a 4x4 neighbourhood;
// a row sampler for affine warps (four samples per SSE2 step) and the value
// and gradient of the interpolant at every pixel node (reference subsets at
// integer centres read these instead of interpolating).

#include <cmath>
#include <vector>

#include "bridgefit/dic/correlation.hpp"
#include "bridgefit/dic/image.hpp"

namespace bridgefit::dic::detail {

// Value and gradient of the interpolant at the pixel nodes (x, y integer),
// row-major, width x height; valid for 1 <= x <= width - 2 (and y alike),
// the rest is zero. B-spline at a node: value (c[-1] + 4 c[0] + c[1]) / 6,
// derivative (c[1] - c[-1]) / 2 per axis; Keys: the pixel, central differences.
struct NodeMaps {
  int width = 0, height = 0;
  std::vector<float> value, gx, gy;
  bool empty() const { return value.empty(); }
};

// Interpolation coefficients of one image. For B-splines these are the
// prefiltered coefficients c with I(x) = sum c_k beta3(x - k); for Keys the
// pixels themselves.
struct InterpolatedImage {
  int width = 0, height = 0;
  Interpolation kind = Interpolation::kBSpline3;
  std::vector<float> coef;

  InterpolatedImage() = default;
  InterpolatedImage(const Image& image, Interpolation kind);

  // Value and gradient at every node (computed on demand, once per reference).
  NodeMaps Nodes() const;

  // Samples I(x0 + j ax, y0 + j ay) for j = 0..count-1 into out; every
  // sample must be Inside (the caller checks the ends of the row).
  void SampleRow(double x0, double y0, double ax, double ay, int count, float* out) const;

  // The 4x4 neighbourhood of (x, y) lies inside the image.
  bool Inside(double x, double y) const {
    return x >= 1.0 && y >= 1.0 && x < width - 2.0 && y < height - 2.0;
  }
  float Value(double x, double y) const {
    const int ix = static_cast<int>(x), iy = static_cast<int>(y);
    float wx[4], wy[4];
    Weights(static_cast<float>(x - ix), wx);
    Weights(static_cast<float>(y - iy), wy);
    const float* row = coef.data() + static_cast<size_t>(iy - 1) * width + (ix - 1);
    float sum = 0.0f;
    for (int j = 0; j < 4; ++j, row += width)
      sum += wy[j] * (wx[0] * row[0] + wx[1] * row[1] + wx[2] * row[2] + wx[3] * row[3]);
    return sum;
  }
  float ValueGrad(double x, double y, float* gx, float* gy) const {
    const int ix = static_cast<int>(x), iy = static_cast<int>(y);
    float wx[4], wy[4], dx[4], dy[4];
    Weights(static_cast<float>(x - ix), wx, dx);
    Weights(static_cast<float>(y - iy), wy, dy);
    const float* row = coef.data() + static_cast<size_t>(iy - 1) * width + (ix - 1);
    float sum = 0.0f, sx = 0.0f, sy = 0.0f;
    for (int j = 0; j < 4; ++j, row += width) {
      const float r = wx[0] * row[0] + wx[1] * row[1] + wx[2] * row[2] + wx[3] * row[3];
      const float rd = dx[0] * row[0] + dx[1] * row[1] + dx[2] * row[2] + dx[3] * row[3];
      sum += wy[j] * r;
      sy += dy[j] * r;
      sx += wy[j] * rd;
    }
    *gx = sx;
    *gy = sy;
    return sum;
  }

 private:
  void Weights(float t, float* w) const {
    if (kind == Interpolation::kBSpline3) {
      const float s = 1.0f - t, t2 = t * t, t3 = t2 * t;
      w[0] = s * s * s * (1.0f / 6.0f);
      w[1] = (3.0f * t3 - 6.0f * t2 + 4.0f) * (1.0f / 6.0f);
      w[2] = (-3.0f * t3 + 3.0f * t2 + 3.0f * t + 1.0f) * (1.0f / 6.0f);
      w[3] = t3 * (1.0f / 6.0f);
    } else {  // Keys, a = -0.5
      const float t2 = t * t, t3 = t2 * t;
      w[0] = -0.5f * t3 + t2 - 0.5f * t;
      w[1] = 1.5f * t3 - 2.5f * t2 + 1.0f;
      w[2] = -1.5f * t3 + 2.0f * t2 + 0.5f * t;
      w[3] = 0.5f * t3 - 0.5f * t2;
    }
  }
  void Weights(float t, float* w, float* d) const {
    Weights(t, w);
    const float t2 = t * t;
    if (kind == Interpolation::kBSpline3) {
      const float s = 1.0f - t;
      d[0] = -0.5f * s * s;
      d[1] = 1.5f * t2 - 2.0f * t;
      d[2] = -1.5f * t2 + t + 0.5f;
      d[3] = 0.5f * t2;
    } else {
      d[0] = -1.5f * t2 + 2.0f * t - 0.5f;
      d[1] = 4.5f * t2 - 5.0f * t;
      d[2] = -4.5f * t2 + 4.0f * t + 0.5f;
      d[3] = 1.5f * t2 - t;
    }
  }
};

}  // namespace bridgefit::dic::detail
