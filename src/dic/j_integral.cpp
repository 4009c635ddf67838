// J integral (equivalent domain integral) and notch-root opening from a
// displacement field; the equations are in include/bridgefit/dic/j_integral.hpp.
#include "bridgefit/dic/j_integral.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <Eigen/Dense>

#include "bridgefit/core/error.hpp"
#include "plane_stress_stiffness.hpp"

namespace bridgefit::dic {

// ---------------------------------------------------------------- constants

ElasticConstants ElasticConstants::Isotropic(double E, double nu) {
  ElasticConstants c;
  c.kind = Kind::kIsotropic;
  c.E = E;
  c.nu = nu;
  return c;
}

ElasticConstants ElasticConstants::Orthotropic(double E1, double E2, double G12, double nu12) {
  ElasticConstants c;
  c.kind = Kind::kOrthotropic;
  c.E1 = E1;
  c.E2 = E2;
  c.G12 = G12;
  c.nu12 = nu12;
  return c;
}

void ElasticConstants::Validate() const {
  auto positive = [](double value, const char* name) {
    BF_CHECK_INPUT(std::isfinite(value) && value > 0, "elastic modulus must be positive",
                   {.field = name, .value = fmt::format("{}", value), .expected = "> 0 Pa"});
  };
  if (kind == Kind::kIsotropic) {
    positive(E, "E");
    BF_CHECK_INPUT(std::isfinite(nu) && nu > -1 && nu < 0.5, "Poisson ratio out of range",
                   {.field = "nu", .value = fmt::format("{}", nu), .expected = "-1 < nu < 0.5"});
    return;
  }
  positive(E1, "E1");
  positive(E2, "E2");
  positive(G12, "G12");
  // Positive definite compliance: 1/(E1 E2) > nu12^2 / E1^2.
  const double limit = std::sqrt(E1 / E2);
  BF_CHECK_INPUT(std::isfinite(nu12) && std::abs(nu12) < limit,
                 "orthotropic Poisson ratio makes the compliance indefinite",
                 {.field = "nu12",
                  .value = fmt::format("{}", nu12),
                  .expected = fmt::format("|nu12| < sqrt(E1/E2) = {:.4g}", limit)});
}

// ---------------------------------------------------------------- options

bool JIntegralOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (!(metres_per_unit > 0) || !std::isfinite(metres_per_unit))
    return fail("metres_per_unit must be > 0");
  if (window_half_width < 1 || window_half_width > 20)
    return fail("window_half_width must be in [1, 20] points");
  if (fit_order != 1 && fit_order != 2) return fail("fit_order must be 1 or 2");
  const int coefficients = fit_order == 1 ? 3 : 6;
  if (min_window_points < coefficients + 1)
    return fail(fmt::format("min_window_points must be >= {} for fit order {}", coefficients + 1,
                            fit_order));
  if (!(min_valid_fraction > 0 && min_valid_fraction <= 1))
    return fail("min_valid_fraction must be in (0, 1]");
  if (opening_rows < 2) return fail("opening_rows must be >= 2 (the fit extrapolates across rows)");
  if (!(opening_half_length > 0)) return fail("opening_half_length must be > 0");
  if (!(opening_ahead_length >= 0)) return fail("opening_ahead_length must be >= 0");
  for (std::size_t k = 0; k < domains.size(); ++k) {
    const DomainSpec& d = domains[k];
    if (!(d.r_in >= 0 && d.r_out > d.r_in) || !std::isfinite(d.r_out) ||
        !std::isfinite(d.centre_offset))
      return fail(
          fmt::format("domain {}: need 0 <= r_in < r_out (got {}, {})", k, d.r_in, d.r_out));
  }
  return true;
}

const char* DomainStatusName(DomainStatus status) {
  switch (status) {
    case DomainStatus::kOk:
      return "ok";
    case DomainStatus::kLeavesField:
      return "leaves field";
    case DomainStatus::kTooFewValid:
      return "too few valid points";
    case DomainStatus::kDoesNotEnclose:
      return "does not enclose tip and zone";
  }
  return "unknown";
}

std::string JIntegralResult::Summary() const {
  std::string s = fmt::format("J integral: {} domain(s), {} gradient points, {:.3f} s\n",
                              domains.size(), gradient_points, wall_s);
  for (const DomainResult& d : domains) {
    s += fmt::format("  {:9s} r {:.4g}-{:.4g} mm: {}",
                     d.spec.kind == DomainKind::kTip ? "tip" : "far field", d.r_in_m * 1e3,
                     d.r_out_m * 1e3, DomainStatusName(d.status));
    if (d.status == DomainStatus::kOk) {
      s += fmt::format(", J {:.6g} J/m^2, excluded {:.1f} %", d.j, 100 * d.excluded_fraction);
      if (d.has_j_tip) s += fmt::format(", J_tip {:.6g} J/m^2", d.j_tip);
    } else {
      s += fmt::format(" (used {} of {} cells)", d.used, d.cells);
    }
    s += "\n";
  }
  if (far_field_ok > 0)
    s += fmt::format("  J_ff {:.6g} J/m^2 over {} domain(s), spread {:.2f} %\n", j_ff, far_field_ok,
                     j_ff_spread_percent);
  else
    s += "  J_ff: no far-field domain succeeded\n";
  if (root_opening.ok)
    s += fmt::format("  delta* {:.6g} +- {:.2g} mm ({} + {} points)\n", root_opening.delta * 1e3,
                     root_opening.delta_std * 1e3, root_opening.points_upper,
                     root_opening.points_lower);
  else
    s += "  delta*: " + root_opening.why + "\n";
  return s;
}

// ---------------------------------------------------------------- internals

namespace {

// The regular grid and the crack frame, in field units.
struct Grid {
  int nx = 0, ny = 0;
  double x0 = 0, y0 = 0, dx = 0, dy = 0;
  double c = 1, s = 0;  // crack direction
  double tip_x = 0, tip_y = 0;
  // Crack-frame coordinates of a point: along (from the tip) and normal.
  void Local(double x, double y, double* along, double* normal) const {
    const double ex = x - tip_x, ey = y - tip_y;
    *along = c * ex + s * ey;
    *normal = -s * ex + c * ey;
  }
};

void CheckFinite(const std::vector<double>& values, const char* name, std::size_t i) {
  BF_CHECK_INPUT(std::isfinite(values[i]),
                 "displacement field holds a non-finite value at a valid point",
                 {.field = fmt::format("{}[{}]", name, i),
                  .value = fmt::format("{}", values[i]),
                  .expected = "a finite number (or a status other than ok)"});
}

Grid CheckField(const DisplacementField& f, const CrackGeometry& crack) {
  const std::size_t n = static_cast<std::size_t>(f.nx) * static_cast<std::size_t>(f.ny);
  BF_CHECK_INPUT(
      f.nx >= 3 && f.ny >= 3, "displacement field too small for a J integral",
      {.field = "nx, ny", .value = fmt::format("{} x {}", f.nx, f.ny), .expected = ">= 3 x 3"});
  BF_CHECK_INPUT(f.x.size() == n && f.y.size() == n && f.u.size() == n && f.v.size() == n &&
                     f.status.size() == n,
                 "displacement field arrays disagree with nx * ny",
                 {.field = "x, y, u, v, status",
                  .value = fmt::format("{} points", f.x.size()),
                  .expected = fmt::format("{} = nx * ny", n)});
  Grid g;
  g.nx = f.nx;
  g.ny = f.ny;
  g.x0 = f.x[0];
  g.y0 = f.y[0];
  g.dx = f.x[1] - f.x[0];
  g.dy = f.y[static_cast<std::size_t>(f.nx)] - f.y[0];
  BF_CHECK_INPUT(
      std::isfinite(g.dx) && std::isfinite(g.dy) && g.dx > 0 && g.dy > 0,
      "displacement field is not a grid with increasing x and y",
      {.field = "x, y", .value = fmt::format("dx {}, dy {}", g.dx, g.dy), .expected = "> 0"});
  const double tol = 1e-6 * std::min(g.dx, g.dy);
  for (std::size_t i = 0; i < n; ++i) {
    const double ix = static_cast<double>(i % f.nx), iy = static_cast<double>(i / f.nx);
    BF_CHECK_INPUT(std::abs(f.x[i] - (g.x0 + ix * g.dx)) <= tol &&
                       std::abs(f.y[i] - (g.y0 + iy * g.dy)) <= tol,
                   "displacement field is not a regular grid",
                   {.field = fmt::format("x[{}], y[{}]", i, i),
                    .value = fmt::format("{}, {}", f.x[i], f.y[i]),
                    .expected = fmt::format("{}, {}", g.x0 + ix * g.dx, g.y0 + iy * g.dy)});
    if (f.status[i] != PointStatus::kOk) continue;
    CheckFinite(f.u, "u", i);
    CheckFinite(f.v, "v", i);
  }
  const double length = std::hypot(crack.direction_x, crack.direction_y);
  BF_CHECK_INPUT(std::isfinite(length) && length > 0 && std::isfinite(crack.tip_x) &&
                     std::isfinite(crack.tip_y) && std::isfinite(crack.root_distance) &&
                     crack.root_distance >= 0,
                 "crack geometry needs a finite tip, a nonzero direction and root_distance >= 0",
                 {.field = "crack",
                  .value = fmt::format("direction ({}, {}), root {}", crack.direction_x,
                                       crack.direction_y, crack.root_distance)});
  g.c = crack.direction_x / length;
  g.s = crack.direction_y / length;
  g.tip_x = crack.tip_x;
  g.tip_y = crack.tip_y;
  return g;
}

// Displacement gradient in the crack frame, per point (valid: has_gradient).
struct Gradients {
  std::vector<char> has;
  std::vector<double> u11, u12, u21, u22;  // u_i,j in the crack frame
};

// Stage 1: local least-squares polynomial per valid point over the valid,
// same-side neighbours in the window; d/dx and d/dy at the centre, rotated.
Gradients FitGradients(const DisplacementField& f, const Grid& g, const JIntegralOptions& o) {
  const std::size_t n = f.size();
  std::vector<double> along(n), normal(n);
  for (std::size_t i = 0; i < n; ++i) g.Local(f.x[i], f.y[i], &along[i], &normal[i]);
  // A neighbour is unusable when the segment to it crosses the crack line
  // behind the tip (the faces are a displacement discontinuity).
  auto crosses = [&](std::size_t i, std::size_t j) {
    const bool side_i = normal[i] >= 0, side_j = normal[j] >= 0;
    if (side_i == side_j) return false;
    const double t = normal[i] / (normal[i] - normal[j]);
    return along[i] + t * (along[j] - along[i]) < 0;
  };
  const int w = o.window_half_width;
  const int p = o.fit_order == 1 ? 3 : 6;
  Gradients out;
  out.has.assign(n, 0);
  out.u11.assign(n, 0);
  out.u12.assign(n, 0);
  out.u21.assign(n, 0);
  out.u22.assign(n, 0);
  for (int iy = 0; iy < g.ny; ++iy) {
    for (int ix = 0; ix < g.nx; ++ix) {
      const std::size_t i = static_cast<std::size_t>(iy) * g.nx + ix;
      if (!f.ok(i)) continue;
      Eigen::Matrix<double, 6, 6> normal_matrix = Eigen::Matrix<double, 6, 6>::Zero();
      Eigen::Matrix<double, 6, 2> rhs = Eigen::Matrix<double, 6, 2>::Zero();
      int count = 0;
      for (int jy = std::max(0, iy - w); jy <= std::min(g.ny - 1, iy + w); ++jy) {
        for (int jx = std::max(0, ix - w); jx <= std::min(g.nx - 1, ix + w); ++jx) {
          const std::size_t j = static_cast<std::size_t>(jy) * g.nx + jx;
          if (!f.ok(j) || crosses(i, j)) continue;
          const double a = jx - ix, b = jy - iy;  // offsets in grid steps
          Eigen::Matrix<double, 6, 1> basis;
          basis << 1, a, b, a * a, a * b, b * b;
          normal_matrix.topLeftCorner(p, p) += basis.head(p) * basis.head(p).transpose();
          rhs.topRows(p).col(0) += basis.head(p) * (f.u[j] - f.u[i]);
          rhs.topRows(p).col(1) += basis.head(p) * (f.v[j] - f.v[i]);
          ++count;
        }
      }
      if (count < o.min_window_points) continue;
      const Eigen::MatrixXd m = normal_matrix.topLeftCorner(p, p);
      Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(m);
      if (qr.rank() < p) continue;
      const Eigen::MatrixXd coef = qr.solve(Eigen::MatrixXd(rhs.topRows(p)));
      // Image-axis gradient (per grid step -> per unit length).
      const double dudx = coef(1, 0) / g.dx, dudy = coef(2, 0) / g.dy;
      const double dvdx = coef(1, 1) / g.dx, dvdy = coef(2, 1) / g.dy;
      // H' = R H R^T with R = [c s; -s c].
      const double c = g.c, s = g.s;
      const double h11 = c * dudx + s * dvdx, h12 = c * dudy + s * dvdy;    // (R H)_1j
      const double h21 = -s * dudx + c * dvdx, h22 = -s * dudy + c * dvdy;  // (R H)_2j
      out.u11[i] = h11 * c + h12 * s;
      out.u12[i] = -h11 * s + h12 * c;
      out.u21[i] = h21 * c + h22 * s;
      out.u22[i] = -h21 * s + h22 * c;
      out.has[i] = 1;
    }
  }
  return out;
}

// q = 1 - smoothstep(t) and dq/dr, t = (r - r_in) / (r_out - r_in).
void Weight(double r, double r_in, double r_out, double* q, double* dqdr) {
  const double width = r_out - r_in;
  const double t = std::clamp((r - r_in) / width, 0.0, 1.0);
  *q = 1 - t * t * t * (10 - 15 * t + 6 * t * t);
  *dqdr = -30 * t * t * (1 - t) * (1 - t) / width;
}

// W(delta) = int_0^delta sigma (Simpson, 400 intervals), J/m^2.
double WorkOfTraction(const std::function<double(double)>& sigma, double delta) {
  if (!(delta > 0)) return 0.0;
  const int m = 400;
  const double h = delta / m;
  double sum = sigma(0) + sigma(delta);
  for (int k = 1; k < m; ++k) sum += (k % 2 ? 4 : 2) * sigma(k * h);
  return sum * h / 3;
}

// Normal and tangential jump across the line at `along` (from the tip), from
// per-side fits a0 + a1 s + a2 s^2 + a3 n of the first `rows` rows beside the
// band within +-half_length (all in field units); see the header, stage 4.
NotchRootOpening OpeningAt(const DisplacementField& f, const Grid& g, double along_at,
                           double behind, double ahead, int rows, double metres_per_unit) {
  const double half_length = std::max(behind, ahead);  // scales s for conditioning
  NotchRootOpening out;
  const double row_spacing = std::abs(g.s) > std::abs(g.c) ? g.dx : g.dy;
  struct Side {
    std::vector<double> s, n, un, ut;
    double a0n = 0, a0t = 0, var = 0;
    double a0n_flat = 0;  // without the n term
    bool ok = false;
  } sides[2];
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (!f.ok(i)) continue;
    double s, n;
    g.Local(f.x[i], f.y[i], &s, &n);
    if (s - along_at < -behind || s - along_at > ahead) continue;
    Side& side = sides[n >= 0 ? 0 : 1];
    side.s.push_back(s - along_at);
    side.n.push_back(n);
    side.un.push_back(-g.s * f.u[i] + g.c * f.v[i]);
    side.ut.push_back(g.c * f.u[i] + g.s * f.v[i]);
  }
  for (int k = 0; k < 2; ++k) {
    Side& side = sides[k];
    if (side.s.empty()) continue;
    double nearest = std::numeric_limits<double>::infinity();
    for (double n : side.n) nearest = std::min(nearest, std::abs(n));
    const double limit = nearest + (rows - 0.5) * row_spacing;
    std::vector<std::size_t> use;
    for (std::size_t i = 0; i < side.s.size(); ++i)
      if (std::abs(side.n[i]) <= limit) use.push_back(i);
    const int m = static_cast<int>(use.size());
    if (m < 8) continue;
    Eigen::MatrixXd X(m, 4);
    Eigen::MatrixXd Y(m, 2);
    for (int r = 0; r < m; ++r) {
      const std::size_t i = use[r];
      const double s = side.s[i] / half_length;  // scaled for conditioning
      X.row(r) << 1, s, s * s, side.n[i] / row_spacing;
      Y(r, 0) = side.un[i];
      Y(r, 1) = side.ut[i];
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
    if (qr.rank() < 4) continue;
    const Eigen::MatrixXd coef = qr.solve(Y);
    const double rss = (X * coef.col(0) - Y.col(0)).squaredNorm();
    const Eigen::Matrix4d inv = (X.transpose() * X).inverse();
    side.a0n = coef(0, 0);
    side.a0t = coef(0, 1);
    // The same rows without the trend in n: their mean level carried to the line.
    const Eigen::VectorXd flat = X.leftCols(3).colPivHouseholderQr().solve(Y.col(0));
    side.a0n_flat = flat(0);
    side.var = rss / std::max(1, m - 4) * inv(0, 0);
    side.ok = true;
    (k == 0 ? out.points_upper : out.points_lower) = m;
  }
  if (!sides[0].ok || !sides[1].ok) {
    out.why = fmt::format(
        "too few valid points beside the band (upper {}, lower {}, need 8 over >= 2 rows)",
        sides[0].s.size(), sides[1].s.size());
    return out;
  }
  out.ok = true;
  out.delta = (sides[0].a0n - sides[1].a0n) * metres_per_unit;
  out.sliding = (sides[0].a0t - sides[1].a0t) * metres_per_unit;
  const double delta_flat = (sides[0].a0n_flat - sides[1].a0n_flat) * metres_per_unit;
  out.delta_model_std = 0.5 * std::abs(out.delta - delta_flat);
  out.delta_std = std::hypot(std::sqrt(sides[0].var + sides[1].var) * metres_per_unit,
                             out.delta_model_std);
  return out;
}

// Stage 3 for one domain: eq. (J1) over the annulus cells.
DomainResult IntegrateDomain(const DisplacementField& f, const Grid& g, const Gradients& grad,
                             const Eigen::Matrix3d& C, const CrackGeometry& crack,
                             const DomainSpec& spec, const JIntegralOptions& o) {
  DomainResult out;
  out.spec = spec;
  const double to_units =
      o.domain_units == DomainUnits::kGridPoints ? std::min(g.dx, g.dy) : 1.0 / o.metres_per_unit;
  const double r_in = spec.r_in * to_units, r_out = spec.r_out * to_units;  // field units
  const double centre = spec.centre_offset * to_units;                      // along, from the tip
  out.r_in_m = r_in * o.metres_per_unit;
  out.r_out_m = r_out * o.metres_per_unit;
  // The q = 1 disc must hold the tip, and for J_ff also the root.
  const double root = -crack.root_distance;
  if (r_in < std::abs(centre) ||
      (spec.kind == DomainKind::kFarField && r_in < std::abs(centre - root))) {
    out.status = DomainStatus::kDoesNotEnclose;
    return out;
  }
  const double cx = g.tip_x + centre * g.c, cy = g.tip_y + centre * g.s;
  const double x1 = g.x0 + (g.nx - 1) * g.dx, y1 = g.y0 + (g.ny - 1) * g.dy;
  if (cx - r_out < g.x0 || cx + r_out > x1 || cy - r_out < g.y0 || cy + r_out > y1) {
    out.status = DomainStatus::kLeavesField;
    return out;
  }
  const double m = o.metres_per_unit;
  const double area = g.dx * g.dy * m * m;
  double sum = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    double a, n;
    g.Local(f.x[i], f.y[i], &a, &n);
    const double ra = a - centre, r = std::hypot(ra, n);
    if (r <= r_in || r >= r_out) continue;
    ++out.cells;
    if (!grad.has[i]) continue;
    ++out.used;
    double q, dqdr;
    Weight(r, r_in, r_out, &q, &dqdr);
    const double q1 = dqdr * ra / r / m, q2 = dqdr * n / r / m;  // 1/m
    const Eigen::Vector3d eps(grad.u11[i], grad.u22[i], grad.u12[i] + grad.u21[i]);
    const Eigen::Vector3d sig = C * eps;  // sigma11, sigma22, sigma12
    const double W = 0.5 * sig.dot(eps);
    const double term1 = sig(0) * grad.u11[i] + sig(2) * grad.u21[i] - W;
    const double term2 = sig(2) * grad.u11[i] + sig(1) * grad.u21[i];
    sum += (term1 * q1 + term2 * q2) * area;
  }
  out.excluded_fraction = out.cells ? 1.0 - static_cast<double>(out.used) / out.cells : 1.0;
  if (out.cells == 0 || 1.0 - out.excluded_fraction < o.min_valid_fraction) {
    out.status = DomainStatus::kTooFewValid;
    return out;
  }
  out.j = sum;
  return out;
}

// Face term of a tip domain with a known traction law (PHYSICS eq. 4):
// int q sigma(delta) (-d delta/dx1) dx1 = W(delta(x_in)) where q = 1, plus
// the annulus part from the measured opening profile (midpoint rule).
void SubtractFaceTerm(const DisplacementField& f, const Grid& g, const JIntegralOptions& o,
                      DomainResult* d) {
  const double m = o.metres_per_unit;
  const double r_in = d->r_in_m / m, r_out = d->r_out_m / m;
  const double centre =
      d->spec.centre_offset *
      (o.domain_units == DomainUnits::kGridPoints ? std::min(g.dx, g.dy) : 1.0 / m);
  const double half = std::min(g.dx, g.dy) * 3;
  const int steps =
      std::max(8, static_cast<int>(std::ceil((r_out - r_in) / std::min(g.dx, g.dy))) * 2);
  auto delta = [&](double along) {
    const NotchRootOpening o2 = OpeningAt(f, g, along, half, half, o.opening_rows, m);
    return o2.ok ? o2.delta : std::numeric_limits<double>::quiet_NaN();
  };
  const double h = (r_out - r_in) / steps;
  std::vector<double> profile(steps + 1);
  for (int k = 0; k <= steps; ++k) profile[k] = delta(centre - r_in - k * h);
  double term = WorkOfTraction(o.bridging_traction, profile[0]);
  for (int k = 0; k < steps; ++k) {
    double q, dqdr;
    Weight(r_in + (k + 0.5) * h, r_in, r_out, &q, &dqdr);
    const double dmid = 0.5 * (profile[k] + profile[k + 1]);
    term += q * o.bridging_traction(dmid) * (profile[k + 1] - profile[k]);
  }
  if (!std::isfinite(term)) return;  // opening not measurable: no J_tip
  d->has_j_tip = true;
  d->face_term = term;
  d->j_tip = d->j - term;
}

}  // namespace

JIntegralResult ComputeJIntegral(const DisplacementField& field, const CrackGeometry& crack,
                                 const ElasticConstants& elastic, const JIntegralOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  std::string why;
  if (!options.IsValid(&why))
    throw Error(ErrorKind::kUsage, "invalid J-integral options: " + why,
                {.field = "JIntegralOptions"});
  elastic.Validate();
  const Grid grid = CheckField(field, crack);
  const Eigen::Matrix3d C = detail::PlaneStressStiffness(elastic);

  JIntegralResult result;
  const Gradients grad = FitGradients(field, grid, options);
  result.gradient_points =
      static_cast<std::size_t>(std::count(grad.has.begin(), grad.has.end(), char{1}));

  double jmin = std::numeric_limits<double>::infinity(), jmax = -jmin, jsum = 0;
  for (const DomainSpec& spec : options.domains) {
    DomainResult d = IntegrateDomain(field, grid, grad, C, crack, spec, options);
    if (d.status == DomainStatus::kOk && spec.kind == DomainKind::kTip && options.bridging_traction)
      SubtractFaceTerm(field, grid, options, &d);
    if (d.status == DomainStatus::kOk && spec.kind == DomainKind::kFarField) {
      ++result.far_field_ok;
      jsum += d.j;
      jmin = std::min(jmin, d.j);
      jmax = std::max(jmax, d.j);
    }
    result.domains.push_back(d);
  }
  if (result.far_field_ok > 0) {
    result.j_ff = jsum / result.far_field_ok;
    if (result.far_field_ok > 1)
      result.j_ff_spread_percent = 100 * (jmax - jmin) / std::abs(result.j_ff);
  }
  const double to_units = options.domain_units == DomainUnits::kGridPoints
                              ? std::min(grid.dx, grid.dy)
                              : 1.0 / options.metres_per_unit;
  // delta* needs the fitted stretch behind the tip (ahead of it there are
  // no faces): otherwise a status, not a number.
  const double root_half_length = options.opening_half_length * to_units;
  const double root_ahead_length =
      (options.opening_ahead_length > 0 ? options.opening_ahead_length
                                        : options.opening_half_length) *
      to_units;
  if (crack.root_distance > root_ahead_length) {
    result.root_opening =
        OpeningAt(field, grid, -crack.root_distance, root_half_length, root_ahead_length,
                  options.opening_rows, options.metres_per_unit);
  } else {
    result.root_opening.why = fmt::format(
        "the root ({} behind the tip) is within the stretch ahead of it ({}): the fit would "
        "reach past the tip",
        crack.root_distance, root_ahead_length);
  }
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace bridgefit::dic
