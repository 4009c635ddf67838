// Test set-up shared by the joint-fit tests (joint_fit_test.cpp,
// joint_subset_test.cpp): R curves of CT specimens with different notches
// made by the analytic model (its own oracle) with 2% noise, each fitted
// alone, and the campaign's joint fit.
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/pipeline/joint_fit.hpp"
#include "bridgefit/scene/reference.hpp"

namespace bridgefit::pipeline::test {

constexpr double kNoise = 0.02;  // relative, 1 sigma (and the stated uncertainty)

// 40 R points every 1.5 mm from the notch, linear law, two starts.
inline FitRequest Specimen(double notch, const inverse::LawParameters& law, unsigned seed,
                           bool profiles) {
  FitRequest request;
  request.scene = ReferenceCtScene(notch);
  request.model = ModelChoice::kAnalytic;
  request.law = laws::LawFamily::kLinear;
  request.fit.starts = 2;
  request.fit.profile_likelihood = profiles;
  RCurve curve;
  curve.method = "energy";
  curve.r_kind = "energy";
  curve.source = fmt::format("analytic CT, a0 = {:g} mm", notch * 1e3);
  curve.initial_crack_length = notch;
  for (int i = 1; i <= 40; ++i) curve.crack_length.push_back(notch + 1.5e-3 * i);
  const auto model = inverse::MakeAnalyticForwardModel(request.scene);
  const inverse::ForwardPrediction p =
      model->Predict(laws::MakeLinearShape(), law, curve.crack_length, inverse::RKind::kEnergy);
  EXPECT_TRUE(p.ok()) << p.message;
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (double r : p.R) {
    curve.R.push_back(r * (1.0 + kNoise * gauss(rng)));
    curve.R_uncertainty.push_back(kNoise * r);
  }
  request.rcurve = curve;
  return request;
}

struct Campaign {
  std::vector<FitRequest> requests;
  std::vector<FitRun> runs;
  std::vector<std::string> names;
  JointFitRun Joint(const inverse::SharedParameters& shared = inverse::kAllShared) const {
    std::vector<const FitRun*> pointers;
    for (const FitRun& r : runs) pointers.push_back(&r);
    return RunJointFit(requests, pointers, names, nullptr, shared);
  }
};

// One specimen per law, notches 30, 35, 40, 45 mm in turn, named CT-1...
inline Campaign Make(const std::vector<inverse::LawParameters>& laws, unsigned seed_base,
                     bool profiles) {
  Campaign c;
  const double notches[] = {0.030, 0.035, 0.040, 0.045};
  for (std::size_t k = 0; k < laws.size(); ++k) {
    c.requests.push_back(
        Specimen(notches[k % 4], laws[k], seed_base + static_cast<unsigned>(k), profiles));
    c.runs.push_back(RunFit(c.requests.back()));
    c.names.push_back(fmt::format("CT-{}", k + 1));
  }
  return c;
}

}  // namespace bridgefit::pipeline::test
