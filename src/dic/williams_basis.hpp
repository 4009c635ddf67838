#pragma once
// Private: the Williams eigenfunctions of a traction-free crack (faces at
// t = +-pi), shared by the crack-tip fit (crack_williams.cpp) and the
// field-wide J fit (j_fit.cpp). Yoneyama et al. 2006 form without 1/(2 mu):
// displacement r^(n/2) f_n(t) in the crack frame; any integer n (negative n
// are the terms singular at the expansion's centre, which a Laurent series
// about a point inside the bridging zone needs outside it).

#include <array>
#include <cmath>
#include <complex>

#include "bridgefit/core/error.hpp"

namespace bridgefit::dic::detail {

inline void WilliamsModeI(int n, double r, double t, double kappa, double* fx, double* fy) {
  const double h = 0.5 * n, rn = std::pow(r, h), sgn = (n % 2 == 0) ? 1.0 : -1.0;
  *fx = rn * (kappa * std::cos(h * t) - h * std::cos((h - 2) * t) + (h + sgn) * std::cos(h * t));
  *fy = rn * (kappa * std::sin(h * t) + h * std::sin((h - 2) * t) - (h + sgn) * std::sin(h * t));
}
inline void WilliamsModeII(int n, double r, double t, double kappa, double* fx, double* fy) {
  const double h = 0.5 * n, rn = std::pow(r, h), sgn = (n % 2 == 0) ? 1.0 : -1.0;
  *fx = -rn * (kappa * std::sin(h * t) - h * std::sin((h - 2) * t) + (h - sgn) * std::sin(h * t));
  *fy = rn * (kappa * std::cos(h * t) + h * std::cos((h - 2) * t) - (h - sgn) * std::cos(h * t));
}

// The same terms for every order n in [lo, hi] at one point, from the powers
// P_n = r^(n/2) e^(i n t/2) of w = sqrt(r) e^(i t/2) (products, one sincos
// and one sqrt a point instead of a pow and four sincos a term; the fits
// evaluate about 10^8 terms a sequence): with Q_n = P_n e^(-2 i t),
//   mode I:  fx = (kappa + h + s) Re P - h Re Q,  fy = (kappa - h - s) Im P + h Im Q,
//   mode II: fx = -(kappa + h - s) Im P + h Im Q, fy = (kappa - h + s) Re P + h Re Q,
// h = n/2, s = +1 for even n, -1 for odd: WilliamsModeI / II above, to
// rounding (tests/dic/j_fit_test.cpp). t in [-pi, pi] as atan2 gives it.
class WilliamsPowers {
 public:
  static constexpr int kMaxOrders = 40;
  WilliamsPowers(double r, double t, int lo, int hi)
      : WilliamsPowers(std::sqrt(r) * std::complex<double>(std::cos(0.5 * t), std::sin(0.5 * t)),
                       std::complex<double>(std::cos(t), -std::sin(t)), lo, hi) {}
  // The same at the point (x, y) of the crack frame, without trigonometry:
  // w = sqrt(x + i y) on the principal branch (t in [-pi, pi], as atan2
  // gives it; the faces behind the tip, y = +-0, at t = +-pi), e^(-i t) =
  // (x - i y) / r. The tip itself (r = 0): every positive power zero.
  static WilliamsPowers AtPoint(double x, double y, int lo, int hi) {
    const double r = std::hypot(x, y);
    const std::complex<double> e =
        r > 0 ? std::complex<double>(x / r, -y / r) : std::complex<double>(1.0, 0.0);
    return WilliamsPowers(std::sqrt(std::complex<double>(x, y)), e, lo, hi);
  }
  void ModeI(int n, double kappa, double* fx, double* fy) const {
    const std::complex<double> P = p_[n - lo_], Q = P * rot_;
    const double h = 0.5 * n, s = (n % 2 == 0) ? 1.0 : -1.0;
    *fx = (kappa + h + s) * P.real() - h * Q.real();
    *fy = (kappa - h - s) * P.imag() + h * Q.imag();
  }
  void ModeII(int n, double kappa, double* fx, double* fy) const {
    const std::complex<double> P = p_[n - lo_], Q = P * rot_;
    const double h = 0.5 * n, s = (n % 2 == 0) ? 1.0 : -1.0;
    *fx = -(kappa + h - s) * P.imag() + h * Q.imag();
    *fy = (kappa - h + s) * P.real() + h * Q.real();
  }

 private:
  // From w = sqrt(r) e^(i t/2) and e = e^(-i t).
  WilliamsPowers(std::complex<double> w, std::complex<double> e, int lo, int hi) : lo_(lo) {
    if (!(hi >= lo && hi - lo < kMaxOrders))
      throw Error(ErrorKind::kUsage, "Williams series: at most 40 orders, lowest <= highest");
    rot_ = e * e;
    // P_lo by repeated products (or quotients), then up.
    std::complex<double> p(1.0, 0.0);
    if (lo >= 0) {
      for (int k = 0; k < lo; ++k) p *= w;
    } else {
      const std::complex<double> inv = 1.0 / w;
      for (int k = 0; k < -lo; ++k) p *= inv;
    }
    for (int k = 0; k <= hi - lo; ++k, p *= w) p_[k] = p;
  }

  int lo_;
  std::complex<double> rot_;
  std::array<std::complex<double>, kMaxOrders> p_{};
};

}  // namespace bridgefit::dic::detail
