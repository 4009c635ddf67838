#pragma once
// The R curves of the fitted-shape tests (tests/inverse/fit_shape_test.cpp,
// tests/pipeline/shape_law_test.cpp): a forward model's own R, with seeded
// relative noise.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bridgefit/inverse/fit.hpp"

namespace bridgefit::inverse::testing {

// n R points of `model` from a0 to a_max, relative Gaussian noise `noise`,
// each with the uncertainty noise x R. The growth Delta a_i is spaced as
// i^2 (the notch-root opening, ~ sqrt(Delta a), about evenly): evenly spaced
// crack lengths leave the law below the first point's opening unseen
// (docs/FIT.md "Law families with a fitted shape").
inline FitData MakeShapeData(const ForwardModel& model, double a0, const laws::LawShape& shape,
                             const LawParameters& truth, double a_max, int n, double noise,
                             unsigned seed) {
  FitData data;
  for (int i = 0; i < n; ++i)
    data.crack_length.push_back(a0 + (a_max - a0) * std::pow((i + 1.0) / n, 2));
  const ForwardPrediction p = model.Predict(shape, truth, data.crack_length, RKind::kEnergy);
  EXPECT_TRUE(p.ok()) << p.message;
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (double r : p.R) {
    data.R.push_back(r * (1.0 + noise * gauss(rng)));
    data.R_uncertainty.push_back(noise * r);
  }
  return data;
}

}  // namespace bridgefit::inverse::testing
