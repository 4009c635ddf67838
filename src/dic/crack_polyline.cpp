// The crack path as a polyline where one straight line fits badly
// (include/bridgefit/dic/crack_path.hpp).
#include <algorithm>
#include <cmath>

#include "bridgefit/dic/crack_path.hpp"

namespace bridgefit::dic {
namespace {

struct Line2 {  // point (px, py) and unit direction (dx, dy)
  double px = 0, py = 0, dx = 1, dy = 0;
};

// Total least squares line through points [a, b).
Line2 FitRun(const std::vector<double>& x, const std::vector<double>& y, size_t a, size_t b) {
  Line2 l;
  const double n = static_cast<double>(b - a);
  for (size_t i = a; i < b; ++i) {
    l.px += x[i] / n;
    l.py += y[i] / n;
  }
  double sxx = 0, syy = 0, sxy = 0;
  for (size_t i = a; i < b; ++i) {
    sxx += (x[i] - l.px) * (x[i] - l.px);
    syy += (y[i] - l.py) * (y[i] - l.py);
    sxy += (x[i] - l.px) * (y[i] - l.py);
  }
  const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
  l.dx = std::cos(angle);
  l.dy = std::sin(angle);
  // Point the direction from the run's first point to its last.
  if ((x[b - 1] - x[a]) * l.dx + (y[b - 1] - y[a]) * l.dy < 0) {
    l.dx = -l.dx;
    l.dy = -l.dy;
  }
  return l;
}

double ChordDistance(double x, double y, double x0, double y0, double x1, double y1) {
  const double L = std::hypot(x1 - x0, y1 - y0);
  if (L <= 0) return std::hypot(x - x0, y - y0);
  return std::abs((x - x0) * (y1 - y0) - (y - y0) * (x1 - x0)) / L;
}

// Run boundaries [a, b) split where the chord misses a point by > tol.
void Split(const std::vector<double>& x, const std::vector<double>& y, size_t a, size_t b, double tol,
           size_t min_points, std::vector<size_t>* cuts) {
  if (b - a < 2 * min_points) return;
  double worst = 0;
  size_t at = a;
  for (size_t i = a + min_points; i + min_points <= b; ++i) {
    const double d = ChordDistance(x[i], y[i], x[a], y[a], x[b - 1], y[b - 1]);
    if (d > worst) {
      worst = d;
      at = i;
    }
  }
  if (worst <= tol) return;
  Split(x, y, a, at, tol, min_points, cuts);
  cuts->push_back(at);
  Split(x, y, at, b, tol, min_points, cuts);
}

double SegmentDistance(double x, double y, double x0, double y0, double x1, double y1) {
  const double ex = x1 - x0, ey = y1 - y0, L2 = ex * ex + ey * ey;
  const double t = L2 > 0 ? std::clamp(((x - x0) * ex + (y - y0) * ey) / L2, 0.0, 1.0) : 0.0;
  return std::hypot(x - x0 - t * ex, y - y0 - t * ey);
}

}  // namespace

void FitCrackPolyline(const std::vector<double>& x, const std::vector<double>& y, double tolerance,
                      int min_points, std::vector<double>* vx, std::vector<double>* vy, double* rms) {
  vx->clear();
  vy->clear();
  *rms = 0;
  const size_t n = x.size();
  if (n < 2) return;
  const size_t m = static_cast<size_t>(std::max(2, min_points));
  std::vector<size_t> cuts = {0};
  Split(x, y, 0, n, tolerance, m, &cuts);
  cuts.push_back(n);
  std::vector<Line2> lines;
  for (size_t k = 0; k + 1 < cuts.size(); ++k) lines.push_back(FitRun(x, y, cuts[k], cuts[k + 1]));
  auto project = [](const Line2& l, double px, double py, double* qx, double* qy) {
    const double t = (px - l.px) * l.dx + (py - l.py) * l.dy;
    *qx = l.px + t * l.dx;
    *qy = l.py + t * l.dy;
  };
  double qx, qy;
  project(lines.front(), x.front(), y.front(), &qx, &qy);
  vx->push_back(qx);
  vy->push_back(qy);
  for (size_t k = 0; k + 1 < lines.size(); ++k) {
    const Line2& a = lines[k];
    const Line2& b = lines[k + 1];
    const double cross = a.dx * b.dy - a.dy * b.dx;
    const size_t shared = cuts[k + 1];
    if (std::abs(cross) < 0.02) {  // within about 1 degree: the common point
      vx->push_back(x[shared]);
      vy->push_back(y[shared]);
      continue;
    }
    const double t = ((b.px - a.px) * b.dy - (b.py - a.py) * b.dx) / cross;
    vx->push_back(a.px + t * a.dx);
    vy->push_back(a.py + t * a.dy);
  }
  project(lines.back(), x.back(), y.back(), &qx, &qy);
  vx->push_back(qx);
  vy->push_back(qy);
  double ss = 0;
  for (size_t i = 0; i < n; ++i) {
    double best = 1e300;
    for (size_t k = 0; k + 1 < vx->size(); ++k)
      best = std::min(best, SegmentDistance(x[i], y[i], (*vx)[k], (*vy)[k], (*vx)[k + 1], (*vy)[k + 1]));
    ss += best * best;
  }
  *rms = std::sqrt(ss / n);
}

}  // namespace bridgefit::dic
