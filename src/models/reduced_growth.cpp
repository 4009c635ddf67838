// The reduced model's growth with the bordered LDL^T factor (reduced_impl.hpp;
// equations in reduced.hpp): BorderedGrowth's stages and GrowBordered.

#include "reduced_impl.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/laws/rcurve_theory.hpp"

namespace bridgefit::models::reduced_internal {

namespace {

// Growth with the stiffness form of (1): S_ff u + b(u) = g p, solved by
// (chord) Newton on (u, p) with the LDL^T factor of S_ff + diag(b') kept
// across crack lengths (bordering, rank-one updates where a slope changed),
// O(t^2) per crack length instead of a dense O(k^3) factorization.
// The state carried across crack lengths and, per tip node t, the step's
// quantities; the stages of a step are the member functions:
//   BeginStep -> Solve (SolveZoneDense | SolveUnbridged | SolveChordNewton)
//   -> Record -> Border.
class BorderedGrowth {
 public:
  BorderedGrowth(const CrackPlaneModel& m, const ElasticTables& tables,
                 const laws::BridgingLaw* law, double J_tip_c, const ReducedOptions& options,
                 int& newton_total)
      : m_(m), tables_(tables), elastic_(tables.factor), law_(law), J_tip_c_(J_tip_c),
        options_(options), newton_total_(newton_total),
        n_(m.size()), h_(m.resolution), S_(m.stiffness.data(), n_, n_), g_(m.load.data(), n_),
        tip_traction_(law ? law->Traction(0.0) : 0.0), delta_max_(n_, 0.0), broken_(n_, 0),
        tangent_(n_), slope_(Eigen::VectorXd::Zero(n_)), work_(n_), work2_(n_),
        u_(Eigen::VectorXd::Zero(n_)), b_(n_), db_(n_), r_u_(n_), a_(n_), x1_(n_), x2_(n_),
        trial_u_(n_), trial_r_(n_), trial_a_(n_), b_u_(n_), du_(n_), step_r_(n_), start_u_(n_), retry_u_(n_), zg_(n_), border_l_(n_),
        force_scale_(S_.diagonal().cwiseAbs().maxCoeff()) {
    tangent_.Border(S_.col(0), S_(0, 0), work_);
  }

  // The equilibrium with the tip at node t: false when Newton did not
  // converge or the load is not positive.
  bool Solve(int t) {
    BeginStep(t);
    retry_u_.head(t) = u_.head(t);
    retry_p_ = p_;
    const int zone_size = law_ ? t - z0_ : 0;
    // Short bridged zone: the dense zone solve (O(k^3), the zone's
    // flexibility from the elastic tables) is cheaper than O(t^2)
    // iterations on all free nodes.
    const bool dense_zone = options_.solver == ReducedOptions::Solver::kHybrid && zone_size > 0 &&
                            p_ > 0.0 && std::pow(zone_size, 3) < 6.0 * t * t;
    bool converged = false;
    if (dense_zone) {
      converged = SolveDenseZone();
    } else if (!law_) {
      converged = SolveUnbridged();
    } else {
      converged = SolveChordNewton();
    }
    return converged && p_ > 0.0;
  }

  // A law that drops to zero with a jump at delta_c (the exponential law,
  // cut at d = 1 where exp(-alpha) > 0) can leave a step without an
  // equilibrium: its oldest bridged point would open past delta_c while
  // bridged and close below it once broken (validation #23, a DCB at
  // a = 78.6 mm; an exponential DCB at 0.5 mm elements, a = 81 mm). That
  // point breaks - the snap the jump implies - and the step starts again
  // from where it began. False (nothing changed) where the law has no jump
  // or the oldest bridged point has not opened half way to delta_c.
  bool BreakAtTheJump() {
    if (!law_ || !(law_->Traction(law_->delta_c * (1.0 - 1e-12)) > 0.0)) return false;
    const int t = t_;
    if (z0_ >= t || !(delta_max_[z0_] >= 0.5 * law_->delta_c)) return false;
    delta_max_[z0_] = law_->delta_c;
    broken_[z0_] = 1;
    u_.head(t) = retry_u_.head(t);
    p_ = retry_p_;
    ++snaps_;
    return true;
  }
  int snaps() const { return snaps_; }

  // The converged point: opening history and the R-curve point of tip t.
  void Record(SimulationResult& result) {
    const int t = t_;
    const Eigen::Ref<const Eigen::VectorXd> s_t = S_.col(t).head(t);
    const double R_t = s_t.dot(u_.head(t)) - g_[t] * p_ + tip_force_;
    const double J_tip = CentredTipEnergy(R_t, phi_, u_[t - 1], psi_, h_);
    RecordPoint(m_, law_, J_tip_c_, t, u_, p_, J_tip, delta_max_, broken_, result);
  }

  // Node t joins the free nodes (flexibility, elastic and tangent factors)
  // shut; its slope is the envelope's at zero opening.
  void Border() {
    const int t = t_;
    double slope_t = 0.0;
    if (law_) slope_t = 2.0 * FaceLength(t) * BridgingTraction(*law_, 0.0, 0.0).slope;
    tangent_.Border(S_.col(t), S_(t, t) + slope_t, work_);
    slope_[t] = slope_t;
    u_[t] = 0.0;
  }

 private:
  double FaceLength(int r) const { return r == 1 ? 0.5 * h_ : h_; }

  // The tip node's flexibility terms and the first node of the bridged zone.
  void BeginStep(int t) {
    t_ = t;
    phi_ = 1.0 / elastic_.pivot(t);
    psi_ = 1.0 / elastic_.pivot(t - 1);
    tip_force_ = law_ ? tip_traction_ * FaceLength(t) : 0.0;
    z0_ = 1;
    while (z0_ < t && broken_[z0_]) ++z0_;
  }

  // Slopes b'_j at the current state.
  void Slopes(const Eigen::VectorXd& x_u) {
    const int t = t_;
    b_.head(t).setZero();
    db_.head(t).setZero();
    if (!law_) return;
    for (int r = z0_; r < t; ++r) {
      const TractionSlope ts = BridgingTraction(*law_, 2.0 * x_u[r], delta_max_[r]);
      b_[r] = FaceLength(r) * ts.sigma;
      db_[r] = 2.0 * FaceLength(r) * ts.slope;
    }
  }

  // Refreshes the tangent factor where the slopes moved; true when any did.
  bool Refresh(double tolerance) {
    bool changed = false;
    const int x2_size = x2_size_;
    for (int r = 1; r < t_; ++r) {
      const double target = (law_ && r >= z0_) ? db_[r] : 0.0;
      if (std::abs(target - slope_[r]) > tolerance * S_(r, r)) {
        tangent_.AddToDiagonal(r, target - slope_[r], work2_);
        slope_[r] = target;
        changed = true;
      }
    }
    x2_size_ = changed ? -1 : x2_size;
    return changed;
  }

  // x2 = K^-1 g for the free nodes 0..t-1, and zg = L^-1 g on the way.
  void SolveX2() {
    const int t = t_;
    zg_.head(t) = g_.head(t);
    tangent_.ForwardLeading(zg_.head(t), t);
    x2_.head(t) = zg_.head(t);
    tangent_.ScaleBackLeading(x2_.head(t), t);
    x2_size_ = t;
  }

  // x2 after node t-1 joined the factor, from the last crack length's x2
  // when the factor has not changed since but by the border: with the new
  // row l and pivot delta of L D L^T and z = L^-1 g,
  //   z_{t-1} = g_{t-1} - l.z, x2_{t-1} = z_{t-1} / delta,
  //   x2 (old nodes) -= x2_{t-1} L^-T l
  // (one back substitution, O(t^2 / 2), instead of a solve, O(t^2)).
  void UpdateX2() {
    const int t = t_;
    if (x2_size_ != t - 1) return SolveX2();
    const int m = t - 1;
    border_l_.head(m) = tangent_.L().row(m).head(m).transpose();
    zg_[m] = g_[m] - border_l_.head(m).dot(zg_.head(m));
    const double last = zg_[m] / tangent_.pivot(m);
    tangent_.BackLeading(border_l_.head(m), m);
    x2_.head(m) -= last * border_l_.head(m);
    x2_[m] = last;
    x2_size_ = t;
  }

  // Force residual r_u = S u + b - g p, with b the tractions of the last
  // Slopes call (a product with S, O(t^2)).
  void ForceResidual(const Eigen::VectorXd& x_u, double x_p, Eigen::VectorXd& ru) const {
    const int t = t_;
    ru.head(t).noalias() = S_.topLeftCorner(t, t).selfadjointView<Eigen::Lower>() * x_u.head(t);
    ru.head(t) += b_.head(t) - g_.head(t) * x_p;
  }

  // The tip residual r_G = sqrt(J_tip / J_c) - 1 and its gradient
  // a = d r_G / d u, e = d r_G / d p (O(t)).
  void TipResidual(const Eigen::VectorXd& x_u, double x_p, Eigen::VectorXd& grad, double& rg,
                   double& de) const {
    const int t = t_;
    const Eigen::Ref<const Eigen::VectorXd> s_t = S_.col(t).head(t);
    const double reaction = s_t.dot(x_u.head(t)) - g_[t] * x_p + tip_force_;
    const double G = CentredTipEnergy(reaction, phi_, x_u[t - 1], psi_, h_);
    const double sqrtG = std::sqrt(std::max(G, 1e-300));
    rg = sqrtG / std::sqrt(J_tip_c_) - 1.0;
    const double scale = 1.0 / (2.0 * sqrtG * std::sqrt(J_tip_c_) * h_);
    grad.head(t) = (scale * reaction * phi_) * s_t;
    grad[t - 1] += scale * x_u[t - 1] / psi_;
    de = -scale * reaction * phi_ * g_[t];
  }

  double Norm(const Eigen::VectorXd& ru, const Eigen::VectorXd& x_u, double rg) const {
    const int t = t_;
    const double u_scale = std::max(x_u.head(t).cwiseAbs().maxCoeff(), 1e-12);
    return std::max(ru.head(t).cwiseAbs().maxCoeff() / (force_scale_ * u_scale), std::abs(rg));
  }

  // The zone's flexibility form (SolveZoneDense); the free nodes' openings
  // then follow from S_ff u = g p - b.
  bool SolveDenseZone() {
    const int t = t_;
    zone_.z0 = z0_;
    zone_.t = t;
    zone_.tip_force = tip_force_;
    zone_.FromTables(tables_);
    zone_u_ = u_.segment(z0_, t - z0_);
    if (!SolveZoneDense(zone_, h_, *law_, delta_max_, J_tip_c_, options_, zone_u_, p_, zone_b_,
                        newton_total_))
      return false;
    u_.head(t) = g_.head(t) * p_;
    u_.segment(z0_, t - z0_) -= zone_b_;
    elastic_.SolveLeading(u_.head(t), t);
    return true;
  }

  // No law: linear in p, u = p S^-1 g, J_tip quadratic in p.
  bool SolveUnbridged() {
    const int t = t_;
    const Eigen::Ref<const Eigen::VectorXd> s_t = S_.col(t).head(t);
    SolveX2();
    const double R1 = s_t.dot(x2_.head(t)) - g_[t];
    const double A = R1 * R1 * phi_ + x2_[t - 1] * x2_[t - 1] / psi_;
    p_ = std::sqrt(2.0 * h_ * J_tip_c_ / A);
    u_.head(t) = p_ * x2_.head(t);
    return std::isfinite(p_);
  }

  // The load step of a Newton iteration. Along the linearized force
  // equations, u(dp) = u - x1 + x2 dp (x1 = K^-1 r_u, x2 = K^-1 g), the
  // reaction R_t and the opening u_{t-1} are affine in dp, so J_tip of (2) is
  // a quadratic in dp: its larger root (the load side, as in SolveUnbridged)
  // is taken instead of the root of rG's linearization, which overshoots
  // from the warm start (the node behind the tip starts shut, where
  // d J_tip / d u_{t-1} = 0) and then needs a second step, and where points
  // cross delta_c on the way, rank-one updates back and forth. Same root, same
  // convergence test; for linear softening on its loading branch it is the
  // solution in one step. Falls back to the linearized step where the
  // quadratic has no root.
  double LoadStep(double r_G, double e) const {
    const int t = t_;
    const Eigen::Ref<const Eigen::VectorXd> s_t = S_.col(t).head(t);
    const double R0 = s_t.dot(u_.head(t) - x1_.head(t)) - g_[t] * p_ + tip_force_;
    const double R1 = s_t.dot(x2_.head(t)) - g_[t];
    const double U0 = u_[t - 1] - x1_[t - 1], U1 = x2_[t - 1];
    const double A = R1 * R1 * phi_ + U1 * U1 / psi_;
    const double B = 2.0 * (R0 * R1 * phi_ + U0 * U1 / psi_);
    const double C = R0 * R0 * phi_ + U0 * U0 / psi_ - 2.0 * h_ * J_tip_c_;
    const double disc = B * B - 4.0 * A * C;
    if (A > 0.0 && disc >= 0.0) {
      // Larger root, in the form without cancellation.
      const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
      const double root = q != 0.0 ? std::max(q / A, C / q) : 0.0;
      if (std::isfinite(root)) return root;
    }
    return LinearLoadStep(r_G, e);
  }

  // The root of rG's linearization: a^T du + e dp = -r_G with du = x2 dp - x1.
  double LinearLoadStep(double r_G, double e) const {
    const int t = t_;
    return (-r_G + a_.head(t).dot(x1_.head(t))) / (a_.head(t).dot(x2_.head(t)) + e);
  }

  // Chord Newton on (u, p) with a backtracking line search; the first step
  // starts from the unbridged LEFM load.
  //
  // The force residual is a product with S only where it must be exact: the
  // start of a crack length that does not follow a converged chord-Newton
  // one, and the convergence test. Elsewhere it is carried: the last crack
  // length's verified residual is the new one's on the old free nodes (same
  // u, p and tractions; the new free node starts shut, one row, O(t)), and
  // along a step (K du = g dp - r_u, K = S + diag(slope)) S du - g dp =
  // -r_u - slope du, so a trial's residual is O(t) past its tractions.
  // A converged point passes the same test on the residual computed from
  // S as before. Where the quadratic load step (LoadStep) does not converge
  // within kQuadraticIterations (a few extreme CT laws, sigma_c 1-10 MPa
  // with J_B 0.8-4.5 kJ/m^2), the crack length is solved again from the same
  // start with the linearized load step, as before, and so is the rest of
  // the run.
  bool SolveChordNewton() {
    const int t = t_;
    const Eigen::Ref<const Eigen::VectorXd> s_t = S_.col(t).head(t);
    const bool carried = carried_t_ == t - 1;
    carried_t_ = -1;
    if (t == 1) p_ = 0.0;
    if (p_ <= 0.0) {
      x2_.head(t) = g_.head(t);
      elastic_.SolveLeading(x2_.head(t), t);
      x2_size_ = -1;  // the elastic factor's
      const double R1 = s_t.dot(x2_.head(t)) - g_[t];
      p_ = std::sqrt(2.0 * h_ * J_tip_c_ / (R1 * R1 * phi_ + x2_[t - 1] * x2_[t - 1] / psi_));
      // The openings of that load (issue 17): from u = 0 the residual is
      // all load, and on a coarse DCB mesh the first Newton step crossed
      // to the root with p < 0 (sqrt(J_tip) = sqrt(J_tip,c) at a negative
      // load), "Newton did not converge at crack length a0".
      u_.head(t) = p_ * x2_.head(t);
    }
    if (linear_steps_) return ChordNewton(carried, false);
    start_u_.head(t) = u_.head(t);
    const double start_p = p_;
    if (ChordNewton(carried, true)) return true;
    // From here on the run takes the linearized step first (where the
    // quadratic one failed once it tends to fail again, each time after its
    // iterations: 60 ms instead of 4 for a 3 kJ/m^2 law).
    linear_steps_ = true;
    u_.head(t) = start_u_.head(t);
    p_ = start_p;
    return ChordNewton(false, false);
  }

  // The iterations of SolveChordNewton; `carried`: r_u_ holds the last
  // crack length's verified residual; `quadratic`: the load step of LoadStep
  // (else the root of rG's linearization).
  bool ChordNewton(bool carried, bool quadratic) {
    const int t = t_;
    Slopes(u_);
    Refresh(1e-9);
    if (carried) {
      // r_u_ holds S u + b_old - g p on nodes 0..t-2 (b_old in b_u_).
      r_u_.head(t - 1) += b_.head(t - 1) - b_u_.head(t - 1);
      r_u_[t - 1] = S_.row(t - 1).head(t - 1).dot(u_.head(t - 1)) + b_[t - 1] - g_[t - 1] * p_;
    } else {
      ForceResidual(u_, p_, r_u_);
    }
    bool exact = true;  // r_u_ is S u + b - g p, not carried along a step
    b_u_.head(t) = b_.head(t);
    double r_G = 0.0, e = 0.0;
    TipResidual(u_, p_, a_, r_G, e);
    UpdateX2();
    x1_.head(t) = r_u_.head(t);
    tangent_.Solve(x1_.head(t));
    bool x1_ready = true;
    bool b_at_u = true;  // b_ (and db_) are the tractions at u_
    double current = Norm(r_u_, u_, r_G);
    double previous = INFINITY;
    bool converged = false;
    // The quadratic step converges in a few iterations or not at all.
    const int iterations =
        quadratic ? std::min(options_.max_newton_iterations, kQuadraticIterations)
                  : options_.max_newton_iterations;
    for (int it = 0; it < iterations; ++it) {
      ++newton_total_;
      if (current < options_.tolerance && !exact) {
        if (!b_at_u) Slopes(u_);
        ForceResidual(u_, p_, r_u_);
        TipResidual(u_, p_, a_, r_G, e);
        b_u_.head(t) = b_.head(t);
        exact = true;
        x1_ready = false;
        current = Norm(r_u_, u_, r_G);
      }
      if (current < options_.tolerance) {
        converged = true;
        break;
      }
      if (current > 0.25 * previous && Refresh(1e-9)) {
        SolveX2();
        x1_ready = false;
      }
      previous = current;
      // [K -g; a^T e] [du; dp] = -[r_u; r_G] by block elimination.
      if (!x1_ready) {
        x1_.head(t) = r_u_.head(t);
        tangent_.Solve(x1_.head(t));
      }
      x1_ready = false;
      const double dp = quadratic ? LoadStep(r_G, e) : LinearLoadStep(r_G, e);
      du_.head(t) = x2_.head(t) * dp - x1_.head(t);
      // S du - g dp, and S u - g p (the residual without its tractions).
      step_r_.head(t) = -r_u_.head(t) - slope_.head(t).cwiseProduct(du_.head(t));
      r_u_.head(t) -= b_u_.head(t);
      double lambda = 1.0, trial = INFINITY, trial_p = p_, trial_rg = 0.0, trial_e = 0.0;
      for (int ls = 0; ls < 30; ++ls, lambda *= 0.5) {
        trial_u_.head(t) = u_.head(t) + lambda * du_.head(t);
        trial_p = p_ + lambda * dp;
        b_at_u = false;
        // The load stays positive: sqrt(J_tip) = sqrt(J_tip,c) has a root
        // at p < 0 too, which a full step can reach on a coarse mesh.
        if (!(trial_p > 0.0)) continue;
        Slopes(trial_u_);
        b_at_u = true;
        trial_r_.head(t) = r_u_.head(t) + lambda * step_r_.head(t) + b_.head(t);
        TipResidual(trial_u_, trial_p, trial_a_, trial_rg, trial_e);
        trial = Norm(trial_r_, trial_u_, trial_rg);
        if (trial < current * (1.0 - 1e-4 * lambda) || trial < options_.tolerance) break;
      }
      u_.head(t) = trial_u_.head(t);
      p_ = trial_p;
      r_u_.head(t) = trial_r_.head(t);
      b_u_.head(t) = b_.head(t);
      a_.head(t) = trial_a_.head(t);
      r_G = trial_rg;
      e = trial_e;
      current = trial;
      exact = false;
    }
    if (!converged && current < options_.tolerance) {
      if (!exact) {
        Slopes(u_);
        ForceResidual(u_, p_, r_u_);
        TipResidual(u_, p_, a_, r_G, e);
        b_u_.head(t) = b_.head(t);
        current = Norm(r_u_, u_, r_G);
      }
      converged = current < options_.tolerance;
    }
    if (converged) carried_t_ = t;  // r_u_ and b_u_ hold the verified state
    return converged;
  }

  const CrackPlaneModel& m_;
  const ElasticTables& tables_;
  const GrowingLdlt& elastic_;  // of all crack-plane nodes (ElasticTables)
  const laws::BridgingLaw* law_;
  const double J_tip_c_;
  const ReducedOptions& options_;
  int& newton_total_;
  const int n_;
  const double h_;
  const Eigen::Map<const Eigen::MatrixXd> S_;
  const Eigen::Map<const Eigen::VectorXd> g_;
  const double tip_traction_;
  std::vector<double> delta_max_;
  std::vector<char> broken_;
  GrowingLdlt tangent_;
  Eigen::VectorXd slope_;  // b' held in `tangent_`
  Eigen::VectorXd work_, work2_;
  Eigen::VectorXd u_, b_, db_, r_u_, a_, x1_, x2_, trial_u_, trial_r_, trial_a_;
  Eigen::VectorXd b_u_;            // tractions at u_ (the b of r_u_)
  Eigen::VectorXd du_, step_r_;    // Newton direction and S du - g dp
  Eigen::VectorXd start_u_;        // openings a crack length's Newton starts from
  Eigen::VectorXd retry_u_;        // openings and load a step began from (BreakAtTheJump)
  double retry_p_ = 0.0;
  int snaps_ = 0;                  // points broken at the jump
  // x2_ = K^-1 g and zg_ = L^-1 g hold for the leading x2_size_ nodes of the
  // current tangent factor (-1: not at all); border_l_: UpdateX2's row.
  Eigen::VectorXd zg_, border_l_;
  int x2_size_ = -1;
  bool linear_steps_ = false;  // the quadratic load step failed once in this run
  static constexpr int kQuadraticIterations = 12;
  int carried_t_ = -1;             // tip of the last verified chord-Newton solve
  double p_ = 0.0;
  const double force_scale_;
  ZoneSystem zone_;
  Eigen::VectorXd zone_u_, zone_b_;
  // The step: tip node, its flexibility terms, tip force, first zone node.
  int t_ = 0, z0_ = 1;
  double phi_ = NAN, psi_ = NAN, tip_force_ = 0.0;
};

}  // namespace

void GrowBordered(const CrackPlaneModel& m, const ElasticTables& tables,
                  const laws::BridgingLaw* law, double J_tip_c, const ReducedOptions& options,
                  SimulationResult& result, int& newton_total) {
  const int n = m.size();
  BorderedGrowth growth(m, tables, law, J_tip_c, options, newton_total);
  Progress progress("reduced model", static_cast<size_t>(n - 1), options.progress);
  for (int t = 1; t < n; ++t) {
    bool solved = growth.Solve(t);
    while (!solved && growth.BreakAtTheJump()) solved = growth.Solve(t);
    if (!solved) {
      result.status = RunStatus::kNotConverged;
      result.message = fmt::format("Newton did not converge at crack length {:.6g} mm",
                                   m.CrackLength(t) * 1e3);
      break;
    }
    growth.Record(result);
    progress.Update(static_cast<size_t>(t));
    if (t + 1 < n) growth.Border();
  }
  progress.Finish();
  if (growth.snaps() > 0) result.figures["points_broken_at_the_law_jump"] = growth.snaps();
}

}  // namespace bridgefit::models::reduced_internal
