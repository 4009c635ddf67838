#pragma once
// Quantities with units at the boundary; SI doubles inside.
//
// ParseQuantity("0.45 MPa", Dimension::Stress()) -> 450000.0 (Pa).
// A bare number in a dimensional field is an error naming the expected unit.

#include <string>
#include <string_view>

#include "bridgefit/core/error.hpp"

namespace bridgefit {

// Physical dimension as exponents of kg, m, s (and pixels for image scales).
struct Dimension {
  int mass = 0;
  int length = 0;
  int time = 0;
  int pixel = 0;

  friend bool operator==(const Dimension&, const Dimension&) = default;

  static constexpr Dimension None() { return {}; }
  static constexpr Dimension Length() { return {0, 1, 0, 0}; }
  static constexpr Dimension Time() { return {0, 0, 1, 0}; }
  static constexpr Dimension Mass() { return {1, 0, 0, 0}; }
  static constexpr Dimension Force() { return {1, 1, -2, 0}; }
  static constexpr Dimension Stress() { return {1, -1, -2, 0}; }
  // J/m^2 = N/m: energy release rate, toughness.
  static constexpr Dimension EnergyPerArea() { return {1, 0, -2, 0}; }
  static constexpr Dimension Energy() { return {1, 2, -2, 0}; }
  static constexpr Dimension Density() { return {1, -3, 0, 0}; }
  static constexpr Dimension Pixel() { return {0, 0, 0, 1}; }
  static constexpr Dimension LengthPerPixel() { return {0, 1, 0, -1}; }
};

// Name of the SI unit of a dimension, e.g. "Pa", "J/m^2", "m".
std::string SiUnitName(const Dimension& dimension);
// A readable example unit for error messages: "a stress such as '0.45 MPa'".
std::string DescribeDimension(const Dimension& dimension);

// A parsed unit: value_in_SI = number * scale.
struct Unit {
  double scale = 1.0;
  Dimension dimension;
};

// Largest |exponent| a unit may write ("m^12"); the dimension a unit adds up
// to is bounded by 4x this. Anything outside is an Error, never a wrap-around.
inline constexpr int kMaxUnitExponent = 12;

// Parses a unit expression: "MPa", "J/m^2", "N/mm", "kg/m^3", "mm/px",
// "kJ/m^2", "m.s^-1", "N*mm". Throws Error naming the unknown symbol, an
// exponent outside [-kMaxUnitExponent, kMaxUnitExponent] or a unit over 128
// characters.
Unit ParseUnit(std::string_view text);

// Parses "<number> <unit>" (space optional) and checks the dimension.
// Throws Error(kInput) for a bare number, an unknown unit or a dimension
// mismatch; the message names the expected unit.
double ParseQuantity(std::string_view text, const Dimension& expected);

// Converts a number given in `unit_text` to SI, checking the dimension.
double ToSi(double value, std::string_view unit_text, const Dimension& expected);
// Converts an SI value to `unit_text` (e.g. metres to "mm").
double FromSi(double value_in_si, std::string_view unit_text,
              const Dimension& expected);

}  // namespace bridgefit
