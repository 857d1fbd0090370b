// The text helpers of `vox info` (tools/cmds/info_text.h): rounding, units,
// tables that fit 80 columns.
#include <gtest/gtest.h>

#include <sstream>

#include "tools/cmds/info_text.h"

using namespace voxcli::infotext;

TEST(InfoText, CountsBytesAndPercentages) {
  EXPECT_EQ(count(0), "0");
  EXPECT_EQ(count(999), "999");
  EXPECT_EQ(count(1000), "1,000");
  EXPECT_EQ(count(16777216), "16,777,216");
  EXPECT_EQ(bytes(999), "999 B");
  EXPECT_EQ(bytes(1000), "1 kB");
  EXPECT_EQ(bytes(51800), "51.8 kB");
  EXPECT_EQ(bytes(1536000), "1.54 MB");
  EXPECT_EQ(bytes(999600), "1 MB") << "999.6 kB rounds up a unit";
  EXPECT_EQ(percent(0), "0%");
  EXPECT_EQ(percent(1), "100%");
  EXPECT_EQ(percent(5.0 / 24), "20.8%");
  EXPECT_EQ(percent(0.0592), "5.92%");
  EXPECT_EQ(percent(1e-6), "<0.01%") << "never rounded to 0% unless it is 0";
  EXPECT_EQ(percent(0.999999), ">99.99%") << "never rounded to 100% unless it is all";
  EXPECT_EQ(percent(0.9996), "99.9%");
}

TEST(InfoText, NounsAgreeWithTheirCount) {
  EXPECT_EQ(countOf(1, "voxel", "voxels"), "1 voxel");
  EXPECT_EQ(countOf(0, "voxel", "voxels"), "0 voxels");
  EXPECT_EQ(countOf(1234, "voxel", "voxels"), "1,234 voxels");
  EXPECT_EQ(measured(1.0, 6, "world unit", "world units"), "1 world unit");
  EXPECT_EQ(measured(1.0000000001, 6, "world unit", "world units"), "1 world unit") << "as printed";
  EXPECT_EQ(measured(0.8, 6, "world unit", "world units"), "0.8 world units");
}

TEST(InfoText, RealsDropTrailingZeros) {
  EXPECT_EQ(real(0.1), "0.1");
  EXPECT_EQ(real(0.1 + 0.2), "0.3");
  EXPECT_EQ(real(25.6), "25.6");
  EXPECT_EQ(real(-12.8), "-12.8");
  EXPECT_EQ(real(2), "2");
  EXPECT_EQ(real(0.0001234), "0.0001234");
  EXPECT_EQ(real(1234567), "1234567");
  EXPECT_EQ(real(1.23456789e12), "1.235e+12");
  EXPECT_EQ(triple(-64, 0, -64), "(-64, 0, -64)");
  EXPECT_EQ(compact(31791), "31,791");
  EXPECT_EQ(compact(1540000), "1.54 M");
  EXPECT_EQ(hexColor(150, 150, 150), "#969696");
}

TEST(InfoText, TablesAlignAndFitEightyColumns) {
  Table t({{"id", true}, {"name", false, true}, {"voxels", true}});
  t.row({"1", "Grass", "1,234"});
  t.row({"12", "a very long material name that would never fit in any sensible column at all, really", "5"});
  const std::string s = t.str();
  std::istringstream in(s);
  std::string l;
  std::vector<std::string> lines;
  while (std::getline(in, l)) lines.push_back(l);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].substr(0, 10), "    id  na");
  EXPECT_EQ(lines[1].substr(0, 14), "     1  Grass ");
  for (const std::string& x : lines) {
    size_t cols = 0;
    for (unsigned char c : x) cols += (c & 0xc0) != 0x80;
    EXPECT_LE(cols, kWidth) << x;
  }
  EXPECT_NE(lines[2].find("…"), std::string::npos) << "the long name is cut with an ellipsis";
  // Numbers stay right-aligned: every row ends at the same column.
  EXPECT_EQ(lines[1].substr(lines[1].size() - 5), "1,234");
  EXPECT_EQ(fit("abcdef", 4), "abc…");
  EXPECT_EQ(fit("abc", 4), "abc");
  EXPECT_EQ(line("dims", "4 x 3 x 2"), "  dims          4 x 3 x 2\n");
}

namespace {
std::vector<std::string> linesOf(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}
}  // namespace

TEST(InfoText, WidthsAreDisplayColumns) {
  EXPECT_EQ(columns("Stone"), 5u);
  EXPECT_EQ(columns("石头"), 4u) << "CJK ideographs take two columns";
  EXPECT_EQ(columns("ｓｔ"), 4u) << "fullwidth forms too";
  EXPECT_EQ(columns("e\u0301"), 1u) << "a combining mark takes none";
  EXPECT_EQ(columns("…"), 1u);
  // fit cuts by columns, never inside a character, ellipsis included.
  EXPECT_EQ(fit("石头石头", 5), "石头…");
  EXPECT_EQ(fit("石头石头", 6), "石头…") << "a wide character that would pass the width stays out";
  EXPECT_EQ(fit("ae\u0301bcd", 3), "ae\u0301…") << "a mark stays with its letter";
}

TEST(InfoText, TablesAlignWideNames) {
  Table t({{"id", true}, {"name", false, true}, {"colour", false}, {"voxels", true}});
  t.row({"1", "石头", "#9499a3", "12"});
  t.row({"2", "Stone", "#9499a3", "3"});
  t.row({"3", "草地草地草地", "#57ad5c", "1,234"});
  t.row({"4", "Cafe\u0301", "#57ad5c", "5"});
  const std::vector<std::string> lines = linesOf(t.str());
  ASSERT_EQ(lines.size(), 5u);
  // Every row puts the colour at the same display column, and ends at the same one.
  const size_t at = columns(lines[1].substr(0, lines[1].find('#')));
  for (size_t i = 1; i < lines.size(); ++i) {
    EXPECT_EQ(columns(lines[i].substr(0, lines[i].find('#'))), at) << lines[i];
    EXPECT_EQ(columns(lines[i]), columns(lines[0])) << lines[i];
  }
  // Shrunk to fit 80 columns: cut by display width.
  Table narrow({{"id", true}, {"name", false, true}, {"note", false}});
  narrow.row({"1", std::string(60 / 2, ' ') + "名前名前名前名前名前名前名前名前名前名前名前名前名前", std::string(20, 'x')});
  for (const std::string& l : linesOf(narrow.str())) EXPECT_LE(columns(l), kWidth) << l;
}

TEST(InfoText, LongValuesWrapWithinEightyColumns) {
  const std::string value = "'free' (Tree_int32_5_4_3, 1,234 leaves of 8^3): vox fuse's free-space counts, read back by vox "
                            "fuse -i (docs/fuse.md)";
  const std::vector<std::string> lines = linesOf(line("free grid", value));
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].substr(0, 16), "  free grid     ");
  EXPECT_EQ(lines[1].substr(0, 16), std::string(16, ' ')) << "continued at the value's column";
  for (const std::string& l : lines) EXPECT_LE(columns(l), kWidth) << l;
  std::string joined = lines[0].substr(16) + " " + lines[1].substr(16);
  EXPECT_EQ(joined, value) << "broken at a space, nothing lost";
  // Wide characters count two; a word longer than a line is split, never inside a character.
  const std::string wide = std::string("名前") + std::string(40, 'a') + " " + std::string(35, 'b') + "草" +
                           std::string(100, 'c');
  const std::vector<std::string> w = linesOf(line("name", wide));
  std::string back;
  for (const std::string& l : w) {
    EXPECT_LE(columns(l), kWidth) << l;
    back += l.substr(16);
  }
  EXPECT_EQ(back, std::string("名前") + std::string(40, 'a') + std::string(35, 'b') + "草" + std::string(100, 'c'));
  EXPECT_EQ(line("dims", "4 x 3 x 2"), "  dims          4 x 3 x 2\n") << "short values are one line, as before";
}

TEST(InfoText, HeadingsPutALongPathOnALineOfItsOwn) {
  EXPECT_EQ(heading("out/h.vdb", "voxbake scene"), "out/h.vdb: voxbake scene\n");
  const std::string path = "/very/long/path/to/a/scene/bake/directory/of/some/project/renders/front.canonical.png";
  const std::string what = "canonical render, 1920 x 1080 x 4 uint16";
  const std::vector<std::string> lines = linesOf(heading(path, what));
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], path + ":") << "the path whole, never cut";
  EXPECT_EQ(lines[1], "  " + what);
  // A description wider than a line wraps at spaces, indented.
  const std::vector<std::string> wrapped = linesOf(heading(path, what + " " + what + " " + what));
  ASSERT_EQ(wrapped.size(), 3u);
  for (size_t i = 1; i < wrapped.size(); ++i) {
    EXPECT_EQ(wrapped[i].substr(0, 2), "  ");
    EXPECT_LE(columns(wrapped[i]), kWidth) << wrapped[i];
  }
  // Exactly 80 columns still fits on one line.
  const std::string eighty = std::string(80 - 2 - what.size(), 'p');
  EXPECT_EQ(heading(eighty, what), eighty + ": " + what + "\n");
}
