#pragma once
// Shape functions of the MPM kernels (internal to the mpm module): uGIMP and
// linear weights on the 3 x 3 node patch of a particle. Shared by the explicit
// solver and the quasi-static growth model so both discretise alike.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <vector>

namespace bridgefit::mpm::detail {

// uGIMP weight and gradient in cell units: d = (x_p - x_i)/h, l = l_p/h,
// inv_l = 1/l (no divisions in the hot loop).
inline void Gimp1D(double d, double l, double inv_l, double& s, double& g) {
  const double ad = std::abs(d);
  const double sgn = d < 0.0 ? -1.0 : 1.0;
  if (ad < l) {
    s = 1.0 - 0.5 * (d * d + l * l) * inv_l;
    g = -d * inv_l;
  } else if (ad < 1.0 - l) {
    s = 1.0 - ad;
    g = -sgn;
  } else if (ad < 1.0 + l) {
    const double t = 1.0 + l - ad;
    s = 0.25 * t * t * inv_l;
    g = -0.5 * sgn * t * inv_l;
  } else {
    s = 0.0;
    g = 0.0;
  }
}

inline void Linear1D(double d, double& s, double& g) {
  const double ad = std::abs(d);
  if (ad < 1.0) {
    s = 1.0 - ad;
    g = d < 0.0 ? 1.0 : -1.0;
  } else {
    s = 0.0;
    g = 0.0;
  }
}

// Weights of one particle on its 3 x 3 node patch starting at (i0, j0).
struct Weights {
  int i0, j0;
  double sx[3], sy[3], gx[3], gy[3];  // gradients in 1/m
};

// Patch weights of a particle at (x, y) on a grid with origin (x0, y0) and
// inverse cell size inv_h; lp: particle half size in cell units (0: linear).
template <bool kGimp>
inline void PatchWeights(double x, double y, double x0, double y0, double inv_h, double lp,
                         double inv_lp, Weights& wt) {
  const double fx = (x - x0) * inv_h, fy = (y - y0) * inv_h;
  wt.i0 = static_cast<int>(std::floor(fx - lp));
  wt.j0 = static_cast<int>(std::floor(fy - lp));
  for (int a = 0; a < 3; ++a) {
    double s, g;
    if constexpr (kGimp) Gimp1D(fx - (wt.i0 + a), lp, inv_lp, s, g);
    else Linear1D(fx - (wt.i0 + a), s, g);
    wt.sx[a] = s;
    wt.gx[a] = g * inv_h;
    if constexpr (kGimp) Gimp1D(fy - (wt.j0 + a), lp, inv_lp, s, g);
    else Linear1D(fy - (wt.j0 + a), s, g);
    wt.sy[a] = s;
    wt.gy[a] = g * inv_h;
  }
}

// The face term of J_tip (PHYSICS 4): int sigma d(delta) from the tip back
// to the contour's crossing x_cross, by trapezoids over crack points
// `opening(k)`, `traction(k)` at x[k] (ascending, the tip last).
template <class Opening, class Traction>
double FaceWork(const std::vector<double>& x, const Opening& opening, const Traction& traction,
                double x_cross) {
  double face = 0.0;
  for (std::size_t near = x.size() - 1; near > 0; --near) {
    const std::size_t far = near - 1;
    const double d_near = opening(near), s_near = traction(near);
    double d_far = opening(far), s_far = traction(far);
    if (x[far] < x_cross) {
      const double f = (x[near] - x_cross) / (x[near] - x[far]);
      d_far = d_near + f * (d_far - d_near);
      s_far = s_near + f * (s_far - s_near);
      return face + 0.5 * (s_near + s_far) * (d_far - d_near);
    }
    face += 0.5 * (s_near + s_far) * (d_far - d_near);
  }
  return face;
}

// A rectangular J contour of grid nodes around the tip of a horizontal crack
// (node indices; the nodes of column iL and rows jb/ja sit just below/above
// the crack line). Full model: the box [iL, iR] x [jB, jT], its left side
// split at the crack, closed by the pieces between the face nodes and the
// crack line (`above` = y(ja) - y_crack, `below` = y_crack - y(jb)). Half
// model (symmetry plane at row jB): right, top and left sides, doubled.
struct ContourBox {
  int iL = 0, iR = 0, jB = 0, jT = 0;
  bool half = false;
  int jb = 0, ja = 0;                 // full model: rows below / above the crack
  double above = 0.0, below = 0.0;    // full model [m]
};

// J = sum over the box's sides of the nodal integrand (trapezoids, spacing
// h) with the outward normal: integrand(i, j, n_x, n_y) at node (i, j).
template <class Integrand>
double ContourIntegral(const ContourBox& box, double h, const Integrand& integrand) {
  double J = 0.0;
  auto side = [&](int i_a, int j_a, int i_b, int j_b, double nxn, double nyn) {
    const int n = std::max(std::abs(i_b - i_a), std::abs(j_b - j_a));
    if (n == 0) return;
    const int di = (i_b > i_a) - (i_b < i_a), dj = (j_b > j_a) - (j_b < j_a);
    for (int s = 0; s <= n; ++s) {
      const double weight = (s == 0 || s == n) ? 0.5 * h : h;
      J += weight * integrand(i_a + s * di, j_a + s * dj, nxn, nyn);
    }
  };
  const auto& [iL, iR, jB, jT, half, jb, ja, above, below] = box;
  if (half) {
    side(iR, jB, iR, jT, 1.0, 0.0);   // right, up from the ligament
    side(iR, jT, iL, jT, 0.0, 1.0);   // top
    side(iL, jT, iL, jB, -1.0, 0.0);  // left, down to the crack face
    return 2.0 * J;
  }
  side(iL, jB, iR, jB, 0.0, -1.0);  // bottom
  side(iR, jB, iR, jT, 1.0, 0.0);   // right
  side(iR, jT, iL, jT, 0.0, 1.0);   // top
  side(iL, jT, iL, ja, -1.0, 0.0);  // left, upper part
  side(iL, jb, iL, jB, -1.0, 0.0);  // left, lower part
  J += above * integrand(iL, ja, -1.0, 0.0);
  J += below * integrand(iL, jb, -1.0, 0.0);
  return J;
}

}  // namespace bridgefit::mpm::detail
