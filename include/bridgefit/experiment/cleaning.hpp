#pragma once
// Cleaning a test record as a lab produces it, before any R-curve method
// (docs/RCURVE_METHODS.md, "Cleaning"). Every rule is named, has a tolerance
// set from the record's own noise (or a fraction of its peak load) and an
// option to change it, and counts the rows it takes out of the R curve.
// A reversal never ends a test: unload-reload cycles are kept apart (the
// compliance methods use them), the record goes on after them.
//
// Rules, in the order they apply:
//   no crack length   NaN crack length in a row (only for methods that need it)
//   negative load     a few negative loads (mostly negative is an error upstream)
//   glitch            one row (or two) whose load or displacement leaves the line
//                     through its neighbours: second difference > glitch_tolerance x
//                     sqrt(6) sigma, the neighbours' of the opposite sign (a spike,
//                     not a step or a reversal); dropped and listed
//   before the preload leading rows with load < preload_fraction x max load
//   after final failure trailing rows after the last with load >= failure_fraction x max
//   unload-reload cycle rows from where the displacement falls more than
//                     reversal_tolerance sigma below its running maximum until it
//                     is back within that band; less than that is jitter, not a
//                     reversal (counted in the notes, rows kept)
//   final unloading   a reversal that never comes back before the record ends

#include <string>
#include <vector>

#include "bridgefit/core/records.hpp"

namespace bridgefit::experiment {

struct CleaningOptions {
  double reversal_tolerance = 3.0;   // [noise sigmas of d] --reversal-tolerance
  double glitch_tolerance = 10.0;    // [noise sigmas] --glitch-tolerance
  double preload_fraction = 0.01;    // [x max load] --preload-fraction
  double failure_fraction = 0.05;    // [x max load] --failure-fraction
  double warn_fraction = 0.05;       // a rule taking more than this share of rows warns

  bool IsValid(std::string* why) const;
};

// One named rule's count; `option` is the CLI option that sets its tolerance.
struct CleaningRule {
  std::string reason;
  std::string option;
  int count = 0;
};

struct CleanedRecord {
  std::vector<int> rows;                 // envelope rows every method uses, record order
  std::vector<std::vector<int>> cycles;  // unload-reload rows, one list per cycle
  std::vector<int> glitch_rows;          // 0-based record rows dropped as glitches
  std::vector<CleaningRule> rules;       // rows taken out, by rule (count > 0 only)
  std::vector<std::string> notes;
  std::vector<std::string> warnings;     // a rule above warn_fraction of the rows
  double load_noise = NAN;               // sigma used for the tolerances [N]
  double displacement_noise = NAN;       // [m]
  int jitter_rows = 0;                   // backward steps inside the jitter band (kept)
  int brief_reversal_rows = 0;           // backward steps beyond it that formed no cycle (kept)
  int repeated_time_rows = 0;            // rows with the time of the row before (kept)
};

// Classifies every row of `record`. `needs_crack_length`: rows without a
// finite crack length are taken out. Noise levels NaN: estimated (robust
// second differences). Every row is in `rows`, in a cycle, or in a rule.
CleanedRecord CleanRecord(const ExperimentRecord& record, const CleaningOptions& options,
                          bool needs_crack_length, double load_noise, double displacement_noise);

}  // namespace bridgefit::experiment
