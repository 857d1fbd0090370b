// How many terminal columns UTF-8 text takes, for text laid out in columns
// (`vox info`'s tables and key-value lines). East Asian Wide and Fullwidth
// characters (CJK ideographs, kana, Hangul syllables, fullwidth forms, most
// emoji) take two columns; combining marks (Mn, Me), format characters (Cf,
// except the soft hyphen) and Hangul medial vowels and final consonants take
// none; everything else one. The tables follow Unicode 14's
// EastAsianWidth.txt and general categories (what wcwidth and Python's
// unicodedata give); a byte that is not part of valid UTF-8 counts one column.
// Thread-safety: pure functions.
#pragma once

#include <cstddef>
#include <string_view>

namespace vox {

/// Columns of one code point: 0, 1 or 2 (see above).
int codePointWidth(char32_t cp);

/// Columns of UTF-8 text.
size_t displayWidth(std::string_view utf8);

/// The length in bytes of the longest prefix of `utf8` that takes at most
/// `columns` columns: it never ends inside a code point, and never separates
/// a character from the combining marks that follow it.
size_t prefixFitting(std::string_view utf8, size_t columns);

}  // namespace vox
