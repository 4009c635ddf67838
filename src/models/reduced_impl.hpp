#pragma once
// Private to src/models: the reduced model's crack-length solvers
// (reduced_zone.cpp) that ReducedModel::Run (reduced.cpp) strings together.

#include <vector>

#include <Eigen/Dense>

#include "bridgefit/models/reduced.hpp"

namespace bridgefit::models::reduced_internal {

using specimen::CrackPlaneModel;

// Traction and d(traction)/d(opening) with elastic unloading to the origin.
struct TractionSlope {
  double sigma = 0.0, slope = 0.0;
};

// Equation (2): centred nodal-release energy per unit growth from the
// reaction holding the tip node shut and the opening of the node behind it.
inline double CentredTipEnergy(double reaction, double phi, double u_behind, double psi, double h) {
  return (reaction * reaction * phi + u_behind * u_behind / psi) / (2.0 * h);
}

TractionSlope BridgingTraction(const laws::BridgingLaw& law, double delta, double delta_max);
// Updates the opening history (breaking points for good) and appends the
// point of tip t with free openings u (nodes 0..t-1), load p and J_tip.
void RecordPoint(const CrackPlaneModel& m, const laws::BridgingLaw* law, double J_tip_c, int t,
                 const Eigen::VectorXd& u, double p, double J_tip, std::vector<double>& delta_max,
                 std::vector<char>& broken, SimulationResult& result);
// Borders the flexibility of the free nodes 0..t-1 with node t once it is
// released (v = F s_t, phi its flexibility).
void BorderFlexibility(Eigen::MatrixXd& F, const Eigen::VectorXd& v, double phi, int t);
// One crack length in the flexibility form (1) on the bridged nodes z0..t-1
// (Newton with a dense LU); on success `u` and `p` hold the solution.
bool SolveZoneDense(const Eigen::MatrixXd& F, const Eigen::VectorXd& Fg, const Eigen::VectorXd& v,
                    double phi, double alpha, double psi, double tip_force, int z0, int t, double h,
                    const laws::BridgingLaw& law, const std::vector<double>& delta_max,
                    double J_tip_c, const ReducedOptions& options, Eigen::VectorXd& u, double& p,
                    int& newton_total);
// Crack growth with the LDL^T factor kept across crack lengths (bordering).
void GrowBordered(const CrackPlaneModel& m, const laws::BridgingLaw* law, double J_tip_c,
                  const ReducedOptions& options, SimulationResult& result, int& newton_total);

}  // namespace bridgefit::models::reduced_internal
