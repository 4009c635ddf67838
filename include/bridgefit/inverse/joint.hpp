#pragma once
// One bridging law fitted to several specimens at once (issue 19's joint
// fit, docs/CAMPAIGN.md "Joint fit"): their R curves side by side as one data
// set, each predicted by its own specimen's forward model, the law's
// parameters shared; and the likelihood-ratio test of whether one law
// describes them all.

#include <cstddef>
#include <string>
#include <vector>

#include "bridgefit/inverse/fit.hpp"
#include "bridgefit/inverse/forward_model.hpp"

namespace bridgefit::inverse {

// Several specimens' models as one: Predict splits the crack lengths into
// the specimens' blocks (sizes `counts`, in order; block k shifted by
// `offsets[k]` on the joined axis, JoinFitData), asks each model for its
// block at its own crack lengths and joins the answers. Per point it says
// whether it lies past its own specimen's steady state (J_B is identified by
// the specimens that reached it), and gives the physical crack length
// (crack_length_physical) and R (R_physical) for the bounds and reports.
// R-curve data only (no PredictLoad).
class JointForwardModel final : public ForwardModel {
 public:
  JointForwardModel(std::vector<const ForwardModel*> models, std::vector<std::size_t> counts,
                    std::vector<double> offsets);
  std::string Name() const override;
  ForwardPrediction Predict(const laws::LawShape& shape, const LawParameters& p,
                            const std::vector<double>& crack_lengths, RKind kind) const override;

 private:
  std::vector<const ForwardModel*> models_;
  std::vector<std::size_t> counts_;
  std::vector<double> offsets_;
};

// The specimens' R-curve data end to end (same kind; uncertainties kept only
// when every specimen has them). A fit's crack-length axis ascends: block k
// is shifted by offsets[k] (>= 0) to start 1 mm past block k - 1's end.
// Throws Error (kInput) for load data or mixed kinds.
FitData JoinFitData(const std::vector<FitData>& parts, std::vector<double>* offsets);

// Likelihood ratio of the joint fit against the separate ones: with the
// noise scale s^2 pooled from the separate fits (sum chi^2 / sum dof, at
// least 1 for weighted data), LR = (chi^2_joint - sum chi^2_i) / s^2 is
// chi^2-distributed with k (n - 1) degrees of freedom when one law describes
// all n specimens (k free parameters). p < alpha: not consistent.
struct ConsistencyTest {
  double statistic = NAN;  // LR
  int degrees_of_freedom = 0;
  double p_value = NAN;
  double noise_scale2 = NAN;  // pooled s^2
  double alpha = 0.05;
  bool consistent() const { return p_value >= alpha; }
  std::string Summary() const;
};
ConsistencyTest TestConsistency(double joint_chi2, const std::vector<double>& separate_chi2,
                                const std::vector<int>& separate_dof, int free_parameters,
                                bool weighted, double alpha = 0.05);

// Upper tail of the chi^2 distribution, Q(dof / 2, x / 2) (regularized
// upper incomplete gamma; series below a + 1, continued fraction above).
double ChiSquareSurvival(double x, int degrees_of_freedom);

}  // namespace bridgefit::inverse
