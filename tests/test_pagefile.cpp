#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <tuple>

#include "formats/pagefile.h"
#include "libvox/atlas_content.h"
#include "libvox/demo_hamlet.h"
#include "libvox/mip.h"
#include "libvox/morton.h"
#include "libvox/pack_chunks.h"
#include "libvox/summary_bytes.h"
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
    for (const auto& v : r.decode(i)) {
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

TEST(PageFile, RoundTripEveryChunkSizeWithMips) {
  const vox::Scene base = colouredScene();
  const auto mips = vox::buildMipPyramid(base, vox::MipSettings{});
  std::vector<const vox::Scene*> levels{&base};
  for (const auto& m : mips) levels.push_back(&m);
  const VoxelMap want = expectedVoxels(levels);
  for (uint32_t C : {8u, 16u, 32u})
    for (uint32_t align : {8u, 4096u}) {
      vox::PackSettings s;
      s.chunkSide = C;
      s.alignment = align;
      const vox::PackResult res = vox::packChunks(levels, s);
      const Reader r = Reader::fromMemory(res.bytes.data(), res.bytes.size(), "mem.vpk");
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
        EXPECT_EQ(e->size, vox::pagefile::bricksPayloadBytes(C * C * C, C * C * C, true, r.header().flags));
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
  vox::PackSettings s;
  s.threads = 1;
  const auto one = vox::packChunks(levels, s);
  s.threads = 4;
  const auto four = vox::packChunks(levels, s);
  EXPECT_EQ(one.bytes, four.bytes);
  const Reader r = Reader::fromMemory(one.bytes.data(), one.bytes.size(), "h.vpk");
  EXPECT_EQ(r.header().flags, vox::pagefile::kFlagSurface);  // no colour in the hamlet; interior voxels
  std::string why;
  EXPECT_TRUE(sameMaps(unpack(r), expectedVoxels(levels), why)) << why;
  // Sorted by (level, key); level ranges.
  size_t total = 0;
  for (int l = 0; l < r.header().levelCount; ++l) {
    const auto [a, b] = r.levelRange(l);
    EXPECT_LT(a, b);
    total += b - a;
  }
  EXPECT_EQ(total, r.entries().size());
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

TEST(PageFile, RefusesBadSettings) {
  const vox::Scene s = colouredScene();
  vox::PackSettings p;
  p.chunkSide = 12;
  EXPECT_TRUE(voxtest::throwsVoxError([&] { vox::packChunks({&s}, p); }, vox::ErrorKind::Usage, {"8, 16 or 32"}));
  p.chunkSide = 16;
  p.alignment = 100;
  EXPECT_TRUE(voxtest::throwsVoxError([&] { vox::packChunks({&s}, p); }, vox::ErrorKind::Usage, {"power of two"}));
}

// A small file for the corruption tests: a few chunks of 8^3, alignment 8.
std::vector<uint8_t> smallFile() {
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
  const auto mips = vox::buildMipPyramid(s, vox::MipSettings{.levels = 1});
  vox::PackSettings p;
  p.chunkSide = 8;
  p.alignment = 8;
  return vox::packChunks({&s, &mips[0]}, p).bytes;
}

TEST(PageFile, EveryTruncationIsRefused) {
  const std::vector<uint8_t> file = smallFile();
  ASSERT_GT(file.size(), 300u);
  ASSERT_LT(file.size(), 4000u);
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
  EXPECT_EQ(Reader::fromMemory(file.data(), file.size(), "t.vpk").verify(), 4u + 3u);  // level 0 + level 1
}

TEST(PageFile, EveryBitFlipInHeaderAndIndexIsDetected) {
  const std::vector<uint8_t> file = smallFile();
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
  std::vector<uint8_t> bad = file;
  const auto& e = ok.entries()[1];
  bad[e.offset + 3] ^= 0x10;
  const Reader r = Reader::fromMemory(bad.data(), bad.size(), "f.vpk");
  EXPECT_TRUE(voxtest::throwsVoxError([&] { r.verify(); }, vox::ErrorKind::BadInput,
                                      {"chunk 1 (level 0, chunk (", "field 'crc32c'"}));
}

TEST(PageFile, PayloadInconsistentWithItsBitmapIsRefused) {
  // Re-serialize a chunk whose bitmap has an extra bit: the CRC is right, the content is not.
  const std::vector<uint8_t> file = smallFile();
  const Reader ok = Reader::fromMemory(file.data(), file.size(), "f.vpk");
  std::vector<vox::pagefile::ChunkBlob> blobs;
  for (size_t i = 0; i < ok.entries().size(); ++i) {
    const auto& e = ok.entries()[i];
    const auto p = ok.payload(i);
    blobs.push_back({e.level, e.key, e.occupied, bool(e.flags & 1), std::vector<uint8_t>(p.begin(), p.end())});
  }
  blobs[0].bytes[10] ^= 0x01;  // voxel 80 of chunk 0: bits say one more voxel than `occupied`
  vox::pagefile::Header h = ok.header();
  const auto bytes = vox::pagefile::serialize(h, ok.metaJson(), blobs);
  const Reader r = Reader::fromMemory(bytes.data(), bytes.size(), "g.vpk");
  EXPECT_TRUE(voxtest::throwsVoxError([&] { r.verify(); }, vox::ErrorKind::BadInput, {"chunk 0", "field 'bitmap'"}));
}

}  // namespace
