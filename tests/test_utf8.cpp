// libvox/core/utf8.h: validation against nlohmann::json's own UTF-8 check
// (what vox's JSON writers need), and Windows-1252 transcoding.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <random>
#include <string>

#include "libvox/core/utf8.h"

using vox::isValidUtf8;
using vox::utf8FromLegacy;

namespace {
bool jsonAccepts(const std::string& s) {
  try {
    (void)nlohmann::json(s).dump();
    return true;
  } catch (const nlohmann::json::type_error&) {
    return false;
  }
}
}  // namespace

TEST(Utf8, ValidationAgreesWithTheJsonWriter) {
  for (const std::string s : {"", "plain", "Mat\xc3\xa9riau", "\xe2\x82\xac", "\xf0\x9f\x99\x82", "Mat\xe9riau", "\xc0\xaf",
                              "\xe0\x80\xaf", "\xed\xa0\x80", "\xf4\x90\x80\x80", "\xc3", "\xe2\x82", "\xff", "\x80"})
    EXPECT_EQ(isValidUtf8(s), jsonAccepts(s)) << "'" << s << "'";
  // Random byte strings, short enough that many are valid.
  std::mt19937 rng(7);
  for (int n = 0; n < 200000; ++n) {
    std::string s(size_t(rng() % 6), '\0');
    for (char& ch : s) ch = char(rng() % 4 == 0 ? rng() % 128 : 0x80 + rng() % 128);
    ASSERT_EQ(isValidUtf8(s), jsonAccepts(s)) << n;
    const std::string fixed = utf8FromLegacy(s);
    ASSERT_TRUE(jsonAccepts(fixed)) << n;
    if (isValidUtf8(s)) {
      ASSERT_EQ(fixed, s) << "valid text is kept byte for byte";
    }
  }
}

TEST(Utf8, LegacyBytesReadAsWindows1252) {
  EXPECT_EQ(utf8FromLegacy("Mat\xe9riau"), "Mat\xc3\xa9riau");                 // é (Latin-1 range)
  EXPECT_EQ(utf8FromLegacy("\x80 \x9f"), "\xe2\x82\xac \xc5\xb8");             // € and Ÿ (0x80-0x9F)
  EXPECT_EQ(utf8FromLegacy("a\x81z"), "a\xef\xbf\xbdz");                        // undefined in 1252: U+FFFD
  EXPECT_EQ(utf8FromLegacy("caf\xc3\xa9 \xe9"), "caf\xc3\xa9 \xc3\xa9");        // valid sequences kept beside it
  EXPECT_EQ(utf8FromLegacy("\xc3"), "\xc3\x83");                                // a cut-off sequence is 1252 too
}
