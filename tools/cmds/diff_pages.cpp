// vox diff of page files (.vpk): the header field by field, the metadata as
// JSON, then chunk by chunk in (level, Morton key) order, each chunk decoded to
// its voxels, so a difference is named by level, chunk and voxel, never by a
// byte offset. Two chunks with identical payload bytes (same layout and chunk
// side) are equal without decoding.
#include <cstring>
#include <iostream>
#include <sstream>

#include "formats/core/json_diff.h"
#include "formats/core/json_text.h"
#include "formats/pagefile/pagefile.h"
#include "libvox/core/number_text.h"
#include "libvox/core/parallel.h"
#include "tools/cli/cli.h"
#include "tools/cmds/diff_common.h"

namespace voxcli {

namespace {

namespace pf = vox::pagefile;

// Exact but short: "0.8", not "0.80000000000000004".
std::string num(double x) { return vox::shortestText(x); }

struct FieldDiff {
  std::string field, a, b;
};

std::vector<FieldDiff> headerDiffs(const pf::Header& a, const pf::Header& b) {
  std::vector<FieldDiff> d;
  auto add = [&](const char* f, const std::string& x, const std::string& y) {
    if (x != y) d.push_back({f, x, y});
  };
  auto dims = [](const std::array<uint32_t, 3>& v) {
    return std::to_string(v[0]) + " x " + std::to_string(v[1]) + " x " + std::to_string(v[2]);
  };
  add("layout", pf::layoutName(a.layout), pf::layoutName(b.layout));
  add("chunk_side", std::to_string(a.chunkSide()), std::to_string(b.chunkSide()));
  add("levels", std::to_string(a.levelCount), std::to_string(b.levelCount));
  add("alignment", std::to_string(1u << a.alignLog2), std::to_string(1u << b.alignLog2));
  add("color", a.flags & pf::kFlagColor ? "yes" : "no", b.flags & pf::kFlagColor ? "yes" : "no");
  add("surface", a.flags & pf::kFlagSurface ? "yes" : "no", b.flags & pf::kFlagSurface ? "yes" : "no");
  add("dims", dims(a.dims), dims(b.dims));
  add("voxel_size", num(a.voxelSize), num(b.voxelSize));
  add("origin", num(a.origin[0]) + ", " + num(a.origin[1]) + ", " + num(a.origin[2]),
      num(b.origin[0]) + ", " + num(b.origin[1]) + ", " + num(b.origin[2]));
  add("chunk_count", std::to_string(a.chunkCount), std::to_string(b.chunkCount));
  return d;
}

// A chunk of either file: indices into both entry lists (npos when absent).
constexpr size_t kNone = size_t(-1);
struct ChunkPair {
  size_t ia = kNone, ib = kNone;
};

struct VoxelRef {
  uint32_t index = 0;  // chunk-local
  std::optional<pf::DecodedVoxel> a, b;
};

struct ChunkResult {
  bool differs = false;
  uint64_t voxelsDiffering = 0;
  std::array<uint64_t, 4> kinds{};  // occupancy, summary, surface, color
  std::optional<VoxelRef> first;   // smallest chunk-local index
  std::string note;                // "only in A", "occupied 12 vs 13"
};

const char* kKindNames[4] = {"occupancy", "summary", "surface", "color"};

ChunkResult compareChunk(const pf::Reader& ra, const pf::Reader& rb, const ChunkPair& p, bool sameCodec,
                         uint32_t colorTolerance) {
  ChunkResult r;
  std::vector<pf::DecodedVoxel> va, vb;
  if (p.ia != kNone && p.ib != kNone) {
    const pf::IndexEntry& ea = ra.entries()[p.ia];
    const pf::IndexEntry& eb = rb.entries()[p.ib];
    if (sameCodec && ea.size == eb.size && ea.crc == eb.crc && ea.flags == eb.flags && ea.occupied == eb.occupied) {
      const auto pa = ra.payload(p.ia), pb = rb.payload(p.ib);
      if (std::memcmp(pa.data(), pb.data(), pa.size()) == 0) return r;
    }
    va = ra.decode(p.ia), vb = rb.decode(p.ib);
    if (ea.occupied != eb.occupied)
      r.note = "occupied " + std::to_string(ea.occupied) + " vs " + std::to_string(eb.occupied);
  } else if (p.ia != kNone) {
    va = ra.decode(p.ia);
    r.note = "only in A";
  } else {
    vb = rb.decode(p.ib);
    r.note = "only in B";
  }
  size_t i = 0, j = 0;
  while (i < va.size() || j < vb.size()) {
    VoxelRef v;
    if (j == vb.size() || (i < va.size() && va[i].index < vb[j].index)) {
      v.index = va[i].index, v.a = va[i++];
    } else if (i == va.size() || vb[j].index < va[i].index) {
      v.index = vb[j].index, v.b = vb[j++];
    } else {
      v.index = va[i].index, v.a = va[i++], v.b = vb[j++];
    }
    bool differs = false;
    if (v.a.has_value() != v.b.has_value()) {
      ++r.kinds[0], differs = true;
    } else {
      if (v.a->summary != v.b->summary) ++r.kinds[1], differs = true;
      if (v.a->surface != v.b->surface) ++r.kinds[2], differs = true;
      uint32_t dc = 0;
      for (int k = 0; k < 4; ++k) dc = std::max<uint32_t>(dc, uint32_t(std::abs(int(v.a->color[size_t(k)]) - int(v.b->color[size_t(k)]))));
      if (dc > colorTolerance || (v.a->color[3] != v.b->color[3])) ++r.kinds[3], differs = true;
    }
    if (!differs) continue;
    ++r.voxelsDiffering;
    if (!r.first) r.first = v;
  }
  r.differs = r.voxelsDiffering > 0 || p.ia == kNone || p.ib == kNone;
  return r;
}

nlohmann::json voxelJson(const std::optional<pf::DecodedVoxel>& v) {
  if (!v) return nullptr;
  return {{"summary", {v->summary[0], v->summary[1], v->summary[2], v->summary[3]}},
          {"surface", v->surface},
          {"color", {v->color[0], v->color[1], v->color[2], v->color[3]}}};
}

std::string voxelText(const std::optional<pf::DecodedVoxel>& v) {
  if (!v) return "empty";
  char buf[128];
  std::snprintf(buf, sizeof buf, "summary (cls %d, conf %d, obs %d, mrg %d) %s color %d,%d,%d,%d", v->summary[0],
                v->summary[1], v->summary[2], v->summary[3], v->surface ? "surface" : "interior", v->color[0],
                v->color[1], v->color[2], v->color[3]);
  return buf;
}

}  // namespace

int diffPageFiles(const DiffOptions& o) {
  const pf::Reader ra = pf::Reader::open(o.a);
  const pf::Reader rb = pf::Reader::open(o.b);
  const std::vector<FieldDiff> header = headerDiffs(ra.header(), rb.header());
  // The metadata as JSON, without the version of the tool that wrote it (a
  // golden file stays valid across releases that pack the same voxels).
  vox::JsonDiffOptions metaOptions;
  metaOptions.ignoreKeys.push_back("tool_version");
  const vox::JsonDiff meta = vox::diffJson(vox::parseJsonDocument(ra.metaJson(), o.a + " metadata"),
                                           vox::parseJsonDocument(rb.metaJson(), o.b + " metadata"), metaOptions);
  const uint32_t side = ra.header().chunkSide();
  const bool comparable = ra.header().chunkLog2 == rb.header().chunkLog2;
  std::vector<ChunkPair> pairs;
  std::vector<ChunkResult> results;
  if (comparable) {
    // Merge join on (level, key): both indexes are sorted that way.
    const auto& ea = ra.entries();
    const auto& eb = rb.entries();
    size_t i = 0, j = 0;
    while (i < ea.size() || j < eb.size()) {
      auto key = [](const pf::IndexEntry& e) { return std::pair(e.level, e.key); };
      if (j == eb.size() || (i < ea.size() && key(ea[i]) < key(eb[j]))) pairs.push_back({i++, kNone});
      else if (i == ea.size() || key(eb[j]) < key(ea[i])) pairs.push_back({kNone, j++});
      else pairs.push_back({i++, j++});
    }
    results.resize(pairs.size());
    const bool sameCodec = ra.header().layout == rb.header().layout && ra.header().flags == rb.header().flags;
    const uint32_t colorTol = uint32_t(std::lround(o.colorTolerance * 255.0));
    vox::parallelForEach(pairs.size(), o.threads, 16, [&](size_t k) {
      results[k] = compareChunk(ra, rb, pairs[k], sameCodec, colorTol);
    });
  }
  uint64_t chunksDiffering = 0, onlyA = 0, onlyB = 0, voxelsDiffering = 0;
  std::array<uint64_t, 4> kinds{};
  std::optional<size_t> firstChunk;
  for (size_t k = 0; k < results.size(); ++k) {
    if (!results[k].differs) continue;
    ++chunksDiffering;
    if (pairs[k].ia == kNone) ++onlyB;
    if (pairs[k].ib == kNone) ++onlyA;
    voxelsDiffering += results[k].voxelsDiffering;
    for (int q = 0; q < 4; ++q) kinds[size_t(q)] += results[k].kinds[size_t(q)];
    if (!firstChunk) firstChunk = k;
  }
  const bool same = header.empty() && meta.same() && comparable && chunksDiffering == 0;

  auto chunkInfo = [&](size_t k) {
    const ChunkPair& p = pairs[k];
    const pf::IndexEntry& e = p.ia != kNone ? ra.entries()[p.ia] : rb.entries()[p.ib];
    const auto c = e.chunk();
    const ChunkResult& r = results[k];
    nlohmann::json j = {{"level", e.level}, {"chunk", {c[0], c[1], c[2]}}, {"key", e.key},
                        {"voxels_differing", r.voxelsDiffering}};
    if (!r.note.empty()) j["note"] = r.note;
    if (r.first) {
      const uint32_t x = r.first->index % side, y = (r.first->index / side) % side, z = r.first->index / (side * side);
      j["first_voxel"] = {{"local", {x, y, z}},
                          {"voxel", {c[0] * side + x, c[1] * side + y, c[2] * side + z}},
                          {"a", voxelJson(r.first->a)},
                          {"b", voxelJson(r.first->b)}};
      j["first_voxel_text"] = "voxel (" + std::to_string(c[0] * side + x) + ", " + std::to_string(c[1] * side + y) +
                              ", " + std::to_string(c[2] * side + z) + ") of level " + std::to_string(e.level) +
                              ", local (" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) +
                              "): A " + voxelText(r.first->a) + " | B " + voxelText(r.first->b);
    }
    return j;
  };

  if (o.json) {
    nlohmann::json h = nlohmann::json::array();
    for (const FieldDiff& f : header) h.push_back({{"field", f.field}, {"a", f.a}, {"b", f.b}});
    nlohmann::json k = nlohmann::json::object();
    for (int q = 0; q < 4; ++q) k[kKindNames[q]] = kinds[size_t(q)];
    nlohmann::json j = {{"kind", "pages"},
                        {"a", o.a},
                        {"b", o.b},
                        {"same", same},
                        {"header", h},
                        {"metadata_same", meta.same()},
                        {"chunks_a", ra.entries().size()},
                        {"chunks_b", rb.entries().size()},
                        {"chunks_compared", pairs.size()},
                        {"chunks_differing", chunksDiffering},
                        {"chunks_only_in_a", onlyA},
                        {"chunks_only_in_b", onlyB},
                        {"voxels_differing", voxelsDiffering},
                        {"voxel_kinds", k}};
    if (!meta.same() && !meta.differences.empty())
      j["metadata_first_difference"] = {{"pointer", meta.differences[0].pointer},
                                        {"a", meta.differences[0].a},
                                        {"b", meta.differences[0].b}};
    if (firstChunk) j["first_chunk"] = chunkInfo(*firstChunk);
    nlohmann::json list = nlohmann::json::array();
    for (size_t q = 0; q < results.size() && list.size() < 20; ++q)
      if (results[q].differs) list.push_back(chunkInfo(q));
    j["differing_chunks"] = list;
    std::cout << vox::jsonText(j, 2) << "\n";
  } else {
    std::ostringstream s;
    s << (same ? "same" : "DIFFERENT") << ": page files, " << counted(pairs.size(), "chunk", "chunks") << " compared, "
      << chunksDiffering << " differ, " << counted(voxelsDiffering, "voxel differs", "voxels differ") << "\n";
    for (const FieldDiff& f : header) s << "  header " << f.field << ": " << f.a << " vs " << f.b << "\n";
    if (!comparable) s << "  chunk sides differ: chunks cannot be compared one for one\n";
    if (!meta.same() && !meta.differences.empty())
      s << "  metadata differs at " << pointerText(meta.differences[0].pointer) << ": " << meta.differences[0].a << " vs "
        << meta.differences[0].b << "\n";
    if (chunksDiffering) {
      s << "  chunks only in A " << onlyA << ", only in B " << onlyB << "; voxels:";
      for (int q = 0; q < 4; ++q) s << " " << kKindNames[q] << " " << kinds[size_t(q)];
      s << "\n";
      size_t shown = 0;
      for (size_t q = 0; q < results.size() && shown < 5; ++q) {
        if (!results[q].differs) continue;
        ++shown;
        const nlohmann::json c = chunkInfo(q);
        s << "  chunk (" << c["chunk"][0] << ", " << c["chunk"][1] << ", " << c["chunk"][2] << ") of level "
          << c["level"] << " (key " << c["key"] << "): "
          << counted(c["voxels_differing"].get<uint64_t>(), "voxel differs", "voxels differ");
        if (c.contains("note")) s << " (" << c["note"].get<std::string>() << ")";
        s << "\n";
        if (c.contains("first_voxel_text")) s << "    first " << c["first_voxel_text"].get<std::string>() << "\n";
      }
      if (chunksDiffering > shown)
        s << "  ... " << counted(chunksDiffering - shown, "more chunk", "more chunks") << " (--json lists 20)\n";
    }
    std::cout << s.str();
  }
  return same ? kExitOk : kExitCheckFailed;
}

}  // namespace voxcli
