// Figures of the test record: load against displacement (with the fitted
// load after a load-displacement fit), crack length against record row (and
// DIC's), and an optional reference toughness column against R.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "report_impl.hpp"

namespace bridgefit::report::detail {
namespace {

std::string OutlierRows(const std::vector<double>& x, const std::vector<double>& y) {
  std::string out = "# displacement[mm] load[N]\n";
  for (size_t i = 0; i < x.size() && i < y.size(); ++i) out += fmt::format("{:.8g} {:.8g}\n", x[i] * 1e3, y[i]);
  return out + "nan nan\n";
}

void AddLoadFigure(const ReportInput& in, FigureSet& set) {
  const ExperimentRecord& rec = *in.record;
  const FitView& f = in.fit;
  std::string dat = "# frame displacement[mm] load[N] crack_length[mm]\n";
  for (size_t i = 0; i < rec.load.size(); ++i)
    dat += fmt::format("{} {:.8g} {:.8g} {:.8g}\n", i, rec.displacement[i] * 1e3, rec.load[i],
                       i < rec.crack_length.size() ? rec.crack_length[i] * 1e3 : NAN);
  WriteFile(set.dir / "record.dat", dat);
  std::string& gp = set.gp;
  gp += kTerminal;
  gp += "set output 'load_displacement.png'\nset title 'Load against load-point displacement'\n";
  gp += "set xlabel 'displacement [mm]'\nset ylabel 'load P [N]'\n";
  if (!f.fit_P.empty()) {
    // A load-displacement fit: the model's load over the record, residuals below.
    std::string fit = "# displacement[mm] load_model[N] residual[N]\n";
    for (size_t i = 0; i < f.fit_d.size(); ++i)
      fit += fmt::format("{:.8g} {:.8g} {:.8g}\n", f.fit_d[i] * 1e3, f.fit_P[i], f.data_P[i] - f.fit_P[i]);
    WriteFile(set.dir / "load_fit.dat", fit);
    WriteFile(set.dir / "load_outliers.dat", OutlierRows(f.out_d, f.out_P));
    gp += "set multiplot\n";
    gp += kUpperPanel;
    gp += "set key top right\n";
    gp += "plot 'record.dat' u 2:3 w p pt 7 ps 0.4 lc rgb '#1f77b4' t 'record', "
          "'load_outliers.dat' u 1:2 w p pt 2 ps 1.2 lc rgb '#d62728' t 'outliers (removed)', "
          "'load_fit.dat' u 1:2 w l lw 2 lc rgb '#ff7f0e' t 'fitted model'\n";
    gp += kLowerPanel;
    gp += "set xlabel 'displacement [mm]'\nset ylabel 'residual [N]'\n";
    gp += "plot 'load_fit.dat' u 1:3 w p pt 7 ps 0.4 lc rgb '#1f77b4', 0 w l lc rgb 'black'\n";
    gp += "unset multiplot\n";
  } else {
    gp += "unset key\nplot 'record.dat' u 2:3 w lp pt 7 ps 0.4 lc rgb '#1f77b4'\n";
  }
  set.Add("load_displacement.png", "record",
          f.fit_P.empty() ? "Load against load-point displacement (the record)."
                          : "Load against load-point displacement: the record, the model fitted to it, "
                            "residuals (record &minus; model) below.");
}

void AddCrackLengthFigure(const ReportInput& in, FigureSet& set) {
  const ExperimentRecord& rec = *in.record;
  std::string dic_plot;
  bool dic_on_rows = false;  // DIC frames drawn at their record rows (image column)
  if (in.dic && !in.dic->frames.empty()) {
    const std::vector<DicFrame>& frames = in.dic->frames;
    // A record whose image column names the frames: each frame at its row.
    std::vector<double> row(frames.size(), NAN);
    if (!rec.images.empty())
      for (size_t k = 0; k < frames.size(); ++k)
        for (size_t r = 0; r < rec.images.size(); ++r)
          if (!rec.images[r].empty() && !frames[k].image.empty() &&
              fs::path(rec.images[r]).filename() == fs::path(frames[k].image).filename()) {
            row[k] = static_cast<double>(r);
            dic_on_rows = true;
            break;
          }
    std::string d = dic_on_rows ? "# record_row crack_length[mm] frame\n" : "# frame crack_length[mm] frame\n";
    for (size_t k = 0; k < frames.size(); ++k)
      d += fmt::format("{} {:.8g} {}\n", dic_on_rows ? row[k] : static_cast<double>(k),
                       frames[k].crack_length * 1e3, k);
    WriteFile(set.dir / "dic.dat", d);
    dic_plot = dic_on_rows
                   ? ", 'dic.dat' u 1:2 w p pt 6 ps 1.5 lw 2 lc rgb '#2ca02c' t 'DIC (at the rows of its images)'"
                     ", '' u 1:2:(sprintf('%d', $3)) w labels offset 0,1 font ',8' tc rgb '#2ca02c' notitle"
                   : ", 'dic.dat' u 1:2 axes x2y1 w lp pt 6 ps 1 lw 2 lc rgb '#2ca02c' t 'DIC (image index, top axis)'";
  }
  if (rec.crack_length.empty() && dic_plot.empty()) return;
  std::string& gp = set.gp;
  gp += kTerminal;
  gp += "set output 'crack_length.png'\nset title 'Crack length against frame'\n";
  gp += "set xlabel 'record row'\nset ylabel 'crack length a [mm]'\n";
  if (!dic_plot.empty() && !dic_on_rows) gp += "set xtics nomirror\nset x2tics\nset x2label 'image index (DIC)'\n";
  gp += "plot ";
  gp += rec.crack_length.empty()
            ? "1/0 notitle"
            : std::string("'record.dat' u 1:4 w p pt 7 ps 0.4 lc rgb '#1f77b4' t '") +
                  (in.record_from_images ? "record (from the images, linear between frames)" : "record") + "'";
  gp += dic_plot + "\n";
  set.Add("crack_length.png", "record",
          "Crack length against frame: the record and, when given, DIC on the images (frame numbers "
          "as in the DIC frame table).");
}

// Mean of the reference rows between the midpoints to the neighbouring R
// points (the record is much denser than the R curve), NaN when none.
std::vector<double> ReferenceAtPoints(const ReferenceView& ref, const std::vector<double>& a) {
  std::vector<double> out(a.size(), NAN);
  for (size_t i = 0; i < a.size(); ++i) {
    const double lo = i > 0 ? 0.5 * (a[i - 1] + a[i]) : a[i] - (a.size() > 1 ? 0.5 * (a[1] - a[0]) : 0.0);
    const double hi = i + 1 < a.size() ? 0.5 * (a[i] + a[i + 1]) : a[i] + (i > 0 ? 0.5 * (a[i] - a[i - 1]) : 0.0);
    double sum = 0.0;
    int count = 0;
    for (size_t j = 0; j < ref.value.size(); ++j)
      if (ref.crack_length[j] >= lo && ref.crack_length[j] <= hi) sum += ref.value[j], ++count;
    if (count > 0) out[i] = sum / count;
  }
  return out;
}

}  // namespace

void AddRecordFigures(const ReportInput& in, FigureSet& set) {
  if (!in.record) {
    set.notes.push_back("no record given: no load-displacement or crack-length figure");
    return;
  }
  AddLoadFigure(in, set);
  AddCrackLengthFigure(in, set);
}

// The reference column against R: upper panel both against crack length,
// lower panel reference - R at the R curve's points; the deviation table.
void AddReferenceFigure(const ReportInput& in, FigureSet& set) {
  if (!in.reference) return;
  const ReferenceView& ref = *in.reference;
  const FitView& f = in.fit;
  const std::vector<double> at = ReferenceAtPoints(ref, f.a);
  std::string rows = fmt::format("# {} rows of {}: crack_length[mm] {}[J/m^2]\n", ref.value.size(),
                                 ref.file.filename().string(), ref.column);
  for (size_t j = 0; j < ref.value.size(); ++j)
    rows += fmt::format("{:.8g} {:.8g}\n", ref.crack_length[j] * 1e3, ref.value[j]);
  WriteFile(set.dir / "reference.dat", rows);
  std::string cmp = fmt::format("# crack_length[mm] R[J/m^2] {}_mean[J/m^2] deviation {}-R [J/m^2] model_R[J/m^2]\n",
                                ref.column, ref.column);
  double sum = 0.0, sum_sq = 0.0, sum_rel = 0.0, sum_model = 0.0;
  int count = 0, model_count = 0;
  for (size_t i = 0; i < f.a.size(); ++i) {
    const double model = i < f.fit_R.size() && i < f.fit_a.size() && std::abs(f.fit_a[i] - f.a[i]) < 1e-12
                             ? f.fit_R[i] : NAN;
    cmp += fmt::format("{:.8g} {:.8g} {:.8g} {:.8g} {:.8g}\n", f.a[i] * 1e3, f.R[i], at[i], at[i] - f.R[i], model);
    if (!std::isfinite(at[i])) continue;
    const double dev = at[i] - f.R[i];
    sum += dev, sum_sq += dev * dev, sum_rel += dev / f.R[i], ++count;
    if (std::isfinite(model)) sum_model += at[i] - model, ++model_count;
  }
  WriteFile(set.dir / "reference_vs_R.dat", cmp);
  const std::string label = GnuplotText(ref.column);
  std::string& gp = set.gp;
  gp += kTerminal;
  gp += "set output 'reference.png'\nset multiplot\nset title '" + label + " of the record against the R curve'\n";
  gp += kUpperPanel;
  gp += "set key bottom right\nset ylabel 'R, " + label + " [J/m^2]'\n";
  gp += "plot 'reference.dat' u 1:2 w p pt 7 ps 0.3 lc rgb '#bbbbbb' t '" + label +
        " (record rows)', 'reference_vs_R.dat' u 1:3 w p pt 5 ps 0.7 lc rgb '#9467bd' t '" + label +
        ", mean near each R point', '' u 1:2 w p pt 7 ps 0.6 lc rgb '#1f77b4' t 'R (data)', '' u 1:5 w l lw 2 "
        "lc rgb '#ff7f0e' t 'fitted model R'\n";
  gp += kLowerPanel;
  gp += "set xlabel 'crack length a [mm]'\nset ylabel '" + label + " - R [J/m^2]'\n";
  gp += "plot 'reference_vs_R.dat' u 1:4 w p pt 5 ps 0.6 lc rgb '#9467bd', 0 w l lc rgb 'black'\n";
  gp += "unset multiplot\n";
  const std::string unit = ref.unit_text.empty() ? "as in the header" : Escape(ref.unit_text);
  std::string html = "<table id=\"reference\">\n";
  html += fmt::format("<tr><th>reference column</th><td>{} ({}, converted to J/m<sup>2</sup>) from {}</td></tr>\n",
                      Escape(ref.column), unit, Escape(ref.file.filename().string()));
  html += fmt::format("<tr><th>R points compared</th><td>{} of {} (record rows: {})</td></tr>\n", count, f.a.size(),
                      ref.value.size());
  if (count > 0) {
    html += fmt::format("<tr><th>mean {0} &minus; R (data)</th><td>{1:.4g} J/m<sup>2</sup> ({2:+.1f}% of R)</td></tr>\n",
                        Escape(ref.column), sum / count, 100 * sum_rel / count);
    html += fmt::format("<tr><th>rms {} &minus; R (data)</th><td>{:.4g} J/m<sup>2</sup></td></tr>\n",
                        Escape(ref.column), std::sqrt(sum_sq / count));
    if (model_count > 0)
      html += fmt::format("<tr><th>mean {} &minus; R (fitted model)</th><td>{:.4g} J/m<sup>2</sup></td></tr>\n",
                          Escape(ref.column), sum_model / model_count);
  }
  set.reference_html = html + "</table>\n";
  set.Add("reference.png", "record",
          "The record's own toughness column " + Escape(ref.column) + " (" + unit +
              ") against the R curve of this report: record rows (grey), their mean near each R point "
              "(purple), R and the fitted model's R; the deviation below and in the table.");
}

}  // namespace bridgefit::report::detail
