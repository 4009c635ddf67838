// --resolution auto (include/bridgefit/inverse/resolution.hpp).

#include "bridgefit/inverse/resolution.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "bridgefit/core/progress.hpp"
#include "fit_impl.hpp"

namespace bridgefit::inverse {

using namespace fit_internal;

bool ResolutionOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!(bias_fraction > 0.0)) return fail("bias_fraction must be positive");
  if (!(coarsest > 0.0 && finest > 0.0 && finest <= coarsest))
    return fail("need 0 < finest <= coarsest element size");
  if (std::string error_why; !error.IsValid(&error_why)) return fail(error_why);
  return true;
}

namespace {

// One rung of the ladder: the fit re-run locally from the pilot's
// parameters with the model at `h`, and the statistical standard
// uncertainties there.
struct Rung {
  bool ok = false;
  std::string note;
  std::vector<double> estimate;  // free parameters, SI
  std::vector<double> sd;
};

Rung EvaluateRung(const ForwardModel* model, const laws::LawShape& shape, const FitData& used,
                  const FitOptions& answer, const std::array<double, kParameterCount>& at,
                  double scale2, int* runs) {
  Rung rung;
  if (!model) {
    rung.note = "the geometry does not take this element size";
    return rung;
  }
  const Objective objective(*model, shape, used, answer);
  const std::vector<int>& free = objective.free();
  std::vector<double> x0;
  for (int index : free) x0.push_back(ToBox(index, at[index], answer));
  const LocalResult result =
      MinimizeLocal(objective, Optimizer::kBobyqa, x0, answer.max_evaluations);
  if (result.chi2 >= kFailedCost) {
    *runs += objective.evaluations();
    rung.note = "every run failed: " + objective.last_failure();
    return rung;
  }
  const std::vector<double> full = objective.Expand(result.x.data());
  for (int index : free) rung.estimate.push_back(full[index]);
  rung.sd.assign(free.size(), NAN);
  Eigen::MatrixXd jacobian;
  if (PhysicalJacobian(objective, full, &jacobian)) {
    const Eigen::MatrixXd jtj = jacobian.transpose() * jacobian;
    const Eigen::MatrixXd covariance = scale2 * jtj.completeOrthogonalDecomposition().pseudoInverse();
    for (std::size_t k = 0; k < free.size(); ++k) rung.sd[k] = std::sqrt(covariance(k, k));
  }
  *runs += objective.evaluations();
  rung.ok = true;
  return rung;
}

// rms of the predicted bias of the model at h (the coarse model's prediction
// minus the fine one's over the Richardson denominator) in noise standard
// deviations; NaN where a run fails.
double OutputBiasInNoise(const ForwardModel* fine, const ForwardModel* coarse,
                         const laws::LawShape& shape, const FitData& used, const LawParameters& p,
                         double scale2, double denominator) {
  if (!fine || !coarse) return NAN;
  std::string why;
  const std::vector<double> y_h = PredictAt(*fine, shape, p, used, &why);
  const std::vector<double> y_2h = PredictAt(*coarse, shape, p, used, &why);
  if (y_h.empty() || y_2h.empty()) return NAN;
  std::vector<double> bias(y_h.size());
  for (std::size_t i = 0; i < y_h.size(); ++i) bias[i] = (y_2h[i] - y_h[i]) / denominator;
  return NoiseRelative(bias, used, scale2)[0];
}

// The ladder of sizes s_j = coarsest r^(2 - j) (candidates j >= 2), each
// level judged against its coarser size (or, where that solve fails, the
// finer one), in named stages: Rung, Judge, JudgeFromCoarser,
// JudgeFromFiner, Level.
class Ladder {
 public:
  Ladder(const ModelAtResolution& model_at, const laws::LawShape& shape, const FitData& used,
         const FitOptions& answer, const std::array<double, kParameterCount>& at,
         std::vector<int> free, std::vector<bool> checked, double scale2,
         const ResolutionOptions& o, int* runs)
      : model_at_(model_at), shape_(shape), used_(used), answer_(answer), at_(at),
        free_(std::move(free)), checked_(std::move(checked)), scale2_(scale2), o_(o),
        r_(o.error.refinement_ratio), runs_(runs) {}

  double Size(int j) const { return o_.coarsest * std::pow(r_, 2 - j); }

  // Level j, judged; `finest` when no finer size is inside the limits.
  ResolutionLevel Level(int j, bool finest) {
    const double h = Size(j);
    ResolutionLevel level;
    level.resolution = h;
    const Rung& fine = RungAt(j);
    level.evaluated = fine.ok;
    if (!fine.ok) {
      level.note = fine.note;
      return level;
    }
    for (std::size_t k = 0; k < free_.size(); ++k) {
      level.estimate[free_[k]] = fine.estimate[k];
      level.sd[free_[k]] = fine.sd[k];
    }
    const Rung& coarse = RungAt(j - 1);
    const Rung& coarser = RungAt(j - 2);
    if (!coarse.ok && !finest) {
      JudgeFromFiner(level, fine, RungAt(j + 1),
                     fmt::format("the {:.3g} mm solve: {}", r_ * h * 1e3, coarse.note));
    } else if (!coarse.ok) {
      level.note = fmt::format("the {:.3g} mm solve: {}", r_ * h * 1e3, coarse.note);
    } else {
      JudgeFromCoarser(level, fine, coarse, coarser);
    }
    return level;
  }

 private:
  // The rung at size j, solved once.
  const Rung& RungAt(int j) {
    auto found = rungs_.find(j);
    if (found != rungs_.end()) return found->second;
    return rungs_[j] =
               EvaluateRung(model_at_(Size(j)), shape_, used_, answer_, at_, scale2_, runs_);
  }

  struct Judged {
    std::string worst, predicted;
  };
  // A level judged against one other size (the coarser r h, or the finer
  // h / r): beta = (p_other - p_h) / denominator for each estimate, each
  // |beta| x widen against bias_fraction x its sd, and the prediction's bias
  // in the data (kOutputBiasNoiseLimit). Sets level.bias and
  // level.output_bias_noise_rms, clears level.meets where a test fails;
  // returns the largest ratio's text and the data-bias text.
  Judged Judge(ResolutionLevel& level, const Rung& fine, const Rung& other, double other_h,
               double denominator, double widen) const {
    Judged out;
    double worst_ratio = 0.0;
    std::string worst;
    for (std::size_t k = 0; k < free_.size(); ++k) {
      const double bias = (other.estimate[k] - fine.estimate[k]) / denominator;
      level.bias[free_[k]] = bias;
      if (!checked_[k]) continue;
      const double ratio = widen * std::abs(bias) / fine.sd[k];
      if (!(ratio <= o_.bias_fraction)) level.meets = false;
      if (!(ratio <= worst_ratio)) {
        worst_ratio = ratio;
        worst = ParameterName(free_[k]);
      }
    }
    out.worst = fmt::format("largest bias {:.2g} sd ({})", worst_ratio, worst);
    // The model's own error where the data can see it: a prediction whose
    // bias exceeds the noise can move a verdict (bridging, steady state)
    // that the estimates' Richardson terms do not show.
    std::array<double, kParameterCount> p = at_;
    for (std::size_t k = 0; k < free_.size(); ++k) p[free_[k]] = fine.estimate[k];
    const double noise_rms = OutputBiasInNoise(
        model_at_(level.resolution), model_at_(other_h), shape_, used_,
        {p[kSigmaC], p[kJB], p[kJTipC]}, used_.weighted() ? 1.0 : scale2_, denominator);
    level.output_bias_noise_rms = noise_rms;
    if (std::isfinite(noise_rms)) {
      out.predicted = fmt::format("; predicted {} bias {:.2g} noise sd rms",
                                  used_.target == FitTarget::kLoad ? "load" : "R", noise_rms);
      if (noise_rms > kOutputBiasNoiseLimit) level.meets = false;
    }
    return out;
  }

  // Richardson against the coarser size r h, the order observed from r^2 h
  // where that solve ran.
  void JudgeFromCoarser(ResolutionLevel& level, const Rung& fine, const Rung& coarse,
                        const Rung& coarser) const {
    const double h = level.resolution;
    std::vector<double> move_fine, move_coarse;
    for (std::size_t k = 0; k < free_.size(); ++k) {
      const double scale = std::isfinite(fine.sd[k]) && fine.sd[k] > 0 ? fine.sd[k]
                                                                      : std::abs(fine.estimate[k]);
      move_fine.push_back((coarse.estimate[k] - fine.estimate[k]) / scale);
      if (coarser.ok) move_coarse.push_back((coarser.estimate[k] - coarse.estimate[k]) / scale);
    }
    const OrderChoice order = ChooseOrder(
        move_fine, move_coarse,
        coarser.ok ? std::string()
                   : fmt::format("the {:.3g} mm solve: {}", r_ * r_ * h * 1e3, coarser.note),
        o_.error);
    level.status = order.observed || order.no_difference ? ModelErrorStatus::kEstimated
                                                         : ModelErrorStatus::kOrderNotObserved;
    level.meets = level.status == ModelErrorStatus::kEstimated;
    const Judged judged = Judge(level, fine, coarse, r_ * h, order.denominator, 1.0);
    level.note = (level.status == ModelErrorStatus::kEstimated
                      ? judged.worst
                      : "order not observed: " + order.problem) +
                 judged.predicted;
  }

  // A size whose coarser solve fails (a DCB arm too coarse for Newton
  // there) is judged from the next finer solve instead, as the model error
  // does (model_error.hpp): the order assumed, beta = (p_h/r - p_h) /
  // (r^-p - 1), and the criterion on beta times F_s(assumed) / F_s(observed)
  // (the wider safety factor of the total interval it would get).
  void JudgeFromFiner(ResolutionLevel& level, const Rung& fine, const Rung& finer,
                      const std::string& coarse_failure) const {
    const double widen = o_.error.unverified_safety_factor / o_.error.safety_factor;
    level.status = ModelErrorStatus::kOrderNotObserved;
    const double h = level.resolution;
    if (!finer.ok) {
      level.note = coarse_failure + fmt::format("; the finer {:.3g} mm solve: {}", h / r_ * 1e3,
                                                finer.note);
      return;
    }
    level.meets = true;
    const Judged j =
        Judge(level, fine, finer, h / r_, std::pow(r_, -o_.error.assumed_order) - 1.0, widen);
    level.note = coarse_failure +
                 fmt::format("; judged from the finer {:.3g} mm solve, order {:g} assumed: {} with "
                             "the x{:.3g} of the assumed order's safety factor",
                             h / r_ * 1e3, o_.error.assumed_order, j.worst, widen) +
                 j.predicted;
  }

  const ModelAtResolution& model_at_;
  const laws::LawShape& shape_;
  const FitData& used_;
  const FitOptions& answer_;
  const std::array<double, kParameterCount>& at_;
  const std::vector<int> free_;
  const std::vector<bool> checked_;
  const double scale2_;
  const ResolutionOptions& o_;
  const double r_;
  int* runs_;
  std::map<int, Rung> rungs_;
};

}  // namespace

ResolutionChoice ChooseResolution(const ModelAtResolution& model_at, const laws::LawShape& shape,
                                  const FitData& data, const FitOptions& options,
                                  const FitSummary& pilot, const ResolutionOptions& o) {
  const Stopwatch clock;
  ResolutionChoice choice;
  std::string why;
  if (!o.IsValid(&why)) {
    choice.resolution = o.finest;
    choice.reason = "invalid options (" + why + "): the finest size taken";
    return choice;
  }
  std::array<double, kParameterCount> at{};
  const FitOptions answer = AnswerParameters(options, pilot, &at);
  const FitData used = RowsUsed(data, pilot);
  std::vector<int> free;
  for (int i = 0; i < kParameterCount; ++i)
    if (!answer.fixed[i]) free.push_back(i);
  // The estimates the criterion is on: those the pilot reported as values
  // (J_B only past steady state; a bound carries no interval).
  const ParameterEstimate* pilot_estimates[] = {&pilot.sigma_c, &pilot.J_B, &pilot.J_tip_c};
  std::vector<bool> checked;
  for (int index : free)
    checked.push_back(pilot_estimates[index]->identified && std::isfinite(pilot_estimates[index]->value));
  if (free.empty() || !std::isfinite(at[kJTipC])) {
    choice.resolution = o.coarsest;
    choice.criterion_met = true;
    choice.reason = "no estimate depends on the model (the coarsest valid size)";
    choice.wall_s = clock.Seconds();
    return choice;
  }
  const double scale2 =
      std::isfinite(pilot.noise_scale2)
          ? pilot.noise_scale2
          : (used.weighted() ? std::max(1.0, pilot.reduced_chi2) : pilot.reduced_chi2);

  Ladder ladder(model_at, shape, used, answer, at, free, checked, scale2, o, &choice.runs);
  const double r = o.error.refinement_ratio;
  for (int j = 2;; ++j) {
    const double h = ladder.Size(j);
    const bool finest = h / r < o.finest * (1.0 - 1e-9);
    const ResolutionLevel level = ladder.Level(j, finest);
    choice.levels.push_back(level);
    if (level.meets || finest) {
      choice.resolution = h;
      choice.criterion_met = level.meets;
      choice.reason =
          level.meets
              ? fmt::format("{:.3g} mm: predicted bias within {:g} of each statistical standard "
                            "uncertainty and of the data within {:g} noise sd ({})",
                            h * 1e3, o.bias_fraction, kOutputBiasNoiseLimit, level.note)
              : fmt::format("{:.3g} mm, the finest tried: the criterion (bias <= {:g} sd, "
                            "predicted data bias <= {:g} noise sd) is not met ({}); the model "
                            "error is in the total interval",
                            h * 1e3, o.bias_fraction, kOutputBiasNoiseLimit, level.note);
      break;
    }
  }
  choice.wall_s = clock.Seconds();
  return choice;
}

}  // namespace bridgefit::inverse
