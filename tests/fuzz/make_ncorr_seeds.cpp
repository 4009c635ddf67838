// Writes the seed corpus of fuzz_ncorr: small Ncorr runs (two frames on a
// 6 x 4 grid) in MAT v5 and v7.3, with and without the ROI mask, through the
// project's own writer. Usage: make_ncorr_seeds DIR
#include <filesystem>
#include <iostream>
#include <vector>

#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/fields.hpp"

int main(int argc, char** argv) {
  using namespace bridgefit;
  if (argc != 2) {
    std::cerr << "usage: make_ncorr_seeds DIR\n";
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::vector<dic::FieldFile> frames(2);
  for (int k = 0; k < 2; ++k) {
    dic::FieldFile& f = frames[k];
    f.unit = "px";
    f.format = dic::FieldFormat::kNcorr;
    dic::DisplacementField& d = f.field;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 6; ++c) {
        d.x.push_back(5.0 * c);
        d.y.push_back(5.0 * r);
        d.u.push_back(0.01 * (k + 1) * c);
        d.v.push_back(r < 2 ? -0.02 * (k + 1) * c : 0.02 * (k + 1) * c);
        d.status.push_back(dic::PointStatus::kOk);
      }
    d.nx = 6;
    d.ny = 4;
  }
  try {
    int n = 0;
    for (bool v73 : {false, true})
      for (bool mask : {true, false})
        dic::WriteNcorrFile(dir / ("seed" + std::to_string(n++) + ".mat"), frames,
                            {.spacing_px = 4, .v73 = v73, .roi_mask = mask});
  } catch (const Error& e) {
    std::cerr << "make_ncorr_seeds: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
