#include "libvox/core/summary_bytes.h"

#include <bit>
#include <cmath>

namespace vox {

namespace {

uint8_t roundedRatio255(uint64_t num, uint64_t total) {  // round(255 * num / total), half up
  const uint64_t a = 255 * num;
  return uint8_t((2 * a + total) / (2 * total));
}

// kObsThreshold[k] = the smallest integer n with 16 * log2(n) >= k, i.e. n >= 2^(k/16).
// 2^(k/16) is an integer only when 16 divides k and otherwise irrational, so the
// ceiling of a long double evaluation is exact here (all values are <= 65536,
// far inside long double's 64-bit mantissa, and none is within 1e-9 of an
// integer except the exact powers of two, which are handled separately).
struct ObsTable {
  std::array<uint64_t, 256> t{};
  ObsTable() {
    for (int k = 0; k < 256; ++k) {
      if (k % 16 == 0) {
        t[k] = uint64_t(1) << (k / 16);
      } else {
        t[k] = uint64_t(std::ceil(std::exp2l((long double)k / 16.0L)));
      }
    }
  }
};

}  // namespace

uint8_t observationByte(uint64_t n) {
  static const ObsTable table;
  // The largest k with table[k] <= n (table is increasing). It lies among
  // the 16 entries of n's power of two (table[16 m] = 2^m <= n < 2^(m+1));
  // counting them without branches beats a binary search's mispredictions.
  if (n >= table.t[255]) return 255;
  if (n == 0) return 0;
  const int m = std::bit_width(n) - 1;  // m <= 15 here
  const uint64_t* t = &table.t[size_t(16 * m)];
  int k = 16 * m;
  for (int j = 1; j < 16; ++j) k += t[j] <= n ? 1 : 0;
  return uint8_t(k);
}

SummaryTexel summarize(std::span<const ClassVotes> votes) {
  // One class (most voxels): conf = mrg = round(255 * n / n) = 255, no division.
  if (votes.size() == 1 && votes[0].votes != 0)
    return {votes[0].classId, 255, observationByte(uint64_t(votes[0].votes) + 1), 255};
  uint64_t total = 0, top = 0, second = 0;
  uint8_t cls = 0;
  for (const ClassVotes& c : votes) {
    if (c.votes == 0) continue;
    total += c.votes;
    if (c.votes > top || (c.votes == top && c.classId < cls)) {
      second = top;
      top = c.votes;
      cls = c.classId;
    } else if (c.votes > second) {
      second = c.votes;
    }
  }
  if (total == 0) return {};
  return {cls, roundedRatio255(top, total), observationByte(total + 1), roundedRatio255(top - second, total)};
}

SummaryTexel summarizeReference(std::span<const ClassVotes> votes) {
  long double total = 0;
  uint64_t best[256] = {};
  for (const ClassVotes& c : votes) best[c.classId] += c.votes, total += c.votes;
  if (total == 0) return {};
  uint64_t top = 0;
  for (int i = 1; i < 256; ++i) top = std::max(top, best[i]);
  int cls = 1;
  while (best[cls] != top) ++cls;  // the lowest id among the maxima
  long double second = 0;
  for (int i = 1; i < 256; ++i)
    if (i != cls) second = std::max<long double>(second, best[i]);
  auto rnd = [](long double x) { return uint8_t(std::floor(x + 0.5L)); };
  const long double obs = std::floor(16.0L * std::log2(total + 1.0L) + 1e-12L);
  return {uint8_t(cls), rnd(255.0L * best[cls] / total), uint8_t(std::min<long double>(255.0L, obs)),
          rnd(255.0L * (best[cls] - second) / total)};
}

}  // namespace vox
