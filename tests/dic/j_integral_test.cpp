// J integral and notch-root opening from displacement fields with a known J:
// the Westergaard/Williams mode-I field (J = K^2 / E), a bridged crack under
// an applied K (J_ff = K^2 / E, J_tip = K_tip^2 / E, PHYSICS eq. 1), and the
// orthotropic near-tip field of Sih, Paris & Irwin (1965).
#include "bridgefit/dic/j_integral.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <random>

#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/speckle.hpp"
#include "lefm_grid_field.hpp"
#include "orthotropic_tip_field.hpp"

namespace bridgefit::dic {
namespace {

using namespace test_fields;

JIntegralOptions TipCentredDomains() {
  JIntegralOptions o;
  o.metres_per_unit = kPx;
  o.domain_units = DomainUnits::kGridPoints;
  o.domains = {{DomainKind::kFarField, 10, 25, 0},
               {DomainKind::kFarField, 20, 45, 0},
               {DomainKind::kFarField, 30, 70, 0}};
  return o;
}

void ExpectAllWithin(const JIntegralResult& r, double j_exact, double tol, const char* what) {
  ASSERT_EQ(r.far_field_ok, static_cast<int>(r.domains.size())) << r.Summary();
  for (const DomainResult& d : r.domains) {
    const double err = d.j / j_exact - 1;
    std::printf("[%s] r %.3g-%.3g mm: J %.5g (exact %.5g), error %+.3f %%, excluded %.2f %%\n",
                what, d.r_in_m * 1e3, d.r_out_m * 1e3, d.j, j_exact, 100 * err,
                100 * d.excluded_fraction);
    EXPECT_LT(std::abs(err), tol) << what;
  }
  std::printf("[%s] spread %.3f %%, %.3f s\n", what, r.j_ff_spread_percent, r.wall_s);
}

TEST(JIntegral, LefmFieldGivesKSquaredOverE) {
  const ModeICrackField m = LefmField();
  const CrackGeometry crack = CrackOf(m.tip_x, m.tip_y, 1, 0);
  const DisplacementField f = SampleGrid(m, crack, 150, 150, 2);
  const JIntegralResult r =
      ComputeJIntegral(f, crack, ElasticConstants::Isotropic(kE, kNu), TipCentredDomains());
  ExpectAllWithin(r, JFromKOver2mu(m.k_over_2mu), 0.02, "lefm");
  EXPECT_LT(r.j_ff_spread_percent, 2.0);
  // The root is at the tip: no opening is read across the tip.
  EXPECT_FALSE(r.root_opening.ok);
  EXPECT_NE(r.root_opening.why.find("past the tip"), std::string::npos) << r.root_opening.why;

  // The same field and domains in metres (metres_per_unit = 1) give the same J.
  DisplacementField metres = f;
  for (auto* a : {&metres.x, &metres.y, &metres.u, &metres.v})
    for (double& value : *a) value *= kPx;
  const CrackGeometry crack_m = CrackOf(m.tip_x * kPx, m.tip_y * kPx, 1, 0);
  JIntegralOptions o = TipCentredDomains();
  o.metres_per_unit = 1;
  o.domain_units = DomainUnits::kMetres;
  for (DomainSpec& d : o.domains) d = {d.kind, d.r_in * 2 * kPx, d.r_out * 2 * kPx, 0};
  const JIntegralResult rm =
      ComputeJIntegral(metres, crack_m, ElasticConstants::Isotropic(kE, kNu), o);
  ASSERT_EQ(rm.far_field_ok, 3) << rm.Summary();
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(rm.domains[k].j / r.domains[k].j, 1.0, 1e-9);
}

// A crack at 20 degrees to the image axes, with a rigid translation and
// rotation: J is frame- and rigid-motion-independent.
TEST(JIntegral, RigidMotionAndInclinedCrackLeaveJUnchanged) {
  ModeICrackField m = LefmField();
  const double angle = 20 * std::numbers::pi / 180;
  m.direction_x = std::cos(angle);
  m.direction_y = std::sin(angle);
  m.tip_x = 3.2;
  m.tip_y = -1.7;
  const CrackGeometry crack = CrackOf(m.tip_x, m.tip_y, m.direction_x, m.direction_y);
  const auto opts = TipCentredDomains();
  const auto iso = ElasticConstants::Isotropic(kE, kNu);
  const JIntegralResult plain =
      ComputeJIntegral(SampleGrid(m, crack, 150, 150, 2), crack, iso, opts);
  m.translation_x = 7.3;
  m.translation_y = -4.1;
  m.rotation = 2e-3;  // rad; the generator's rotation is linearised
  const JIntegralResult moved =
      ComputeJIntegral(SampleGrid(m, crack, 150, 150, 2), crack, iso, opts);
  const double j_exact = JFromKOver2mu(m.k_over_2mu);
  ExpectAllWithin(plain, j_exact, 0.02, "inclined");
  ExpectAllWithin(moved, j_exact, 0.02, "inclined+rigid");
  for (std::size_t k = 0; k < moved.domains.size(); ++k) {
    const double change = moved.domains[k].j / plain.domains[k].j - 1;
    std::printf("[rigid] domain %zu: J change %.2e\n", k, change);
    EXPECT_LT(std::abs(change), 1e-3);
  }
  EXPECT_LT(moved.j_ff_spread_percent, 2.0);
}

// 0.5 % noise; a wider window (half-width 4, quadratic: 81 points) smooths
// before differentiating. Measured over 30 seeds (half-width 4): J error per
// domain, small to large, mean -0.30 / -0.11 / -0.13 %, std 0.78 / 0.32 /
// 0.26 %, largest 2.0 %; spread up to 2.1 %. The bounds are 4 std of the
// smallest domain plus its bias (3.5 %) and 4 % spread. (Half-width 2 gives
// std 1.5 / 0.6 / 0.4 % with a -1.1 % bias: too little smoothing.)
TEST(JIntegral, NoisyLefmField) {
  const ModeICrackField m = LefmField();
  const CrackGeometry crack = CrackOf(m.tip_x, m.tip_y, 1, 0);
  const DisplacementField clean = SampleGrid(m, crack, 150, 150, 2);
  JIntegralOptions o = TipCentredDomains();
  o.window_half_width = 4;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    DisplacementField f = clean;
    AddNoise(&f, 0.005, seed);
    const JIntegralResult r = ComputeJIntegral(f, crack, ElasticConstants::Isotropic(kE, kNu), o);
    ExpectAllWithin(r, JFromKOver2mu(m.k_over_2mu), 0.035, "noise");
    EXPECT_LT(r.j_ff_spread_percent, 4.0);
  }
}

// Linear softening bridging law on a semi-infinite crack; the whole zone
// (60 px behind the tip, the notch root) carries traction (delta_c above the
// root opening), so the root is the zone's end.
struct Bridged {
  static constexpr double kSigmaCOver2mu = 0.001;
  static constexpr double kDeltaCPx = 2.0;
  static constexpr double kZonePx = 60.0;
  BridgedCrackField field;
  Bridged() {
    field.tip_x = 0.5;
    field.k_over_2mu = 0.05;
    field.kappa = kKappa;
    field.zone_length = kZonePx;
    field.segments = 400;
    field.traction_over_2mu = [](double d) {
      return d < kDeltaCPx ? kSigmaCOver2mu * (1 - d / kDeltaCPx) : 0.0;
    };
    field.Solve();
  }
  // The law in SI: sigma (Pa) of delta (m).
  static double SigmaSi(double delta_m) {
    const double d = delta_m / kPx;
    return d < kDeltaCPx ? 2 * kMu * kSigmaCOver2mu * (1 - d / kDeltaCPx) : 0.0;
  }
  // W(delta) = sigma_c (delta - delta^2 / (2 delta_c)), J/m^2.
  static double WorkSi(double delta_m) {
    const double sc = 2 * kMu * kSigmaCOver2mu, dc = kDeltaCPx * kPx;
    const double d = std::min(delta_m, dc);
    return sc * (d - d * d / (2 * dc));
  }
};

// The bridged field is solved and sampled once (about 2 s).
const Bridged& SharedBridged() {
  static const Bridged b;
  return b;
}
CrackGeometry BridgedCrack() {
  return CrackOf(SharedBridged().field.tip_x, 0, 1, 0, Bridged::kZonePx);
}
const DisplacementField& BridgedGrid() {
  static const DisplacementField f = SampleGrid(SharedBridged().field, BridgedCrack(), 200, 150, 2);
  return f;
}
// Far-field domains centred on the zone's midpoint (30 px = 15 grid points
// behind the tip), tip domains inside the 60 px zone.
JIntegralOptions BridgedDomains() {
  JIntegralOptions o;
  o.metres_per_unit = kPx;
  o.domain_units = DomainUnits::kGridPoints;
  const double mid = -Bridged::kZonePx / 2 / 2;
  o.domains = {{DomainKind::kFarField, 18, 40, mid},
               {DomainKind::kFarField, 25, 55, mid},
               {DomainKind::kFarField, 32, 68, mid},
               {DomainKind::kTip, 5, 12, 0},
               {DomainKind::kTip, 4, 18, 0}};
  o.bridging_traction = Bridged::SigmaSi;
  return o;
}

TEST(JIntegral, BridgedCrackFarFieldTipAndRootOpening) {
  const Bridged& b = SharedBridged();
  const CrackGeometry crack = BridgedCrack();
  const DisplacementField& f = BridgedGrid();
  const JIntegralOptions o = BridgedDomains();
  const JIntegralResult r = ComputeJIntegral(f, crack, ElasticConstants::Isotropic(kE, kNu), o);
  std::printf("%s", r.Summary().c_str());

  const double j_ff_exact = JFromKOver2mu(b.field.k_over_2mu);
  const double j_tip_exact = JFromKOver2mu(b.field.TipKOver2mu());
  const double delta_exact = b.field.OpeningAt(Bridged::kZonePx) * kPx;
  // The generator itself satisfies eq. (1) to its discretisation.
  std::printf("[bridged] oracle: J_ff %.5g, J_tip %.5g, W(delta_root) %.5g, J_ff - J_tip %.5g\n",
              j_ff_exact, j_tip_exact, Bridged::WorkSi(delta_exact), j_ff_exact - j_tip_exact);
  ASSERT_EQ(r.far_field_ok, 3) << r.Summary();
  for (const DomainResult& d : r.domains) {
    ASSERT_EQ(d.status, DomainStatus::kOk) << r.Summary();
    if (d.spec.kind != DomainKind::kFarField) continue;
    const double err = d.j / j_ff_exact - 1;
    std::printf("[bridged] far field r %.3g-%.3g mm: J error %+.3f %%\n", d.r_in_m * 1e3,
                d.r_out_m * 1e3, 100 * err);
    EXPECT_LT(std::abs(err), 0.03);
  }
  EXPECT_LT(r.j_ff_spread_percent, 2.0);

  // delta* against the generator's face opening at the root.
  ASSERT_TRUE(r.root_opening.ok) << r.root_opening.why;
  const double delta_err = r.root_opening.delta / delta_exact - 1;
  std::printf(
      "[bridged] delta* %.5g um (exact %.5g um), error %+.3f %%, std %.2g um, sliding %.2g um\n",
      r.root_opening.delta * 1e6, delta_exact * 1e6, 100 * delta_err,
      r.root_opening.delta_std * 1e6, r.root_opening.sliding * 1e6);
  EXPECT_LT(std::abs(delta_err), 0.01);
  EXPECT_LT(std::abs(r.root_opening.sliding), 1e-3 * delta_exact);

  // Tip domains: J(x) includes the zone's share; with the law the face term
  // is removed (eq. 4) and J_ff - J_tip = W(delta*) (eq. 1).
  const double w_root = Bridged::WorkSi(r.root_opening.delta);
  for (const DomainResult& d : r.domains) {
    if (d.spec.kind != DomainKind::kTip) continue;
    ASSERT_TRUE(d.has_j_tip);
    const double tip_err = d.j_tip / j_tip_exact - 1;
    const double eq1_err = (r.j_ff - d.j_tip) / w_root - 1;
    std::printf(
        "[bridged] tip r %.3g-%.3g mm: J(x) %.5g, face %.5g, J_tip %.5g (exact %.5g) "
        "error %+.3f %%; (J_ff - J_tip) / W(delta*) - 1 = %+.3f %%\n",
        d.r_in_m * 1e3, d.r_out_m * 1e3, d.j, d.face_term, d.j_tip, j_tip_exact, 100 * tip_err,
        100 * eq1_err);
    EXPECT_LT(std::abs(tip_err), 0.03);
    EXPECT_LT(std::abs(eq1_err), 0.03);
    // Without the law the tip domain reads J(x), between J_tip and J_ff.
    EXPECT_GT(d.j, 1.05 * j_tip_exact);
    EXPECT_LT(d.j, j_ff_exact);
  }
}

// delta* on a short zone (8 grid points from the root to the tip, as in the
// first frames after the onset) seen through subsets about as long as the
// zone: the smoothed opening bends down toward the tip more than the exact
// one, so a quadratic through a stretch reaching 0.9 of the zone ahead of
// the root reads the root low; 8 points behind the root (the free notch
// faces) and 0.35 of the zone ahead (dic::FrameJOptions::
// opening_ahead_fraction) halves that. On the exact field both read the
// root within 0.4 %.
TEST(JIntegral, RootOpeningOnAShortZoneWithAShortStretchAhead) {
  constexpr double kZone = 16.0, kSpacing = 2.0;  // px: 8 grid points
  constexpr double kSmooth = 8.0;                 // px: half a subset of about the zone's length
  BridgedCrackField field;
  field.tip_x = 0.5;
  field.k_over_2mu = 0.05;
  field.kappa = kKappa;
  field.zone_length = kZone;
  field.segments = 200;
  field.traction_over_2mu = [](double d) {
    return d < Bridged::kDeltaCPx ? Bridged::kSigmaCOver2mu * (1 - d / Bridged::kDeltaCPx) : 0.0;
  };
  field.Solve();
  const CrackGeometry crack = CrackOf(field.tip_x, 0, 1, 0, kZone);
  const DisplacementField exact_field = SampleGrid(field, crack, 120, 80, kSpacing);
  // DIC subsets average the displacement over their width (31 px on zones
  // of 20-50 px in the end-to-end test): a running mean along each row over
  // +-kSmooth px stands in for it.
  DisplacementField f = exact_field;
  for (std::size_t i = 0; i < f.size(); ++i) {
    double su = 0, sv = 0;
    int n = 0;
    for (std::size_t k = 0; k < f.size(); ++k)
      if (exact_field.y[k] == exact_field.y[i] &&
          std::abs(exact_field.x[k] - exact_field.x[i]) <= kSmooth) {
        su += exact_field.u[k], sv += exact_field.v[k], ++n;
      }
    f.u[i] = su / n, f.v[i] = sv / n;
  }
  const double exact = field.OpeningAt(kZone) * kPx;
  auto read = [&](double ahead_points) {
    JIntegralOptions o;
    o.metres_per_unit = kPx;
    o.domain_units = DomainUnits::kGridPoints;
    o.opening_half_length = 8;
    o.opening_ahead_length = ahead_points;
    const JIntegralResult r = ComputeJIntegral(f, crack, ElasticConstants::Isotropic(kE, kNu), o);
    EXPECT_TRUE(r.root_opening.ok) << r.root_opening.why;
    return r.root_opening.delta / exact - 1;
  };
  const double symmetric = read(0.9 * kZone / kSpacing);  // the old stretch: 7.2 points each side
  const double short_ahead = read(0.35 * kZone / kSpacing);
  std::printf(
      "[short zone] delta* error: 0.9 of the zone both sides %+.2f %%, 8 behind + 0.35 "
      "of the zone ahead %+.2f %%\n",
      100 * symmetric, 100 * short_ahead);
  // Measured -2.8 % and -1.3 % (-0.3 % and +0.2 % without the smoothing).
  EXPECT_LT(std::abs(short_ahead), 0.02);
  EXPECT_LT(symmetric, short_ahead - 0.01);  // the bias it removes is there
}

// The bridged field with 0.5 % noise, 10 seeds: J_ff, and delta* against its
// reported uncertainty (is the uncertainty calibrated?).
TEST(JIntegral, NoisyBridgedField) {
  const Bridged& b = SharedBridged();
  const double j_ff_exact = JFromKOver2mu(b.field.k_over_2mu);
  const double j_tip_exact = JFromKOver2mu(b.field.TipKOver2mu());
  const double delta_exact = b.field.OpeningAt(Bridged::kZonePx) * kPx;
  JIntegralOptions o = BridgedDomains();
  o.window_half_width = 4;
  double sq_err = 0, sum_std = 0;
  const int seeds = 10;
  for (int seed = 1; seed <= seeds; ++seed) {
    DisplacementField f = BridgedGrid();
    AddNoise(&f, 0.005, 100 + seed);
    const JIntegralResult r =
        ComputeJIntegral(f, BridgedCrack(), ElasticConstants::Isotropic(kE, kNu), o);
    ASSERT_EQ(r.far_field_ok, 3) << r.Summary();
    for (const DomainResult& d : r.domains) {
      if (d.spec.kind == DomainKind::kFarField) {
        EXPECT_LT(std::abs(d.j / j_ff_exact - 1), 0.035);
      } else {
        // Tip domains are small, so noisier: over these seeds the rms J_tip
        // error was 2.2 % (r 0.1-0.24 mm) and 1.3 % (0.08-0.36 mm); the
        // larger one is held to 4 x 1.3 % rounded up, the smaller reported.
        const double tip_err = d.j_tip / j_tip_exact - 1;
        std::printf("[noisy bridged] seed %d tip r %.3g-%.3g mm: J_tip error %+.2f %%\n", seed,
                    d.r_in_m * 1e3, d.r_out_m * 1e3, 100 * tip_err);
        if (d.spec.r_out > 15) {
          EXPECT_LT(std::abs(tip_err), 0.055);
        }
      }
    }
    const double err = r.root_opening.delta - delta_exact;
    std::printf(
        "[noisy bridged] seed %d: J_ff error %+.2f %%, spread %.2f %%, delta* error %+.3f %% "
        "(%.2f std)\n",
        seed, 100 * (r.j_ff / j_ff_exact - 1), r.j_ff_spread_percent, 100 * err / delta_exact,
        err / r.root_opening.delta_std);
    EXPECT_LT(r.j_ff_spread_percent, 4.0);
    EXPECT_LT(std::abs(err), 4 * r.root_opening.delta_std);
    sq_err += err * err;
    sum_std += r.root_opening.delta_std;
  }
  const double ratio = std::sqrt(sq_err / seeds) / (sum_std / seeds);
  std::printf("[noisy bridged] delta*: rms error / mean reported std = %.2f\n", ratio);
  EXPECT_GT(ratio, 0.5);
  EXPECT_LT(ratio, 2.0);
}

using test_fields::OrthotropicTipField;

TEST(JIntegral, OrthotropicClosedForm) {
  // Wood-like: stiff along the crack.
  const double E1 = 10e9, E2 = 3e9, G12 = 1.5e9, nu12 = 0.3;
  const OrthotropicTipField field(0.4e6, E1, E2, G12, nu12, kPx);
  const CrackGeometry crack = CrackOf(0, 0, 1, 0);
  const DisplacementField f = SampleGrid(field, crack, 150, 150, 2);
  const JIntegralResult r = ComputeJIntegral(
      f, crack, ElasticConstants::Orthotropic(E1, E2, G12, nu12), TipCentredDomains());
  std::printf("[ortho] mu1 %.4f%+.4fi, mu2 %.4f%+.4fi\n", field.mu1.real(), field.mu1.imag(),
              field.mu2.real(), field.mu2.imag());
  ExpectAllWithin(r, field.J(), 0.02, "ortho");
  EXPECT_LT(r.j_ff_spread_percent, 2.0);
}

TEST(JIntegral, OrthotropicCodeWithIsotropicConstantsMatchesIsotropic) {
  const ModeICrackField m = LefmField();
  const CrackGeometry crack = CrackOf(m.tip_x, m.tip_y, 1, 0);
  const DisplacementField f = SampleGrid(m, crack, 150, 150, 2);
  const auto opts = TipCentredDomains();
  const JIntegralResult iso =
      ComputeJIntegral(f, crack, ElasticConstants::Isotropic(kE, kNu), opts);
  const JIntegralResult ortho = ComputeJIntegral(
      f, crack, ElasticConstants::Orthotropic(kE, kE, kE / (2 * (1 + kNu)), kNu), opts);
  for (std::size_t k = 0; k < iso.domains.size(); ++k)
    EXPECT_NEAR(ortho.domains[k].j / iso.domains[k].j, 1.0, 1e-12);
}

// ---------------------------------------------------------------- faults

TEST(JIntegral, DomainStatusesForMissingPointsLeavingAndNotEnclosing) {
  const ModeICrackField m = LefmField();
  const CrackGeometry crack = CrackOf(m.tip_x, m.tip_y, 1, 0, 30);
  DisplacementField f = SampleGrid(m, crack, 150, 150, 2);
  // Lose every point 34-100 px from the domains' centre, 15 px behind the
  // tip (a failed ring of subsets).
  const double cx = m.tip_x - 15;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const double r = std::hypot(f.x[i] - cx, f.y[i] - m.tip_y);
    if (r > 34 && r < 100 && f.status[i] == PointStatus::kOk)
      f.status[i] = PointStatus::kLowCorrelation;
  }
  JIntegralOptions o = TipCentredDomains();
  o.domains = {{DomainKind::kFarField, 18, 48, -7.5},  // inside the lost ring
               {DomainKind::kFarField, 50, 65, -7.5},  // outside it: fine
               {DomainKind::kFarField, 50, 90, -7.5},  // leaves the 150 px field
               {DomainKind::kFarField, 10, 30, 0}};    // root 30 px behind: not enclosed
  const JIntegralResult r = ComputeJIntegral(f, crack, ElasticConstants::Isotropic(kE, kNu), o);
  std::printf("%s", r.Summary().c_str());
  EXPECT_EQ(r.domains[0].status, DomainStatus::kTooFewValid);
  EXPECT_GT(r.domains[0].excluded_fraction, 0.9);
  EXPECT_EQ(r.domains[0].j, 0.0);
  EXPECT_EQ(r.domains[1].status, DomainStatus::kOk);
  EXPECT_NEAR(r.domains[1].j / JFromKOver2mu(m.k_over_2mu), 1.0, 0.02);
  EXPECT_EQ(r.domains[2].status, DomainStatus::kLeavesField);
  EXPECT_EQ(r.domains[3].status, DomainStatus::kDoesNotEnclose);
  EXPECT_EQ(r.far_field_ok, 1);
  EXPECT_EQ(r.j_ff_spread_percent, 0.0);
  EXPECT_NE(r.Summary().find("too few valid points"), std::string::npos);
  // The root (15 px from the centre) keeps enough points beside the band.
  EXPECT_TRUE(r.root_opening.ok) << r.root_opening.why;
}

TEST(JIntegral, RootOpeningWithoutPointsIsAStatus) {
  const ModeICrackField m = LefmField();
  const CrackGeometry crack = CrackOf(m.tip_x, m.tip_y, 1, 0, 60);
  DisplacementField f = SampleGrid(m, crack, 150, 150, 2);
  for (std::size_t i = 0; i < f.size(); ++i)
    if (f.y[i] < 0 && std::abs(f.x[i] + 60) < 30) f.status[i] = PointStatus::kNoConvergence;
  const JIntegralResult r =
      ComputeJIntegral(f, crack, ElasticConstants::Isotropic(kE, kNu), TipCentredDomains());
  EXPECT_FALSE(r.root_opening.ok);
  EXPECT_NE(r.root_opening.why.find("lower 0"), std::string::npos) << r.root_opening.why;
}

TEST(JIntegral, NanAtAValidPointIsAnErrorNamingTheArray) {
  const ModeICrackField m = LefmField();
  const CrackGeometry crack = CrackOf(m.tip_x, m.tip_y, 1, 0);
  DisplacementField f = SampleGrid(m, crack, 40, 40, 2);
  const auto iso = ElasticConstants::Isotropic(kE, kNu);
  JIntegralOptions o = TipCentredDomains();
  o.domains = {{DomainKind::kFarField, 5, 15, 0}};
  // NaN at a point that is not ok is ignored.
  f.v[7] = std::numeric_limits<double>::quiet_NaN();
  f.status[7] = PointStatus::kLowCorrelation;
  EXPECT_NO_THROW(ComputeJIntegral(f, crack, iso, o));
  f.status[7] = PointStatus::kOk;
  try {
    ComputeJIntegral(f, crack, iso, o);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kInput);
    EXPECT_EQ(e.context().field, "v[7]");
    EXPECT_EQ(e.context().value, "nan");
    EXPECT_NE(e.context().expected.find("finite"), std::string::npos);
  }
}

TEST(JIntegral, InvalidInputsAreErrors) {
  const ModeICrackField m = LefmField();
  const CrackGeometry crack = CrackOf(m.tip_x, m.tip_y, 1, 0);
  const DisplacementField f = SampleGrid(m, crack, 40, 40, 2);
  JIntegralOptions o = TipCentredDomains();
  std::string why;
  o.fit_order = 3;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("fit_order"), std::string::npos);
  try {
    ComputeJIntegral(f, crack, ElasticConstants::Isotropic(kE, kNu), o);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kUsage);
  }
  o = TipCentredDomains();
  o.domains.push_back({DomainKind::kFarField, 5, 5, 0});
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("domain 3"), std::string::npos) << why;
  try {
    ComputeJIntegral(f, crack, ElasticConstants::Orthotropic(10e9, 1e9, 1e9, 4.0),
                     TipCentredDomains());
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_EQ(e.context().field, "nu12");
  }
  DisplacementField bent = f;
  bent.x[5] += 0.3;  // not a regular grid
  EXPECT_THROW(
      ComputeJIntegral(bent, crack, ElasticConstants::Isotropic(kE, kNu), TipCentredDomains()),
      Error);
  const CrackGeometry no_direction = CrackOf(0, 0, 0, 0);
  EXPECT_THROW(
      ComputeJIntegral(f, no_direction, ElasticConstants::Isotropic(kE, kNu), TipCentredDomains()),
      Error);
}

}  // namespace
}  // namespace bridgefit::dic
