// Display columns of UTF-8 text (libvox/core/display_width.h), against
// Unicode's East Asian Width and general categories.
#include <gtest/gtest.h>

#include "libvox/core/display_width.h"

using vox::codePointWidth;
using vox::displayWidth;
using vox::prefixFitting;

TEST(DisplayWidth, CodePoints) {
  EXPECT_EQ(codePointWidth(U'a'), 1);
  EXPECT_EQ(codePointWidth(U'é'), 1);
  EXPECT_EQ(codePointWidth(U'\u0301'), 0) << "combining acute accent (Mn)";
  EXPECT_EQ(codePointWidth(U'\u20DD'), 0) << "combining enclosing circle (Me)";
  EXPECT_EQ(codePointWidth(U'\u200B'), 0) << "zero width space (Cf)";
  EXPECT_EQ(codePointWidth(U'\u00AD'), 1) << "the soft hyphen is shown";
  EXPECT_EQ(codePointWidth(U'\u1100'), 2) << "Hangul choseong";
  EXPECT_EQ(codePointWidth(U'\u1160'), 0) << "Hangul jungseong joins the syllable";
  EXPECT_EQ(codePointWidth(U'\u4E00'), 2);
  EXPECT_EQ(codePointWidth(U'\u3042'), 2) << "hiragana";
  EXPECT_EQ(codePointWidth(U'\uAC00'), 2) << "Hangul syllable";
  EXPECT_EQ(codePointWidth(U'\uFF21'), 2) << "fullwidth A";
  EXPECT_EQ(codePointWidth(U'\uFF61'), 1) << "halfwidth ideographic full stop";
  EXPECT_EQ(codePointWidth(U'\U0001F600'), 2) << "emoji";
  EXPECT_EQ(codePointWidth(U'\U00020000'), 2) << "CJK extension B";
  EXPECT_EQ(codePointWidth(U'\u2026'), 1) << "the ellipsis vox info writes";
}

TEST(DisplayWidth, Text) {
  EXPECT_EQ(displayWidth(""), 0u);
  EXPECT_EQ(displayWidth("Stone"), 5u);
  EXPECT_EQ(displayWidth("石头 stone"), 10u);
  EXPECT_EQ(displayWidth("Cafe\u0301"), 4u);
  EXPECT_EQ(displayWidth("\xff\xfe"), 2u) << "bytes outside UTF-8 count one each";
  EXPECT_EQ(displayWidth("\xe4\xb8"), 2u) << "a cut sequence: one per byte";
}

TEST(DisplayWidth, Prefixes) {
  const std::string s = "石头ab";
  EXPECT_EQ(prefixFitting(s, 0), 0u);
  EXPECT_EQ(prefixFitting(s, 1), 0u) << "half a wide character does not fit";
  EXPECT_EQ(prefixFitting(s, 2), 3u);
  EXPECT_EQ(prefixFitting(s, 3), 3u);
  EXPECT_EQ(prefixFitting(s, 5), 7u);
  EXPECT_EQ(prefixFitting(s, 100), s.size());
  EXPECT_EQ(prefixFitting("e\u0301x", 1), 3u) << "the mark stays with its letter";
}
