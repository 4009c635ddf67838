#pragma once
// Private pieces of law_free.cpp: sample checks, the hat-function basis, the
// penalised least squares with its lambda search, plateau and onset tests.

#include <Eigen/Dense>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bridgefit/laws/law_free.hpp"

namespace bridgefit::laws::law_free_detail {

// Samples sorted by opening; `order[k]` is the caller's index of sample k.
struct Samples {
  std::vector<double> x, y, u;
  std::vector<int> order;
};

// Checks sizes, finiteness, u > 0, count >= min_points, and strictly
// increasing openings after sorting; throws Error naming the field.
Samples CheckAndSort(const std::vector<double>& opening, const std::vector<double>& value,
                     const std::vector<double>& uncertainty, const std::string& opening_name,
                     const std::string& value_name, int min_points);

// Uniform nodes from 0 to x_max; sigma is piecewise linear on them.
struct Grid {
  std::vector<double> nodes;
  double h = 0.0;
};
Grid MakeGrid(double x_max, int node_count);
// a_j(x) = int_0^x phi_j for every node j (row of length nodes.size()).
Eigen::RowVectorXd HatIntegrals(const Grid& grid, double x);
// phi_j(x) for every node j.
Eigen::RowVectorXd HatValues(const Grid& grid, double x);
// Second differences s_{j-1} - 2 s_j + s_{j+1}, j = 1 .. M-2: (M-2) x M.
Eigen::MatrixXd SecondDifferences(int node_count);

// min |b - A x|^2 + lambda x^T P x (rows of A and b already divided by u).
struct PenalisedFit {
  Eigen::VectorXd x;
  Eigen::MatrixXd covariance;  // s^2 (A^T A + lambda P)^-1
  double lambda = 0.0, log10_relative = 0.0;
  double chi2 = 0.0, trace_h = 0.0, noise_scale = 1.0;
  bool at_search_edge = false;  // the criterion's minimum lies on the lambda grid's edge
  // The chosen fit lies in the penalty's null space (tr H within 0.5 of its
  // dimension: sigma linear): `covariance` is then the best curved
  // alternative's plus d d^T, d the step to it (the band's allowance for
  // curvature the data do not resolve), and this is that alternative's
  // tr H. 0 when not applied.
  double null_space_allowance_dof = 0.0;
};
PenalisedFit SolvePenalised(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                            const Eigen::MatrixXd& P, PenaltyRule rule, double gcv_gamma);
// The solution at a given penalty lambda (the same rows; no penalty choice)
// and the diagonal of its posterior covariance s^2 (A^T A + lambda P)^-1 at
// the noise scale s given (a chosen fit's).
struct PenaltySolution {
  Eigen::VectorXd x, variance;
};
PenaltySolution SolveAtPenalty(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                               const Eigen::MatrixXd& P, double lambda, double noise_scale);

// The R route's weighted rows (elastic zone, eq. 3, law_free.hpp) on
// `grid`: unknowns (J_tip,c unless given, t_0 .. t_{M-2}) with
// s_j = t_j + sigma_end and t_{M-1} = 0: sigma at the grid's last node is
// pinned to sigma_end (0: steady state; pinning removes the null space
// s_j = C g_j). P penalises the second differences of t, which are s's.
struct RCurveSystem {
  Eigen::MatrixXd A, P;
  Eigen::VectorXd b;
  int offset = 0, free_nodes = 0;  // s_j is unknown offset + j
};
RCurveSystem MakeRCurveSystem(const Samples& s, const Grid& grid, std::optional<double> J_tip_c,
                              double sigma_end);

// sigma, its standard error and band on the grid from the fit (law_free.cpp);
// nodes past `free_nodes` are zero. `less`: the fit at the smaller penalty
// (LessSmoothed), whose change joins the standard error.
PenaltySolution LessSmoothed(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                             const Eigen::MatrixXd& P, const PenalisedFit& fit,
                             const LawFreeOptions& options);
void FillSigma(const Grid& grid, const PenalisedFit& fit, int offset, int free_nodes,
               const PenaltySolution& less, const LawFreeOptions& options, LawFreeResult* r);

// The range's ends (law_free_ends.cpp; LawFreeOptions::end_window_fraction):
// the band over the half of each end window next to its end becomes the
// union with the window's own fit's band. Return the opening intervals
// whose window held too few samples for a fit, or whose own fit failed (a
// note says which), which LeaveUnresolved then leaves unresolved. J route: `g` from the onset,
// `ux` the openings' uncertainties in its order; both ends. R route: the
// start only (sigma at the window's far end pinned to the whole fit's, as
// the R route knows sigma only up to + C delta otherwise; the end is
// sigma = 0 in steady state and unresolved without it).
using OpeningIntervals = std::vector<std::pair<double, double>>;
OpeningIntervals AllowForTheRangesEnds(const Samples& g, const std::vector<double>& ux,
                                       const LawFreeOptions& options, LawFreeResult* r);
OpeningIntervals AllowForTheRCurvesStart(const Samples& s, std::optional<double> J_tip_c,
                                         const LawFreeOptions& options, LawFreeResult* r);
void LeaveUnresolved(const OpeningIntervals& intervals, LawFreeResult& r);

// A tail of samples [start, end) flat within its noise (see law_free.hpp).
struct Plateau {
  bool found = false;
  int start = 0;      // index into Samples
  double mean = 0.0;  // weighted mean of the tail [J/m^2]
  double mean_se = 0.0;
};
Plateau FindPlateau(const Samples& samples, int first, const LawFreeOptions& options);

// The sample where J_ff stops rising steeply (index into Samples), or 0
// with *note set when no clear kink is found.
int DetectOnset(const Samples& samples, const LawFreeOptions& options, std::string* note);

}  // namespace bridgefit::laws::law_free_detail
