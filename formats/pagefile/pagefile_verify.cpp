#include "formats/pagefile/pagefile_verify.h"

#include <array>
#include <atomic>
#include <exception>
#include <mutex>
#include <string>
#include <vector>

#include "formats/pagefile/pagefile_meta.h"
#include "formats/pagefile/svo_layout.h"
#include "libvox/core/error.h"
#include "libvox/core/parallel.h"
#include "libvox/core/types.h"

namespace vox::pagefile {

namespace {

// The class ids of the table, for messages: "1, 2, 5" (the first few).
std::string idList(const ClassTable& classes) {
  if (classes.size() == 0) return "none";
  std::string out;
  size_t listed = 0;
  for (const ClassInfo& c : classes.classes()) {
    if (listed == 16) return out + ", ...";
    out += (listed++ ? ", " : "") + std::to_string(c.id);
  }
  return out;
}

std::string coords(uint32_t x, uint32_t y, uint32_t z) { return toString(Coord3{int32_t(x), int32_t(y), int32_t(z)}); }

}  // namespace

uint64_t verifyPageFile(const Reader& r, unsigned threads) {
  const PageMeta meta = readPageMeta(r.metaJson(), r.name());
  std::array<bool, 256> known{};
  for (const ClassInfo& c : meta.classes.classes()) known[c.id] = true;
  auto checkClass = [&](size_t i, uint8_t cls, const std::string& voxel) {
    if (!known[cls])
      throwBadInput(r.name() + ": " + r.describe(i) + ": " + voxel + ": field 'summary': class " + std::to_string(cls) +
                    " is not in the metadata's class table (ids " + idList(meta.classes) +
                    "); the file is corrupt: pack it again");
  };
  const uint32_t C = r.header().chunkSide();
  // One chunk's voxels, or its fault thrown.
  auto verifyChunk = [&](size_t i) -> uint64_t {
    const IndexEntry& e = r.entries()[i];
    const auto c = e.chunk();
    // The voxel of the level at chunk-local index `at`, for messages.
    auto levelVoxel = [&](uint32_t at) {
      return "voxel " + coords(c[0] * C + at % C, c[1] * C + at / C % C, c[2] * C + at / (C * C)) + " of level " +
             std::to_string(e.level);
    };
    if (r.header().layout == Layout::Svo) {
      // Every brick, leaf and mip: the mip bricks carry summary bytes of their own.
      for (const SvoBrick& b : svoBricks(r, i))
        for (const DecodedVoxel& v : b.voxels) {
          if (known[v.summary[0]]) continue;
          const uint32_t bx = v.index % 8, by = v.index / 8 % 8, bz = v.index / 64;
          if (b.level == 0)
            checkClass(i, v.summary[0], levelVoxel(b.origin[0] + bx + C * (b.origin[1] + by + C * (b.origin[2] + bz))));
          else
            checkClass(i, v.summary[0], "mip brick of node " + std::to_string(b.node) + " (tree level " +
                                            std::to_string(b.level) + "), brick voxel " + coords(bx, by, bz));
        }
      return e.occupied;  // svoBricks checked that the leaves hold `occupied` voxels
    }
    const std::vector<DecodedVoxel> decoded = r.decode(i);
    for (const DecodedVoxel& v : decoded)
      if (!known[v.summary[0]]) checkClass(i, v.summary[0], levelVoxel(v.index));
    return decoded.size();
  };

  // Chunks are checked in parallel; the fault reported is that of the first
  // faulty chunk in index order, whatever the thread count, so the message
  // (and a golden file of it) does not depend on scheduling. Chunks after a
  // known fault are skipped; chunks before it are still checked.
  const size_t n = r.entries().size();
  std::vector<uint64_t> voxelsOf(n, 0);
  std::mutex faultMutex;
  std::atomic<size_t> firstFault{n};
  std::exception_ptr fault;
  parallelForEach(n, threads, 16, [&](size_t i) {
    if (i > firstFault.load(std::memory_order_relaxed)) return;
    try {
      voxelsOf[i] = verifyChunk(i);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(faultMutex);
      if (i < firstFault.load(std::memory_order_relaxed)) {
        firstFault.store(i, std::memory_order_relaxed);
        fault = std::current_exception();
      }
    }
  });
  if (fault) std::rethrow_exception(fault);
  r.checkPadding();
  uint64_t voxels = 0;
  for (uint64_t v : voxelsOf) voxels += v;
  return voxels;
}

}  // namespace vox::pagefile
