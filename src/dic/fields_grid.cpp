// Exported fields on a square lattice arranged as a grid (fields.hpp,
// ArrangeAsGrid): the J integral, the continuum test and the shadows of
// failed clusters read grid neighbours, which a scattered list has not.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Dense>

#include "bridgefit/dic/fields.hpp"

namespace bridgefit::dic {
namespace {

// The lattice of one axis: every value lo + k step (k integer, within a
// thousandth of a step); false where the values are not on one.
bool AxisLattice(const std::vector<double>& values, double* lo, double* step, int* count) {
  std::vector<double> s = values;
  std::sort(s.begin(), s.end());
  const double range = s.back() - s.front();
  if (!std::isfinite(range) || !(range > 0)) return false;
  const double tiny = 1e-9 * range;
  double gap = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k + 1 < s.size(); ++k)
    if (s[k + 1] - s[k] > tiny) gap = std::min(gap, s[k + 1] - s[k]);
  if (!std::isfinite(gap) || range / gap > 1e7) return false;
  for (double v : values) {
    const double k = (v - s.front()) / gap;
    if (std::abs(k - std::round(k)) > 1e-3) return false;
  }
  *lo = s.front();
  *step = gap;
  *count = static_cast<int>(std::lround(range / gap)) + 1;
  return true;
}

}  // namespace

bool ArrangeAsGrid(DisplacementField* f) {
  const size_t n = f->size();
  if (n < 9) return false;
  for (size_t i = 0; i < n; ++i)
    if (!std::isfinite(f->x[i]) || !std::isfinite(f->y[i])) return false;
  double x0, dx, y0, dy;
  int nx, ny;
  if (!AxisLattice(f->x, &x0, &dx, &nx) || !AxisLattice(f->y, &y0, &dy, &ny)) return false;
  if (std::abs(dx - dy) > 1e-3 * dx) return false;  // square lattices only (as the J integral)
  if (nx < 3 || ny < 3 || static_cast<double>(nx) * ny > 4.0 * static_cast<double>(n)) return false;
  const size_t cells = static_cast<size_t>(nx) * ny;
  std::vector<size_t> at(cells, n);
  for (size_t i = 0; i < n; ++i) {
    const size_t ix = static_cast<size_t>(std::lround((f->x[i] - x0) / dx));
    const size_t iy = static_cast<size_t>(std::lround((f->y[i] - y0) / dy));
    const size_t c = iy * nx + ix;
    if (at[c] != n) return false;  // a repeated node: not a grid
    at[c] = i;
  }
  DisplacementField g;
  g.nx = nx;
  g.ny = ny;
  for (size_t c = 0; c < cells; ++c) {
    const size_t i = at[c];
    const bool in_file = i != n;
    g.x.push_back(in_file ? f->x[i] : x0 + static_cast<double>(c % nx) * dx);
    g.y.push_back(in_file ? f->y[i] : y0 + static_cast<double>(c / nx) * dy);
    g.u.push_back(in_file ? f->u[i] : 0.0);
    g.v.push_back(in_file ? f->v[i] : 0.0);
    g.dudx.push_back(in_file ? f->dudx[i] : 0.0);
    g.dudy.push_back(in_file ? f->dudy[i] : 0.0);
    g.dvdx.push_back(in_file ? f->dvdx[i] : 0.0);
    g.dvdy.push_back(in_file ? f->dvdy[i] : 0.0);
    g.zncc.push_back(in_file ? f->zncc[i] : 0.0);
    g.iterations.push_back(in_file ? f->iterations[i] : 0);
    // A node the file does not hold: outside what the export covered.
    g.status.push_back(in_file ? f->status[i] : PointStatus::kMasked);
  }
  *f = std::move(g);
  return true;
}

FieldExtent ValidExtent(const DisplacementField& f) {
  FieldExtent e;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (!f.ok(i)) continue;
    e.x0 = std::min(e.x0, f.x[i]);
    e.x1 = std::max(e.x1, f.x[i]);
    e.y0 = std::min(e.y0, f.y[i]);
    e.y1 = std::max(e.y1, f.y[i]);
    ++e.valid;
  }
  return e;
}

double FieldSpacing(const DisplacementField& f) {
  const double nearest = PointSpacing(f);
  if (f.ny > 1 || !(nearest > 0)) return nearest;
  // The area the valid points cover: occupied cells of two nearest spacings.
  const double cell = 2 * nearest;
  const FieldExtent e = ValidExtent(f);
  std::vector<std::pair<long long, long long>> cells;
  cells.reserve(e.valid);
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (!f.ok(i)) continue;
    const double cx = std::floor((f.x[i] - e.x0) / cell), cy = std::floor((f.y[i] - e.y0) / cell);
    if (!(cx < 1e15 && cy < 1e15)) return nearest;  // a span no cell count holds
    cells.push_back({static_cast<long long>(cx), static_cast<long long>(cy)});
  }
  std::sort(cells.begin(), cells.end());
  const double occupied =
      static_cast<double>(std::unique(cells.begin(), cells.end()) - cells.begin());
  return std::max(nearest, std::sqrt(occupied * cell * cell / static_cast<double>(e.valid)));
}

DisplacementField ResampleOntoGrid(const DisplacementField& f, double spacing) {
  DisplacementField g;
  const auto [x0, x1, y0, y1, valid] = ValidExtent(f);
  if (valid < 9 || !(spacing > 0) || !std::isfinite(x1 - x0) || !std::isfinite(y1 - y0)) return g;
  const double cols = std::floor((x1 - x0) / spacing) + 1, rows = std::floor((y1 - y0) / spacing) + 1;
  if (cols < 3 || rows < 3 || cols * rows > 4.0 * static_cast<double>(valid)) return g;
  const int nx = static_cast<int>(cols), ny = static_cast<int>(rows);
  // Buckets of one spacing; a node reads the valid points within 1.5
  // spacings (5 x 5 buckets about its own).
  std::vector<std::vector<std::size_t>> bucket(static_cast<std::size_t>(nx) * ny);
  auto cell = [&](double v, double lo, int n) {  // clamped before the cast
    return static_cast<int>(std::clamp(std::floor((v - lo) / spacing + 0.5), 0.0, n - 1.0));
  };
  for (std::size_t i = 0; i < f.size(); ++i)
    if (f.ok(i))
      bucket[static_cast<std::size_t>(cell(f.y[i], y0, ny)) * nx + cell(f.x[i], x0, nx)].push_back(i);
  const double reach = 1.5 * spacing;
  g.nx = nx;
  g.ny = ny;
  const std::size_t n = bucket.size();
  for (auto* a : {&g.x, &g.y, &g.u, &g.v, &g.dudx, &g.dudy, &g.dvdx, &g.dvdy, &g.zncc})
    a->assign(n, 0.0);
  g.iterations.assign(n, 0);
  g.status.assign(n, PointStatus::kMasked);
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      const std::size_t c = static_cast<std::size_t>(iy) * nx + ix;
      const double X = x0 + ix * spacing, Y = y0 + iy * spacing;
      g.x[c] = X;
      g.y[c] = Y;
      // Weighted local plane u = a + b dx + c dy (and v) through the points
      // within reach, weights 1 - (d / reach)^2; the node must lie among
      // them (points on at least three sides), else it is not read.
      Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
      Eigen::Vector3d bu = Eigen::Vector3d::Zero(), bv = Eigen::Vector3d::Zero();
      int sides = 0, count = 0;
      for (int by = std::max(0, iy - 2); by <= std::min(ny - 1, iy + 2); ++by)
        for (int bx = std::max(0, ix - 2); bx <= std::min(nx - 1, ix + 2); ++bx)
          for (std::size_t i : bucket[static_cast<std::size_t>(by) * nx + bx]) {
            const double dx = f.x[i] - X, dy = f.y[i] - Y, d = std::hypot(dx, dy);
            if (d > reach) continue;
            const double w = 1 - (d / reach) * (d / reach);
            const Eigen::Vector3d row(1, dx / spacing, dy / spacing);
            M += w * row * row.transpose();
            bu += w * f.u[i] * row;
            bv += w * f.v[i] * row;
            sides |= (dx > 0.1 * spacing ? 1 : 0) | (dx < -0.1 * spacing ? 2 : 0) |
                     (dy > 0.1 * spacing ? 4 : 0) | (dy < -0.1 * spacing ? 8 : 0);
            ++count;
          }
      if (count < 4 || __builtin_popcount(sides) < 3) continue;
      const Eigen::LDLT<Eigen::Matrix3d> ldlt(M);
      if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-6)) continue;
      g.u[c] = ldlt.solve(bu)(0);
      g.v[c] = ldlt.solve(bv)(0);
      g.zncc[c] = 1;
      g.status[c] = PointStatus::kOk;
    }
  return g;
}

DisplacementField WithoutRigidRotation(const DisplacementField& field, double* theta) {
  *theta = 0;
  double n = 0, x0 = 0, y0 = 0, X0 = 0, Y0 = 0;
  for (std::size_t i = 0; i < field.size(); ++i) {
    if (!field.ok(i)) continue;
    n += 1;
    x0 += field.x[i];
    y0 += field.y[i];
    X0 += field.x[i] + field.u[i];
    Y0 += field.y[i] + field.v[i];
  }
  if (n < 3) return field;
  x0 /= n, y0 /= n, X0 /= n, Y0 /= n;
  double dot = 0, cross = 0;
  for (std::size_t i = 0; i < field.size(); ++i) {
    if (!field.ok(i)) continue;
    const double px = field.x[i] - x0, py = field.y[i] - y0;
    const double qx = field.x[i] + field.u[i] - X0, qy = field.y[i] + field.v[i] - Y0;
    dot += px * qx + py * qy;
    cross += px * qy - py * qx;
  }
  const double t = std::atan2(cross, dot);
  if (!std::isfinite(t) || 1.0 - std::cos(t) < 1e-7) return field;
  *theta = t;
  const double c = std::cos(t), s = std::sin(t);
  DisplacementField f = field;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (!f.ok(i)) continue;
    const double qx = f.x[i] + f.u[i] - X0, qy = f.y[i] + f.v[i] - Y0;
    f.u[i] = X0 + c * qx + s * qy - f.x[i];
    f.v[i] = Y0 - s * qx + c * qy - f.y[i];
  }
  return f;
}

}  // namespace bridgefit::dic
