// parseDouble and parseInt64 (formats/core/text_numbers.h) against
// std::from_chars: the same end pointer, error and value bits for every
// string, on the numbers exporters write (printf's %f, %g, %e of random
// doubles at every precision), on digit strings around the shortcut's limits
// (19 significant digits, 2^53, 22 fraction digits) and on random strings
// over the characters numbers are made of, with text after them.
#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "formats/core/text_numbers.h"

using namespace vox;

namespace {

size_t checkedDoubles = 0, checkedInts = 0;

void sameAsFromChars(const std::string& s) {
  const char* b = s.data();
  const char* e = b + s.size();
  double want = 12345.0, got = 12345.0;  // untouched on errors: both must leave it
  const auto w = std::from_chars(b, e, want);
  const auto g = parseDouble(b, e, got);
  ASSERT_EQ(g.ptr - b, w.ptr - b) << "'" << s << "'";
  ASSERT_EQ(int(g.ec), int(w.ec)) << "'" << s << "'";
  ASSERT_EQ(std::bit_cast<uint64_t>(got), std::bit_cast<uint64_t>(want)) << "'" << s << "': " << got << " vs " << want;
  int64_t wantI = 777, gotI = 777;
  const auto wi = std::from_chars(b, e, wantI);
  const auto gi = parseInt64(b, e, gotI);
  ASSERT_EQ(gi.ptr - b, wi.ptr - b) << "'" << s << "'";
  ASSERT_EQ(int(gi.ec), int(wi.ec)) << "'" << s << "'";
  ASSERT_EQ(gotI, wantI) << "'" << s << "'";
  ++checkedDoubles, ++checkedInts;
}

}  // namespace

TEST(TextNumbers, EdgeCases) {
  for (const char* s :
       {"", "-", "+1", ".", "-.", ".5", "-.5", "5.", "-5.", "0", "-0", "-0.0", "00012", "0.000", "1e5", "1E-5", "1e",
        "1e+", "2.5e3x", "inf", "-inf", "nan", "infinity", "NaN", "0x1p3", " 1", "1 ", "1,5", "1..2", "1.2.3", "--1",
        "-0.0378297", "0.1", "0.2", "0.3", "9007199254740992", "9007199254740993", "9007199254740991.5",
        "1234567890123456789", "12345678901234567890", "0.1234567890123456789", "0.12345678901234567890",
        "0.0000000000000000000001", "0.00000000000000000000001", "1.0000000000000000000000", "999999999999999999",
        "9999999999999999999", "9223372036854775807", "9223372036854775808", "-9223372036854775808",
        "-9223372036854775809", "123456789012345678", "-123456789012345678", "1/2/3", "7//9", "3\r\n", "4\t5"})
    sameAsFromChars(s);
}

// The readers' entry point: one optional '+' before what parseDouble reads.
TEST(TextNumbers, OneLeadingPlusIsTakenAndNothingMore) {
  for (const std::string s : {"1", "0.25", "1e5", "inf", ".5", "9007199254740993", "7 8", "x", "", "e5"}) {
    SCOPED_TRACE("'" + s + "'");
    const std::string plus = "+" + s;
    double want = 1.5, got = 1.5;
    const auto w = parseDouble(s.data(), s.data() + s.size(), want);
    const auto g = parseDoubleAllowingPlus(plus.data(), plus.data() + plus.size(), got);
    EXPECT_EQ(g.ptr - plus.data(), w.ptr - s.data() + 1) << "on failure too: past the '+'";
    EXPECT_EQ(int(g.ec), int(w.ec));
    EXPECT_EQ(std::bit_cast<uint64_t>(got), std::bit_cast<uint64_t>(want));
    double unsignedGot = 1.5;  // without a '+' it is parseDouble itself
    const auto u = parseDoubleAllowingPlus(s.data(), s.data() + s.size(), unsignedGot);
    EXPECT_EQ(u.ptr, w.ptr);
    EXPECT_EQ(std::bit_cast<uint64_t>(unsignedGot), std::bit_cast<uint64_t>(want));
  }
  for (const std::string s : {"+-1", "++1", "+ 1", "+", "-+1"}) {
    double v = 1.5;
    const auto r = parseDoubleAllowingPlus(s.data(), s.data() + s.size(), v);
    EXPECT_NE(int(r.ec), 0) << "'" << s << "' is not a number";
    EXPECT_EQ(v, 1.5) << "'" << s << "': the value is left alone";
  }
  double v = 0;
  const std::string minus = "-2.5";
  EXPECT_EQ(int(parseDoubleAllowingPlus(minus.data(), minus.data() + minus.size(), v).ec), 0);
  EXPECT_EQ(v, -2.5);
}

TEST(TextNumbers, PrintedDoubles) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  char buf[64];
  for (int k = 0; k < 300000; ++k) {
    const double scale = std::ldexp(1.0, int(rng() % 80) - 40);
    const double v = unit(rng) * scale;
    const int precision = int(rng() % 20);
    switch (k % 4) {
      case 0: std::snprintf(buf, sizeof buf, "%.*f", precision, v); break;
      case 1: std::snprintf(buf, sizeof buf, "%.*g", precision + 1, v); break;
      case 2: std::snprintf(buf, sizeof buf, "%.*e", precision, v); break;
      default: std::snprintf(buf, sizeof buf, "%.17g", v); break;
    }
    sameAsFromChars(std::string(buf) + (k % 3 == 0 ? " 1.5" : k % 3 == 1 ? "/2" : ""));
    if (HasFatalFailure()) return;
  }
}

TEST(TextNumbers, DigitStringsAroundTheLimits) {
  // Up to 25 digits with a point anywhere: the 19-digit, 2^53 and 22-fraction-digit limits.
  std::mt19937_64 rng(5);
  for (int k = 0; k < 400000; ++k) {
    const int n = 1 + int(rng() % 25);
    std::string s = rng() % 2 ? "-" : "";
    const int point = int(rng() % (n + 2)) - 1;  // -1: none
    const bool zeros = rng() % 4 == 0;           // runs of leading zeros
    for (int i = 0; i < n; ++i) {
      if (i == point) s += '.';
      s += char('0' + (zeros && i < n / 2 ? 0 : int(rng() % 10)));
    }
    if (point == n) s += '.';
    sameAsFromChars(s);
    if (HasFatalFailure()) return;
  }
}

TEST(TextNumbers, RandomStrings) {
  std::mt19937_64 rng(7);
  const size_t before = checkedDoubles;
  const char alphabet[] = "0123456789.-+eE niaf/x";
  for (int k = 0; k < 1000000; ++k) {
    std::string s;
    const int n = int(rng() % 14);
    for (int i = 0; i < n; ++i) s += alphabet[rng() % (sizeof alphabet - 1)];
    sameAsFromChars(s);
    if (HasFatalFailure()) return;
  }
  EXPECT_EQ(checkedDoubles - before, size_t(1000000)) << "every string compared";
}
