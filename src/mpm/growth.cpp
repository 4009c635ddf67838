#include "bridgefit/mpm/growth.hpp"

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

namespace bridgefit::mpm {

const char* GrowthSymmetryName(GrowthSymmetry symmetry) {
  switch (symmetry) {
    case GrowthSymmetry::kAuto: return "auto";
    case GrowthSymmetry::kHalf: return "half";
    case GrowthSymmetry::kFull: return "full";
  }
  return "?";
}

bool GrowthOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!(cell > 0.0)) return fail("cell must be positive");
  if (ppc < 1 || ppc > 8) return fail("ppc must be 1..8");
  if (!(increment >= 0.0)) return fail("increment must be >= 0");
  if (contour_cells.empty()) return fail("at least one J contour is needed");
  for (int k : contour_cells)
    if (k < 1) return fail("contour half sizes must be >= 1 cell");
  if (!(max_crack_length >= 0.0)) return fail("max_crack_length must be >= 0");
  if (!(tolerance > 0.0 && tolerance < 0.1)) return fail("tolerance must be in (0, 0.1)");
  if (max_iterations < 2) return fail("max_iterations must be >= 2");
  if (threads < 0) return fail("threads must be >= 0");
  return true;
}

bool SceneIsSymmetric(const Scene& scene) {
  const MaterialSpec& m = scene.material;
  if (!m.orthotropic) return true;
  const double a = std::fmod(std::abs(m.angle), M_PI);
  return a < 1e-9 || std::abs(a - 0.5 * M_PI) < 1e-9 || std::abs(a - M_PI) < 1e-9;
}

namespace {

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

void StaticGrowth::AssembleInitial(double x_tip) {
  mask_.assign(P_, 0);
  slot_mass_.assign(slots_, 0.0);
  std::vector<std::vector<Eigen::Triplet<double>>> parts(threads_);
#pragma omp parallel num_threads(threads_)
  {
    auto& trip = parts[omp_get_thread_num()];
    int dofs[18];
    double ke[18][18];
    Weights wt;
#pragma omp for schedule(static)
    for (std::size_t p = 0; p < P_; ++p) {
      ParticleWeights(p, wt);
      const std::uint16_t bits = Mask(p, wt, x_tip);
      mask_[p] = bits;
      ParticleMatrix(p, wt, bits, dofs, ke);
      for (int i = 0; i < 18; ++i)
        for (int j = 0; j <= i; ++j) {
          if (ke[i][j] == 0.0) continue;
          const int r = std::max(dofs[i], dofs[j]), c = std::min(dofs[i], dofs[j]);
          trip.emplace_back(r, c, ke[i][j]);
        }
      if (Candidate(p)) {
        // Every field choice the crack can give this particle's nodes: the
        // pattern is fixed, the tip only changes values.
        int all[36];
        int count = 0;
        for (int b = 0; b < 3; ++b)
          for (int a = 0; a < 3; ++a) {
            const int node = (wt.j0 + b) * nx_ + wt.i0 + a;
            for (int f = 0; f < 2; ++f) {
              const int slot = Slot(node, f == 1);
              all[count++] = 2 * slot;
              all[count++] = 2 * slot + 1;
            }
          }
        for (int i = 0; i < count; ++i)
          for (int j = 0; j <= i; ++j)
            trip.emplace_back(std::max(all[i], all[j]), std::min(all[i], all[j]), 0.0);
      }
    }
  }
  std::vector<Eigen::Triplet<double>> all;
  std::size_t total = ndof_;
  for (const auto& t : parts) total += t.size();
  all.reserve(total);
  for (auto& t : parts) {
    all.insert(all.end(), t.begin(), t.end());
    std::vector<Eigen::Triplet<double>>().swap(t);
  }
  for (int d = 0; d < ndof_; ++d) all.emplace_back(d, d, 0.0);
  // Penalty couplings (x-y of a pin node) are inside the particle pattern.
  K_.resize(ndof_, ndof_);
  K_.setFromTriplets(all.begin(), all.end());
  K_.makeCompressed();
  diag_.assign(ndof_, -1);
  for (int c = 0; c < ndof_; ++c) {
    const int start = K_.outerIndexPtr()[c];
    BF_CHECK_INPUT(K_.innerIndexPtr()[start] == c, "internal: missing diagonal in the MPM matrix");
    diag_[c] = start;
  }
  Weights wt;
  for (std::size_t p = 0; p < P_; ++p) {
    ParticleWeights(p, wt);
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) {
        const int node = (wt.j0 + b) * nx_ + wt.i0 + a;
        slot_mass_[Slot(node, (mask_[p] >> (b * 3 + a)) & 1u)] += wt.sx[a] * wt.sy[b] * vol_[p];
      }
  }
}

void StaticGrowth::AddToMatrix(std::size_t p, const Weights& wt, std::uint16_t bits,
                               double sign) {
  int dofs[18];
  double ke[18][18];
  ParticleMatrix(p, wt, bits, dofs, ke);
  for (int i = 0; i < 18; ++i)
    for (int j = 0; j <= i; ++j) {
      if (ke[i][j] == 0.0) continue;
      K_.coeffRef(std::max(dofs[i], dofs[j]), std::min(dofs[i], dofs[j])) += sign * ke[i][j];
    }
  for (int b = 0; b < 3; ++b)
    for (int a = 0; a < 3; ++a) {
      const int node = (wt.j0 + b) * nx_ + wt.i0 + a;
      slot_mass_[Slot(node, (bits >> (b * 3 + a)) & 1u)] += sign * wt.sx[a] * wt.sy[b] * vol_[p];
    }
}

void StaticGrowth::UpdateMasks(double x_tip) {
  if (half_) return;
  Weights wt;
  for (std::size_t p = 0; p < P_; ++p) {
    if (!Candidate(p)) continue;
    ParticleWeights(p, wt);
    const std::uint16_t bits = Mask(p, wt, x_tip);
    if (bits == mask_[p]) continue;
    AddToMatrix(p, wt, mask_[p], -1.0);
    AddToMatrix(p, wt, bits, 1.0);
    mask_[p] = bits;
  }
}

// Penalties: pins (normal displacement of the pushed hole nodes), arm ends,
// the symmetry plane ahead of the tip (half model), an x anchor where nothing
// else holds x; unit slots for empty ones. Builds F_d.
bool StaticGrowth::Factorize(double x_tip) {
  Kf_ = K_;
  double* v = Kf_.valuePtr();
  const double empty = 1e-12 * cell_volume_;
  for (int s = 0; s < slots_; ++s) {
    if (slot_mass_[s] > empty) continue;
    v[diag_[2 * s]] += k_scale_;
    v[diag_[2 * s + 1]] += k_scale_;
  }
  F_d_ = Vec::Zero(ndof_);
  bool holds_x = false;
  auto add_block = [&](int node, double nxn, double nyn, double target) {
    // k (u.n - target d) n: matrix k n n^T, load k target n.
    const int dx = 2 * node, dy = dx + 1;
    v[diag_[dx]] += k_penalty_ * nxn * nxn;
    v[diag_[dy]] += k_penalty_ * nyn * nyn;
    if (nxn != 0.0 && nyn != 0.0) Kf_.coeffRef(dy, dx) += k_penalty_ * nxn * nyn;
    F_d_[dx] += k_penalty_ * target * nxn;
    F_d_[dy] += k_penalty_ * target * nyn;
  };
  for (const NodeConstraint& c : model_.constraints) {
    for (int n : c.nodes) {
      if (slot_mass_[n] <= empty) continue;
      if (c.radial) {
        double ex, ey, push;
        if (!PinContact(c, n, &ex, &ey, &push)) continue;
        add_block(n, ex, ey, push);
        holds_x = true;
      } else {
        if (c.constrain_x) {
          add_block(n, 1.0, 0.0, c.share_x);
          holds_x = true;
        }
        if (c.constrain_y) add_block(n, 0.0, 1.0, c.share_y);
      }
    }
  }
  if (!holds_x && model_.load_constraint >= 0) {
    const auto& nodes = model_.constraints[model_.load_constraint].nodes;
    if (!nodes.empty()) add_block(nodes[nodes.size() / 2], 1.0, 0.0, 0.0);
  }
  if (half_) {
    for (int i = 0; i < nx_; ++i) {
      const int n = j_sym_ * nx_ + i;
      if (NodeX(n) < x_tip - 1e-9 * h_ || slot_mass_[n] <= empty) continue;
      add_block(n, 0.0, 1.0, 0.0);
    }
  }
  // A tiny spring on every dof keeps weakly held slots near the tip regular.
  for (int d = 0; d < ndof_; ++d) v[diag_[d]] += 1e-10 * k_scale_;
  if (!analyzed_) {
    ldlt_.analyzePattern(Kf_);
    analyzed_ = true;
  }
  ldlt_.factorize(Kf_);
  return ldlt_.info() == Eigen::Success;
}

// COD functional at x on the crack plane: mass-weighted face displacements
// of the cell's nodes (full model), 2 u_y of the node (half model).
Functional StaticGrowth::CodFunctional(double x) const {
  Functional f;
  if (half_) {
    const int i = static_cast<int>(std::floor((x - x0_) * inv_h_ + 1e-9));
    const double r = std::clamp((x - x0_) * inv_h_ - i, 0.0, 1.0);
    for (int a = 0; a < 2; ++a) {
      const double w = a ? r : 1.0 - r;
      if (w <= 1e-12) continue;
      f.dof.push_back(2 * (j_sym_ * nx_ + i + a) + 1);
      f.coef.push_back(2.0 * w);
    }
    return f;
  }
  const int i = static_cast<int>(std::floor((x - x0_) * inv_h_));
  const double r = (x - x0_) * inv_h_ - i;
  const double empty = 1e-12 * cell_volume_;
  for (int side = 0; side < 2; ++side) {  // 0: above face, 1: below face
    double total = 0.0;
    std::vector<std::pair<int, double>> terms;
    for (int row = 0; row < 2; ++row) {   // 0: row below the crack, 1: above
      const int j = row ? ja_ : jb_;
      for (int a = 0; a < 2; ++a) {
        const int node = j * nx_ + i + a;
        // The above face of a node above the crack is its own field.
        const bool own = (row == 1) == (side == 0);
        const int slot = Slot(node, !own);
        const double m = slot_mass_[slot];
        if (m <= empty) continue;
        const double w = (a ? r : 1.0 - r) * 0.5 * m;
        terms.emplace_back(2 * slot + 1, w);
        total += w;
      }
    }
    if (total <= 0.0) continue;
    for (const auto& [dof, w] : terms) {
      f.dof.push_back(dof);
      f.coef.push_back((side == 0 ? 1.0 : -1.0) * w / total);
    }
  }
  return f;
}

// Load on the load constraint [N]: the penalty reaction along its direction.
double StaticGrowth::ReactionLoad(const Vec& u, double d) const {
  if (model_.load_constraint < 0) return NAN;
  const NodeConstraint& c = model_.constraints[model_.load_constraint];
  const double share = std::hypot(c.share_x, c.share_y);
  const double sx = c.share_x / share, sy = c.share_y / share;
  const double empty = 1e-12 * cell_volume_;
  double rx = 0.0, ry = 0.0;
  for (int n : c.nodes) {
    if (slot_mass_[n] <= empty) continue;
    const double ux = u[2 * n], uy = u[2 * n + 1];
    if (c.radial) {
      double ex, ey, push;
      if (!PinContact(c, n, &ex, &ey, &push)) continue;
      const double f = k_penalty_ * (push * d - (ux * ex + uy * ey));
      rx += f * ex;
      ry += f * ey;
    } else {
      if (c.constrain_x) rx += k_penalty_ * (c.share_x * d - ux);
      if (c.constrain_y) ry += k_penalty_ * (c.share_y * d - uy);
    }
  }
  return (rx * sx + ry * sy) * model_.thickness;
}

// Particle strain (xx, yy, engineering xy), u_{x,x}, u_{y,x} and the strain
// energy density from the grid displacements.
void StaticGrowth::ParticleFields(const Vec& u, std::size_t, const Weights& wt,
                                  std::uint16_t bits, double f[6]) const {
  double exx = 0, eyy = 0, gxy = 0, uyx = 0;
  for (int b = 0; b < 3; ++b)
    for (int a = 0; a < 3; ++a) {
      const int k = b * 3 + a;
      const int slot = Slot((wt.j0 + b) * nx_ + wt.i0 + a, (bits >> k) & 1u);
      const double ux = u[2 * slot], uy = u[2 * slot + 1];
      const double dx = wt.gx[a] * wt.sy[b], dy = wt.sx[a] * wt.gy[b];
      exx += ux * dx;
      eyy += uy * dy;
      gxy += ux * dy + uy * dx;
      uyx += uy * dx;
    }
  const double sxx = Q_[0] * exx + Q_[1] * eyy + Q_[2] * gxy;
  const double syy = Q_[3] * exx + Q_[4] * eyy + Q_[5] * gxy;
  const double sxy = Q_[6] * exx + Q_[7] * eyy + Q_[8] * gxy;
  f[0] = sxx;
  f[1] = syy;
  f[2] = sxy;
  f[3] = exx;  // u_{x,x}
  f[4] = uyx;
  f[5] = 0.5 * (sxx * exx + syy * eyy + sxy * gxy);
}

// J on a rectangular grid contour of half size k cells around the tip:
// int (W n_x - t . u_{,x}) ds with particle fields extrapolated to the nodes
// of each side's own field (mass-weighted). Half model: twice the upper half.
double StaticGrowth::ContourJ(const Vec& u, double x_tip, int k) const {
  const int it = static_cast<int>(std::lround((x_tip - x0_) * inv_h_));
  int iL = it - k, iR = it + k, jB, jT;
  if (half_) {
    jB = j_sym_;
    jT = j_sym_ + k;
  } else {
    jB = jb_ - (k - 1);
    jT = ja_ + (k - 1);
  }
  if (iL < 0 || iR >= nx_ || jB < 0 || jT >= ny_) return NAN;
  const double xlo = x0_ + (iL - 2) * h_, xhi = x0_ + (iR + 2) * h_;
  const double ylo = y0_ + (jB - 2) * h_, yhi = y0_ + (jT + 2) * h_;
  // Box-local node storage: (iL-2 .. iR+2) x (jB-2 .. jT+2), two fields.
  const int bi0 = std::max(0, iL - 2), bj0 = std::max(0, jB - 2);
  const int bw = std::min(nx_ - 1, iR + 2) - bi0 + 1, bh = std::min(ny_ - 1, jT + 2) - bj0 + 1;
  constexpr int kQ = 7;  // m, sxx, syy, sxy, uxx, uyx, w
  std::vector<double> ext(static_cast<std::size_t>(2) * bw * bh * kQ, 0.0);
  auto local = [&](int i, int j, int field) {
    return ((static_cast<std::size_t>(field) * bh + (j - bj0)) * bw + (i - bi0)) * kQ;
  };
  Weights wt;
  double f[6];
  for (std::size_t p = 0; p < P_; ++p) {
    if (px_[p] < xlo || px_[p] > xhi || py_[p] < ylo || py_[p] > yhi) continue;
    ParticleWeights(p, wt);
    const std::uint16_t bits = mask_[p];
    ParticleFields(u, p, wt, bits, f);
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) {
        const int i = wt.i0 + a, j = wt.j0 + b;
        if (i < bi0 || i >= bi0 + bw || j < bj0 || j >= bj0 + bh) continue;
        const double S = wt.sx[a] * wt.sy[b] * vol_[p];
        if (S <= 0.0) continue;
        const std::size_t q = local(i, j, (bits >> (b * 3 + a)) & 1u);
        ext[q] += S;
        for (int c = 0; c < 6; ++c) ext[q + 1 + c] += S * f[c];
      }
  }
  auto integrand = [&](int i, int j, double nxn, double nyn) {
    const std::size_t q = local(i, j, 0);
    const double m = ext[q];
    if (m <= 0.0) return 0.0;
    const double s11 = ext[q + 1] / m, s22 = ext[q + 2] / m, s12 = ext[q + 3] / m;
    const double uxx = ext[q + 4] / m, uyx = ext[q + 5] / m, wd = ext[q + 6] / m;
    return wd * nxn - (s11 * nxn + s12 * nyn) * uxx - (s12 * nxn + s22 * nyn) * uyx;
  };
  detail::ContourBox box{.iL = iL, .iR = iR, .jB = jB, .jT = jT, .half = half_};
  if (!half_) {
    // The crack line is y = 0.
    box.jb = jb_;
    box.ja = ja_;
    box.above = y0_ + ja_ * h_;
    box.below = -(y0_ + jb_ * h_);
  }
  return detail::ContourIntegral(box, h_, integrand);
}

GrowthResult StaticGrowth::Run(const laws::BridgingLaw* law, double J_tip_c) {
  Stopwatch watch;
  BF_CHECK_INPUT(std::isfinite(J_tip_c) && J_tip_c > 0.0, "J_tip,c must be positive",
                 {.field = "fracture.J_tip_c", .value = fmt::format("{:g} J/m^2", J_tip_c)});
  if (law)
    BF_CHECK_INPUT(law->shape && law->delta_c > 0.0 && law->sigma_c > 0.0,
                   "the bridging law needs sigma_c > 0 and delta_c > 0", {.field = "bridging"});
  GrowthResult out;
  out.half = half_;
  out.cell = h_;
  out.increment = increment_;
  out.particles = P_;
  out.dofs = static_cast<std::size_t>(ndof_);
  out.contour_cells = opt_.contour_cells;
  SimulationResult& res = out.result;
  res.model = "mpm";
  res.figures["cell_m"] = h_;
  res.figures["increment_m"] = increment_;
  res.figures["particles"] = static_cast<double>(P_);
  res.figures["dofs"] = ndof_;
  res.figures["half_model"] = half_ ? 1.0 : 0.0;

  double x_tip = a0_;
  {
    Stopwatch s;
    AssembleInitial(x_tip);
    t_assembly_ += s.Seconds();
  }
  // Bridged points: crack points from a0 to the tip (full model, the tip
  // point included), released symmetry-plane nodes behind the tip (half).
  std::vector<BridgedPoint> pts;
  if (law && !half_) pts.push_back({.x = a0_});
  const int steps_total = static_cast<int>(std::floor((x_end_ - a0_) / increment_ + 1e-9)) + 1;
  Progress progress("MPM growth", static_cast<std::size_t>(steps_total), opt_.progress);
  double d_prev = NAN;
  const Functional mouth = CodFunctional(x_front_ + (half_ ? 0.0 : 0.25 * h_));
  int step = 0;
  for (;; ++step) {
    // ---- system for this crack length
    {
      Stopwatch s;
      UpdateMasks(x_tip);
      t_assembly_ += s.Seconds();
    }
    {
      Stopwatch s;
      const bool ok = Factorize(x_tip);
      t_factor_ += s.Seconds();
      if (!ok) {
        res.status = RunStatus::kFailed;
        res.message = fmt::format("the static system is singular at a = {:.4g} mm", x_tip * 1e3);
        break;
      }
    }
    // Active (unbroken) bridged points and their face lengths.
    std::vector<int> act;
    std::vector<double> c;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      if (pts[k].broken) continue;
      const double prev = k == 0 ? a0_ : pts[k - 1].x;
      const double next = k + 1 < pts.size() ? pts[k + 1].x : (half_ ? x_tip : pts[k].x);
      const double w = 0.5 * (std::max(next, a0_) - std::max(prev, a0_));
      if (w <= 0.0) continue;
      act.push_back(static_cast<int>(k));
      c.push_back(half_ ? 0.5 * w : w);
    }
    const int nb = static_cast<int>(act.size());
    // Opening functionals of every crack point, once per crack length.
    std::vector<Functional> cod(pts.size());
    for (std::size_t k = 0; k < pts.size(); ++k) cod[k] = CodFunctional(pts[k].x);
    const Functional tip_cod = CodFunctional(x_tip);
    std::vector<Functional> g(nb);
    Vec U_d;
    Eigen::MatrixXd G(ndof_, nb);
    {
      Stopwatch s;
      U_d = ldlt_.solve(F_d_);
      for (int q = 0; q < nb; ++q) {
        g[q] = cod[act[q]];
        Vec rhs = Vec::Zero(ndof_);
        for (std::size_t e = 0; e < g[q].dof.size(); ++e) rhs[g[q].dof[e]] += g[q].coef[e];
        G.col(q) = ldlt_.solve(rhs);
      }
      t_solve_ += s.Seconds();
    }
    Stopwatch nonlinear;
    Vec A(nb);
    Eigen::MatrixXd M(nb, nb);
    for (int q = 0; q < nb; ++q) {
      A[q] = g[q].Apply(U_d);
      for (int r = 0; r < nb; ++r) M(q, r) = g[q].Apply(G.col(r));
    }
    // Traction and slope at opening x of active point q.
    auto traction = [&](int q, double x, double* slope) {
      const BridgedPoint& b = pts[act[q]];
      const double s0 = law->TractionWithHistory(x, b.delta_max);
      if (slope) {
        const double e = 1e-7 * law->delta_c;
        *slope = (law->TractionWithHistory(x + e, b.delta_max) -
                  law->TractionWithHistory(x - e, b.delta_max)) / (2.0 * e);
      }
      return s0;
    };
    Vec delta = Vec::Zero(nb), sig = Vec::Zero(nb);
    for (int q = 0; q < nb; ++q) delta[q] = pts[act[q]].delta;
    // Openings at load-point displacement d (Newton on delta, damped).
    auto solve_openings = [&](double d) {
      if (nb == 0) return true;
      Vec r(nb), slope(nb);
      for (int it = 0; it < 100; ++it) {
        for (int q = 0; q < nb; ++q) sig[q] = c[q] * traction(q, delta[q], &slope[q]);
        r = delta - d * A + M * sig;
        const double norm = r.cwiseAbs().maxCoeff();
        if (norm < 1e-13 * law->delta_c + 1e-15) return true;
        const Vec cs = Eigen::Map<const Vec>(c.data(), nb).cwiseProduct(slope);
        Eigen::MatrixXd Jm = M * cs.asDiagonal();
        Jm.diagonal().array() += 1.0;
        Vec step_v = Jm.partialPivLu().solve(r);
        double lambda = 1.0;
        for (int ls = 0; ls < 30; ++ls) {
          Vec trial = delta - lambda * step_v;
          Vec st(nb);
          for (int q = 0; q < nb; ++q) st[q] = c[q] * traction(q, trial[q], nullptr);
          const double tn = (trial - d * A + M * st).cwiseAbs().maxCoeff();
          if (tn < norm || ls == 29) {
            delta = trial;
            break;
          }
          lambda *= 0.5;
        }
      }
      return false;
    };
    auto field = [&](double d) {
      Vec u = d * U_d;
      if (nb > 0) u.noalias() -= G * sig;
      return u;
    };
    // J_tip on each contour: contour J minus int sigma d(delta) between the
    // contour's crossing of the crack and the tip (PHYSICS 4).
    std::vector<double> J_all(opt_.contour_cells.size()), Jtip_all(opt_.contour_cells.size());
    auto tip_J = [&](const Vec& u) {
      // Openings and tractions of every crack point behind the tip, tip last.
      std::vector<double> xs, ds, ss;
      for (std::size_t k = 0; k < pts.size(); ++k) {
        if (half_ || pts[k].x < x_tip - 1e-9 * h_) {
          xs.push_back(pts[k].x);
          ds.push_back(cod[k].Apply(u));
          ss.push_back(law ? law->TractionWithHistory(ds.back(), pts[k].delta_max) : 0.0);
          if (pts[k].broken) ss.back() = 0.0;
        }
      }
      xs.push_back(x_tip);
      ds.push_back(half_ ? 0.0 : tip_cod.Apply(u));
      ss.push_back(law && !half_ ? law->TractionWithHistory(ds.back(), pts.back().delta_max)
                                 : 0.0);
      for (std::size_t q = 0; q < opt_.contour_cells.size(); ++q) {
        const int k = opt_.contour_cells[q];
        const double J = ContourJ(u, x_tip, k);
        const int it = static_cast<int>(std::lround((x_tip - x0_) * inv_h_));
        const double face = detail::FaceWork(
            xs, [&](std::size_t e) { return ds[e]; }, [&](std::size_t e) { return ss[e]; },
            x0_ + (it - k) * h_);
        J_all[q] = J;
        Jtip_all[q] = J - face;
      }
      return Jtip_all[0];
    };
    // ---- load-point displacement with J_tip = J_tip,c (secant on sqrt J).
    auto residual = [&](double d, bool* ok) {
      *ok = solve_openings(d);
      const double Jt = tip_J(field(d));
      return std::sqrt(std::max(Jt, 0.0) / J_tip_c) - 1.0;
    };
    bool ok = true;
    double d1;
    if (!std::isfinite(d_prev)) {
      // Linear estimate with the openings frozen at zero.
      for (int q = 0; q < nb; ++q) sig[q] = 0.0;
      const double j1 = tip_J(field(1.0));
      d1 = j1 > 0.0 ? std::sqrt(J_tip_c / j1) : 1e-3;
    } else {
      d1 = d_prev;
    }
    double f1 = residual(d1, &ok);
    double d2 = d1 / (1.0 + f1), f2 = residual(d2, &ok);
    int iterations = 2;
    while (std::abs(f2) > 0.5 * opt_.tolerance && iterations < opt_.max_iterations) {
      const double slope = (f2 - f1) / (d2 - d1);
      double d3 = std::abs(slope) > 0.0 && std::isfinite(slope) ? d2 - f2 / slope : d2 / (1.0 + f2);
      if (!(d3 > 0.0)) d3 = 0.5 * d2;
      d1 = d2;
      f1 = f2;
      d2 = d3;
      f2 = residual(d2, &ok);
      ++iterations;
    }
    t_nonlinear_ += nonlinear.Seconds();
    if (std::abs(f2) > 0.5 * opt_.tolerance || !ok) {
      res.status = RunStatus::kNotConverged;
      res.message = fmt::format(
          "the load for J_tip = J_tip,c did not converge at a = {:.4g} mm ({} iterations, "
          "|sqrt(J_tip/J_tip,c) - 1| = {:.3g}{})",
          x_tip * 1e3, iterations, std::abs(f2), ok ? "" : ", bridging openings unconverged");
      break;
    }
    const double d = d2;
    d_prev = d;
    const Vec u = field(d);
    // ---- record this crack length
    SimulationPoint point;
    point.crack_length = x_tip;
    point.J_tip = Jtip_all[0];
    point.load = ReactionLoad(u, d);
    point.displacement = d;
    point.cmod = mouth.Apply(u);
    double delta_root = 0.0, root = a0_;
    if (law && !pts.empty()) {
      for (std::size_t k = 0; k < pts.size(); ++k) {
        BridgedPoint& b = pts[k];
        if (b.broken) continue;
        const double now = cod[k].Apply(u);
        b.delta = now;
        b.delta_max = std::max(b.delta_max, now);
        if (b.delta_max >= law->delta_c) b.broken = true;
      }
      // The notch root opening (zero while the root is still the tip).
      delta_root = pts.front().x < x_tip - 1e-9 * h_ ? pts.front().delta : 0.0;
      if (pts.front().broken) {
        std::size_t first = 0;
        while (first < pts.size() && pts[first].broken) ++first;
        const double d_broken = pts[first - 1].delta;
        const double d_next = first < pts.size() ? pts[first].delta : 0.0;
        const double x_next = first < pts.size() ? pts[first].x : x_tip;
        const double frac = d_broken > d_next ? std::clamp((d_broken - law->delta_c) /
                                                               (d_broken - d_next), 0.0, 1.0)
                                              : 0.0;
        root = pts[first - 1].x + frac * (x_next - pts[first - 1].x);
        delta_root = law->delta_c;
        if (!res.steady_state_reached) {
          res.steady_state_reached = true;
          res.steady_state_crack_length = x_tip;
        }
      }
    }
    point.delta_root = delta_root;
    point.root_position = root;
    point.bridging_zone_length = x_tip - root;
    point.R = law ? laws::ElasticZoneR(*law, delta_root, J_tip_c) : J_tip_c;
    point.J_ff = law ? laws::FarFieldJ(*law, delta_root, point.J_tip) : point.J_tip;
    res.points.push_back(point);
    out.J_contours.push_back(J_all);
    out.J_tip_contours.push_back(Jtip_all);
    progress.Update(static_cast<std::size_t>(step + 1));
    // ---- advance the tip
    const double next = x_tip + increment_;
    if (next > x_end_ + 1e-9 * h_) break;
    if (law) {
      if (half_) {
        for (double x = x_tip; x < next - 1e-9 * h_; x += h_) pts.push_back({.x = x});
      } else {
        pts.push_back({.x = next});
      }
    }
    x_tip = next;
  }
  progress.Finish();
  FillEnergyR(res.points, model_.thickness);
  if (!res.points.empty()) res.initiation_load = res.points.front().load;
  if (res.status == RunStatus::kOk)
    res.message = fmt::format("crack grown from {:.6g} to {:.6g} mm ({} model, {} points)",
                              a0_ * 1e3, res.points.empty() ? a0_ * 1e3
                                                            : res.points.back().crack_length * 1e3,
                              half_ ? "half" : "full", res.points.size());
  res.wall_s = watch.Seconds();
  out.stage_seconds = {{"assembly", t_assembly_},
                       {"factorization", t_factor_},
                       {"solves", t_solve_},
                       {"nonlinear_and_J", t_nonlinear_}};
  return out;
}

}  // namespace

GrowthResult SimulateGrowth(const Scene& scene, const laws::BridgingLaw* law, double J_tip_c,
                            const GrowthOptions& options) {
  StaticGrowth growth(scene, options);
  return growth.Run(law, J_tip_c);
}

}  // namespace bridgefit::mpm
