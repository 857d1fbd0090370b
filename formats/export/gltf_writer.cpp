#include "formats/export/gltf_writer.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <nlohmann/json.hpp>

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

BufferPlan planBuffer(const GltfScene& scene) {
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
    l.min.fill(std::numeric_limits<float>::infinity());
    l.max.fill(-std::numeric_limits<float>::infinity());
    for (const BlockQuad& q : p.quads)
      for (const BlockVertex& v : quadVertices(q, scene.frame))
        for (int a = 0; a < 3; ++a) {
          l.min[size_t(a)] = std::min(l.min[size_t(a)], v.position[size_t(a)]);
          l.max[size_t(a)] = std::max(l.max[size_t(a)], v.position[size_t(a)]);
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

// Streams the buffer: each primitive's vertices (then its indices), in blocks.
void writeBuffer(const GltfScene& scene, const BufferPlan& plan, OutputFile& out) {
  constexpr size_t kBlockQuads = 4096;
  std::vector<BlockVertex> vertices;
  std::vector<uint8_t> indices;
  vertices.reserve(kBlockQuads * 6);
  for (const PrimitiveLayout& l : plan.primitives) {
    const std::span<const BlockQuad> quads = l.primitive->quads;
    for (size_t first = 0; first < quads.size(); first += kBlockQuads) {
      vertices.clear();
      const size_t last = std::min(quads.size(), first + kBlockQuads);
      for (size_t q = first; q < last; ++q) {
        const std::array<BlockVertex, 4> corners = quadVertices(quads[q], scene.frame);
        if (scene.indexed) vertices.insert(vertices.end(), corners.begin(), corners.end());
        else
          for (uint8_t c : kQuadTriangles) vertices.push_back(corners[c]);
      }
      out.write(vertices.data(), vertices.size() * sizeof(BlockVertex));
    }
    if (!l.indexType) continue;
    const size_t width = l.indexType == kUnsignedShort ? 2 : 4;
    for (size_t first = 0; first < quads.size(); first += kBlockQuads) {
      indices.clear();
      const size_t last = std::min(quads.size(), first + kBlockQuads);
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

GltfWriteResult writeGlb(const GltfScene& scene, const std::string& path) {
  const BufferPlan plan = planBuffer(scene);
  std::string text = documentJson(scene, plan, "").dump();
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
                          const std::string& binUri) {
  const BufferPlan plan = planBuffer(scene);
  const std::string text = documentJson(scene, plan, binUri).dump(1) + "\n";
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
