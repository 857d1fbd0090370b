#include "formats/export/gltf_writer.h"

#include <algorithm>
#include <bit>
#include <future>
#include <limits>
#include <nlohmann/json.hpp>

#include "formats/core/json_text.h"
#include "formats/core/uri_segment.h"
#include "formats/export/output_file.h"
#include "libvox/core/error.h"

namespace vox {

static_assert(std::endian::native == std::endian::little, "glTF buffers are little-endian; so is this writer");

namespace {

using nlohmann::json;

// glTF enums.
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
constexpr int kFloat = 5126, kUnsignedShort = 5123, kUnsignedInt = 5125;
constexpr int kTriangles = 4;
constexpr uint32_t kGlbMagic = 0x46546C67, kChunkJson = 0x4E4F534A, kChunkBin = 0x004E4942;

uint64_t align4(uint64_t n) { return (n + 3) & ~uint64_t(3); }

// Where one primitive's data sits in the buffer.
struct PrimitiveLayout {
  const GltfPrimitive* primitive = nullptr;
  uint64_t vertices = 0, indices = 0;
  int indexType = 0;  // 0: not indexed
  uint64_t vertexOffset = 0, indexOffset = 0, indexBytes = 0;
  std::array<float, 3> min{}, max{};
};

struct BufferPlan {
  std::vector<PrimitiveLayout> primitives;
  uint64_t bytes = 0;
};

// The accessor bounds of POSITION without building the vertices. A vertex's
// coordinate on axis a is float(g * voxelSize + origin[a]) of its grid
// coordinate g (quadVertices: g = block + corner * extent, in double), a
// non-decreasing function of g when voxelSize > 0 (each step is a correctly
// rounded operation on a positive scale). So the smallest and largest
// coordinates are those of the smallest and largest g, and the quads that
// reach them are found from their integer corners: exactly what a pass over
// every vertex finds, at a fraction of its cost (that pass was a tenth of a
// large export's time).
struct GridBounds {
  std::array<double, 3> lo, hi;
  std::array<size_t, 3> loQuad{}, hiQuad{};  // a quad that reaches lo / hi on each axis
};

GridBounds quadGridBounds(std::span<const BlockQuad> quads) {
  // Per face and axis: the smallest and largest corner offset (0 or 1).
  std::array<std::array<std::array<uint8_t, 2>, 3>, 6> cornerRange{};
  for (size_t f = 0; f < 6; ++f)
    for (size_t i = 0; i < 3; ++i) {
      uint8_t lo = 1, hi = 0;
      for (size_t c = 0; c < 4; ++c) {
        const uint8_t v = uint8_t(kBlockFaces[f].corners[c][i]);
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
      cornerRange[f][i] = {lo, hi};
    }
  GridBounds b;
  b.lo.fill(std::numeric_limits<double>::infinity());
  b.hi.fill(-std::numeric_limits<double>::infinity());
  for (size_t k = 0; k < quads.size(); ++k) {
    const BlockQuad& q = quads[k];
    const auto [pa, pb] = inPlaneAxes(q.face);
    std::array<uint32_t, 3> extent{1, 1, 1};
    extent[size_t(pa)] = q.extent[0];
    extent[size_t(pb)] = q.extent[1];
    const int32_t base[3] = {q.block.u, q.block.v, q.block.w};
    for (size_t i = 0; i < 3; ++i) {
      const auto [clo, chi] = cornerRange[size_t(q.face)][i];
      const double lo = double(base[i]) + double(clo) * double(extent[i]);
      const double hi = double(base[i]) + double(chi) * double(extent[i]);
      if (lo < b.lo[i]) b.lo[i] = lo, b.loQuad[i] = k;
      if (hi > b.hi[i]) b.hi[i] = hi, b.hiQuad[i] = k;
    }
  }
  return b;
}

BufferPlan planBuffer(const GltfScene& scene) {
  if (!(scene.frame.voxelSize > 0))  // quadGridBounds relies on it; every scene has one
    throw Error(ErrorKind::Internal, "glTF export of a grid whose voxel size is not positive");
  BufferPlan plan;
  for (const GltfPrimitive& p : scene.primitives) {
    if (p.quads.empty()) continue;
    PrimitiveLayout l;
    l.primitive = &p;
    l.vertices = p.quads.size() * (scene.indexed ? 4 : 6);
    if (scene.indexed) {
      l.indices = p.quads.size() * 6;
      // 65535 is the primitive restart value of UNSIGNED_SHORT indices.
      l.indexType = l.vertices <= 65535 ? kUnsignedShort : kUnsignedInt;
      l.indexBytes = l.indices * (l.indexType == kUnsignedShort ? 2 : 4);
    }
    // The floats themselves come from quadVertices of the quads that reach
    // the extremes, so they are the written vertices' own values.
    const GridBounds bounds = quadGridBounds(p.quads);
    l.min.fill(std::numeric_limits<float>::infinity());
    l.max.fill(-std::numeric_limits<float>::infinity());
    for (size_t a = 0; a < 3; ++a) {
      for (const BlockVertex& v : quadVertices(p.quads[bounds.loQuad[a]], scene.frame))
        l.min[a] = std::min(l.min[a], v.position[a]);
      for (const BlockVertex& v : quadVertices(p.quads[bounds.hiQuad[a]], scene.frame))
        l.max[a] = std::max(l.max[a], v.position[a]);
    }
    l.vertexOffset = plan.bytes;
    plan.bytes += l.vertices * sizeof(BlockVertex);
    l.indexOffset = plan.bytes;
    plan.bytes = align4(plan.bytes + l.indexBytes);
    plan.primitives.push_back(l);
  }
  return plan;
}

json documentJson(const GltfScene& scene, const BufferPlan& plan, const std::string& binUri) {
  json doc;
  doc["asset"] = {{"version", "2.0"}, {"generator", scene.generator}};
  doc["scene"] = 0;
  json sceneJson = {{"name", scene.name}};
  if (plan.primitives.empty()) {
    doc["scenes"] = json::array({sceneJson});  // a scene with no nodes: an empty, valid file
    return doc;
  }
  sceneJson["nodes"] = {0};
  doc["scenes"] = json::array({sceneJson});
  doc["nodes"] = json::array({{{"name", scene.name}, {"mesh", 0}}});
  json buffer = {{"byteLength", plan.bytes}};
  if (!binUri.empty()) buffer["uri"] = binUri;
  doc["buffers"] = json::array({buffer});
  json views = json::array(), accessors = json::array(), primitives = json::array();
  for (const PrimitiveLayout& l : plan.primitives) {
    const size_t vertexView = views.size();
    views.push_back({{"buffer", 0},
                     {"byteOffset", l.vertexOffset},
                     {"byteLength", l.vertices * sizeof(BlockVertex)},
                     {"byteStride", sizeof(BlockVertex)},
                     {"target", kArrayBuffer}});
    auto attribute = [&](size_t offset, const char* type) {
      accessors.push_back({{"bufferView", vertexView},
                           {"byteOffset", offset},
                           {"componentType", kFloat},
                           {"count", l.vertices},
                           {"type", type}});
      return accessors.size() - 1;
    };
    json attributes;
    attributes["POSITION"] = attribute(offsetof(BlockVertex, position), "VEC3");
    accessors.back()["min"] = {l.min[0], l.min[1], l.min[2]};
    accessors.back()["max"] = {l.max[0], l.max[1], l.max[2]};
    attributes["NORMAL"] = attribute(offsetof(BlockVertex, normal), "VEC3");
    attributes["COLOR_0"] = attribute(offsetof(BlockVertex, color), "VEC3");
    attributes["TEXCOORD_0"] = attribute(offsetof(BlockVertex, uv), "VEC2");
    json prim = {{"attributes", attributes}, {"material", l.primitive->material}, {"mode", kTriangles}};
    if (l.indexType) {
      views.push_back({{"buffer", 0},
                       {"byteOffset", l.indexOffset},
                       {"byteLength", l.indexBytes},
                       {"target", kElementArrayBuffer}});
      accessors.push_back({{"bufferView", views.size() - 1},
                           {"componentType", l.indexType},
                           {"count", l.indices},
                           {"type", "SCALAR"}});
      prim["indices"] = accessors.size() - 1;
    }
    primitives.push_back(prim);
  }
  doc["bufferViews"] = views;
  doc["accessors"] = accessors;
  doc["meshes"] = json::array({{{"name", scene.name}, {"primitives", primitives}}});
  json materials = json::array();
  for (const GltfMaterial& m : scene.materials) {
    // Colour comes from COLOR_0; a dielectric, fully rough surface like the
    // block renderer's diffuse shading.
    json mat = {{"name", m.name}, {"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}}};
    if (m.classId) mat["extras"] = {{"vox_class_id", *m.classId}};
    materials.push_back(mat);
  }
  doc["materials"] = materials;
  return doc;
}

// Streams the buffer: each primitive's vertices (then its indices), in
// batches of quads. Expanding quads into vertices costs about as much as the
// kernel's copy of the bytes into the file, so with threads > 1 the next
// batch is expanded on a second thread while this one is written; the bytes
// and their order are the same either way.
constexpr size_t kBatchQuads = 1 << 15;  // 8.6 MB of vertices unindexed

void writeBuffer(const GltfScene& scene, const BufferPlan& plan, OutputFile& out) {
  struct Batch {
    std::span<const BlockQuad> quads;
    std::vector<BlockVertex> vertices;
  };
  auto expand = [&](Batch& b) {
    b.vertices.clear();
    b.vertices.reserve(b.quads.size() * 6);
    for (const BlockQuad& q : b.quads) {
      const std::array<BlockVertex, 4> corners = quadVertices(q, scene.frame);
      if (scene.indexed) b.vertices.insert(b.vertices.end(), corners.begin(), corners.end());
      else
        for (uint8_t c : kQuadTriangles) b.vertices.push_back(corners[c]);
    }
  };
  std::vector<uint8_t> indices;
  for (const PrimitiveLayout& l : plan.primitives) {
    const std::span<const BlockQuad> quads = l.primitive->quads;
    const size_t batches = (quads.size() + kBatchQuads - 1) / kBatchQuads;
    auto batchAt = [&](size_t k) { return quads.subspan(k * kBatchQuads, std::min(kBatchQuads, quads.size() - k * kBatchQuads)); };
    std::array<Batch, 2> slots;
    const bool overlap = scene.threads > 1;
    if (batches) {
      slots[0].quads = batchAt(0);
      expand(slots[0]);
    }
    for (size_t k = 0; k < batches; ++k) {
      Batch& now = slots[k % 2];
      Batch& ahead = slots[(k + 1) % 2];
      std::future<void> next;
      if (k + 1 < batches) {
        ahead.quads = batchAt(k + 1);
        if (overlap) next = std::async(std::launch::async, [&expand, &ahead] { expand(ahead); });
      }
      try {
        out.write(now.vertices.data(), now.vertices.size() * sizeof(BlockVertex));
      } catch (...) {
        if (next.valid()) next.wait();  // the worker writes into `slots`
        throw;
      }
      if (next.valid()) next.get();
      else if (k + 1 < batches) expand(ahead);
    }
    if (!l.indexType) continue;
    const size_t width = l.indexType == kUnsignedShort ? 2 : 4;
    for (size_t first = 0; first < quads.size(); first += kBatchQuads) {
      indices.clear();
      const size_t last = std::min(quads.size(), first + kBatchQuads);
      for (size_t q = first; q < last; ++q)
        for (uint8_t c : kQuadTriangles) {
          const uint32_t index = uint32_t(q * 4 + c);
          for (size_t b = 0; b < width; ++b) indices.push_back(uint8_t(index >> (8 * b)));
        }
      out.write(indices.data(), indices.size());
    }
    out.repeat(0, size_t(align4(l.indexBytes) - l.indexBytes));
  }
}

GltfWriteResult summarize(const BufferPlan& plan) {
  GltfWriteResult r;
  for (const PrimitiveLayout& l : plan.primitives) {
    r.vertices += l.vertices;
    r.indices += l.indices;
    r.triangles += 2 * l.primitive->quads.size();
    r.unindexedBufferBytes += l.primitive->quads.size() * 6 * sizeof(BlockVertex);
  }
  r.bufferBytes = plan.bytes;
  return r;
}

}  // namespace


uint64_t gltfWriteBufferBytes(bool indexed) {
  // Each batch reserves six vertices a quad, indexed or not (expand above).
  const uint64_t vertices = 2 * uint64_t(kBatchQuads) * 6 * sizeof(BlockVertex);
  return vertices + (indexed ? uint64_t(kBatchQuads) * 6 * 4 : 0);
}

GltfWriteResult writeGlb(const GltfScene& scene, const std::string& path) {
  const BufferPlan plan = planBuffer(scene);
  std::string text = jsonText(documentJson(scene, plan, ""));
  text.append(size_t(align4(text.size()) - text.size()), ' ');  // the JSON chunk is padded with spaces
  const uint64_t total = 12 + 8 + text.size() + (plan.bytes ? 8 + plan.bytes : 0);
  if (total > std::numeric_limits<uint32_t>::max())
    throwBadInput(path + ": the mesh needs " + std::to_string(total) +
                  " bytes, more than a .glb can hold (4 GiB); export a smaller region or merge faces");
  OutputFile out(path);
  out.u32(kGlbMagic);
  out.u32(2);
  out.u32(uint32_t(total));
  out.u32(uint32_t(text.size()));
  out.u32(kChunkJson);
  out.write(text);
  if (plan.bytes) {
    out.u32(uint32_t(plan.bytes));
    out.u32(kChunkBin);
    writeBuffer(scene, plan, out);
  }
  out.close();
  GltfWriteResult r = summarize(plan);
  r.fileBytes = total;
  return r;
}

GltfWriteResult writeGltf(const GltfScene& scene, const std::string& path, const std::string& binPath,
                          const std::string& binName) {
  const BufferPlan plan = planBuffer(scene);
  const std::string text = jsonText(documentJson(scene, plan, uriPathSegment(binName)), 1) + "\n";
  OutputFile json(path);
  json.write(text);
  json.close();
  GltfWriteResult r = summarize(plan);
  r.fileBytes = text.size();
  if (plan.bytes) {
    OutputFile bin(binPath);
    writeBuffer(scene, plan, bin);
    bin.close();
    r.fileBytes += plan.bytes;
  }
  return r;
}

}  // namespace vox
