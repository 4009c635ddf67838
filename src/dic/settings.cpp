// DIC settings -> sequence options (dic/settings.hpp): the one place the
// grid-dependent defaults and the settings that set two options are applied.
#include "bridgefit/dic/settings.hpp"

#include "bridgefit/core/error.hpp"

namespace bridgefit::dic {

CrackSequenceOptions MakeSequenceOptions(const DicSettings& s) {
  CrackSequenceOptions opt;
  opt.scale_m_per_px = s.scale_m_per_px;
  opt.offset_m = s.offset_m;
  opt.has_line = s.crack_line.has_value();
  opt.find_path = !s.fixed_line;
  opt.sequence_path = !s.own_paths;
  if (s.fixed_line && !opt.has_line)
    throw Error(ErrorKind::kUsage, "a fixed crack line needs the line",
                {.field = "fixed_line", .expected = "the crack line x0,y0,x1,y1 in px"});
  if (opt.has_line) {
    opt.tip.line = *s.crack_line;
    if (!(opt.tip.line.Length() > 1))
      throw Error(ErrorKind::kUsage, "crack line end points coincide",
                  {.field = "crack_line", .expected = "two points more than 1 px apart"});
  }
  CorrelationOptions& c = opt.correlation;
  c.min_zncc = s.min_zncc;
  c.seed_search_radius = s.seed_search_px;
  c.threads = s.threads;
  opt.method = ParseTipMethod(s.tip_method);
  SetGridDefaults(s.subset_px, s.step_px, &opt);
  opt.tip.threshold_floor_px = s.threshold_px;
  if (s.fit_radius_px > 0) opt.tip.fit_radius_px = opt.tip.sqrt_window_px = s.fit_radius_px;
  opt.path.min_jump_px = opt.tip.threshold_floor_px;
  opt.path.search_half_width_px = s.path_search_px;
  opt.show_progress = s.show_progress;
  return opt;
}

}  // namespace bridgefit::dic
