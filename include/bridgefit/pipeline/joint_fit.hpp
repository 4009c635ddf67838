#pragma once
// The joint fit of a campaign (issue 19, docs/CAMPAIGN.md "Joint fit"): one
// bridging law for every specimen, each specimen's R curve predicted by its
// own model (its scene, its element size), and the likelihood-ratio test of
// whether one law describes them all.

#include <optional>
#include <string>
#include <vector>

#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/inverse/joint.hpp"
#include "bridgefit/inverse/model_error.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/parallel/communicator.hpp"
#include "bridgefit/pipeline/fit.hpp"

namespace bridgefit::pipeline {

// A specimen's own value of a law parameter the joint fit does not share
// (docs/CAMPAIGN.md "A subset shared"), at the joint optimum. Its interval
// adds to the conditional one (the specimen's own profile with the shared
// parameters held at the joint values) the shared parameters' uncertainty
// carried through: in ln p, half-width^2 = conditional^2 + (sum_j |d ln v /
// d ln s_j| h_j)^2, h_j the half-width of shared s_j's joint interval in ln
// s_j, the sensitivities by central differences (+-1% in s_j) of the
// profiled value; the sum bounds the correlated sum from above (|rho| <= 1).
// Open (NaN) where a shared interval or the conditional one is open.
struct OwnParameterValue {
  std::string specimen;
  int parameter = 0;  // inverse::ParameterIndex
  double value = NAN;             // SI
  double ci95_low = NAN, ci95_high = NAN;
  double conditional_ci95_low = NAN, conditional_ci95_high = NAN;
};

// The specimens that carry a shared parameter's information (issue 19),
// by the rule of kCarrierRule (docs/CAMPAIGN.md).
struct ParameterCarriers {
  int parameter = 0;  // inverse::ParameterIndex
  std::vector<std::string> specimens;
  // Per specimen of the joint fit (its order): why it does or does not carry.
  std::vector<std::string> reasons;
};
inline constexpr double kCarrierWidthRatio = 10.0;
inline constexpr const char* kCarrierRule =
    "a specimen carries J_B when its data reach past its steady state at the joint law (the "
    "plateau bounds J_B from above; before it only a lower bound, PHYSICS 7); sigma_c or "
    "J_tip,c when its own fit closes that parameter's 95% interval (identified, both ends "
    "finite, not open or ending on the box) no wider than 10 times the joint interval (it holds "
    "at least 1% of the joint information)";

struct JointFitRun {
  std::vector<std::string> specimens;      // those joined, in order
  // The law parameters shared (the rest each specimen's own: profiled out
  // of the joint model, their estimates in `summary` NaN with a note).
  inverse::SharedParameters shared = inverse::kAllShared;
  inverse::FitSummary summary;             // the shared law's fit
  // Each specimen's own values of the parameters not shared (specimen order,
  // then parameter order); empty when all are shared.
  std::vector<OwnParameterValue> own_values;
  // Per shared parameter (free in the fit), who carries it (kCarrierRule).
  std::vector<ParameterCarriers> carriers;
  laws::LawShape shape;
  inverse::ConsistencyTest consistency;
  // The joint model's discretisation error (issue 17): every specimen's
  // reduced model at twice and four times its own element size, joined,
  // the joint fit re-run locally from its optimum with each
  // (inverse::EstimateModelError); applied to `summary` (its intervals are
  // the totals, the statistical ones kept). Not estimated (said) where a
  // specimen has no coarser reduced model (analytic, mesh invalid).
  inverse::ModelErrorEstimate model_error;
  // Per specimen: its chi^2 at the joint law over its own optimum's, in
  // units of s^2, and that difference's chi^2 tail on k degrees of freedom.
  std::vector<double> specimen_statistic, specimen_p_value;
  // Load-displacement records (empty for R curves): each specimen's modulus
  // factor (all moduli x it) profiled at the joint law, and its own fit's
  // calibrated one that the profile starts from (ModulusProfiledLoadModel).
  std::vector<double> specimen_modulus_factor, specimen_calibrated_modulus_factor;
  // Not one law: the specimens set aside one at a time (the one the joint
  // law misses most) until the rest is consistent or two are left, and the
  // joint fit of the rest.
  std::vector<std::string> flagged;
  std::optional<inverse::FitSummary> summary_without_flagged;
  inverse::ConsistencyTest consistency_without_flagged;
  std::vector<ParameterCarriers> carriers_without_flagged;  // names: the rest's
  double wall_s = 0.0;
  std::string BriefReport() const;
};

// Specimens already fitted one by one (their requests and runs, same order as
// `names`), all R-curve fits (one R kind) or all load-displacement fits, of
// one law shape with the reduced or analytic model (--model auto: its
// reduced model). A load record's modulus scale is profiled out at every law
// (inverse::ModulusProfiledLoadModel, from its own fit's calibrated value),
// its series compliance held at its own fit's value, and each record's rows
// weighted by its own noise scale (its chi^2 alone over its dof). Each model is rebuilt as
// the specimen's own fit used it (element size, scene); the specimens are
// re-fitted alone with the joint fit's options (no outlier removal) so the
// likelihood ratio compares like with like. Throws Error (kInput) for
// specimens that cannot be joined, naming the specimen.
// With `ranks` (the ranks of an MPI job, each calling this with the same
// specimens at the same time): the fits alone dealt round-robin over them
// and each joint fit's profiles too (inverse::FitOptions::ranks), every rank
// receiving all; the result is the one of a process alone, bit for bit, on
// every rank. An Error is then thrown on every rank alike when it is of kind
// kInput or kUsage (found before any work is shared) or names the field
// kRanksAgreeField (a fit on one rank failed: every rank was told); any other
// (a message lost or garbled, ranks that reached different optima) is this
// rank's alone, and the job must end (parallel::Communicator::Abort).
inline constexpr const char* kRanksAgreeField = "joint fit over MPI ranks";
// `shared`: the law parameters every specimen shares (default all); the
// others are each specimen's own, profiled out of the joint model
// (inverse::OwnParameterProfiledModel), and the likelihood ratio then has
// k_shared (n - 1) degrees of freedom.
JointFitRun RunJointFit(const std::vector<FitRequest>& requests,
                        const std::vector<const FitRun*>& runs,
                        const std::vector<std::string>& names,
                        parallel::Communicator* ranks = nullptr,
                        const inverse::SharedParameters& shared = inverse::kAllShared);

}  // namespace bridgefit::pipeline
