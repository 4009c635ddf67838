// The model error in every interval (issue 17, inverse/model_error.hpp),
// against oracles: the bias predicted from two coarser solves against the
// actual difference from a much finer solve, and the predicted parameter
// bias against the actual error of a fit to data made by the finer model.
// Cases made here (not the issue's): CT and DCB, isotropic and orthotropic,
// linear, exponential and cubic laws.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <memory>

#include <fmt/format.h>

#include "bridgefit/inverse/model_error.hpp"
#include "bridgefit/inverse/reduced_forward.hpp"
#include "bridgefit/inverse/resolution.hpp"
#include "bridgefit/models/reduced.hpp"

namespace bridgefit::inverse {
namespace {

Scene Ct(bool orthotropic) {
  Scene s;
  s.source = "model_error_test CT";
  s.specimen.type = SpecimenType::kCT;
  s.specimen.width = 0.040;
  s.specimen.height = 0.048;
  s.specimen.thickness = 0.010;
  s.specimen.notch = 0.016;
  s.specimen.plane = PlaneCondition::kPlaneStress;
  if (orthotropic) {
    s.material.orthotropic = true;
    s.material.E1 = 11e9;
    s.material.E2 = 0.9e9;
    s.material.G12 = 0.75e9;
    s.material.nu12 = 0.35;
  } else {
    s.material.E = 4e9;
    s.material.nu = 0.3;
  }
  return s;
}

Scene Dcb(bool orthotropic) {
  Scene s;
  s.source = "model_error_test DCB";
  s.specimen.type = SpecimenType::kDCB;
  s.specimen.width = 0.025;
  s.specimen.height = orthotropic ? 0.008 : 0.010;
  s.specimen.length = 0.200;
  s.specimen.notch = 0.045;
  s.specimen.plane = PlaneCondition::kPlaneStress;
  if (orthotropic) {
    s.material.orthotropic = true;
    s.material.E1 = 40e9;
    s.material.E2 = 8e9;
    s.material.G12 = 3e9;
    s.material.nu12 = 0.3;
  } else {
    s.material.E = 4e9;
    s.material.nu = 0.3;
  }
  return s;
}

std::unique_ptr<SimulationForwardModel> Model(const Scene& scene, double h, double a_max) {
  models::ReducedOptions options;
  options.mesh.resolution = h;
  options.mesh.max_crack_length = a_max;
  return MakeReducedForwardModel(scene, options);
}

struct Case {
  std::string name;
  Scene scene;
  laws::LawShape shape;
  LawParameters truth;
  double a_first, a_last;  // data window [m]
  double h;                // the fit's element size [m]
  double h_reference;      // the much finer solve [m]
};

// The four specimens with a law each; windows that reach steady state.
std::vector<Case> Cases() {
  return {
      {"CT isotropic, linear", Ct(false), laws::MakeLinearShape(), {1.2e6, 300.0, 800.0},
       0.0165, 0.027, 1e-3, 0.125e-3},
      {"CT orthotropic, exponential", Ct(true), laws::MakeExponentialShape(3.0),
       {1.5e6, 400.0, 300.0}, 0.0165, 0.027, 1e-3, 0.125e-3},
      {"DCB isotropic, linear", Dcb(false), laws::MakeLinearShape(), {0.8e6, 400.0, 1000.0},
       0.046, 0.090, 1e-3, 0.25e-3},
      {"DCB orthotropic, cubic", Dcb(true), laws::MakeCubicShape(), {2.0e6, 600.0, 400.0},
       0.046, 0.080, 1e-3, 0.25e-3},
  };
}

FitData Window(const Case& c) {
  FitData data;
  data.kind = RKind::kEnergy;
  for (double a = c.a_first; a <= c.a_last + 1e-12; a += 0.5e-3) data.crack_length.push_back(a);
  return data;
}

// R over the case's window from the much finer model at the truth, with
// 0.3% uncertainties (noise-free data); empty R when that run fails.
FitData NoiseFreeData(const Case& c) {
  const auto reference = Model(c.scene, c.h_reference, c.a_last + 2 * c.h);
  FitData data = Window(c);
  const ForwardPrediction truth = reference->Predict(c.shape, c.truth, data.crack_length, data.kind);
  EXPECT_TRUE(truth.ok()) << truth.message;
  if (!truth.ok()) return data;
  data.R = truth.R;
  for (double r : truth.R) data.R_uncertainty.push_back(0.003 * r);
  return data;
}

// Every identified estimate's total interval holds the case's truth;
// returns how many statistical intervals alone miss it.
int ExpectTotalsCoverTheTruth(const Case& c, const FitSummary& fit) {
  const double truths[] = {c.truth.sigma_c, c.truth.J_B, c.truth.J_tip_c};
  const ParameterEstimate* estimates[] = {&fit.sigma_c, &fit.J_B, &fit.J_tip_c};
  int statistical_misses = 0;
  for (int i = 0; i < kParameterCount; ++i) {
    const ParameterEstimate& p = *estimates[i];
    if (!p.identified || !std::isfinite(p.value)) continue;
    SCOPED_TRACE(ParameterName(i));
    std::cout << fmt::format(
        "  {}: error {:+.4g}, predicted bias {:+.4g}, total [{:.5g}, {:.5g}], statistical [{:.5g}, "
        "{:.5g}]\n",
        ParameterName(i), p.value - truths[i], p.model_bias, p.ci95_low, p.ci95_high,
        p.statistical_ci95_low, p.statistical_ci95_high);
    EXPECT_LE(p.ci95_low, truths[i]);
    EXPECT_GE(p.ci95_high, truths[i]);
    statistical_misses += truths[i] < p.statistical_ci95_low || truths[i] > p.statistical_ci95_high;
  }
  return statistical_misses;
}

double Rms(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x * x;
  return std::sqrt(sum / std::max<std::size_t>(1, v.size()));
}

// A case's models at h, 2h and 4h (each grown two of its elements past the
// data, as the pipeline's), its R over the window from the much finer solve
// at the truth, the model's R there at h and their difference, and a "fit"
// that landed on the truth: the error model at those parameters.
struct Ladder {
  std::unique_ptr<SimulationForwardModel> fine, coarse, coarser;
  FitData data;                // R of the much finer solve; no uncertainties yet
  std::vector<double> actual;  // R at h minus the much finer solve's
  FitSummary fit;
  bool ok = false;

  explicit Ladder(const Case& c)
      : fine(Model(c.scene, c.h, c.a_last + 2 * c.h)),
        coarse(Model(c.scene, 2 * c.h, c.a_last + 4 * c.h)),
        coarser(Model(c.scene, 4 * c.h, c.a_last + 8 * c.h)),
        data(Window(c)) {
    const auto reference = Model(c.scene, c.h_reference, c.a_last + 2 * c.h);
    const ForwardPrediction truth = reference->Predict(c.shape, c.truth, data.crack_length, data.kind);
    const ForwardPrediction at_h = fine->Predict(c.shape, c.truth, data.crack_length, data.kind);
    EXPECT_TRUE(truth.ok() && at_h.ok()) << truth.message << at_h.message;
    if (!truth.ok() || !at_h.ok()) return;
    data.R = truth.R;
    for (std::size_t i = 0; i < truth.R.size(); ++i) actual.push_back(at_h.R[i] - truth.R[i]);
    fit.target = FitTarget::kRCurve;
    fit.best_parameters = {c.truth.sigma_c, c.truth.J_B, c.truth.J_tip_c};
    fit.chi2 = 0.0;
    ok = true;
  }
  ModelErrorEstimate Estimate(const Case& c) const {
    return EstimateModelError(*fine, coarse.get(), coarser.get(), c.h, c.shape, data, FitOptions(),
                              fit);
  }
};

// The predicted bias of the model's R (from h, 2h, 4h) against its actual
// difference from the much finer solve, at the same parameters.
TEST(ModelError, PredictedRBiasMatchesAFinerSolve) {
  for (const Case& c : Cases()) {
    SCOPED_TRACE(c.name);
    Ladder ladder(c);
    ASSERT_TRUE(ladder.ok);
    for (double r : ladder.data.R) ladder.data.R_uncertainty.push_back(0.002 * r);
    const ModelErrorEstimate e = ladder.Estimate(c);
    const std::vector<double>& actual = ladder.actual;
    ASSERT_TRUE(e.estimated()) << e.reason;
    ASSERT_EQ(e.output_bias.size(), actual.size());
    double dot = 0.0;
    for (std::size_t i = 0; i < actual.size(); ++i) dot += actual[i] * e.output_bias[i];
    std::cout << fmt::format("{}: {}; actual rms {:.3g} J/m^2 (predicted / actual {:.2f})\n",
                             c.name, e.Summary(), Rms(actual), e.output_bias_rms / Rms(actual));
    // Same direction, and never much below the actual difference (the
    // finer solve has its own error, an eighth to a quarter of it at order
    // 1); conservative, but within a factor 3.
    EXPECT_GT(dot, 0.0);
    EXPECT_GT(e.output_bias_rms, 0.8 * Rms(actual));
    EXPECT_LT(e.output_bias_rms, 3.0 * Rms(actual));
  }
}

// The warning that the model is too coarse for the data, against the actual
// error of the model at h (its R at the truth minus the much finer solve's):
// data whose noise is a third of that error get it, data whose noise is
// three times the largest error do not; the predicted error in noise
// standard deviations is within the factor of the bias test above.
TEST(ModelError, WarnsWhenTheModelsErrorExceedsTheDataNoise) {
  for (const Case& c : Cases()) {
    SCOPED_TRACE(c.name);
    Ladder ladder(c);
    ASSERT_TRUE(ladder.ok);
    const std::vector<double>& actual = ladder.actual;
    // Noise a third of the model's rms error: 3 noise sd rms.
    ladder.data.R_uncertainty.assign(actual.size(), Rms(actual) / 3.0);
    const ModelErrorEstimate small_noise = ladder.Estimate(c);
    ASSERT_TRUE(small_noise.estimated()) << small_noise.reason;
    std::cout << c.name << ": " << small_noise.Summary() << "\n  " << small_noise.warning << "\n";
    EXPECT_FALSE(small_noise.warning.empty());
    EXPECT_GT(small_noise.output_bias_noise_rms, 0.8 * 3.0);
    EXPECT_LT(small_noise.output_bias_noise_rms, 3.0 * 3.0);
    EXPECT_NE(small_noise.warning.find("--resolution"), std::string::npos);
    // Noise three times the largest error: no warning.
    double largest = 0.0;
    for (double a : actual) largest = std::max(largest, std::abs(a));
    ladder.data.R_uncertainty.assign(actual.size(), 3.0 * largest);
    const ModelErrorEstimate large_noise = ladder.Estimate(c);
    ASSERT_TRUE(large_noise.estimated()) << large_noise.reason;
    EXPECT_TRUE(large_noise.warning.empty()) << large_noise.warning;
    EXPECT_LT(large_noise.output_bias_noise_rms, kOutputBiasNoiseLimit);
  }
}

// A fit at h to noise-free data of the much finer model: the statistical
// interval (0.3% uncertainties) can be narrower than the model's bias; the
// total interval covers the truth. (The predicted bias need not point the
// way of the actual error: on the CT case sigma_c is 1.584 MPa at 2 mm,
// 1.396 at 1 mm and the truth 1.5 - the estimates cross the converged value
// - and the observed order, 3.1, is not trusted, so F_s = 3; docs/FIT.md.)
TEST(ModelError, TotalIntervalCoversTheFinerModelsTruth) {
  const std::vector<Case> cases = Cases();
  int covered_only_by_total = 0;
  for (int index : {1, 2}) {  // CT orthotropic exponential; DCB isotropic linear
    const Case& c = cases[index];
    SCOPED_TRACE(c.name);
    const auto fine = Model(c.scene, c.h, c.a_last + 2 * c.h);
    const auto coarse = Model(c.scene, 2 * c.h, c.a_last + 4 * c.h);
    const auto coarser = Model(c.scene, 4 * c.h, c.a_last + 8 * c.h);
    const FitData data = NoiseFreeData(c);
    ASSERT_FALSE(data.R.empty());
    FitOptions options;
    options.starts = 2;
    options.profile_likelihood = false;
    FitSummary fit = FitBridgingLaw(*fine, c.shape, data, options);
    ASSERT_TRUE(fit.converged) << fit.stop_reason;
    const ModelErrorEstimate e = EstimateModelError(*fine, coarse.get(), coarser.get(), c.h,
                                                    c.shape, data, options, fit);
    ASSERT_TRUE(e.estimated()) << e.reason;
    ApplyModelError(e, fit);
    std::cout << c.name << ": " << e.Summary() << "\n" << fit.BriefReport();
    covered_only_by_total += ExpectTotalsCoverTheTruth(c, fit);
  }
  // The model error matters here: some statistical interval misses the
  // truth (else this test could not fail).
  EXPECT_GE(covered_only_by_total, 1);
}

// The fallback where a coarser model cannot follow the data (a DCB arm with
// too few elements): one finer solve at h / 2, Richardson with the order
// assumed (F_s = 3). Same oracle as above: the total interval covers the much
// finer model's truth, on the two cases above and the orthotropic DCB with
// the cubic law. (The isotropic CT's fit at 1 mm ends on its evaluation limit
// with two starts: not a case for this check.)
TEST(ModelError, FinerSolveFallbackCoversTheFinerModelsTruth) {
  const std::vector<Case> cases = Cases();
  for (int index : {1, 2, 3}) {
    const Case& c = cases[index];
    SCOPED_TRACE(c.name);
    const auto fit_model = Model(c.scene, c.h, c.a_last + 2 * c.h);
    const auto finer = Model(c.scene, 0.5 * c.h, c.a_last + 2 * c.h);
    const FitData data = NoiseFreeData(c);
    ASSERT_FALSE(data.R.empty());
    FitOptions options;
    options.starts = 2;
    options.profile_likelihood = false;
    FitSummary fit = FitBridgingLaw(*fit_model, c.shape, data, options);
    ASSERT_TRUE(fit.converged) << fit.stop_reason;
    ModelErrorOptions error_options;
    error_options.refinement_ratio = 0.5;
    const ModelErrorEstimate e =
        EstimateModelError(*fit_model, finer.get(), nullptr, c.h, c.shape, data, options, fit, error_options);
    ASSERT_TRUE(e.estimated()) << e.reason;
    EXPECT_EQ(e.status, ModelErrorStatus::kOrderNotObserved);
    EXPECT_EQ(e.safety_factor, error_options.unverified_safety_factor);
    EXPECT_NE(e.Summary().find("one finer solve at 0.5 mm"), std::string::npos) << e.Summary();
    ApplyModelError(e, fit);
    std::cout << c.name << ": " << e.Summary() << "\n";
    ExpectTotalsCoverTheTruth(c, fit);
  }
}

// Where the coarse side's order is not observed, the finer side's estimate
// is weighed against it parameter by parameter: the larger magnitude wins
// (an unestimated side never erases a finite bias), the safety factor is
// the larger, the reason names what was taken, the runs add up.
TEST(ModelError, TheFinerSideWinsWhereItPredictsMore) {
  ModelErrorEstimate coarse;
  coarse.status = ModelErrorStatus::kOrderNotObserved;
  coarse.reason = "the differences between successive solves change direction";
  coarse.parameter_bias = {0.02e6, -3.0, NAN};
  coarse.safety_factor = 3.0;
  coarse.runs = 40;
  ModelErrorEstimate finer = coarse;
  finer.coarse_resolution = 0.25e-3;
  finer.parameter_bias = {-0.01e6, -12.0, 8.0};
  finer.runs = 60;
  ModelErrorEstimate e = coarse;
  TakeTheLargerBias(finer, e);
  EXPECT_DOUBLE_EQ(e.parameter_bias[kSigmaC], 0.02e6);  // the coarse side's is larger
  EXPECT_DOUBLE_EQ(e.parameter_bias[kJB], -12.0);
  EXPECT_DOUBLE_EQ(e.parameter_bias[kJTipC], 8.0);      // none on the coarse side
  EXPECT_EQ(e.runs, 100);
  EXPECT_NE(e.reason.find("the finer side (0.25 mm) predicts a larger bias of J_B, J_tip_c"),
            std::string::npos)
      << e.reason;

  ModelErrorEstimate failed;
  failed.status = ModelErrorStatus::kNotEstimated;
  failed.reason = "the fit with the 0.25 mm model failed";
  failed.coarse_resolution = 0.25e-3;
  failed.parameter_bias = {1e9, 1e9, 1e9};  // not to be read: not estimated
  ModelErrorEstimate kept = coarse;
  TakeTheLargerBias(failed, kept);
  EXPECT_DOUBLE_EQ(kept.parameter_bias[kJB], -3.0);
  EXPECT_NE(kept.reason.find("not estimated: the fit with the 0.25 mm model failed"),
            std::string::npos)
      << kept.reason;
}

// --resolution auto on noise-free data of a much finer model: a looser
// criterion never picks a finer size, the chosen size's predicted bias meets
// the criterion, and the estimate there lies within its total interval of
// the truth (the model error is what the criterion bounds).
TEST(ModelError, AutoResolutionMeetsItsCriterion) {
  const Case c = Cases()[2];  // DCB isotropic, linear
  const FitData data = NoiseFreeData(c);
  ASSERT_FALSE(data.R.empty());
  std::map<double, std::unique_ptr<SimulationForwardModel>> cache;
  const ModelAtResolution model_at = [&](double h) -> const ForwardModel* {
    auto& m = cache[h];
    if (!m) m = Model(c.scene, h, c.a_last + 2 * h);
    return m.get();
  };
  FitOptions options;
  options.starts = 2;
  options.profile_likelihood = false;
  ResolutionOptions strict;
  strict.coarsest = 2.5e-3;  // a quarter of the arm
  strict.finest = 0.3e-3;
  const FitSummary pilot = FitBridgingLaw(*model_at(strict.coarsest), c.shape, data, options);
  ASSERT_TRUE(pilot.converged) << pilot.stop_reason;
  const ResolutionChoice chosen = ChooseResolution(model_at, c.shape, data, options, pilot, strict);
  ResolutionOptions loose = strict;
  loose.bias_fraction = 3.0;
  const ResolutionChoice coarser = ChooseResolution(model_at, c.shape, data, options, pilot, loose);
  std::cout << "strict: " << chosen.reason << "\nloose: " << coarser.reason << "\n";
  for (const ResolutionLevel& l : chosen.levels)
    std::cout << fmt::format("  {:.3g} mm: sigma_c {:.5g} (bias {:+.3g}, sd {:.3g}), {}\n",
                             l.resolution * 1e3, l.estimate[kSigmaC], l.bias[kSigmaC],
                             l.sd[kSigmaC], l.note);
  ASSERT_FALSE(chosen.levels.empty());
  EXPECT_GE(coarser.resolution, chosen.resolution);
  if (chosen.criterion_met) {
    const ResolutionLevel& at = chosen.levels.back();
    for (int i : {kSigmaC, kJB, kJTipC}) {
      EXPECT_LE(std::abs(at.bias[i]), strict.bias_fraction * at.sd[i]) << ParameterName(i);
    }
    // The estimate there against the truth: within the total interval's
    // half-width beyond the statistical one (1.96 sd + F_s |bias|).
    const double truths[] = {c.truth.sigma_c, c.truth.J_B, c.truth.J_tip_c};
    for (int i : {kSigmaC, kJB, kJTipC})
      EXPECT_LE(std::abs(at.estimate[i] - truths[i]), 1.96 * at.sd[i] + 1.25 * std::abs(at.bias[i]))
          << ParameterName(i);
  }
}

// A model whose every run fails (as the reduced model's Newton does on a
// DCB arm too coarse for it).
class FailingModel final : public ForwardModel {
 public:
  std::string Name() const override { return "failing"; }
  ForwardPrediction Predict(const laws::LawShape&, const LawParameters&,
                            const std::vector<double>&, RKind) const override {
    ForwardPrediction p;
    p.status = RunStatus::kNotConverged;
    p.message = "Newton did not converge (injected)";
    return p;
  }
};

// --resolution auto where the size above a candidate cannot run: the
// candidate is judged from the next finer solve (order assumed, criterion
// widened by the assumed order's safety factor) instead of never meeting
// the criterion; where it is chosen, its estimate lies within the total
// half-width it would get (1.96 sd + F_s(assumed) |bias|) of the truth.
TEST(ModelError, AutoResolutionJudgesASizeFromAFinerSolveWhenTheCoarserFails) {
  const Case c = Cases()[2];  // DCB isotropic, linear
  FitData data = NoiseFreeData(c);
  ASSERT_FALSE(data.R.empty());
  // 2% uncertainties: the model's error at the coarse sizes is below them.
  for (std::size_t i = 0; i < data.R.size(); ++i) data.R_uncertainty[i] = 0.02 * data.R[i];
  std::map<double, std::unique_ptr<ForwardModel>> cache;
  ResolutionOptions options;
  options.coarsest = 2.5e-3;  // a quarter of the arm
  options.finest = 0.3e-3;
  // Every size above 1.3 mm fails: 1.25 mm has no coarser solve.
  const ModelAtResolution model_at = [&](double h) -> const ForwardModel* {
    auto& m = cache[h];
    if (!m) m = h > 1.3e-3 ? std::unique_ptr<ForwardModel>(std::make_unique<FailingModel>())
                           : std::unique_ptr<ForwardModel>(Model(c.scene, h, c.a_last + 2 * h));
    return m.get();
  };
  FitOptions fit_options;
  fit_options.starts = 2;
  fit_options.profile_likelihood = false;
  const auto pilot_model = Model(c.scene, 1.25e-3, c.a_last + 2.5e-3);
  const FitSummary pilot = FitBridgingLaw(*pilot_model, c.shape, data, fit_options);
  ASSERT_TRUE(pilot.converged) << pilot.stop_reason;
  for (double fraction : {0.3, 3.0}) {
    options.bias_fraction = fraction;
    const ResolutionChoice chosen = ChooseResolution(model_at, c.shape, data, fit_options, pilot, options);
    std::cout << "fraction " << fraction << ": " << chosen.reason << "\n";
    for (const ResolutionLevel& l : chosen.levels) std::cout << "  " << l.note << "\n";
    const auto at_1_25 = std::find_if(chosen.levels.begin(), chosen.levels.end(), [](const auto& l) {
      return std::abs(l.resolution - 1.25e-3) < 1e-9;
    });
    ASSERT_NE(at_1_25, chosen.levels.end());
    EXPECT_EQ(at_1_25->status, ModelErrorStatus::kOrderNotObserved);
    EXPECT_NE(at_1_25->note.find("judged from the finer 0.625 mm solve"), std::string::npos)
        << at_1_25->note;
    if (!chosen.criterion_met) continue;
    const ResolutionLevel& at = chosen.levels.back();
    const double widen = options.error.unverified_safety_factor / options.error.safety_factor;
    const double truths[] = {c.truth.sigma_c, c.truth.J_B, c.truth.J_tip_c};
    for (int i : {kSigmaC, kJB, kJTipC}) {
      SCOPED_TRACE(ParameterName(i));
      const double factor = at.status == ModelErrorStatus::kEstimated ? 1.0 : widen;
      EXPECT_LE(factor * std::abs(at.bias[i]), fraction * at.sd[i]);
      const double f_s = at.status == ModelErrorStatus::kEstimated
                             ? options.error.safety_factor
                             : options.error.unverified_safety_factor;
      EXPECT_LE(std::abs(at.estimate[i] - truths[i]), 1.96 * at.sd[i] + f_s * std::abs(at.bias[i]));
    }
  }
}

}  // namespace
}  // namespace bridgefit::inverse
