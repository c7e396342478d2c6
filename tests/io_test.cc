// The plumbing every reader and writer shares (sim/io): CSV, strict
// number parsing and formatting, input errors. The expected values are
// the rules the headers state.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "sim/io/csv.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

// The message of the InputError `statement` throws, or "no error".
template <typename Function>
std::string InputErrorOf(Function statement) {
  try {
    statement();
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(NumbersTest, ParseDoubleTakesOnlyAWholeNumber) {
  EXPECT_EQ(ParseDouble("1"), 1.0);
  EXPECT_EQ(ParseDouble("-2.5"), -2.5);
  EXPECT_EQ(ParseDouble("+3e-4"), 3e-4);
  EXPECT_EQ(ParseDouble(".5"), 0.5);
  EXPECT_EQ(ParseDouble("0.1"), 0.1);
  EXPECT_TRUE(std::isinf(*ParseDouble("-inf")));
  EXPECT_TRUE(std::isnan(*ParseDouble("nan")));
  for (const char* bad : {"", " 1", "1 ", "1e", "1,5", "abc", "+-1", "++1", "-", "+", "0x10",
                          "1e400", "1.0.0"}) {
    EXPECT_FALSE(ParseDouble(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(NumbersTest, ParseIntegerTakesOnlyAWholeNumber) {
  EXPECT_EQ(ParseInteger("0"), 0L);
  EXPECT_EQ(ParseInteger("-12"), -12L);
  EXPECT_EQ(ParseInteger("+7"), 7L);
  for (const char* bad : {"", "1.0", "1e3", " 1", "x", "99999999999999999999"}) {
    EXPECT_FALSE(ParseInteger(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(NumbersTest, FormatsReadBackExactly) {
  for (double value : {0.1, 1.0 / 3.0, 6.02214076e23, -1.5e-300, kPi}) {
    EXPECT_EQ(*ParseDouble(FormatDouble(value)), value);
    EXPECT_EQ(*ParseDouble(FormatShortest(value)), value);
  }
  EXPECT_EQ(FormatShortest(0.001), "0.001");
  EXPECT_EQ(FormatShortest(1000.0), "1000");
  EXPECT_EQ(FormatDouble(0.1), "0.10000000000000001");
  EXPECT_EQ(FormatDouble(kPi, 6), "3.14159");
  EXPECT_EQ(FormatDouble(1e-5, 10), "1e-05");
  EXPECT_EQ(2.0 * kPi, kTwoPi);
  EXPECT_EQ(kPi, std::acos(-1.0));
}

// FormatDouble against printf's "%.*g" itself, which it stands for: signs,
// zeros, subnormals, the extremes, non-finite values, short decimals and
// pseudo-random values over 600 decades, at every precision CSVs use.
TEST(NumbersTest, FormatDoubleIsPrintfsG) {
  std::vector<double> values = {0.0, -0.0, 5e-324, -2.2250738585072014e-308, 1.7976931348623157e308,
                                std::nan(""), -std::nan(""), HUGE_VAL, -HUGE_VAL, 1e-5, 0.5, 1e15,
                                123456789012345678.0, 0.1, 2.675};
  unsigned long long state = 12345;
  for (int i = 0; i < 20000; ++i) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;  // Knuth's LCG
    const double mantissa = static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5;
    const int decade = static_cast<int>((state >> 3) % 600) - 300;
    values.push_back(i % 7 == 0 ? static_cast<double>(state % 100000) / 1000.0
                                : mantissa * std::pow(10.0, decade));
  }
  for (int digits : {-1, 0, 1, 4, 6, 10, 12, 15, 17, 20}) {
    for (double value : values) {
      char expected[128];
      std::snprintf(expected, sizeof(expected), "%.*g", digits, value);
      ASSERT_EQ(FormatDouble(value, digits), expected) << digits << " digits";
    }
  }
  // Beyond the 64-character buffer: printf, as before (cut at 63 characters).
  char expected[128];
  std::snprintf(expected, sizeof(expected), "%.*g", 80, 1.0 / 3.0);
  EXPECT_EQ(FormatDouble(1.0 / 3.0, 80), std::string(expected).substr(0, 63));
}

TEST(CsvTest, QuotedFieldsRoundTrip) {
  const std::vector<std::string> fields = {"plain", "a, b", "say \"hi\"", "two\nlines",
                                           " padded ", "", "\ttab"};
  CsvWriter writer;
  writer.Row({"c1", "c2", "c3", "c4", "c5", "c6", "c7"});
  writer.Row(fields);
  const CsvTable table = CsvTable::Parse(writer.Text(), "t.csv");
  ASSERT_EQ(table.Rows(), 1u);
  EXPECT_EQ(table.Row(0), fields);
  EXPECT_EQ(table.Line(0), 2);
}

TEST(CsvTest, BlanksCarriageReturnsAndBlankLines) {
  const CsvTable table =
      CsvTable::Parse("time_s , x\r\n\r\n 1, 2.5 \r\n  \n\"3\" ,\"a\nb\"\n5,6\n", "t.csv");
  EXPECT_EQ(table.columns(), (std::vector<std::string>{"time_s", "x"}));
  ASSERT_EQ(table.Rows(), 3u);
  EXPECT_EQ(table.Numbers("time_s"), (std::vector<double>{1, 3, 5}));
  EXPECT_EQ(table.Text(1, 1), "a\nb");
  // Each row's line is the one it starts on, quoted line breaks counted.
  EXPECT_EQ(table.Line(0), 3);
  EXPECT_EQ(table.Line(1), 5);
  EXPECT_EQ(table.Line(2), 7);
  EXPECT_EQ(table.Number(0, 1), 2.5);
}

TEST(CsvTest, WriterFormatsNumbersAtItsDigits) {
  CsvWriter writer(4);
  writer.Add("x").Add(kPi).AddInteger(-3).EndRow();
  EXPECT_EQ(writer.Text(), "x,3.142,-3\n");
}

TEST(CsvTest, ErrorsNameTheSourceLineAndColumn) {
  EXPECT_EQ(InputErrorOf([] { CsvTable::Parse("", "t.csv"); }),
            "t.csv: empty file (no header row)");
  EXPECT_EQ(InputErrorOf([] { CsvTable::Parse("a,b\n1,2\n3\n", "t.csv"); }),
            "t.csv:3: expected 2 cells, got 1");
  EXPECT_EQ(InputErrorOf([] { CsvTable::Parse("a,b\n1,\"2\n", "t.csv"); }),
            "t.csv:2: unterminated quoted cell");
  const CsvTable table = CsvTable::Parse("a,b\n1,x\ninf,2\n", "t.csv");
  EXPECT_EQ(InputErrorOf([&] { table.Column("c"); }), "t.csv: no column 'c' (columns: a, b)");
  EXPECT_EQ(InputErrorOf([&] { table.Numbers("b"); }), "t.csv:2: column b: 'x' is not a number");
  EXPECT_EQ(InputErrorOf([&] { table.FiniteNumbers("a"); }),
            "t.csv:3: column a: value is not finite (inf)");
  try {
    table.Numbers("b");
  } catch (const InputError& error) {
    EXPECT_EQ(error.problem(), InputProblem::kBadValue);
    EXPECT_EQ(error.where().file, "t.csv");
    EXPECT_EQ(error.where().line, 2u);
    EXPECT_EQ(error.key(), "b");
    EXPECT_EQ(error.message(), "column b: 'x' is not a number");
  }
}

TEST(InputErrorTest, IsOneLineWithItsLocation) {
  const InputError error(InputProblem::kSyntax, {"f.toml", 3, 7}, "", "bad\nthing");
  EXPECT_STREQ(error.what(), "f.toml:3:7: bad thing");
  EXPECT_STREQ(InputError(InputProblem::kMissing, {"f.toml"}, "model", "x").what(), "f.toml: x");
}

}  // namespace
}  // namespace ipmc
