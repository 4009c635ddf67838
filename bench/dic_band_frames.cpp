// Synthetic cracked sequence for the crack-band bench (bench/dic_band.sh):
// speckle frames of SIZE x SIZE px (speckle generator, 8 bit) with an LEFM
// mode I crack on y = SIZE/2 + 0.5 from x = 0, whose tip advances linearly
// from 0.3 SIZE (frame 1) to 0.7 SIZE (last frame), plus a slow rigid drift;
// frame 0 is the undeformed reference. Writes OUT/frame_NNNN.png and
// OUT/truth.csv (frame, tip_x_px = crack length from x = 0 in px).
//   bench/dic_band_frames OUT [FRAMES=200] [SIZE=2048]
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "bridgefit/dic/image.hpp"
#include "bridgefit/dic/speckle.hpp"

using namespace bridgefit::dic;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: dic_band_frames OUT [FRAMES=200] [SIZE=2048]\n");
    return 2;
  }
  const std::filesystem::path out = argv[1];
  const int frames = argc > 2 ? std::atoi(argv[2]) : 200;
  const int size = argc > 3 ? std::atoi(argv[3]) : 2048;
  if (frames < 2 || size < 256) {
    std::fprintf(stderr, "need FRAMES >= 2 and SIZE >= 256\n");
    return 2;
  }
  std::filesystem::create_directories(out);
  SpeckleOptions so;
  so.width = so.height = size;
  so.seed = 7;
  const SpeckleRenderer renderer(so);
  std::ofstream truth(out / "truth.csv");
  truth << "frame,tip_x_px\n";
  for (int k = 0; k < frames; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", k);
    Image image;
    if (k == 0) {
      image = renderer.RenderReference(1000);
      truth << "0,\n";
    } else {
      ModeICrackField m;
      m.tip_x = size * (0.3 + 0.4 * (k - 1) / std::max(1, frames - 2));
      m.tip_y = size / 2 + 0.5;
      m.k_over_2mu = 0.07;  // px^0.5: about 3 px opening 300 px behind the tip
      m.translation_x = 0.01 * k;
      m.translation_y = -0.005 * k;
      image = renderer.Render(m, 1000 + k);
      truth << k << "," << m.tip_x << "\n";
    }
    WriteImage(out / name, image, 8);
    std::fprintf(stderr, "\rframe %d/%d", k + 1, frames);
  }
  std::fprintf(stderr, "\n");
  return 0;
}
