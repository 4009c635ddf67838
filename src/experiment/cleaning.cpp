// Record cleaning by named rules (include/bridgefit/experiment/cleaning.hpp).
#include "bridgefit/experiment/cleaning.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bridgefit/experiment/rcurve.hpp"

namespace bridgefit::experiment {
namespace {

enum Fate : int {
  kKeep = 0,
  kNoCrack,
  kNegative,
  kGlitch,
  kPreload,
  kFailure,
  kCycle,
  kFinalUnloading,
  kFateCount
};

// Rule names and the option that sets each one's tolerance (CLI names;
// the library fields are CleaningOptions' of the same name).
const char* RuleReason(int fate) {
  switch (fate) {
    case kNoCrack: return "no crack length (NaN) in the row";
    case kNegative: return "negative load";
    case kGlitch: return "glitch (a one- or two-row spike in load or displacement)";
    case kPreload: return "before the preload (load below the preload fraction of the maximum)";
    case kFailure: return "after final failure (load below the failure fraction of the maximum)";
    case kCycle: return "unload-reload cycle (no R point; its compliance is used)";
    case kFinalUnloading: return "final unloading (displacement falls and never comes back)";
  }
  return "?";
}
const char* RuleOption(int fate) {
  switch (fate) {
    case kNoCrack: return "--method equivalent (needs no crack length)";
    case kNegative: return "check the load's sign convention";
    case kGlitch: return "--glitch-tolerance";
    case kPreload: return "--preload-fraction";
    case kFailure: return "--failure-fraction";
    case kCycle:
    case kFinalUnloading: return "--reversal-tolerance";
  }
  return "?";
}

std::vector<int> KeptRows(const std::vector<int>& fate) {
  std::vector<int> rows;
  for (int i = 0; i < static_cast<int>(fate.size()); ++i)
    if (fate[i] == kKeep) rows.push_back(i);
  return rows;
}

// A one-row spike in v over the kept rows: its second difference s_k is
// beyond `tol` and the neighbours' second differences have the opposite sign
// and at least a quarter of its size (an outlier e gives e, -2e, e; a step or a
// reversal gives e, -e, 0).
void MarkGlitches(const std::vector<double>& v, double tol, std::vector<int>& fate,
                  std::vector<int>& listed) {
  const std::vector<int> rows = KeptRows(fate);
  const int m = static_cast<int>(rows.size());
  if (m < 5) return;
  auto s = [&](int q) { return v[rows[q - 1]] - 2.0 * v[rows[q]] + v[rows[q + 1]]; };
  for (int q = 1; q + 1 < m; ++q) {
    const double here = s(q);
    if (!(std::abs(here) > tol)) continue;
    bool spike = true;
    for (int nb : {q - 1, q + 1}) {
      if (nb < 1 || nb + 1 >= m) continue;
      const double other = s(nb);
      spike &= other * here < 0.0 && std::abs(other) > 0.25 * std::abs(here);
    }
    if (!spike) continue;
    fate[rows[q]] = kGlitch;
    listed.push_back(rows[q]);
    ++q;  // the next row's test used this one
  }
  // Two-row spikes (offset e on rows q, q + 1): second differences e, -e, -e, e
  // (a step gives e, -e, 0).
  const std::vector<int> left = KeptRows(fate);
  const int ml = static_cast<int>(left.size());
  auto s2 = [&](int q) { return v[left[q - 1]] - 2.0 * v[left[q]] + v[left[q + 1]]; };
  for (int q = 2; q + 3 < ml; ++q) {
    const double a = s2(q), b = s2(q + 1);
    if (!(std::abs(a) > tol && std::abs(b) > tol && a * b > 0.0)) continue;
    const double before = s2(q - 1), after = s2(q + 2);
    const double size = std::min(std::abs(a), std::abs(b));
    if (!(before * a < 0.0 && after * a < 0.0 && std::abs(before) > 0.5 * size &&
          std::abs(after) > 0.5 * size))
      continue;
    fate[left[q]] = fate[left[q + 1]] = kGlitch;
    listed.push_back(left[q]);
    listed.push_back(left[q + 1]);
    q += 2;
  }
}

}  // namespace

bool CleaningOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!(reversal_tolerance >= 0)) return fail("reversal_tolerance must be >= 0 noise sigmas");
  if (!(glitch_tolerance > 0)) return fail("glitch_tolerance must be > 0 noise sigmas");
  if (!(preload_fraction >= 0 && preload_fraction < 1))
    return fail("preload_fraction must be in [0, 1) of the maximum load");
  if (!(failure_fraction >= 0 && failure_fraction < 1))
    return fail("failure_fraction must be in [0, 1) of the maximum load");
  if (!(warn_fraction > 0)) return fail("warn_fraction must be > 0");
  return true;
}

CleanedRecord CleanRecord(const ExperimentRecord& record, const CleaningOptions& options,
                          bool needs_crack_length, double load_noise, double displacement_noise) {
  const int n = static_cast<int>(record.size());
  CleanedRecord out;
  std::vector<int> fate(n, kKeep);
  if (needs_crack_length && record.has_crack_length())
    for (int i = 0; i < n; ++i)
      if (!std::isfinite(record.crack_length[i])) fate[i] = kNoCrack;
  for (int i = 0; i < n; ++i)
    if (fate[i] == kKeep && record.load[i] < 0.0) fate[i] = kNegative;

  // Noise levels from the rows left (robust to spikes and cycles).
  std::vector<double> P, d;
  for (int i : KeptRows(fate)) P.push_back(record.load[i]), d.push_back(record.displacement[i]);
  double maxP = 0.0, maxd = 0.0;
  for (double p : P) maxP = std::max(maxP, p);
  for (double x : d) maxd = std::max(maxd, std::abs(x));
  out.load_noise = std::max(std::isnan(load_noise) ? RobustNoiseSigma(P) : load_noise, 1e-9 * maxP);
  out.displacement_noise = std::max(
      std::isnan(displacement_noise) ? RobustNoiseSigma(d) : displacement_noise, 1e-9 * maxd);

  // Single-row glitches: displacement first, then load.
  MarkGlitches(record.displacement, options.glitch_tolerance * std::sqrt(6.0) * out.displacement_noise,
               fate, out.glitch_rows);
  MarkGlitches(record.load, options.glitch_tolerance * std::sqrt(6.0) * out.load_noise, fate,
               out.glitch_rows);
  std::sort(out.glitch_rows.begin(), out.glitch_rows.end());

  // Preload and final failure, from the peak of the rows left.
  std::vector<int> rows = KeptRows(fate);
  double peak = 0.0;
  for (int i : rows) peak = std::max(peak, record.load[i]);
  if (peak > 0.0) {
    for (int i : rows) {
      if (record.load[i] >= options.preload_fraction * peak) break;
      fate[i] = kPreload;
    }
    for (auto it = rows.rbegin(); it != rows.rend(); ++it) {
      if (record.load[*it] >= options.failure_fraction * peak) break;
      fate[*it] = kFailure;
    }
  }

  // Reversals. The envelope level is the running maximum of the displacement
  // held for 3 rows (min over 3 rows), so a noisy maximum does not set it; a
  // reversal starts where the displacement stays below level - tol for 3 rows
  // and ends where it is back within tol of the level.
  rows = KeptRows(fate);
  const int m = static_cast<int>(rows.size());
  const double tol = std::max(options.reversal_tolerance * out.displacement_noise, 1e-6 * maxd);
  auto dq = [&](int q) { return record.displacement[rows[q]]; };
  double level = -INFINITY;
  std::vector<int> cycle;
  for (int q = 0; q < m; ++q) {
    if (cycle.empty()) {
      bool below = true;
      for (int r = q; r < std::min(m, q + 3); ++r) below &= dq(r) < level - tol;
      if (!below) {
        // A step back: jitter within the tolerance, else a reversal too brief
        // (or too shallow against the held maximum) to form a cycle.
        if (q > 0 && dq(q) < dq(q - 1)) ++(dq(q - 1) - dq(q) > tol ? out.brief_reversal_rows : out.jitter_rows);
        double held = dq(q);
        for (int r = q + 1; r < std::min(m, q + 3); ++r) held = std::min(held, dq(r));
        level = std::max(level, held);
        continue;
      }
      cycle.push_back(rows[q]);
      continue;
    }
    if (dq(q) >= level - tol) {
      out.cycles.push_back(cycle);
      cycle.clear();
      continue;
    }
    cycle.push_back(rows[q]);
  }
  for (const std::vector<int>& c : out.cycles)
    for (int i : c) fate[i] = kCycle;
  for (int i : cycle) fate[i] = kFinalUnloading;

  if (!record.time.empty()) {
    int previous = -1;
    for (int i = 0; i < n; ++i) {
      if (fate[i] != kKeep) continue;
      if (previous >= 0 && record.time[i] == record.time[previous]) ++out.repeated_time_rows;
      previous = i;
    }
  }

  out.rows = KeptRows(fate);
  std::vector<int> counts(kFateCount, 0);
  for (int f : fate) ++counts[f];
  for (int f = kNoCrack; f < kFateCount; ++f) {
    if (counts[f] == 0) continue;
    out.rules.push_back({RuleReason(f), RuleOption(f), counts[f]});
    if (counts[f] > options.warn_fraction * n)
      out.warnings.push_back(fmt::format(
          "{}: cleaning rule '{}' took {} of {} rows ({:.1f}%) out of the R curve; {} {}",
          record.source, RuleReason(f), counts[f], n, 100.0 * counts[f] / n,
          f == kNoCrack || f == kNegative ? "way out:" : "its tolerance is set by", RuleOption(f)));
  }
  if (!out.glitch_rows.empty()) {
    std::string list;
    for (std::size_t k = 0; k < std::min<std::size_t>(out.glitch_rows.size(), 12); ++k)
      list += (k ? ", " : "") + std::to_string(out.glitch_rows[k] + 1);
    if (out.glitch_rows.size() > 12) list += fmt::format(" and {} more", out.glitch_rows.size() - 12);
    out.notes.push_back(fmt::format(
        "glitches (one- or two-row spikes) dropped at record rows {} (1-based; tolerance {:g} noise sigmas)", list,
        options.glitch_tolerance));
  }
  if (!out.cycles.empty()) {
    std::string list;
    for (std::size_t k = 0; k < std::min<std::size_t>(out.cycles.size(), 8); ++k)
      list += fmt::format("{}{}-{}", k ? ", " : "", out.cycles[k].front() + 1, out.cycles[k].back() + 1);
    if (out.cycles.size() > 8) list += fmt::format(" and {} more", out.cycles.size() - 8);
    out.notes.push_back(fmt::format(
        "{} unload-reload cycle(s) at rows {}: kept apart (no R points on them; the record goes on "
        "after each); reversal tolerance {:.3g} mm ({:g} noise sigmas)",
        out.cycles.size(), list, tol * 1e3, options.reversal_tolerance));
  }
  if (out.jitter_rows > 0)
    out.notes.push_back(fmt::format(
        "{} rows step back in displacement by less than the reversal tolerance ({:.3g} mm): "
        "jitter, kept",
        out.jitter_rows, tol * 1e3));
  if (out.brief_reversal_rows > 0)
    out.notes.push_back(fmt::format(
        "{} rows step back in displacement by more than the reversal tolerance ({:.3g} mm) but "
        "too briefly to count as an unload-reload cycle (fewer than 3 rows below the held "
        "maximum): kept as envelope rows; check them (rows of a brief unloading give R below "
        "the toughness if they fall after initiation)",
        out.brief_reversal_rows, tol * 1e3));
  if (out.repeated_time_rows > 0)
    out.notes.push_back(fmt::format(
        "{} rows repeat the time stamp of the row before: kept (values differ); time-based "
        "smoothing uses the row order instead",
        out.repeated_time_rows));
  return out;
}

}  // namespace bridgefit::experiment
