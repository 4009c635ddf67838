// Speed against accuracy of the reduced model (issue 3).
//   bf_models_bench [out_prefix] [resolutions_mm = 4,2,1,0.5,0.25,0.125]
//       -> <prefix>.csv and <prefix>.svg; each resolution half the previous
//       (the reference is the Richardson extrapolation of the last three)
// CT of the issues (W = 100 mm, a0 = 30 mm, B = 12.7 mm, E = 3 GPa, plane
// stress), linear softening sigma_c = 0.45 MPa, J_B = 500 J/m^2, crack grown
// to 80 mm. For each resolution h: time to build the crack-plane model (once
// per geometry), median time per R curve on one core (default hybrid solver,
// and the dense and bordered solvers for comparison), and the error of R at
// the probe crack lengths against the Richardson extrapolation of the three finest
// resolutions (with the observed order). Probes at a = 46, 54, 62, 70 mm.

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bridgefit/scene/reference.hpp"
#include "bridgefit/core/progress.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/models/reduced.hpp"

using namespace bridgefit;

namespace {
const double kProbe[4] = {0.046, 0.054, 0.062, 0.070};  // on every grid

struct Row {
  double h = 0, build_s = 0, curve_s = 0, curve_min_s = 0, dense_s = 0, bordered_s = 0;
  int points = 0, dofs = 0;
  double R[4] = {0, 0, 0, 0};
  double err_R = 0, err_bridging = 0;
};

std::string Svg(const std::vector<Row>& rows) {
  // log-log: x = time per R curve [ms], y = largest error of R - J_tip,c [%].
  const double W = 640, H = 420, L = 70, B = 50, T = 20, Rm = 20;
  double x0 = 1e9, x1 = 0, y0 = 1e9, y1 = 0;
  for (const Row& r : rows) {
    if (r.err_bridging <= 0) continue;
    x0 = std::min(x0, r.curve_s * 1e3), x1 = std::max(x1, r.curve_s * 1e3);
    y0 = std::min(y0, r.err_bridging * 100), y1 = std::max(y1, r.err_bridging * 100);
  }
  const double lx0 = std::floor(std::log10(x0)), lx1 = std::ceil(std::log10(x1));
  const double ly0 = std::floor(std::log10(y0)), ly1 = std::ceil(std::log10(y1));
  auto X = [&](double v) { return L + (std::log10(v) - lx0) / (lx1 - lx0) * (W - L - Rm); };
  auto Y = [&](double v) { return H - B - (std::log10(v) - ly0) / (ly1 - ly0) * (H - B - T); };
  std::string s = "<svg xmlns='http://www.w3.org/2000/svg' width='640' height='420' "
                  "font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' "
                  "fill='white'/>\n";
  char buf[512];
  for (double e = lx0; e <= lx1; ++e) {
    std::snprintf(buf, sizeof buf,
                  "<line x1='%.1f' y1='%.1f' x2='%.1f' y2='%.1f' stroke='#ddd'/><text x='%.1f' "
                  "y='%.1f' text-anchor='middle'>%g</text>\n",
                  X(std::pow(10, e)), T, X(std::pow(10, e)), H - B, X(std::pow(10, e)), H - B + 16,
                  std::pow(10, e));
    s += buf;
  }
  for (double e = ly0; e <= ly1; ++e) {
    std::snprintf(buf, sizeof buf,
                  "<line x1='%.1f' y1='%.1f' x2='%.1f' y2='%.1f' stroke='#ddd'/><text x='%.1f' "
                  "y='%.1f' text-anchor='end'>%g</text>\n",
                  L, Y(std::pow(10, e)), W - Rm, Y(std::pow(10, e)), L - 6, Y(std::pow(10, e)) + 4,
                  std::pow(10, e));
    s += buf;
  }
  std::snprintf(buf, sizeof buf,
                "<text x='%.1f' y='%.1f' text-anchor='middle'>time per R curve, one core [ms]"
                "</text>\n<text transform='translate(16,%.1f) rotate(-90)' text-anchor='middle'>"
                "largest error of R - J_tip,c [%%]</text>\n",
                0.5 * (L + W - Rm), H - 12, 0.5 * (T + H - B));
  s += buf;
  std::string path;
  for (const Row& r : rows) {
    if (r.err_bridging <= 0) continue;
    const double x = X(r.curve_s * 1e3), y = Y(r.err_bridging * 100);
    path += (path.empty() ? "M" : " L") + std::to_string(x) + " " + std::to_string(y);
    std::snprintf(buf, sizeof buf,
                  "<circle cx='%.1f' cy='%.1f' r='4' fill='#1f77b4'/><text x='%.1f' y='%.1f'>"
                  "h = %g mm (%d pts)</text>\n",
                  x, y, x + 7, y - 7, r.h * 1e3, r.points);
    s += buf;
  }
  s += "<path d='" + path + "' fill='none' stroke='#1f77b4'/>\n</svg>\n";
  return s;
}
}  // namespace

int main(int argc, char** argv) {
  const std::string prefix = argc > 1 ? argv[1] : "reduced_bench";
  std::vector<double> resolutions = {0.004, 0.002, 0.001, 0.0005, 0.00025, 0.000125};
  if (argc > 2) {
    resolutions.clear();
    std::stringstream list(argv[2]);
    for (std::string item; std::getline(list, item, ',');)
      resolutions.push_back(std::atof(item.c_str()) * 1e-3);
    if (resolutions.size() < 3) {
      std::fprintf(stderr, "bf_models_bench: at least three resolutions are needed\n");
      return 2;
    }
  }
  Scene scene = ReferenceCtScene();
  const double J_tip_c = 2210.0;
  const laws::LawShape shape = laws::MakeLinearShape();
  const laws::BridgingLaw law{&shape, 0.45e6, 2.0 * 500.0 / 0.45e6};

  std::vector<Row> rows;
  for (double h : resolutions) {
    Row row;
    row.h = h;
    specimen::CrackPlaneOptions mesh;
    mesh.resolution = h;
    mesh.max_crack_length = 0.08;
    omp_set_num_threads(1);  // one core for the build too
    Stopwatch build;
    const models::ReducedModel model(scene, mesh);
    row.build_s = build.Seconds();
    row.dofs = model.crack_plane().dofs;
    SimulationResult result;
    auto time_runs = [&](const models::ReducedOptions& options, std::vector<double>& times) {
      Stopwatch total;
      while (times.size() < 3 || (total.Seconds() < 1.0 && times.size() < 200)) {
        Stopwatch one;
        result = model.Run(&law, J_tip_c, options);
        times.push_back(one.Seconds());
      }
      std::sort(times.begin(), times.end());
    };
    std::vector<double> dense_times, times;
    models::ReducedOptions dense;
    dense.solver = models::ReducedOptions::Solver::kDense;
    time_runs(dense, dense_times);
    row.dense_s = dense_times[dense_times.size() / 2];
    std::vector<double> bordered_times;
    models::ReducedOptions bordered;
    bordered.solver = models::ReducedOptions::Solver::kBordered;
    time_runs(bordered, bordered_times);
    row.bordered_s = bordered_times[bordered_times.size() / 2];
    time_runs({}, times);  // the default (hybrid) solver last: `result` is its
    row.curve_s = times[times.size() / 2];
    row.curve_min_s = times.front();
    row.points = static_cast<int>(result.points.size());
    for (int i = 0; i < 4; ++i)
      for (const SimulationPoint& p : result.points)
        if (std::abs(p.crack_length - kProbe[i]) < 1e-9) row.R[i] = p.R;
    rows.push_back(row);
    std::fprintf(stderr, "h = %g mm: build %.3f s, R curve %.3f ms (%d points)\n", h * 1e3,
                 row.build_s, row.curve_s * 1e3, row.points);
  }
  // Reference: Richardson extrapolation from the three finest resolutions.
  const size_t n = rows.size();
  double reference[4];
  double order_sum = 0;
  for (int i = 0; i < 4; ++i) {
    const double d1 = rows[n - 2].R[i] - rows[n - 3].R[i];
    const double d2 = rows[n - 1].R[i] - rows[n - 2].R[i];
    const double order = std::log2(std::abs(d1 / d2));
    order_sum += order;
    reference[i] = rows[n - 1].R[i] + d2 / (std::pow(2.0, order) - 1.0);
  }
  std::ofstream csv(prefix + ".csv");
  csv << "# bf_models_bench: CT W=100 mm a0=30 mm, linear sigma_c=0.45 MPa J_B=500 J/m^2, "
         "a to 80 mm; observed order "
      << order_sum / 4 << "\n";
  csv << "resolution [mm], dofs, build [s], R curve median [ms], R curve min [ms], crack lengths, "
         "median per 100 lengths [ms], max error R [%], max error R-J_tip_c [%], "
         "dense solver median [ms], bordered solver median [ms]\n";
  for (Row& r : rows) {
    for (int i = 0; i < 4; ++i) {
      r.err_R = std::max(r.err_R, std::abs(r.R[i] - reference[i]) / reference[i]);
      r.err_bridging =
          std::max(r.err_bridging, std::abs(r.R[i] - reference[i]) / (reference[i] - J_tip_c));
    }
    char line[256];
    std::snprintf(line, sizeof line, "%g, %d, %.4f, %.4f, %.4f, %d, %.4f, %.4f, %.4f, %.4f, %.4f\n",
                  r.h * 1e3, r.dofs, r.build_s, r.curve_s * 1e3, r.curve_min_s * 1e3, r.points,
                  r.curve_s * 1e3 * 100.0 / r.points, 100 * r.err_R, 100 * r.err_bridging,
                  r.dense_s * 1e3, r.bordered_s * 1e3);
    csv << line;
    std::printf("%s", line);
  }
  std::printf("observed order of R: %.2f\n", order_sum / 4);
  std::ofstream(prefix + ".svg") << Svg(rows);
  return 0;
}
