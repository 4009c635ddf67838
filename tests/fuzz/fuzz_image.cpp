// libFuzzer harness: image decoding (dic/image.cpp: OpenCV behind the pixel limit).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/image.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // OpenCV's own pre-decode check, at the harness's limit (the CLI does the same).
  setenv("OPENCV_IO_MAX_IMAGE_PIXELS", "4194304", 1);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  bridgefit::InputLimits limits;
  limits.max_image_pixels = 1 << 22;
  try {
    (void)bridgefit::dic::DecodeImage(
        std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.img", limits);
  } catch (const bridgefit::Error&) {
  }
  return 0;
}
