// Far-field J from a field-wide Laurent-Williams fit (dic/j_fit.hpp).
#include "bridgefit/dic/j_fit.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "plane_stress_stiffness.hpp"
#include "orthotropic_series.hpp"
#include "williams_basis.hpp"

namespace bridgefit::dic {

bool FieldFitJOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  if (lowest_order > -1 || lowest_order < -21) return fail("lowest_order must be in [-21, -1]");
  if (highest_order < 1 || highest_order > 9) return fail("highest_order must be in [1, 9]");
  if (!(check_points > 0)) return fail("check_points must be > 0");
  if (min_points < 50) return fail("min_points must be >= 50");
  if (!(max_residual_fraction > 0 && max_residual_fraction < 1))
    return fail("max_residual_fraction must be in (0, 1)");
  if (correlation_lag < 0 || correlation_lag > 40) return fail("correlation_lag must be in [0, 40]");
  if (!(dilatation_z > 0)) return fail("dilatation_z must be > 0");
  if (tile_points != 0 && (tile_points < 2 || tile_points > 200))
    return fail("tile_points must be 0 or in [2, 200]");
  return true;
}

const char* FieldFitJStatusName(FieldFitJStatus status) {
  switch (status) {
    case FieldFitJStatus::kNotRequested: return "not_requested";
    case FieldFitJStatus::kOk: return "ok";
    case FieldFitJStatus::kTooFewPoints: return "too_few_points";
    case FieldFitJStatus::kPoorFit: return "poor_fit";
  }
  return "unknown";
}

namespace {

// The basis in the crack frame about the centre, lengths in units of the
// exclusion radius: columns translation 1, 2, rotation, a uniform
// dilatation (kDilatation: no traction-free field, see FitFarFieldJ), then
// the series:
// isotropic, mode I n (n != 0) and mode II n (n != 0, 2; n = 2 is the
// rotation); orthotropic, the two terms of each order of
// orthotropic_series.hpp (one for n = 2, the T-stress).
constexpr int kDilatation = 3;  // the dilatation's column, where fitted

struct Basis {
  int lo = -3, hi = 5;
  double kappa = 0;
  bool dilatation = true;
  std::optional<detail::OrthotropicSeries> ortho;
  int FirstSeries() const { return dilatation ? 4 : 3; }
  int Size() const {
    return ortho ? FirstSeries() + ortho->Columns() : FirstSeries() + 2 * (hi - lo) - 1;
  }
  double Reach(double x1, double x2) const {
    return ortho ? ortho->Reach(x1, x2) : std::hypot(x1, x2);
  }
  // Displacement (u1, u2) of every column at polar (r, t).
  void Eval(double r, double t, Eigen::Ref<Eigen::VectorXd> u1, Eigen::Ref<Eigen::VectorXd> u2) const {
    const double x = r * std::cos(t), y = r * std::sin(t);
    u1(0) = 1; u2(0) = 0;
    u1(1) = 0; u2(1) = 1;
    u1(2) = -y; u2(2) = x;
    if (dilatation) {
      u1(kDilatation) = x;
      u2(kDilatation) = y;
    }
    if (ortho) {
      ortho->Eval(r, t, u1.data() + FirstSeries(), u2.data() + FirstSeries());
      return;
    }
    const detail::WilliamsPowers powers(r, t, lo, hi);
    int c = FirstSeries();
    for (int n = lo; n <= hi; ++n) {
      if (n == 0) continue;
      powers.ModeI(n, kappa, &u1(c), &u2(c));
      ++c;
    }
    for (int n = lo; n <= hi; ++n) {
      if (n == 0 || n == 2) continue;
      powers.ModeII(n, kappa, &u1(c), &u2(c));
      ++c;
    }
  }
};

// The J integrand (W n1 - sigma_ij n_j u_i,1) as a quadratic form h^T M h
// of h = (u1,1, u1,2, u2,1, u2,2), outward normal n.
Eigen::Matrix4d IntegrandForm(const Eigen::Matrix3d& C, double n1, double n2) {
  auto integrand = [&](const Eigen::Vector4d& h) {
    const Eigen::Vector3d strain(h(0), h(3), h(1) + h(2));
    const Eigen::Vector3d stress = C * strain;
    const double W = 0.5 * stress.dot(strain);
    return W * n1 - (stress(0) * n1 + stress(2) * n2) * h(0) -
           (stress(2) * n1 + stress(1) * n2) * h(2);
  };
  Eigen::Matrix4d M;
  for (int a = 0; a < 4; ++a)
    for (int b = a; b < 4; ++b) {
      const Eigen::Vector4d ea = Eigen::Vector4d::Unit(a), eb = Eigen::Vector4d::Unit(b);
      M(a, b) = M(b, a) = 0.5 * (integrand(ea + eb) - integrand(ea) - integrand(eb));
    }
  return M;
}

// Q of J = c^T Q c on the circle of radius rho (units of the exclusion
// radius), per unit radius: J [Pa x unit] = c^T Q c / R_unit. Composite
// 5-point Gauss-Legendre over t in (-pi, pi) (nodes stay off the faces).
Eigen::MatrixXd ContourForm(const Basis& basis, const Eigen::Matrix3d& C, double rho) {
  static const double x5[5] = {-0.9061798459386640, -0.5384693101056831, 0.0,
                               0.5384693101056831, 0.9061798459386640};
  static const double w5[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                               0.4786286704993665, 0.2369268850561891};
  const int p = basis.Size(), panels = 64;
  const double width = 2 * std::numbers::pi / panels, dt = 1e-6;
  Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(p, p);
  Eigen::VectorXd u1(p), u2(p), a1(p), a2(p), b1(p), b2(p);
  Eigen::MatrixXd G(4, p);
  for (int k = 0; k < panels; ++k)
    for (int g = 0; g < 5; ++g) {
      const double t = -std::numbers::pi + width * (k + 0.5 + 0.5 * x5[g]);
      const double w = 0.5 * width * w5[g] * rho;  // ds = rho dt
      basis.Eval(rho, t, u1, u2);
      // d/dr by a relative step (r^h g(t) terms and the rigid motion are
      // smooth off the centre), d/dt centrally (t stays inside (-pi, pi)).
      const double dr = 1e-6 * rho;
      basis.Eval(rho + dr, t, a1, a2);
      basis.Eval(rho - dr, t, b1, b2);
      const Eigen::VectorXd ur1 = (a1 - b1) / (2 * dr), ur2 = (a2 - b2) / (2 * dr);
      basis.Eval(rho, t + dt, a1, a2);
      basis.Eval(rho, t - dt, b1, b2);
      const Eigen::VectorXd ut1 = (a1 - b1) / (2 * dt * rho), ut2 = (a2 - b2) / (2 * dt * rho);
      const double c = std::cos(t), s = std::sin(t);
      G.row(0) = (c * ur1 - s * ut1).transpose();  // u1,1
      G.row(1) = (s * ur1 + c * ut1).transpose();  // u1,2
      G.row(2) = (c * ur2 - s * ut2).transpose();  // u2,1
      G.row(3) = (s * ur2 + c * ut2).transpose();  // u2,2
      Q += w * G.transpose() * IntegrandForm(C, c, s) * G;
    }
  return Q;
}

struct FitOutcome {
  bool ok = false;
  Eigen::VectorXd coef;
  Eigen::MatrixXd covariance_unit;  // (A^T A)^-1
  std::vector<std::size_t> index;   // field points used
  std::vector<double> res_u, res_v;
  Eigen::MatrixXd A;  // design rows (u, v per point)
  Eigen::VectorXd scale;          // column norms of A (the solve's conditioning)
  Eigen::MatrixXd ata_scaled;     // (A D^-1)^T (A D^-1), D = diag(scale)
  double ssr = 0;
  double signal_rms = 0;  // RMS of the fitted displacement less the rigid motion
};

FitOutcome FitSeries(const DisplacementField& f, double cx, double cy, double c, double s,
                     double radius, const Basis& basis, int min_points) {
  FitOutcome out;
  // Points where the series converges: outside the circle (isotropic) or
  // where min_k |z_k| >= radius (orthotropic: an ellipse per root).
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (!f.ok(i)) continue;
    const double ex = f.x[i] - cx, ey = f.y[i] - cy;
    const double x1 = c * ex + s * ey, x2 = -s * ex + c * ey;
    if (basis.Reach(x1, x2) >= radius) out.index.push_back(i);
  }
  const int n = static_cast<int>(out.index.size()), p = basis.Size();
  if (n < min_points || 2 * n < 4 * p) return out;
  Eigen::MatrixXd A(2 * n, p);
  Eigen::VectorXd b(2 * n), u1(p), u2(p);
  for (int k = 0; k < n; ++k) {
    const std::size_t i = out.index[k];
    const double ex = (f.x[i] - cx) / radius, ey = (f.y[i] - cy) / radius;
    const double x1 = c * ex + s * ey, x2 = -s * ex + c * ey;
    basis.Eval(std::hypot(x1, x2), std::atan2(x2, x1), u1, u2);
    A.row(2 * k) = u1.transpose();
    A.row(2 * k + 1) = u2.transpose();
    b(2 * k) = c * f.u[i] + s * f.v[i];
    b(2 * k + 1) = -s * f.u[i] + c * f.v[i];
  }
  const Eigen::VectorXd scale = A.colwise().norm().transpose().cwiseMax(1e-300);
  const Eigen::MatrixXd As = A * scale.cwiseInverse().asDiagonal();
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(As);
  if (qr.rank() < p) return out;
  out.coef = qr.solve(b).cwiseQuotient(scale);
  out.ata_scaled = As.transpose() * As;
  out.covariance_unit = scale.cwiseInverse().asDiagonal() * out.ata_scaled.inverse() *
                        scale.cwiseInverse().asDiagonal();
  out.scale = scale;
  const Eigen::VectorXd r = b - A * out.coef;
  out.res_u.resize(n);
  out.res_v.resize(n);
  for (int k = 0; k < n; ++k) {
    out.res_u[k] = r(2 * k);
    out.res_v[k] = r(2 * k + 1);
  }
  out.ssr = r.squaredNorm();
  out.signal_rms = std::sqrt(
      (A.rightCols(p - basis.FirstSeries()) * out.coef.tail(p - basis.FirstSeries())).squaredNorm() /
      (2.0 * n));
  out.A = std::move(A);
  out.ok = true;
  return out;
}

// Each point's residual as its tile would see it from a fit without the
// tile (tiles of `tile` x `tile` grid points): r~_b = y_b - A_b c_(-b)
//   = r_b + A_b M_b^-1 A_b^T r_b,  M_b = A^T A - A_b^T A_b.
// A fit absorbs part of an error correlated over many points (a patch of
// DIC bias that the series' smooth terms follow): the plain residuals miss
// that part, the leave-tile-out residuals restore it (the block form of
// the jackknife's HC3 correction). Returned in res_u, res_v.
void LeaveTileOutResiduals(const DisplacementField& f, int tile, const FitOutcome& fit,
                           std::vector<double>* res_u, std::vector<double>* res_v) {
  *res_u = fit.res_u;
  *res_v = fit.res_v;
  const int n = static_cast<int>(fit.index.size()), p = static_cast<int>(fit.A.cols());
  const int tiles_x = (f.nx + tile - 1) / tile;
  std::vector<std::vector<int>> members;
  std::vector<int> slot(static_cast<std::size_t>(tiles_x) * ((f.ny + tile - 1) / tile), -1);
  for (int k = 0; k < n; ++k) {
    const std::size_t i = fit.index[k];
    const int t = static_cast<int>(i / f.nx) / tile * tiles_x + static_cast<int>(i % f.nx) / tile;
    if (slot[t] < 0) {
      slot[t] = static_cast<int>(members.size());
      members.emplace_back();
    }
    members[slot[t]].push_back(k);
  }
  const Eigen::RowVectorXd inv_scale = fit.scale.cwiseInverse().transpose();
  for (const std::vector<int>& rows : members) {
    const int m = static_cast<int>(rows.size());
    Eigen::MatrixXd Ab(2 * m, p);
    Eigen::VectorXd rb(2 * m);
    for (int j = 0; j < m; ++j) {
      Ab.row(2 * j) = fit.A.row(2 * rows[j]).cwiseProduct(inv_scale);
      Ab.row(2 * j + 1) = fit.A.row(2 * rows[j] + 1).cwiseProduct(inv_scale);
      rb(2 * j) = fit.res_u[rows[j]];
      rb(2 * j + 1) = fit.res_v[rows[j]];
    }
    const Eigen::LDLT<Eigen::MatrixXd> mb(fit.ata_scaled - Ab.transpose() * Ab);
    if (mb.info() != Eigen::Success) continue;  // the tile carries the fit: kept as is
    const Eigen::VectorXd rt = rb + Ab * mb.solve(Ab.transpose() * rb);
    for (int j = 0; j < m; ++j) {
      (*res_u)[rows[j]] = rt(2 * j);
      (*res_v)[rows[j]] = rt(2 * j + 1);
    }
  }
}

// The variance of a linear functional g^T c of the fit under spatially
// correlated, unequal point errors (a spatial HAC / sandwich estimate): with
// h = (A^T A)^-1 g, point i's share e_i = h . (a_u,i r~_u,i + a_v,i r~_v,i),
//   Var = sum_i sum_j e_i e_j  over pairs within max_lag grid lags in x and y
// (uniform weights: Bartlett's taper read a box-correlated noise's variance
// 1.4x low in SD; max_lag well beyond the correlation length), r~ the
// leave-tile-out residuals (`tile` grid points; the plain residuals when
// 0). DIC errors are correlated over a subset and larger where the strain
// varies.
double CorrelatedVariance(const DisplacementField& f, const FitOutcome& fit,
                          const Eigen::VectorXd& g, int max_lag, int tile) {
  std::vector<double> tile_u, tile_v;
  if (tile > 0) LeaveTileOutResiduals(f, tile, fit, &tile_u, &tile_v);
  const std::vector<double>& res_u = tile > 0 ? tile_u : fit.res_u;
  const std::vector<double>& res_v = tile > 0 ? tile_v : fit.res_v;
  const Eigen::VectorXd h = fit.covariance_unit * g;
  const Eigen::VectorXd ah = fit.A * h;
  std::vector<double> e(f.size(), 0.0);
  std::vector<char> used(f.size(), 0);
  for (std::size_t k = 0; k < fit.index.size(); ++k) {
    e[fit.index[k]] = ah(2 * k) * res_u[k] + ah(2 * k + 1) * res_v[k];
    used[fit.index[k]] = 1;
  }
  double var = 0;
  for (int ly = -max_lag; ly <= max_lag; ++ly)
    for (int lx = -max_lag; lx <= max_lag; ++lx) {
      double acc = 0;
      for (std::size_t i : fit.index) {
        const int ix = static_cast<int>(i % f.nx) + lx, iy = static_cast<int>(i / f.nx) + ly;
        if (ix < 0 || iy < 0 || ix >= f.nx || iy >= f.ny) continue;
        const std::size_t j = static_cast<std::size_t>(iy) * f.nx + ix;
        if (used[j]) acc += e[i] * e[j];
      }
      var += acc;
    }
  return std::max(0.0, var);
}

// The fit with one basis (the dilatation column or not): J, its
// uncertainty, K_I and, with the column, the dilatation.
struct FitGeometry {
  double cx, cy, c, s, radius, step, metres_per_unit;
};

FieldFitJResult FitWithBasis(const DisplacementField& field, const FitGeometry& g,
                             const Basis& basis, const ElasticConstants& elastic,
                             const FieldFitJOptions& options) {
  FieldFitJResult out;
  std::vector<double> k_factor;  // K_I per unit coefficient at r = 1, per series column
  if (basis.ortho) {
    k_factor = basis.ortho->ModeIFactor();
  } else {
    // u = a1 r^1/2 f_1 with K_I / (2 mu) = a1 sqrt(2 pi): the mode I n = 1 column.
    k_factor.assign(basis.Size() - basis.FirstSeries(), 0.0);
    k_factor[-basis.lo] = elastic.E / (1 + elastic.nu) * std::sqrt(2 * std::numbers::pi);
  }
  out.terms = basis.Size();
  const Eigen::MatrixXd Q = ContourForm(basis, detail::PlaneStressStiffness(elastic), 1.0);
  // J of the series and the rigid motion: the dilatation is stress-free
  // (FieldFitJResult::dilatation), its coefficient left out.
  auto elastic_part = [&](const Eigen::VectorXd& coef) {
    Eigen::VectorXd e = coef;
    if (basis.dilatation) e(kDilatation) = 0;
    return e;
  };
  auto j_of = [&](const FitOutcome& fit, double radius) {
    const Eigen::VectorXd e = elastic_part(fit.coef);
    return e.dot(Q * e) * g.metres_per_unit / radius;
  };
  const FitOutcome fit = FitSeries(field, g.cx, g.cy, g.c, g.s, g.radius, basis, options.min_points);
  out.points = static_cast<int>(fit.index.size());
  if (!fit.ok) {
    out.status = FieldFitJStatus::kTooFewPoints;
    out.why = fmt::format("{} valid points outside the circle of {:.1f} grid points (need {})",
                          out.points, g.radius / g.step, options.min_points);
    return out;
  }
  out.J = j_of(fit, g.radius);
  const double to_j = g.metres_per_unit / g.radius;
  const Eigen::VectorXd grad = elastic_part(2 * Q * elastic_part(fit.coef) * to_j);
  const double white = fit.ssr / std::max(1, 2 * out.points - out.terms) *
                       grad.dot(fit.covariance_unit * grad);
  const double correlated = CorrelatedVariance(field, fit, grad, options.correlation_lag,
                                                 options.tile_points);
  out.J_statistical = std::sqrt(correlated);
  out.correlation_factor = white > 0 ? correlated / white : 1;
  out.residual_rms_m = std::sqrt(fit.ssr / (2.0 * out.points)) * g.metres_per_unit;
  out.signal_rms_m = fit.signal_rms * g.metres_per_unit;
  // K_I from the n = 1 columns: K = factor x coefficient / sqrt(R) (SI).
  double k_sum = 0;
  for (std::size_t j = 0; j < k_factor.size(); ++j)
    k_sum += k_factor[j] * fit.coef(basis.FirstSeries() + j);
  out.K_I = k_sum / std::sqrt(g.radius) * std::sqrt(g.metres_per_unit);
  if (basis.dilatation) {
    // Per unit length (the coefficient is per exclusion radius), its
    // standard error correlation-scaled (spatial HAC), at least the
    // white-noise one times J's correlation factor (the spatial sum can
    // cancel to zero: a seed-1 synth frame's did, and its 1e-5 read as
    // shown).
    const Eigen::VectorXd unit = Eigen::VectorXd::Unit(basis.Size(), kDilatation);
    const double white_var = fit.ssr / std::max(1, 2 * out.points - out.terms) *
                             fit.covariance_unit(kDilatation, kDilatation);
    const double var = CorrelatedVariance(field, fit, unit, options.correlation_lag,
                                          options.tile_points);
    out.dilatation = fit.coef(kDilatation) / g.radius;
    out.dilatation_se =
        std::sqrt(std::max(var, white_var * std::max(1.0, out.correlation_factor))) / g.radius;
  }
  const double check_radius = g.radius + options.check_points * g.step;
  const FitOutcome check =
      FitSeries(field, g.cx, g.cy, g.c, g.s, check_radius, basis, options.min_points);
  out.J_check = check.ok ? j_of(check, check_radius) : NAN;
  const double shift = std::isfinite(out.J_check) ? out.J_check - out.J : 0;
  out.J_uncertainty = std::hypot(out.J_statistical, shift);
  // The dilatation's move with the circle joins its standard error, as J's.
  if (basis.dilatation && check.ok)
    out.dilatation_se =
        std::hypot(out.dilatation_se, check.coef(kDilatation) / check_radius - out.dilatation);
  out.status = FieldFitJStatus::kOk;
  if (out.residual_rms_m > options.max_residual_fraction * out.signal_rms_m) {
    out.status = FieldFitJStatus::kPoorFit;
    out.why = fmt::format(
        "residual RMS {:.3g} um is {:.1f} % of the fitted displacement's {:.3g} um (at most {:.1f} %)",
        out.residual_rms_m * 1e6, 100 * out.residual_rms_m / out.signal_rms_m,
        out.signal_rms_m * 1e6, 100 * options.max_residual_fraction);
  }
  return out;
}

}  // namespace

FieldFitJResult FitFarFieldJ(const DisplacementField& field, double centre_x, double centre_y,
                             double direction_x, double direction_y, double exclusion_radius,
                             const ElasticConstants& elastic, double metres_per_unit,
                             const FieldFitJOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid J fit options: " + why);
  const double length = std::hypot(direction_x, direction_y);
  if (!(length > 0) || !(exclusion_radius > 0) || field.nx < 3 || field.ny < 3) {
    FieldFitJResult out;
    out.status = FieldFitJStatus::kTooFewPoints;
    out.why = "no crack direction, exclusion radius or grid";
    return out;
  }
  const FitGeometry g{centre_x, centre_y, direction_x / length, direction_y / length,
                      exclusion_radius, field.x[1] - field.x[0], metres_per_unit};
  Basis basis;
  basis.lo = options.lowest_order;
  basis.hi = options.highest_order;
  if (elastic.kind == ElasticConstants::Kind::kIsotropic) {
    basis.kappa = (3 - elastic.nu) / (1 + elastic.nu);
  } else {
    basis.ortho.emplace(1 / elastic.E1, 1 / elastic.E2, -elastic.nu12 / elastic.E1,
                        1 / elastic.G12, basis.lo, basis.hi);
  }
  // The dilatation is fitted beside the series and taken out only where
  // the field shows it (|e| > dilatation_z standard errors): fitted
  // always, it costs J 2-3x its precision (it trades off against the
  // series' low orders), and no forward model's field has one.
  basis.dilatation = false;
  const FieldFitJResult plain = FitWithBasis(field, g, basis, elastic, options);
  basis.dilatation = true;
  const FieldFitJResult dilated = FitWithBasis(field, g, basis, elastic, options);
  const bool shown = dilated.status != FieldFitJStatus::kTooFewPoints &&
                     dilated.dilatation_se > 0 &&
                     std::abs(dilated.dilatation) > options.dilatation_z * dilated.dilatation_se;
  FieldFitJResult out_fit = shown ? dilated : plain;
  out_fit.dilatation = dilated.dilatation;
  out_fit.dilatation_se = dilated.dilatation_se;
  out_fit.dilatation_removed = shown;
  return out_fit;
}

}  // namespace bridgefit::dic
