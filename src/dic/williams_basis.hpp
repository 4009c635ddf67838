#pragma once
// Private: the Williams eigenfunctions of a traction-free crack (faces at
// t = +-pi), shared by the crack-tip fit (crack_williams.cpp) and the
// field-wide J fit (j_fit.cpp). Yoneyama et al. 2006 form without 1/(2 mu):
// displacement r^(n/2) f_n(t) in the crack frame; any integer n (negative n
// are the terms singular at the expansion's centre, which a Laurent series
// about a point inside the bridging zone needs outside it).

#include <cmath>

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

}  // namespace bridgefit::dic::detail
