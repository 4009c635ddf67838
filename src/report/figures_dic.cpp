// DIC evidence: the reference frame, the last frame and every flagged frame
// with the crack line (or path), the tips of all frames and the field-fit
// window drawn on them; the opening along the crack for a few frames; the
// frame table linking to the drawn frames.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/image.hpp"
#include "report_impl.hpp"

namespace bridgefit::report::detail {
namespace {

// An 8-bit copy of a frame for gnuplot: gray levels stretched between the
// 0.5 and 99.5 percentiles (16-bit and dark images stay readable), block-
// averaged by an integer factor so it is at most 1000 px wide. Returns the
// factor (pixels of the original per pixel of the copy).
int WritePreview(const fs::path& source, const fs::path& target, int* width, int* height) {
  const dic::Image image = dic::ReadImage(source);
  *width = image.width;
  *height = image.height;
  const int factor = std::max(1, (image.width + 999) / 1000);
  dic::Image small(image.width / factor, image.height / factor);
  for (int y = 0; y < small.height; ++y)
    for (int x = 0; x < small.width; ++x) {
      double sum = 0.0;
      for (int j = 0; j < factor; ++j)
        for (int i = 0; i < factor; ++i) sum += image.at(x * factor + i, y * factor + j);
      small.at(x, y) = static_cast<float>(sum / (factor * factor));
    }
  std::vector<float> sorted(small.pixels);
  std::sort(sorted.begin(), sorted.end());
  const float lo = sorted[sorted.size() / 200], hi = sorted[sorted.size() - 1 - sorted.size() / 200];
  const float span = hi > lo ? hi - lo : 1.0f;
  for (float& p : small.pixels) p = std::clamp((p - lo) / span * 255.0f, 0.0f, 255.0f);
  dic::WriteImage(target, small, 8);
  return factor;
}

std::string FrameName(size_t k) { return fmt::format("dic_frame_{:04d}", k); }

// Position along the crack line of an image point, in px from (x0, y0).
double AlongLine(const DicView& dic, double x, double y) {
  const double dx = dic.line[2] - dic.line[0], dy = dic.line[3] - dic.line[1];
  const double length = std::hypot(dx, dy);
  return ((x - dic.line[0]) * dx + (y - dic.line[1]) * dy) / length;
}

// The frames drawn: reference, last, flagged (at most `max_flagged`).
std::vector<size_t> FramesToDraw(const DicView& dic, int max_flagged, std::vector<std::string>& notes) {
  std::vector<size_t> frames{0};
  int flagged = 0, skipped = 0;
  for (size_t k = 1; k + 1 < dic.frames.size(); ++k)
    if (!dic.frames[k].flag.empty()) (flagged++ < max_flagged ? frames.push_back(k) : void(++skipped));
  if (dic.frames.size() > 1) frames.push_back(dic.frames.size() - 1);
  if (skipped > 0)
    notes.push_back(fmt::format("{} more flagged DIC frames not drawn (at most {}; see the frame table)", skipped,
                                max_flagged));
  return frames;
}

void AddOverlay(const DicView& dic, size_t k, FigureSet& set, double window_px, bool window_assumed) {
  const DicFrame& frame = dic.frames[k];
  const std::string name = FrameName(k);
  int width = 0, height = 0;
  const int factor = WritePreview(frame.image_file, set.dir / (name + "_image.png"), &width, &height);
  std::string& gp = set.gp;
  gp += kTerminal;
  const int canvas_w = 860;
  const int canvas_h = std::clamp(static_cast<int>(canvas_w * 0.86 * height / width) + 110, 300, 1100);
  gp += fmt::format("set terminal pngcairo size {},{} enhanced font 'Sans,10'\n", canvas_w, canvas_h);
  gp += "set output '" + name + ".png'\n";
  const std::string title = k == 0 ? "reference frame" : k + 1 == dic.frames.size() ? "last frame" : "flagged frame";
  gp += fmt::format("set title '{} {}: {}{}' noenhanced\n", title, k,
                    GnuplotText(fs::path(frame.image).filename().string()),
                    frame.flag.empty() ? "" : " (flagged: see the caption)");
  gp += "set style textbox opaque fc rgb 'white' noborder margins 1,1\n";
  gp += "set size ratio -1\nset lmargin at screen 0.07\nset rmargin at screen 0.75\n";
  gp += fmt::format("set xrange [0:{}]\nset yrange [{}:0]\n", width - 1, height - 1);
  gp += "set xlabel 'x [px]'\nset ylabel 'y [px]'\nset key outside right top font ',9'\nset ytics out\n";
  // The field-fit window: this frame's (bold), or on the reference every frame's (faint).
  int objects = 0;  // the circles; the legend entry is a dummy line of the same style
  for (size_t j = 1; j < dic.frames.size(); ++j) {
    const DicFrame& f = dic.frames[j];
    if (!(std::isfinite(f.tip_x) && std::isfinite(window_px)) || (k != 0 && j != k)) continue;
    gp += fmt::format("set object {} circle at {:.6g},{:.6g} size {:.6g} front fs empty border lc rgb '{}' lw {} {}\n",
                      ++objects, f.tip_x, f.tip_y, window_px, k == 0 ? "#ffbf00" : "#ff7f0e", k == 0 ? 1.5 : 2.5,
                      k == 0 ? "dt 2" : "");
  }
  std::string plot = fmt::format("plot '{}_image.png' binary filetype=png flipy dx={} dy={} with rgbimage notitle",
                                 name, factor, factor);
  if (dic.has_line)
    plot += ", 'dic_line.dat' u 1:2 w l lw 2 lc rgb '#1f77b4' t 'crack line (DIC)'";
  const bool frame_path = !frame.path_x.empty();
  if (frame_path || !dic.path_x.empty()) {
    std::string path = "# x[px] y[px]\n";
    const std::vector<double>& px = frame_path ? frame.path_x : dic.path_x;
    const std::vector<double>& py = frame_path ? frame.path_y : dic.path_y;
    for (size_t i = 0; i < px.size(); ++i) path += fmt::format("{:.6g} {:.6g}\n", px[i], py[i]);
    WriteFile(set.dir / (name + "_path.dat"), path);
    plot += ", '" + name + "_path.dat' u 1:2 w l lw 2 lc rgb '#d62728' t 'crack path (DIC)'";
  }
  plot += ", 'dic_tips.dat' u 1:2 w p pt 6 ps 1.2 lw 2 lc rgb '#2ca02c' t 'tips, all frames'"
          ", '' u 1:2:(sprintf('%d', $3)) w labels boxed offset 0,-1.3 font ',8' tc rgb '#006400' notitle";
  // Each tip method's position on this frame's line: the evidence of a disagreement.
  if (k != 0 && dic.has_line) {
    const double dx = dic.line[2] - dic.line[0], dy = dic.line[3] - dic.line[1], length = std::hypot(dx, dy);
    std::string methods = "# x[px] y[px] method (0 williams, 1 jump, 2 sqrt)\n";
    const double along[3] = {frame.tip_williams_s, frame.tip_jump_s, frame.tip_sqrt_s};
    bool any = false;
    for (int m = 0; m < 3; ++m)
      if (std::isfinite(along[m])) {
        methods += fmt::format("{:.6g} {:.6g} {}\n", dic.line[0] + along[m] * dx / length,
                               dic.line[1] + along[m] * dy / length, m);
        any = true;
      }
    if (any) {
      WriteFile(set.dir / (name + "_methods.dat"), methods);
      plot += ", '" + name + "_methods.dat' u 1:($3 == 0 ? $2 : 1/0) w p pt 2 ps 1.6 lw 2 lc rgb '#e377c2' t 'Williams fit'"
              ", '' u 1:($3 == 1 ? $2 : 1/0) w p pt 4 ps 1.6 lw 2 lc rgb '#8c564b' t 'jump'"
              ", '' u 1:($3 == 2 ? $2 : 1/0) w p pt 8 ps 1.6 lw 2 lc rgb '#17becf' t 'sqrt opening'";
    }
  }
  if (k != 0 && std::isfinite(frame.tip_x)) {
    WriteFile(set.dir / (name + "_tip.dat"), fmt::format("# tip_x[px] tip_y[px]\n{:.6g} {:.6g}\n", frame.tip_x,
                                                         frame.tip_y));
    plot += ", '" + name + "_tip.dat' u 1:2 w p pt 3 ps 2.5 lw 3 lc rgb '#ff7f0e' t 'this frame''s tip'";
  }
  if (objects > 0)
    plot += fmt::format(", 1/0 w l lw 2 {} lc rgb '{}' t 'field-fit window{}{}'", k == 0 ? "dt 2" : "",
                        k == 0 ? "#ffbf00" : "#ff7f0e", k == 0 ? "s" : "", window_assumed ? " (default radius)" : "");
  gp += plot + "\n";
  set.Add(name + ".png", "dic",
          fmt::format("DIC {} {} ({}): crack line{} in blue, the tips of all frames (green, numbered), "
                      "{} (radius {:.0f} px{}). Positions in reference-image pixels.",
                      title, k, Escape(frame.image), frame_path || !dic.path_x.empty() ? " and path (red)" : "",
                      k == 0 ? "the field-fit window of every frame (dashed)"
                             : "this frame's tip (orange star), where each tip method put it (Williams fit, displacement jump, sqrt opening) and the field-fit window",
                      window_px, window_assumed ? ", the default: the DIC file does not record it" : "") +
              (frame.flag.empty() ? "" : " <b>Flagged:</b> " + Escape(frame.flag) + "."));
}

// Opening along the crack for up to four frames spread over the sequence.
void AddOpeningFigure(const DicView& dic, FigureSet& set) {
  std::vector<size_t> with_cod;
  for (size_t k = 1; k < dic.frames.size(); ++k)
    if (!dic.frames[k].cod_s.empty()) with_cod.push_back(k);
  if (with_cod.empty() || !std::isfinite(dic.scale_m_per_px)) return;
  std::vector<size_t> chosen;
  const size_t count = std::min<size_t>(4, with_cod.size());
  for (size_t i = 0; i < count; ++i) {
    const size_t k = with_cod[count == 1 ? with_cod.size() - 1
                                         : (i * (with_cod.size() - 1) + (count - 1) / 2) / (count - 1)];
    if (std::find(chosen.begin(), chosen.end(), k) == chosen.end()) chosen.push_back(k);
  }
  const double offset_mm = std::isfinite(dic.offset_m) ? dic.offset_m * 1e3 : 0.0;
  const char* colours[] = {"#1f77b4", "#2ca02c", "#9467bd", "#d62728"};
  std::string& gp = set.gp;
  gp += kTerminal;
  gp += "set output 'dic_opening.png'\nset title 'Opening along the crack line (DIC displacement jump)'\n";
  gp += "set xlabel 'position along the crack line, as crack length a [mm]'\nset ylabel 'opening [{/Symbol m}m]'\n";
  gp += "set key top right\nset lmargin at screen 0.11\nset rmargin at screen 0.97\n";
  std::string plot = "plot 0 w l lc rgb 'black' notitle";
  for (size_t i = 0; i < chosen.size(); ++i) {
    const DicFrame& f = dic.frames[chosen[i]];
    std::string dat = "# a[mm] opening[um] (frame " + std::to_string(chosen[i]) + ")\n";
    for (size_t j = 0; j < f.cod_s.size(); ++j)
      dat += fmt::format("{:.8g} {:.8g}\n", offset_mm + f.cod_s[j] * dic.scale_m_per_px * 1e3,
                         f.cod_opening[j] * dic.scale_m_per_px * 1e6);
    const std::string file = fmt::format("dic_opening_{:04d}.dat", chosen[i]);
    WriteFile(set.dir / file, dat);
    plot += fmt::format(", '{}' u 1:2 w lp pt 7 ps 0.4 lc rgb '{}' t 'frame {}'", file, colours[i % 4], chosen[i]);
    double tip_mm = std::isfinite(f.crack_length) ? f.crack_length * 1e3 : NAN;
    if (!std::isfinite(tip_mm) && dic.has_line && std::isfinite(f.tip_x))
      tip_mm = offset_mm + AlongLine(dic, f.tip_x, f.tip_y) * dic.scale_m_per_px * 1e3;
    if (std::isfinite(tip_mm))
      gp += fmt::format("set arrow from {0:.8g}, graph 0 to {0:.8g}, graph 1 nohead dt 2 lc rgb '{1}'\n", tip_mm,
                        colours[i % 4]);
  }
  gp += plot + "\n";
  set.Add("dic_opening.png", "dic",
          "Opening (normal displacement jump across the crack line) against position, for frames spread over "
          "the sequence; the dashed line of each colour is that frame's tip (its reported crack length).");
}

}  // namespace

void AddDicFigures(const ReportInput& in, FigureSet& set) {
  if (!in.dic) return;
  const DicView& dic = *in.dic;
  if (!dic.has_geometry()) {
    set.notes.push_back("DIC evidence figures need the DIC HDF5 file (bridgefit dic --out dic.h5, then "
                        "--dic dic.h5): only the crack lengths of the CSV are shown");
  } else {
    if (dic.has_line) {
      WriteFile(set.dir / "dic_line.dat", fmt::format("# x[px] y[px]\n{:.6g} {:.6g}\n{:.6g} {:.6g}\n", dic.line[0],
                                                      dic.line[1], dic.line[2], dic.line[3]));
    }
    std::string tips = "# tip_x[px] tip_y[px] frame crack_length[mm]\n";
    for (size_t k = 0; k < dic.frames.size(); ++k)
      if (std::isfinite(dic.frames[k].tip_x))
        tips += fmt::format("{:.6g} {:.6g} {} {:.6g}\n", dic.frames[k].tip_x, dic.frames[k].tip_y, k,
                            dic.frames[k].crack_length * 1e3);
    WriteFile(set.dir / "dic_tips.dat", tips + "nan nan nan nan\n");
    double window = dic.fit_radius_px;
    const bool assumed = !std::isfinite(window);
    // bridgefit dic's default: max(60, 5 subsets).
    if (assumed && std::isfinite(dic.subset_px)) window = std::max(60.0, 5.0 * dic.subset_px);
    for (size_t k : FramesToDraw(dic, set.max_flagged_frames, set.notes)) {
      if (dic.frames[k].image_file.empty()) continue;
      try {
        AddOverlay(dic, k, set, window, assumed);
      } catch (const Error& e) {
        set.notes.push_back(fmt::format("DIC frame {} not drawn: {}", k, e.what()));
      }
    }
    AddOpeningFigure(dic, set);
  }
  // The frame table, each drawn frame linked to its figure.
  std::string html = "<table id=\"dic-frames\">\n<tr><th>frame</th><th>image</th><th>a [mm]</th>"
                     "<th>tip x, y [px]</th><th>tip method</th><th>valid points</th><th>flag</th><th>figure</th></tr>\n";
  for (size_t k = 0; k < dic.frames.size(); ++k) {
    const DicFrame& f = dic.frames[k];
    const std::string figure = FrameName(k) + ".png";
    const bool drawn = std::any_of(set.figures.begin(), set.figures.end(),
                                   [&](const Figure& fig) { return fig.file == figure; });
    html += fmt::format(
        "<tr{}><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
        f.flag.empty() ? "" : " class=\"flagged\"", k, Escape(fs::path(f.image).filename().string()),
        Num(f.crack_length, 1e3),
        std::isfinite(f.tip_x) ? fmt::format("{:.1f}, {:.1f}", f.tip_x, f.tip_y) : "&ndash;",
        Escape(f.tip_method.empty() ? "" : f.tip_method),
        std::isfinite(f.valid_fraction) ? fmt::format("{:.0f}%", 100 * f.valid_fraction) : "&ndash;",
        f.flag.empty() ? (k == 0 ? "reference" : "") : Escape(f.flag),
        drawn ? fmt::format("<a href=\"#{}\">{}</a>", FrameName(k), figure) : "&ndash;");
  }
  set.dic_table_html = html + "</table>\n";
}

}  // namespace bridgefit::report::detail
