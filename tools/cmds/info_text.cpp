#include "tools/cmds/info_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "libvox/core/display_width.h"

namespace voxcli::infotext {

size_t columns(const std::string& s) { return vox::displayWidth(s); }

namespace {

std::string pad(const std::string& s, size_t width, bool right) {
  const size_t w = columns(s);
  if (w >= width) return s;
  return right ? std::string(width - w, ' ') + s : s + std::string(width - w, ' ');
}

}  // namespace

std::string count(uint64_t n) {
  std::string digits = std::to_string(n), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string bytes(uint64_t n) {
  if (n < 1000) return std::to_string(n) + " B";
  static const char* const units[] = {"kB", "MB", "GB", "TB"};
  double v = double(n);
  int u = -1;
  while (v >= 999.5 && u < 3) v /= 1000.0, ++u;
  return real(v, 3) + " " + units[u];
}

std::string percent(double f) {
  if (!std::isfinite(f)) return "-";
  const double p = 100.0 * f;
  if (p == 0) return "0%";
  if (p == 100) return "100%";
  char buf[32];
  if (p < 0.01) return "<0.01%";
  if (p > 99.99 && p < 100) return ">99.99%";
  if (p < 10) std::snprintf(buf, sizeof buf, "%.2f%%", p);
  else std::snprintf(buf, sizeof buf, "%.1f%%", p);
  // 99.96 would print "100.0%": keep the "not all" visible.
  std::string s = buf;
  if (s == "100.0%" && p < 100) s = "99.9%";
  return s;
}

std::string countOf(uint64_t n, const std::string& one, const std::string& many) {
  return count(n) + " " + (n == 1 ? one : many);
}

std::string measured(double x, int significant, const std::string& one, const std::string& many) {
  const std::string text = real(x, significant);
  return text + " " + (text == "1" ? one : many);
}

std::string real(double x, int significant) {
  if (!std::isfinite(x)) return std::isnan(x) ? "nan" : (x > 0 ? "inf" : "-inf");
  if (x == 0) return "0";
  char buf[64];
  const double a = std::fabs(x);
  if (a >= 1e-4 && a < 1e9) {
    // Fixed notation with `significant` digits, trailing zeros dropped.
    const int intDigits = a >= 1 ? int(std::floor(std::log10(a))) + 1 : 0;
    int decimals = std::max(0, significant - intDigits);
    if (a < 1) decimals = significant - int(std::floor(std::log10(a))) - 1;
    std::snprintf(buf, sizeof buf, "%.*f", decimals, x);
    std::string s = buf;
    if (s.find('.') != std::string::npos) {
      while (s.back() == '0') s.pop_back();
      if (s.back() == '.') s.pop_back();
    }
    return s;
  }
  std::snprintf(buf, sizeof buf, "%.*g", significant, x);
  return buf;
}

std::string triple(double x, double y, double z, int significant) {
  return "(" + real(x, significant) + ", " + real(y, significant) + ", " + real(z, significant) + ")";
}

std::string compact(uint64_t n) {
  if (n < 100000) return count(n);
  static const char* const units[] = {"k", "M", "G", "T", "P"};
  double v = double(n);
  int u = -1;
  while (v >= 999.5 && u < 4) v /= 1000.0, ++u;
  return real(v, 3) + " " + units[u];
}

std::string hexColor(int r, int g, int b) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", r & 255, g & 255, b & 255);
  return buf;
}

std::string fit(const std::string& s, size_t width) {
  if (columns(s) <= width) return s;
  if (width == 0) return "";
  return s.substr(0, vox::prefixFitting(s, width - 1)) + "…";
}

std::vector<std::string> wrapWords(const std::string& text, size_t firstWidth, size_t width) {
  std::vector<std::string> lines(1);
  size_t used = 0;
  auto room = [&] { return lines.size() == 1 ? firstWidth : width; };
  size_t pos = 0;
  while (pos <= text.size()) {
    const size_t space = std::min(text.find(' ', pos), text.size());
    std::string word = text.substr(pos, space - pos);
    pos = space + 1;
    size_t w = columns(word);
    if (used > 0 && used + 1 + w > room()) lines.emplace_back(), used = 0;
    if (used > 0) lines.back() += ' ', ++used;
    // A word wider than a whole line: what fits, the rest on the next lines.
    while (used + w > room()) {
      // (used is 0 or the first line's short lead: the word did not fit after other text.)
      size_t cut = vox::prefixFitting(word, room() > used ? room() - used : 0);
      if (cut == 0) cut = vox::prefixFitting(word, 2);  // a line narrower than one character: it goes whole
      lines.back() += word.substr(0, cut);
      word = word.substr(cut);
      w = columns(word);
      lines.emplace_back(), used = 0;
    }
    lines.back() += word;
    used += w;
  }
  return lines;
}

std::string line(const std::string& key, const std::string& value) {
  const std::string lead = "  " + pad(key, kValueColumn - 2, false);
  const size_t leadColumns = columns(lead);
  const std::vector<std::string> lines =
      wrapWords(value, leadColumns < kWidth ? kWidth - leadColumns : 1, kWidth - kValueColumn);
  std::string out;
  for (size_t i = 0; i < lines.size(); ++i) out += (i ? std::string(kValueColumn, ' ') : lead) + lines[i] + "\n";
  return out;
}

std::string heading(const std::string& path, const std::string& what) {
  if (columns(path) + 2 + columns(what) <= kWidth) return path + ": " + what + "\n";
  // The path whole on its own line (a path cut or broken is no use to copy),
  // what the file is below it, wrapped at spaces.
  std::string out = path + ":\n";
  for (const std::string& l : wrapWords(what, kWidth - 2, kWidth - 2)) out += "  " + l + "\n";
  return out;
}

std::string regionText(const nlohmann::json& r) {
  std::string s = "tile " + r["index"].dump() + " of " + r["count"].dump() + ", ";
  const nlohmann::json& b = r["box"];
  if (b.is_null())
    s += "empty tile";
  else
    s += "box (" + b[0].dump() + ", " + b[1].dump() + ", " + b[2].dump() + ") .. (" + b[3].dump() + ", " + b[4].dump() +
         ", " + b[5].dump() + ")";
  return s + ", world " + r["world_key"].get<std::string>().substr(0, 12);
}

std::string Table::str() const {
  const size_t n = columns_.size();
  std::vector<size_t> width(n, 0);
  for (size_t c = 0; c < n; ++c) width[c] = columns(columns_[c].header);
  for (const auto& r : rows_)
    for (size_t c = 0; c < n && c < r.size(); ++c) width[c] = std::max(width[c], columns(r[c]));
  // Shrink the shrinkable columns, widest first, until a line fits.
  const size_t indent = 4;
  auto total = [&] {
    size_t t = indent;
    for (size_t c = 0; c < n; ++c) t += width[c] + (c ? 2 : 0);
    return t;
  };
  while (total() > kWidth) {
    size_t best = n;
    for (size_t c = 0; c < n; ++c)
      if (columns_[c].shrink && width[c] > std::max<size_t>(6, columns(columns_[c].header)) &&
          (best == n || width[c] > width[best]))
        best = c;
    if (best == n) break;  // nothing left to cut: the line stays long
    --width[best];
  }
  std::string out;
  auto emit = [&](const std::vector<std::string>& cells) {
    std::string l(indent, ' ');
    for (size_t c = 0; c < n; ++c) {
      const std::string cell = c < cells.size() ? fit(cells[c], width[c]) : "";
      if (c) l += "  ";
      l += c + 1 == n && !columns_[c].right ? cell : pad(cell, width[c], columns_[c].right);
    }
    out += l + "\n";
  };
  std::vector<std::string> header;
  for (const auto& c : columns_) header.push_back(c.header);
  emit(header);
  for (const auto& r : rows_) emit(r);
  return out;
}

}  // namespace voxcli::infotext
