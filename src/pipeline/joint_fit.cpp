#include "bridgefit/pipeline/joint_fit.hpp"

#include <fmt/format.h>

#include <deque>
#include <memory>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "fit_models.hpp"

namespace bridgefit::pipeline {

namespace {

// Why specimen `k` cannot join, or "".
std::string CannotJoin(const FitRequest& request, const FitRun& run, const FitRun& first) {
  if (run.load_data || request.target != inverse::FitTarget::kRCurve)
    return "it was fitted to its load-displacement record (the joint fit takes R curves)";
  if (request.model == ModelChoice::kMpm)
    return "it was fitted with the MPM model (the joint fit runs the reduced or analytic model)";
  if (run.r_kind != first.r_kind)
    return fmt::format("its R is {}, the first specimen's {}", inverse::RKindName(run.r_kind),
                       inverse::RKindName(first.r_kind));
  if (run.shape.family != first.shape.family || run.shape.alpha != first.shape.alpha ||
      run.shape.peak_ratio != first.shape.peak_ratio)
    return "its law shape differs from the first specimen's (give every specimen the same law)";
  return "";
}

// A separate fit's chi^2 at its bridged optimum (its starts' lowest): the
// summary's chi^2 is the flat model's where the fit found no bridging.
double OptimumChi2(const inverse::FitSummary& s) {
  double best = s.chi2;
  for (const inverse::StartResult& start : s.starts) best = std::min(best, start.cost);
  return best;
}


}  // namespace

JointFitRun RunJointFit(const std::vector<FitRequest>& requests,
                        const std::vector<const FitRun*>& runs,
                        const std::vector<std::string>& names) {
  const Stopwatch clock;
  BF_CHECK_INPUT(requests.size() == runs.size() && runs.size() == names.size(),
                 "one request, run and name per specimen", {.field = "joint fit"});
  BF_CHECK_INPUT(runs.size() >= 2, "a joint fit needs two or more fitted specimens",
                 {.field = "joint fit", .value = fmt::format("{}", runs.size()), .expected = ">= 2"});
  JointFitRun out;
  out.specimens = names;
  out.shape = runs.front()->shape;
  // Each specimen's model as its own fit built it; FitModels keeps a
  // reference to its request, so the copies live in a deque.
  std::deque<FitRequest> rebuilt;
  std::vector<std::unique_ptr<FitModels>> models;
  std::vector<const inverse::ForwardModel*> model_of;
  std::vector<std::size_t> counts;
  std::vector<inverse::FitData> parts;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const std::string why = CannotJoin(requests[k], *runs[k], *runs.front());
    BF_CHECK_INPUT(why.empty(), "specimen '" + names[k] + "' cannot join the joint fit: " + why,
                   {.file = requests[k].input_path, .field = "joint fit"});
    FitRequest& r = rebuilt.emplace_back(requests[k]);
    if (r.model == ModelChoice::kAuto) r.model = ModelChoice::kReduced;
    r.resolution = runs[k]->resolution;
    models.push_back(std::make_unique<FitModels>(r, runs[k]->input, runs[k]->data, false,
                                                 runs[k]->r_kind));
    models.back()->Build(1.0, 0.0);
    model_of.push_back(&models.back()->model());
    counts.push_back(runs[k]->data.R.size());
    parts.push_back(runs[k]->data);
  }
  std::vector<double> offsets;
  const inverse::FitData joined = inverse::JoinFitData(parts, &offsets);
  inverse::FitOptions options = requests.front().fit;
  options.outlier_threshold = 0.0;  // like with like: the same points alone and together
  inverse::FitOptions alone = options;
  alone.profile_likelihood = false;
  alone.progress = false;
  std::vector<int> dof;
  int free = 0;
  for (int i = 0; i < inverse::kParameterCount; ++i) free += !options.fixed[i];
  // Each specimen's data on its own crack lengths with the joined data's
  // weighting (uncertainties dropped for all when one specimen lacks them).
  std::vector<inverse::FitData> alone_data = parts;
  for (inverse::FitData& d : alone_data)
    if (!joined.weighted()) d.R_uncertainty.clear();
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const inverse::FitSummary s =
        inverse::FitBridgingLaw(*model_of[k], out.shape, alone_data[k], alone);
    out.separate_chi2.push_back(OptimumChi2(s));
    out.separate_points.push_back(s.data_points);
    dof.push_back(std::max(1, s.data_points - free));
  }
  const inverse::JointForwardModel joint(model_of, counts, offsets);
  out.summary = inverse::FitBridgingLaw(joint, out.shape, joined, options);
  // Each specimen alone also from the joint optimum: a separate fit that
  // stopped above it would shrink the likelihood ratio (no power).
  if (std::isfinite(out.summary.chi2))
    for (std::size_t k = 0; k < runs.size(); ++k) {
      // The joint's best start's end: every free parameter, J_B included
      // where the summary reports it as a bound only.
      inverse::FitOptions from_joint = alone;
      const inverse::StartResult* best = nullptr;
      for (const inverse::StartResult& start : out.summary.starts)
        if (!best || start.cost < best->cost) best = &start;
      if (!best) break;
      for (int i = 0; i < inverse::kParameterCount; ++i)
        if (!options.fixed[i] && std::isfinite(best->end[i])) from_joint.initial[i] = best->end[i];
      const inverse::FitSummary s =
          inverse::FitBridgingLaw(*model_of[k], out.shape, alone_data[k], from_joint);
      out.separate_chi2[k] = std::min(out.separate_chi2[k], OptimumChi2(s));
    }
  // The summary's crack lengths on the specimens' own axes, not the joined one.
  out.summary.fitted_crack_length.clear();
  for (const inverse::FitData& d : parts)
    out.summary.fitted_crack_length.insert(out.summary.fitted_crack_length.end(),
                                           d.crack_length.begin(), d.crack_length.end());
  out.summary.steady_state_crack_length = NAN;  // one per specimen
  out.consistency = inverse::TestConsistency(out.summary.chi2, out.separate_chi2, dof, free,
                                             joined.weighted());
  out.wall_s = clock.Seconds();
  return out;
}

std::string JointFitRun::BriefReport() const {
  std::string names;
  for (const std::string& s : specimens) names += (names.empty() ? "" : ", ") + s;
  std::string text = fmt::format("joint fit of {} specimens ({}), one {} law, {:.2f} s:\n",
                                 specimens.size(), names, laws::LawFamilyName(shape.family), wall_s);
  text += summary.BriefReport();
  text += "  consistency: " + consistency.Summary() + "\n";
  return text;
}

}  // namespace bridgefit::pipeline
