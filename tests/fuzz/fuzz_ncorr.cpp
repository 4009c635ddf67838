// libFuzzer harness: Ncorr's saved analysis (MAT v5/v7 read by matio's own
// parser; v7.3 is HDF5). The bytes are written to a file and read as
// `bridgefit crack run.mat` reads it: an HDF5 file (v7.3) is first read in a
// child (io::CheckH5FileInChildProcess, as fuzz_h5), then opened with
// dic::NcorrFile and every frame converted, with the node spacing of each.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/fields.hpp"
#include "bridgefit/io/hdf5.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace bridgefit;
  static const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("fuzz_ncorr_" + std::to_string(getpid()) + ".mat");
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    if (dic::IsMatFile(file))
      io::CheckH5FileInChildProcess(file, 10.0, [] { dic::ReadEveryNcorrFrame(file); });
    if (dic::IsMatFile(file)) {
      const dic::NcorrFile ncorr(file);
      for (std::size_t k = 0; k < ncorr.Frames() && k < 16; ++k) {
        const dic::FieldFile frame = ncorr.Frame(k);
        (void)dic::PointSpacing(frame.field);
        (void)ncorr.FrameName(k);
      }
    }
  } catch (const Error&) {
  }
  return 0;
}
