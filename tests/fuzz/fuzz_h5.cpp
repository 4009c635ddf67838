// libFuzzer harness: HDF5 inputs of every kind `fit`, `report` and `rcurve`
// accept. Each input is written to a file and read the way the CLI reads a
// file named on its command line: first completely in a child process (a
// crash inside libhdf5 there is a refusal, "corrupt HDF5 file"), then in
// this process through bridgefit's checked readers, where ASan and UBSan
// watch bridgefit's own code.
//
// BRIDGEFIT_FUZZ_H5_IN_PROCESS=1 skips the child: the fuzzer then finds the
// crashes inside libhdf5 1.10.8 itself (how tests/fuzz/regressions/h5 was
// collected).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "bridgefit/core/error.hpp"
#include "h5_inputs.hpp"

namespace {

std::filesystem::path ScratchFile() {
  const char* shm = "/dev/shm";
  const std::filesystem::path folder =
      std::filesystem::is_directory(shm) ? shm : std::filesystem::temp_directory_path();
  return folder / ("bridgefit-fuzz-" + std::to_string(::getpid()) + ".h5");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path path = ScratchFile();
  static const bool in_process = std::getenv("BRIDGEFIT_FUZZ_H5_IN_PROCESS") != nullptr;
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    (void)bridgefit::fuzz::ReadAsEveryH5Input(path, !in_process);
  } catch (const bridgefit::Error&) {
  }
  return 0;
}
