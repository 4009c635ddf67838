#pragma once
// Private to src/inverse: the joint search of a law's shape with its scale
// parameters (fit_shape.cpp) and what the table's knot choice and the
// comparison (fit_shape_compare.cpp) need from it.

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "bridgefit/inverse/fit_shape.hpp"

namespace bridgefit::inverse::shape_internal {

// Which break points and knot values a family frees (fit_shape.hpp).
struct ShapeLayout {
  ShapeFamily family = ShapeFamily::kTable;
  int knots = 0;  // table
  laws::TableInterpolation interpolation = laws::TableInterpolation::kMonotoneCubic;  // table

  int positions() const;    // free break points d
  int values() const;       // knot values s
  bool normalised() const;  // peak rescaled to 1 (the peak knot is sigma_c, not counted)
  int dims() const { return positions() + values(); }
  int counted() const { return dims() - (normalised() ? 1 : 0); }
  std::vector<std::string> Names() const;
  std::vector<double> PositionsFromBox(const double* x) const;
  std::vector<double> PositionsToBox(const std::vector<double>& d) const;
  // The shape from break points and knot values; false when impossible
  // (positions out of order or range, a value < 0, no traction, bilinear
  // s1 > 1).
  bool Build(const std::vector<double>& d, const std::vector<double>& v, laws::LawShape* out) const;
  // sum of squared second differences of the normalised knots (table), else 0.
  double Roughness(const laws::LawShape& shape) const;
  // Box coordinates of the shape closest to `seed` (a start).
  std::vector<double> Project(const laws::LawShape& seed) const;
};

// The joint optimum of one family and what the intervals need.
struct JointResult {
  ShapeLayout layout;
  bool ok = false;
  bool converged = false;
  std::string stop_reason;
  double chi2 = NAN;    // the data's
  double lambda = 0.0;  // penalty weight
  double roughness = 0.0;
  std::array<double, kParameterCount> main = {NAN, NAN, NAN};
  std::vector<double> positions, values;  // values normalised to a peak of 1
  laws::LawShape shape;
  int pinned = -1;                    // index of the peak knot (normalised shapes)
  double effective_parameters = NAN;  // (2) of fit_shape.hpp
  int nominal_parameters = 0;
  // (J^T J + lambda D^T D)^-1 over the Wald coordinates: the free scale
  // parameters (physical), positions, values other than the pinned one.
  Eigen::MatrixXd inverse_information;
  int evaluations = 0;
};

// The scale parameters left free by the options.
std::vector<int> FreeScaleParameters(const FitOptions& options);
// chi2 / s^2 + 2k + 2k(k+1)/(n-k-1); NaN when n - k - 1 <= 0.
double Aicc(double chi2_over_s2, double k, int n);
// s^2 of lambda and the AICc: 1 with reported uncertainties, else the best
// reduced chi^2 (n - 3 dof) among the converged seeds; 1 if none.
double SeedScale(const FitData& data, const std::vector<LawComparison>& seeds);
// The linear and cubic laws fitted (no profiles) to start a shape's search.
std::vector<LawComparison> SeedFits(const ForwardModel& model, const FitData& data,
                                    const FitOptions& options);
// Multi-start search of one layout, then the Jacobian and (2).
JointResult RunJoint(const ForwardModel& model, const ShapeLayout& layout, const FitData& data,
                     const FitOptions& options, const ShapeFitOptions& shape_options,
                     const std::vector<LawComparison>& seeds, double scale2);
// The fit with the shape held at the joint optimum, its intervals widened to
// the Wald ones with the shape free, and the shape parameters' errors.
ShapeFit FinishShapeFit(const ForwardModel& model, const FitData& data, const FitOptions& options,
                        const JointResult& joint);
// Too few points for `k` parameters: the reason, else empty.
std::string TooFewPoints(int points, int k, const std::string& what);

}  // namespace bridgefit::inverse::shape_internal
