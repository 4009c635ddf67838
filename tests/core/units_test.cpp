#include "bridgefit/core/units.hpp"

#include <gtest/gtest.h>

namespace bridgefit {
namespace {

TEST(Units, AcceptedForms) {
  EXPECT_DOUBLE_EQ(ParseQuantity("0.45 MPa", Dimension::Stress()), 0.45e6);
  EXPECT_DOUBLE_EQ(ParseQuantity("500 J/m^2", Dimension::EnergyPerArea()), 500.0);
  EXPECT_DOUBLE_EQ(ParseQuantity("2.57 mm", Dimension::Length()), 2.57e-3);
  EXPECT_DOUBLE_EQ(ParseQuantity("3 GPa", Dimension::Stress()), 3e9);
  EXPECT_DOUBLE_EQ(ParseQuantity("609 kg/m^3", Dimension::Density()), 609.0);
  EXPECT_DOUBLE_EQ(ParseQuantity("12.7 mm", Dimension::Length()), 12.7e-3);
  EXPECT_DOUBLE_EQ(ParseQuantity("0.5 kJ/m^2", Dimension::EnergyPerArea()), 500.0);
  EXPECT_DOUBLE_EQ(ParseQuantity("1 N/mm", Dimension::EnergyPerArea()), 1000.0);
  EXPECT_DOUBLE_EQ(ParseQuantity("2.5mm", Dimension::Length()), 2.5e-3);
  EXPECT_DOUBLE_EQ(ParseQuantity("1e-3 m", Dimension::Length()), 1e-3);
  EXPECT_DOUBLE_EQ(ParseQuantity("0.05 mm/px", Dimension::LengthPerPixel()), 5e-5);
  EXPECT_DOUBLE_EQ(ParseQuantity("2 min", Dimension::Time()), 120.0);
  EXPECT_DOUBLE_EQ(ParseQuantity("250 N", Dimension::Force()), 250.0);
  EXPECT_DOUBLE_EQ(ParseQuantity("1 kN", Dimension::Force()), 1000.0);
  EXPECT_NEAR(ParseQuantity("1 in", Dimension::Length()), 0.0254, 1e-15);
  EXPECT_DOUBLE_EQ(ParseQuantity("3 um", Dimension::Length()), 3e-6);
  EXPECT_DOUBLE_EQ(ParseQuantity("1 N*m/m^3", Dimension::Stress()), 1.0);
  EXPECT_DOUBLE_EQ(ParseQuantity("0.3", Dimension::None()), 0.3);
}

std::string MessageOf(const std::string& text, const Dimension& d) {
  try {
    ParseQuantity(text, d);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kInput);
    return e.what();
  }
  ADD_FAILURE() << "no error for '" << text << "'";
  return "";
}

TEST(Units, BareNumberNamesExpectedUnit) {
  const std::string m = MessageOf("500", Dimension::EnergyPerArea());
  EXPECT_NE(m.find("bare number needs a unit"), std::string::npos) << m;
  EXPECT_NE(m.find("J/m^2"), std::string::npos) << m;
}

TEST(Units, WrongDimension) {
  const std::string m = MessageOf("3 mm", Dimension::Stress());
  EXPECT_NE(m.find("wrong unit"), std::string::npos) << m;
  EXPECT_NE(m.find("'mm' is m"), std::string::npos) << m;
  EXPECT_NE(m.find("MPa"), std::string::npos) << m;
}

TEST(Units, RejectedForms) {
  EXPECT_NE(MessageOf("12 furlongs", Dimension::Length()).find("unknown unit symbol 'furlongs'"),
            std::string::npos);
  EXPECT_NE(MessageOf("mm", Dimension::Length()).find("not a number with a unit"),
            std::string::npos);
  EXPECT_NE(MessageOf("", Dimension::Length()).find("not a number"), std::string::npos);
  EXPECT_NE(MessageOf("1 J/m/m", Dimension::EnergyPerArea()).find("only one '/'"),
            std::string::npos);
  EXPECT_NE(MessageOf("1 m^x", Dimension::Length()).find("exponent"), std::string::npos);
  EXPECT_NE(MessageOf("1 J/", Dimension::EnergyPerArea()).find("ends with an operator"),
            std::string::npos);
  EXPECT_NE(MessageOf("inf MPa", Dimension::Stress()).find("not finite"), std::string::npos);
}

// Fuzzing found exponents that wrapped int and passed as the right dimension.
TEST(Units, WrappedExponentsAreRefusedNotWrapped) {
  for (const char* text : {"2 m^2147483647*m^2147483647*m^3", "1 m^-2147483648",
                           "1 m^99999999999999999999", "1 m^13", "1 s^-13", "1 m^0013",
                           "1 m^12*m^12*m^12*m^12*m^12"}) {
    const std::string m = MessageOf(text, Dimension::Length());
    EXPECT_NE(m.find("exponent out of range"), std::string::npos) << text << ": " << m;
    EXPECT_NE(m.find("between -12 and 12"), std::string::npos) << m;
  }
  // The bounds themselves still parse.
  EXPECT_DOUBLE_EQ(ParseUnit("m^12/m^11").scale, 1.0);
  EXPECT_EQ(ParseUnit("m^12/m^11").dimension, Dimension::Length());
  EXPECT_EQ(ParseUnit("m^+2*s^-12").dimension, (Dimension{0, 2, -12, 0}));
  EXPECT_EQ(ParseUnit("m^007").dimension, (Dimension{0, 7, 0, 0}));
}

// "m^" at the very end of the text: the exponent check must not read past it.
// A string_view into a larger buffer puts a digit right after the end.
TEST(Units, ExponentSignAtEndOfTextStaysInside) {
  const std::string buffer = "m^2";
  EXPECT_THROW(ParseUnit(std::string_view(buffer.data(), 2)), Error);
  const std::string minus = "m^-3";
  EXPECT_THROW(ParseUnit(std::string_view(minus.data(), 3)), Error);
  const std::string m = MessageOf("1 m^", Dimension::Length());
  EXPECT_NE(m.find("malformed unit exponent"), std::string::npos) << m;
}

TEST(Units, ScaleOverflowIsAnErrorNotInfinity) {
  // Dimensionless overall, but the scale is 1e108 * 1e108 * 1e72 * 1e72.
  const std::string m = MessageOf("1 Gm^12*Gm^12/um^12*um^12", Dimension::None());
  EXPECT_NE(m.find("unit scale overflows"), std::string::npos) << m;
  EXPECT_NE(MessageOf("1e300 GPa", Dimension::Stress()).find("overflows"), std::string::npos);
  EXPECT_NE(MessageOf(std::string("1 ") + std::string(200, 'm'), Dimension::Length())
                .find("longer than 128"),
            std::string::npos);
}

TEST(Units, RoundTripThroughSi) {
  EXPECT_DOUBLE_EQ(FromSi(0.0254, "mm", Dimension::Length()), 25.4);
  EXPECT_DOUBLE_EQ(ToSi(19.3, "GPa", Dimension::Stress()), 19.3e9);
  EXPECT_THROW(ToSi(1.0, "N", Dimension::Length()), Error);
}

TEST(Units, SiNames) {
  EXPECT_EQ(SiUnitName(Dimension::EnergyPerArea()), "J/m^2");
  EXPECT_EQ(SiUnitName(Dimension::Stress()), "Pa");
  EXPECT_EQ(SiUnitName(Dimension{0, 1, -1, 0}), "m*s^-1");
}

}  // namespace
}  // namespace bridgefit
