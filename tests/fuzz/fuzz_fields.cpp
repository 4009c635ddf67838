// libFuzzer harness: displacement-field exports of other DIC software
// (dic/fields_read.cpp: plain CSV, Aramis nodemap, DICe solution, DaVis
// vector text), read the way `bridgefit crack FIELDS...` reads them, then the
// node spacing and a write-back in the detected format.
#include <cstddef>
#include <cstdint>
#include <string>

#include "bridgefit/core/error.hpp"
#include "bridgefit/dic/fields.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace bridgefit;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const dic::FieldFile file = dic::ReadFieldText(text, "fuzz.txt");
    (void)dic::PointSpacing(file.field);
    (void)dic::WriteFieldText(file, file.format);
  } catch (const Error&) {
  }
  return 0;
}
