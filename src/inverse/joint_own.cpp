// The law parameters a joint fit does not share: their names, and each
// specimen's own values profiled out inside the joint model
// (inverse/joint.hpp, docs/CAMPAIGN.md "A subset shared").
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bridgefit/core/error.hpp"
#include "bridgefit/inverse/joint.hpp"
#include "brent.hpp"

namespace bridgefit::inverse {

namespace {

std::array<double, kParameterCount> AsArray(const LawParameters& p) {
  return {p.sigma_c, p.J_B, p.J_tip_c};
}
LawParameters AsLaw(const std::array<double, kParameterCount>& p) {
  return {p[kSigmaC], p[kJB], p[kJTipC]};
}

// The data's own axis, to rounding (a joint model's block is shifted onto
// the joined axis and back).
bool SameAxis(const std::vector<double>& asked, const std::vector<double>& own) {
  if (asked.size() != own.size()) return false;
  for (std::size_t i = 0; i < own.size(); ++i)
    if (std::abs(asked[i] - own[i]) > 1e-9 * std::max(1.0, std::abs(own[i]))) return false;
  return true;
}

ForwardPrediction Refused(RunStatus status, const char* message) {
  ForwardPrediction out;
  out.status = status;
  out.message = message;
  return out;
}

bool AllFinite(const LawParameters& q) {
  return std::isfinite(q.sigma_c) && std::isfinite(q.J_B) && std::isfinite(q.J_tip_c);
}

constexpr const char* kNoOwnValue = "no value of the specimen's own parameters gave a valid run";

}  // namespace

SharedParameters ParseSharedParameters(const std::vector<std::string>& names) {
  const std::string allowed = "sigma_c, J_B, J_tip_c (one or more, e.g. [\"sigma_c\", \"J_B\"])";
  BF_CHECK_INPUT(!names.empty(), "the list of shared parameters is empty",
                 {.field = "joint", .value = "[]", .expected = allowed});
  SharedParameters shared = {false, false, false};
  for (const std::string& name : names) {
    int index = -1;
    for (int i = 0; i < kParameterCount; ++i)
      if (name == ParameterName(i)) index = i;
    if (name == "delta_c")
      throw Error(ErrorKind::kInput,
                  "delta_c is not a parameter of its own in the joint fit: it follows from J_B "
                  "and sigma_c, and is shared when both are",
                  {.field = "joint", .value = name, .expected = allowed});
    BF_CHECK_INPUT(index >= 0, "unknown parameter", {.field = "joint", .value = name, .expected = allowed});
    BF_CHECK_INPUT(!shared[index], "parameter named twice",
                   {.field = "joint", .value = name, .expected = allowed});
    shared[index] = true;
  }
  return shared;
}

std::string SharedParametersText(const SharedParameters& shared) {
  std::string text;
  for (int i = 0; i < kParameterCount; ++i)
    if (shared[i]) text += (text.empty() ? "" : ", ") + std::string(ParameterName(i));
  return text;
}

OwnParameterProfiledModel::OwnParameterProfiledModel(const ForwardModel& base, FitData data,
                                                     SharedParameters shared,
                                                     std::array<double, kParameterCount> lower,
                                                     std::array<double, kParameterCount> upper,
                                                     std::array<double, kParameterCount> start)
    : base_(base), data_(std::move(data)), shared_(shared), lower_(lower), upper_(upper),
      start_(start) {
  BF_CHECK_INPUT(data_.size() > 0, "a specimen's own parameters need its data",
                 {.field = "joint fit"});
  for (int i = 0; i < kParameterCount; ++i) {
    if (shared_[i]) continue;
    BF_CHECK_INPUT(lower_[i] > 0.0 && upper_[i] > lower_[i],
                   "a specimen's own parameter needs a positive box",
                   {.field = ParameterName(i),
                    .value = fmt::format("[{:g}, {:g}]", lower_[i], upper_[i])});
    // A start outside the box (or unknown): the box's geometric middle.
    if (!(start_[i] >= lower_[i] && start_[i] <= upper_[i]))
      start_[i] = std::sqrt(lower_[i] * upper_[i]);
  }
}

double OwnParameterProfiledModel::Chi2(const laws::LawShape& shape, const LawParameters& p) const {
  const bool load = data_.target == FitTarget::kLoad;
  const ForwardPrediction q = load ? base_.PredictLoad(shape, p, data_.displacement)
                                   : base_.Predict(shape, p, data_.crack_length, data_.kind);
  const std::vector<double>& values = load ? data_.load : data_.R;
  const std::vector<double>& predicted = load ? q.load : q.R;
  const std::vector<double>& u = load ? data_.load_uncertainty : data_.R_uncertainty;
  if (!q.ok() || predicted.size() != values.size()) return INFINITY;
  double sum = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i)
    sum += std::pow((predicted[i] - values[i]) / (data_.weighted() ? u[i] : 1.0), 2);
  return std::isfinite(sum) ? sum : INFINITY;
}

LawParameters OwnParameterProfiledModel::Profiled(const laws::LawShape& shape,
                                                  const LawParameters& p) const {
  std::array<double, kParameterCount> at = AsArray(p);
  std::vector<int> own;
  for (int i = 0; i < kParameterCount; ++i)
    if (!shared_[i]) own.push_back(i), at[i] = start_[i];
  if (own.empty()) return p;
  constexpr double kTol = 2.5e-6;  // in ln p
  // One parameter i along ln p, the others as `at` holds them; first within
  // a factor e of where it stands, the whole box when that ends on an edge.
  const auto along = [&](int i) {
    const double lo = std::log(lower_[i]), hi = std::log(upper_[i]);
    const auto chi2 = [&](double ln_value) {
      std::array<double, kParameterCount> q = at;
      q[i] = std::exp(ln_value);
      return Chi2(shape, AsLaw(q));
    };
    const double x0 = std::log(at[i]);
    const double a = std::max(lo, x0 - 1.0), b = std::min(hi, x0 + 1.0);
    detail::BrentMinimum m = detail::BrentMinimize(chi2, a, b, x0, kTol);
    const bool on_edge = (m.x - a < 1e-3 && a > lo) || (b - m.x < 1e-3 && b < hi);
    if (on_edge || !std::isfinite(m.f)) {
      const detail::BrentMinimum wide = detail::BrentMinimize(chi2, lo, hi, std::clamp(m.x, lo, hi), kTol);
      if (wide.f <= m.f || !std::isfinite(m.f)) m = wide;
    }
    if (!std::isfinite(m.f)) return false;
    at[i] = std::exp(m.x);
    return true;
  };
  const int sweeps = own.size() == 1 ? 1 : 8;
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    double moved = 0.0;
    for (int i : own) {
      const double before = at[i];
      if (!along(i)) {
        for (int j : own) at[j] = NAN;
        return AsLaw(at);
      }
      moved = std::max(moved, std::abs(std::log(at[i] / before)));
    }
    if (moved < 1e-4) break;
  }
  return AsLaw(at);
}

ForwardPrediction OwnParameterProfiledModel::Predict(const laws::LawShape& shape,
                                                     const LawParameters& p,
                                                     const std::vector<double>& crack_lengths,
                                                     RKind kind) const {
  if (data_.target != FitTarget::kRCurve || !SameAxis(crack_lengths, data_.crack_length) ||
      kind != data_.kind)
    return Refused(RunStatus::kInvalidInput,
                   "a model with its own parameters profiled predicts its specimen's own R curve only");
  const LawParameters q = Profiled(shape, p);
  if (!AllFinite(q)) return Refused(RunStatus::kFailed, kNoOwnValue);
  return base_.Predict(shape, q, crack_lengths, kind);
}

ForwardPrediction OwnParameterProfiledModel::PredictLoad(
    const laws::LawShape& shape, const LawParameters& p,
    const std::vector<double>& displacements) const {
  if (data_.target != FitTarget::kLoad || !SameAxis(displacements, data_.displacement))
    return Refused(RunStatus::kInvalidInput,
                   "a model with its own parameters profiled predicts its specimen's own rows only");
  const LawParameters q = Profiled(shape, p);
  if (!AllFinite(q)) return Refused(RunStatus::kFailed, kNoOwnValue);
  return base_.PredictLoad(shape, q, displacements);
}

}  // namespace bridgefit::inverse
