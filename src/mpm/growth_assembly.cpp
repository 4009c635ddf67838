// StaticGrowth: assembly, masks, factorization and field evaluations (growth_impl.hpp).
#include "growth_impl.hpp"

namespace bridgefit::mpm::growth_internal {

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

}  // namespace bridgefit::mpm::growth_internal
