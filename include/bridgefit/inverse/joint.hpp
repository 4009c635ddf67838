#pragma once
// One bridging law fitted to several specimens at once (issue 19's joint
// fit, docs/CAMPAIGN.md "Joint fit"): their R curves side by side as one data
// set, each predicted by its own specimen's forward model, the law's
// parameters shared; and the likelihood-ratio test of whether one law
// describes them all.

#include <array>
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
// PredictLoad does the same for load-displacement records: the displacements
// split into the blocks (no shift: a load fit's rows need not ascend), each
// specimen's model - built at its own calibrated moduli and series
// compliance - predicting its own rows.
class JointForwardModel final : public ForwardModel {
 public:
  JointForwardModel(std::vector<const ForwardModel*> models, std::vector<std::size_t> counts,
                    std::vector<double> offsets);
  std::string Name() const override;
  ForwardPrediction Predict(const laws::LawShape& shape, const LawParameters& p,
                            const std::vector<double>& crack_lengths, RKind kind) const override;
  ForwardPrediction PredictLoad(const laws::LawShape& shape, const LawParameters& p,
                                const std::vector<double>& displacements) const override;

 private:
  // Joins the blocks' predictions (`load`: PredictLoad's, else Predict's).
  ForwardPrediction Joined(const laws::LawShape& shape, const LawParameters& p,
                           const std::vector<double>& axis, RKind kind, bool load) const;
  std::vector<const ForwardModel*> models_;
  std::vector<std::size_t> counts_;
  std::vector<double> offsets_;
};

// A specimen's load-displacement model with its modulus scale profiled out
// (the joint fit's per-specimen nuisance parameter, docs/CAMPAIGN.md): the
// model at moduli g x those of `base` (built at the specimen's calibrated
// modulus factor f0, without series compliance) and `series_compliance`
// [m/N] in series, with g chosen at every law to minimise the chi^2 of the
// specimen's own `rows` (Brent's minimiser on ln g within +-`span`, to 1e-5).
// No model is rebuilt: all moduli x g is the same elastic problem with
// displacements / g, so the model at g under (sigma_c, J_B, J_tip,c) is the
// base model under (sigma_c, g J_B, g J_tip,c) at displacements g D with the
// series compliance g C_s, its R and openings / g and its loads as they are
// (exact for a linear-elastic model with every modulus scaled alike).
// PredictLoad must be asked at the rows' own displacements.
class ModulusProfiledLoadModel final : public ForwardModel {
 public:
  ModulusProfiledLoadModel(const SimulationForwardModel& base, double series_compliance,
                           FitData rows, double span = 0.05);
  std::string Name() const override { return base_.Name() + " (modulus scale profiled)"; }
  ForwardPrediction Predict(const laws::LawShape& shape, const LawParameters& p,
                            const std::vector<double>& crack_lengths, RKind kind) const override;
  ForwardPrediction PredictLoad(const laws::LawShape& shape, const LawParameters& p,
                                const std::vector<double>& displacements) const override;
  // The base model at relative modulus scale g (no profiling).
  ForwardPrediction PredictLoadAtScale(const laws::LawShape& shape, const LawParameters& p,
                                       const std::vector<double>& displacements, double g) const;
  // The scale g [-] the profile chooses for law p (NaN when every run failed).
  double ProfiledScale(const laws::LawShape& shape, const LawParameters& p) const;

 private:
  const SimulationForwardModel& base_;
  double series_compliance_;
  FitData rows_;
  double span_;
};

// Which law parameters a joint fit shares (issue 19: "sigma_c, J_B,
// delta_c, J_tip,c, or a subset named by the user"), in the fitter's order
// (kSigmaC, kJB, kJTipC); the others are each specimen's own. delta_c is no
// parameter of its own: it follows from J_B and sigma_c (shared when both are).
using SharedParameters = std::array<bool, kParameterCount>;
inline constexpr SharedParameters kAllShared = {true, true, true};
// "sigma_c", "J_B", "J_tip_c" -> the mask; throws Error (kInput) naming the
// allowed names for any other (delta_c included, with why) and for an empty
// list or a name given twice.
SharedParameters ParseSharedParameters(const std::vector<std::string>& names);
std::string SharedParametersText(const SharedParameters& shared);  // "sigma_c, J_B"

// A specimen's model with the law parameters it does not share profiled out
// (the joint fit's per-specimen law parameters, docs/CAMPAIGN.md "A subset
// shared"): for the shared values in p, its own ones (!shared[i]) are those
// that minimise the chi^2 of its own `data` (R curve or load record, as
// given to the joint fit), searched in ln p within the box [lower, upper]:
// Brent's minimiser for one (first within a factor e of `start`, its own
// fit's optimum, then over the whole box when that ends on an edge), Brent
// sweeps over each in turn for two (until a sweep moves neither by more than
// 1e-4 in ln p, at most 8). Stateless (safe on the profile threads).
// Predict / PredictLoad must be asked at the data's own axis.
class OwnParameterProfiledModel final : public ForwardModel {
 public:
  OwnParameterProfiledModel(const ForwardModel& base, FitData data, SharedParameters shared,
                            std::array<double, kParameterCount> lower,
                            std::array<double, kParameterCount> upper,
                            std::array<double, kParameterCount> start);
  std::string Name() const override { return base_.Name() + " (own parameters profiled)"; }
  ForwardPrediction Predict(const laws::LawShape& shape, const LawParameters& p,
                            const std::vector<double>& crack_lengths, RKind kind) const override;
  ForwardPrediction PredictLoad(const laws::LawShape& shape, const LawParameters& p,
                                const std::vector<double>& displacements) const override;
  // p with its own (not shared) parameters at their profiled values (NaN
  // there when every run failed).
  LawParameters Profiled(const laws::LawShape& shape, const LawParameters& p) const;
  // The specimen's chi^2 under the base model at p as it is.
  double Chi2(const laws::LawShape& shape, const LawParameters& p) const;

 private:
  const ForwardModel& base_;
  FitData data_;
  SharedParameters shared_;
  std::array<double, kParameterCount> lower_, upper_, start_;
};

// The specimens' data end to end (uncertainties kept only when every
// specimen has them). R curves (same kind): a fit's crack-length axis
// ascends, so block k is shifted by offsets[k] (>= 0) to start 1 mm past
// block k - 1's end. Load-displacement records: the rows joined as they are
// (offsets all 0). Throws Error (kInput) for mixed targets or R kinds.
FitData JoinFitData(const std::vector<FitData>& parts, std::vector<double>* offsets);

// Likelihood ratio of the joint fit against the separate ones: with the
// noise scale s^2 pooled from the separate fits (sum chi^2 / sum dof, at
// least 1 for weighted data), LR = (chi^2_joint - sum chi^2_i) / s^2 is
// chi^2-distributed with k (n - 1) degrees of freedom when one law describes
// all n specimens (k free parameters shared; a parameter each specimen keeps
// as its own costs no degree of freedom). p < alpha: not consistent.
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
