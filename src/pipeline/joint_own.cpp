// A joint fit's per-specimen parameters and the carriers of the shared ones
// (issue 19; docs/CAMPAIGN.md "A subset shared" and "Who carries a
// parameter").
#include "joint_own.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bridgefit/core/error.hpp"

namespace bridgefit::pipeline::detail {

namespace {

const inverse::ParameterEstimate& Estimate(const inverse::FitSummary& s, int i) {
  return i == inverse::kSigmaC ? s.sigma_c : i == inverse::kJB ? s.J_B : s.J_tip_c;
}
inverse::ParameterEstimate& Estimate(inverse::FitSummary& s, int i) {
  return i == inverse::kSigmaC ? s.sigma_c : i == inverse::kJB ? s.J_B : s.J_tip_c;
}
double Get(const inverse::LawParameters& p, int i) {
  return i == inverse::kSigmaC ? p.sigma_c : i == inverse::kJB ? p.J_B : p.J_tip_c;
}
bool Closed(const inverse::ParameterEstimate& e) {
  return e.identified && std::isfinite(e.ci95_low) && std::isfinite(e.ci95_high) &&
         e.ci95_high > e.ci95_low && e.interval_status != inverse::IntervalStatus::kOpen &&
         e.interval_status != inverse::IntervalStatus::kEndsOnBound;
}

}  // namespace

std::vector<OwnParameterValue> OwnValues(const std::vector<std::string>& names,
                                         const std::vector<const inverse::ForwardModel*>& base,
                                         const std::vector<const inverse::ForwardModel*>& profiled,
                                         const std::vector<inverse::FitData>& data,
                                         const laws::LawShape& shape,
                                         const inverse::FitSummary& fit,
                                         const inverse::FitOptions& alone,
                                         const inverse::SharedParameters& shared) {
  std::vector<OwnParameterValue> out;
  const std::array<double, inverse::kParameterCount>& at = fit.best_parameters;
  const inverse::LawParameters joint{at[inverse::kSigmaC], at[inverse::kJB], at[inverse::kJTipC]};
  // The shared parameters free in the joint fit, with their intervals'
  // half-widths in ln (NaN: open).
  std::vector<int> free_shared;
  std::vector<double> half_width;
  for (int j = 0; j < inverse::kParameterCount; ++j) {
    const inverse::ParameterEstimate& e = Estimate(fit, j);
    if (!shared[j] || e.fixed) continue;
    free_shared.push_back(j);
    half_width.push_back(e.ci95_low > 0.0 && std::isfinite(e.ci95_high)
                             ? 0.5 * std::log(e.ci95_high / e.ci95_low)
                             : NAN);
  }
  bool joint_found = true;  // a failed joint fit has no optimum to profile at
  for (int j = 0; j < inverse::kParameterCount; ++j)
    joint_found = joint_found && (!shared[j] || std::isfinite(at[j]));
  for (std::size_t k = 0; k < base.size(); ++k) {
    if (!joint_found) {
      for (int i = 0; i < inverse::kParameterCount; ++i)
        if (!shared[i] && !alone.fixed[i]) out.push_back({.specimen = names[k], .parameter = i});
      continue;
    }
    const auto* own = dynamic_cast<const inverse::OwnParameterProfiledModel*>(profiled[k]);
    if (!own)
      throw Error(ErrorKind::kInternal,
                  "a joint fit with parameters not shared profiles them per specimen",
                  {.field = "joint fit", .value = names[k]});
    const inverse::LawParameters value = own->Profiled(shape, joint);
    // Conditional: the specimen alone, the shared parameters held at the
    // joint values, its own free from their profiled values, with profiles.
    inverse::FitOptions held = alone;
    held.profile_likelihood = true;
    held.starts = 1;
    held.threads = 1;
    for (int i = 0; i < inverse::kParameterCount; ++i) {
      if (alone.fixed[i]) continue;
      held.fixed[i] = shared[i];
      if (shared[i]) held.fixed_value[i] = at[i];
      else held.initial[i] = Get(value, i);
    }
    const inverse::FitSummary conditional = inverse::FitBridgingLaw(*base[k], shape, data[k], held);
    // Sensitivities of each own value to each shared one (+-1% in ln).
    constexpr double kStep = 0.01;
    std::vector<inverse::LawParameters> up, down;
    for (int j : free_shared) {
      std::array<double, inverse::kParameterCount> p = at, q = at;
      p[j] *= std::exp(kStep), q[j] *= std::exp(-kStep);
      up.push_back(own->Profiled(shape, {p[0], p[1], p[2]}));
      down.push_back(own->Profiled(shape, {q[0], q[1], q[2]}));
    }
    for (int i = 0; i < inverse::kParameterCount; ++i) {
      if (shared[i] || alone.fixed[i]) continue;
      OwnParameterValue v;
      v.specimen = names[k];
      v.parameter = i;
      v.value = Get(value, i);
      const inverse::ParameterEstimate& c = Estimate(conditional, i);
      v.conditional_ci95_low = c.ci95_low;
      v.conditional_ci95_high = c.ci95_high;
      double carried = 0.0;  // sum_j |d ln v / d ln s_j| h_j
      for (std::size_t n = 0; n < free_shared.size(); ++n)
        carried += std::abs(std::log(Get(up[n], i) / Get(down[n], i)) / (2.0 * kStep)) * half_width[n];
      if (v.value > 0.0 && c.ci95_low > 0.0 && std::isfinite(c.ci95_high) && std::isfinite(carried)) {
        const double ln_v = std::log(v.value);
        v.ci95_low = std::exp(ln_v - std::hypot(ln_v - std::log(std::min(c.ci95_low, v.value)), carried));
        v.ci95_high = std::exp(ln_v + std::hypot(std::log(std::max(c.ci95_high, v.value)) - ln_v, carried));
      }
      out.push_back(v);
    }
  }
  return out;
}

std::vector<ParameterCarriers> Carriers(const std::vector<std::string>& names,
                                        const std::vector<const FitRun*>& runs,
                                        const inverse::FitSummary& joint,
                                        const std::vector<bool>& past_steady_state,
                                        const inverse::SharedParameters& shared_parameters) {
  std::vector<ParameterCarriers> out;
  for (int i = 0; i < inverse::kParameterCount; ++i) {
    const inverse::ParameterEstimate& shared = Estimate(joint, i);
    if (shared.fixed || !shared_parameters[i]) continue;  // fixed by the user, or each one's own
    ParameterCarriers c;
    c.parameter = i;
    const double joint_width =
        Closed(shared) ? shared.ci95_high - shared.ci95_low : static_cast<double>(NAN);
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const inverse::ParameterEstimate& e = Estimate(runs[k]->summary, i);
      const double ratio = (e.ci95_high - e.ci95_low) / joint_width;  // NaN: either open
      std::string carries, not_why;
      if (i == inverse::kJB) {
        const bool past = k < past_steady_state.size() && past_steady_state[k];
        const std::string alone = Closed(e) ? fmt::format("its own fit closes it too")
                                  : std::isfinite(e.lower_bound)
                                      ? std::string("alone it gives only a lower bound")
                                      : std::string("alone it does not close it");
        if (past) carries = "past steady state at the joint law (" + alone + ")";
        else not_why = "not past steady state at the joint law (" + alone + ")";
      } else if (!Closed(e)) {
        not_why = std::isfinite(e.lower_bound) ? "its own fit gives only a lower bound"
                                               : "its own fit does not close the interval";
      } else if (std::isfinite(joint_width) && ratio > kCarrierWidthRatio) {
        not_why = fmt::format("its own interval is {:.3g} times the joint one (> {:g})", ratio,
                              kCarrierWidthRatio);
      } else {
        carries = std::isfinite(joint_width)
                      ? fmt::format("its own interval {:.3g} times the joint one", ratio)
                      : std::string("its own fit closes the interval (the joint one is not closed)");
      }
      if (!carries.empty()) {
        c.specimens.push_back(names[k]);
        c.reasons.push_back("carries it: " + carries);
      } else {
        c.reasons.push_back("does not carry it: " + not_why);
      }
    }
    out.push_back(std::move(c));
  }
  return out;
}

void MarkOwnEstimates(const inverse::SharedParameters& shared, inverse::FitSummary& fit) {
  const auto mark = [](inverse::ParameterEstimate& e, const std::string& note) {
    e = inverse::ParameterEstimate{};
    e.note = note;
    e.decided_by = "per specimen";
    e.interval_status = inverse::IntervalStatus::kOpen;
  };
  for (int i = 0; i < inverse::kParameterCount; ++i)
    if (!shared[i])
      mark(Estimate(fit, i), "not shared: each specimen's own value (the joint fit's per-specimen table)");
  if (!shared[inverse::kSigmaC] || !shared[inverse::kJB])
    mark(fit.delta_c, "not shared: it follows from each specimen's own J_B and sigma_c");
}

}  // namespace bridgefit::pipeline::detail

namespace bridgefit::pipeline {

namespace {
std::string Names(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
  return text;
}
}  // namespace

std::string JointFitRun::BriefReport() const {
  std::string text = fmt::format("joint fit of {} specimens ({}), one {} law, {:.2f} s:\n",
                                 specimens.size(), Names(specimens),
                                 laws::LawFamilyName(shape.family), wall_s);
  if (shared != inverse::kAllShared)
    text += fmt::format("  shared: {} (the others each specimen's own, profiled out)\n",
                        inverse::SharedParametersText(shared));
  text += summary.BriefReport();
  text += "  consistency: " + consistency.Summary() + "\n";
  for (const OwnParameterValue& v : own_values) {
    const bool stress = v.parameter == inverse::kSigmaC;
    const double scale = stress ? 1e6 : 1.0;
    const char* unit = stress ? "MPa" : "J/m^2";
    const auto end = [&](double x) {
      return std::isfinite(x) ? fmt::format("{:.4g}", x / scale) : std::string("open");
    };
    text += fmt::format("  {:<16} own {} = {:.4g} {} [95% CI {} .. {}] (conditional {} .. {})\n",
                        v.specimen, inverse::ParameterName(v.parameter), v.value / scale, unit,
                        end(v.ci95_low), end(v.ci95_high), end(v.conditional_ci95_low),
                        end(v.conditional_ci95_high));
  }
  for (const ParameterCarriers& c : carriers)
    text += fmt::format("  {} carried by: {}\n", inverse::ParameterName(c.parameter),
                        c.specimens.empty() ? std::string("(none)") : Names(c.specimens));
  for (std::size_t k = 0; k < specimen_p_value.size(); ++k)
    text += fmt::format("  {:<16} chi^2 at the joint law - its own optimum's: {:.3g} s^2, p = {:.3g}{}\n",
                        specimens[k], specimen_statistic[k], specimen_p_value[k],
                        std::find(flagged.begin(), flagged.end(), specimens[k]) != flagged.end()
                            ? "  FLAGGED: set aside, the others are one law without it"
                            : "");
  for (std::size_t k = 0; k < specimen_modulus_factor.size(); ++k)
    text += fmt::format("  {:<16} modulus factor at the joint law {:.4f} (its own fit's {:.4f}; "
                        "series compliance held at its own fit's)\n",
                        specimens[k], specimen_modulus_factor[k],
                        specimen_calibrated_modulus_factor[k]);
  if (summary_without_flagged) {
    std::vector<std::string> rest;
    for (const std::string& s : specimens)
      if (std::find(flagged.begin(), flagged.end(), s) == flagged.end()) rest.push_back(s);
    text += fmt::format("  without {}: the joint fit of {}:\n", Names(flagged), Names(rest));
    text += summary_without_flagged->BriefReport();
    text += "  consistency without them: " + consistency_without_flagged.Summary() + "\n";
    for (const ParameterCarriers& c : carriers_without_flagged)
      text += fmt::format("  without them, {} carried by: {}\n", inverse::ParameterName(c.parameter),
                          c.specimens.empty() ? std::string("(none)") : Names(c.specimens));
  }
  text += "  " + model_error.Summary() +
          " (each specimen's reduced model at twice and four times its own element size)\n";
  if (!model_error.warning.empty()) text += "  warning: " + model_error.warning + "\n";
  return text;
}

}  // namespace bridgefit::pipeline
