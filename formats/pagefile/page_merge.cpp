#include "formats/pagefile/page_merge.h"

#include <algorithm>
#include <chrono>
#include <exception>

#include "formats/pagefile/layouts.h"
#include "formats/pagefile/pagefile_meta.h"
#include "formats/pagefile/svo_layout.h"
#include "libvox/core/error.h"
#include "libvox/core/morton.h"
#include "libvox/core/parallel.h"
#include "libvox/core/regions.h"
#include "libvox/core/version.h"

namespace vox {

namespace {

using pagefile::Reader;

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// One part: its reader, metadata and the scene header checkRegionParts reads.
struct Part {
  const Reader* reader = nullptr;
  pagefile::PageMeta meta;
  SceneHeader header;
};

// The scene header a part's page file describes: placement from the file
// header, class table, sources, block world and region from the metadata.
SceneHeader sceneHeaderOf(const Reader& r, const pagefile::PageMeta& meta) {
  SceneHeader h;
  const pagefile::Header& ph = r.header();
  h.dims = {ph.dims[0], ph.dims[1], ph.dims[2]};
  h.voxelSize = ph.voxelSize;
  h.origin = ph.origin;
  h.classes = meta.classes;
  h.sources = meta.sources;
  h.blockWorld = meta.blockWorld;
  h.region = meta.region;
  return h;
}

[[noreturn]] void refuse(const Reader& r, const std::string& what) { throwBadInput(r.name() + ": " + what); }

// Every part is a part, and the parts agree on what decides the bytes of the
// merged file besides their voxels.
void checkSettingsAgree(const std::vector<Part>& parts) {
  const Part& first = parts.front();
  const pagefile::Header& a = first.reader->header();
  for (const Part& p : parts) {
    const pagefile::Header& b = p.reader->header();
    auto differs = [&](const std::string& what, const std::string& va, const std::string& vb) {
      refuse(*p.reader, what + " " + vb + ", but " + first.reader->name() + " has " + va +
                            ": pack every part with the same --chunk, --layout, --align and --mips");
    };
    if (b.chunkLog2 != a.chunkLog2)
      differs("chunk side", std::to_string(a.chunkSide()), std::to_string(b.chunkSide()));
    if (b.layout != a.layout) differs("layout", pagefile::layoutName(a.layout), pagefile::layoutName(b.layout));
    if (b.alignLog2 != a.alignLog2)
      differs("payload alignment", std::to_string(1u << a.alignLog2), std::to_string(1u << b.alignLog2));
    if (b.levelCount != 1)
      refuse(*p.reader, "the part has " + std::to_string(b.levelCount) +
                            " levels: --merge joins level 0 only so far; pack the parts without --mips, merge, "
                            "then build the levels from the merged scene");
    if (p.meta.mipOccupancy != first.meta.mipOccupancy)
      differs("mip occupancy", "'" + first.meta.mipOccupancy + "'", "'" + p.meta.mipOccupancy + "'");
  }
}

// A chunk of the output and where its voxels come from: (part, entry) pairs,
// one per part that holds the chunk.
struct OutChunk {
  uint8_t level = 0;
  uint64_t key = 0;
  std::vector<std::pair<uint32_t, uint32_t>> sources;
  bool copy = false;
};

// The level-0 voxel box of chunk `cc` (C^3 at level 0), clipped to the domain.
IndexBox chunkBox(const std::array<uint32_t, 3>& cc, uint32_t C, const std::array<uint32_t, 3>& dims) {
  IndexBox b;
  b.min = {int64_t(cc[0]) * C, int64_t(cc[1]) * C, int64_t(cc[2]) * C};
  b.max = {std::min<int64_t>(b.min.u + C, dims[0]) - 1, std::min<int64_t>(b.min.v + C, dims[1]) - 1,
           std::min<int64_t>(b.min.w + C, dims[2]) - 1};
  return b;
}

bool contains(const IndexBox& outer, const IndexBox& inner) {
  return !outer.empty() && inner.min.u >= outer.min.u && inner.min.v >= outer.min.v && inner.min.w >= outer.min.w &&
         inner.max.u <= outer.max.u && inner.max.v <= outer.max.v && inner.max.w <= outer.max.w;
}

// Chunks of every part, sorted by (level, key); a level-0 chunk has one source
// and must lie inside its part's box.
std::vector<OutChunk> collectChunks(const std::vector<Part>& parts) {
  struct Item {
    uint8_t level;
    uint64_t key;
    uint32_t part, entry;
  };
  std::vector<Item> items;
  for (uint32_t pi = 0; pi < parts.size(); ++pi) {
    const Reader& r = *parts[pi].reader;
    const IndexBox& box = parts[pi].meta.region->box;
    const auto& entries = r.entries();
    for (uint32_t ei = 0; ei < entries.size(); ++ei) {
      const pagefile::IndexEntry& e = entries[ei];
      if (e.level == 0 && !contains(box, chunkBox(e.chunk(), r.header().chunkSide(), r.header().dims)))
        refuse(r, r.describe(ei) + " lies outside the part's box: the file is not the part its 'region' says");
      items.push_back({e.level, e.key, pi, ei});
    }
  }
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    return a.level != b.level ? a.level < b.level : a.key != b.key ? a.key < b.key : a.part < b.part;
  });
  std::vector<OutChunk> out;
  for (const Item& it : items) {
    if (out.empty() || out.back().level != it.level || out.back().key != it.key) out.push_back({it.level, it.key, {}, false});
    out.back().sources.push_back({it.part, it.entry});
  }
  for (const OutChunk& c : out)
    if (c.level == 0 && c.sources.size() > 1) {
      const Reader& r = *parts[c.sources[1].first].reader;
      refuse(r, r.describe(c.sources[1].second) + " is also in " + parts[c.sources[0].first].reader->name() +
                    ": the parts overlap");
    }
  return out;
}

// The payload of `c` in the world's flags, from its sources' decoded voxels
// through the layout's encoder (svo: from the decoded bricks, leaf and mip).
std::vector<uint8_t> reencode(const std::vector<Part>& parts, const OutChunk& c, const pagefile::Header& world) {
  const pagefile::LayoutCodec& codec = pagefile::codecOf(world.layout);
  const uint32_t C = world.chunkSide();
  if (world.layout == pagefile::Layout::Svo) {
    std::vector<pagefile::SvoBrick> bricks;
    for (const auto& [pi, ei] : c.sources) {
      std::vector<pagefile::SvoBrick> b = pagefile::svoBricks(*parts[pi].reader, ei);
      bricks.insert(bricks.end(), std::make_move_iterator(b.begin()), std::make_move_iterator(b.end()));
    }
    return pagefile::encodeSvoFromBricks(bricks, C, world.flags);
  }
  pagefile::ChunkVoxels v;
  const uint32_t N = world.chunkVoxels();
  v.side = C;
  v.bits.assign(N / 64, 0);
  v.summary.assign(N, {0, 0, 0, 0});
  v.color.assign(N, {0, 0, 0, 0});
  v.surface.assign(N, 0);
  for (const auto& [pi, ei] : c.sources)
    for (const pagefile::DecodedVoxel& d : parts[pi].reader->decode(ei)) {
      v.bits[d.index >> 6] |= uint64_t(1) << (d.index & 63);
      ++v.count;
      v.summary[d.index] = d.summary;
      v.color[d.index] = d.color;
      v.surface[d.index] = d.surface ? 1 : 0;
    }
  return codec.encode(v, world.flags, {c.level, mortonDecode(c.key)});
}

// Runs `work(i)` for the chunks in `which`, in parallel; the first error in
// chunk order is rethrown, so the message does not depend on the threads.
template <typename Fn>
void forChunks(const std::vector<size_t>& which, unsigned threads, Fn&& work) {
  std::vector<std::exception_ptr> errors(which.size());
  parallelForEach(which.size(), threads, 16, [&](size_t i) {
    try {
      work(which[i]);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace

MergeResult mergePageFiles(std::span<const Reader* const> readers, const MergeSettings& settings) {
  if (readers.empty()) throw Error(ErrorKind::Internal, "mergePageFiles: no parts");
  MergeResult result;
  MergeStats& st = result.stats;
  auto t0 = std::chrono::steady_clock::now();

  // Check: every file a part, one bake, the same settings, chunks in their tiles.
  std::vector<Part> parts(readers.size());
  for (size_t i = 0; i < readers.size(); ++i) {
    Part& p = parts[i];
    p.reader = readers[i];
    p.meta = pagefile::readPageMeta(p.reader->metaJson(), p.reader->name());
    if (!p.meta.region)
      refuse(*p.reader, "a whole page file, not a part of a region bake (its metadata has no 'region'); --merge "
                        "joins the page files of the parts (vox voxelize --region I/N, then vox pack-chunks)");
    p.header = sceneHeaderOf(*p.reader, p.meta);
    st.partFileBytes += p.reader->header().fileBytes;
  }
  std::vector<RegionPart> rp;
  for (size_t i = 0; i < parts.size(); ++i) rp.push_back({parts[i].reader->name(), &parts[i].header});
  checkRegionParts(rp);
  checkSettingsAgree(parts);

  const Part& first = parts.front();
  pagefile::Header h;
  h.layout = first.reader->header().layout;
  h.chunkLog2 = first.reader->header().chunkLog2;
  h.alignLog2 = first.reader->header().alignLog2;
  h.levelCount = first.reader->header().levelCount;
  h.dims = first.reader->header().dims;
  h.voxelSize = first.reader->header().voxelSize;
  h.origin = first.reader->header().origin;
  // A channel is in the world when a part has it: colour when some part has
  // colour, the surface bit when some part has an interior voxel.
  for (const Part& p : parts) h.flags |= p.reader->header().flags;
  st.flagsFromParts = h.flags;

  std::vector<OutChunk> chunks = collectChunks(parts);
  std::vector<size_t> toCopy, toEncode;
  for (size_t i = 0; i < chunks.size(); ++i) {
    OutChunk& c = chunks[i];
    c.copy = c.sources.size() == 1 && parts[c.sources[0].first].reader->header().flags == h.flags;
    (c.copy ? toCopy : toEncode).push_back(i);
  }
  st.checkSeconds = secondsSince(t0);

  // Copy: payloads of parts whose flags are the world's, CRC checked.
  std::vector<pagefile::ChunkBlob> blobs(chunks.size());
  for (size_t i = 0; i < chunks.size(); ++i) {
    blobs[i].level = chunks[i].level;
    blobs[i].key = chunks[i].key;
  }
  t0 = std::chrono::steady_clock::now();
  forChunks(toCopy, settings.threads, [&](size_t i) {
    const auto [pi, ei] = chunks[i].sources[0];
    const Reader& r = *parts[pi].reader;
    const pagefile::IndexEntry& e = r.entries()[ei];
    const std::span<const uint8_t> bytes = r.payload(ei);  // checks the CRC
    blobs[i].occupied = e.occupied;
    blobs[i].full = e.flags & pagefile::kChunkFull;
    blobs[i].bytes.assign(bytes.begin(), bytes.end());
  });
  st.copySeconds = secondsSince(t0);

  // Re-encode: chunks of parts that lack a channel of the world.
  t0 = std::chrono::steady_clock::now();
  forChunks(toEncode, settings.threads, [&](size_t i) {
    uint32_t occupied = 0;
    for (const auto& [pi, ei] : chunks[i].sources) occupied += parts[pi].reader->entries()[ei].occupied;
    blobs[i].occupied = occupied;
    blobs[i].full = occupied == h.chunkVoxels();
    blobs[i].bytes = reencode(parts, chunks[i], h);
  });
  st.reencodeSeconds = secondsSince(t0);
  st.copiedChunks = toCopy.size();
  st.reencodedChunks = toEncode.size();
  for (size_t i : toCopy) st.copiedBytes += blobs[i].bytes.size();
  for (size_t i : toEncode) st.reencodedBytes += blobs[i].bytes.size();

  // The metadata the single-process pack writes: the parts' class table,
  // sources and block world, no region, the levels counted here.
  t0 = std::chrono::steady_clock::now();
  pagefile::PageMeta meta;
  meta.toolVersion = kToolVersion;
  meta.classes = first.meta.classes;
  meta.sources = first.meta.sources;
  meta.mipOccupancy = first.meta.mipOccupancy;
  meta.blockWorld = first.meta.blockWorld;
  for (int l = 0; l < h.levelCount; ++l) {
    MergeResult::Level lv;
    lv.level = l;
    for (const pagefile::ChunkBlob& b : blobs)
      if (b.level == l) {
        ++lv.chunks;
        lv.fullChunks += b.full ? 1 : 0;
        lv.voxels += b.occupied;
        lv.payloadBytes += b.bytes.size();
      }
    result.levels.push_back(lv);
    const auto d = h.levelDims(l);
    double vs = h.voxelSize;
    for (int k = 0; k < l; ++k) vs *= 2;
    meta.levels.push_back({uint32_t(l), d, vs, lv.chunks, lv.voxels});
  }
  result.bytes = pagefile::serialize(h, pagefile::writePageMeta(meta), blobs);
  st.serializeSeconds = secondsSince(t0);
  return result;
}

}  // namespace vox
