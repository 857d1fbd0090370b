#include "formats/pagefile/pack_chunks.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <exception>
#include <nlohmann/json.hpp>
#include <thread>

#include "libvox/core/atlas_content.h"
#include "libvox/core/error.h"
#include "libvox/core/morton.h"
#include "formats/pagefile/pack_columns.h"
#include "formats/pagefile/pack_svo.h"
#include "libvox/scene/scene_grids.h"
#include "libvox/core/summary_bytes.h"
#include "libvox/core/version.h"

namespace vox {

namespace {

using nlohmann::json;
using BoolLeaf = openvdb::BoolTree::LeafNodeType;
using IntLeaf = openvdb::Int32Tree::LeafNodeType;
using ColorLeaf = openvdb::Vec3STree::LeafNodeType;

template <typename Fn>
void parallelFor(size_t n, unsigned threads, Fn&& fn) {  // fn(begin, end)
  threads = std::max(1u, std::min<unsigned>(threads, unsigned(std::max<size_t>(1, n))));
  if (threads == 1) return fn(size_t(0), n);
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < threads; ++t) pool.emplace_back([&, t] { fn(n * t / threads, n * (t + 1) / threads); });
  for (std::thread& th : pool) th.join();
}

json rgbJson(Rgb8 c) { return json::array({c.r, c.g, c.b}); }

json classesJson(const ClassTable& t) {
  json arr = json::array();
  for (const ClassInfo& c : t.classes()) {
    json j = {{"id", c.id}, {"name", c.name}, {"color", rgbJson(c.color)}};
    if (c.faces) {
      j["top"] = rgbJson(c.faces->top);
      j["bottom"] = rgbJson(c.faces->bottom);
      j["side"] = rgbJson(c.faces->side);
    }
    arr.push_back(std::move(j));
  }
  return arr;
}

void putU64(uint8_t* p, uint64_t v) {
  for (int b = 0; b < 8; ++b) p[b] = uint8_t(v >> (8 * b));
}

// Bricks layout: bitmap (absent when full), then summary, colour and surface of
// the occupied voxels in rank order.
std::vector<uint8_t> encodeBricks(const packdetail::ChunkVoxels& sc, uint32_t flags) {
  const uint32_t N = sc.side * sc.side * sc.side;
  const bool full = sc.count == N;
  const bool color = flags & pagefile::kFlagColor, surfaceCh = flags & pagefile::kFlagSurface;
  std::vector<uint8_t> bytes(pagefile::bricksPayloadBytes(N, sc.count, full, flags), 0);
  uint8_t* p = bytes.data();
  if (!full) {
    for (uint32_t w = 0; w < N / 64; ++w) putU64(p + 8 * w, sc.bits[w]);
    p += N / 8;
  }
  uint8_t* sum = p;
  uint8_t* colp = sum + 4ull * sc.count;
  uint8_t* surf = colp + (color ? 4ull * sc.count : 0);
  uint32_t rank = 0;
  for (uint32_t w = 0; w < N / 64; ++w)
    for (uint64_t word = sc.bits[w]; word; word &= word - 1) {
      const uint32_t k = w * 64 + uint32_t(std::countr_zero(word));
      std::memcpy(sum + 4 * rank, sc.summary[k].data(), 4);
      if (color) std::memcpy(colp + 4 * rank, sc.color[k].data(), 4);
      if (surfaceCh && sc.surface[k]) surf[rank / 8] |= uint8_t(1u << (rank % 8));
      ++rank;
    }
  return bytes;
}

}  // namespace

PackResult packChunks(const std::vector<const Scene*>& levels, const PackSettings& s) {
  if (s.chunkSide != 8 && s.chunkSide != 16 && s.chunkSide != 32)
    throwUsage("--chunk " + std::to_string(s.chunkSide) + ": expected 8, 16 or 32");
  if (s.alignment < 8 || s.alignment > 65536 || !std::has_single_bit(s.alignment))
    throwUsage("--align " + std::to_string(s.alignment) + ": expected a power of two from 8 to 65536");
  if (s.layout != pagefile::Layout::Bricks && s.layout != pagefile::Layout::Svo && s.layout != pagefile::Layout::Columns)
    throwUsage("packChunks: unknown layout " + std::to_string(int(s.layout)));
  if (levels.empty() || levels.size() > 255) throw Error(ErrorKind::Internal, "packChunks: 1..255 levels");
  const Scene& base = *levels[0];
  const SceneHeader& bh = base.header();

  pagefile::Header h;
  h.layout = s.layout;
  h.chunkLog2 = uint8_t(std::countr_zero(s.chunkSide));
  h.levelCount = uint8_t(levels.size());
  h.alignLog2 = uint8_t(std::countr_zero(s.alignment));
  h.dims = {bh.dims.x, bh.dims.y, bh.dims.z};
  h.voxelSize = bh.voxelSize;
  h.origin = bh.origin;
  bool anyInterior = false;
  for (const Scene* l : levels) {
    if (l->hasColor()) h.flags |= pagefile::kFlagColor;
    for (auto it = l->grids().occupancy->cbeginValueOn(); it && !anyInterior; ++it) anyInterior = !*it;
  }
  if (anyInterior) h.flags |= pagefile::kFlagSurface;

  const uint32_t C = s.chunkSide, N = C * C * C, log2C = h.chunkLog2;
  PackResult result;
  std::vector<pagefile::ChunkBlob> blobs;
  json levelTable = json::array();
  for (size_t li = 0; li < levels.size(); ++li) {
    const Scene& scene = *levels[li];
    const SceneGrids& g = scene.grids();
    const auto expectDims = h.levelDims(int(li));
    if (scene.header().dims.x != expectDims[0] || scene.header().dims.y != expectDims[1] ||
        scene.header().dims.z != expectDims[2])
      throw Error(ErrorKind::Internal, "packChunks: level " + std::to_string(li) + " has the wrong dims");
    // Non-empty chunks, in Morton order.
    std::vector<uint64_t> keys;
    for (auto leaf = g.occupancy->tree().cbeginLeaf(); leaf; ++leaf) {
      const openvdb::Coord o = leaf->origin();
      keys.push_back(mortonEncode(uint32_t(o.x()) >> log2C, uint32_t(o.y()) >> log2C, uint32_t(o.z()) >> log2C));
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    std::vector<pagefile::ChunkBlob> out(keys.size());
    const size_t nClasses = g.votes.size();
    const bool withVotes = s.layout == pagefile::Layout::Svo;
    std::vector<std::exception_ptr> errors(keys.size());  // a layout's refusal, reported for the first chunk in order
    parallelFor(keys.size(), s.threads, [&](size_t begin, size_t end) {
      packdetail::ChunkVoxels sc;
      sc.side = C;
      sc.bits.assign(N / 64, 0);
      sc.summary.resize(N);
      sc.color.resize(N);
      sc.surface.resize(N);
      sc.withVotes = withVotes;
      if (withVotes) {
        sc.voteBegin.resize(N);
        sc.voteEnd.resize(N);
        sc.linear.resize(N);
      }
      std::vector<ClassVotes> votes;
      std::vector<const IntLeaf*> voteLeaves(nClasses);
      const uint32_t leavesPerAxis = C / 8;
      for (size_t ci = begin; ci < end; ++ci) {
        const auto cc = mortonDecode(keys[ci]);
        std::fill(sc.bits.begin(), sc.bits.end(), 0);
        sc.votes.clear();
        uint32_t count = 0;
        for (uint32_t a = 0; a < leavesPerAxis; ++a)
          for (uint32_t b = 0; b < leavesPerAxis; ++b)
            for (uint32_t c = 0; c < leavesPerAxis; ++c) {
              const openvdb::Coord lo(int(cc[0] * C + 8 * a), int(cc[1] * C + 8 * b), int(cc[2] * C + 8 * c));
              const BoolLeaf* occ = g.occupancy->tree().probeConstLeaf(lo);
              if (!occ) continue;
              for (size_t k = 0; k < nClasses; ++k) voteLeaves[k] = g.votes[k].grid->tree().probeConstLeaf(lo);
              const ColorLeaf* col = g.color ? g.color->tree().probeConstLeaf(lo) : nullptr;
              for (auto it = occ->cbeginValueOn(); it; ++it) {
                const openvdb::Index off = it.pos();
                const uint32_t x = 8 * a + (off >> 6), y = 8 * b + ((off >> 3) & 7), z = 8 * c + (off & 7);
                const uint32_t k = x + C * (y + C * z);
                sc.bits[k >> 6] |= uint64_t(1) << (k & 63);
                ++count;
                votes.clear();
                for (size_t q = 0; q < nClasses; ++q)
                  if (voteLeaves[q] && voteLeaves[q]->isValueOn(off))
                    votes.push_back({g.votes[q].classId, uint32_t(voteLeaves[q]->getValue(off))});
                const SummaryTexel t = summarize(votes);
                sc.summary[k] = {t.cls, t.conf, t.obs, t.mrg};
                sc.surface[k] = *it ? 1 : 0;
                if (withVotes) {
                  sc.voteBegin[k] = uint32_t(sc.votes.size());
                  sc.votes.insert(sc.votes.end(), votes.begin(), votes.end());
                  sc.voteEnd[k] = uint32_t(sc.votes.size());
                }
                if (col && col->isValueOn(off)) {
                  const openvdb::Vec3s& v = col->getValue(off);
                  sc.color[k] = {linearToSrgb8(v[0]), linearToSrgb8(v[1]), linearToSrgb8(v[2]), 255};
                  if (withVotes) sc.linear[k] = {v[0], v[1], v[2]};
                } else {
                  sc.color[k] = {0, 0, 0, 0};
                }
              }
            }
        sc.count = count;
        pagefile::ChunkBlob& blob = out[ci];
        blob.level = uint8_t(li);
        blob.key = keys[ci];
        blob.occupied = count;
        blob.full = count == N;
        if (count == 0) continue;  // a leaf without active voxels
        try {
          switch (s.layout) {
            case pagefile::Layout::Bricks: blob.bytes = encodeBricks(sc, h.flags); break;
            case pagefile::Layout::Svo: blob.bytes = packdetail::encodeSvo(sc, h.flags); break;
            case pagefile::Layout::Columns:
              blob.bytes = packdetail::encodeColumns(sc, h.flags, {int(li), cc});
              break;
          }
        } catch (...) {
          errors[ci] = std::current_exception();
        }
      }
    });
    for (const std::exception_ptr& e : errors)
      if (e) std::rethrow_exception(e);
    PackResult::Level lv;
    lv.level = int(li);
    for (pagefile::ChunkBlob& b : out) {
      if (b.occupied == 0) continue;  // a leaf without active voxels
      ++lv.chunks;
      lv.fullChunks += b.full ? 1 : 0;
      lv.voxels += b.occupied;
      lv.payloadBytes += b.bytes.size();
      blobs.push_back(std::move(b));
    }
    result.levels.push_back(lv);
    const SceneHeader& sh = scene.header();
    levelTable.push_back({{"level", li},
                          {"dims", {sh.dims.x, sh.dims.y, sh.dims.z}},
                          {"voxel_size", sh.voxelSize},
                          {"chunks", lv.chunks},
                          {"voxels", lv.voxels}});
  }
  json meta = {{"format", "voxbake-pages"},
               {"tool_version", kToolVersion},
               {"classes", classesJson(bh.classes)},
               {"levels", levelTable}};
  json sources = json::array();
  for (const SceneSource& src : bh.sources)
    sources.push_back({{"path", src.path}, {"kind", src.kind}, {"sha256", src.sha256}, {"bytes", src.bytes}});
  meta["sources"] = sources;
  if (!s.mipOccupancy.empty()) meta["mip_occupancy"] = s.mipOccupancy;
  if (bh.blockWorld)
    meta["block_world"] = {{"worldScale", bh.blockWorld->worldScale}, {"gridSize", bh.blockWorld->gridSize}};
  result.bytes = pagefile::serialize(h, meta.dump(), blobs);
  return result;
}

}  // namespace vox
