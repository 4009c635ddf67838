#pragma once
// Test oracle shared by j_integral_test.cpp and j_fit_test.cpp: the mode I
// near-tip field of a rectilinearly anisotropic plate (Sih, Paris & Irwin
// 1965) with compliances a11, a22, a12, a66 (a16 = a26 = 0), roots mu_k of
// a11 mu^4 + (2 a12 + a66) mu^2 + a22 = 0 with Im mu > 0, and
// J = G = -(K^2 / 2) a22 Im((mu1 + mu2) / (mu1 mu2)).

#include <cmath>
#include <complex>
#include <numbers>

namespace bridgefit::dic::test_fields {

struct OrthotropicTipField {
  double k;         // Pa m^0.5
  double px;        // metres per px
  double tip_x = 0, tip_y = 0;  // px; the crack runs along -x from the tip
  double a11, a22, a12, a66;
  std::complex<double> mu1, mu2;
  OrthotropicTipField(double k_si, double E1, double E2, double G12, double nu12, double m_per_px)
      : k(k_si), px(m_per_px) {
    a11 = 1 / E1;
    a22 = 1 / E2;
    a12 = -nu12 / E1;
    a66 = 1 / G12;
    const double b = 2 * a12 + a66, disc = b * b - 4 * a11 * a22;
    const std::complex<double> root = std::sqrt(std::complex<double>(disc));
    const std::complex<double> m1sq = (-b + root) / (2 * a11), m2sq = (-b - root) / (2 * a11);
    mu1 = std::sqrt(m1sq);
    mu2 = std::sqrt(m2sq);
    if (mu1.imag() < 0) mu1 = -mu1;
    if (mu2.imag() < 0) mu2 = -mu2;
  }
  double J() const { return -0.5 * k * k * a22 * ((mu1 + mu2) / (mu1 * mu2)).imag(); }
  // (X, Y) in px; result in px.
  void operator()(double X, double Y, double* u, double* v) const {
    X -= tip_x;
    Y -= tip_y;
    const double r = std::hypot(X, Y) * px, t = std::atan2(Y, X);
    const std::complex<double> p1 = a11 * mu1 * mu1 + a12, p2 = a11 * mu2 * mu2 + a12;
    const std::complex<double> q1 = a12 * mu1 + a22 / mu1, q2 = a12 * mu2 + a22 / mu2;
    const std::complex<double> s1 = std::sqrt(std::cos(t) + mu1 * std::sin(t));
    const std::complex<double> s2 = std::sqrt(std::cos(t) + mu2 * std::sin(t));
    const double a = k * std::sqrt(2 * r / std::numbers::pi);
    const std::complex<double> inv = 1.0 / (mu1 - mu2);
    *u = a * (inv * (mu1 * p2 * s2 - mu2 * p1 * s1)).real() / px;
    *v = a * (inv * (mu1 * q2 * s2 - mu2 * q1 * s1)).real() / px;
  }
};

}  // namespace bridgefit::dic::test_fields
