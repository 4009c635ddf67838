#pragma once
// Synthetic speckle images with an exactly known motion, for tests and data
// samples. A speckle pattern is a sum of Gaussian dots integrated exactly over
// each pixel (erf), so a rigid translation of the pattern is rendered without
// interpolation error. Deformed images are rendered by inverting x = X + u(X)
// per pixel (fixed-point iteration); pixels with no material point (an open
// crack) get the gap intensity.

#include <cstdint>
#include <complex>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bridgefit/dic/image.hpp"

namespace bridgefit::dic {

struct SpeckleOptions {
  int width = 256, height = 256;   // px
  double speckle_radius_px = 2.0;  // 1/e radius of one dot
  double density = 0.6;            // dots per dot area (pi r^2)
  double background = 0.2;         // fraction of full scale
  double contrast = 0.6;           // dot amplitude, fraction of full scale
  double noise_std = 0.005;        // Gaussian noise, fraction of full scale
  double gap_intensity = 0.02;     // inside an open crack, fraction of full scale
  int bit_depth = 8;               // 8 or 16: quantization of the output
  int margin_px = 64;              // pattern extends this far outside the image
  std::uint64_t seed = 1;          // dot positions

  bool IsValid(std::string* why) const;
};

// Displacement (px) of the material point at reference position (X, Y).
using DisplacementFunction = std::function<void(double X, double Y, double* u, double* v)>;

class SpeckleRenderer {
 public:
  explicit SpeckleRenderer(const SpeckleOptions& options);  // throws Error(kUsage)
  ~SpeckleRenderer();
  SpeckleRenderer(SpeckleRenderer&&) noexcept;
  // Reference image (no motion) or deformed image; `noise_seed` draws the
  // noise (use different seeds for different frames).
  Image Render(const DisplacementFunction& displacement, std::uint64_t noise_seed) const;
  Image RenderReference(std::uint64_t noise_seed) const;
  const SpeckleOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Mode I LEFM near-tip field plus rigid motion, in pixels:
//   u_x' = A sqrt(r / 2 pi) cos(t/2) [kappa - 1 + 2 sin^2(t/2)]
//   u_y' = A sqrt(r / 2 pi) sin(t/2) [kappa + 1 - 2 cos^2(t/2)]
// with A = K_I / (2 mu) (px^0.5), (r, t) polar about the tip in the frame
// whose x' axis points in the growth direction (crack faces at t = +-pi).
struct ModeICrackField {
  double tip_x = 0, tip_y = 0;            // px
  double direction_x = 1, direction_y = 0; // growth direction (unit after normalizing)
  double k_over_2mu = 0.05;               // K_I / (2 mu), px^0.5
  double kappa = (3.0 - 0.3) / 1.3;       // plane stress, nu = 0.3
  double translation_x = 0, translation_y = 0, rotation = 0;  // rigid motion (rad)

  void operator()(double X, double Y, double* u, double* v) const;
  // Crack opening displacement at distance r behind the tip: (kappa + 1) A sqrt(2 r / pi).
  double OpeningAt(double r) const;
};

// A bridged mode I crack: a semi-infinite crack (Westergaard, plane
// elasticity) under the applied K_I, with closing tractions on its faces
// behind the tip set by a bridging law at the local opening, solved
// self-consistently (opening -> traction -> opening). Lengths in one unit
// throughout (px or mm). With Z(z) = A / sqrt(2 pi z)
//   - sum_j (q_j / pi) sqrt(xi_j) / ((z + xi_j) sqrt(z))   (closing pairs q_j
// at xi_j behind the tip, q = traction w / (2 mu)) and Zb its integral,
//   u_x' = (kappa - 1)/2 Re Zb - y' Im Z,  u_y' = (kappa + 1)/2 Im Zb - y' Re Z;
// without tractions this is ModeICrackField. The faces' opening uses the
// traction integrated exactly over each segment (Tada's log kernel); the
// field off the faces uses 4 point pairs per segment.
struct BridgedCrackField {
  double tip_x = 0, tip_y = 0;
  double direction_x = 1, direction_y = 0;
  double k_over_2mu = 0.05;          // applied K_I / (2 mu), unit^0.5
  double kappa = (3.0 - 0.3) / 1.3;  // plane stress, nu = 0.3
  double translation_x = 0, translation_y = 0, rotation = 0;
  // Bridging traction / (2 mu) at opening delta (unit); >= 0 closes.
  std::function<double(double)> traction_over_2mu;
  double zone_length = 20;  // faces behind the tip that may carry traction (unit)
  int segments = 400;

  // Solves for the face tractions; call before use. Throws Error(kRuntime)
  // when the fixed point does not converge.
  void Solve();
  void operator()(double X, double Y, double* u, double* v) const;
  // Opening 2 u_y' of the faces at r behind the tip.
  double OpeningAt(double r) const;
  // K_tip / (2 mu): the applied K less the bridging tractions' share.
  double TipKOver2mu() const;
  double TractionAt(double r) const;  // solved traction / (2 mu) at r behind the tip

  // An orthotropic plate, axis 1 along the crack, in-plane compliances
  // b11, b22, b12, b66 [1/Pa] (plane stress a_ij, or plane strain's
  // reduced ones): the same Z and Zb (which set the faces' tractions and
  // opening) drive Lekhnitskii's potentials phi_k = c_k 2mu Zb(z_k),
  // z_k = x' + mu_k y' (roots of b11 mu^4 + (2 b12 + b66) mu^2 + b22 = 0,
  // Im > 0), c_1 = -mu_2 / (2 (mu_1 - mu_2)), c_2 = mu_1 / (2 (mu_1 - mu_2)),
  //   u_x' = 2 Re(p_1 phi_1 + p_2 phi_2),  u_y' = 2 Re(q_1 phi_1 + q_2 phi_2),
  // so that sigma_12 = 0 and sigma_22 = 2mu Re Z on the crack line, as for
  // an isotropic plate. Sets kappa = 1; `two_mu` [Pa] must be E'/2 (E' the
  // plate's effective modulus, specimen::EffectiveModulus) and k_over_2mu,
  // traction_over_2mu divided by it: the opening is then (kappa + 1)/(2 mu)
  // = 4/E' times the isotropic form, as the plate's. Without tractions the
  // field is Sih, Paris & Irwin's (1965).
  void SetOrthotropic(double b11, double b22, double b12, double b66, double two_mu);

 private:
  // Z and Zb (per 2 mu) at z in the crack frame (the branch cut on the faces).
  void Westergaard(std::complex<double> z, std::complex<double>* Z, std::complex<double>* Zb) const;
  std::vector<double> tau_;  // per segment, traction / (2 mu)
  double h_ = 0;
  bool orthotropic_ = false;
  std::complex<double> mu1_, mu2_, P1_, P2_, Q1_, Q2_;  // P_k = 2mu c_k p_k, Q_k = 2mu c_k q_k
};

}  // namespace bridgefit::dic
