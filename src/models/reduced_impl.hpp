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
// Dense LDL^T factor of a symmetric matrix that grows by bordering (one new
// last row) and takes rank-one diagonal updates (Bennett's algorithm), both
// O(m^2). L is unit lower triangular, column-major. The factor of a leading
// block is the leading block of the factor (SolveLeading).
class GrowingLdlt {
 public:
  explicit GrowingLdlt(int capacity)
      : L_(Eigen::MatrixXd::Zero(capacity, capacity)), d_(capacity) {}
  int size() const { return m_; }
  double pivot(int i) const { return d_[i]; }
  const Eigen::MatrixXd& L() const { return L_; }
  // Pivot the new row (column `col` of the matrix above the diagonal, and its
  // diagonal) would get; fills `l` with its L entries. Does not modify.
  double Preview(const Eigen::Ref<const Eigen::VectorXd>& col, double diagonal,
                 Eigen::VectorXd& l) const;
  void Border(const Eigen::Ref<const Eigen::VectorXd>& col, double diagonal, Eigen::VectorXd& l);
  // A + alpha e_j e_j^T.
  void AddToDiagonal(int j, double alpha, Eigen::VectorXd& w);
  // x = A^-1 r (in place).
  void Solve(Eigen::Ref<Eigen::VectorXd> x) const { SolveLeading(x, m_); }
  // x = A_m^-1 r with A_m the leading m x m block (m <= size()).
  void SolveLeading(Eigen::Ref<Eigen::VectorXd> x, int m) const;
  // Its two halves: z = L_m^-1 r, and x = L_m^-T D_m^-1 z (in place).
  void ForwardLeading(Eigen::Ref<Eigen::VectorXd> x, int m) const;
  void ScaleBackLeading(Eigen::Ref<Eigen::VectorXd> x, int m) const;
  // x = L_m^-T x (in place).
  void BackLeading(Eigen::Ref<Eigen::VectorXd> x, int m) const;

 private:
  Eigen::MatrixXd L_;
  Eigen::VectorXd d_;
  int m_ = 0;
};

// What the elastic crack plane gives every run on one model (geometry,
// material and resolution only; built once per ReducedModel and shared
// read-only by concurrent runs): S = L D L^T of all n crack-plane nodes,
// whose leading t x t block is the factor of the free nodes 0..t-1 of tip t,
// and Linv = L^-1, y = Linv g. For tip t (free nodes 0..t-1):
//   phi_t = 1/d_t, psi_t = F_t(t-1, t-1) = 1/d_{t-1},
//   v_t = F_t s_t = -Linv(t, 0..t-1)^T, alpha_t = v_t.g - g_t = -y_t,
//   F_t(i, j) = sum_{s = max(i, j)}^{t-1} Linv(s, i) Linv(s, j) / d_s,
//   (F_t g)_i = sum_{s = i}^{t-1} Linv(s, i) y_s / d_s.
struct ElasticTables {
  explicit ElasticTables(const CrackPlaneModel& m);
  GrowingLdlt factor;
  Eigen::MatrixXd Linv;
  Eigen::VectorXd y;
};

// Equations (1)-(2) restricted to the bridged nodes z0..t-1 (k of them) in
// the flexibility form: the zone block of F_t, the row of the node behind
// the tip over the zone, F_t g on the zone and behind the tip, v_t on the
// zone, and the tip's flexibility terms.
struct ZoneSystem {
  int z0 = 1, t = 1;
  Eigen::MatrixXd F_zz;
  Eigen::VectorXd F_back, Fg_z, v_z;
  double Fg_back = 0.0, phi = 0.0, alpha = 0.0, psi = 0.0, tip_force = 0.0;
  // From the full flexibility F of nodes 0..t-1 (the kDense solver), Fg = F g, v = F s_t.
  void FromFlexibility(const Eigen::MatrixXd& F, const Eigen::VectorXd& Fg,
                       const Eigen::VectorXd& v);
  // From the elastic tables (the bordered solver keeps no F).
  void FromTables(const ElasticTables& tables);
};
// One crack length in the flexibility form (1) on the zone (Newton with a
// dense LU); on success `p` holds the load, `u_zone` the zone's openings and
// `b` their closing forces (w_j sigma_j).
bool SolveZoneDense(const ZoneSystem& zone, double h, const laws::BridgingLaw& law,
                    const std::vector<double>& delta_max, double J_tip_c,
                    const ReducedOptions& options, Eigen::VectorXd& u_zone, double& p,
                    Eigen::VectorXd& b, int& newton_total);
// Crack growth with the LDL^T factor kept across crack lengths (bordering).
void GrowBordered(const CrackPlaneModel& m, const ElasticTables& tables,
                  const laws::BridgingLaw* law, double J_tip_c, const ReducedOptions& options,
                  SimulationResult& result, int& newton_total);

}  // namespace bridgefit::models::reduced_internal
