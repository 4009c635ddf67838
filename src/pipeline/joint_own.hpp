#pragma once
// What a joint fit reports beyond the shared law (src/pipeline/joint_own.cpp,
// with JointFitRun::BriefReport):
// each specimen's own values of the parameters not shared, and the
// specimens that carry each shared one (docs/CAMPAIGN.md).

#include <string>
#include <vector>

#include "bridgefit/pipeline/joint_fit.hpp"

namespace bridgefit::pipeline::detail {

// Per specimen k: `base[k]` its model, `profiled[k]` the same with its own
// parameters profiled out (an inverse::OwnParameterProfiledModel), `data[k]`
// its data as the joint fit weighs them. `fit`: the joint fit (its shared
// intervals final, the model error applied); `alone`: a fit alone's options.
// The values and intervals of OwnParameterValue.
std::vector<OwnParameterValue> OwnValues(const std::vector<std::string>& names,
                                         const std::vector<const inverse::ForwardModel*>& base,
                                         const std::vector<const inverse::ForwardModel*>& profiled,
                                         const std::vector<inverse::FitData>& data,
                                         const laws::LawShape& shape,
                                         const inverse::FitSummary& fit,
                                         const inverse::FitOptions& alone,
                                         const inverse::SharedParameters& shared);

// The carriers of every parameter shared and free in `joint` (kCarrierRule), from each
// specimen's own fit (runs[k]->summary) and whether it is past steady state
// at the joint law (`past_steady_state[k]`).
std::vector<ParameterCarriers> Carriers(const std::vector<std::string>& names,
                                        const std::vector<const FitRun*>& runs,
                                        const inverse::FitSummary& joint,
                                        const std::vector<bool>& past_steady_state,
                                        const inverse::SharedParameters& shared);

// The estimates of the parameters not shared (and delta_c when J_B or
// sigma_c is not) say so instead of the optimiser's held value.
void MarkOwnEstimates(const inverse::SharedParameters& shared, inverse::FitSummary& fit);

}  // namespace bridgefit::pipeline::detail
