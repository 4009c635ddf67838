#pragma once
// The design chart (issue 19, `bridgefit design --chart DIR`): steady-state
// onset crack length against specimen size, the bound law's as a line, the
// fit region's spread shaded, the specimen's notch and the valid end of its
// growth window for reference (gnuplot, like the reports). The input is a
// value: campaign::DesignChartOf builds it from a design.

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace bridgefit::report {

struct DesignChartView {
  std::string title;            // plain text
  std::string size_name = "W";  // CT W, DCB L
  // Per size [m]; NaN where none. The shaded band runs from region_low to
  // region_high: the earliest and latest onset over the region's laws, up to
  // the window's end where some law of the region does not reach it.
  std::vector<double> size, notch, window_end, bound_onset, region_low, region_high;
  double smallest_bound = NAN, smallest_region = NAN;  // [m], NaN: none in the range
};

// Writes `out_dir`/onset.png with its data table (onset.dat) and script
// (chart.gp); an existing `out_dir` is replaced. Returns the PNG's path.
// Throws Error(kRuntime) when gnuplot fails (naming its log), kUsage for an
// empty view.
std::filesystem::path WriteDesignChart(const DesignChartView& view,
                                       const std::filesystem::path& out_dir,
                                       const std::string& gnuplot = "gnuplot");

}  // namespace bridgefit::report
