#include "libvox/core/bijection_proof.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <vector>

#include "libvox/core/parallel.h"

namespace vox {

namespace {

struct FailureLog {
  std::mutex m;
  std::atomic<uint64_t> count{0};
  std::optional<BijectionFailure> first;
  uint64_t firstKey = ~uint64_t(0);
  void add(uint64_t orderKey, BijectionFailure f) {
    ++count;
    std::lock_guard<std::mutex> lock(m);
    if (orderKey < firstKey) firstKey = orderKey, first = std::move(f);
  }
};

/// fn(begin, end) over one contiguous range of [0, n) per thread. Failures are
/// kept by their order key and counts are sums, so the result does not depend
/// on the split.
template <typename Fn>
void parallel(uint64_t n, unsigned threads, Fn&& fn) {
  const unsigned pieces = std::max(1u, std::min<unsigned>(threads, unsigned(std::max<uint64_t>(1, n))));
  parallelPieces(n, pieces, pieces, [&](size_t begin, size_t end, size_t) { fn(begin, end); });
}

BijectionResult exhaustive(const AtlasLayout& L, unsigned threads) {
  BijectionResult r;
  r.method = "exhaustive";
  const Dims d = L.dims;
  const uint64_t W = L.width, H = L.height;
  const uint64_t texels = uint64_t(L.layers) * W * H;
  std::vector<std::atomic<uint64_t>> hit((texels + 63) / 64);
  FailureLog log;
  // Voxel pass, by w-slices.
  parallel(d.z, threads, [&](uint64_t w0, uint64_t w1) {
    for (uint32_t w = uint32_t(w0); w < w1; ++w)
      for (uint32_t v = 0; v < d.y; ++v) {
        for (uint32_t u = 0; u < d.x; ++u) {
          const TexelAddress t = L.toTexel(u, v, w);
          const uint64_t key = (uint64_t(w) * d.y + v) * d.x + u;
          if (t.layer >= L.layers || t.x >= W || t.y >= H) {
            log.add(key, {"out of range", {int32_t(u), int32_t(v), int32_t(w)}, t, std::nullopt, std::nullopt});
            continue;
          }
          const uint64_t idx = (uint64_t(t.layer) * H + t.y) * W + t.x;
          const uint64_t bit = uint64_t(1) << (idx & 63);
          if (hit[idx >> 6].fetch_or(bit, std::memory_order_relaxed) & bit)
            log.add(key, {"collision", {int32_t(u), int32_t(v), int32_t(w)}, t, L.toVoxel(t.layer, t.x, t.y), std::nullopt});
          const std::optional<Coord3> back = L.toVoxel(t.layer, t.x, t.y);
          if (!back || back->u != int32_t(u) || back->v != int32_t(v) || back->w != int32_t(w))
            log.add(key, {"inverse differs", {int32_t(u), int32_t(v), int32_t(w)}, t, back, std::nullopt});
        }
      }
  });
  r.voxelsChecked = d.count();
  // Texel pass: every texel not hit must be padding.
  std::atomic<uint64_t> padding{0};
  const uint64_t rows = uint64_t(L.layers) * H;
  parallel(rows, threads, [&](uint64_t r0, uint64_t r1) {
    uint64_t pad = 0;
    for (uint64_t row = r0; row < r1; ++row) {
      const uint32_t layer = uint32_t(row / H), y = uint32_t(row % H);
      for (uint32_t x = 0; x < W; ++x) {
        const uint64_t idx = row * W + x;
        if ((hit[idx >> 6].load(std::memory_order_relaxed) >> (idx & 63)) & 1) continue;
        ++pad;
        const std::optional<Coord3> claimed = L.toVoxel(layer, x, y);
        if (claimed)
          log.add(d.count() + idx, {"padding aliased", *claimed, {layer, x, y}, claimed, std::nullopt});
      }
    }
    padding += pad;
  });
  r.texelsChecked = texels;
  r.paddingTexels = padding;
  r.failures = log.count;
  r.first = log.first;
  return r;
}

BijectionResult byParts(const AtlasLayout& L) {  // serial: the parts are small
  BijectionResult r;
  r.method = "by-parts";
  FailureLog log;
  const Dims d = L.dims;
  // Part 1: the in-tile map. x depends on (u, w) only and y on (v, w) only, so
  // each axis is checked on its own, over every u (every v), at the first and
  // last tile column (tile row) of a layer.
  const uint32_t cols[2] = {0, L.tilesPerRow - 1}, rowsIn[2] = {0, L.rowsPerLayer - 1};
  for (uint32_t c : cols)
    for (uint32_t ri : rowsIn) {
      const uint64_t w = uint64_t(ri) * L.tilesPerRow + c;  // a tile slot of layer 0
      if (w >= d.z) continue;
      for (uint32_t u = 0; u < d.x; ++u) {
        const TexelAddress t = L.toTexel(u, 0, uint32_t(w)), t2 = L.toTexel(u, d.y - 1, uint32_t(w));
        const auto back = L.toVoxel(t.layer, t.x, t.y);
        ++r.voxelsChecked;
        if (t.x != c * d.x + u || t2.x != t.x || !back || back->u != int32_t(u) || back->w != int32_t(w))
          log.add(r.voxelsChecked, {"inverse differs", {int32_t(u), 0, int32_t(w)}, t, back, std::nullopt});
      }
      for (uint32_t v = 0; v < d.y; ++v) {
        const TexelAddress t = L.toTexel(0, v, uint32_t(w)), t2 = L.toTexel(d.x - 1, v, uint32_t(w));
        const auto back = L.toVoxel(t.layer, t.x, t.y);
        ++r.voxelsChecked;
        if (t.y != ri * d.y + v || t2.y != t.y || !back || back->v != int32_t(v) || back->w != int32_t(w))
          log.add(r.voxelsChecked, {"inverse differs", {0, int32_t(v), int32_t(w)}, t, back, std::nullopt});
      }
    }
  // Part 2: the tile-index map, every w, and every tile slot beyond Z is padding.
  uint64_t slots = uint64_t(L.layers) * L.rowsPerLayer * L.tilesPerRow;
  for (uint64_t slot = 0; slot < slots; ++slot) {
    const uint32_t layer = uint32_t(slot / (uint64_t(L.rowsPerLayer) * L.tilesPerRow));
    const uint32_t rowIn = uint32_t(slot / L.tilesPerRow % L.rowsPerLayer), col = uint32_t(slot % L.tilesPerRow);
    const auto back = L.toVoxel(layer, col * d.x, rowIn * d.y);
    ++r.texelsChecked;
    if (slot < d.z) {
      const TexelAddress t = L.toTexel(0, 0, uint32_t(slot));
      if (!back || back->w != int32_t(slot) || t.layer != layer || t.x != col * d.x || t.y != rowIn * d.y)
        log.add(slot, {"inverse differs", {0, 0, int32_t(slot)}, t, back, std::nullopt});
    } else {
      r.paddingTexels += uint64_t(d.x) * d.y;
      if (back) log.add(slot, {"padding aliased", *back, {layer, col * d.x, rowIn * d.y}, back, std::nullopt});
    }
  }
  r.argument =
      "x = col * X + u with 0 <= u < X is Euclidean division of x by X, so (col, u) <-> x is a bijection of "
      "[0, T) x [0, X) onto [0, T * X); likewise (rowInLayer, v) <-> y onto [0, R * Y). Checked: the u and v "
      "axes exhaustively at the first and last tile column and row (x depends on u and w only, y on v and w "
      "only), and the tile-index map w <-> (layer, rowInLayer, col) for every w and every tile slot. Composed, "
      "(u, v, w) <-> (layer, x, y) is a bijection onto the texels of the first Z tile slots; the texels of the "
      "remaining slots are padding, which the inverse rejects.";
  r.failures = log.count;
  r.first = log.first;
  return r;
}

}  // namespace

BijectionResult proveBijection(const AtlasLayout& layout, unsigned threads, uint64_t exhaustiveLimit) {
  const uint64_t texels = uint64_t(layout.layers) * layout.width * layout.height;
  if (layout.dims.count() <= exhaustiveLimit && texels <= 2 * exhaustiveLimit) return exhaustive(layout, threads);
  return byParts(layout);
}

}  // namespace vox
