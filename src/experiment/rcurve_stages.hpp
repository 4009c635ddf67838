#pragma once
// Private: the state every R-curve method starts from (after cleaning,
// crack-length noise, validity window and initiation), and one function per
// method (src/experiment/rcurve*.cpp).
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "bridgefit/experiment/cleaning.hpp"
#include "bridgefit/experiment/rcurve.hpp"

namespace bridgefit::experiment::detail {

struct LinearFit {
  double slope = NAN;
  double intercept = NAN;
};
LinearFit FitLine(const std::vector<double>& x, const std::vector<double>& y);

void AddDropped(RCurveResult& result, const std::string& reason, int count);
std::string Mm(double metres);

// The rows kept after cleaning, in record order.
struct Rows {
  std::vector<int> row;
  std::vector<double> P, d, a_raw, a;
  std::size_t size() const { return row.size(); }
  void Truncate(std::size_t n);
};

// Everything the methods share.
struct Prepared {
  const ExperimentRecord* record = nullptr;
  const RCurveOptions* options = nullptr;
  std::string src;
  bool is_ct = false;
  bool has_a = false;  // the method uses measured crack lengths
  double B = NAN;      // crack-front width
  Rows w;              // envelope rows
  CleanedRecord cleaned;
  double sigma_P = NAN, sigma_d = NAN;
  double sigma_a = NAN;            // crack-length noise for the uncertainty
  double sigma_a_increment = NAN;  // crack-length scatter about a smooth monotone fit
  double a_limit = NAN;
  LinearFit lin;  // d = d0 + C0 P
  int imax = -1, nl = -1, off = -1;
  int first_growth = -1;  // first row of visible growth (crack lengths), else -1
  double a0 = NAN;
};

// G(P, d, a) for one row, and the crack length reported for (P, d, a_measured).
using Formula = std::function<double(double, double, double)>;
// One point per row from first_point on (-1: NL); uncertainty by central
// differences of +-1 sigma of P, d and a; initiation values at NL and 5%
// offset / max; every other row counted under a reason.
void PointwiseCurve(const Prepared& p, RCurveResult& result, const Formula& G,
                    const Formula& crack_of, int first_point);

// Appends one point of a point-wise method.
void PushPoint(const Prepared& p, RCurveResult& result, int k, double a, double R, double U);

// The methods; each fills result.curve, points_used and its dropped rows.
void EnergyMethod(const Prepared& p, RCurveResult& result);
void BeamMethod(const Prepared& p, RCurveResult& result);  // DCB mbt, cc
void CtMethod(const Prepared& p, RCurveResult& result);    // CT lefm, equivalent
void DcbLefmMethod(const Prepared& p, RCurveResult& result);
void DcbEquivalentMethod(const Prepared& p, RCurveResult& result);

}  // namespace bridgefit::experiment::detail
