// The design chart (include/bridgefit/report/design_chart.hpp): data table +
// gnuplot script -> RunGnuplot -> Publish (the reports' staging).
#include "bridgefit/report/design_chart.hpp"

#include <sstream>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "report_impl.hpp"

namespace bridgefit::report {

std::filesystem::path WriteDesignChart(const DesignChartView& view,
                                       const std::filesystem::path& out_dir,
                                       const std::string& gnuplot) {
  if (view.size.empty())
    throw Error(ErrorKind::kUsage, "no sizes to chart", {.field = "design chart"});
  if (out_dir.empty())
    throw Error(ErrorKind::kUsage, "the chart folder is empty", {.field = "--chart"});
  detail::StagingFolder staging(out_dir);
  detail::FigureSet set;
  set.dir = staging.path;
  std::ostringstream data;
  data << "# size [mm], notch a0 [mm], window end [mm], bound-law onset [mm], region earliest "
          "onset [mm], region latest onset [mm] (nan: not reached)\n";
  const auto mm = [](double v) {
    return std::isfinite(v) ? fmt::format("{:.6g}", v * 1e3) : std::string("nan");
  };
  for (std::size_t i = 0; i < view.size.size(); ++i)
    data << fmt::format("{} {} {} {} {} {}\n", mm(view.size[i]), mm(view.notch[i]),
                        mm(view.window_end[i]), mm(view.bound_onset[i]), mm(view.region_low[i]),
                        mm(view.region_high[i]));
  detail::WriteFile(set.dir / "onset.dat", data.str());
  std::string marks;
  if (std::isfinite(view.smallest_bound))
    marks += fmt::format(
        "set arrow from {0:.6g}, graph 0 to {0:.6g}, graph 1 nohead dt 2 lc rgb '#1f4e9a'\n"
        "set label 'smallest, bound law' at {0:.6g}, graph 0.60 left offset 0.5,0 tc rgb "
        "'#1f4e9a'\n",
        view.smallest_bound * 1e3);
  if (std::isfinite(view.smallest_region))
    marks += fmt::format(
        "set arrow from {0:.6g}, graph 0 to {0:.6g}, graph 1 nohead dt 2 lc rgb '#c0392b'\n"
        "set label 'smallest, whole region' at {0:.6g}, graph 0.53 left offset 0.5,0 tc rgb "
        "'#c0392b'\n",
        view.smallest_region * 1e3);
  set.gp =
      "# gnuplot script of the design chart (run: gnuplot chart.gp)\nset datafile missing "
      "'nan'\nset grid\n";
  set.gp += detail::kTerminal;
  set.gp += fmt::format(
      "set output 'onset.png'\nset key inside top left opaque box samplen 2 font 'Sans,9'\nset "
      "xlabel 'specimen size {0} [mm]'\n"
      "set ylabel 'crack length a [mm]'\nset title '{1}' noenhanced\n{2}"
      "plot 'onset.dat' using 1:5:6 with filledcurves fs transparent solid 0.3 noborder lc rgb "
      "'#c0392b' title 'fit region: onset (to the window end where not reached)', "
      "'' using 1:4 with linespoints pt 7 lw 2 lc rgb '#1f4e9a' title 'bound law: onset', "
      "'' using 1:3 with lines dt 3 lw 2 lc rgb 'black' title 'valid end of the window', "
      "'' using 1:2 with lines dt 4 lc rgb 'gray40' title 'notch a0'\n",
      detail::GnuplotText(view.size_name), detail::GnuplotText(view.title), marks);
  set.Add("onset.png", "design", "steady-state onset against size");
  detail::RunGnuplot(set, gnuplot);
  std::filesystem::rename(set.dir / "report.gp", set.dir / "chart.gp");
  staging.Publish();
  return staging.target / "onset.png";
}

}  // namespace bridgefit::report
