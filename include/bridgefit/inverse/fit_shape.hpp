#pragma once
// Fits of laws whose shape is fitted too (issue 21): bilinear softening,
// trilinear (the law module's three segments) and a tabulated law with N
// knots, next to sigma_c, J_B and J_tip,c; and `--law compare` over them
// and the fixed-shape families (docs/FIT.md "Law families with a fitted
// shape").
//
// Shapes (d = delta / delta_c, the law module's table and trilinear shapes):
//   bilinear   (0, 1) - (d1, s1) - (1, 0), 0.02 <= d1 <= 0.98, 0 <= s1 <= 1
//   trilinear  (0, s0) - (d1, s1) - (d2, s2) - (1, 0), peak rescaled to 1
//   table N    (j / N, s_j) for j = 0 .. N-1, then (1, 0), peak rescaled to
//              1; the monotone cubic between the knots by default (below)
// Why the table's default is the monotone cubic: with g = R - J_tip,c,
// PHYSICS (3) gives dg/d delta = (sigma - delta sigma') / 2, so on a straight
// segment c + m delta the R curve sees only its intercept c / 2; a law that
// rises from zero (the cubic: g ~ delta^3) then needs a positive intercept
// on the first chord, and the knot at d = 0 came out +7.5..+14% of sigma_c
// also without noise (N = 5..8). A C1 cubic carries the curvature, and the
// bias goes (docs/FIT.md "Law families with a fitted shape").
// The joint search (NLopt BOBYQA, multi-start) minimises
//   chi^2 + lambda sum_j (s_(j-1) - 2 s_j + s_(j+1))^2      (table only)   (1)
// over the box coordinates of the free scale parameters and the shape, with
// lambda = smoothness x s^2 (s^2: the noise scale of the fixed-shape
// families, 1 with reported uncertainties). Parameters counted in AICc:
// the free scale parameters + positions + knot values less the one that is
// the peak (it is sigma_c); for the table the effective number
//   k_eff = tr[(J^T J + lambda D^T D)^-1 J^T J]                           (2)
// (J: the residuals' Jacobian in those parameters, D: the second
// differences), which is <= N + 2 and tends to it as lambda -> 0.
// Intervals of sigma_c, J_B, J_tip,c: the hull of the profile likelihood
// with the fitted shape held (the fixed-shape fit's machinery: profiles,
// steady state, PHYSICS 7 bounds, no-bridging test) and the Wald interval
// with the shape free, C = s^2 (J^T J + lambda D^T D)^-1. Shape parameters:
// Wald standard errors from the same C.

#include <string>
#include <vector>

#include "bridgefit/inverse/fit.hpp"

namespace bridgefit::inverse {

enum class ShapeFamily { kBilinear, kTrilinear, kTable };
const char* ShapeFamilyName(ShapeFamily family);  // "bilinear", "trilinear", "table"

struct ShapeFitOptions {
  std::vector<int> table_knots = {3, 4, 5, 6};  // N tried by the table; AICc chooses
  // lambda = smoothness x s^2 in (1): a Gaussian prior on each second
  // difference of the normalised knots with standard deviation
  // 1 / sqrt(2 smoothness) (weak: the cubic law's second differences at
  // N = 6 are <= 0.56).
  double smoothness = 1.0;
  // Between the table's knots: the monotone cubic (PCHIP) by default; straight
  // segments bias the knot at d = 0 of a law that rises from zero (docs/FIT.md).
  laws::TableInterpolation table_interpolation = laws::TableInterpolation::kMonotoneCubic;
  int seed_starts = 2;         // starts from the fixed-shape fits with the lowest chi^2
  int random_starts = 2;       // Latin-hypercube starts besides those
  int max_evaluations = 3000;  // per local search
  bool IsValid(std::string* why) const;
};

struct ShapeFit {
  ShapeFamily family = ShapeFamily::kTable;
  std::string law;  // "bilinear", "trilinear", "table"
  bool fitted = false;
  std::string skip_reason;  // why it was not fitted (too few points for its parameters)
  laws::LawShape shape;     // the fitted shape (family kTable or kTrilinear)
  // The fit with the shape held at its optimum, with the intervals widened
  // to the hull described above. chi2 is the data's (the penalty not in it).
  FitSummary summary;
  std::vector<ShapeParameter> shape_parameters;
  int parameters = 0;                 // nominal free parameters
  double effective_parameters = NAN;  // (2) for the table; = parameters otherwise
  int knots = 0;                      // table: N chosen
  double penalty = 0.0;               // lambda in (1)
  double roughness = 0.0;             // sum of squared second differences at the optimum
  std::vector<int> knots_tried;       // table: every N, with
  std::vector<double> knots_aicc;     // its AICc (NaN: skipped, too few points)
  std::string note;                   // what was skipped or assumed
  int evaluations = 0;                // forward runs of the joint search
  double wall_s = 0.0;
  std::string BriefReport() const;
};

// One shape family (table: `knots` knots). `seeds`: fixed-shape fits whose
// optima start the search (null: the linear and cubic laws are fitted first).
// `scale2`: s^2 of lambda and of the table's AICc (NaN: 1 with reported
// uncertainties, else the seeds' best reduced chi^2). Never throws for too
// few points: `fitted` false and `skip_reason`; throws Error for invalid
// options or data.
ShapeFit FitShapeFamily(const ForwardModel& model, ShapeFamily family, const FitData& data,
                        const FitOptions& options, const ShapeFitOptions& shape_options,
                        int knots = 0, const std::vector<LawComparison>* seeds = nullptr,
                        double scale2 = NAN);
// The table law with N chosen among shape_options.table_knots by AICc.
ShapeFit FitTableLaw(const ForwardModel& model, const FitData& data, const FitOptions& options,
                     const ShapeFitOptions& shape_options,
                     const std::vector<LawComparison>* seeds = nullptr, double scale2 = NAN);

// CompareLawFamilies over `shapes` (their results unchanged), then each of
// `families` fitted with its shape, on the same s^2; AICc differences and
// Akaike weights over all. A family skipped for too few points has a NaN
// AICc, weight 0 and its reason in `note`.
std::vector<LawComparison> CompareLawFamiliesWithShapes(const ForwardModel& model,
                                                        const std::vector<laws::LawShape>& shapes,
                                                        const std::vector<ShapeFamily>& families,
                                                        const FitData& data,
                                                        const FitOptions& options,
                                                        const ShapeFitOptions& shape_options = {});

}  // namespace bridgefit::inverse
