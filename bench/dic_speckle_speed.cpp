// Speed of the speckle generator (SpeckleRenderer): seconds per frame for a
// reference frame (pattern only) and for a deformed frame (LEFM crack field
// plus drift, as bench/dic_band_frames renders), and the difference of the
// deformed frame from a stored one (to check a faster renderer draws the
// same image).
//   bench/dic_speckle_speed [SIZE=512] [THREADS=0 (all)] [WRITE_OR_COMPARE.png]
#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "bridgefit/dic/image.hpp"
#include "bridgefit/dic/speckle.hpp"

using namespace bridgefit::dic;

int main(int argc, char** argv) {
  const int size = argc > 1 ? std::atoi(argv[1]) : 512;
  const int threads = argc > 2 ? std::atoi(argv[2]) : 0;
  if (threads > 0) omp_set_num_threads(threads);
  SpeckleOptions so;
  so.width = so.height = size;
  so.seed = 7;
  auto now = [] { return std::chrono::steady_clock::now(); };
  auto t0 = now();
  const SpeckleRenderer renderer(so);
  auto t1 = now();
  const Image ref = renderer.RenderReference(1000);
  auto t2 = now();
  ModeICrackField m;
  m.tip_x = 0.5 * size;
  m.tip_y = size / 2 + 0.5;
  m.k_over_2mu = 0.07;
  m.translation_x = 0.5;
  m.translation_y = -0.25;
  const Image def = renderer.Render(m, 1001);
  auto t3 = now();
  auto sec = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  std::printf("size %d, threads %d: setup %.3f s, reference %.3f s, deformed %.3f s (%.3f us/px)\n",
              size, threads > 0 ? threads : omp_get_max_threads(), sec(t0, t1), sec(t1, t2),
              sec(t2, t3), 1e6 * sec(t2, t3) / (double(size) * size));
  if (argc > 3) {
    const std::filesystem::path path = argv[3];
    if (!std::filesystem::exists(path)) {
      WriteImage(path, def, 8);
      std::printf("wrote %s\n", path.c_str());
    } else {
      const Image old = ReadImage(path);
      double max_diff = 0;
      size_t differ = 0;
      for (size_t i = 0; i < old.pixels.size(); ++i) {
        const double d = std::abs(double(old.pixels[i]) - def.pixels[i]);
        max_diff = std::max(max_diff, d);
        differ += d > 0;
      }
      std::printf("against %s: %zu of %zu pixels differ, max %.0f gray levels\n", path.c_str(),
                  differ, old.pixels.size(), max_diff);
    }
  }
  return 0;
}
