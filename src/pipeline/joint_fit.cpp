#include "bridgefit/pipeline/joint_fit.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/parallel/bytes.hpp"
#include "bridgefit/parallel/communicator.hpp"
#include "fit_models.hpp"
#include "joint_own.hpp"

namespace bridgefit::pipeline {

namespace {

// Why specimen `k` cannot join, or "".
std::string CannotJoin(const FitRequest& request, const FitRun& run, const FitRun& first) {
  const bool load = run.load_data.has_value(), first_load = first.load_data.has_value();
  if (load != first_load)
    return fmt::format(
        "it was fitted to its {}, the first specimen to its {} (a joint fit compares like with "
        "like: fit every specimen to its R curve, or every one to its load-displacement record)",
        load ? "load-displacement record" : "R curve",
        first_load ? "load-displacement record" : "R curve");
  if (load && request.target != inverse::FitTarget::kLoad)
    return "its fit request does not name its load-displacement record (fit_to)";
  if (request.model == ModelChoice::kMpm)
    return "it was fitted with the MPM model (the joint fit runs the reduced or analytic model)";
  if (run.r_kind != first.r_kind)
    return fmt::format("its R is {}, the first specimen's {}", inverse::RKindName(run.r_kind),
                       inverse::RKindName(first.r_kind));
  // A fitted shape (--law compare's bilinear, trilinear, table) is its points.
  if (run.shape.family != first.shape.family || run.shape.alpha != first.shape.alpha ||
      run.shape.peak_ratio != first.shape.peak_ratio || run.shape.d_points != first.shape.d_points ||
      run.shape.s_points != first.shape.s_points ||
      run.shape.interpolation != first.shape.interpolation)
    return "its law shape differs from the first specimen's (give every specimen the same law)";
  return "";
}

// The start that ended lowest (its end holds every free parameter, J_B
// included where the summary gives only a bound); null without starts.
const inverse::StartResult* BestStart(const inverse::FitSummary& s) {
  const inverse::StartResult* best = nullptr;
  for (const inverse::StartResult& start : s.starts)
    if (std::isfinite(start.cost) && (!best || start.cost < best->cost)) best = &start;
  return best;
}

// The model's prediction of `data` (R at its crack lengths, or the load at
// its displacements) at law parameters p.
inverse::ForwardPrediction PredictData(const inverse::ForwardModel& model,
                                       const laws::LawShape& shape, const inverse::FitData& data,
                                       const inverse::LawParameters& p) {
  return data.target == inverse::FitTarget::kLoad
             ? model.PredictLoad(shape, p, data.displacement)
             : model.Predict(shape, p, data.crack_length, data.kind);
}

// chi^2 of `data` (R curve or load record) under `model` at physical
// parameters p (infinite when the model fails).
double Chi2(const inverse::ForwardModel& model, const laws::LawShape& shape,
            const inverse::FitData& data, const std::array<double, inverse::kParameterCount>& p) {
  const bool load = data.target == inverse::FitTarget::kLoad;
  const inverse::ForwardPrediction prediction =
      PredictData(model, shape, data, {p[inverse::kSigmaC], p[inverse::kJB], p[inverse::kJTipC]});
  const std::vector<double>& values = load ? data.load : data.R;
  const std::vector<double>& predicted = load ? prediction.load : prediction.R;
  const std::vector<double>& u = load ? data.load_uncertainty : data.R_uncertainty;
  if (!prediction.ok() || predicted.size() != values.size()) return INFINITY;
  double chi2 = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i)
    chi2 += std::pow((predicted[i] - values[i]) / (data.weighted() ? u[i] : 1.0), 2);
  return chi2;
}

// A separate fit's chi^2 at its bridged optimum (its starts' lowest): the
// summary's chi^2 is the flat model's where the fit found no bridging.
double OptimumChi2(const inverse::FitSummary& s) {
  double best = s.chi2;
  for (const inverse::StartResult& start : s.starts) best = std::min(best, start.cost);
  return best;
}

// What the joint fit keeps of a specimen's fit alone: its chi^2 at its
// bridged optimum, its data points and that optimum (its starts' lowest end).
struct AloneFit {
  double chi2 = INFINITY;
  int data_points = 0;
  std::array<double, inverse::kParameterCount> optimum = {NAN, NAN, NAN};
  AloneFit() = default;
  explicit AloneFit(const inverse::FitSummary& s)
      : chi2(OptimumChi2(s)), data_points(s.data_points) {
    if (const inverse::StartResult* best = BestStart(s)) optimum = best->end;
  }
};

// fit(j) for j < count: with several ranks, item j on rank j mod N and every
// rank receiving them all (doubles bit for bit); an Error on any rank is
// re-thrown on every rank (the first in rank order; field kRanksAgreeField),
// so all go on or none.
template <class Fit>
std::vector<AloneFit> Dealt(parallel::Communicator* ranks, std::size_t count, Fit&& fit) {
  std::vector<AloneFit> out(count);
  if (!ranks || ranks->size() == 1) {
    for (std::size_t j = 0; j < count; ++j) out[j] = fit(j);
    return out;
  }
  parallel::ByteWriter own;
  std::string error;
  ErrorKind kind = ErrorKind::kRuntime;
  for (std::size_t j = 0; j < count && error.empty(); ++j) {
    if (ranks->OwnerOf(j) != ranks->rank()) continue;
    try {
      out[j] = fit(j);
    } catch (const Error& e) {
      if (e.kind() == ErrorKind::kInterrupted) throw;
      error = e.what(), kind = e.kind();
    }
    own.Field(static_cast<std::uint64_t>(j));
    own.Field(out[j].chi2), own.Field(out[j].data_points), own.Field(out[j].optimum);
  }
  parallel::ByteWriter message;
  message.Field(error), message.Field(kind), message.Field(own.Take());
  const std::vector<std::string> all = ranks->AllGather(message.Take());
  for (int from = 0; from < static_cast<int>(all.size()); ++from) {
    parallel::ByteReader in(all[from], "joint-fit results", from);
    std::string their_error, fits;
    ErrorKind their_kind = ErrorKind::kRuntime;
    in.Field(their_error), in.Field(their_kind), in.Field(fits);
    if (!in.done()) in.Corrupt();
    if (!their_error.empty())
      throw Error(their_kind, fmt::format("rank {}: {}", from, their_error),
                  {.field = kRanksAgreeField});
    parallel::ByteReader items(fits, "joint-fit results", from);
    while (!items.done()) {
      std::uint64_t j = 0;
      items.Field(j);
      if (j >= count || ranks->OwnerOf(j) != from) items.Corrupt();
      items.Field(out[j].chi2), items.Field(out[j].data_points), items.Field(out[j].optimum);
    }
  }
  return out;
}

// The specimens' models and data, fitted alone once; joint fits of any
// subset of them (the whole campaign, then without flagged specimens).
class JointFitter {
 public:
  struct Result {
    inverse::FitSummary summary;
    inverse::ConsistencyTest consistency;
    std::vector<double> statistic, p_value;  // per member
  };

  // `ranks` (may be null): the job's ranks, each making this same joint fit.
  // `starts` (empty, or one per specimen): where each specimen's fit alone
  // starts (its own single fit's optimum; load-displacement records).
  // `shared`: the law parameters every specimen shares; the others (free in
  // `options`) are each specimen's own, profiled out of the joint model
  // (inverse::OwnParameterProfiledModel) and held fixed in the joint
  // optimiser's box, their values there unused.
  JointFitter(std::vector<const inverse::ForwardModel*> models, std::vector<inverse::FitData> data,
              laws::LawShape shape, inverse::FitOptions options, parallel::Communicator* ranks,
              std::vector<std::array<double, inverse::kParameterCount>> starts = {},
              inverse::SharedParameters shared = inverse::kAllShared)
      : models_(std::move(models)),
        data_(std::move(data)),
        shape_(std::move(shape)),
        options_(std::move(options)),
        ranks_(ranks) {
    options_.outlier_threshold = 0.0;  // like with like: the same points alone and together
    options_.ranks = ranks;            // the joint fits' starts and profiles dealt over the ranks
    alone_ = options_;
    alone_.profile_likelihood = false;
    alone_.progress = false;
    alone_.ranks = nullptr;  // a fit alone runs on one rank (Dealt)
    for (int i = 0; i < inverse::kParameterCount; ++i) {
      own_[i] = !shared[i] && !options_.fixed[i];  // a parameter the user fixed stays fixed for all
      alone_free_ += !options_.fixed[i];
      if (!own_[i]) continue;
      options_.fixed[i] = true;  // profiled inside the joint model: the value is not used
      options_.fixed_value[i] = std::sqrt(options_.lower[i] * options_.upper[i]);
    }
    for (int i = 0; i < inverse::kParameterCount; ++i) free_ += !options_.fixed[i];
    BF_CHECK_INPUT(free_ > 0, "a joint fit needs at least one shared parameter that is not fixed",
                   {.field = "joint", .value = inverse::SharedParametersText(shared)});
    std::vector<inverse::FitData> parts = data_;
    std::vector<double> offsets;
    weighted_ = inverse::JoinFitData(parts, &offsets).weighted();
    // Uncertainties dropped for all when one specimen lacks them.
    for (inverse::FitData& d : data_)
      if (!weighted_) d.R_uncertainty.clear(), d.load_uncertainty.clear();
    const std::vector<AloneFit> alone = Dealt(ranks_, models_.size(), [&](std::size_t k) {
      inverse::FitOptions own = alone_;
      if (k < starts.size())
        for (int i = 0; i < inverse::kParameterCount; ++i)
          if (!own.fixed[i] && std::isfinite(starts[k][i])) own.initial[i] = starts[k][i];
      return AloneFit(inverse::FitBridgingLaw(*models_[k], shape_, data_[k], own));
    });
    for (const AloneFit& a : alone) {
      chi2_.push_back(a.chi2);
      dof_.push_back(std::max(1, a.data_points - alone_free_));
      optima_.push_back(a.optimum);
    }
    if (!data_.empty() && data_.front().target == inverse::FitTarget::kLoad) ScaleByOwnNoise();
    // The value an own parameter is held at in the optimiser's box: unused by
    // the profiled models, but the fit's checks read it (e.g. the bridging
    // rise over J_tip,c): the specimens' own optima's geometric mean.
    for (int i = 0; i < inverse::kParameterCount; ++i) {
      if (!own_[i]) continue;
      double sum = 0.0;
      int count = 0;
      for (const auto& optimum : optima_)
        if (optimum[i] > 0.0 && std::isfinite(optimum[i])) sum += std::log(optimum[i]), ++count;
      if (count > 0) options_.fixed_value[i] = std::exp(sum / count);
    }
    joint_models_ = Profiled(models_, &own_models_);
  }

  // `models` (one per specimen, any may be null) with each specimen's own
  // parameters profiled out, the wrappers kept in `keep`; as they are when
  // every parameter is shared.
  std::vector<const inverse::ForwardModel*> Profiled(
      const std::vector<const inverse::ForwardModel*>& models,
      std::vector<std::unique_ptr<inverse::OwnParameterProfiledModel>>* keep) const {
    if (!any_own()) return models;
    std::vector<const inverse::ForwardModel*> out;
    for (std::size_t k = 0; k < models.size(); ++k) {
      if (!models[k]) {
        out.push_back(nullptr);
        continue;
      }
      keep->push_back(std::make_unique<inverse::OwnParameterProfiledModel>(
          *models[k], data_[k], shared(), options_.lower, options_.upper, optima_[k]));
      out.push_back(keep->back().get());
    }
    return out;
  }

  Result Fit(const std::vector<std::size_t>& members) {
    std::vector<const inverse::ForwardModel*> models;
    std::vector<inverse::FitData> parts;
    std::vector<std::size_t> counts;
    for (std::size_t k : members)
      models.push_back(joint_models_[k]), parts.push_back(data_[k]), counts.push_back(data_[k].size());
    std::vector<double> offsets;
    const inverse::FitData joined = inverse::JoinFitData(parts, &offsets);
    const inverse::JointForwardModel joint(models, counts, offsets);
    // First start: the members' own optimum the joined data like best (the
    // joint optimum usually lies near one; a start read off the joined R
    // curves alone ended in a local minimum on the bundled DCBs).
    inverse::FitOptions options = options_;
    double best_chi2 = INFINITY;
    for (std::size_t k : members) {
      const double chi2 = Chi2(joint, shape_, joined, optima_[k]);
      if (chi2 < best_chi2) {
        best_chi2 = chi2;
        for (int i = 0; i < inverse::kParameterCount; ++i)
          if (!options.fixed[i]) options.initial[i] = optima_[k][i];
      }
    }
    Result r;
    r.summary = inverse::FitBridgingLaw(joint, shape_, joined, options);
    const inverse::StartResult* best = BestStart(r.summary);
    // Each member alone also from the joint optimum: a separate fit that
    // stopped above it would shrink the likelihood ratio (no power).
    if (best) {
      inverse::FitOptions from_joint = alone_;
      for (int i = 0; i < inverse::kParameterCount; ++i)
        if (!options_.fixed[i] && std::isfinite(best->end[i])) from_joint.initial[i] = best->end[i];
      const std::vector<AloneFit> again = Dealt(ranks_, members.size(), [&](std::size_t j) {
        const std::size_t k = members[j];
        inverse::FitOptions own = from_joint;  // its own parameters from its own optimum
        for (int i = 0; i < inverse::kParameterCount; ++i)
          if (own_[i] && std::isfinite(optima_[k][i])) own.initial[i] = optima_[k][i];
        return AloneFit(inverse::FitBridgingLaw(*models_[k], shape_, data_[k], own));
      });
      for (std::size_t j = 0; j < members.size(); ++j)
        chi2_[members[j]] = std::min(chi2_[members[j]], again[j].chi2);
    }
    std::vector<double> chi2;
    std::vector<int> dof;
    for (std::size_t k : members) chi2.push_back(chi2_[k]), dof.push_back(dof_[k]);
    // Like with like: the joint fit's bridged optimum too (its summary's chi^2 is the
    // flat model's where it found no bridging, the fits alone's their bridged ones).
    r.consistency = inverse::TestConsistency(OptimumChi2(r.summary), chi2, dof, free_, weighted_);
    // Each member's chi^2 at the joint law over its own optimum's.
    for (std::size_t k : members) {
      const double at_joint = best ? Chi2(*joint_models_[k], shape_, data_[k], best->end) : NAN;
      const double statistic = std::max(0.0, at_joint - chi2_[k]) / r.consistency.noise_scale2;
      r.statistic.push_back(statistic);
      r.p_value.push_back(inverse::ChiSquareSurvival(statistic, free_));
    }
    // The verdict per specimen: which reached steady state at the joint law.
    // (A load fit's crack lengths are already the specimens' own: the
    // model's physical ones.)
    if (joined.target != inverse::FitTarget::kLoad) {
      r.summary.fitted_crack_length.clear();
      for (const inverse::FitData& d : parts)
        r.summary.fitted_crack_length.insert(r.summary.fitted_crack_length.end(),
                                             d.crack_length.begin(), d.crack_length.end());
    }
    r.summary.steady_state_crack_length = NAN;  // one per specimen
    if (r.summary.steady_state_reached) {
      const inverse::ForwardPrediction p =
          PredictData(joint, shape_, joined, inverse::FittedLaw(r.summary));
      std::vector<std::size_t> reached;
      std::size_t start = 0;
      for (std::size_t j = 0; j < members.size(); start += counts[j], ++j)
        for (std::size_t i = start; i < start + counts[j] && i < p.past_steady_state.size(); ++i)
          if (p.past_steady_state[i]) {
            reached.push_back(j);
            break;
          }
      reached_ = reached;
    }
    return r;
  }
  // The model error of `fit` (the joint fit of `members`) from each
  // member's model at r h and r^2 h (`coarse`, `coarser`: one per specimen
  // of the fitter, null where it has none), as a single fit's.
  inverse::ModelErrorEstimate ModelError(
      const std::vector<std::size_t>& members,
      const std::vector<std::unique_ptr<inverse::ForwardModel>>& coarse,
      const std::vector<std::unique_ptr<inverse::ForwardModel>>& coarser, double resolution,
      const inverse::FitSummary& fit) const {
    std::vector<const inverse::ForwardModel*> at_h, at_2h, at_4h, coarse_all, coarser_all;
    for (std::size_t k = 0; k < models_.size(); ++k)
      coarse_all.push_back(coarse[k].get()), coarser_all.push_back(coarser[k].get());
    // Each specimen's own parameters profiled at the coarser sizes too.
    std::vector<std::unique_ptr<inverse::OwnParameterProfiledModel>> keep;
    coarse_all = Profiled(coarse_all, &keep);
    coarser_all = Profiled(coarser_all, &keep);
    std::vector<inverse::FitData> parts;
    std::vector<std::size_t> counts;
    bool have_coarse = true, have_coarser = true;
    for (std::size_t k : members) {
      at_h.push_back(joint_models_[k]), at_2h.push_back(coarse_all[k]), at_4h.push_back(coarser_all[k]);
      have_coarse = have_coarse && coarse[k];
      have_coarser = have_coarser && coarser[k];
      parts.push_back(data_[k]), counts.push_back(data_[k].size());
    }
    std::vector<double> offsets;
    const inverse::FitData joined = inverse::JoinFitData(parts, &offsets);
    const inverse::JointForwardModel joint(at_h, counts, offsets);
    std::optional<inverse::JointForwardModel> joint_2h, joint_4h;
    if (have_coarse) joint_2h.emplace(at_2h, counts, offsets);
    if (have_coarse && have_coarser) joint_4h.emplace(at_4h, counts, offsets);
    // Every rank makes the same local fits (deterministic): not dealt.
    inverse::FitOptions options = options_;
    options.ranks = nullptr;
    options.progress = false;
    return inverse::EstimateModelError(joint, joint_2h ? &*joint_2h : nullptr,
                                       joint_4h ? &*joint_4h : nullptr, resolution, shape_, joined,
                                       options, fit);
  }
  // Each specimen's own noise scale s_k^2 (its chi^2 alone over its dof)
  // in its load uncertainties: records of different specimens carry loads of
  // different size and noise (and model error), so each row is weighted by
  // its own specimen's scatter about its own optimum, as the single fit's
  // intervals are (s_k^2 there). Each chi^2 alone becomes its dof; the
  // joint chi^2 and the likelihood ratio are then in these units (weighted).
  void ScaleByOwnNoise() {
    for (std::size_t k = 0; k < data_.size(); ++k) {
      const double s2 = chi2_[k] / dof_[k];
      if (!(std::isfinite(s2) && s2 > 0.0)) continue;  // a failed fit alone: left as it is
      inverse::FitData& d = data_[k];
      if (d.load_uncertainty.empty()) d.load_uncertainty.assign(d.load.size(), 1.0);
      for (double& u : d.load_uncertainty) u *= std::sqrt(s2);
      chi2_[k] /= s2;
    }
    weighted_ = true;
  }
  // Members (positions in the last Fit's list) past steady state at its law.
  const std::vector<std::size_t>& reached() const { return reached_; }
  int free() const { return free_; }
  inverse::SharedParameters shared() const {
    return {!own_[0], !own_[1], !own_[2]};
  }
  bool any_own() const { return own_[0] || own_[1] || own_[2]; }
  // Specimen k's model with its own parameters profiled (its model as it is
  // when all are shared), its data as the joint fit weighs it, the joint
  // fit's options and a fit alone's.
  const inverse::ForwardModel& joint_model(std::size_t k) const { return *joint_models_[k]; }
  const inverse::ForwardModel& model(std::size_t k) const { return *models_[k]; }
  const inverse::FitData& data(std::size_t k) const { return data_[k]; }
  const inverse::FitOptions& options() const { return options_; }
  const inverse::FitOptions& alone_options() const { return alone_; }

 private:
  std::vector<const inverse::ForwardModel*> models_;
  std::vector<inverse::FitData> data_;
  laws::LawShape shape_;
  inverse::FitOptions options_, alone_;
  parallel::Communicator* ranks_ = nullptr;
  int free_ = 0, alone_free_ = 0;
  std::array<bool, inverse::kParameterCount> own_ = {false, false, false};
  std::vector<std::unique_ptr<inverse::OwnParameterProfiledModel>> own_models_;
  std::vector<const inverse::ForwardModel*> joint_models_;  // own parameters profiled
  bool weighted_ = false;
  std::vector<double> chi2_;  // each specimen alone, at its lowest optimum found
  std::vector<int> dof_;
  std::vector<std::array<double, inverse::kParameterCount>> optima_;
  std::vector<std::size_t> reached_;
};

std::string Names(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
  return text;
}

// Who carries each shared parameter of the fit of every specimen (its
// final intervals; the specimens past steady state at its law: the fitter's
// last fit), and each specimen's own values of the others.
void CarriersAndOwnValues(const JointFitter& fitter, const std::vector<const FitRun*>& runs,
                          const std::vector<std::string>& names, JointFitRun& out) {
  std::vector<bool> past(runs.size(), false);
  if (out.summary.steady_state_reached)
    for (std::size_t j : fitter.reached()) past[j] = true;
  out.carriers = detail::Carriers(names, runs, out.summary, past, out.shared);
  if (!fitter.any_own()) return;
  std::vector<const inverse::ForwardModel*> own_base, own_profiled;
  std::vector<inverse::FitData> own_data;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    own_base.push_back(&fitter.model(k));
    own_profiled.push_back(&fitter.joint_model(k));
    own_data.push_back(fitter.data(k));
  }
  out.own_values = detail::OwnValues(names, own_base, own_profiled, own_data, out.shape,
                                     out.summary, fitter.alone_options(), out.shared);
}

}  // namespace

JointFitRun RunJointFit(const std::vector<FitRequest>& requests,
                        const std::vector<const FitRun*>& runs,
                        const std::vector<std::string>& names, parallel::Communicator* ranks,
                        const inverse::SharedParameters& shared) {
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
  std::vector<inverse::FitData> parts;
  std::vector<std::array<double, inverse::kParameterCount>> starts;
  std::vector<std::unique_ptr<inverse::ModulusProfiledLoadModel>> profiled;
  std::vector<double> calibrated_factor, held_series;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const std::string why = CannotJoin(requests[k], *runs[k], *runs.front());
    BF_CHECK_INPUT(why.empty(), "specimen '" + names[k] + "' cannot join the joint fit: " + why,
                   {.file = requests[k].input_path, .field = "joint fit"});
    FitRequest& r = rebuilt.emplace_back(requests[k]);
    if (r.model == ModelChoice::kAuto) r.model = ModelChoice::kReduced;
    r.resolution = runs[k]->resolution;
    const bool load = runs[k]->load_data.has_value();
    models.push_back(std::make_unique<FitModels>(r, runs[k]->input, runs[k]->data, load,
                                                 runs[k]->r_kind));
    if (!load) {
      models.back()->Build(1.0, 0.0);
      model_of.push_back(&models.back()->model());
      parts.push_back(runs[k]->data);
      continue;
    }
    // A load record's nuisance parameters: its modulus scale, profiled out
    // at every law from its own fit's calibrated value (the model built
    // there), and its series compliance, held at its own fit's value.
    const inverse::ComplianceCalibrationResult& c = runs[k]->calibration;
    const double f0 = c.calibrated() ? c.modulus_factor : 1.0;
    models.back()->Build(f0, 0.0);
    const auto* base = dynamic_cast<const inverse::SimulationForwardModel*>(&models.back()->model());
    BF_CHECK_INPUT(base != nullptr,
                   "specimen '" + names[k] + "' cannot join the joint fit: its model (" +
                       models.back()->model().Name() + ") gives no load-displacement record",
                   {.file = requests[k].input_path, .field = "joint fit"});
    held_series.push_back(c.calibrated() ? c.series_compliance : 0.0);
    profiled.push_back(std::make_unique<inverse::ModulusProfiledLoadModel>(
        *base, held_series.back(), *runs[k]->load_data));
    model_of.push_back(profiled.back().get());
    parts.push_back(*runs[k]->load_data);
    starts.push_back(runs[k]->summary.best_parameters);
    calibrated_factor.push_back(f0);
  }
  JointFitter fitter(model_of, parts, out.shape, requests.front().fit, ranks, starts, shared);
  out.shared = fitter.shared();
  std::vector<std::size_t> members(runs.size());
  for (std::size_t k = 0; k < members.size(); ++k) members[k] = k;
  const JointFitter::Result all = fitter.Fit(members);
  out.summary = all.summary;
  // The joint model's own error, each specimen coarsened from its own size
  // (a load record's coarser model with its modulus scale profiled too: it
  // is re-calibrated at that size, as a single fit's model error does).
  std::vector<std::unique_ptr<inverse::ForwardModel>> coarse, coarser, coarse_bases;
  const auto coarsened = [&](std::size_t k, double size) -> std::unique_ptr<inverse::ForwardModel> {
    std::unique_ptr<inverse::ForwardModel> m = models[k]->ReducedAt(size);
    if (!m || profiled.empty()) return m;
    const auto* base = dynamic_cast<const inverse::SimulationForwardModel*>(m.get());
    if (!base) return nullptr;
    auto wrapped = std::make_unique<inverse::ModulusProfiledLoadModel>(*base, held_series[k],
                                                                       *runs[k]->load_data);
    coarse_bases.push_back(std::move(m));
    return wrapped;
  };
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const double h = runs[k]->resolution;
    coarse.push_back(std::isfinite(h) ? coarsened(k, 2.0 * h) : nullptr);
    coarser.push_back(std::isfinite(h) ? coarsened(k, 4.0 * h) : nullptr);
  }
  out.model_error =
      fitter.ModelError(members, coarse, coarser, runs.front()->resolution, out.summary);
  inverse::ApplyModelError(out.model_error, out.summary);
  CarriersAndOwnValues(fitter, runs, names, out);
  out.consistency = all.consistency;
  out.specimen_statistic = all.statistic;
  out.specimen_p_value = all.p_value;
  // Each load record's modulus factor at the joint law (its calibrated f0 x g).
  if (!profiled.empty()) {
    const inverse::LawParameters at = inverse::FittedLaw(out.summary);
    for (std::size_t k = 0; k < profiled.size(); ++k) {
      // With its own parameters at their values at the joint law.
      const auto* own = dynamic_cast<const inverse::OwnParameterProfiledModel*>(&fitter.joint_model(k));
      const inverse::LawParameters law = own ? own->Profiled(out.shape, at) : at;
      out.specimen_modulus_factor.push_back(calibrated_factor[k] *
                                            profiled[k]->ProfiledScale(out.shape, law));
      out.specimen_calibrated_modulus_factor.push_back(calibrated_factor[k]);
    }
  }
  // The verdict of a joint fit of `members` past steady state names the
  // specimens that reach it (one steady-state crack length per specimen).
  const auto name_reached = [&](const std::vector<std::size_t>& of, inverse::FitSummary& fit) {
    if (!fit.steady_state_reached) return;
    std::vector<std::string> reached;
    for (std::size_t j : fitter.reached()) reached.push_back(names[of[j]]);
    fit.verdict = fmt::format(
        "steady state reached at the joint law inside the windows of {}: all parameters estimated "
        "(a specimen's own lower bound on J_B holds at its own J_tip,c)",
        reached.empty() ? std::string("(none at the optimum)") : Names(reached));
  };
  name_reached(members, out.summary);
  // Not one law: the specimen the joint law misses most is set aside and the
  // rest fitted again, until the rest is consistent or two are left. One
  // specimen of another law pulls the joint law off the others too, so the
  // worst is taken one at a time rather than every p below a limit.
  JointFitter::Result rest = all;
  while (std::isfinite(rest.consistency.p_value) && !rest.consistency.consistent() &&
         members.size() >= 3) {
    const std::size_t worst =
        std::max_element(rest.statistic.begin(), rest.statistic.end()) - rest.statistic.begin();
    out.flagged.push_back(names[members[worst]]);
    members.erase(members.begin() + static_cast<std::ptrdiff_t>(worst));
    rest = fitter.Fit(members);
    name_reached(members, rest.summary);
  }
  if (!out.flagged.empty()) {
    out.consistency_without_flagged = rest.consistency;
    out.summary_without_flagged = rest.summary;
    inverse::ApplyModelError(
        fitter.ModelError(members, coarse, coarser, runs.front()->resolution, rest.summary),
        *out.summary_without_flagged);
    detail::MarkOwnEstimates(out.shared, *out.summary_without_flagged);
    std::vector<std::string> rest_names;
    std::vector<const FitRun*> rest_runs;
    for (std::size_t k : members) rest_names.push_back(names[k]), rest_runs.push_back(runs[k]);
    std::vector<bool> rest_past(members.size(), false);
    if (rest.summary.steady_state_reached)
      for (std::size_t j : fitter.reached()) rest_past[j] = true;
    out.carriers_without_flagged =
        detail::Carriers(rest_names, rest_runs, *out.summary_without_flagged, rest_past, out.shared);
  }
  detail::MarkOwnEstimates(out.shared, out.summary);
  out.wall_s = clock.Seconds();
  return out;
}

}  // namespace bridgefit::pipeline
