#pragma once
// Private: the eigenfunctions of a traction-free crack (faces at t = +-pi)
// in a rectilinearly orthotropic plate with its axes along and across the
// crack, plane stress (Lekhnitskii's complex potentials; Sih, Paris & Irwin
// 1965 for n = 1). With compliances s11, s22, s12, s66 the roots mu_1, mu_2
// (Im > 0) of s11 mu^4 + (2 s12 + s66) mu^2 + s22 = 0 and z_k = x1 + mu_k x2,
// a term of order n (lambda = n/2) is phi_k(z_k) = A_k z_k^lambda and
//   u1 = 2 Re(p1 phi1 + p2 phi2),  u2 = 2 Re(q1 phi1 + q2 phi2),
//   p_k = s11 mu_k^2 + s12,  q_k = s12 mu_k + s22 / mu_k,
//   sigma22 = 2 Re(phi1' + phi2'),  sigma12 = -2 Re(mu1 phi1' + mu2 phi2').
// Traction-free faces (sigma22 = sigma12 = 0 at t = +-pi) are four real
// equations in (A_1, A_2); for integer n they leave a two-dimensional null
// space: two terms per order, as modes I and II of the isotropic series
// (found numerically, so no closed form per order to get wrong). n = 2 is
// the T-stress alone (its other term is the rigid rotation, which the fit
// carries separately). The field-wide J fit (j_fit.cpp) uses it for an
// orthotropic material in place of the isotropic Williams series.

#include <algorithm>
#include <complex>
#include <vector>

namespace bridgefit::dic::detail {

// The roots mu_1, mu_2 (Im > 0) of s11 mu^4 + (2 s12 + s66) mu^2 + s22 = 0,
// moved apart when within 2 % of each other (a nearly isotropic plate, whose
// double root has no potentials of the form A_k f(z_k)) by raising s66 by
// at most 0.1 %; returns the relative raise (0 if none).
double OrthotropicRoots(double s11, double s22, double s12, double s66, std::complex<double>* mu1,
                        std::complex<double>* mu2);

class OrthotropicSeries {
 public:
  // Plane-stress compliances [1/Pa]: s11 = 1/E1, s22 = 1/E2,
  // s12 = -nu12/E1, s66 = 1/G12 (axis 1 along the crack). Orders lo..hi,
  // n != 0. Roots closer than 2 % (a nearly isotropic material) are moved
  // apart as OrthotropicRoots says: the potentials of a double root are not
  // of this form.
  OrthotropicSeries(double s11, double s22, double s12, double s66, int lo, int hi);
  // Columns per order: 2, but 1 for n = 2; in the order n = lo..hi.
  int Columns() const { return static_cast<int>(terms_.size()); }
  // Displacement of every column at polar (r, t) in the crack frame.
  void Eval(double r, double t, double* u1, double* u2) const;
  // K_I [stress x length^1/2 per unit coefficient at r = 1] of each column:
  // sqrt(2 pi) times sigma22 r^1/2 ahead of the tip (n = 1 only, else 0).
  std::vector<double> ModeIFactor() const;
  // min_k |x1 + mu_k x2|: the series about the centre converges where this
  // exceeds the distance to the farthest singular point on the crack line
  // (r for an isotropic material; less across the crack when mu_k < 1).
  double Reach(double x1, double x2) const {
    return std::min(std::abs(x1 + mu1_ * x2), std::abs(x1 + mu2_ * x2));
  }

 private:
  struct Term {
    int n = 0;
    bool t_stress = false;
    std::complex<double> A1, A2;
  };
  // Displacement of one term at polar (r, t).
  void TermAt(const Term& term, double r, double t, double* u1, double* u2) const;
  double s11_, s22_, s12_;
  std::complex<double> mu1_, mu2_, p1_, p2_, q1_, q2_;
  std::vector<Term> terms_;
};

}  // namespace bridgefit::dic::detail
