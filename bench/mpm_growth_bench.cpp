// MPM crack growth with bridging (issue 5 bench): R(Delta a) of the CT scene
// (W = 100 mm, a0 = 30 mm, J_tip,c = 2210 J/m^2, linear softening, J_B = 500
// J/m^2) for sigma_c = 0.45 and 1.0 MPa at 5, 2.5 and 1.25 mm cells, half and
// full model, against the reduced model at its converged resolution (0.25 mm).
// Writes PREFIX.csv, PREFIX_curves.csv, PREFIX.gp and PREFIX.png (time
// against error, via gnuplot).
//   bf_mpm_growth_bench [PREFIX] [--quick]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bridgefit/core/progress.hpp"
#include "bridgefit/laws/law.hpp"
#include "bridgefit/models/reduced.hpp"
#include "bridgefit/mpm/growth.hpp"
#include "bridgefit/scene/reference.hpp"

using namespace bridgefit;

namespace {

Scene CtScene(double sigma_c) {
  Scene s = ReferenceCtScene();
  AddLinearBridging(s, sigma_c, 500.0);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::string prefix = "mpm_growth_bench";
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--quick") quick = true;
    else prefix = arg;
  }
  const std::vector<double> sigmas = {0.45e6, 1.0e6};
  const std::vector<double> cells =
      quick ? std::vector<double>{0.005} : std::vector<double>{0.005, 0.0025, 0.00125};
  const double a_max = 0.080;  // compare up to here (the edge limit of the coarse cells)
  std::ofstream csv(prefix + ".csv");
  csv << "sigma_c [MPa], model, cell [mm], particles, equations, points, wall [s], "
         "max |R error| [%], max |R_energy error| [%], steady state onset [mm], "
         "reference onset [mm]\n";
  std::ofstream curves(prefix + "_curves.csv");
  curves << "sigma_c [MPa], model, cell [mm], crack_length [mm], R [J/m^2], "
            "R_energy [J/m^2], R_reference [J/m^2], R_energy_reference [J/m^2]\n";
  std::map<std::string, std::string> plot;
  std::printf("%-8s %-5s %6s %9s %9s %7s %8s %8s %10s %8s %8s\n", "sigma_c", "model", "cell",
              "particles", "equations", "points", "wall_s", "R_err%", "Ren_err%", "onset_mm",
              "ref_mm");
  for (double sigma_c : sigmas) {
    const Scene scene = CtScene(sigma_c);
    const laws::BridgingLaw law = scene.bridging->Law();
    models::ReducedOptions ropt;
    ropt.mesh.resolution = quick ? 0.0005 : 0.00025;
    const SimulationResult ref = models::SimulateReduced(scene, ropt);
    for (const char* model : {"half", "full"}) {
      for (double cell : cells) {
        mpm::GrowthOptions opt;
        opt.cell = cell;
        opt.symmetry = std::string(model) == "half" ? mpm::GrowthSymmetry::kHalf
                                                    : mpm::GrowthSymmetry::kFull;
        opt.threads = 1;
        const mpm::GrowthResult g = mpm::SimulateGrowth(scene, &law, 2210.0, opt);
        double err_r = 0.0, err_e = 0.0;
        for (const SimulationPoint& p : g.result.points) {
          if (p.crack_length > a_max + 1e-9) continue;
          const double r = InterpolatePoints(ref.points, p.crack_length, &SimulationPoint::R);
          const double re = InterpolatePoints(ref.points, p.crack_length, &SimulationPoint::R_energy);
          if (!std::isfinite(r)) continue;
          err_r = std::max(err_r, std::abs(p.R / r - 1.0));
          err_e = std::max(err_e, std::abs(p.R_energy / re - 1.0));
          curves << fmt::format("{:g}, {}, {:g}, {:.4f}, {:.2f}, {:.2f}, {:.2f}, {:.2f}\n",
                                sigma_c * 1e-6, model, cell * 1e3, p.crack_length * 1e3, p.R,
                                p.R_energy, r, re);
        }
        const double onset = g.result.steady_state_reached
                                 ? g.result.steady_state_crack_length * 1e3 : NAN;
        const double ref_onset =
            ref.steady_state_reached ? ref.steady_state_crack_length * 1e3 : NAN;
        std::printf("%-8.2f %-5s %6.2f %9zu %9zu %7zu %8.3f %8.2f %10.2f %8.2f %8.2f\n",
                    sigma_c * 1e-6, model, cell * 1e3, g.particles, g.dofs,
                    g.result.points.size(), g.result.wall_s, 100 * err_r, 100 * err_e, onset,
                    ref_onset);
        std::fflush(stdout);
        csv << fmt::format("{:g}, {}, {:g}, {}, {}, {}, {:.4f}, {:.3f}, {:.3f}, {:.2f}, {:.2f}\n",
                           sigma_c * 1e-6, model, cell * 1e3, g.particles, g.dofs,
                           g.result.points.size(), g.result.wall_s, 100 * err_r, 100 * err_e,
                           onset, ref_onset);
        plot[fmt::format("{} {:g} MPa", model, sigma_c * 1e-6)] +=
            fmt::format("{:.5f} {:.4f} {:g}\n", g.result.wall_s, std::max(100 * err_e, 1e-3),
                        cell * 1e3);
      }
    }
  }
  csv.close();
  curves.close();
  std::ofstream dat(prefix + "_plot.dat");
  std::string titles;
  for (const auto& [name, rows] : plot) {
    dat << "# " << name << "\n" << rows << "\n\n";
    titles += (titles.empty() ? "" : "|") + name;
  }
  dat.close();
  std::ofstream gp(prefix + ".gp");
  gp << "set terminal pngcairo size 900,600\nset output '" << prefix << ".png'\n"
     << "set logscale xy\nset xlabel 'wall time per R curve [s] (one thread)'\n"
     << "set ylabel 'largest |R_{energy} error| vs reduced model (0.25 mm) [%]'\n"
     << "set key outside right\nset grid\n"
     << "set title 'MPM crack growth, CT, linear softening: 5 / 2.5 / 1.25 mm cells'\n"
     << "titles = '" << titles << "'\n"
     << "plot for [i=0:" << plot.size() - 1 << "] '" << prefix << "_plot.dat' index i using "
     << "1:2 with linespoints pointsize 1.5 title system(sprintf(\"echo '%s' | cut -d'|' -f%d\", "
        "titles, i+1)), '' using 1:2:3 with labels offset 1,0.7 notitle\n";
  gp.close();
  if (std::system(("gnuplot '" + prefix + ".gp' 2>/dev/null").c_str()) != 0)
    std::fprintf(stderr, "gnuplot failed; the CSV is written\n");
  return 0;
}
