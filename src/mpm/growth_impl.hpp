#pragma once
// Private to src/mpm: the quasi-static growth solver behind SimulateGrowth
// (growth.hpp): its class (this header), its assembly, factorization and
// field evaluations (growth_assembly.cpp) and its growth loop (growth.cpp).

#include <omp.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/laws/rcurve_theory.hpp"
#include "bridgefit/mpm/material.hpp"
#include "bridgefit/mpm/model.hpp"
#include "shape.hpp"
#include "bridgefit/mpm/growth.hpp"

namespace bridgefit::mpm::growth_internal {


using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using detail::Weights;
using Vec = Eigen::VectorXd;

// A linear functional of the displacement vector: sum coef * u[dof].
struct Functional {
  std::vector<int> dof;
  std::vector<double> coef;
  double Apply(const Vec& u) const {
    double s = 0.0;
    for (std::size_t i = 0; i < dof.size(); ++i) s += coef[i] * u[dof[i]];
    return s;
  }
};

// One bridged crack point (full model: a crack point; half model: a released
// node on the symmetry plane).
struct BridgedPoint {
  double x = 0.0;
  double delta_max = 0.0;
  bool broken = false;
  double delta = 0.0;  // current opening
};

class StaticGrowth {
 public:
  StaticGrowth(const Scene& scene, const GrowthOptions& opt) : scene_(scene), opt_(opt) {
    std::string why;
    if (!opt_.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid MPM growth options: " + why);
    // Auto: the half model when the scene is symmetric and its notch tip
    // lies on a node (grid nodes sit on multiples of the cell), else full.
    const double tip_nodes = scene.specimen.notch / opt_.cell;
    const bool tip_on_node = std::abs(tip_nodes - std::round(tip_nodes)) < 1e-6;
    half_ = opt_.symmetry == GrowthSymmetry::kHalf ||
            (opt_.symmetry == GrowthSymmetry::kAuto && SceneIsSymmetric(scene) && tip_on_node);
    if (!half_)
      BF_CHECK_INPUT(opt_.ppc % 2 == 0,
                     "the full explicit-crack model needs an even number of particles per cell "
                     "(the crack plane lies between particle rows)",
                     {.field = "ppc", .value = std::to_string(opt_.ppc), .expected = "2, 4, 6 or 8"});
    // The quasi-static solve has no inertia: the density (optional in the
    // scene, docs/FORMATS.md) only has to satisfy the model's check.
    Scene static_scene = scene;
    if (!(static_scene.material.density > 0.0)) static_scene.material.density = 1.0;
    model_ = half_ ? BuildHalfSpecimenModel(static_scene, opt_.cell, opt_.ppc)
                   : BuildSpecimenModel(static_scene, opt_.cell, opt_.ppc);
    const auto* elastic = dynamic_cast<const LinearElastic*>(model_.law.get());
    BF_CHECK_INPUT(elastic != nullptr, "MPM crack growth needs a linear elastic material");
    Q_ = elastic->Stiffness();
    const GridSpec& g = model_.grid;
    h_ = g.cell;
    inv_h_ = 1.0 / h_;
    x0_ = g.x0;
    y0_ = g.y0;
    nx_ = g.nx;
    ny_ = g.ny;
    N_ = static_cast<int>(g.NodeCount());
    lp_ = opt_.shape == ShapeFunction::kGimp ? 0.5 / opt_.ppc : 0.0;
    inv_lp_ = lp_ > 0.0 ? 1.0 / lp_ : 0.0;
    slots_ = half_ ? N_ : 2 * N_;
    ndof_ = 2 * slots_;
    const auto& s = model_.particles;
    P_ = s.size();
    px_ = s.x;
    py_ = s.y;
    vol_ = s.volume;
    cell_volume_ = h_ * h_;

    const SpecimenSpec& sp = scene.specimen;
    if (sp.type == SpecimenType::kCT) {
      x_front_ = -0.25 * sp.width;
      x_back_ = sp.width;
    } else {
      x_front_ = 0.0;
      x_back_ = sp.length;
    }
    x_mouth_ = x_front_ - h_;
    a0_ = sp.notch;
    if (half_) {
      j_sym_ = static_cast<int>(std::lround(-y0_ * inv_h_));
      // The tip sits on a node of the symmetry plane.
      const double i_tip = (a0_ - x0_) * inv_h_;
      BF_CHECK_INPUT(std::abs(i_tip - std::round(i_tip)) < 1e-6,
                     "the half model needs the notch tip on a node: a0 must be a multiple of the "
                     "cell size",
                     {.field = "cell", .value = fmt::format("{:g} mm", h_ * 1e3),
                      .expected = fmt::format("a divisor of a0 = {:g} mm", a0_ * 1e3)});
      increment_ = opt_.increment > 0.0 ? opt_.increment : h_;
      const double steps = increment_ * inv_h_;
      BF_CHECK_INPUT(std::abs(steps - std::round(steps)) < 1e-6 && steps > 1.0 - 1e-6,
                     "the half model advances the tip from node to node: the increment must be "
                     "a multiple of the cell size",
                     {.field = "increment", .value = fmt::format("{:g} mm", increment_ * 1e3),
                      .expected = fmt::format("a multiple of {:g} mm", h_ * 1e3)});
    } else {
      jb_ = static_cast<int>(std::floor(-y0_ * inv_h_));
      ja_ = jb_ + 1;
      increment_ = opt_.increment > 0.0 ? opt_.increment : h_;
    }
    const int kmax = *std::max_element(opt_.contour_cells.begin(), opt_.contour_cells.end());
    const double edge_limit = x_back_ - (kmax + 2) * h_;
    x_end_ = edge_limit;
    double wanted = opt_.max_crack_length > 0.0 ? opt_.max_crack_length
                    : scene.run.max_crack_length ? *scene.run.max_crack_length
                                                 : edge_limit;
    x_end_ = std::min(wanted, edge_limit);
    BF_CHECK_INPUT(x_end_ > a0_ + increment_, "no room for crack growth",
                   {.field = "run.max_crack_length",
                    .value = fmt::format("{:g} mm", wanted * 1e3),
                    .expected = fmt::format("> a0 + one increment = {:g} mm and at most {:g} mm "
                                            "(the J contour must fit before the back edge)",
                                            (a0_ + increment_) * 1e3, edge_limit * 1e3)});
    k_scale_ = std::max(Q_[0], Q_[4]);
    k_penalty_ = 1e6 * k_scale_;
    threads_ = opt_.threads > 0 ? opt_.threads : omp_get_max_threads();
  }

  GrowthResult Run(const laws::BridgingLaw* law, double J_tip_c);

 private:
  // ------------------------------------------------------------ geometry
  double NodeX(int n) const { return x0_ + (n % nx_) * h_; }
  double NodeY(int n) const { return y0_ + (n / nx_) * h_; }

  void ParticleWeights(std::size_t p, Weights& wt) const {
    if (lp_ > 0.0) detail::PatchWeights<true>(px_[p], py_[p], x0_, y0_, inv_h_, lp_, inv_lp_, wt);
    else detail::PatchWeights<false>(px_[p], py_[p], x0_, y0_, inv_h_, 0.0, 0.0, wt);
  }

  // Bit (b*3 + a) set: the line from particle p to node (i0 + a, j0 + b)
  // crosses the straight crack y = 0, x_mouth <= x < x_tip (full model).
  std::uint16_t Mask(std::size_t p, const Weights& wt, double x_tip) const {
    if (half_) return 0;
    const double x = px_[p], y = py_[p];
    std::uint16_t bits = 0;
    for (int b = 0; b < 3; ++b) {
      const double yn = y0_ + (wt.j0 + b) * h_;
      if ((yn > 0.0) == (y > 0.0)) continue;
      for (int a = 0; a < 3; ++a) {
        const double xn = x0_ + (wt.i0 + a) * h_;
        const double xi = x + (xn - x) * (-y) / (yn - y);
        if (xi >= x_mouth_ && xi < x_tip) bits |= static_cast<std::uint16_t>(1u << (b * 3 + a));
      }
    }
    return bits;
  }

  // Slots (node, field) and their dofs.
  int Slot(int node, bool other_field) const { return node + (other_field ? N_ : 0); }

  // Particle stiffness V B^T Q B (18 x 18) on its patch's dofs.
  void ParticleMatrix(std::size_t p, const Weights& wt, std::uint16_t bits, int dofs[18],
                      double ke[18][18]) const {
    double B[3][18];
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) {
        const int k = b * 3 + a;
        const int node = (wt.j0 + b) * nx_ + wt.i0 + a;
        const int slot = Slot(node, (bits >> k) & 1u);
        dofs[2 * k] = 2 * slot;
        dofs[2 * k + 1] = 2 * slot + 1;
        const double dx = wt.gx[a] * wt.sy[b], dy = wt.sx[a] * wt.gy[b];
        B[0][2 * k] = dx;  B[0][2 * k + 1] = 0.0;
        B[1][2 * k] = 0.0; B[1][2 * k + 1] = dy;
        B[2][2 * k] = dy;  B[2][2 * k + 1] = dx;
      }
    double QB[3][18];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 18; ++c)
        QB[r][c] = Q_[3 * r] * B[0][c] + Q_[3 * r + 1] * B[1][c] + Q_[3 * r + 2] * B[2][c];
    const double V = vol_[p];
    for (int i = 0; i < 18; ++i)
      for (int j = 0; j <= i; ++j)
        ke[i][j] = V * (B[0][i] * QB[0][j] + B[1][i] * QB[1][j] + B[2][i] * QB[2][j]);
  }

  // A node of a rigid pin's hole that the pin pushes on: the unit normal
  // from the pin centre and the displacement along it per unit load-point
  // displacement (the pin pushes on the far side of its hole only).
  bool PinContact(const NodeConstraint& c, int n, double* ex, double* ey, double* push) const {
    double x = NodeX(n) - c.center_x, y = NodeY(n) - c.center_y;
    const double r = std::hypot(x, y);
    if (r <= 0.0) return false;
    *ex = x / r;
    *ey = y / r;
    *push = c.share_x * *ex + c.share_y * *ey;
    return *push > 0.0;
  }

  // Particles whose mask can change as the tip advances (full model).
  bool Candidate(std::size_t p) const {
    return !half_ && std::abs(py_[p]) < (1.0 + lp_) * h_ && px_[p] > a0_ - 2.0 * h_ &&
           px_[p] < x_end_ + 2.0 * h_;
  }

  void AssembleInitial(double x_tip);
  void UpdateMasks(double x_tip);
  void AddToMatrix(std::size_t p, const Weights& wt, std::uint16_t bits, double sign);
  bool Factorize(double x_tip);
  Functional CodFunctional(double x) const;
  double ReactionLoad(const Vec& u, double d) const;
  void ParticleFields(const Vec& u, std::size_t p, const Weights& wt, std::uint16_t bits,
                      double f[6]) const;
  double ContourJ(const Vec& u, double x_tip, int k) const;

  // ------------------------------------------------------------ Run's stages
  // (growth.cpp; each states its equation at its definition)
  // One crack length's unit fields, reduced bridged system and state.
  struct LengthSystem {
    double x_tip = 0;
    std::vector<int> act;               // active (unbroken) bridged points
    std::vector<double> c;              // their face lengths
    int nb = 0;                         // act.size()
    std::vector<Functional> cod;        // opening functionals of every crack point
    Functional tip_cod;                 // opening at the tip
    std::vector<Functional> g;          // cod of the active points
    Vec U_d;                            // K^-1 F_d
    Eigen::MatrixXd G;                  // K^-1 g_q, one column per active point
    Vec A;                              // g_q . U_d
    Eigen::MatrixXd M;                  // g_q . G_r
    Vec delta, sig;                     // openings and closing forces c sigma
    std::vector<double> J_all, Jtip_all;  // per contour
  };
  struct LoadSolution {
    double d2 = 0, f2 = 0;  // last secant iterate and its residual
    int iterations = 0;
    bool ok = true;  // bridged openings converged
  };
  bool FactorizeAt(double x_tip);
  LengthSystem UnitFields(const std::vector<BridgedPoint>& pts, double x_tip);
  void ReduceToBridgedPoints(const std::vector<BridgedPoint>& pts, LengthSystem& sys) const;
  bool SolveOpenings(const laws::BridgingLaw* law, const std::vector<BridgedPoint>& pts,
                     LengthSystem& sys, double d) const;
  static Vec Field(const LengthSystem& sys, double d);
  double TipJ(const laws::BridgingLaw* law, const std::vector<BridgedPoint>& pts,
              LengthSystem& sys, const Vec& u) const;
  LoadSolution SolveLoadForJtipc(const laws::BridgingLaw* law, double J_tip_c,
                                 const std::vector<BridgedPoint>& pts, double d_prev,
                                 LengthSystem& sys) const;
  SimulationPoint RecordCrackLength(const laws::BridgingLaw* law, double J_tip_c,
                                    const Functional& mouth, const Vec& u, double d,
                                    const LengthSystem& sys, std::vector<BridgedPoint>& pts,
                                    SimulationResult& res) const;
  void AddBridgedPoints(const laws::BridgingLaw* law, double x_tip, double next,
                        std::vector<BridgedPoint>& pts) const;

  const Scene& scene_;
  GrowthOptions opt_;
  Model model_;
  bool half_ = false;
  std::array<double, 9> Q_{};
  double h_ = 0, inv_h_ = 0, x0_ = 0, y0_ = 0, lp_ = 0, inv_lp_ = 0, cell_volume_ = 0;
  int nx_ = 0, ny_ = 0, N_ = 0, slots_ = 0, ndof_ = 0;
  int j_sym_ = 0, jb_ = 0, ja_ = 0;
  std::size_t P_ = 0;
  std::vector<double> px_, py_, vol_;
  std::vector<std::uint16_t> mask_;
  std::vector<double> slot_mass_;
  double x_front_ = 0, x_back_ = 0, x_mouth_ = 0, a0_ = 0, x_end_ = 0, increment_ = 0;
  double k_scale_ = 0, k_penalty_ = 0;
  int threads_ = 1;

  SpMat K_;                  // particle stiffness, lower triangle, fixed pattern
  std::vector<int> diag_;    // value index of each column's diagonal
  SpMat Kf_;                 // with penalties and inactive slots
  Eigen::SimplicialLDLT<SpMat, Eigen::Lower> ldlt_;
  bool analyzed_ = false;
  Vec F_d_;                  // load vector of a unit load-point displacement

  double t_assembly_ = 0, t_factor_ = 0, t_solve_ = 0, t_nonlinear_ = 0;
};

}  // namespace bridgefit::mpm::growth_internal
