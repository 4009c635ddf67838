// Finite-element crack-plane model (see crack_plane.hpp): mesh, QM6 element
// stiffness, assembly and static condensation onto the crack-plane openings.

#include "bridgefit/specimen/crack_plane.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/specimen/calibrations.hpp"

namespace bridgefit::specimen {
namespace {

using Matrix3 = Eigen::Matrix3d;
using Matrix8 = Eigen::Matrix<double, 8, 8>;

enum class LoadKind { kPin, kEnd, kFacePressure };

// The upper half of a specimen: [x0, x1] x [0, y1], crack faces free on
// x0 <= x < a0 - h/2, retained nodes a0 - h ... a_last, ligament beyond.
struct Domain {
  double x0 = 0, x1 = 0, y1 = 0;
  bool hole = false;
  double hole_xc = 0, hole_yc = 0, hole_r = 0;
  LoadKind load = LoadKind::kPin;
  double notch = 0, h = 0, a_last = 0;
  double coarse = 0;          // largest element size [m]
  double grading = 1.15;
  int uniform_y_cells = 0;    // > 0: uniform cells through the height (DCB arm)
};

// Steps growing by `ratio` from h0 (capped at hmax) that add up to `length`.
std::vector<double> GradedSteps(double length, double h0, double ratio, double hmax) {
  std::vector<double> steps;
  if (length <= 1e-12 * std::max(1.0, h0)) return steps;
  double total = 0.0, step = h0;
  while (total < length * (1.0 - 1e-9)) {
    step = std::min(step * ratio, hmax);
    steps.push_back(step);
    total += step;
  }
  // Shrink (never stretch by more than one step) so the steps end at `length`.
  if (steps.size() > 1 && total - length > 0.5 * steps.back()) {
    total -= steps.back();
    steps.pop_back();
  }
  for (double& s : steps) s *= length / total;
  return steps;
}

// Plane elasticity matrix D (stress = D strain, engineering shear).
Matrix3 ElasticityMatrix(const MaterialSpec& m, PlaneCondition plane) {
  double a11, a22, a12, a66, a33, a13, a23;
  if (m.orthotropic) {
    a11 = 1.0 / m.E1; a22 = 1.0 / m.E2; a12 = -m.nu12 / m.E1; a66 = 1.0 / m.G12;
    // Out-of-plane constants (plane strain only): E3 = E2, nu13 = nu23 = nu12.
    a33 = 1.0 / m.E2; a13 = -m.nu12 / m.E1; a23 = -m.nu12 / m.E2;
  } else {
    a11 = a22 = a33 = 1.0 / m.E; a12 = a13 = a23 = -m.nu / m.E;
    a66 = 2.0 * (1.0 + m.nu) / m.E;
  }
  if (plane == PlaneCondition::kPlaneStrain) {
    a11 -= a13 * a13 / a33;
    a22 -= a23 * a23 / a33;
    a12 -= a13 * a23 / a33;
  }
  Matrix3 compliance;
  compliance << a11, a12, 0, a12, a22, 0, 0, 0, a66;
  return compliance.inverse();
}

// QM6 (Wilson-Taylor incompatible modes) stiffness of an axis-aligned
// rectangle dx x dy, unit thickness; node order (-1,-1),(1,-1),(1,1),(-1,1),
// dofs (ux, uy) per node. The 4 internal modes (1-xi^2, 1-eta^2 for u and v)
// are condensed out.
Matrix8 RectangleStiffness(double dx, double dy, const Matrix3& D) {
  using Matrix12 = Eigen::Matrix<double, 12, 12>;
  Matrix12 k = Matrix12::Zero();
  const double xi_n[4] = {-1, 1, 1, -1};
  const double eta_n[4] = {-1, -1, 1, 1};
  const double g = 1.0 / std::sqrt(3.0);
  const double jx = 2.0 / dx, jy = 2.0 / dy;  // d(xi)/dx, d(eta)/dy
  for (int gi = 0; gi < 4; ++gi) {
    const double xi = (gi == 0 || gi == 3) ? -g : g;
    const double eta = (gi < 2) ? -g : g;
    Eigen::Matrix<double, 3, 12> B = Eigen::Matrix<double, 3, 12>::Zero();
    for (int n = 0; n < 4; ++n) {
      const double dndx = 0.25 * xi_n[n] * (1 + eta * eta_n[n]) * jx;
      const double dndy = 0.25 * eta_n[n] * (1 + xi * xi_n[n]) * jy;
      B(0, 2 * n) = dndx;
      B(1, 2 * n + 1) = dndy;
      B(2, 2 * n) = dndy;
      B(2, 2 * n + 1) = dndx;
    }
    // Incompatible modes P1 = 1 - xi^2, P2 = 1 - eta^2 (dofs 8,9: u; 10,11: v).
    const double dp1dx = -2.0 * xi * jx, dp2dy = -2.0 * eta * jy;
    // d(P1)/dy = d(P2)/dx = 0.
    B(0, 8) = dp1dx;
    B(2, 9) = dp2dy;
    B(1, 11) = dp2dy;
    B(2, 10) = dp1dx;
    k += B.transpose() * D * B * (0.25 * dx * dy);
  }
  const Eigen::Matrix<double, 8, 4> kci = k.block<8, 4>(0, 8);
  const Eigen::Matrix4d kii = k.block<4, 4>(8, 8);
  return k.block<8, 8>(0, 0) - kci * kii.ldlt().solve(kci.transpose());
}

struct DofMap {
  enum Kind : int { kInterior = 0, kRetained = 1, kFixed = 2 };
  std::vector<int> kind;   // per global dof
  std::vector<int> index;  // index within its kind
};

// The grid of a domain: graded lines, the retained crack-plane nodes.
struct Grid {
  std::vector<double> xs, ys;
  int nx = 0, ny = 0;
  int first_retained_ix = 0;  // grid column of the notch node
  int n_retained = 0;         // notch node + a0 .. a_last
  int Node(int ix, int iy) const { return iy * (nx + 1) + ix; }
};

// Elements of the grid, the CT pin hole immersed: an element keeps the
// fraction of its area outside the hole as a stiffness factor.
struct Elements {
  std::vector<double> solid;  // per element, 0..1
  std::vector<char> active;   // per node: touched by an element
  int count = 0;
};

// The stiffness blocks (interior i, retained r) and the unit load pattern.
struct Blocks {
  Eigen::SparseMatrix<double> k_ii, k_ir;
  Eigen::MatrixXd k_rr;
  Eigen::VectorXd w_i, w_r;
};

// Grid lines: h-spaced through the retained zone (3 fine cells either side),
// graded outwards to the domain's edges; a line on the load line x = 0.
Grid GridLines(const Domain& d) {
  const double h = d.h;
  const int left_fine = std::min(3, static_cast<int>(std::floor((d.notch - d.x0) / h + 1e-9)));
  const int right_fine = std::min(3, static_cast<int>(std::floor((d.x1 - d.a_last) / h + 1e-9)));
  const int retained_steps = static_cast<int>(std::lround((d.a_last - d.notch) / h));
  Grid g;
  std::vector<double>& xs = g.xs;
  {
    const double xf0 = d.notch - left_fine * h;
    // Leftward from xf0, with a grid line on the load line x = 0 when it is
    // inside (the CT load-line gauge point).
    std::vector<double> rev{xf0};
    double x = xf0, last = h;
    const double stops[2] = {d.x0 < 0.0 && xf0 > 0.0 ? 0.0 : d.x0, d.x0};
    for (double stop : stops) {
      if (x <= stop) continue;
      auto steps = GradedSteps(x - stop, last, d.grading, d.coarse);
      for (double st : steps) rev.push_back(x -= st);
      rev.back() = x = stop;
      if (!steps.empty()) last = steps.back();
    }
    xs.assign(rev.rbegin(), rev.rend());
    for (int i = 1; i <= left_fine + retained_steps + right_fine; ++i) xs.push_back(xf0 + i * h);
    const double xf1 = xs.back();
    auto right = GradedSteps(d.x1 - xf1, h, d.grading, d.coarse);
    x = xf1;
    for (double s : right) xs.push_back(x += s);
    if (!right.empty()) xs.back() = d.x1;
  }
  std::vector<double>& ys = g.ys;
  ys.push_back(0.0);
  if (d.uniform_y_cells > 0) {
    for (int j = 1; j <= d.uniform_y_cells; ++j) ys.push_back(d.y1 * j / d.uniform_y_cells);
  } else {
    double y = 0.0;
    for (double s : GradedSteps(d.y1, h / d.grading, d.grading, d.coarse)) ys.push_back(y += s);
    ys.back() = d.y1;
  }
  g.nx = static_cast<int>(xs.size()) - 1;
  g.ny = static_cast<int>(ys.size()) - 1;
  g.first_retained_ix = static_cast<int>(std::lround(
      std::distance(xs.begin(), std::lower_bound(xs.begin(), xs.end(), d.notch - h - 0.5 * h))));
  g.n_retained = retained_steps + 2;  // notch node + a0 .. a_last
  return g;
}

// The CT pin hole is immersed in the grid, not cut out along element
// edges: an element keeps the fraction of its area outside the hole
// (sampled on 8 x 8 points) as a stiffness factor. A staircase of whole
// elements would change the hole's area, and with it the compliance, by
// up to 2% as the graded grid shifts with h.
Elements ImmerseHole(const Domain& d, const Grid& g) {
  const std::vector<double>& xs = g.xs;
  const std::vector<double>& ys = g.ys;
  const int nx = g.nx, ny = g.ny;
  Elements e;
  e.solid.assign(static_cast<size_t>(nx) * ny, 1.0);
  e.active.assign(static_cast<size_t>(nx + 1) * (ny + 1), 0);
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      // Elements clear of the circle (nearest point farther than r) are solid.
      auto meets_hole = [&] {
        const double gap_x = std::max({xs[ix] - d.hole_xc, 0.0, d.hole_xc - xs[ix + 1]});
        const double gap_y = std::max({ys[iy] - d.hole_yc, 0.0, d.hole_yc - ys[iy + 1]});
        return std::hypot(gap_x, gap_y) < d.hole_r;
      };
      if (d.hole && meets_hole()) {
        constexpr int kSamples = 8;
        int outside = 0;
        for (int sy = 0; sy < kSamples; ++sy)
          for (int sx = 0; sx < kSamples; ++sx) {
            const double x = xs[ix] + (sx + 0.5) / kSamples * (xs[ix + 1] - xs[ix]);
            const double y = ys[iy] + (sy + 0.5) / kSamples * (ys[iy + 1] - ys[iy]);
            outside += std::hypot(x - d.hole_xc, y - d.hole_yc) >= d.hole_r;
          }
        e.solid[iy * nx + ix] = double(outside) / (kSamples * kSamples);
        if (outside == 0) continue;
      }
      ++e.count;
      e.active[g.Node(ix, iy)] = e.active[g.Node(ix + 1, iy)] = 1;
      e.active[g.Node(ix + 1, iy + 1)] = e.active[g.Node(ix, iy + 1)] = 1;
    }
  return e;
}

// Dof classes: u_x free but for one node (rigid translation); u_y on the
// crack plane retained over the zone, fixed on the ligament (symmetry).
DofMap ClassifyDofs(const Grid& g, const Elements& e, int& n_interior) {
  const int n_nodes = (g.nx + 1) * (g.ny + 1);
  DofMap map;
  map.kind.assign(2 * n_nodes, DofMap::kFixed);
  map.index.assign(2 * n_nodes, -1);
  n_interior = 0;
  for (int iy = 0; iy <= g.ny; ++iy)
    for (int ix = 0; ix <= g.nx; ++ix) {
      const int nd = g.Node(ix, iy);
      if (!e.active[nd]) continue;
      // u_x: free, except one node fixing the rigid translation.
      if (!(iy == 0 && ix == g.nx)) {
        map.kind[2 * nd] = DofMap::kInterior;
        map.index[2 * nd] = n_interior++;
      }
      if (iy == 0) {
        const int r = ix - g.first_retained_ix;
        if (r >= 0 && r < g.n_retained) {
          map.kind[2 * nd + 1] = DofMap::kRetained;
          map.index[2 * nd + 1] = r;
          continue;
        }
        if (r >= g.n_retained) continue;  // ligament: u_y = 0 (symmetry)
      }
      map.kind[2 * nd + 1] = DofMap::kInterior;
      map.index[2 * nd + 1] = n_interior++;
    }
  return map;
}

// The load pattern (unit load per unit thickness) on the interior and
// retained dofs: pin bearing, end load or notch-face pressure.
void AddLoadPattern(const Domain& d, const Grid& g, const DofMap& map, Blocks& b) {
  const std::vector<double>& xs = g.xs;
  const std::vector<double>& ys = g.ys;
  const int ny = g.ny;
  auto node = [&](int ix, int iy) { return g.Node(ix, iy); };
  Eigen::VectorXd& w_i = b.w_i;
  Eigen::VectorXd& w_r = b.w_r;
  auto add_load = [&](int nd, double value) {
    const int dof = 2 * nd + 1;
    if (map.kind[dof] == DofMap::kInterior) w_i[map.index[dof]] += value;
    if (map.kind[dof] == DofMap::kRetained) w_r[map.index[dof]] += value;
  };
  if (d.load == LoadKind::kPin) {
    // Pin bearing on the upper half of the hole's circle: a vertical push
    // with density proportional to the cosine from the vertical (sin theta),
    // integrated along the arc (midpoint rule) and shared out to the nodes
    // of the element each arc point lies in by the bilinear shape functions,
    // so the load, like the hole, does not depend on where grid lines fall.
    constexpr int kArcPoints = 720;
    auto cell = [](const std::vector<double>& grid, double v) {
      const auto it = std::upper_bound(grid.begin(), grid.end(), v);
      return std::clamp(static_cast<int>(std::distance(grid.begin(), it)) - 1, 0,
                        static_cast<int>(grid.size()) - 2);
    };
    double total = 0.0;
    for (int k = 0; k < kArcPoints; ++k) total += std::sin(std::numbers::pi * (k + 0.5) / kArcPoints);
    for (int k = 0; k < kArcPoints; ++k) {
      const double theta = std::numbers::pi * (k + 0.5) / kArcPoints;
      const double x = d.hole_xc + d.hole_r * std::cos(theta);
      const double y = d.hole_yc + d.hole_r * std::sin(theta);
      const int ix = cell(xs, x), iy = cell(ys, y);
      const double sx = (x - xs[ix]) / (xs[ix + 1] - xs[ix]);
      const double sy = (y - ys[iy]) / (ys[iy + 1] - ys[iy]);
      const double f = std::sin(theta) / total;
      add_load(node(ix, iy), f * (1 - sx) * (1 - sy));
      add_load(node(ix + 1, iy), f * sx * (1 - sy));
      add_load(node(ix + 1, iy + 1), f * sx * sy);
      add_load(node(ix, iy + 1), f * (1 - sx) * sy);
    }
  } else if (d.load == LoadKind::kEnd) {
    for (int iy = 0; iy <= ny; ++iy) {
      const double below = iy > 0 ? ys[iy] - ys[iy - 1] : 0.0;
      const double above = iy < ny ? ys[iy + 1] - ys[iy] : 0.0;
      add_load(node(0, iy), 0.5 * (below + above) / d.y1);
    }
  } else {
    // Unit pressure on the notch faces x0 .. a0 - h (the retained part is the
    // caller's traction).
    const double end = xs[g.first_retained_ix];
    for (int ix = 0; ix <= g.first_retained_ix; ++ix) {
      const double left = ix > 0 ? xs[ix] - xs[ix - 1] : 0.0;
      const double right = xs[ix] < end - 1e-12 ? xs[ix + 1] - xs[ix] : 0.0;
      add_load(node(ix, 0), 0.5 * (left + right));
    }
  }
}

// QM6 element stiffnesses (one per element size) into the K_ii, K_iR and
// K_RR blocks.
void Assemble(const Grid& g, const Elements& e, const DofMap& map, const Matrix3& D, int n_interior,
              Blocks& b) {
  const std::vector<double>& xs = g.xs;
  const std::vector<double>& ys = g.ys;
  const int nx = g.nx, ny = g.ny, n_retained = g.n_retained;
  auto node = [&](int ix, int iy) { return g.Node(ix, iy); };
  std::map<std::pair<double, double>, Matrix8> cache;
  std::vector<Eigen::Triplet<double>> t_ii, t_ir;
  Eigen::MatrixXd& k_rr = b.k_rr;
  k_rr = Eigen::MatrixXd::Zero(n_retained, n_retained);
  t_ii.reserve(static_cast<size_t>(e.count) * 50);
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      const double fraction = e.solid[iy * nx + ix];
      if (fraction == 0.0) continue;
      const std::pair<double, double> size{xs[ix + 1] - xs[ix], ys[iy + 1] - ys[iy]};
      auto it = cache.find(size);
      if (it == cache.end())
        it = cache.emplace(size, RectangleStiffness(size.first, size.second, D)).first;
      const Matrix8 ke = fraction * it->second;
      const int nodes[4] = {node(ix, iy), node(ix + 1, iy), node(ix + 1, iy + 1),
                            node(ix, iy + 1)};
      int dofs[8];
      for (int n = 0; n < 4; ++n) dofs[2 * n] = 2 * nodes[n], dofs[2 * n + 1] = 2 * nodes[n] + 1;
      for (int a = 0; a < 8; ++a) {
        const int ka = map.kind[dofs[a]], ia = map.index[dofs[a]];
        if (ka == DofMap::kFixed) continue;
        for (int bb = 0; bb < 8; ++bb) {
          const int kb = map.kind[dofs[bb]], ib = map.index[dofs[bb]];
          if (kb == DofMap::kFixed) continue;
          if (ka == DofMap::kInterior && kb == DofMap::kInterior)
            t_ii.emplace_back(ia, ib, ke(a, bb));
          else if (ka == DofMap::kInterior && kb == DofMap::kRetained)
            t_ir.emplace_back(ia, ib, ke(a, bb));
          else if (ka == DofMap::kRetained && kb == DofMap::kRetained)
            k_rr(ia, ib) += ke(a, bb);
        }
      }
    }
  b.k_ii.resize(n_interior, n_interior);
  b.k_ir.resize(n_interior, n_retained);
  b.k_ii.setFromTriplets(t_ii.begin(), t_ii.end());
  b.k_ir.setFromTriplets(t_ir.begin(), t_ir.end());
}

// Static condensation onto the retained openings, S = K_RR - K_Ri K_ii^-1
// K_iR, with the load's condensed pattern and the compliances and couplings
// of the load line, the mouth and the gauge point.
void Condense(const Domain& d, const Grid& g, const DofMap& map, const Blocks& blocks,
              const std::string& key, CrackPlaneModel& model) {
  const std::vector<double>& xs = g.xs;
  const int n_retained = g.n_retained;
  const int n_interior = static_cast<int>(blocks.k_ii.rows());
  auto node = [&](int ix, int iy) { return g.Node(ix, iy); };
  const Eigen::SparseMatrix<double>& k_ii = blocks.k_ii;
  const Eigen::SparseMatrix<double>& k_ir = blocks.k_ir;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(k_ii);
  if (solver.info() != Eigen::Success)
    throw Error(ErrorKind::kRuntime, "the finite-element stiffness matrix is singular",
                {.field = "mesh", .value = key});
  // K_ii = P^T L D L^T P, Z = D^-1/2 L^-1 P K_iR (forward halves only, which
  // skip the sparse columns' zeros): K_Ri K_ii^-1 K_iR = Z^T Z (docs/REDUCED.md).
  const Eigen::MatrixXd PK = solver.permutationP() * Eigen::MatrixXd(k_ir);
  Eigen::MatrixXd Z(n_interior, n_retained);
  const Eigen::VectorXd d_inv_sqrt = solver.vectorD().cwiseSqrt().cwiseInverse();
#pragma omp parallel for schedule(dynamic, 4)
  for (int c = 0; c < n_retained; ++c) {
    Eigen::VectorXd z = PK.col(c);
    solver.matrixL().solveInPlace(z);
    Z.col(c) = d_inv_sqrt.cwiseProduct(z);
  }
  const Eigen::VectorXd Y = solver.solve(blocks.w_i);  // the load's column: a full solve

  model.node_x.resize(n_retained);
  for (int r = 0; r < n_retained; ++r) model.node_x[r] = d.notch + (r - 1) * d.h;
  Eigen::MatrixXd S = blocks.k_rr;
  S.selfadjointView<Eigen::Lower>().rankUpdate(Z.transpose(), -1.0);
  const Eigen::MatrixXd S_sym = S.selfadjointView<Eigen::Lower>();
  model.stiffness.assign(S_sym.data(), S_sym.data() + S_sym.size());
  const Eigen::VectorXd load = blocks.w_r - k_ir.transpose() * Y;
  model.load.assign(load.data(), load.data() + load.size());
  model.load_compliance = blocks.w_i.dot(Y);
  model.load_coupling = model.load;  // q = w_R - X^T w_i = g (Maxwell-Betti)
  auto row_of_x = [&](int j) -> Eigen::VectorXd {  // row j of K_ii^-1 K_iR (K_ii symmetric)
    return k_ir.transpose() * solver.solve(Eigen::VectorXd::Unit(n_interior, j));
  };
  const int mouth_dof = map.index[2 * node(0, 0) + 1];
  BF_DEBUG_ASSERT(map.kind[2 * node(0, 0) + 1] == DofMap::kInterior);
  model.mouth_compliance = Y[mouth_dof];
  const Eigen::VectorXd mouth_x = row_of_x(mouth_dof);
  model.mouth_coupling.resize(n_retained);
  for (int r = 0; r < n_retained; ++r) model.mouth_coupling[r] = -mouth_x[r];
  const int gauge_ix = static_cast<int>(
      std::distance(xs.begin(), std::min_element(xs.begin(), xs.end(), [](double a, double b) {
                      return std::abs(a) < std::abs(b);
                    })));
  const int gauge_dof = map.index[2 * node(gauge_ix, 0) + 1];
  model.gauge_x = xs[gauge_ix];
  model.gauge_compliance = Y[gauge_dof];
  const Eigen::VectorXd gauge_x = row_of_x(gauge_dof);
  model.gauge_coupling.resize(n_retained);
  for (int r = 0; r < n_retained; ++r) model.gauge_coupling[r] = -gauge_x[r];
}

// The crack-plane model of a domain, in named stages: grid, immersed hole,
// dof classes, load pattern, assembly, static condensation.
CrackPlaneModel Build(const Domain& d, const MaterialSpec& material, PlaneCondition plane,
                      double thickness, const std::string& key) {
  Stopwatch watch;
  const Grid grid = GridLines(d);
  const Elements elements = ImmerseHole(d, grid);
  int n_interior = 0;
  const DofMap map = ClassifyDofs(grid, elements, n_interior);
  Blocks blocks;
  blocks.w_i = Eigen::VectorXd::Zero(n_interior);
  blocks.w_r = Eigen::VectorXd::Zero(grid.n_retained);
  AddLoadPattern(d, grid, map, blocks);
  Assemble(grid, elements, map, ElasticityMatrix(material, plane), n_interior, blocks);

  CrackPlaneModel model;
  model.key = key;
  model.load_kind = d.load == LoadKind::kPin ? "pin" : d.load == LoadKind::kEnd ? "end"
                                                                                : "face-pressure";
  model.resolution = d.h;
  model.notch = d.notch;
  model.thickness = thickness;
  model.effective_modulus = EffectiveModulus(material, plane);
  Condense(d, grid, map, blocks, key, model);
  model.elements = elements.count;
  model.dofs = n_interior + grid.n_retained;
  model.build_s = watch.Seconds();
  return model;
}

std::string MaterialKey(const MaterialSpec& m, PlaneCondition plane) {
  const char* p = plane == PlaneCondition::kPlaneStress ? "stress" : "strain";
  if (m.orthotropic)
    return fmt::format("ortho E1={:.6g} E2={:.6g} G12={:.6g} nu12={:.6g} plane-{}", m.E1, m.E2,
                       m.G12, m.nu12, p);
  return fmt::format("iso E={:.6g} nu={:.6g} plane-{}", m.E, m.nu, p);
}

void CheckMaterial(const MaterialSpec& m) {
  if (m.orthotropic && m.angle != 0.0)
    throw Error(ErrorKind::kInput,
                "the reduced model needs material axis 1 along the crack (mode I symmetry)",
                {.field = "material.angle", .value = fmt::format("{:g} rad", m.angle),
                 .expected = "0"});
}

}  // namespace

bool CrackPlaneOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* text) {
    if (why) *why = text;
    return false;
  };
  if (!(resolution >= 0.0)) return fail("resolution must be >= 0 (0: default)");
  if (!(max_crack_length >= 0.0)) return fail("max_crack_length must be >= 0 (0: default)");
  if (!(grading >= 1.0 && grading <= 2.0)) return fail("grading must lie in [1, 2]");
  if (!(coarse_factor > 0.0)) return fail("coarse_factor must be positive");
  return true;
}

double DefaultResolution(const SpecimenSpec& s) {
  if (s.type == SpecimenType::kCT) return s.width / 200.0;
  return std::min(s.height / 4.0, s.length / 400.0);
}

double DefaultMaxCrackLength(const Scene& scene) {
  if (scene.run.max_crack_length) return *scene.run.max_crack_length;
  const SpecimenSpec& s = scene.specimen;
  if (s.type == SpecimenType::kCT) return 0.8 * s.width;
  return std::max(s.length - 10.0 * s.height, 0.5 * (s.notch + s.length));
}

CrackPlaneModel BuildCrackPlaneModel(const Scene& scene, const CrackPlaneOptions& options) {
  scene.Validate();
  std::string why;
  if (!options.IsValid(&why))
    throw Error(ErrorKind::kUsage, "invalid crack-plane model options: " + why);
  CheckMaterial(scene.material);
  const SpecimenSpec& s = scene.specimen;
  const double h = options.resolution > 0.0 ? options.resolution : DefaultResolution(s);
  const double a_max =
      options.max_crack_length > 0.0 ? options.max_crack_length : DefaultMaxCrackLength(scene);
  Domain d;
  d.h = h;
  d.notch = s.notch;
  d.grading = options.grading;
  if (s.type == SpecimenType::kCT) {
    const double alpha = s.notch / s.width;
    if (!(alpha >= kCtMinRelativeCrack && alpha <= kCtMaxRelativeCrack))
      throw Error(ErrorKind::kInput, "the CT notch is outside the valid range of a/W",
                  {.file = scene.source, .field = "specimen.notch",
                   .value = fmt::format("a0/W = {:g}", alpha),
                   .expected = fmt::format("{} <= a0/W <= {}", kCtMinRelativeCrack,
                                           kCtMaxRelativeCrack)});
    if (!(a_max <= kCtMaxRelativeCrack * s.width && a_max > s.notch))
      throw Error(ErrorKind::kInput, "the largest crack length is outside the valid CT range",
                  {.file = scene.source, .field = "run.max_crack_length",
                   .value = fmt::format("{:g} mm", a_max * 1e3),
                   .expected = fmt::format("a0 < a <= {} W = {:g} mm", kCtMaxRelativeCrack,
                                           kCtMaxRelativeCrack * s.width * 1e3)});
    d.x0 = -0.25 * s.width;
    d.x1 = s.width;
    d.y1 = 0.5 * s.height;
    d.hole = true;
    d.hole_xc = 0.0;
    d.hole_yc = 0.275 * s.width;
    d.hole_r = 0.125 * s.width;
    d.load = LoadKind::kPin;
    d.coarse = options.coarse_factor * s.width / 40.0;
    BF_CHECK_INPUT(d.hole_yc + d.hole_r < d.y1, "the CT specimen is too low for its pin holes",
                   {.file = scene.source, .field = "specimen.height",
                    .value = fmt::format("{:g} mm", s.height * 1e3),
                    .expected = fmt::format("> {:g} mm", 2e3 * (d.hole_yc + d.hole_r))});
  } else {
    d.x0 = 0.0;
    d.x1 = s.length;
    d.y1 = s.height;
    d.load = LoadKind::kEnd;
    d.uniform_y_cells = std::max(4, static_cast<int>(std::lround(s.height / h)));
    d.coarse = options.coarse_factor * s.height;
    if (!(a_max > s.notch && a_max <= s.length - 2.0 * h))
      throw Error(ErrorKind::kInput, "the largest crack length is outside the DCB",
                  {.file = scene.source, .field = "run.max_crack_length",
                   .value = fmt::format("{:g} mm", a_max * 1e3),
                   .expected = fmt::format("a0 < a <= L - 2 h = {:g} mm",
                                           (s.length - 2 * h) * 1e3)});
    BF_CHECK_INPUT(s.notch >= 2.0 * h, "the DCB notch must be at least two elements long",
                   {.file = scene.source, .field = "specimen.notch",
                    .value = fmt::format("{:g} mm", s.notch * 1e3),
                    .expected = fmt::format(">= {:g} mm (2 x resolution)", 2e3 * h)});
  }
  const int steps = static_cast<int>(std::floor((a_max - s.notch) / h + 1e-9));
  BF_CHECK_INPUT(steps >= 2, "the resolution is too coarse for the crack growth range",
                 {.field = "resolution", .value = fmt::format("{:g} mm", h * 1e3),
                  .expected = fmt::format("<= {:g} mm", 0.5e3 * (a_max - s.notch))});
  d.a_last = s.notch + steps * h;
  const std::string key = fmt::format(
      "{} W={:.6g} H={:.6g} L={:.6g} a0={:.6g} alast={:.6g} h={:.6g} grading={:.4g} "
      "coarse={:.4g} {}",
      s.type == SpecimenType::kCT ? "CT" : "DCB", s.width, s.height, s.length, s.notch, d.a_last,
      h, d.grading, d.coarse, MaterialKey(scene.material, s.plane));
  return Build(d, scene.material, s.plane, s.CrackFrontWidth(), key);
}

CrackPlaneModel BuildEdgeCrackStripModel(const EdgeCrackStrip& strip, const MaterialSpec& material,
                                         PlaneCondition plane, const CrackPlaneOptions& options) {
  std::string why;
  if (!options.IsValid(&why))
    throw Error(ErrorKind::kUsage, "invalid crack-plane model options: " + why);
  CheckMaterial(material);
  BF_CHECK_INPUT(strip.width > 0 && strip.half_height > 0 && strip.notch > 0 &&
                     strip.max_crack_length > strip.notch && strip.max_crack_length < strip.width,
                 "invalid edge-crack strip", {.field = "strip"});
  Domain d;
  d.h = options.resolution > 0.0 ? options.resolution : strip.width / 200.0;
  d.notch = strip.notch;
  d.grading = options.grading;
  d.x0 = 0.0;
  d.x1 = strip.width;
  d.y1 = strip.half_height;
  d.load = LoadKind::kFacePressure;
  d.coarse = options.coarse_factor * strip.width / 20.0;
  const int steps = static_cast<int>(std::floor((strip.max_crack_length - strip.notch) / d.h + 1e-9));
  d.a_last = strip.notch + steps * d.h;
  const std::string key =
      fmt::format("strip b={:.6g} H={:.6g} a0={:.6g} alast={:.6g} h={:.6g} {}", strip.width,
                  strip.half_height, strip.notch, d.a_last, d.h, MaterialKey(material, plane));
  return Build(d, material, plane, 1.0, key);
}

}  // namespace bridgefit::specimen
