// How `vox info` writes for people: rounded numbers with their units, and
// aligned tables that fit an 80-column terminal. The --json output never goes
// through here (it keeps every digit).
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>
#include <vector>

namespace voxcli::infotext {

/// The terminal width the text output is laid out for. Widths are display
/// columns (libvox/core/display_width.h): a CJK character takes two, a
/// combining mark none.
inline constexpr size_t kWidth = 80;
/// The column where line()'s values start (two spaces, a 14-column key).
inline constexpr size_t kValueColumn = 16;

/// Display columns of UTF-8 text.
size_t columns(const std::string& s);

/// 1234567 -> "1,234,567".
std::string count(uint64_t n);
/// count(n) and its noun: "1 voxel", "1,234 voxels".
std::string countOf(uint64_t n, const std::string& one, const std::string& many);
/// real(x, significant) and its unit: "1 world unit", "0.8 world units".
std::string measured(double x, int significant, const std::string& one, const std::string& many);
/// Bytes in decimal units: "512 B", "12.3 kB", "4.56 MB", "1.20 GB".
std::string bytes(uint64_t n);
/// A fraction as a percentage, "0%", "<0.01%", "12.3%", "99.99%", "100%"
/// (never rounded to 0% or 100% unless it is exactly that).
std::string percent(double fraction);
/// A real number with `significant` digits, no exponent for ordinary sizes,
/// trailing zeros dropped: 0.100000001 -> "0.1", 25.6 -> "25.6".
std::string real(double x, int significant = 4);
/// "(x, y, z)" of reals.
std::string triple(double x, double y, double z, int significant = 4);
/// Large integers in engineering form: 1234 -> "1234", 12345678 -> "12.3 M".
std::string compact(uint64_t n);
/// "#rrggbb".
std::string hexColor(int r, int g, int b);
/// Cuts `s` to `width` display columns, ending in "…" when cut.
std::string fit(const std::string& s, size_t width);

/// A key-value line: two spaces, the key padded to 14 columns, the value.
/// A value wider than the rest of the line is wrapped at spaces onto further
/// lines indented to the value's column (a word wider than a line is split),
/// so every line fits kWidth.
std::string line(const std::string& key, const std::string& value);
/// `text` in lines of at most `firstWidth` columns (the first) and `width`
/// (the others), broken at spaces; a word wider than its line is split.
std::vector<std::string> wrapWords(const std::string& text, size_t firstWidth, size_t width);

/// The first line of a file's description, "PATH: WHAT". When that is wider
/// than kWidth, the path stands alone ("PATH:") and WHAT follows on lines of
/// its own, indented by two and wrapped at spaces.
std::string heading(const std::string& path, const std::string& what);

/// A part of a region bake, from its `region` JSON (formats/scene/scene_meta.h):
/// "tile I of N, box (u, v, w) .. (u, v, w), world KEY12…" (or "empty tile").
std::string regionText(const nlohmann::json& region);

/// A table: columns left- or right-aligned, widths from the content, two
/// spaces between columns, indented by four. Columns marked `shrink` are cut
/// (with "…") so that each line fits kWidth.
class Table {
 public:
  struct Column {
    std::string header;
    bool right = false;   // numbers: right-aligned
    bool shrink = false;  // names: cut to fit the width
  };
  explicit Table(std::vector<Column> columns) : columns_(std::move(columns)) {}
  void row(std::vector<std::string> cells) { rows_.push_back(std::move(cells)); }
  size_t rows() const { return rows_.size(); }
  std::string str() const;

 private:
  std::vector<Column> columns_;
  std::vector<std::vector<std::string>> rows_;
};

}  // namespace voxcli::infotext
