// The orthotropic traction-free crack series (orthotropic_series.hpp).
#include "orthotropic_series.hpp"

#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#include "bridgefit/core/error.hpp"

namespace bridgefit::dic::detail {

using cd = std::complex<double>;

double OrthotropicRoots(double s11, double s22, double s12, double s66, cd* mu1, cd* mu2) {
  auto roots = [&](double b) {
    const cd root = std::sqrt(cd(b * b - 4 * s11 * s22));
    *mu1 = std::sqrt((-b + root) / (2 * s11));
    *mu2 = std::sqrt((-b - root) / (2 * s11));
    if (mu1->imag() < 0) *mu1 = -*mu1;
    if (mu2->imag() < 0) *mu2 = -*mu2;
  };
  roots(2 * s12 + s66);
  double raised = 0;
  for (double raise = 1e-5; std::abs(*mu1 - *mu2) < 0.02 * std::abs(*mu1); raise *= 2) {
    if (raise > 1e-3)
      throw Error(ErrorKind::kInternal, "orthotropic roots: they stay within 2 %");
    raised = raise;
    roots(2 * s12 + s66 * (1 + raise));
  }
  return raised;
}

OrthotropicSeries::OrthotropicSeries(double s11, double s22, double s12, double s66, int lo,
                                     int hi)
    : s11_(s11), s22_(s22), s12_(s12) {
  OrthotropicRoots(s11_, s22_, s12_, s66, &mu1_, &mu2_);
  p1_ = s11_ * mu1_ * mu1_ + s12_;
  p2_ = s11_ * mu2_ * mu2_ + s12_;
  q1_ = s12_ * mu1_ + s22_ / mu1_;
  q2_ = s12_ * mu2_ + s22_ / mu2_;
  for (int n = lo; n <= hi; ++n) {
    if (n == 0) continue;
    if (n == 2) {
      terms_.push_back({.n = 2, .t_stress = true, .A1 = 1.0});
      continue;
    }
    // Face tractions of (A1, A2) = (a0 + i a1, a2 + i a3) at t = +-pi,
    // less the common factor 2 lambda |x|^(lambda - 1):
    //   Re(w (A1 + A2)) = 0,  Re(w (mu1 A1 + mu2 A2)) = 0,  w = e^(+-i (lambda - 1) pi).
    const double lambda = 0.5 * n;
    Eigen::Matrix4d M;
    int row = 0;
    for (double side : {1.0, -1.0}) {
      const cd w = std::polar(1.0, side * (lambda - 1) * std::numbers::pi);
      const cd c1 = w * mu1_, c2 = w * mu2_;
      M.row(row++) << w.real(), -w.imag(), w.real(), -w.imag();
      M.row(row++) << c1.real(), -c1.imag(), c2.real(), -c2.imag();
    }
    const Eigen::JacobiSVD<Eigen::Matrix4d> svd(M, Eigen::ComputeFullV);
    const Eigen::Vector4d sv = svd.singularValues();
    if (!(sv(2) <= 1e-9 * sv(0)))
      throw Error(ErrorKind::kInternal, "orthotropic series: no two-term null space at an order");
    for (int k = 2; k < 4; ++k) {
      const Eigen::Vector4d a = svd.matrixV().col(k);
      terms_.push_back({.n = n, .A1 = cd(a(0), a(1)), .A2 = cd(a(2), a(3))});
    }
  }
  // Scale each term to a unit RMS displacement on the unit circle (the
  // fit scales its columns anyway; this keeps Q and the K factors O(1/s)).
  for (Term& term : terms_) {
    double ss = 0;
    for (int k = 0; k < 16; ++k) {
      double u1 = 0, u2 = 0;
      TermAt(term, 1.0, std::numbers::pi * (-0.9375 + 0.125 * k), &u1, &u2);
      ss += u1 * u1 + u2 * u2;
    }
    const double scale = 1 / std::sqrt(ss / 16);
    term.A1 *= scale;
    term.A2 *= scale;
  }
}

void OrthotropicSeries::TermAt(const Term& term, double r, double t, double* u1,
                               double* u2) const {
  const double c = std::cos(t), s = std::sin(t);
  if (term.t_stress) {
    // sigma11 = T, sigma22 = sigma12 = 0 (T = A1 / s11): u = (x1, s12/s11 x2) A1.
    *u1 = term.A1.real() * r * c;
    *u2 = term.A1.real() * (s12_ / s11_) * r * s;
    return;
  }
  const double lambda = 0.5 * term.n, rl = std::pow(r, lambda);
  const cd f1 = term.A1 * std::pow(c + mu1_ * s, lambda) * rl;
  const cd f2 = term.A2 * std::pow(c + mu2_ * s, lambda) * rl;
  *u1 = 2 * (p1_ * f1 + p2_ * f2).real();
  *u2 = 2 * (q1_ * f1 + q2_ * f2).real();
}

void OrthotropicSeries::Eval(double r, double t, double* u1, double* u2) const {
  for (std::size_t k = 0; k < terms_.size(); ++k) TermAt(terms_[k], r, t, &u1[k], &u2[k]);
}

std::vector<double> OrthotropicSeries::ModeIFactor() const {
  std::vector<double> out(terms_.size(), 0.0);
  for (std::size_t k = 0; k < terms_.size(); ++k)
    if (terms_[k].n == 1)
      out[k] = std::sqrt(2 * std::numbers::pi) * (terms_[k].A1 + terms_[k].A2).real();
  return out;
}

}  // namespace bridgefit::dic::detail
