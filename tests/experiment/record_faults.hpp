#pragma once
// Faults a lab's record really has (issue 15), injected into a clean record:
// the issue's seven and six of our own. Each returns a new record; the rows
// the fault leaves alone keep their (load, displacement) values exactly, so a
// faulted R curve can be matched point by point with the clean one.
// Used by faults_test.cpp (R-curve methods) and faults_fit_test.cpp (fits).
// bridgefit headers first: <signal.h> (via gtest) defines a macro si_value
// that core/units.hpp uses as a parameter name.
#include "bridgefit/core/records.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace bridgefit::testing {

using Fault = std::function<ExperimentRecord(const ExperimentRecord&)>;
struct NamedFault {
  std::string name;
  Fault apply;
  bool from_issue = true;  // in issue 15's list (else one of our own)
};

inline int RowNearLoad(const ExperimentRecord& r, double fraction_of_max) {
  const double peak = *std::max_element(r.load.begin(), r.load.end());
  for (std::size_t i = 0; i < r.size(); ++i)
    if (r.load[i] >= fraction_of_max * peak) return static_cast<int>(i);
  return 0;
}
inline int LateGrowthRow(const ExperimentRecord& r) { return static_cast<int>(0.8 * r.size()); }
inline int MidRow(const ExperimentRecord& r) { return static_cast<int>(0.5 * r.size()); }

// Inserts `depth_m` of unloading and the reloading back after row k: linear
// in P-d through the origin of the row's secant, `steps` rows each way, at
// row k's crack length; time spread between rows k and k + 1.
inline ExperimentRecord InsertCycle(const ExperimentRecord& r, int k, double depth_m, int steps) {
  ExperimentRecord out = r;
  std::vector<double> P, d, a, t;
  const double C = r.displacement[k] / r.load[k];
  for (int s = 1; s <= 2 * steps; ++s) {
    const double frac = s <= steps ? double(s) / steps : double(2 * steps - s) / steps;
    const double dd = r.displacement[k] - frac * depth_m;
    d.push_back(dd);
    P.push_back(dd / C);
    if (r.has_crack_length()) a.push_back(r.crack_length[k]);
  }
  auto insert = [&](std::vector<double>& v, const std::vector<double>& extra) {
    if (!v.empty()) v.insert(v.begin() + k + 1, extra.begin(), extra.end());
  };
  insert(out.load, P);
  insert(out.displacement, d);
  insert(out.crack_length, a);
  if (!out.time.empty()) {
    const double t0 = r.time[k], t1 = k + 1 < int(r.size()) ? r.time[k + 1] : t0 + 1.0;
    for (int s = 0; s < 2 * steps; ++s) t.push_back(t0 + (t1 - t0) * (s + 1) / (2 * steps + 1));
    insert(out.time, t);
  }
  if (!out.images.empty()) out.images.insert(out.images.begin() + k + 1, 2 * steps, "");
  return out;
}

// `rows` rows in all: rows inserted between the originals (load,
// displacement and time linear; the crack reading held until the next
// row), the originals unchanged.
inline ExperimentRecord Resampled(const ExperimentRecord& r, int rows) {
  const int n = static_cast<int>(r.size());
  const int per = (rows - n) / (n - 1) + 1;
  ExperimentRecord o;
  o.source = r.source;
  for (int i = 0; i + 1 < n; ++i)
    for (int s = 0; s < per; ++s) {
      const double w = double(s) / per;
      auto mix = [&](const std::vector<double>& v) { return v[i] + w * (v[i + 1] - v[i]); };
      o.load.push_back(mix(r.load));
      o.displacement.push_back(mix(r.displacement));
      if (r.has_crack_length()) o.crack_length.push_back(r.crack_length[i]);
      if (!r.time.empty()) o.time.push_back(mix(r.time));
    }
  o.load.push_back(r.load.back());
  o.displacement.push_back(r.displacement.back());
  if (r.has_crack_length()) o.crack_length.push_back(r.crack_length.back());
  if (!r.time.empty()) o.time.push_back(r.time.back());
  return o;
}

// The issue's seven faults, in its order, then our own six.
inline std::vector<NamedFault> RecordFaults() {
  std::vector<NamedFault> f;
  f.push_back({"unload-reload 0.1 mm near the start", [](const ExperimentRecord& r) {
                 return InsertCycle(r, RowNearLoad(r, 0.3), 1e-4, 3);
               }});
  f.push_back({"0.04 mm displacement jitter at low load", [](const ExperimentRecord& r) {
                 ExperimentRecord o = r;
                 o.displacement[RowNearLoad(r, 0.12)] -= 4e-5;
                 return o;
               }});
  f.push_back({"0.07 mm single-row glitch late in growth", [](const ExperimentRecord& r) {
                 ExperimentRecord o = r;
                 o.displacement[LateGrowthRow(r)] -= 7e-5;
                 return o;
               }});
  f.push_back({"55-row NaN tail in crack length", [](const ExperimentRecord& r) {
                 ExperimentRecord o = r;
                 for (std::size_t i = r.size() - 55; i < r.size(); ++i) o.crack_length[i] = NAN;
                 return o;
               }});
  f.push_back({"repeated time stamp", [](const ExperimentRecord& r) {
                 ExperimentRecord o = r;
                 const int k = MidRow(r);
                 o.time[k] = o.time[k - 1];
                 return o;
               }});
  f.push_back({"full unload-reload cycle at mid-test", [](const ExperimentRecord& r) {
                 const int k = MidRow(r);
                 return InsertCycle(r, k, 0.95 * r.displacement[k], 15);
               }});
  f.push_back({"resampled to 100,000 rows",
               [](const ExperimentRecord& r) { return Resampled(r, 100000); }});
  f.push_back({"own: single-row load spike +20% mid-test",
               [](const ExperimentRecord& r) {
                 ExperimentRecord o = r;
                 o.load[MidRow(r) + 7] *= 1.2;
                 return o;
               },
               false});
  f.push_back({"own: two-row 0.04 mm jitter at low load",
               [](const ExperimentRecord& r) {
                 ExperimentRecord o = r;
                 const int k = RowNearLoad(r, 0.15);
                 o.displacement[k] -= 4e-5;
                 o.displacement[k + 1] -= 4e-5;
                 return o;
               },
               false});
  f.push_back({"own: partial unloading to 60% late in growth",
               [](const ExperimentRecord& r) {
                 const int k = LateGrowthRow(r) - 10;
                 return InsertCycle(r, k, 0.4 * r.displacement[k], 6);
               },
               false});
  f.push_back({"own: 30 preload rows and 25 rows after failure",
               [](const ExperimentRecord& r) {
                 ExperimentRecord o = r;
                 for (int s = 0; s < 30; ++s) {
                   o.load.insert(o.load.begin(), 0.001 * (s % 3));
                   o.displacement.insert(o.displacement.begin(), -1e-6 * (s + 1));
                   o.crack_length.insert(o.crack_length.begin(), r.crack_length.front());
                   if (!o.time.empty()) o.time.insert(o.time.begin(), r.time.front() - 0.1 * (s + 1));
                   if (!o.images.empty()) o.images.insert(o.images.begin(), "");
                 }
                 for (int s = 1; s <= 25; ++s) {
                   o.load.push_back(0.002 * r.load.back() * (s % 2));
                   o.displacement.push_back(r.displacement.back() + 1e-6 * s);
                   o.crack_length.push_back(r.crack_length.back());
                   if (!o.time.empty()) o.time.push_back(r.time.back() + s);
                   if (!o.images.empty()) o.images.push_back("");
                 }
                 return o;
               },
               false});
  f.push_back({"own: 40-row NaN stretch in crack length mid-test",
               [](const ExperimentRecord& r) {
                 ExperimentRecord o = r;
                 for (int i = MidRow(r); i < MidRow(r) + 40; ++i) o.crack_length[i] = NAN;
                 return o;
               },
               false});
  f.push_back({"own: 20 random single-row glitches in growth",
               [](const ExperimentRecord& r) {
                 ExperimentRecord o = r;
                 std::mt19937 rng(15);
                 const int n = static_cast<int>(r.size());
                 std::uniform_int_distribution<int> row(n / 3, n - 5);
                 std::uniform_real_distribution<double> size(3e-5, 1e-4);
                 for (int g = 0; g < 20; ++g) {
                   const int k = row(rng);
                   o.displacement[k] += (g % 2 ? 1 : -1) * size(rng);
                 }
                 return o;
               },
               false});
  return f;
}

// Every fault of the issue's list at once (where they can be combined):
// what a bad day in the lab gives.
inline ExperimentRecord AllIssueFaults(const ExperimentRecord& clean) {
  ExperimentRecord r = clean;
  for (const NamedFault& f : RecordFaults())
    if (f.from_issue && f.name.find("100,000") == std::string::npos) r = f.apply(r);
  return r;
}

}  // namespace bridgefit::testing
