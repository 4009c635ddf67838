// Stage 3 of FitBridgingLaw: profile likelihoods and the ends of their 95%
// intervals, with the checks that make an interval trustworthy (docs/FIT.md
// "Profiles you can trust"): a chi^2 that jumps at an end is bisected down to
// the jump and the far side re-solved from more starts; a profile that comes
// back under the threshold past a jump is followed (the interval widened);
// an end at the optimum (zero width), an optimum on the box edge, a profile
// that falls going outward or finds a lower chi^2 than the optimum are
// reported with their reason, never printed as a confident interval.

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>

#include <fmt/format.h>

#include "bridgefit/parallel/communicator.hpp"
#include "fit_impl.hpp"

namespace bridgefit::inverse::fit_internal {
namespace {

constexpr double kFirstStep = 0.004;      // box coordinates
constexpr int kBisections = 5;            // every end to at least the bracket / 2^5
constexpr double kCloseEnough = 0.95;     // an inside end at this fraction of the threshold is found
constexpr int kExtraBisections = 24;      // at most, near a jump or at the optimum
constexpr double kMinBracket = 1e-9;      // box coordinates: the finest bisection
constexpr double kJumpFactor = 4.0;       // Delta chi^2 past a smooth crossing stays below 4x the threshold
constexpr double kOnBound = 1e-3;         // box coordinates: an optimum this close to the edge is on it
constexpr double kZeroWidth = 1e-4;       // relative: an end this close to the value prints as the value
constexpr int kResolveStarts = 4;         // extra starts of a re-solved profile point
constexpr int kResolveEvaluations = 200;  // per start

int Severity(IntervalStatus s) {
  switch (s) {
    case IntervalStatus::kReliable: return 0;
    case IntervalStatus::kOpen: return 1;
    case IntervalStatus::kEndsOnBound: return 2;
    case IntervalStatus::kUnreliableNonSmooth: return 3;
    case IntervalStatus::kUnreliableZeroWidth: return 4;
    case IntervalStatus::kUnreliableMisfit: return 5;
  }
  return 0;
}

// The profile of one parameter: chi^2 with the parameter pinned at a box
// coordinate and the others re-optimized, and the search for its ends.
class ProfileSearch {
 public:
  ProfileSearch(const ForwardModel& model, const laws::LawShape& shape, const FitData& data,
                const FitOptions& options, int k, const LocalResult& best,
                const std::vector<double>& full, double threshold,
                const Eigen::MatrixXd* covariance, Profile& profile)
      : objective_(model, shape, data, options), options_(options), k_(k),
        index_(objective_.free()[k]), best_(best), full_(full), threshold_(threshold),
        profile_(profile), warm_(best.x) {
    SeedFromCovariance(covariance);
  }

  const Objective& objective() const { return objective_; }

  ProfileEdge Edge(double direction) {
    const double x0 = best_.x[k_];
    const bool up = direction > 0;
    if (up ? x0 >= 1.0 - kOnBound : x0 <= kOnBound)
      return {NAN, IntervalStatus::kEndsOnBound,
              fmt::format("the optimum sits on the box's {} edge ({:.4g}): the box, not the data, "
                          "ends the interval there; widen --bounds",
                          up ? "upper" : "lower", up ? options_.upper[index_] : options_.lower[index_])};
    warm_ = best_.x;
    double in = x0;
    std::string jump;
    for (int round = 0; round < 4; ++round) {
      const Bracket b = StepOut(direction, in);
      if (b.open) {
        if (jump.empty()) return {NAN, IntervalStatus::kOpen, ""};
        return {NAN, IntervalStatus::kUnreliableNonSmooth,
                jump + "; past it the profile comes back under the threshold and stays there to the box edge"};
      }
      if (!IsJump(b)) {
        if (!jump.empty())
          return {b.lo, IntervalStatus::kUnreliableNonSmooth,
                  jump + "; past it the profile comes back under the threshold: the interval is "
                         "widened to its last crossing"};
        if (b.lo == x0)
          return {NAN, IntervalStatus::kUnreliableZeroWidth,
                  fmt::format("the profile crosses the threshold within {:.2g} (box) of the optimum "
                              "even after {} bisections", kMinBracket, kBisections + kExtraBisections)};
        return {b.lo, IntervalStatus::kReliable, ""};
      }
      // A jump: the far side re-solved from more starts (a profile point may
      // have stopped in a poor local minimum).
      if (Inside(Resolve(b.hi))) {
        in = b.hi;
        continue;
      }
      if (jump.empty()) jump = JumpText(b);
      // Does the profile come back under the threshold further out?
      double p = b.hi, step = kFirstStep, back = NAN;
      while (true) {
        const double q = std::clamp(p + direction * step, 0.0, 1.0);
        if (q == p) break;
        if (Inside(Chi2(q))) {
          back = q;
          break;
        }
        p = q;
        step *= 2.0;
      }
      if (std::isnan(back)) {
        const double end = FromBox(index_, b.lo, options_);
        const bool zero = std::abs(end - full_[index_]) <= kZeroWidth * std::abs(full_[index_]);
        return {NAN, zero ? IntervalStatus::kUnreliableZeroWidth : IntervalStatus::kUnreliableNonSmooth,
                jump + (zero ? ", next to the optimum (a zero-width side)" : "") +
                    ", and stays above it out to the box edge, also re-solved from " +
                    std::to_string(kResolveStarts + 2) +
                    " starts: the forward model is not smooth there; no interval end printed"};
      }
      in = back;
    }
    return {NAN, IntervalStatus::kUnreliableNonSmooth,
            (jump.empty() ? std::string("the profile chi^2 jumps at every end found, and each re-solve "
                                        "from more starts moved it further out (4 rounds)")
                          : jump + " repeatedly") +
                "; no interval end printed"};
  }

  // A profile that falls going away from the optimum, or finds a lower
  // chi^2 than the optimum's.
  ProfileEdge Monotonicity() const {
    const double v0 = full_[index_];
    const double lower_tol = BelowOptimumTolerance(threshold_, best_.chi2);
    for (const ProfilePoint& p : profile_.points)
      if (p.ok && p.chi2 < best_.chi2 - lower_tol)
        return {NAN, IntervalStatus::kUnreliableNonSmooth,
                fmt::format("the profile finds chi^2 {:.5g} at {:.5g}, below the optimum's {:.5g}: "
                            "the fit stopped in a local minimum (rerun with more --starts)",
                            p.chi2, p.value, best_.chi2)};
    for (double direction : {-1.0, 1.0}) {
      std::vector<const ProfilePoint*> side;
      for (const ProfilePoint& p : profile_.points)
        if (p.ok && (p.value - v0) * direction > 0) side.push_back(&p);
      std::sort(side.begin(), side.end(), [&](const ProfilePoint* a, const ProfilePoint* b) {
        return (a->value - v0) * direction < (b->value - v0) * direction;
      });
      const ProfilePoint* highest = nullptr;
      for (const ProfilePoint* p : side) {
        if (highest && p->chi2 < highest->chi2 - 0.5 * threshold_)
          return {NAN, IntervalStatus::kUnreliableNonSmooth,
                  fmt::format("the profile is not monotone: chi^2 falls from {:.5g} at {:.5g} to "
                              "{:.5g} at {:.5g} going away from the optimum",
                              highest->chi2, highest->value, p->chi2, p->value)};
        if (!highest || p->chi2 > highest->chi2) highest = p;
      }
    }
    return {};
  }

  int resolves() const { return resolves_; }

 private:
  struct Bracket {
    double lo = NAN, hi = NAN;  // last inside, first outside (box coordinates)
    double chi2_lo = NAN, chi2_hi = NAN;
    bool open = false;          // inside up to the box edge
  };

  bool Inside(double chi2) const { return chi2 < kFailedCost && chi2 - best_.chi2 <= threshold_; }

  // The Jacobian covariance (physical units, free x free; may be null or
  // singular) gives each side's first step (30% of the Wald end's offset in
  // box coordinates: the steps out then probe about 30% and 60% of the
  // interval, where a jump inside it shows, and the next usually brackets
  // the end) and the linearised path of the other parameters along the
  // profile (their conditional mean, d p_j / d p_k = C_jk / C_kk, taken in
  // box coordinates, logarithmic for sigma_c and J_B), which starts the
  // local search of every point within two Wald half-widths of the optimum.
  void SeedFromCovariance(const Eigen::MatrixXd* covariance) {
    const std::vector<int>& free = objective_.free();
    slope_.assign(free.size(), 0.0);
    if (!covariance || covariance->rows() != static_cast<int>(free.size())) return;
    const double ckk = (*covariance)(k_, k_);
    if (!(std::isfinite(ckk) && ckk > 0.0)) return;
    const double sd = std::sqrt(ckk), v0 = full_[index_], x0 = best_.x[k_];
    wald_offset_[0] = x0 - ToBox(index_, v0 - 1.96 * sd, options_);
    wald_offset_[1] = ToBox(index_, v0 + 1.96 * sd, options_) - x0;
    // d x / d p of a box coordinate at the optimum.
    auto box_rate = [&](int index) {
      const double p = full_[index], lo = options_.lower[index], hi = options_.upper[index];
      return IsLogScale(index) ? 1.0 / (p * std::log(hi / lo)) : 1.0 / (hi - lo);
    };
    for (std::size_t j = 0; j < free.size(); ++j) {
      const double cjk = (*covariance)(static_cast<int>(j), k_);
      if (static_cast<int>(j) == k_ || !std::isfinite(cjk)) continue;
      const double slope = cjk / ckk * box_rate(free[j]) / box_rate(index_);
      if (std::isfinite(slope)) slope_[j] = slope;
    }
  }

  // The first step out from the optimum on one side (box coordinates).
  double FirstStep(double direction) const {
    const double wald = wald_offset_[direction > 0 ? 1 : 0];
    if (!(std::isfinite(wald) && wald > 0.0)) return kFirstStep;
    return std::clamp(0.3 * wald, kFirstStep, 0.25);
  }

  // The local search's start at box coordinate x: the nearest solved point
  // inside the interval moved along the linearised path (near the optimum).
  std::vector<double> StartAt(double x) const {
    std::vector<double> start = warm_;
    const double reach = 2.0 * std::max(wald_offset_[0], wald_offset_[1]);
    if (!(std::abs(x - best_.x[k_]) <= reach)) return start;
    const double dx = x - warm_[k_];
    for (std::size_t j = 0; j < start.size(); ++j)
      if (static_cast<int>(j) != k_) start[j] = std::clamp(warm_[j] + slope_[j] * dx, 0.0, 1.0);
    return start;
  }

  // The profile chi^2 at x; a point outside the region is solved again from
  // the plain warm start when the path's start differed (a start off the
  // path's validity must not make a profile look non-monotone).
  double Chi2(double x) {
    const std::vector<double> start = StartAt(x);
    const double chi2 = Solve(x, {start}, 80);
    if (Inside(chi2) || start == warm_) return chi2;
    const double again = Solve(x, {warm_}, 80);
    // One point per x in the profile: the better of the two.
    auto& points = profile_.points;
    points.erase(points.end() - (again < chi2 ? 2 : 1));
    return std::min(chi2, again);
  }

  // Profile chi^2 at x from the given starts; the point is recorded.
  double Solve(double x, const std::vector<std::vector<double>>& starts, int evaluations) {
    const double value = FromBox(index_, x, options_);
    std::vector<double> at = full_;
    at[index_] = value;
    double chi2 = kFailedCost;
    if (objective_.free().size() == 1) {
      chi2 = objective_.Chi2(at);
    } else {
      for (const std::vector<double>& x0 : starts) {
        // The pinned coordinate stays in the vector; its value is overridden.
        const LocalResult r =
            MinimizeNlopt(objective_, Optimizer::kBobyqa, x0, evaluations, index_, value, 1e-4);
        if (r.chi2 < chi2) {
          chi2 = r.chi2;
          at = objective_.Expand(r.x.data(), index_, value);
          if (Inside(chi2)) warm_ = r.x;
        }
      }
    }
    profile_.points.push_back({value, chi2, chi2 < kFailedCost, {at[0], at[1], at[2]}});
    return chi2;
  }

  // The profile point at x again, from the warm start, the optimum and a
  // Latin-hypercube design; the best is kept.
  double Resolve(double x) {
    if (objective_.free().size() == 1) return Chi2(x);
    ++resolves_;
    std::vector<std::vector<double>> starts = {warm_, best_.x};
    const auto design = LatinHypercube(kResolveStarts, static_cast<int>(best_.x.size()),
                                       options_.seed + 7919u * static_cast<unsigned>(resolves_));
    starts.insert(starts.end(), design.begin(), design.end());
    return Solve(x, starts, kResolveEvaluations);
  }

  // Where the bracket's crossing of the threshold lies: interpolated in
  // sqrt(Delta chi^2), linear in the parameter for a quadratic profile,
  // aimed just inside (the inside end is the one reported); a bisection
  // where the outside point is a jump or a failure, and kept off the
  // bracket's ends.
  double NextPoint(const Bracket& b) const {
    const double mid = 0.5 * (b.lo + b.hi);
    if (IsJump(b)) return mid;
    const double s_lo = std::sqrt(std::max(b.chi2_lo - best_.chi2, 0.0));
    const double s_hi = std::sqrt(std::max(b.chi2_hi - best_.chi2, 0.0));
    const double target = 0.99 * std::sqrt(threshold_);
    if (!(s_hi > s_lo)) return mid;
    const double t = std::clamp((target - s_lo) / (s_hi - s_lo), 0.1, 0.9);
    return b.lo + t * (b.hi - b.lo);
  }

  // Steps out from `in` (inside) until the profile leaves the 95% region,
  // then narrows the bracket (NextPoint) until its inside end is within
  // kCloseEnough of the threshold or after kBisections points; near a
  // jump, or while the inside end is still the optimum, bisection goes on
  // down to kMinBracket.
  Bracket StepOut(double direction, double in) {
    const double x0 = best_.x[k_];
    double step = in == x0 ? FirstStep(direction) : kFirstStep, chi2_in = best_.chi2;
    while (true) {
      const double out = std::clamp(in + direction * step, 0.0, 1.0);
      if (out == in) return {.open = true};
      const double c = Chi2(out);
      if (!Inside(c)) {
        Bracket b{in, out, chi2_in, c, false};
        // Narrowing: at most the old five bisections' precision (the
        // bracket / 2^kBisections); an interpolation that did not halve the
        // bracket is followed by a bisection (no one-sided stagnation).
        const double coarse_width = std::abs(b.hi - b.lo) / std::pow(2.0, kBisections);
        bool bisect_next = false;
        int narrowing = 0, extra = 0;
        while (true) {
          const bool fine = narrowing >= 2 * kBisections || std::abs(b.hi - b.lo) <= coarse_width;
          const bool located = b.lo != x0 && !IsJump(b) &&
                               b.chi2_lo - best_.chi2 >= kCloseEnough * threshold_;
          if (!fine && located) break;
          if (fine && !((b.chi2_hi - best_.chi2 > kJumpFactor * threshold_ || b.lo == x0) &&
                        std::abs(b.hi - b.lo) > kMinBracket && extra < kExtraBisections))
            break;
          ++(fine ? extra : narrowing);
          const double width = std::abs(b.hi - b.lo);
          const double mid = fine || bisect_next ? 0.5 * (b.lo + b.hi) : NextPoint(b);
          const double cm = Chi2(mid);
          if (Inside(cm)) {
            b.lo = mid;
            b.chi2_lo = cm;
          } else {
            b.hi = mid;
            b.chi2_hi = cm;
          }
          bisect_next = !bisect_next && std::abs(b.hi - b.lo) > 0.5 * width;
        }
        return b;
      }
      in = out;
      chi2_in = c;
      step *= 2.0;
    }
  }

  bool IsJump(const Bracket& b) const {
    return b.chi2_hi >= kFailedCost || b.chi2_hi - best_.chi2 > kJumpFactor * threshold_;
  }

  std::string JumpText(const Bracket& b) const {
    const double lo = FromBox(index_, b.lo, options_), hi = FromBox(index_, b.hi, options_);
    if (b.chi2_hi >= kFailedCost)
      return fmt::format("the forward runs fail between {:.6g} and {:.6g} (chi^2 {:.5g} inside)", lo,
                         hi, b.chi2_lo);
    return fmt::format("the profile chi^2 jumps from {:.5g} to {:.5g} between {:.6g} and {:.6g} "
                       "(threshold {:.5g} above the optimum's {:.5g})",
                       b.chi2_lo, b.chi2_hi, lo, hi, threshold_, best_.chi2);
  }

  const Objective objective_;
  const FitOptions& options_;
  const int k_, index_;
  const LocalResult& best_;
  const std::vector<double>& full_;
  const double threshold_;
  Profile& profile_;
  std::vector<double> warm_;  // the nearest point solved inside the interval
  std::vector<double> slope_;  // d p_j / d p_k along the linearised profile path
  std::array<double, 2> wald_offset_ = {NAN, NAN};  // Wald end offsets below, above (box)
  int resolves_ = 0;
};

}  // namespace

std::vector<ProfileRun> RunProfiles(const ForwardModel& model, const laws::LawShape& shape,
                                    const FitData& data, const FitOptions& options,
                                    const std::vector<int>& ks, const LocalResult& best,
                                    const std::vector<double>& full, double threshold,
                                    bool lower_side, const Eigen::MatrixXd* covariance) {
  std::vector<ProfileRun> runs;
  for (int k : ks) runs.push_back({.k = k});
  // Over ranks (options.ranks): profile q on rank q mod N, then every rank
  // gets every profile; the ranks must start from one optimum.
  parallel::Communicator* ranks =
      options.ranks && options.ranks->size() > 1 ? options.ranks : nullptr;
  if (ranks) CheckSameOptimum(*ranks, best, full, threshold);
  std::vector<std::size_t> mine;
  for (std::size_t q = 0; q < runs.size(); ++q)
    if (!ranks || ranks->OwnerOf(q) == ranks->rank()) mine.push_back(q);
  const int profile_threads = options.threads > 0 ? options.threads : 2;
  // The profiles are independent, and so are a profile's two sides (each
  // search starts from the optimum: ProfileSearch::Edge resets its warm
  // start): every side is a task with its own objective (and counters), so
  // three profiles fill two threads evenly; a profile's points are merged
  // before its shape check.
  struct Task {
    std::size_t q;
    double direction;
  };
  std::vector<Task> tasks;
  for (std::size_t q : mine) {
    if (lower_side) tasks.push_back({q, -1.0});
    tasks.push_back({q, +1.0});
  }
  std::vector<Profile> side_points(tasks.size());
  std::vector<ProfileEdge> edges(tasks.size());
  std::vector<int> evaluations(tasks.size()), failures(tasks.size()), resolves(tasks.size());
#pragma omp parallel for num_threads(profile_threads) \
    schedule(dynamic) if (tasks.size() > 1 && profile_threads > 1)
  for (std::size_t t = 0; t < tasks.size(); ++t) {
    ProfileSearch search(model, shape, data, options, runs[tasks[t].q].k, best, full, threshold,
                         covariance, side_points[t]);
    edges[t] = search.Edge(tasks[t].direction);
    evaluations[t] = search.objective().evaluations();
    failures[t] = search.objective().failures();
    resolves[t] = search.resolves();
  }
  for (std::size_t q : mine) {
    ProfileRun& run = runs[q];
    Profile& profile = run.profile;
    run.low = ProfileEdge{.x = 0.0};
    for (std::size_t t = 0; t < tasks.size(); ++t) {
      if (tasks[t].q != q) continue;
      (tasks[t].direction < 0.0 ? run.low : run.high) = edges[t];
      profile.points.insert(profile.points.end(), side_points[t].points.begin(),
                            side_points[t].points.end());
      profile.resolves += resolves[t];
      run.evaluations += evaluations[t];
      run.failures += failures[t];
    }
    const ProfileSearch search(model, shape, data, options, run.k, best, full, threshold,
                               covariance, profile);
    const int index = search.objective().free()[run.k];
    profile.parameter = index;
    profile.chi2_threshold = threshold;
    profile.points.push_back({full[index], best.chi2, true, {full[0], full[1], full[2]}});
    std::sort(profile.points.begin(), profile.points.end(),
              [](const ProfilePoint& a, const ProfilePoint& b) { return a.value < b.value; });
    profile.flat = run.low.status == IntervalStatus::kOpen || run.high.status == IntervalStatus::kOpen;
    // The worse side's status; a smooth-looking pair of ends is still
    // checked for a profile that falls outward or beats the optimum.
    const ProfileEdge shape_check = search.Monotonicity();
    for (const ProfileEdge* e : std::initializer_list<const ProfileEdge*>{&run.low, &run.high, &shape_check}) {
      if (Severity(e->status) > Severity(profile.status)) profile.status = e->status;
      if (!e->reason.empty()) {
        const char* side = e == &run.low ? "below: " : e == &run.high ? "above: " : "";
        profile.status_reason += (profile.status_reason.empty() ? "" : "; ") + std::string(side) + e->reason;
      }
    }
  }
  if (ranks) ShareProfileRuns(*ranks, runs);
  return runs;
}

}  // namespace bridgefit::inverse::fit_internal
