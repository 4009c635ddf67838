// Cubic B-spline prefilter (Unser 1991): causal + anticausal recursion with
// the pole z = sqrt(3) - 2 and mirror boundaries, separable in x and y.
#include "interpolation.hpp"

#include <algorithm>

#if defined(__SSE2__)
#include <emmintrin.h>
#include <xmmintrin.h>
#endif

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


#if defined(__SSE2__)
// Cubic weights of four samples at once (lanes = samples), the same
// polynomials as InterpolatedImage::Weights.
void CubicWeights4(__m128 t, bool bspline, __m128* w) {
  const __m128 t2 = _mm_mul_ps(t, t), t3 = _mm_mul_ps(t2, t);
  auto c = [](float v) { return _mm_set1_ps(v); };
  if (bspline) {
    const __m128 s = _mm_sub_ps(c(1.0f), t);
    w[0] = _mm_mul_ps(_mm_mul_ps(_mm_mul_ps(s, s), s), c(1.0f / 6.0f));
    w[1] = _mm_add_ps(_mm_sub_ps(_mm_mul_ps(c(0.5f), t3), t2), c(4.0f / 6.0f));
    w[3] = _mm_mul_ps(t3, c(1.0f / 6.0f));
    w[2] = _mm_sub_ps(_mm_sub_ps(_mm_sub_ps(c(1.0f), w[0]), w[1]), w[3]);
  } else {  // Keys, a = -0.5
    w[0] = _mm_add_ps(_mm_mul_ps(c(-0.5f), t3), _mm_sub_ps(t2, _mm_mul_ps(c(0.5f), t)));
    w[1] = _mm_add_ps(_mm_sub_ps(_mm_mul_ps(c(1.5f), t3), _mm_mul_ps(c(2.5f), t2)), c(1.0f));
    w[3] = _mm_sub_ps(_mm_mul_ps(c(0.5f), t3), _mm_mul_ps(c(0.5f), t2));
    w[2] = _mm_sub_ps(_mm_sub_ps(_mm_sub_ps(c(1.0f), w[0]), w[1]), w[3]);
  }
}
#endif

}  // namespace

InterpolatedImage::InterpolatedImage(const Image& image, Interpolation interpolation)
    : width(image.width), height(image.height), kind(interpolation) {
  coef.assign(image.pixels.begin(), image.pixels.end());
  if (kind != Interpolation::kBSpline3) return;
  // Rows, then columns in blocks of kBlock (gathered row by row, so the
  // reads and writes stay contiguous); both passes in parallel (OpenMP),
  // each line with the same arithmetic as a serial pass.
  constexpr int kBlock = 16;
#pragma omp parallel
  {
    std::vector<double> line(std::max(width, height));
    std::vector<double> block(static_cast<size_t>(kBlock) * height);
#pragma omp for schedule(static)
    for (int y = 0; y < height; ++y) {
      float* row = coef.data() + static_cast<size_t>(y) * width;
      for (int x = 0; x < width; ++x) line[x] = row[x];
      Prefilter1D(line.data(), width);
      for (int x = 0; x < width; ++x) row[x] = static_cast<float>(line[x]);
    }
#pragma omp for schedule(static)
    for (int x0 = 0; x0 < width; x0 += kBlock) {
      const int nb = std::min(kBlock, width - x0);
      for (int y = 0; y < height; ++y) {
        const float* row = coef.data() + static_cast<size_t>(y) * width + x0;
        for (int b = 0; b < nb; ++b) block[static_cast<size_t>(b) * height + y] = row[b];
      }
      for (int b = 0; b < nb; ++b) Prefilter1D(block.data() + static_cast<size_t>(b) * height, height);
      for (int y = 0; y < height; ++y) {
        float* row = coef.data() + static_cast<size_t>(y) * width + x0;
        for (int b = 0; b < nb; ++b) row[b] = static_cast<float>(block[static_cast<size_t>(b) * height + y]);
      }
    }
  }
}

NodeMaps InterpolatedImage::Nodes() const {
  NodeMaps m;
  m.width = width;
  m.height = height;
  const size_t size = static_cast<size_t>(width) * height;
  m.value.assign(size, 0.0f);
  m.gx.assign(size, 0.0f);
  m.gy.assign(size, 0.0f);
  if (width < 3 || height < 3) return m;
  // Node weights of the interpolant (-1, 0, +1): value and first derivative.
  const bool bspline = kind == Interpolation::kBSpline3;
  const float side = bspline ? 1.0f / 6.0f : 0.0f, centre = bspline ? 4.0f / 6.0f : 1.0f;
  std::vector<float> smooth(width), diff(width);
  for (int y = 1; y < height - 1; ++y) {
    const float* up = coef.data() + static_cast<size_t>(y - 1) * width;
    const float* mid = up + width;
    const float* down = mid + width;
    for (int x = 0; x < width; ++x) {
      smooth[x] = side * (up[x] + down[x]) + centre * mid[x];
      diff[x] = 0.5f * (down[x] - up[x]);
    }
    float* value = m.value.data() + static_cast<size_t>(y) * width;
    float* gx = m.gx.data() + static_cast<size_t>(y) * width;
    float* gy = m.gy.data() + static_cast<size_t>(y) * width;
    for (int x = 1; x < width - 1; ++x) {
      value[x] = side * (smooth[x - 1] + smooth[x + 1]) + centre * smooth[x];
      gx[x] = 0.5f * (smooth[x + 1] - smooth[x - 1]);
      gy[x] = side * (diff[x - 1] + diff[x + 1]) + centre * diff[x];
    }
  }
  return m;
}

void InterpolatedImage::SampleRow(double x0, double y0, double ax, double ay, int count,
                                  float* out) const {
  int j = 0;
#if defined(__SSE2__)
  // Four samples per step: weights with the samples in the lanes, then per
  // sample the four coefficient rows (one unaligned load each) combined
  // with its y weights and x weights; a transpose sums the four taps.
  if (count >= 4) {
    const bool bspline = kind == Interpolation::kBSpline3;
    auto group = [&](int j0) {
      const __m128d xa = _mm_set_pd(x0 + ax * (j0 + 1), x0 + ax * j0);
      const __m128d xb = _mm_set_pd(x0 + ax * (j0 + 3), x0 + ax * (j0 + 2));
      const __m128d ya = _mm_set_pd(y0 + ay * (j0 + 1), y0 + ay * j0);
      const __m128d yb = _mm_set_pd(y0 + ay * (j0 + 3), y0 + ay * (j0 + 2));
      // Positions are >= 1 (Inside), so truncation is the floor.
      const __m128i ixa = _mm_cvttpd_epi32(xa), ixb = _mm_cvttpd_epi32(xb);
      const __m128i iya = _mm_cvttpd_epi32(ya), iyb = _mm_cvttpd_epi32(yb);
      const __m128 tx = _mm_movelh_ps(_mm_cvtpd_ps(_mm_sub_pd(xa, _mm_cvtepi32_pd(ixa))),
                                      _mm_cvtpd_ps(_mm_sub_pd(xb, _mm_cvtepi32_pd(ixb))));
      const __m128 ty = _mm_movelh_ps(_mm_cvtpd_ps(_mm_sub_pd(ya, _mm_cvtepi32_pd(iya))),
                                      _mm_cvtpd_ps(_mm_sub_pd(yb, _mm_cvtepi32_pd(iyb))));
      alignas(16) int ix[4], iy[4];
      _mm_store_si128(reinterpret_cast<__m128i*>(ix), _mm_unpacklo_epi64(ixa, ixb));
      _mm_store_si128(reinterpret_cast<__m128i*>(iy), _mm_unpacklo_epi64(iya, iyb));
      __m128 wx[4], wy[4];
      CubicWeights4(tx, bspline, wx);
      CubicWeights4(ty, bspline, wy);
      _MM_TRANSPOSE4_PS(wx[0], wx[1], wx[2], wx[3]);  // wx[s]: the four x taps of sample s
      _MM_TRANSPOSE4_PS(wy[0], wy[1], wy[2], wy[3]);
      __m128 taps[4];
      for (int s = 0; s < 4; ++s) {
        const float* p = coef.data() + static_cast<size_t>(iy[s] - 1) * width + (ix[s] - 1);
        const __m128 w = wy[s];
        __m128 r = _mm_mul_ps(_mm_loadu_ps(p), _mm_shuffle_ps(w, w, 0x00));
        r = _mm_add_ps(r, _mm_mul_ps(_mm_loadu_ps(p + width), _mm_shuffle_ps(w, w, 0x55)));
        r = _mm_add_ps(r, _mm_mul_ps(_mm_loadu_ps(p + 2 * width), _mm_shuffle_ps(w, w, 0xAA)));
        r = _mm_add_ps(r, _mm_mul_ps(_mm_loadu_ps(p + 3 * width), _mm_shuffle_ps(w, w, 0xFF)));
        taps[s] = _mm_mul_ps(r, wx[s]);
      }
      _MM_TRANSPOSE4_PS(taps[0], taps[1], taps[2], taps[3]);
      _mm_storeu_ps(out + j0, _mm_add_ps(_mm_add_ps(taps[0], taps[1]), _mm_add_ps(taps[2], taps[3])));
    };
    for (; j + 4 <= count; j += 4) group(j);
    if (j < count) group(count - 4);  // overlaps the previous group
    return;
  }
#endif
  for (; j < count; ++j) out[j] = Value(x0 + ax * j, y0 + ay * j);
}

}  // namespace bridgefit::dic::detail
