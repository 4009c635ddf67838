// MPM speed against accuracy on the CT scene of the issues (W = 100 mm,
// a0 = 30 mm, B = 12.7 mm, E = 3 GPa, plane stress): particle-steps per
// second on 1 and 2 threads at 5, 2.5 and 1.25 mm cells, with the error of
// the contour J against K^2/E' from ASTM E399 and of the load-line
// compliance against Saxena-Hudak, plus where the time goes.
//   bf_mpm_bench [--cells 5,2.5,1.25] [--threads 1,2] [--csv out.csv]
#include <cmath>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "bridgefit/scene/reference.hpp"
#include "bridgefit/mpm/solver.hpp"

namespace {

std::vector<double> ParseList(const char* text) {
  std::vector<double> v;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) v.push_back(std::atof(item.c_str()));
  return v;
}

double E399Factor(double u) {
  return (2.0 + u) / std::pow(1.0 - u, 1.5) *
         (0.886 + 4.64 * u - 13.32 * u * u + 14.72 * u * u * u - 5.6 * u * u * u * u);
}
double SaxenaHudak(double u) {
  const double r = (1.0 + u) / (1.0 - u);
  return r * r *
         (2.1630 + 12.219 * u - 20.065 * u * u - 0.9925 * std::pow(u, 3) + 20.609 * std::pow(u, 4) -
          9.9314 * std::pow(u, 5));
}

}  // namespace

int main(int argc, char** argv) {
  using namespace bridgefit;
  std::vector<double> cells = {5.0, 2.5, 1.25};
  std::vector<double> threads = {1, 2};
  std::string csv;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    if (key == "--cells") cells = ParseList(argv[i + 1]);
    else if (key == "--threads") threads = ParseList(argv[i + 1]);
    else if (key == "--csv") csv = argv[i + 1];
  }
  Scene scene = ReferenceCtScene();
  const double W = 0.1, a = 0.03, B = 0.0127, E = 3e9, u = a / W;
  std::string table =
      "cell_mm,threads,particles,steps,wall_s,cpu_s,Mparticle_steps_per_s,M_per_cpu_s,J_small,J_large,"
      "J_err_pct,C_err_pct,p2g_s,grid_s,g2p_s,stress_s,crack_s,other_s\n";
  std::printf("%s", table.c_str());
  for (double cell_mm : cells) {
    for (double t : threads) {
      const double h = cell_mm * 1e-3;
      mpm::Model model = mpm::BuildSpecimenModel(scene, h, 2);
      mpm::SolverOptions opt;
      opt.threads = static_cast<int>(t);
      opt.target_displacement = 0.5e-3;
      // Contours of about 7.5 and 12.5 mm half size (at least 2 cells).
      const int small = std::max(2, static_cast<int>(std::lround(7.5e-3 / h)));
      const int large = std::max(small + 1, static_cast<int>(std::lround(12.5e-3 / h)));
      opt.contour_cells = {small, large};
      opt.history_every = 200;
      mpm::Solver solver(model, opt);
      const std::clock_t cpu0 = std::clock();
      const mpm::Summary s = solver.Run();
      // CPU seconds of the process (all threads): on a shared machine the
      // wall clock includes time other processes held the cores.
      const double cpu_s = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
      const double per_cpu = static_cast<double>(s.particles) * s.steps / cpu_s;
      const double P = s.final_load;
      const double K = P / (B * std::sqrt(W)) * E399Factor(u);
      const double J_ref = K * K / E;
      const double C_ref = SaxenaHudak(u) / (E * B);
      const double J = s.final_J[0].J;
      double other = 0.0;
      for (std::size_t k = 5; k < s.stage_seconds.size(); ++k) other += s.stage_seconds[k].second;
      char line[512];
      std::snprintf(line, sizeof line,
                    "%g,%d,%zu,%ld,%.3f,%.3f,%.3f,%.3f,%.2f,%.2f,%.2f,%.2f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f\n",
                    cell_mm, s.threads, s.particles, s.steps, s.wall_s, cpu_s,
                    s.particle_steps_per_s * 1e-6, per_cpu * 1e-6, J, s.final_J[1].J, 100.0 * (J / J_ref - 1.0),
                    100.0 * (s.final_load_line_cod / P / C_ref - 1.0), s.stage_seconds[0].second,
                    s.stage_seconds[1].second, s.stage_seconds[2].second,
                    s.stage_seconds[3].second, s.stage_seconds[4].second, other);
      std::printf("%s", line);
      std::fflush(stdout);
      table += line;
      if (s.status != RunStatus::kOk) std::fprintf(stderr, "%s\n", s.BriefReport().c_str());
    }
  }
  if (!csv.empty()) {
    FILE* f = std::fopen(csv.c_str(), "w");
    if (f) {
      std::fputs(table.c_str(), f);
      std::fclose(f);
    }
  }
  return 0;
}
