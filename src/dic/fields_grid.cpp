// Exported fields on a square lattice arranged as a grid (fields.hpp,
// ArrangeAsGrid): the J integral, the continuum test and the shadows of
// failed clusters read grid neighbours, which a scattered list has not.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

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

}  // namespace bridgefit::dic
