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
  // low[i] = the largest j in 0..15 with 2^(j/16) <= 1 + i/256: for n with
  // m = floor(log2 n) and the 8 bits after its leading one i, floor(16 log2 n)
  // is 16 m + low[i] or one more (a step of i moves 16 log2 by < 0.1), so one
  // comparison with t settles it. 1 + i/256 is rational and 2^(j/16)
  // irrational for j > 0: the long double comparison is exact here.
  std::array<uint8_t, 256> low{};
  ObsTable() {
    for (int k = 0; k < 256; ++k) {
      if (k % 16 == 0) {
        t[k] = uint64_t(1) << (k / 16);
      } else {
        t[k] = uint64_t(std::ceil(std::exp2l((long double)k / 16.0L)));
      }
    }
    for (int i = 0; i < 256; ++i) {
      int j = 0;
      while (j < 15 && std::exp2l((long double)(j + 1) / 16.0L) <= 1.0L + (long double)i / 256.0L) ++j;
      low[size_t(i)] = uint8_t(j);
    }
  }
};

}  // namespace

uint8_t observationByte(uint64_t n) {
  static const ObsTable table;
  // The largest k with table[k] <= n (table is increasing): 16 m + low[i]
  // or one more (ObsTable), without the mispredicted branches of a search.
  if (n >= table.t[255]) return 255;
  if (n == 0) return 0;
  const int m = std::bit_width(n) - 1;  // m <= 15 here
  const size_t i = size_t((n << (63 - m)) >> 55) & 255;  // the 8 bits after the leading one
  const int k = 16 * m + table.low[i];
  return uint8_t(table.low[i] < 15 && table.t[size_t(k + 1)] <= n ? k + 1 : k);
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
