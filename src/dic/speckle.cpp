// Speckle renderer: Gaussian dots, exact pixel integration (erf, tabulated).
#include "bridgefit/dic/speckle.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <vector>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "orthotropic_series.hpp"

namespace bridgefit::dic {

bool SpeckleOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (width < 8 || height < 8) return fail("image must be at least 8x8 px");
  if (!(speckle_radius_px >= 0.5)) return fail("speckle radius must be >= 0.5 px");
  if (!(density > 0)) return fail("density must be > 0");
  if (!(contrast > 0) || !(background >= 0) || background + contrast > 1.0)
    return fail("background + contrast must lie in (0, 1]");
  if (!(noise_std >= 0)) return fail("noise must be >= 0");
  if (bit_depth != 8 && bit_depth != 16) return fail("bit depth must be 8 or 16");
  if (margin_px < 0) return fail("margin must be >= 0");
  return true;
}

// The pixel-integrated profile of one dot along one axis,
//   g(d) = int_{d-1/2}^{d+1/2} exp(-t^2 / R^2) dt
//        = (sqrt(pi) R / 2) [erf((d + 1/2) / R) - erf((d - 1/2) / R)],
// g'(d) = exp(-(d + 1/2)^2 / R^2) - exp(-(d - 1/2)^2 / R^2),
// tabulated on |d| <= 4R every R/128 and evaluated by cubic Hermite
// interpolation (error below 1e-9 of g's peak, against four erf calls per
// dot and pixel before; the image is quantized to 1/255 or 1/65535).
class DotProfile {
 public:
  DotProfile() = default;
  explicit DotProfile(double R) : cutoff_(4.0 * R), h_(R / 128.0), inv_h_(128.0 / R) {
    const int n = 1024;
    const double scale = 0.5 * std::sqrt(std::numbers::pi) * R;
    value_.resize(n + 2);
    slope_.resize(n + 2);
    for (int j = 0; j <= n + 1; ++j) {
      const double d = -cutoff_ + j * h_;
      value_[j] = scale * (std::erf((d + 0.5) / R) - std::erf((d - 0.5) / R));
      slope_[j] = h_ * (std::exp(-(d + 0.5) * (d + 0.5) / (R * R)) -
                        std::exp(-(d - 0.5) * (d - 0.5) / (R * R)));
    }
  }
  double cutoff() const { return cutoff_; }
  // g(d) for |d| <= cutoff.
  double operator()(double d) const {
    const double t = (d + cutoff_) * inv_h_;
    const int j = std::min(static_cast<int>(t), static_cast<int>(value_.size()) - 2);
    const double f = t - j, f2 = f * f, f3 = f2 * f;
    return (2 * f3 - 3 * f2 + 1) * value_[j] + (f3 - 2 * f2 + f) * slope_[j] +
           (3 * f2 - 2 * f3) * value_[j + 1] + (f3 - f2) * slope_[j + 1];
  }

 private:
  double cutoff_ = 0, h_ = 1, inv_h_ = 1;
  std::vector<double> value_, slope_;  // g and h g' at the nodes
};

struct SpeckleRenderer::Impl {
  SpeckleOptions opt;
  DotProfile profile;
  // Dot centres grouped by cell (cells of 4R, row-major; dots of cell c at
  // [cell_start[c], cell_start[c + 1]) in the order they were drawn).
  std::vector<double> dot_x, dot_y;
  std::vector<int> cell_start;
  double cell = 1, x_min = 0, y_min = 0;
  int cells_x = 0, cells_y = 0;

  // Pattern integrated over the unit pixel centred at (X, Y), in [0, 1).
  double Pattern(double X, double Y) const {
    const double cutoff = profile.cutoff();
    const int cx0 = std::max(0, static_cast<int>((X - cutoff - x_min) / cell));
    const int cx1 = std::min(cells_x - 1, static_cast<int>((X + cutoff - x_min) / cell));
    const int cy0 = std::max(0, static_cast<int>((Y - cutoff - y_min) / cell));
    const int cy1 = std::min(cells_y - 1, static_cast<int>((Y + cutoff - y_min) / cell));
    double sum = 0;
    for (int cy = cy0; cy <= cy1; ++cy) {
      const int row = cy * cells_x;
      const int k0 = cell_start[row + cx0], k1 = cell_start[row + cx1 + 1];
      for (int k = k0; k < k1; ++k) {
        const double dx = X - dot_x[k], dy = Y - dot_y[k];
        if (std::abs(dx) > cutoff || std::abs(dy) > cutoff) continue;
        sum += profile(dx) * profile(dy);
      }
    }
    return 1.0 - std::exp(-1.5 * sum);  // smooth saturation where dots overlap
  }
};

SpeckleRenderer::SpeckleRenderer(const SpeckleOptions& options) : impl_(std::make_unique<Impl>()) {
  std::string why;
  if (!options.IsValid(&why)) throw Error(ErrorKind::kUsage, "invalid speckle options: " + why);
  Impl& m = *impl_;
  m.opt = options;
  const double R = options.speckle_radius_px;
  m.profile = DotProfile(R);
  m.x_min = -options.margin_px;
  m.y_min = -options.margin_px;
  const double w = options.width + 2.0 * options.margin_px;
  const double h = options.height + 2.0 * options.margin_px;
  const auto count = static_cast<size_t>(options.density * w * h / (std::numbers::pi * R * R));
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> ux(m.x_min, m.x_min + w), uy(m.y_min, m.y_min + h);
  m.cell = 4.0 * R;
  m.cells_x = static_cast<int>(std::ceil(w / m.cell)) + 1;
  m.cells_y = static_cast<int>(std::ceil(h / m.cell)) + 1;
  std::vector<double> xs(count), ys(count);
  std::vector<int> cell_of(count);
  m.cell_start.assign(static_cast<size_t>(m.cells_x) * m.cells_y + 1, 0);
  for (size_t k = 0; k < count; ++k) {
    xs[k] = ux(rng);
    ys[k] = uy(rng);
    const int cx = static_cast<int>((xs[k] - m.x_min) / m.cell);
    const int cy = static_cast<int>((ys[k] - m.y_min) / m.cell);
    cell_of[k] = cy * m.cells_x + cx;
    ++m.cell_start[cell_of[k] + 1];
  }
  // Counting sort by cell, stable: a cell's dots keep the order drawn.
  for (size_t c = 1; c < m.cell_start.size(); ++c) m.cell_start[c] += m.cell_start[c - 1];
  std::vector<int> fill(m.cell_start.begin(), m.cell_start.end() - 1);
  m.dot_x.resize(count);
  m.dot_y.resize(count);
  for (size_t k = 0; k < count; ++k) {
    const int at = fill[cell_of[k]]++;
    m.dot_x[at] = xs[k];
    m.dot_y[at] = ys[k];
  }
}

SpeckleRenderer::~SpeckleRenderer() = default;
SpeckleRenderer::SpeckleRenderer(SpeckleRenderer&&) noexcept = default;
const SpeckleOptions& SpeckleRenderer::options() const { return impl_->opt; }

Image SpeckleRenderer::RenderReference(std::uint64_t noise_seed) const {
  return Render([](double, double, double* u, double* v) { *u = *v = 0; }, noise_seed);
}

Image SpeckleRenderer::Render(const DisplacementFunction& displacement,
                              std::uint64_t noise_seed) const {
  const Impl& m = *impl_;
  const SpeckleOptions& o = m.opt;
  const double full = o.bit_depth == 8 ? 255.0 : 65535.0;
  Image image(o.width, o.height, 0.0f, o.bit_depth);
#pragma omp parallel for schedule(dynamic, 4)
  for (int y = 0; y < o.height; ++y) {
    // Start from the left neighbour's displacement where it had a material
    // point: the iteration then starts |grad u| x 1 px from its fixed point.
    double u_left = 0, v_left = 0;
    for (int x = 0; x < o.width; ++x) {
      // Material point X with X + u(X) = x (fixed point; fails in a gap).
      double X = x - u_left, Y = y - v_left, u = 0, v = 0;
      for (int it = 0; it < 60; ++it) {
        displacement(X, Y, &u, &v);
        const double nx = x - u, ny = y - v;
        const double change = std::abs(nx - X) + std::abs(ny - Y);
        X = nx;
        Y = ny;
        if (change < 1e-9) break;
      }
      displacement(X, Y, &u, &v);
      const bool material = std::abs(X + u - x) + std::abs(Y + v - y) < 1e-6;
      u_left = material ? u : 0.0;
      v_left = material ? v : 0.0;
      const double level = material ? o.background + o.contrast * m.Pattern(X, Y) : o.gap_intensity;
      image.at(x, y) = static_cast<float>(level * full);
    }
  }
  std::mt19937_64 rng(noise_seed * 0x9E3779B97F4A7C15ULL + 12345);
  std::normal_distribution<double> noise(0.0, o.noise_std * full);
  for (float& p : image.pixels) {
    const double q = std::round(p + (o.noise_std > 0 ? noise(rng) : 0.0));
    p = static_cast<float>(std::clamp(q, 0.0, full));
  }
  return image;
}

void ModeICrackField::operator()(double X, double Y, double* u, double* v) const {
  const double L = std::hypot(direction_x, direction_y);
  const double c = direction_x / L, s = direction_y / L;
  const double dx = X - tip_x, dy = Y - tip_y;
  const double xl = c * dx + s * dy, yl = -s * dx + c * dy;  // local frame
  const double r = std::hypot(xl, yl);
  const double a = k_over_2mu * std::sqrt(r / (2.0 * std::numbers::pi));
  // cos(t/2), sin(t/2) of t = atan2(yl, xl) in (-pi, pi] by the half-angle
  // formulas, cos^2 = (r + xl) / 2r, sin^2 = (r - xl) / 2r, the smaller of
  // r +- xl as yl^2 / (r -+ xl) (no cancellation), sin(t/2) with yl's sign
  // (a signed zero on the faces, as atan2). No trigonometric calls: this is
  // the inner loop of the speckle renderer's inverse mapping.
  double ch = 1, sh = 0;
  if (r > 0) {
    const double r_plus = xl >= 0 ? r + xl : yl * yl / (r - xl);
    const double r_minus = xl >= 0 ? yl * yl / (r + xl) : r - xl;
    ch = std::sqrt(r_plus / (2.0 * r));
    sh = std::copysign(std::sqrt(r_minus / (2.0 * r)), yl);
  }
  const double ul = a * ch * (kappa - 1.0 + 2.0 * sh * sh);
  const double vl = a * sh * (kappa + 1.0 - 2.0 * ch * ch);
  // Back to image axes, plus rigid motion about the tip.
  *u = c * ul - s * vl + translation_x - rotation * dy;
  *v = s * ul + c * vl + translation_y + rotation * dx;
}

double ModeICrackField::OpeningAt(double r) const {
  return (kappa + 1.0) * k_over_2mu * std::sqrt(2.0 * r / std::numbers::pi);
}

namespace {

// Integral over xi in [xa, xb] of ln|(sqrt(xi) + c) / (sqrt(xi) - c)|,
// c = sqrt(x): with s = sqrt(xi), F(s) = (s^2 - c^2) ln|(s + c)/(s - c)| + 2 c s.
double LogKernelIntegral(double xa, double xb, double x) {
  const double c = std::sqrt(x);
  auto F = [c](double xi) {
    const double s = std::sqrt(xi);
    const double d = std::abs(s - c);
    const double log_term = d > 0 ? (s * s - c * c) * std::log((s + c) / d) : 0.0;
    return log_term + 2.0 * c * s;
  };
  return F(xb) - F(xa);
}

}  // namespace

void BridgedCrackField::Solve() {
  if (!(zone_length > 0) || segments < 1)
    throw Error(ErrorKind::kUsage, "bridged crack needs a positive zone length and segments");
  h_ = zone_length / segments;
  const size_t n = static_cast<size_t>(segments);
  tau_.assign(n, 0.0);
  if (!traction_over_2mu) return;
  const double pi = std::numbers::pi;
  // delta_i = delta_K(x_i) - (kappa + 1) / pi sum_j tau_j C_ij at the midpoints.
  std::vector<double> C(n * n), delta_k(n);
  for (size_t i = 0; i < n; ++i) {
    const double x = (i + 0.5) * h_;
    delta_k[i] = (kappa + 1.0) * k_over_2mu * std::sqrt(2.0 * x / pi);
    for (size_t j = 0; j < n; ++j)
      C[i * n + j] = (kappa + 1.0) / pi * LogKernelIntegral(j * h_, (j + 1) * h_, x);
  }
  std::vector<double> delta(delta_k);
  double change = 1;
  for (int it = 0; it < 2000 && change > 1e-12; ++it) {
    std::vector<double> target(n);
    for (size_t j = 0; j < n; ++j) target[j] = std::max(0.0, traction_over_2mu(std::max(0.0, delta[j])));
    change = 0;
    double scale = 1e-300;
    for (size_t j = 0; j < n; ++j) {
      const double next = tau_[j] + 0.3 * (target[j] - tau_[j]);
      change = std::max(change, std::abs(next - tau_[j]));
      scale = std::max(scale, std::abs(next));
      tau_[j] = next;
    }
    change /= scale;
    for (size_t i = 0; i < n; ++i) {
      double closing = 0;
      for (size_t j = 0; j < n; ++j) closing += C[i * n + j] * tau_[j];
      delta[i] = delta_k[i] - closing;
    }
  }
  if (change > 1e-9)
    throw Error(ErrorKind::kRuntime, "bridged crack tractions did not converge",
                {.value = fmt::format("relative change {:.2e}", change), .expected = "< 1e-9"});
}

double BridgedCrackField::TractionAt(double r) const {
  if (tau_.empty() || r < 0 || r >= zone_length) return 0.0;
  return tau_[std::min(tau_.size() - 1, static_cast<size_t>(r / h_))];
}

double BridgedCrackField::OpeningAt(double r) const {
  const double pi = std::numbers::pi;
  double delta = (kappa + 1.0) * k_over_2mu * std::sqrt(2.0 * r / pi);
  for (size_t j = 0; j < tau_.size(); ++j)
    delta -= (kappa + 1.0) / pi * tau_[j] * LogKernelIntegral(j * h_, (j + 1) * h_, r);
  return delta;
}

double BridgedCrackField::TipKOver2mu() const {
  // K of closing pairs q at xi: q sqrt(2 / (pi xi)); integrated per segment:
  // int sqrt(2 / (pi xi)) dxi = 2 sqrt(2 / pi) (sqrt(xb) - sqrt(xa)).
  double k = k_over_2mu;
  for (size_t j = 0; j < tau_.size(); ++j)
    k -= tau_[j] * 2.0 * std::sqrt(2.0 / std::numbers::pi) *
         (std::sqrt((j + 1) * h_) - std::sqrt(j * h_));
  return k;
}

void BridgedCrackField::Westergaard(std::complex<double> z, std::complex<double>* Z,
                                    std::complex<double>* Zb) const {
  const double pi = std::numbers::pi;
  const std::complex<double> root = std::sqrt(z);  // branch cut on the crack (negative x')
  *Z = k_over_2mu / (std::sqrt(2.0 * pi) * root);
  *Zb = 2.0 * k_over_2mu * root / std::sqrt(2.0 * pi);
  constexpr int kSub = 4;
  for (size_t j = 0; j < tau_.size(); ++j) {
    if (tau_[j] == 0) continue;
    for (int k = 0; k < kSub; ++k) {
      const double xi = (j + (k + 0.5) / kSub) * h_;
      const double q = tau_[j] * h_ / kSub;
      const double sx = std::sqrt(xi);
      *Z -= q / pi * sx / ((z + xi) * root);
      *Zb -= 2.0 * q / pi * std::atan(root / sx);
    }
  }
}

void BridgedCrackField::SetOrthotropic(double b11, double b22, double b12, double b66,
                                       double two_mu) {
  using C = std::complex<double>;
  // A double root (isotropic constants) is moved apart as the field-wide J
  // fit's series does (one home: dic/orthotropic_series.hpp).
  detail::OrthotropicRoots(b11, b22, b12, b66, &mu1_, &mu2_);
  const C c1 = -mu2_ / (2.0 * (mu1_ - mu2_)), c2 = mu1_ / (2.0 * (mu1_ - mu2_));
  P1_ = two_mu * c1 * (b11 * mu1_ * mu1_ + b12);
  P2_ = two_mu * c2 * (b11 * mu2_ * mu2_ + b12);
  Q1_ = two_mu * c1 * (b12 * mu1_ + b22 / mu1_);
  Q2_ = two_mu * c2 * (b12 * mu2_ + b22 / mu2_);
  kappa = 1.0;
  orthotropic_ = true;
}

void BridgedCrackField::operator()(double X, double Y, double* u, double* v) const {
  using C = std::complex<double>;
  const double L = std::hypot(direction_x, direction_y);
  const double c = direction_x / L, s = direction_y / L;
  const double dx = X - tip_x, dy = Y - tip_y;
  const double xl = c * dx + s * dy, yl = -s * dx + c * dy;
  double ul = 0, vl = 0;
  C Z, Zb;
  if (orthotropic_) {
    C Z2, Zb2;
    Westergaard(C(xl, 0) + mu1_ * yl, &Z, &Zb);
    Westergaard(C(xl, 0) + mu2_ * yl, &Z2, &Zb2);
    ul = 2 * (P1_ * Zb + P2_ * Zb2).real();
    vl = 2 * (Q1_ * Zb + Q2_ * Zb2).real();
  } else {
    Westergaard(C(xl, yl), &Z, &Zb);
    ul = 0.5 * (kappa - 1.0) * Zb.real() - yl * Z.imag();
    vl = 0.5 * (kappa + 1.0) * Zb.imag() - yl * Z.real();
  }
  *u = c * ul - s * vl + translation_x - rotation * dy;
  *v = s * ul + c * vl + translation_y + rotation * dx;
}

}  // namespace bridgefit::dic
