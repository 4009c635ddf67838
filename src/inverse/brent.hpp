#pragma once
// Brent's one-dimensional minimiser (golden section with parabolic steps,
// Brent 1973 ch. 5), the one home of the joint fit's profiled nuisance
// parameters: a specimen's modulus scale (ModulusProfiledLoadModel) and the
// law parameters it does not share (OwnParameterProfiledModel).

#include <cmath>

namespace bridgefit::inverse::detail {

struct BrentMinimum {
  double x = NAN;
  double f = INFINITY;  // infinite: every evaluation failed
};

// The minimum of f on [a, b], started at x0 (inside), to `tol` in x. A
// failed evaluation returns +infinity (NaN is treated alike: every
// comparison fails, so the step is golden).
template <class F>
BrentMinimum BrentMinimize(F&& f, double a, double b, double x0, double tol) {
  constexpr double kGold = 0.3819660112501051;
  double x = x0, w = x0, v = x0;
  double fx = f(x), fw = fx, fv = fx;
  double d = 0.0, e = 0.0;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double m = 0.5 * (a + b);
    if (std::abs(x - m) <= 2.0 * tol - 0.5 * (b - a)) break;
    bool golden = true;
    if (std::abs(e) > tol) {  // the parabola through x, w, v
      const double r = (x - w) * (fx - fv);
      double q = (x - v) * (fx - fw);
      double step = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0) step = -step;
      q = std::abs(q);
      const double e_before = e;
      e = d;
      // Accepted only inside the bracket and shorter than half the step
      // before last.
      if (std::abs(step) < std::abs(0.5 * q * e_before) && step > q * (a - x) &&
          step < q * (b - x)) {
        d = step / q;
        if (x + d - a < 2.0 * tol || b - (x + d) < 2.0 * tol) d = m > x ? tol : -tol;
        golden = false;
      }
    }
    if (golden) {
      e = x >= m ? a - x : b - x;
      d = kGold * e;
    }
    const double u = std::abs(d) >= tol ? x + d : x + (d > 0.0 ? tol : -tol);
    const double fu = f(u);
    if (fu <= fx) {
      (u >= x ? a : b) = x;
      v = w, fv = fw, w = x, fw = fx, x = u, fx = fu;
    } else {
      (u < x ? a : b) = u;
      if (fu <= fw || w == x) {
        v = w, fv = fw, w = u, fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u, fv = fu;
      }
    }
  }
  return {x, std::isfinite(fx) ? fx : static_cast<double>(INFINITY)};
}

}  // namespace bridgefit::inverse::detail
