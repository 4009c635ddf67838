#pragma once
// The settings of a crack-length DIC run as a user states them - `bridgefit
// dic`'s flags, a campaign manifest's [specimen.dic] table - in numbers (SI
// and px), and the one rule that turns them into CrackSequenceOptions: the
// grid-dependent defaults (SetGridDefaults), the jump threshold's floor as
// the path's smallest jump too, the Williams fit radius as the sqrt window
// too, a given line as a hint unless fixed. Defaults are `bridgefit dic`'s.

#include <optional>
#include <string>

#include "bridgefit/dic/sequence.hpp"

namespace bridgefit::dic {

struct DicSettings {
  double scale_m_per_px = 0;            // required, > 0
  double offset_m = 0;                  // added to every crack length
  std::optional<CrackLine> crack_line;  // reference px, from the notch into the material
  bool fixed_line = false;              // the line is the crack (no path search)
  bool own_paths = false;               // no sequence path (CrackSequenceOptions::sequence_path)
  int subset_px = 31;
  int step_px = 5;
  std::string tip_method = "williams";  // williams | jump | sqrt
  double threshold_px = 0.02;           // floor of the jump threshold
  double fit_radius_px = 0;             // Williams fit radius; 0: max(60, 5 subsets)
  double path_search_px = 40;           // path search half width across the line
  double min_zncc = 0.8;
  int seed_search_px = 40;
  int threads = 0;                      // OpenMP threads; 0: all
  bool show_progress = false;           // on stderr
};

// The options of AnalyzeCrackSequence for `settings`. Throws Error(kUsage)
// for an unknown tip method, a fixed line without a line, or a line whose
// ends coincide (field: the setting's name); the caller checks IsValid too.
CrackSequenceOptions MakeSequenceOptions(const DicSettings& settings);

}  // namespace bridgefit::dic
