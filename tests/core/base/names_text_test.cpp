// The enum name tables and the number formatters every unit shares.
#include <gtest/gtest.h>

#include "popcut/names.h"
#include "popcut/text.h"

namespace popcut {
namespace {

enum class Colour { red, green, blue };
constexpr auto kColourNames =
    enum_names<Colour>({{Colour::red, "red"}, {Colour::green, "green"}, {Colour::blue, "blue"}});

TEST(EnumNames, NameAndFindRoundTrip) {
  static_assert(kColourNames.name(Colour::green) == "green");
  for (Colour c : {Colour::red, Colour::green, Colour::blue}) {
    ASSERT_TRUE(kColourNames.find(kColourNames.name(c)).has_value());
    EXPECT_EQ(*kColourNames.find(kColourNames.name(c)), c);
  }
  EXPECT_FALSE(kColourNames.find("Red").has_value());
  EXPECT_FALSE(kColourNames.find("").has_value());
  EXPECT_TRUE(kColourNames.name(static_cast<Colour>(7)).empty());
}

TEST(EnumNames, ListsForMessages) {
  EXPECT_EQ(kColourNames.list(), "red, green or blue");
  EXPECT_EQ(kColourNames.quoted_list(), "'red', 'green' or 'blue'");
  EXPECT_EQ(kColourNames.list(", "), "red, green, blue");
  constexpr auto one = enum_names<Colour>({{Colour::red, "red"}});
  EXPECT_EQ(one.list(), "red");
}

TEST(NumberText, Decimal) {
  EXPECT_EQ(format_decimal(12.5, 3), "12.5");
  EXPECT_EQ(format_decimal(2.0, 3), "2");
  EXPECT_EQ(format_decimal(-0.0001, 2), "0");
  EXPECT_EQ(format_decimal(-1.25, 1), "-1.2");  // printf rounds half to even on this binary value
}

TEST(NumberText, FixedAndSignificant) {
  EXPECT_EQ(format_fixed(2.0, 1), "2.0");
  EXPECT_EQ(format_fixed(-0.04, 1), "0.0");
  EXPECT_EQ(format_fixed(-0.06, 1), "-0.1");
  EXPECT_EQ(format_fixed(10.0, 0), "10");
  EXPECT_EQ(format_significant(0.1), "0.1");
  EXPECT_EQ(format_significant(1e-7), "1e-07");
  EXPECT_EQ(format_significant(1234567.0), "1.23457e+06");
  EXPECT_EQ(format_significant(1.0 / 3.0, 15), "0.333333333333333");
}

}  // namespace
}  // namespace popcut
