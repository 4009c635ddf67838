// Fit options, data and summary text (include/bridgefit/inverse/fit.hpp).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/inverse/fit.hpp"

namespace bridgefit::inverse {

const char* ParameterName(int index) {
  static constexpr const char* kNames[] = {"sigma_c", "J_B", "J_tip_c"};
  return kNames[index];
}

const char* OptimizerName(Optimizer optimizer) {
  switch (optimizer) {
    case Optimizer::kCeresLm: return "ceres-lm";
    case Optimizer::kBobyqa: return "bobyqa";
    case Optimizer::kNelderMead: return "neldermead";
    case Optimizer::kCobyla: return "cobyla";
    case Optimizer::kDirect: return "direct";
    case Optimizer::kCrs2: return "crs2";
  }
  return "unknown";
}

Optimizer ParseOptimizer(const std::string& name) {
  for (Optimizer o : {Optimizer::kCeresLm, Optimizer::kBobyqa, Optimizer::kNelderMead,
                      Optimizer::kCobyla, Optimizer::kDirect, Optimizer::kCrs2})
    if (name == OptimizerName(o)) return o;
  throw Error(ErrorKind::kUsage, "unknown optimizer",
              {.field = "--optimizer", .value = name,
               .expected = "ceres-lm, bobyqa, neldermead, cobyla, direct or crs2"});
}

bool FitOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (starts < 1) return fail("starts must be >= 1");
  if (max_evaluations < 10) return fail("max_evaluations must be >= 10");
  if (threads < 0) return fail("threads must be >= 0");
  if (!(min_bridging_fraction >= 0.0 && min_bridging_fraction < 1.0))
    return fail("min_bridging_fraction must be in [0, 1)");
  for (int i = 0; i < kParameterCount; ++i) {
    if (fixed[i]) {
      if (!(fixed_value[i] >= 0.0) || !std::isfinite(fixed_value[i]))
        return fail(std::string("fixed ") + ParameterName(i) + " must be finite and >= 0");
      continue;
    }
    if (!(lower[i] > 0.0 && upper[i] > lower[i] && std::isfinite(upper[i])))
      return fail(std::string("bounds of ") + ParameterName(i) + " must satisfy 0 < low < high");
  }
  if (std::count(fixed.begin(), fixed.end(), false) == 0) return fail("every parameter is fixed");
  return true;
}

FitData FitData::FromRCurve(const RCurve& curve, RKind kind) {
  FitData data;
  data.crack_length = curve.crack_length;
  data.R = curve.R;
  // The fit weights by one standard uncertainty.
  BF_CHECK_INPUT(curve.uncertainty_coverage > 0.0, "the R uncertainty's coverage factor must be > 0",
                 {.field = "coverage_factor"});
  for (double u : curve.R_uncertainty) data.R_uncertainty.push_back(u / curve.uncertainty_coverage);
  data.kind = kind;
  {
    // An equivalent crack length from a noisy compliance is not monotone:
    // order the points by it (an R curve is R(a); the model's curve is
    // compared the same way).
    std::vector<std::size_t> order(data.R.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return data.crack_length[a] < data.crack_length[b];
    });
    FitData sorted;
    sorted.kind = kind;
    for (std::size_t i : order) {
      sorted.crack_length.push_back(data.crack_length[i]);
      sorted.R.push_back(data.R[i]);
      if (!data.R_uncertainty.empty()) sorted.R_uncertainty.push_back(data.R_uncertainty[i]);
    }
    data = std::move(sorted);
  }
  data.Validate();
  return data;
}

const char* IntervalStatusName(IntervalStatus status) {
  switch (status) {
    case IntervalStatus::kReliable: return "reliable";
    case IntervalStatus::kOpen: return "open";
    case IntervalStatus::kEndsOnBound: return "ends_on_bound";
    case IntervalStatus::kUnreliableZeroWidth: return "unreliable_zero_width";
    case IntervalStatus::kUnreliableNonSmooth: return "unreliable_non_smooth";
    case IntervalStatus::kUnreliableMisfit: return "unreliable_misfit";
  }
  return "reliable";
}

std::string MisfitRun::Describe() const {
  if (points == 0) return "";
  return fmt::format(
      "{} R points in runs at a = {:.4g}-{:.4g} mm lie up to {:.3g} robust SD {} the model: the "
      "model does not follow the data there (kept, not removed as outliers; a rise shorter than "
      "the elements, or a law that does not fit): every interval is unreliable",
      points, crack_length_from * 1e3, crack_length_to * 1e3, largest_sd,
      side > 0 ? "above" : side < 0 ? "below" : "on both sides of");
}

const char* FitTargetName(FitTarget target) {
  return target == FitTarget::kLoad ? "load-displacement" : "r-curve";
}

FitTarget ParseFitTarget(const std::string& name) {
  if (name == "r-curve") return FitTarget::kRCurve;
  if (name == "load-displacement") return FitTarget::kLoad;
  throw Error(ErrorKind::kUsage, "unknown fit target",
              {.field = "--fit-to", .value = name, .expected = "r-curve or load-displacement"});
}

FitData FitData::FromRecord(const ExperimentRecord& record, double load_noise,
                            double displacement_noise) {
  BF_CHECK_INPUT(load_noise >= 0.0 && displacement_noise >= 0.0,
                 "record noise must be >= 0", {.file = record.source, .field = "noise"});
  FitData data;
  data.target = FitTarget::kLoad;
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < record.size(); ++i)
    if (record.displacement[i] > 0.0) rows.push_back(i);
  for (std::size_t i : rows) {
    data.displacement.push_back(record.displacement[i]);
    data.load.push_back(record.load[i]);
  }
  if (load_noise > 0.0 || displacement_noise > 0.0) {
    constexpr int kHalf = 3;
    const int n = static_cast<int>(rows.size());
    for (int i = 0; i < n; ++i) {
      // Least-squares slope dP/dd over rows i - 3 .. i + 3.
      double sd = 0, sp = 0, sdd = 0, sdp = 0;
      int count = 0;
      for (int j = std::max(0, i - kHalf); j <= std::min(n - 1, i + kHalf); ++j, ++count) {
        sd += data.displacement[j];
        sp += data.load[j];
        sdd += data.displacement[j] * data.displacement[j];
        sdp += data.displacement[j] * data.load[j];
      }
      const double denominator = count * sdd - sd * sd;
      const double slope = denominator > 0.0 ? (count * sdp - sd * sp) / denominator : 0.0;
      data.load_uncertainty.push_back(
          std::hypot(load_noise, slope * displacement_noise));
    }
  }
  data.Validate();
  return data;
}

FitData FitData::Subset(const std::vector<int>& keep) const {
  FitData out;
  out.target = target;
  out.kind = kind;
  auto pick = [&keep](const std::vector<double>& from, std::vector<double>& to) {
    if (from.empty()) return;
    for (int i : keep) to.push_back(from[i]);
  };
  pick(crack_length, out.crack_length);
  pick(R, out.R);
  pick(R_uncertainty, out.R_uncertainty);
  pick(displacement, out.displacement);
  pick(load, out.load);
  pick(load_uncertainty, out.load_uncertainty);
  return out;
}

namespace {
// One series of a fit's data: values against an axis, optional uncertainties.
void ValidateSeries(const char* axis_name, const std::vector<double>& axis, const char* name,
                    const std::vector<double>& values, const std::vector<double>& uncertainty,
                    bool axis_ascending) {
  BF_CHECK_INPUT(values.size() >= 4, fmt::format("a fit needs at least four {} values", name),
                 {.field = name, .value = std::to_string(values.size()) + " points"});
  BF_CHECK_INPUT(axis.size() == values.size(),
                 fmt::format("{} and {} differ in length", axis_name, name));
  BF_CHECK_INPUT(uncertainty.empty() || uncertainty.size() == values.size(),
                 fmt::format("the {} uncertainties and {} differ in length", name, name));
  for (size_t i = 0; i < values.size(); ++i) {
    BF_CHECK_INPUT(std::isfinite(values[i]) && std::isfinite(axis[i]), "fit data must be finite",
                   {.field = "row " + std::to_string(i + 1)});
    if (axis_ascending && i > 0)
      BF_CHECK_INPUT(axis[i] >= axis[i - 1],
                     fmt::format("the {} of the data must not decrease", axis_name),
                     {.field = axis_name, .value = std::to_string(axis[i])});
    if (!uncertainty.empty())
      BF_CHECK_INPUT(uncertainty[i] > 0.0, "uncertainties must be positive",
                     {.field = std::string(name) + "_uncertainty",
                      .value = std::to_string(uncertainty[i])});
  }
}
}  // namespace

void FitData::Validate() const {
  if (target == FitTarget::kLoad)
    ValidateSeries("displacement", displacement, "load", load, load_uncertainty, false);
  else
    ValidateSeries("crack_length", crack_length, "R", R, R_uncertainty, true);
}

std::string FitSummary::BriefReport() const {
  auto line = [](const char* name, const ParameterEstimate& e, double scale, const char* unit) {
    if (e.fixed) return fmt::format("  {:<8} = {:.4g} {} (fixed)\n", name, e.value / scale, unit);
    auto end = [&](double v) { return std::isfinite(v) ? fmt::format("{:.4g}", v / scale) : "open"; };
    const bool no_interval = !std::isfinite(e.ci95_low) && !std::isfinite(e.ci95_high);
    const bool warn = e.interval_status != IntervalStatus::kReliable &&
                      e.interval_status != IntervalStatus::kOpen;
    // With the model error applied: the total interval, then its parts.
    const std::string parts_text =
        std::isfinite(e.model_bias)
            ? fmt::format(" (statistical {} .. {}, model bias {:+.3g} {})", end(e.statistical_ci95_low),
                          end(e.statistical_ci95_high), e.model_bias / scale, unit)
            : std::string();
    if (std::isfinite(e.value) && warn)
      return fmt::format("  {:<8} = {:.4g} {} {}(interval unreliable: {})\n", name, e.value / scale,
                         unit,
                         no_interval ? std::string()
                                     : fmt::format("[95% CI {} .. {}]{} ", end(e.ci95_low),
                                                   end(e.ci95_high), parts_text),
                         e.interval_reason);
    if (std::isfinite(e.value))  // with no interval at all, the note says why (e.g. J_B = 0)
      return fmt::format("  {:<8} = {:.4g} {} [95% CI {} .. {}]{}{}{}\n", name, e.value / scale, unit,
                         end(e.ci95_low), end(e.ci95_high), parts_text,
                         e.identified ? "" : " (not identifiable)",
                         no_interval && !e.note.empty() ? " (" + e.note + ")" : std::string());
    if (std::isfinite(e.lower_bound))
      return fmt::format("  {:<8} >= {:.4g} {} (lower bound: {})\n", name, e.lower_bound / scale,
                         unit, e.note);
    return fmt::format("  {:<8}   not identifiable: {}\n", name, e.note);
  };
  std::string out = fmt::format(
      "fit ({} law, {} model, {}, {}): {} evaluations ({} failed), {:.2f} s, {}; rms residual "
      "{:.4g} {}\n  {}\n",
      law, model, optimizer, FitTargetName(target), evaluations, failed_evaluations, wall_s,
      converged ? "converged" : "NOT converged (" + stop_reason + ")", rms_residual,
      target == FitTarget::kLoad ? "N" : "J/m^2", verdict);
  if (reduced_chi2 > 1.5 && std::isfinite(reduced_chi2))
    out += fmt::format("  reduced chi^2 {:.3g}: the data scatter more than their uncertainties say; "
                       "intervals widened by it\n", reduced_chi2);
  if (interval_inflation > 1.0)
    out += fmt::format("  residuals correlated (lag-1 rho {:.2f} over {} points): intervals widened "
                       "x {:.3g} (about {:.0f} independent points)\n",
                       residual_autocorrelation, data_points, std::sqrt(interval_inflation),
                       data_points / interval_inflation);
  out += line("sigma_c", sigma_c, 1e6, "MPa");
  out += line("J_B", J_B, 1.0, "J/m^2");
  out += line("delta_c", delta_c, 1e-3, "mm");
  out += line("J_tip_c", J_tip_c, 1.0, "J/m^2");
  return out;
}

}  // namespace bridgefit::inverse
