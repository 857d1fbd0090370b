#include <gtest/gtest.h>

#include <bit>
#include <fstream>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <sstream>
#include <tuple>

#include "formats/pagefile/bricks_layout.h"
#include "formats/pagefile/columns_layout.h"
#include "formats/pagefile/layouts.h"
#include "formats/pagefile/pack_chunks.h"
#include "formats/pagefile/pagefile.h"
#include "formats/pagefile/pagefile_meta.h"
#include "formats/pagefile/pagefile_verify.h"
#include "formats/pagefile/svo_layout.h"
#include "libvox/core/atlas_content.h"
#include "libvox/core/crc32c.h"
#include "libvox/core/morton.h"
#include "libvox/core/summary_bytes.h"
#include "libvox/core/version.h"
#include "libvox/scene/demo_hamlet.h"
#include "libvox/scene/mip.h"
#include "test_util.h"

namespace {

using vox::pagefile::Reader;

struct Expected {
  std::array<uint8_t, 4> summary{};
  bool surface = true;
  std::array<uint8_t, 4> color{};
};
using VoxelMap = std::map<std::tuple<int, int, int, int>, Expected>;  // level, u, v, w

VoxelMap expectedVoxels(const std::vector<const vox::Scene*>& levels) {
  VoxelMap m;
  for (size_t l = 0; l < levels.size(); ++l)
    levels[l]->forEachVoxel([&](const vox::VoxelView& v) {
      const vox::SummaryTexel t = vox::summarize(v.votes);
      Expected e;
      e.summary = {t.cls, t.conf, t.obs, t.mrg};
      e.surface = v.surface;
      if (v.color) e.color = {vox::linearToSrgb8(v.color->r), vox::linearToSrgb8(v.color->g), vox::linearToSrgb8(v.color->b), 255};
      m[{int(l), v.at.u, v.at.v, v.at.w}] = e;
    });
  return m;
}

VoxelMap unpack(const Reader& r) {
  VoxelMap m;
  const uint32_t C = r.header().chunkSide();
  for (size_t i = 0; i < r.entries().size(); ++i) {
    const auto& e = r.entries()[i];
    const auto c = e.chunk();
    uint32_t last = 0;
    bool firstVoxel = true;
    for (const auto& v : r.decode(i)) {
      EXPECT_TRUE(firstVoxel || v.index > last) << r.describe(i) << ": voxels not in rank order";
      firstVoxel = false;
      last = v.index;
      const int x = int(c[0] * C + (v.index % C)), y = int(c[1] * C + (v.index / C) % C), z = int(c[2] * C + v.index / (C * C));
      m[{e.level, x, y, z}] = {v.summary, v.surface, v.color};
    }
  }
  return m;
}

bool sameMaps(const VoxelMap& a, const VoxelMap& b, std::string& why) {
  if (a.size() != b.size()) {
    why = "sizes " + std::to_string(a.size()) + " vs " + std::to_string(b.size());
    return false;
  }
  for (auto ia = a.begin(), ib = b.begin(); ia != a.end(); ++ia, ++ib) {
    if (ia->first != ib->first) {
      why = "voxel sets differ";
      return false;
    }
    if (ia->second.summary != ib->second.summary || ia->second.surface != ib->second.surface ||
        ia->second.color != ib->second.color) {
      const auto [l, u, v, w] = ia->first;
      why = "values differ at level " + std::to_string(l) + " (" + std::to_string(u) + "," + std::to_string(v) + "," +
            std::to_string(w) + ")";
      return false;
    }
  }
  return true;
}

vox::Scene colouredScene() {
  vox::SceneHeader h;
  h.dims = {37, 20, 33};
  h.voxelSize = 0.25;
  h.origin = {-1, 0, 2};
  h.classes.add({1, "a", {}, {}});
  h.classes.add({2, "b", {}, {}});
  h.classes.add({5, "e", {}, {}});
  vox::SceneBuilder b(h);
  // A full 16^3 block at (16..31, 0..15, 0..15), interior without colour.
  for (int z = 0; z < 16; ++z)
    for (int y = 0; y < 16; ++y) b.addRun({16, y, z}, 1, 1, 1, false), b.addRun({17, y, z}, 1, 2, 1, false);
  for (int z = 0; z < 16; ++z)
    for (int y = 0; y < 16; ++y)
      for (int x = 18; x < 32; ++x) b.addVotes({x, y, z}, 1, uint32_t(1 + (x * 7 + y * 3 + z) % 13), false);
  // Scattered coloured surface voxels up to the odd edges.
  for (int i = 0; i < 300; ++i) {
    const vox::Coord3 c{(i * 17) % 37, (i * 5) % 20, (i * 11) % 33};
    b.addVotes(c, uint8_t(i % 3 == 0 ? 5 : 2), uint32_t(i + 1), true);
    b.addVotes(c, 1, uint32_t(i % 7), true);
    b.setColor(c, {float(i % 10) / 9.f, 0.5f, float(i % 4) / 3.f});
  }
  return std::move(b).build();
}

using vox::pagefile::Layout;

// Every layout of the table: a new layout is round-tripped, truncated and
// bit-flipped by the tests below without touching them.
std::vector<Layout> allLayouts() {
  std::vector<Layout> out;
  for (const auto& l : vox::pagefile::layoutTable()) out.push_back(l.id);
  return out;
}
const std::vector<Layout> kLayouts = allLayouts();

TEST(PageFile, RoundTripEveryChunkSizeWithMips) {
  const vox::Scene base = colouredScene();
  const auto mips = vox::buildMipPyramid(base, vox::MipSettings{});
  std::vector<const vox::Scene*> levels{&base};
  for (const auto& m : mips) levels.push_back(&m);
  const VoxelMap want = expectedVoxels(levels);
  for (Layout layout : kLayouts)
  for (uint32_t C : {8u, 16u, 32u})
    for (uint32_t align : {8u, 4096u}) {
      SCOPED_TRACE(std::string(vox::pagefile::layoutName(layout)) + " C=" + std::to_string(C) + " align=" + std::to_string(align));
      vox::PackSettings s;
      s.chunkSide = C;
      s.alignment = align;
      s.layout = layout;
      const vox::PackResult res = vox::packChunks(levels, s);
      const Reader r = Reader::fromMemory(res.bytes.data(), res.bytes.size(), "mem.vpk");
      EXPECT_EQ(r.header().layout, layout);
      EXPECT_EQ(r.header().chunkSide(), C);
      EXPECT_EQ(r.header().levelCount, levels.size());
      EXPECT_EQ(r.header().flags, vox::pagefile::kFlagColor | vox::pagefile::kFlagSurface);
      for (const auto& e : r.entries()) EXPECT_EQ(e.offset % align, 0u);
      std::string why;
      EXPECT_TRUE(sameMaps(unpack(r), want, why)) << "C=" << C << ": " << why;
      uint64_t voxels = 0;
      for (const auto* l : levels) voxels += l->occupiedCount();
      EXPECT_EQ(r.verify(), voxels);
      // The full block is stored without a bitmap at C = 8 and 16.
      if (C <= 16) {
        const auto* e = r.find(0, 16 / C, 0, 0);
        ASSERT_NE(e, nullptr);
        EXPECT_TRUE(e->flags & vox::pagefile::kChunkFull);
        const uint32_t N = C * C * C;
        if (layout == Layout::Bricks) {
          EXPECT_EQ(e->size, vox::pagefile::bricksPayloadBytes(N, N, true, r.header().flags));
        }
        // Columns: no solid mask and no ladder; the block is interior except its faces.
        if (layout == Layout::Columns) {
          const auto pl = r.payload(size_t(e - r.entries().data()));
          const uint32_t S = uint32_t(pl[0] | pl[1] << 8 | pl[2] << 16 | uint32_t(pl[3]) << 24);
          EXPECT_EQ(e->size, vox::pagefile::columnsPayloadBytes(C, N, S, true, r.header().flags));
        }
        if (layout == Layout::Svo) {  // every brick full: no bitmap stored
          const auto bricks = vox::pagefile::svoBricks(r, size_t(e - r.entries().data()));
          EXPECT_EQ(e->size, vox::pagefile::svoPayloadBytes(bricks.size(), 0, 512 * bricks.size(), r.header().flags));
          for (const auto& b : bricks) EXPECT_EQ(b.flags & vox::pagefile::kSvoNodeFull, vox::pagefile::kSvoNodeFull);
        }
      }
      // Lookup: every entry is found; an empty chunk is not.
      for (const auto& e : r.entries()) {
        const auto c = e.chunk();
        EXPECT_EQ(r.find(e.level, c[0], c[1], c[2]), &e);
      }
      EXPECT_EQ(r.find(0, 1000, 0, 0), nullptr);
      EXPECT_EQ(r.find(200, 0, 0, 0), nullptr);
    }
}

TEST(PageFile, HamletRoundTripAndIdenticalAtAnyThreadCount) {
  vox::HamletOptions ho;
  ho.resolution = 48;
  const vox::Scene base = vox::buildHamlet(ho);
  const auto mips = vox::buildMipPyramid(base, vox::MipSettings{});
  std::vector<const vox::Scene*> levels{&base};
  for (const auto& m : mips) levels.push_back(&m);
  const VoxelMap want = expectedVoxels(levels);
  for (Layout layout : {Layout::Svo, Layout::Columns}) {
    vox::PackSettings s;
    s.layout = layout;
    s.threads = 1;
    const auto one = vox::packChunks(levels, s);
    s.threads = 3;
    const auto three = vox::packChunks(levels, s);
    EXPECT_EQ(one.bytes, three.bytes) << vox::pagefile::layoutName(layout);
    const Reader r = Reader::fromMemory(one.bytes.data(), one.bytes.size(), "h.vpk");
    std::string why;
    EXPECT_TRUE(sameMaps(unpack(r), want, why)) << vox::pagefile::layoutName(layout) << ": " << why;
  }
  vox::PackSettings s;
  s.threads = 1;
  const auto one = vox::packChunks(levels, s);
  s.threads = 4;
  const auto four = vox::packChunks(levels, s);
  EXPECT_EQ(one.bytes, four.bytes);
  const Reader r = Reader::fromMemory(one.bytes.data(), one.bytes.size(), "h.vpk");
  EXPECT_EQ(r.header().flags, vox::pagefile::kFlagSurface);  // no colour in the hamlet; interior voxels
  std::string why;
  EXPECT_TRUE(sameMaps(unpack(r), want, why)) << why;
  // Sorted by (level, key); level ranges.
  size_t total = 0;
  for (int l = 0; l < r.header().levelCount; ++l) {
    const auto [a, b] = r.levelRange(l);
    EXPECT_LT(a, b);
    total += b - a;
  }
  EXPECT_EQ(total, r.entries().size());
}

// The mip bricks of the svo layout are the scene's own mip levels (`any`), voxel for voxel.
TEST(PageFile, SvoMipBricksAreThePyramidLevels) {
  const vox::Scene base = colouredScene();
  const auto mips = vox::buildMipPyramid(base, vox::MipSettings{});
  std::vector<const vox::Scene*> levels{&base};
  for (const auto& m : mips) levels.push_back(&m);
  const VoxelMap want = expectedVoxels(levels);
  for (uint32_t C : {16u, 32u}) {
    vox::PackSettings s;
    s.chunkSide = C;
    s.alignment = 8;
    s.layout = Layout::Svo;
    const auto res = vox::packChunks(levels, s);
    const Reader r = Reader::fromMemory(res.bytes.data(), res.bytes.size(), "svo.vpk");
    size_t mipVoxels = 0;
    for (size_t i = 0; i < r.entries().size(); ++i) {
      const auto& e = r.entries()[i];
      const auto c = e.chunk();
      const auto bricks = vox::pagefile::svoBricks(r, i);
      ASSERT_FALSE(bricks.empty());
      EXPECT_EQ(bricks[0].level, std::countr_zero(C) - 3);  // the root
      for (const auto& b : bricks) {
        if (b.level == 0 || e.level + b.level >= int(levels.size())) continue;
        // Every voxel of the level e.level + b.level inside the node's region is in its brick.
        size_t inRegion = 0;
        const uint32_t step = 1u << b.level;
        for (const auto& [key, value] : want) {
          const auto [l, u, v, w] = key;
          if (l != e.level + b.level) continue;
          const uint32_t x0 = (c[0] * C + b.origin[0]) / step, y0 = (c[1] * C + b.origin[1]) / step,
                         z0 = (c[2] * C + b.origin[2]) / step;
          if (uint32_t(u) >= x0 && uint32_t(u) < x0 + 8 && uint32_t(v) >= y0 && uint32_t(v) < y0 + 8 && uint32_t(w) >= z0 &&
              uint32_t(w) < z0 + 8)
            ++inRegion;
        }
        EXPECT_EQ(b.voxels.size(), inRegion);
        for (const auto& v : b.voxels) {
          const int u = int((c[0] * C + b.origin[0]) / step + (v.index & 7));
          const int vv = int((c[1] * C + b.origin[1]) / step + ((v.index >> 3) & 7));
          const int w = int((c[2] * C + b.origin[2]) / step + (v.index >> 6));
          const auto it = want.find({e.level + b.level, u, vv, w});
          ASSERT_NE(it, want.end()) << "mip voxel (" << u << "," << vv << "," << w << ") of level " << e.level + b.level;
          EXPECT_EQ(v.summary, it->second.summary);
          EXPECT_EQ(v.surface, it->second.surface);
          EXPECT_EQ(v.color, it->second.color);
          ++mipVoxels;
        }
      }
    }
    EXPECT_GT(mipVoxels, 0u);
  }
}

TEST(PageFile, ColumnsRefuseAColouredInteriorVoxel) {
  vox::SceneHeader h;
  h.dims = {10, 10, 10};
  h.classes.add({1, "a", {}, {}});
  vox::SceneBuilder b(h);
  b.addVotes({1, 2, 3}, 1, 5, true);
  b.addVotes({4, 5, 6}, 1, 5, false);
  b.setColor({4, 5, 6}, {0.5f, 0.5f, 0.5f});
  const vox::Scene sc = std::move(b).build();
  vox::PackSettings p;
  p.layout = Layout::Columns;
  EXPECT_TRUE(voxtest::throwsVoxError([&] { vox::packChunks({&sc}, p); }, vox::ErrorKind::Usage,
                                      {"voxel (4, 5, 6) of level 0 (chunk (0, 0, 0), field 'colors') is interior and has a colour"}));
  p.layout = Layout::Svo;  // the other layouts keep it
  const auto res = vox::packChunks({&sc}, p);
  const Reader r = Reader::fromMemory(res.bytes.data(), res.bytes.size(), "i.vpk");
  std::string why;
  EXPECT_TRUE(sameMaps(unpack(r), expectedVoxels({&sc}), why)) << why;
}

TEST(PageFile, EmptySceneHasNoChunks) {
  vox::SceneHeader h;
  h.dims = {4, 4, 4};
  const vox::Scene empty = vox::SceneBuilder(h).build();
  const auto res = vox::packChunks({&empty}, vox::PackSettings{});
  const Reader r = Reader::fromMemory(res.bytes.data(), res.bytes.size(), "e.vpk");
  EXPECT_TRUE(r.entries().empty());
  EXPECT_EQ(r.verify(), 0u);
  EXPECT_EQ(res.bytes.size(), 4096u);  // header + metadata, padded to the first payload offset
}

// --align auto (the default): 4 KiB when page padding makes the payload area
// at most 1/8 larger than 64-byte padding, else 64 bytes.
TEST(PageFile, AutomaticAlignmentRule) {
  using vox::pagefile::ChunkSlot;
  using vox::pagefile::chooseAlignLog2;
  using vox::pagefile::kAutoAlignCompactLog2;
  using vox::pagefile::kAutoAlignPageLog2;
  auto slots = [](std::initializer_list<std::pair<int, uint64_t>> runs) {  // (count, size) runs
    std::vector<ChunkSlot> out;
    for (const auto& [n, size] : runs)
      for (int i = 0; i < n; ++i) out.push_back({0, uint64_t(out.size()), 1, false, size, 0});
    return out;
  };
  EXPECT_EQ(chooseAlignLog2(slots({})), kAutoAlignPageLog2);
  EXPECT_EQ(chooseAlignLog2(slots({{10, 8192}})), kAutoAlignPageLog2);        // no padding either way
  EXPECT_EQ(chooseAlignLog2(slots({{1, 1}, {1, 65536}})), kAutoAlignPageLog2);  // 69632 <= 65600 * 9/8
  EXPECT_EQ(chooseAlignLog2(slots({{100, 300}})), kAutoAlignCompactLog2);
  // The boundary: 503 chunks of 4 KiB and 64 of 64 bytes make 4 KiB padding
  // exactly 9/8 of 64-byte padding (2322432 = 2064384 + 2064384 / 8); one
  // chunk of 4 KiB fewer tips it.
  EXPECT_EQ(chooseAlignLog2(slots({{503, 4096}, {64, 64}})), kAutoAlignPageLog2);
  EXPECT_EQ(chooseAlignLog2(slots({{502, 4096}, {64, 64}})), kAutoAlignCompactLog2);

  // Packed files: a dense block keeps 4 KiB, a sparse scatter takes 64 bytes;
  // every payload starts at a multiple of what the header says.
  vox::SceneHeader h;
  h.dims = {64, 64, 64};
  h.classes.add({1, "a", {}, {}});
  vox::SceneBuilder dense(h), sparse(h);
  for (int z = 0; z < 64; ++z)
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) dense.addVotes({x, y, z}, 1, 1, true);
  for (int i = 0; i < 50; ++i) sparse.addVotes({(i * 7) % 64, (i * 13) % 64, (i * 29) % 64}, 1, 1, true);
  for (auto& [builder, want] : {std::pair{&dense, kAutoAlignPageLog2}, std::pair{&sparse, kAutoAlignCompactLog2}}) {
    const vox::Scene scene = std::move(*builder).build();
    vox::PackSettings p;
    p.chunkSide = 32;
    EXPECT_EQ(p.alignment, 0u) << "auto is the default";
    const auto res = vox::packChunks({&scene}, p);
    const Reader r = Reader::fromMemory(res.bytes.data(), res.bytes.size(), "a.vpk");
    EXPECT_EQ(r.header().alignLog2, want);
    for (const auto& e : r.entries()) EXPECT_EQ(e.offset % (1u << want), 0u);
    EXPECT_EQ(r.verify(), scene.occupiedCount());
  }
}

TEST(PageFile, RefusesBadSettings) {
  const vox::Scene s = colouredScene();
  vox::PackSettings p;
  p.chunkSide = 12;
  EXPECT_TRUE(voxtest::throwsVoxError([&] { vox::packChunks({&s}, p); }, vox::ErrorKind::Usage, {"8, 16 or 32"}));
  p.chunkSide = 16;
  p.alignment = 100;
  EXPECT_TRUE(voxtest::throwsVoxError([&] { vox::packChunks({&s}, p); }, vox::ErrorKind::Usage, {"power of two"}));
}

// A small file for the corruption tests: a few chunks, alignment 8 unless asked.
std::vector<uint8_t> smallFile(Layout layout = Layout::Bricks, uint32_t C = 8, uint32_t align = 8) {
  vox::SceneHeader h;
  h.dims = {20, 9, 10};
  h.classes.add({1, "a", {}, {}});
  h.classes.add({2, "b", {}, {}});
  vox::SceneBuilder b(h);
  b.addVotes({0, 0, 0}, 1, 3, true);
  b.addVotes({1, 0, 0}, 2, 4, false);
  b.addVotes({19, 8, 9}, 2, 1, true);
  b.addVotes({9, 3, 2}, 1, 2, true);
  b.setColor({0, 0, 0}, {1, 0, 0});
  const vox::Scene s = std::move(b).build();
  vox::MipSettings ms;
  ms.levels = 1;
  const auto mips = vox::buildMipPyramid(s, ms);
  vox::PackSettings p;
  p.chunkSide = C;
  p.alignment = align;
  p.layout = layout;
  return vox::packChunks({&s, &mips[0]}, p).bytes;
}

TEST(PageFile, EveryTruncationIsRefused) {
  for (Layout layout : kLayouts)
    for (uint32_t C : {8u, 16u, 32u}) {
      SCOPED_TRACE(std::string(vox::pagefile::layoutName(layout)) + " C=" + std::to_string(C));
      const std::vector<uint8_t> file = smallFile(layout, C);
      ASSERT_GT(file.size(), 300u);
      ASSERT_LT(file.size(), 30000u);
      EXPECT_EQ(Reader::fromMemory(file.data(), file.size(), "t.vpk").verify(), 4u + 3u);  // level 0 + level 1
      for (size_t n = 0; n < file.size(); ++n) {
        // An exact-size heap copy, so that ASan catches any read past the end.
        std::unique_ptr<uint8_t[]> prefix(new uint8_t[n ? n : 1]);
        std::copy(file.begin(), file.begin() + long(n), prefix.get());
        EXPECT_TRUE(voxtest::throwsVoxError([&] { Reader::fromMemory(prefix.get(), n, "t.vpk").verify(); },
                                            vox::ErrorKind::BadInput, {"t.vpk: "}))
            << "prefix of " << n << " bytes";
      }
      // Truncated past the header: named as such.
      EXPECT_TRUE(voxtest::throwsVoxError([&] { Reader::fromMemory(file.data(), file.size() - 1, "t.vpk"); },
                                          vox::ErrorKind::BadInput, {"file_bytes", "truncated"}));
    }
}

TEST(PageFile, EveryBitFlipInHeaderAndIndexIsDetected) {
  for (Layout layout : kLayouts) {
    SCOPED_TRACE(vox::pagefile::layoutName(layout));
    const std::vector<uint8_t> file = smallFile(layout);
    const Reader ok = Reader::fromMemory(file.data(), file.size(), "f.vpk");
    const size_t end = ok.header().metaOffset + ok.header().metaBytes;  // header, index and metadata
    for (size_t bit = 0; bit < end * 8; ++bit) {
      std::vector<uint8_t> bad = file;
      bad[bit / 8] ^= uint8_t(1u << (bit % 8));
      EXPECT_TRUE(voxtest::throwsVoxError([&] { Reader::fromMemory(bad.data(), bad.size(), "f.vpk"); },
                                          vox::ErrorKind::BadInput, {"f.vpk: "}))
          << "bit " << bit;
    }
    // A flipped payload bit opens, and fails on read naming the chunk and the field.
    for (size_t i = 0; i < ok.entries().size(); ++i)
      for (size_t bit = 0; bit < ok.entries()[i].size * 8; bit += 7) {
        std::vector<uint8_t> bad = file;
        bad[ok.entries()[i].offset + bit / 8] ^= uint8_t(1u << (bit % 8));
        const Reader r = Reader::fromMemory(bad.data(), bad.size(), "f.vpk");
        EXPECT_TRUE(voxtest::throwsVoxError([&] { r.verify(); }, vox::ErrorKind::BadInput,
                                            {r.describe(i) + ": field 'crc32c'"}))
            << "chunk " << i << " bit " << bit;
      }
  }
}

// The chunks of a file, as blobs to re-serialize (with correct CRCs).
std::vector<vox::pagefile::ChunkBlob> blobsOf(const Reader& r) {
  std::vector<vox::pagefile::ChunkBlob> blobs;
  for (size_t i = 0; i < r.entries().size(); ++i) {
    const auto& e = r.entries()[i];
    const auto p = r.payload(i);
    blobs.push_back({e.level, e.key, e.occupied, bool(e.flags & vox::pagefile::kChunkFull), std::vector<uint8_t>(p.begin(), p.end())});
  }
  return blobs;
}

TEST(PageFile, PayloadInconsistentWithItsBitmapIsRefused) {
  // Re-serialize a chunk whose bitmap has an extra bit: the CRC is right, the content is not.
  const std::vector<uint8_t> file = smallFile();
  const Reader ok = Reader::fromMemory(file.data(), file.size(), "f.vpk");
  std::vector<vox::pagefile::ChunkBlob> blobs = blobsOf(ok);
  blobs[0].bytes[10] ^= 0x01;  // voxel 80 of chunk 0: bits say one more voxel than `occupied`
  vox::pagefile::Header h = ok.header();
  const auto bytes = vox::pagefile::serialize(h, ok.metaJson(), blobs);
  const Reader r = Reader::fromMemory(bytes.data(), bytes.size(), "g.vpk");
  EXPECT_TRUE(voxtest::throwsVoxError([&] { r.verify(); }, vox::ErrorKind::BadInput, {"chunk 0", "field 'bitmap'"}));
}

// The header's reserved u32 is 0 in version 1: another value is refused on
// opening, even under a correct header CRC.
TEST(PageFile, HeaderReservedFieldMustBeZero) {
  std::vector<uint8_t> file = smallFile();
  namespace hf = vox::pagefile::header_field;
  file[hf::kReserved] = 7;
  const uint32_t crc = vox::crc32c(file.data(), hf::kHeaderCrc);
  for (int k = 0; k < 4; ++k) file[hf::kHeaderCrc + size_t(k)] = uint8_t(crc >> (8 * k));
  EXPECT_TRUE(voxtest::throwsVoxError([&] { Reader::fromMemory(file.data(), file.size(), "r.vpk"); },
                                      vox::ErrorKind::BadInput, {"r.vpk: header field 'reserved'", "7, must be 0"}));
}

// The bytes between the metadata and the first payload and between payloads
// are zeros. No CRC covers them, so verify() reads every one: each non-zero
// byte is refused naming the chunk it precedes.
TEST(PageFile, VerifyRefusesNonZeroPadding) {
  for (Layout layout : kLayouts) {
    SCOPED_TRACE(vox::pagefile::layoutName(layout));
    const std::vector<uint8_t> file = smallFile(layout, 8, 64);
    const Reader ok = Reader::fromMemory(file.data(), file.size(), "f.vpk");
    EXPECT_EQ(ok.verify(), 7u);
    EXPECT_EQ(vox::pagefile::verifyPageFile(ok), 7u);
    size_t tried = 0;
    uint64_t gapStart = ok.header().metaOffset + ok.header().metaBytes;
    for (size_t i = 0; i < ok.entries().size(); ++i) {
      for (uint64_t at = gapStart; at < ok.entries()[i].offset; ++at, ++tried) {
        std::vector<uint8_t> bad = file;
        bad[at] = 0x20;
        const Reader r = Reader::fromMemory(bad.data(), bad.size(), "f.vpk");  // opens: no CRC covers padding
        EXPECT_TRUE(voxtest::throwsVoxError([&] { r.verify(); }, vox::ErrorKind::BadInput,
                                            {"f.vpk: padding before " + r.describe(i), "byte " + std::to_string(at)}))
            << "byte " << at;
        EXPECT_TRUE(voxtest::throwsVoxError([&] { vox::pagefile::verifyPageFile(r); }, vox::ErrorKind::BadInput,
                                            {"padding before " + r.describe(i)}));
      }
      gapStart = ok.entries()[i].offset + ok.entries()[i].size;
    }
    EXPECT_GT(tried, 64u);
  }
  // A file without chunks: its metadata is padded to the alignment.
  vox::SceneHeader h;
  h.dims = {4, 4, 4};
  const vox::Scene empty = vox::SceneBuilder(h).build();
  std::vector<uint8_t> bytes = vox::packChunks({&empty}, vox::PackSettings{}).bytes;
  bytes[bytes.size() - 1] = 1;
  const Reader r = Reader::fromMemory(bytes.data(), bytes.size(), "e.vpk");
  EXPECT_TRUE(voxtest::throwsVoxError([&] { r.verify(); }, vox::ErrorKind::BadInput,
                                      {"padding before the end of the file"}));
}

// verifyPageFile (`vox pack-chunks --verify`) reads the metadata with the
// reader `vox info` uses: text with a good CRC that is not JSON is refused.
TEST(PageFileVerify, MetadataThatIsNotJsonIsRefused) {
  const std::vector<uint8_t> file = smallFile();
  const Reader ok = Reader::fromMemory(file.data(), file.size(), "f.vpk");
  EXPECT_NO_THROW(vox::pagefile::readPageMeta(ok.metaJson(), "f.vpk"));
  const std::string cut = ok.metaJson().substr(0, ok.metaJson().size() - 1);  // the closing brace
  const auto bytes = vox::pagefile::serialize(ok.header(), cut, blobsOf(ok));
  const Reader r = Reader::fromMemory(bytes.data(), bytes.size(), "m.vpk");
  EXPECT_EQ(r.verify(), 7u);  // the container and the payloads are sound
  EXPECT_TRUE(voxtest::throwsVoxError([&] { vox::pagefile::verifyPageFile(r); }, vox::ErrorKind::BadInput,
                                      {"m.vpk: metadata is not valid JSON"}));
}

// Every voxel's class is in the metadata's class table, in every layout, and
// in the mip bricks of an svo chunk: a summary byte changed under a good CRC
// decodes (class 40 is not 0), and verifyPageFile names the chunk and voxel.
TEST(PageFileVerify, EveryClassIsInTheClassTable) {
  for (Layout layout : kLayouts)
    for (uint32_t C : {8u, 16u, 32u}) {
      SCOPED_TRACE(std::string(vox::pagefile::layoutName(layout)) + " C=" + std::to_string(C));
      const std::vector<uint8_t> file = smallFile(layout, C);
      const Reader ok = Reader::fromMemory(file.data(), file.size(), "f.vpk");
      EXPECT_EQ(vox::pagefile::verifyPageFile(ok), 7u);
      std::vector<vox::pagefile::ChunkBlob> blobs = blobsOf(ok);
      std::vector<uint8_t>& b = blobs[0].bytes;
      ASSERT_FALSE(blobs[0].full);
      const uint32_t N = C * C * C;
      // The first summary record of chunk 0: voxel (0, 0, 0), or in svo with
      // C > 8 the first voxel of the root's mip brick.
      size_t summary = 0;
      if (layout == Layout::Bricks) summary = N / 8;
      if (layout == Layout::Svo) {
        auto u32 = [&](size_t at) { return uint32_t(b[at] | b[at + 1] << 8 | b[at + 2] << 16 | uint32_t(b[at + 3]) << 24); };
        summary = vox::pagefile::kSvoFixedBytes + 16 * size_t(u32(vox::pagefile::svo_field::kNodeCount)) +
                  64 * size_t(u32(vox::pagefile::svo_field::kBitmapCount));
      }
      if (layout == Layout::Columns)
        summary = vox::pagefile::kColumnsFixedBytes + N / 8 + vox::pagefile::columnsLadderBytes(C) +
                  ((ok.header().flags & vox::pagefile::kFlagSurface) ? N / 8 : 0);
      ASSERT_TRUE(b[summary] == 1 || b[summary] == 2) << int(b[summary]);  // a class of the table
      b[summary] = 40;
      const auto bytes = vox::pagefile::serialize(ok.header(), ok.metaJson(), blobs);
      const Reader r = Reader::fromMemory(bytes.data(), bytes.size(), "c.vpk");
      EXPECT_EQ(r.verify(), 7u);  // the layout's own checks pass: class 40 is a class
      const std::string voxel = layout == Layout::Svo && C > 8 ? "mip brick of node 0" : "voxel (0, 0, 0) of level 0";
      EXPECT_TRUE(voxtest::throwsVoxError([&] { vox::pagefile::verifyPageFile(r); }, vox::ErrorKind::BadInput,
                                          {"c.vpk: " + r.describe(0) + ": " + voxel,
                                           "class 40 is not in the metadata's class table (ids 1, 2)"}));
    }
}

// verifyPageFile checks chunks in parallel, yet reports the first faulty
// chunk in index order at any thread count, and counts every voxel.
TEST(PageFileVerify, TheFirstFaultyChunkIsReportedAtAnyThreadCount) {
  vox::SceneHeader h;
  h.dims = {64, 64, 64};
  h.classes.add({1, "a", {}, {}});
  vox::SceneBuilder b(h);
  for (int32_t z = 0; z < 64; z += 4)
    for (int32_t y = 0; y < 64; y += 4)
      for (int32_t x = 0; x < 64; x += 4) b.addVotes({x, y, z}, 1, 1, true);
  const vox::Scene s = std::move(b).build();
  vox::PackSettings p;
  p.chunkSide = 8;
  p.layout = Layout::Bricks;
  const std::vector<uint8_t> file = vox::packChunks({&s}, p).bytes;
  const Reader ok = Reader::fromMemory(file.data(), file.size(), "f.vpk");
  ASSERT_EQ(ok.entries().size(), 512u);
  for (unsigned threads : {1u, 2u, 0u}) EXPECT_EQ(vox::pagefile::verifyPageFile(ok, threads), 4096u);
  std::vector<vox::pagefile::ChunkBlob> blobs = blobsOf(ok);
  for (size_t i : {size_t(100), size_t(300), size_t(511)}) blobs[i].bytes[8 * 8 * 8 / 8] = 40;  // the first summary
  const auto bytes = vox::pagefile::serialize(ok.header(), ok.metaJson(), blobs);
  const Reader r = Reader::fromMemory(bytes.data(), bytes.size(), "c.vpk");
  for (unsigned threads : {1u, 2u, 0u})
    for (int round = 0; round < 20; ++round)
      EXPECT_TRUE(voxtest::throwsVoxError([&] { vox::pagefile::verifyPageFile(r, threads); }, vox::ErrorKind::BadInput,
                                          {"c.vpk: " + r.describe(100) + ": voxel", "class 40"}))
          << "threads " << threads;
}

// Every bit of the structural part of every svo and columns payload (counts,
// nodes, brick table, bitmaps / masks, ladder, colour offsets), flipped under a
// correct CRC, is refused by decode() naming the chunk and a field.
TEST(PageFile, EveryStructuralBitFlipUnderAGoodCrcIsRefused) {
  for (Layout layout : {Layout::Svo, Layout::Columns})
    for (uint32_t C : {8u, 16u, 32u}) {
      SCOPED_TRACE(std::string(vox::pagefile::layoutName(layout)) + " C=" + std::to_string(C));
      const std::vector<uint8_t> file = smallFile(layout, C);
      const Reader ok = Reader::fromMemory(file.data(), file.size(), "f.vpk");
      const auto& h = ok.header();
      const std::vector<vox::pagefile::ChunkBlob> blobs = blobsOf(ok);
      size_t tried = 0;
      for (size_t i = 0; i < blobs.size(); ++i) {
        const auto& b = blobs[i].bytes;
        auto u32 = [&](size_t at) { return uint32_t(b[at] | b[at + 1] << 8 | b[at + 2] << 16 | uint32_t(b[at + 3]) << 24); };
        // Structural ranges [begin, end) of the payload, in bytes.
        std::vector<std::pair<size_t, size_t>> ranges;
        if (layout == Layout::Svo) {
          const size_t B = u32(vox::pagefile::svo_field::kNodeCount), M = u32(vox::pagefile::svo_field::kBitmapCount);
          ranges.push_back({0, vox::pagefile::kSvoFixedBytes + 16 * B + 64 * M});
        } else {
          const uint32_t N = C * C * C;
          const bool full = blobs[i].full;
          const size_t masks = vox::pagefile::kColumnsFixedBytes + (full ? 0 : N / 8 + vox::pagefile::columnsLadderBytes(C)) + ((h.flags & vox::pagefile::kFlagSurface) ? N / 8 : 0);
          ranges.push_back({0, masks});
          if (h.flags & vox::pagefile::kFlagColor) {
            const size_t off = masks + 4ull * blobs[i].occupied;
            ranges.push_back({off, off + 4ull * (C * C + 1)});
          }
        }
        for (const auto& [begin, end] : ranges)
          for (size_t bit = begin * 8; bit < end * 8; ++bit) {
            std::vector<vox::pagefile::ChunkBlob> bad = blobs;
            bad[i].bytes[bit / 8] ^= uint8_t(1u << (bit % 8));
            const auto bytes = vox::pagefile::serialize(h, ok.metaJson(), bad);
            const Reader r = Reader::fromMemory(bytes.data(), bytes.size(), "s.vpk");
            EXPECT_TRUE(voxtest::throwsVoxError([&] { r.decode(i); }, vox::ErrorKind::BadInput, {r.describe(i) + ": ", "field '"}))
                << "chunk " << i << " byte " << bit / 8 << " bit " << bit % 8;
            ++tried;
          }
      }
      EXPECT_GT(tried, 100u);
    }
}

// ------------------------------------------------------------------ the layout table

TEST(PageFileLayouts, TableListsIdsInOrderWithUniqueNames) {
  const auto table = vox::pagefile::layoutTable();
  ASSERT_EQ(table.size(), 3u);
  std::set<std::string> names;
  for (size_t i = 0; i < table.size(); ++i) {
    const auto& l = table[i];
    EXPECT_EQ(uint8_t(l.id), i + 1) << l.name;
    EXPECT_TRUE(names.insert(l.name).second) << l.name;
    EXPECT_EQ(vox::pagefile::findLayout(uint8_t(l.id)), &l);
    EXPECT_EQ(vox::pagefile::findLayout(std::string_view(l.name)), &l);
    EXPECT_EQ(&vox::pagefile::codecOf(l.id), &l);
    EXPECT_STREQ(vox::pagefile::layoutName(l.id), l.name);
    EXPECT_NE(l.encode, nullptr);
    EXPECT_NE(l.decode, nullptr);
  }
  EXPECT_EQ(vox::pagefile::layoutNameList(), "bricks, svo or columns");
  EXPECT_EQ(vox::pagefile::findLayout(uint8_t(0)), nullptr);
  EXPECT_EQ(vox::pagefile::findLayout(uint8_t(table.size() + 1)), nullptr);
  EXPECT_EQ(vox::pagefile::findLayout(std::string_view("octree")), nullptr);
  EXPECT_STREQ(vox::pagefile::layoutName(Layout(0)), "unknown");
  EXPECT_TRUE(voxtest::throwsVoxError([] { vox::pagefile::codecOf(Layout(0)); }, vox::ErrorKind::Internal, {"layout"}));
}

// A header whose layout byte is outside the table is refused, naming the field.
TEST(PageFileLayouts, UnknownLayoutByteIsRefused) {
  std::vector<uint8_t> file = smallFile();
  file[vox::pagefile::header_field::kLayout] = uint8_t(vox::pagefile::layoutTable().size() + 1);
  const uint32_t crc = vox::crc32c(file.data(), vox::pagefile::header_field::kHeaderCrc);
  for (int b = 0; b < 4; ++b) file[vox::pagefile::header_field::kHeaderCrc + size_t(b)] = uint8_t(crc >> (8 * b));
  EXPECT_TRUE(voxtest::throwsVoxError([&] { Reader::fromMemory(file.data(), file.size(), "u.vpk"); },
                                      vox::ErrorKind::BadInput, {"u.vpk: header field 'layout': 4, expected 1..3"}));
}

// The field offsets the writer and the reader share are those PAGEFILE.md gives.
std::map<std::string, size_t> specOffsets(const std::string& section) {
  std::ifstream in(voxtest::sourceDir() + "/formats/pagefile/PAGEFILE.md");
  std::map<std::string, size_t> out;
  const std::regex row(R"(^\| (\d+) \| [^|]+ \| `?([a-z0-9_]+)`? \|)");
  bool inSection = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("## ", 0) == 0) inSection = line.rfind(section, 0) == 0;
    std::smatch m;
    if (inSection && std::regex_search(line, m, row)) out[m[2]] = std::stoul(m[1]);
  }
  return out;
}

TEST(PageFileLayouts, FieldOffsetsAreTheSpecs) {
  namespace hf = vox::pagefile::header_field;
  namespace ef = vox::pagefile::entry_field;
  namespace sf = vox::pagefile::svo_field;
  const std::map<std::string, size_t> header = {
      {"magic", hf::kMagic}, {"version", hf::kVersion}, {"header_bytes", hf::kHeaderBytes}, {"layout", hf::kLayout},
      {"chunk_log2", hf::kChunkLog2}, {"level_count", hf::kLevelCount}, {"align_log2", hf::kAlignLog2},
      {"flags", hf::kFlags}, {"dims", hf::kDims}, {"voxel_size", hf::kVoxelSize}, {"origin", hf::kOrigin},
      {"chunk_count", hf::kChunkCount}, {"index_offset", hf::kIndexOffset}, {"meta_offset", hf::kMetaOffset},
      {"meta_bytes", hf::kMetaBytes}, {"payload_offset", hf::kPayloadOffset}, {"file_bytes", hf::kFileBytes},
      {"meta_crc32c", hf::kMetaCrc}, {"index_crc32c", hf::kIndexCrc}, {"reserved", hf::kReserved},
      {"header_crc32c", hf::kHeaderCrc}};
  const std::map<std::string, size_t> entry = {{"level", ef::kLevel},   {"flags", ef::kFlags},   {"reserved", ef::kReserved},
                                               {"occupied", ef::kOccupied}, {"key", ef::kKey}, {"offset", ef::kOffset},
                                               {"size", ef::kSize},     {"crc32c", ef::kCrc}};
  const std::map<std::string, size_t> svo = {{"node_count", sf::kNodeCount}, {"bitmap_count", sf::kBitmapCount},
                                             {"record_count", sf::kRecordCount}, {"reserved", sf::kReserved},
                                             {"nodes", vox::pagefile::kSvoFixedBytes}};
  EXPECT_EQ(specOffsets("## Header"), header);
  EXPECT_EQ(specOffsets("## Index entry"), entry);
  EXPECT_EQ(specOffsets("## Payload, `svo` layout"), svo);
  EXPECT_EQ(hf::kHeaderCrc + 4, vox::pagefile::kHeaderBytes);
  EXPECT_EQ(ef::kCrc + 4, vox::pagefile::kIndexEntryBytes);
}

// Settings the library refuses carry the setting to change and name no option.
TEST(PageFileLayouts, RefusalsNameTheSettingNotTheOption) {
  const vox::Scene sc = colouredScene();
  auto settingOf = [&](const vox::PackSettings& p) {
    try {
      vox::packChunks({&sc}, p);
    } catch (const vox::Error& e) {
      EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << e.what();
      return e.setting;
    }
    return vox::Setting::None;
  };
  vox::PackSettings p;
  p.chunkSide = 64;
  EXPECT_EQ(settingOf(p), vox::Setting::ChunkSide);
  p = {};
  p.alignment = 4;
  EXPECT_EQ(settingOf(p), vox::Setting::PageAlignment);
  p = {};
  p.layout = Layout(9);
  EXPECT_EQ(settingOf(p), vox::Setting::PageLayout);
  // The column layout cannot store a coloured interior voxel.
  vox::SceneHeader h;
  h.dims = {4, 4, 4};
  h.classes.add({1, "a", {}, {}});
  vox::SceneBuilder b(h);
  b.addVotes({1, 1, 1}, 1, 5, false);
  b.setColor({1, 1, 1}, {0.5f, 0.5f, 0.5f});
  const vox::Scene interior = std::move(b).build();
  p = {};
  p.layout = Layout::Columns;
  try {
    vox::packChunks({&interior}, p);
    ADD_FAILURE() << "no error";
  } catch (const vox::Error& e) {
    EXPECT_EQ(e.setting, vox::Setting::PageLayout);
    EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << e.what();
  }
}

// ------------------------------------------------------------------ metadata

vox::pagefile::PageMeta fullMeta() {
  vox::pagefile::PageMeta m;
  m.toolVersion = "1.2.3";
  m.classes.add({1, "grass", {10, 200, 30}, vox::FacePalette{{1, 2, 3}, {4, 5, 6}, {7, 8, 9}}});
  m.classes.add({7, "water \"deep\" \u00e9", {0, 0, 255}, {}});
  m.sources = {{"meshes/a.obj", "mesh", "ab12", 123456789012ull}, {"demo:hamlet", "demo", "", 0}};
  m.levels = {{0, {37, 20, 33}, 0.25, 12, 3000}, {1, {19, 10, 17}, 0.5, 3, 400}};
  m.mipOccupancy = "from pyramid.vdb";
  m.blockWorld = vox::BlockWorldPlacement{0.1, {64, 48, 64}};
  return m;
}

TEST(PageFileMeta, WriteThenReadGivesTheSameMeta) {
  const vox::pagefile::PageMeta m = fullMeta();
  const std::string text = vox::pagefile::writePageMeta(m);
  EXPECT_EQ(vox::pagefile::readPageMeta(text, "m.vpk"), m);
  EXPECT_EQ(vox::pagefile::writePageMeta(vox::pagefile::readPageMeta(text, "m.vpk")), text);
  // A part's alignment asked: auto (0) and bytes.
  for (uint32_t align : {0u, 64u, 65536u}) {
    vox::pagefile::PageMeta part = fullMeta();
    part.regionAlign = align;
    const std::string partText = vox::pagefile::writePageMeta(part);
    EXPECT_NE(partText.find(align ? "\"region_align\":" + std::to_string(align) : "\"region_align\":\"auto\""),
              std::string::npos);
    EXPECT_EQ(vox::pagefile::readPageMeta(partText, "p.vpk"), part);
  }
  // Without mips, block world, classes or sources: the optional keys are absent.
  vox::pagefile::PageMeta bare;
  bare.toolVersion = "0";
  const std::string bareText = vox::pagefile::writePageMeta(bare);
  EXPECT_EQ(bareText.find("mip_occupancy"), std::string::npos);
  EXPECT_EQ(bareText.find("block_world"), std::string::npos);
  EXPECT_EQ(vox::pagefile::readPageMeta(bareText, "b.vpk"), bare);
}

// The exact text: sorted keys, no whitespace (PAGEFILE.md "Metadata").
TEST(PageFileMeta, TextIsPinned) {
  vox::pagefile::PageMeta m;
  m.toolVersion = "9.9";
  m.classes.add({1, "a", {10, 20, 30}, {}});
  m.sources = {{"m.obj", "mesh", "00", 42}};
  m.levels = {{0, {4, 5, 6}, 0.5, 2, 9}};
  m.mipOccupancy = "majority";
  EXPECT_EQ(vox::pagefile::writePageMeta(m),
            R"({"classes":[{"color":[10,20,30],"id":1,"name":"a"}],"format":"voxbake-pages",)"
            R"("levels":[{"chunks":2,"dims":[4,5,6],"level":0,"voxel_size":0.5,"voxels":9}],"mip_occupancy":"majority",)"
            R"("sources":[{"bytes":42,"kind":"mesh","path":"m.obj","sha256":"00"}],"tool_version":"9.9"})");
}

TEST(PageFileMeta, PackedFilesCarryTheScenesMeta) {
  const vox::Scene base = colouredScene();
  const auto mips = vox::buildMipPyramid(base, vox::MipSettings{});
  std::vector<const vox::Scene*> levels{&base};
  for (const auto& l : mips) levels.push_back(&l);
  vox::PackSettings s;
  s.mipOccupancy = "any";
  const auto res = vox::packChunks(levels, s);
  const Reader r = Reader::fromMemory(res.bytes.data(), res.bytes.size(), "p.vpk");
  const vox::pagefile::PageMeta m = vox::pagefile::readPageMeta(r.metaJson(), r.name());
  EXPECT_EQ(m.toolVersion, vox::kToolVersion);
  EXPECT_EQ(m.classes, base.header().classes);
  EXPECT_EQ(m.sources, base.header().sources);
  EXPECT_EQ(m.mipOccupancy, "any");
  EXPECT_FALSE(m.blockWorld);
  ASSERT_EQ(m.levels.size(), levels.size());
  for (size_t l = 0; l < levels.size(); ++l) {
    const auto [a, b] = r.levelRange(int(l));
    uint64_t voxels = 0;
    for (size_t i = a; i < b; ++i) voxels += r.entries()[i].occupied;
    EXPECT_EQ(m.levels[l].level, l);
    EXPECT_EQ(m.levels[l].dims, r.header().levelDims(int(l)));
    EXPECT_EQ(m.levels[l].voxelSize, levels[l]->header().voxelSize);
    EXPECT_EQ(m.levels[l].chunks, b - a);
    EXPECT_EQ(m.levels[l].voxels, voxels);
  }
}

TEST(PageFileMeta, RefusesBadMetadataNamingTheFileAndKey) {
  auto refused = [](const std::string& text, std::initializer_list<std::string> needles) {
    return voxtest::throwsVoxError([&] { vox::pagefile::readPageMeta(text, "x.vpk"); }, vox::ErrorKind::BadInput, needles);
  };
  for (const char* bad : {R"({"region_align":100})", R"({"region_align":4})", R"({"region_align":"page"})",
                          R"({"region_align":-64})", R"({"region_align":131072})"})
    EXPECT_TRUE(refused(bad, {"x.vpk: metadata 'region_align'", "auto"})) << bad;
  EXPECT_TRUE(refused("{", {"x.vpk: metadata is not valid JSON"}));
  EXPECT_TRUE(refused("[]", {"x.vpk: metadata must be a JSON object"}));
  EXPECT_TRUE(refused(R"({"format":"voxbake-scene"})", {"x.vpk: metadata 'format'", "voxbake-pages"}));
  EXPECT_TRUE(refused(R"({"classes":{}})", {"x.vpk: metadata 'classes' must be a JSON array"}));
  EXPECT_TRUE(refused(R"({"classes":[{"id":0,"name":"a","color":[1,2,3]}]})", {"x.vpk: metadata 'classes'[0] has id 0; ids are 1..255"}));
  EXPECT_TRUE(refused(R"({"classes":[{"id":1,"name":"a"}]})", {"x.vpk: metadata 'classes'[0] needs a \"color\""}));
  EXPECT_TRUE(refused(R"({"classes":[{"id":1,"name":"a","color":[1,2,300]}]})", {"x.vpk: metadata 'classes'[0] \"color\"", "0..255"}));
  EXPECT_TRUE(refused(R"({"classes":[{"id":1,"name":"a","color":[1,2,3],"top":[1,2,3]}]})",
                      {"x.vpk: metadata 'classes'[0] needs all of \"top\", \"bottom\" and \"side\" or none"}));
  EXPECT_TRUE(refused(R"({"classes":[{"id":1,"name":"a","color":[1,2,3]},{"id":1,"name":"b","color":[1,2,3]}]})",
                      {"x.vpk: metadata 'classes'"}));
  EXPECT_TRUE(refused(R"({"sources":[{"path":1}]})", {"x.vpk: metadata 'sources'[0] needs a string \"path\""}));
  EXPECT_TRUE(refused(R"({"levels":[{"level":0,"dims":[1,2]}]})", {"x.vpk: metadata is malformed"}));
  // Unknown keys are ignored; absent keys give empty values.
  EXPECT_EQ(vox::pagefile::readPageMeta(R"({"future":1})", "x.vpk"), vox::pagefile::PageMeta{});
}

}  // namespace
