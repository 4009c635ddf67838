// libFuzzer harness: unit and quantity parsing (core/units.cpp).
#include <cstddef>
#include <cstdint>
#include <string>

#include "bridgefit/core/units.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // A view into exactly the fuzzer's bytes: no terminating NUL to hide a
  // read past the end.
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  using bridgefit::Dimension;
  try {
    const bridgefit::Unit unit = bridgefit::ParseUnit(text);
    (void)bridgefit::SiUnitName(unit.dimension);
  } catch (const bridgefit::Error&) {
  }
  for (const Dimension& d : {Dimension::Length(), Dimension::Stress(), Dimension::EnergyPerArea(),
                             Dimension::None()}) {
    try {
      (void)bridgefit::ParseQuantity(text, d);
    } catch (const bridgefit::Error&) {
    }
  }
  return 0;
}
