// DIC speed against accuracy on DIC Challenge Sample 14 L1: IC-GN points per
// second at 21x21 and 33x33 subsets on 1 and 2 threads, with RMS(u - exact)
// of each run. Two image sources:
//   crop (default): tests/data/dic/sample14 (rows 230..349 of the full image)
//   full: --full DIR with DIR/Sample14/"Sample14 Reference.tif",
//         DIR/Sample14/"Sample 14 L1 Amp0.1.tif" and
//         DIR/Images_Sample14_Exact/Sample14Exact.csv
// Grid: x = 20..2026, y = 250..330 of the full image, step 2 (41,164 points);
// first order unless --second. Convergence as OpenCorr's IC-GN (|dp| < 0.001
// px, at most 10 iterations; --max-iter 40 gives the product's default).
//   bench/dic_speed [--full DIR | --crop DIR] [--step 2] [--subsets 21,33]
//                   [--threads 1,2] [--reps 5] [--second] [--max-iter 10]
//   bench/dic_speed CROP_DIR STEP SUBSETS THREADS   (older form, both shapes)
// Per run: wall time, CPU time of the process (all threads) and the per
// thread rate (points = grid points); the row is the run with the least CPU
// time (the figure least disturbed by other processes on a shared machine),
// best_wall the best wall-clock rate of the runs.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bridgefit/dic/correlation.hpp"

using namespace bridgefit::dic;

namespace {
std::vector<int> ParseInts(const char* text) {
  std::vector<int> values;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) values.push_back(std::atoi(item.c_str()));
  return values;
}

double Now(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

std::vector<double> ReadExactU(const std::string& path) {
  std::vector<double> exact(2048, 0.0);
  std::ifstream in(path);
  if (!in) {
    std::fprintf(stderr, "cannot read %s\n", path.c_str());
    std::exit(1);
  }
  std::string line;
  std::getline(in, line);
  for (int i = 0; i < 2048 && std::getline(in, line); ++i) {
    std::stringstream s(line);
    std::string a, b;
    std::getline(s, a, ',');
    std::getline(s, b, ',');
    exact[i] = std::stod(b);
  }
  return exact;
}
}  // namespace

int main(int argc, char** argv) {
  std::string crop_dir = std::string(BRIDGEFIT_SOURCE_DIR) + "/tests/data/dic";
  std::string full_dir;
  int step = 2, reps = 5, max_iter = 10;
  bool with_second = false;
  std::vector<int> subsets{21, 33}, thread_counts{1, 2};
  // The older positional form (bench/run_all.sh): DIR STEP SUBSETS THREADS on
  // the crop, both shapes, best of 3.
  if (argc > 1 && std::strncmp(argv[1], "--", 2) != 0) {
    crop_dir = argv[1];
    if (argc > 2) step = std::atoi(argv[2]);
    if (argc > 3) subsets = ParseInts(argv[3]);
    if (argc > 4) thread_counts = ParseInts(argv[4]);
    with_second = true;
    reps = 3;
    argc = 1;
  }
  for (int a = 1; a < argc; ++a) {
    auto next = [&]() -> const char* {
      if (a + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", argv[a]);
        std::exit(2);
      }
      return argv[++a];
    };
    if (!std::strcmp(argv[a], "--full")) full_dir = next();
    else if (!std::strcmp(argv[a], "--crop")) crop_dir = next();
    else if (!std::strcmp(argv[a], "--step")) step = std::atoi(next());
    else if (!std::strcmp(argv[a], "--reps")) reps = std::atoi(next());
    else if (!std::strcmp(argv[a], "--subsets")) subsets = ParseInts(next());
    else if (!std::strcmp(argv[a], "--threads")) thread_counts = ParseInts(next());
    else if (!std::strcmp(argv[a], "--second")) with_second = true;
    else if (!std::strcmp(argv[a], "--max-iter")) max_iter = std::atoi(next());
    else {
      std::fprintf(stderr, "unknown argument %s\n", argv[a]);
      return 2;
    }
  }
  Image ref, def;
  std::vector<double> exact;
  int row0 = 0;  // row of the image's first line in the full image
  if (!full_dir.empty()) {
    ref = ReadImage(full_dir + "/Sample14/Sample14 Reference.tif");
    def = ReadImage(full_dir + "/Sample14/Sample 14 L1 Amp0.1.tif");
    exact = ReadExactU(full_dir + "/Images_Sample14_Exact/Sample14Exact.csv");
  } else {
    ref = ReadImage(crop_dir + "/sample14/Sample14 Reference rows230-349.png");
    def = ReadImage(crop_dir + "/sample14/Sample 14 L1 Amp0.1 rows230-349.png");
    exact = ReadExactU(crop_dir + "/sample14/Sample14Exact.csv");
    row0 = 230;
  }
  std::printf("# images %dx%d (%s), grid x 20..2026, y 250..330 (full-image rows), step %d\n",
              ref.width, ref.height, full_dir.empty() ? "crop" : "full", step);
  std::printf("%-7s %-7s %-7s %-7s %-9s %-9s %-11s %-11s %-11s %-8s %-6s %-9s\n", "subset",
              "shape", "threads", "points", "wall_s", "cpu_s", "points_per_s", "per_cpu_s",
              "best_wall", "valid", "iters", "rms_u_px");
  std::vector<std::string> profiles;
  auto fmt_profile = [](int subset, int threads, double construct,
                        const CorrelationSummary::StageSeconds& st, const CorrelationSummary& s) {
    char line[512];
    std::snprintf(line, sizeof line,
                  "profile %-7d %-7d %-9.3f %-9.3f %-9.3f %-9.3f %-9.3f %-9.3f %-9.3f %-9.3f %-7zu %.2f",
                  subset, threads, construct, st.setup, st.search, st.reference, st.interpolation,
                  st.residual, st.update, st.propagation, s.solves, s.mean_iterations);
    return std::string(line);
  };
  std::vector<ShapeFunction> shapes{ShapeFunction::kFirstOrder};
  if (with_second) shapes.push_back(ShapeFunction::kSecondOrder);
  for (int subset : subsets) {
    for (ShapeFunction shape : shapes) {
      for (int threads : thread_counts) {
        CorrelationOptions opt;
        opt.subset_size = subset;
        opt.step = step;
        opt.shape = shape;
        opt.threads = threads;
        opt.max_iterations = max_iter;  // OpenCorr: at most 10 iterations, |dp| < 0.001
        opt.convergence_px = 1e-3;
        opt.roi_x0 = 20;
        opt.roi_x1 = 2027;
        opt.roi_y0 = 250 - row0;
        opt.roi_y1 = 331 - row0;
        double best_cpu = 1e300, best_cpu_wall = 0, best_wall = 1e300;
        DisplacementField f;
        CorrelationSummary s;
        for (int rep = 0; rep < reps; ++rep) {
          const double w0 = Now(CLOCK_MONOTONIC), c0 = Now(CLOCK_PROCESS_CPUTIME_ID);
          f = CorrelatePair(ref, def, opt, &s);
          const double wall = Now(CLOCK_MONOTONIC) - w0;
          const double cpu = Now(CLOCK_PROCESS_CPUTIME_ID) - c0;
          if (cpu < best_cpu) {
            best_cpu = cpu;
            best_cpu_wall = wall;
          }
          best_wall = std::min(best_wall, wall);
        }
        double sum2 = 0;
        size_t n = 0, valid = 0;
        for (size_t i = 0; i < f.size(); ++i) {
          if (!f.ok(i)) continue;
          ++valid;
          const double e = f.u[i] - exact[static_cast<size_t>(f.x[i])];
          sum2 += e * e;
          ++n;
        }
        // One more run with the stage clocks on (not part of the timing).
        CorrelationOptions popt = opt;
        popt.profile_stages = true;
        CorrelationSummary ps;
        const double pw0 = Now(CLOCK_MONOTONIC);
        CorrelatePair(ref, def, popt, &ps);
        const double construct = Now(CLOCK_MONOTONIC) - pw0 - ps.wall_s;
        const CorrelationSummary::StageSeconds& st = ps.stages;
        profiles.push_back(fmt_profile(subset, threads, construct, st, ps));
        const double points = static_cast<double>(f.size());
        std::printf("%-7d %-7s %-7d %-7zu %-9.3f %-9.3f %-11.0f %-11.0f %-11.0f %-8zu %-6.2f %-9.4f\n",
                    subset, shape == ShapeFunction::kFirstOrder ? "first" : "second", threads,
                    f.size(), best_cpu_wall, best_cpu, points / best_cpu_wall, points / best_cpu,
                    points / best_wall, valid, s.mean_iterations,
                    std::sqrt(sum2 / std::max<size_t>(n, 1)));
        std::fflush(stdout);
      }
    }
  }
  // Stage profile (seconds summed over threads, one profiled run each):
  // construct = reference interpolant and grid (Correlator), setup = frame
  // interpolant, propagation = the rest of the pass.
  std::printf("\n# stage profile (s)\nprofile %-7s %-7s %-9s %-9s %-9s %-9s %-9s %-9s %-9s %-9s %-7s %s\n",
              "subset", "threads", "construct", "setup", "search", "reference", "interp",
              "residual", "update", "propag", "solves", "iters");
  for (const std::string& line : profiles) std::printf("%s\n", line.c_str());
  return 0;
}
