#pragma once
// Synthetic law-free data from the project's closed forms (laws::FarFieldJ,
// laws::ElasticZoneR) with 0.5 % Gaussian noise, fixed seeds: shared by
// law_free_test.cpp and law_free_bounds_test.cpp.

#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "bridgefit/laws/law.hpp"
#include "bridgefit/laws/law_free.hpp"
#include "bridgefit/laws/rcurve_theory.hpp"

namespace bridgefit::laws::synthetic {

constexpr double kJtipc = 2210.0;                  // [J/m^2]
constexpr double kJB = 1000.0;                     // [J/m^2]
constexpr double kDeltaC = 2.5e-3;                 // [m]
constexpr double kNoise = 0.005;                   // relative standard uncertainty
constexpr int kPreOnset = 10;                      // J_ff samples while J_tip rises
constexpr int kGrowth = 150;                       // samples during growth
constexpr double kOnsetOpening = 0.004 * kDeltaC;  // delta* at the onset [m]

struct Truth {
  std::string name;
  LawShape shape;
  double sigma_c = 0.0;
  BridgingLaw Law() const { return {&shape, sigma_c, kDeltaC}; }
};

inline Truth MakeTruth(const std::string& name, LawShape shape) {
  Truth t{name, std::move(shape)};
  t.sigma_c = kJB / (t.shape.Area() * kDeltaC);
  return t;
}

inline std::vector<Truth> Families() {
  return {MakeTruth("linear", MakeLinearShape()), MakeTruth("cubic", MakeCubicShape()),
          MakeTruth("exponential", MakeExponentialShape(3.0))};
}
inline Truth Trilinear() {
  return MakeTruth("trilinear", MakeTrilinearShape(1.0, 0.2, 0.6, 0.55, 0.25));
}

// Standard normal by Box-Muller (std::normal_distribution differs between
// standard libraries).
class Noise {
 public:
  explicit Noise(unsigned seed) : engine_(seed) {}
  double Next() {
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    const double u1 = 1.0 - uniform(engine_), u2 = uniform(engine_);
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }

 private:
  std::mt19937_64 engine_;
};

// J_ff(delta*): a steep pre-onset rise to J_tip,c, then eq. (1) with the
// opening counted from the onset, up to `end` delta_c.
inline FarFieldJSamples MakeFarFieldJ(const Truth& truth, double end, unsigned seed) {
  Noise noise(seed);
  const BridgingLaw law = truth.Law();
  FarFieldJSamples d;
  auto add = [&](double opening, double J) {
    d.opening.push_back(opening);
    d.uncertainty.push_back(kNoise * J);
    d.J_ff.push_back(J + kNoise * J * noise.Next());
  };
  for (int i = 0; i < kPreOnset; ++i)
    add(kOnsetOpening * i / (kPreOnset - 1), kJtipc * (0.4 + 0.6 * i / (kPreOnset - 1)));
  for (int k = 1; k <= kGrowth; ++k) {
    const double x = end * kDeltaC * k / kGrowth;
    add(kOnsetOpening + x, FarFieldJ(law, x, kJtipc));
  }
  return d;
}

// R(delta_root), eq. (3), from just after the onset up to `end` delta_c.
inline RCurveSamples MakeRCurve(const Truth& truth, double end, unsigned seed) {
  Noise noise(seed);
  const BridgingLaw law = truth.Law();
  RCurveSamples d;
  for (int k = 1; k <= kGrowth; ++k) {
    const double x = end * kDeltaC * k / kGrowth;
    const double R = ElasticZoneR(law, x, kJtipc);
    d.opening.push_back(x);
    d.uncertainty.push_back(kNoise * R);
    d.R.push_back(R + kNoise * R * noise.Next());
  }
  return d;
}

}  // namespace bridgefit::laws::synthetic
