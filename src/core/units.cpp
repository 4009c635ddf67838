#include "bridgefit/core/units.hpp"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <string>

namespace bridgefit {
namespace {

struct Symbol {
  std::string_view name;
  double scale;
  Dimension dimension;
  bool takes_prefix;
};

// Base symbols. Prefixes are applied only to those with takes_prefix.
constexpr std::array<Symbol, 16> kSymbols = {{
    {"m", 1.0, Dimension::Length(), true},
    {"g", 1e-3, Dimension::Mass(), true},
    {"s", 1.0, Dimension::Time(), true},
    {"N", 1.0, Dimension::Force(), true},
    {"Pa", 1.0, Dimension::Stress(), true},
    {"J", 1.0, Dimension::Energy(), true},
    {"W", 1.0, {1, 2, -3, 0}, true},
    {"Hz", 1.0, {0, 0, -1, 0}, true},
    {"px", 1.0, Dimension::Pixel(), false},
    {"pixel", 1.0, Dimension::Pixel(), false},
    {"min", 60.0, Dimension::Time(), false},
    {"h", 3600.0, Dimension::Time(), false},
    {"in", 0.0254, Dimension::Length(), false},
    {"lbf", 4.4482216152605, Dimension::Force(), false},
    {"psi", 6894.757293168, Dimension::Stress(), false},
    {"bar", 1e5, Dimension::Stress(), false},
}};

struct Prefix {
  std::string_view name;
  double scale;
};
constexpr std::array<Prefix, 9> kPrefixes = {{{"G", 1e9},
                                              {"M", 1e6},
                                              {"k", 1e3},
                                              {"c", 1e-2},
                                              {"m", 1e-3},
                                              {"u", 1e-6},
                                              {"\xC2\xB5", 1e-6},  // micro sign
                                              {"\xCE\xBC", 1e-6},  // Greek mu
                                              {"n", 1e-9}}};

// Exponents are small integers in practice (m^3, s^-2); bounding them keeps
// every dimension sum far from int overflow, so a wrapped exponent can never
// pass as a valid dimension (fuzzing found "m^2147483647*m^2147483647*m^3").
constexpr int kMaxWrittenExponent = kMaxUnitExponent;
constexpr int kMaxDimensionExponent = 4 * kMaxUnitExponent;
constexpr std::size_t kMaxUnitLength = 128;

[[noreturn]] void ExponentOutOfRange(std::string_view whole, const std::string& what) {
  throw Error(ErrorKind::kInput, "unit exponent out of range: " + what,
              {.value = std::string(whole),
               .expected = "integer exponents between -" + std::to_string(kMaxWrittenExponent) +
                           " and " + std::to_string(kMaxWrittenExponent) +
                           ", e.g. 'm^2' or 's^-2'"});
}

// One dimension exponent += power * factor exponent, checked.
int CombineExponent(int total, int factor, int power, std::string_view whole) {
  long long scaled = static_cast<long long>(factor) * power;  // |.| <= 4 * 12
  long long sum = static_cast<long long>(total) + scaled;
  if (sum > kMaxDimensionExponent || sum < -kMaxDimensionExponent)
    ExponentOutOfRange(whole, "the combined exponent " + std::to_string(sum) + " exceeds " +
                                  std::to_string(kMaxDimensionExponent));
  return static_cast<int>(sum);
}

Dimension Combine(const Dimension& total, const Dimension& factor, int power,
                  std::string_view whole) {
  return {CombineExponent(total.mass, factor.mass, power, whole),
          CombineExponent(total.length, factor.length, power, whole),
          CombineExponent(total.time, factor.time, power, whole),
          CombineExponent(total.pixel, factor.pixel, power, whole)};
}

// Reads the integer after '^' in text[begin, ...); returns it and sets *end.
int ParseExponent(std::string_view text, size_t begin, size_t* end, std::string_view whole) {
  size_t digits = begin;
  int sign = 1;
  if (digits < text.size() && (text[digits] == '-' || text[digits] == '+')) {
    sign = text[digits] == '-' ? -1 : 1;
    ++digits;
  }
  size_t stop = digits;
  while (stop < text.size() && std::isdigit(static_cast<unsigned char>(text[stop]))) ++stop;
  if (stop == digits)
    throw Error(ErrorKind::kInput, "malformed unit exponent",
                {.value = std::string(whole), .expected = "an integer exponent such as 'm^2'"});
  // Leading zeros aside, more than two digits is out of range whatever they say.
  size_t first = digits;
  while (first + 1 < stop && text[first] == '0') ++first;
  if (stop - first > 2)
    ExponentOutOfRange(whole, "'" + std::string(text.substr(begin, stop - begin)) + "'");
  int magnitude = 0;
  for (size_t i = first; i < stop; ++i) magnitude = magnitude * 10 + (text[i] - '0');
  if (magnitude > kMaxWrittenExponent)
    ExponentOutOfRange(whole, "'" + std::string(text.substr(begin, stop - begin)) + "'");
  *end = stop;
  return sign * magnitude;
}

Unit LookupSymbol(std::string_view symbol, std::string_view whole) {
  for (const Symbol& s : kSymbols) {
    if (s.name == symbol) return {s.scale, s.dimension};
  }
  for (const Prefix& p : kPrefixes) {
    if (symbol.size() <= p.name.size() || symbol.substr(0, p.name.size()) != p.name)
      continue;
    std::string_view rest = symbol.substr(p.name.size());
    for (const Symbol& s : kSymbols) {
      if (s.takes_prefix && s.name == rest) return {p.scale * s.scale, s.dimension};
    }
  }
  throw Error(ErrorKind::kInput, "unknown unit symbol '" + std::string(symbol) + "'",
              {.value = std::string(whole),
               .expected = "units built from m, mm, um, in, g, kg, s, min, N, kN, "
                           "Pa, kPa, MPa, GPa, J, kJ, px, with '/', '*' and '^'"});
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

}  // namespace

std::string SiUnitName(const Dimension& d) {
  if (d == Dimension::None()) return "1";
  if (d == Dimension::Length()) return "m";
  if (d == Dimension::Time()) return "s";
  if (d == Dimension::Mass()) return "kg";
  if (d == Dimension::Force()) return "N";
  if (d == Dimension::Stress()) return "Pa";
  if (d == Dimension::EnergyPerArea()) return "J/m^2";
  if (d == Dimension::Energy()) return "J";
  if (d == Dimension::Density()) return "kg/m^3";
  if (d == Dimension::Pixel()) return "px";
  if (d == Dimension::LengthPerPixel()) return "m/px";
  std::string out;
  auto term = [&out](const char* name, int power) {
    if (power == 0) return;
    if (!out.empty()) out += "*";
    out += name;
    if (power != 1) out += "^" + std::to_string(power);
  };
  term("kg", d.mass);
  term("m", d.length);
  term("s", d.time);
  term("px", d.pixel);
  return out;
}

std::string DescribeDimension(const Dimension& d) {
  if (d == Dimension::Length()) return "a length such as '12.7 mm'";
  if (d == Dimension::Stress()) return "a stress or modulus such as '0.45 MPa' or '3 GPa'";
  if (d == Dimension::EnergyPerArea())
    return "an energy per area such as '500 J/m^2', '0.5 kJ/m^2' or '1 N/mm'";
  if (d == Dimension::Density()) return "a density such as '609 kg/m^3'";
  if (d == Dimension::Force()) return "a force such as '250 N'";
  if (d == Dimension::Time()) return "a time such as '2 s'";
  if (d == Dimension::Pixel()) return "a pixel count such as '0.02 px'";
  if (d == Dimension::LengthPerPixel()) return "a scale such as '0.05 mm/px'";
  if (d == Dimension::None()) return "a plain number";
  return "a quantity in " + SiUnitName(d);
}

Unit ParseUnit(std::string_view text) {
  const std::string_view whole = text;
  text = Trim(text);
  if (text.empty())
    throw Error(ErrorKind::kInput, "empty unit", {.expected = "a unit such as 'mm' or 'MPa'"});
  if (text.size() > kMaxUnitLength)
    throw Error(ErrorKind::kInput,
                "unit longer than " + std::to_string(kMaxUnitLength) + " characters",
                {.value = std::string(whole.substr(0, 40)) + "...",
                 .expected = "a unit such as 'J/m^2' or 'kg/m^3'"});
  Unit unit;
  int sign = +1;  // +1 before the first '/', -1 after
  size_t pos = 0;
  while (pos < text.size()) {
    // One factor: symbol [^ integer]
    size_t end = pos;
    while (end < text.size() && text[end] != '/' && text[end] != '*' &&
           text[end] != '.' && text[end] != '^' &&
           !std::isspace(static_cast<unsigned char>(text[end])))
      ++end;
    std::string_view symbol = text.substr(pos, end - pos);
    if (symbol.empty())
      throw Error(ErrorKind::kInput, "malformed unit", {.value = std::string(whole),
                  .expected = "a unit such as 'J/m^2' or 'kg/m^3'"});
    int power = 1;
    if (end < text.size() && text[end] == '^') power = ParseExponent(text, end + 1, &end, whole);
    const Unit factor = LookupSymbol(symbol, whole);
    unit.scale *= std::pow(factor.scale, sign * power);  // |sign * power| <= 12
    unit.dimension = Combine(unit.dimension, factor.dimension, sign * power, whole);
    if (!std::isfinite(unit.scale) || unit.scale == 0.0)
      throw Error(ErrorKind::kInput, "unit scale overflows a double",
                  {.value = std::string(whole), .expected = "a unit such as 'J/m^2' or 'kg/m^3'"});
    while (end < text.size() && std::isspace(static_cast<unsigned char>(text[end]))) ++end;
    if (end >= text.size()) break;
    const char op = text[end];
    if (op == '/') {
      if (sign < 0)
        throw Error(ErrorKind::kInput, "a unit may contain only one '/'",
                    {.value = std::string(whole), .expected = "a form such as 'kg/m^3'"});
      sign = -1;
    } else if (op != '*' && op != '.') {
      throw Error(ErrorKind::kInput, "malformed unit", {.value = std::string(whole),
                  .expected = "factors joined by '*', '.' or one '/'"});
    }
    pos = end + 1;
    while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos]))) ++pos;
    if (pos >= text.size())
      throw Error(ErrorKind::kInput, "unit ends with an operator", {.value = std::string(whole)});
  }
  return unit;
}

double ParseQuantity(std::string_view text, const Dimension& expected) {
  const std::string whole(text);
  std::string_view s = Trim(text);
  // Number: the longest prefix strtod accepts.
  const std::string buffer(s);
  const char* begin = buffer.c_str();
  char* end = nullptr;
  const double number = std::strtod(begin, &end);
  if (end == begin)
    throw Error(ErrorKind::kInput, "not a number with a unit",
                {.value = whole, .expected = DescribeDimension(expected)});
  if (!std::isfinite(number))
    throw Error(ErrorKind::kInput, "the number is not finite",
                {.value = whole, .expected = DescribeDimension(expected)});
  const std::string_view unit_text = Trim(std::string_view(end));
  if (unit_text.empty()) {
    if (expected == Dimension::None()) return number;
    throw Error(ErrorKind::kInput, "a bare number needs a unit",
                {.value = whole, .expected = DescribeDimension(expected)});
  }
  Unit unit;
  try {
    unit = ParseUnit(unit_text);
  } catch (const Error& e) {
    // The whole quantity as written, e.g. "2 m^99", is what the user can find.
    ErrorContext context = e.context();
    context.value = whole;
    if (context.expected.empty()) context.expected = DescribeDimension(expected);
    throw Error(e.kind(), e.message(), context);
  }
  if (!(unit.dimension == expected))
    throw Error(ErrorKind::kInput,
                "wrong unit: '" + std::string(unit_text) + "' is " + SiUnitName(unit.dimension) +
                    " but the field needs " + SiUnitName(expected),
                {.value = whole, .expected = DescribeDimension(expected)});
  const double si = number * unit.scale;
  if (!std::isfinite(si))
    throw Error(ErrorKind::kInput, "the value overflows a double in SI units",
                {.value = whole, .expected = DescribeDimension(expected)});
  return si;
}

double ToSi(double value, std::string_view unit_text, const Dimension& expected) {
  const Unit unit = ParseUnit(unit_text);
  if (!(unit.dimension == expected))
    throw Error(ErrorKind::kInput,
                "wrong unit: '" + std::string(unit_text) + "' is " + SiUnitName(unit.dimension) +
                    " but the field needs " + SiUnitName(expected),
                {.value = std::string(unit_text), .expected = DescribeDimension(expected)});
  return value * unit.scale;
}

double FromSi(double si_value, std::string_view unit_text, const Dimension& expected) {
  return si_value / ToSi(1.0, unit_text, expected);
}

}  // namespace bridgefit
