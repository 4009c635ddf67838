#pragma once
// Weighted polynomial fit with a standard error that does not trust the
// weights: the crack path's line and curvature tests (crack_path.cpp).

#include <vector>

namespace bridgefit::dic::detail {

// y = sum_j c_j (x - x_ref)^j, j = 0..degree, weighted least squares
// (weights w, e.g. J^2 for crack points: not inverse variances), with the
// sandwich covariance, HC3 (MacKinnon & White 1985), inflated for residuals
// correlated in blocks of `inflation` (>= 1) neighbouring points:
//   cov = inflation * B^-1 (sum_i w_i^2 e_i^2 x_i x_i^T) B^-1,
//   B = sum_i w_i x_i x_i^T,  e_i = r_i / (1 - h_i),
//   h_i = w_i x_i^T B^-1 x_i (the leverage; sum_i h_i = p).
// Valid whatever each point's scatter. Not ok (no standard error) when a
// point alone decides the fit (h_i = 1) or there are no more than p
// independent points (n / inflation <= p).
struct WeightedPoly {
  bool ok = false;  // see above; c, cov empty when not
  int points = 0;
  double x_ref = 0;                // the weighted mean of x
  std::vector<double> c;           // degree + 1 coefficients
  std::vector<double> cov;         // (degree + 1)^2, row major
  double Value(double x) const;    // the fit at x
  double Se(double x) const;       // standard error of the fit at x
  double CoefSe(int j) const;      // standard error of c_j
};

WeightedPoly FitWeightedPoly(const std::vector<double>& x, const std::vector<double>& y,
                             const std::vector<double>& w, int degree, double inflation);

}  // namespace bridgefit::dic::detail
