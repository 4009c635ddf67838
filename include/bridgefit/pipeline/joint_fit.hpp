#pragma once
// The joint fit of a campaign (issue 19, docs/CAMPAIGN.md "Joint fit"): one
// bridging law for every specimen, each specimen's R curve predicted by its
// own model (its scene, its element size), and the likelihood-ratio test of
// whether one law describes them all.

#include <string>
#include <vector>

#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/inverse/joint.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/pipeline/fit.hpp"

namespace bridgefit::pipeline {

struct JointFitRun {
  std::vector<std::string> specimens;      // those joined, in order
  inverse::FitSummary summary;             // the shared law's fit
  laws::LawShape shape;
  std::vector<double> separate_chi2;       // each specimen alone, same options
  std::vector<int> separate_points;
  inverse::ConsistencyTest consistency;
  double wall_s = 0.0;
  std::string BriefReport() const;
};

// Specimens already fitted one by one (their requests and runs, same order as
// `names`), R-curve fits of one law shape and one R kind with the reduced or
// analytic model (--model auto: its reduced model). Each model is rebuilt as
// the specimen's own fit used it (element size, scene); the specimens are
// re-fitted alone with the joint fit's options (no outlier removal) so the
// likelihood ratio compares like with like. Throws Error (kInput) for
// specimens that cannot be joined, naming the specimen.
JointFitRun RunJointFit(const std::vector<FitRequest>& requests,
                        const std::vector<const FitRun*>& runs,
                        const std::vector<std::string>& names);

}  // namespace bridgefit::pipeline
