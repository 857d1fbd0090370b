#include "libvox/core/color_quantize.h"

#include <algorithm>
#include <cmath>

namespace vox {

namespace {

struct Entry {
  uint32_t rgb;
  uint64_t count;
  int channel(int c) const { return int(rgb >> (16 - 8 * c)) & 255; }
};

// A box of entries [begin, end) of the shared entry list.
struct Box {
  size_t begin, end;
  int widestChannel = 0, range = 0;
};

void measure(const std::vector<Entry>& e, Box& b) {
  b.range = -1;
  for (int c = 0; c < 3; ++c) {
    int lo = 255, hi = 0;
    for (size_t i = b.begin; i < b.end; ++i) lo = std::min(lo, e[i].channel(c)), hi = std::max(hi, e[i].channel(c));
    if (hi - lo > b.range) b.range = hi - lo, b.widestChannel = c;
  }
}

uint32_t distance2(uint32_t a, Rgb8 b) {
  const int dr = int(a >> 16 & 255) - b.r, dg = int(a >> 8 & 255) - b.g, db = int(a & 255) - b.b;
  return uint32_t(dr * dr + dg * dg + db * db);
}

}  // namespace

QuantizedPalette quantizeColors(const ColorHistogram& histogram, size_t maxColors) {
  std::vector<Entry> entries;
  entries.reserve(histogram.size());
  for (const auto& [rgb, count] : histogram) entries.push_back({rgb, count});
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.rgb < b.rgb; });
  QuantizedPalette p;
  if (entries.size() <= maxColors) {
    for (const Entry& e : entries) {
      p.slotOf[e.rgb] = uint32_t(p.colors.size());
      p.colors.push_back(unpackRgb(e.rgb));
    }
    return p;
  }
  p.exact = false;
  std::vector<Box> boxes{{0, entries.size()}};
  measure(entries, boxes[0]);
  while (boxes.size() < maxColors) {
    size_t pick = boxes.size();
    for (size_t i = 0; i < boxes.size(); ++i)
      if (boxes[i].end - boxes[i].begin > 1 && (pick == boxes.size() || boxes[i].range > boxes[pick].range)) pick = i;
    if (pick == boxes.size()) break;  // every box is a single colour
    Box& b = boxes[pick];
    const int c = b.widestChannel;
    std::sort(entries.begin() + long(b.begin), entries.begin() + long(b.end), [c](const Entry& x, const Entry& y) {
      return x.channel(c) != y.channel(c) ? x.channel(c) < y.channel(c) : x.rgb < y.rgb;
    });
    uint64_t total = 0, running = 0;
    for (size_t i = b.begin; i < b.end; ++i) total += entries[i].count;
    size_t cut = b.begin + 1;  // both halves keep at least one colour
    for (size_t i = b.begin; i + 1 < b.end; ++i) {
      running += entries[i].count;
      cut = i + 1;
      if (2 * running >= total) break;
    }
    Box upper{cut, b.end};
    b.end = cut;
    measure(entries, b);
    measure(entries, upper);
    boxes.push_back(upper);
  }
  for (const Box& b : boxes) {
    uint64_t n = 0, sum[3] = {0, 0, 0};
    for (size_t i = b.begin; i < b.end; ++i) {
      n += entries[i].count;
      for (int c = 0; c < 3; ++c) sum[c] += uint64_t(entries[i].channel(c)) * entries[i].count;
    }
    p.colors.push_back({uint8_t((2 * sum[0] + n) / (2 * n)), uint8_t((2 * sum[1] + n) / (2 * n)),
                        uint8_t((2 * sum[2] + n) / (2 * n))});
  }
  uint64_t voxels = 0;
  double weighted = 0;
  for (const Entry& e : entries) {
    uint32_t best = 0, bestD = UINT32_MAX;
    for (uint32_t k = 0; k < p.colors.size(); ++k)
      if (const uint32_t d = distance2(e.rgb, p.colors[k]); d < bestD) best = k, bestD = d;
    p.slotOf[e.rgb] = best;
    const double d = std::sqrt(double(bestD));
    p.maxError = std::max(p.maxError, d);
    weighted += d * double(e.count);
    voxels += e.count;
  }
  p.meanError = weighted / double(voxels);
  return p;
}

}  // namespace vox
