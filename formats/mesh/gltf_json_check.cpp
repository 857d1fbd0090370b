#include "formats/mesh/gltf_json_check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <nlohmann/json.hpp>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/core/json_input.h"
#include "libvox/core/counted.h"
#include "libvox/core/error.h"

namespace vox {

namespace {

using nlohmann::json;

// Extensions vox reads (KHR_mesh_quantization: the accessor reader takes every
// component type and the normalized flag; KHR_draco_mesh_compression:
// gltf_draco.h; EXT_meshopt_compression: gltf_meshopt.h; KHR_texture_transform
// and EXT_mesh_gpu_instancing: gltf_reader.cpp; EXT_texture_webp: gltf_images.h), and extensions that only
// change lights or shading vox does not bake, so the voxels cannot change.
constexpr std::array<const char*, 6> kHonoured = {"KHR_mesh_quantization", "KHR_draco_mesh_compression",
                                                  "EXT_meshopt_compression", "KHR_texture_transform",
                                                  "EXT_mesh_gpu_instancing", "EXT_texture_webp"};
constexpr std::array<const char*, 1> kNoEffectOnVoxels = {"KHR_lights_punctual"};

/// KHR_materials_* extensions shade on top of the base colour (clearcoat,
/// sheen, transmission, unlit, variants' default...): none changes the base
/// colour or the geometry, so none can change the voxels. The exception,
/// KHR_materials_pbrSpecularGlossiness, replaces the base colour: it is read
/// (its diffuseFactor and diffuseTexture, gltf_reader.cpp).
bool materialShadingOnly(const std::string& ext) { return ext.rfind("KHR_materials_", 0) == 0; }

template <size_t N>
bool listed(const std::array<const char*, N>& names, const std::string& s) {
  for (const char* n : names)
    if (s == n) return true;
  return false;
}

class Checker {
 public:
  Checker(const json& doc, const std::string& path) : doc_(doc), path_(path) {}

  void run() {
    extensions();
    defaultScene();
    for (size_t i = 0; i < size("bufferViews"); ++i) bufferView(i);
    for (size_t i = 0; i < size("accessors"); ++i) accessor(i);
    for (size_t i = 0; i < size("meshes"); ++i) mesh(i);
    for (size_t i = 0; i < size("nodes"); ++i) node(i);
    for (size_t i = 0; i < size("scenes"); ++i) scene(i);
    for (size_t i = 0; i < size("materials"); ++i) material(i);
    for (size_t i = 0; i < size("textures"); ++i) texture(i);
  }

 private:
  size_t size(const char* array) const {
    auto it = doc_.find(array);
    return it != doc_.end() && it->is_array() ? it->size() : 0;
  }

  [[noreturn]] void bad(const std::string& element, const std::string& what) const {
    throwBadInput(path_ + ": " + element + " " + what + "; the file is malformed (re-export it, or check it with "
                  "the Khronos glTF validator)");
  }

  /// obj[key] when present: an integer in [lo, hi], else an error naming `element.key`.
  std::optional<int64_t> integer(const json& obj, const char* key, const std::string& element, int64_t lo,
                                 int64_t hi) const {
    auto it = obj.find(key);
    if (it == obj.end()) return std::nullopt;
    const std::string name = element + "." + key;
    if (it->is_number_unsigned() && it->get<uint64_t>() > uint64_t(hi))
      bad(name, "is " + it->dump() + ", above its limit " + std::to_string(hi));
    if (!it->is_number_integer()) bad(name, "is " + it->dump().substr(0, 40) + ", not an integer");
    const int64_t v = it->get<int64_t>();
    if (v < lo || v > hi)
      bad(name, "is " + std::to_string(v) + ", outside " + std::to_string(lo) + ".." + std::to_string(hi));
    return v;
  }

  /// obj[key], when present, indexes an existing element of the top-level array `target`.
  void reference(const json& obj, const char* key, const std::string& element, const char* target) const {
    const size_t n = size(target);
    auto it = obj.find(key);
    if (it == obj.end()) return;
    const std::string name = element + "." + key;
    if (n == 0) bad(name, "refers to " + std::string(target) + " but the file has none");
    if (!it->is_number_integer() || it->get<int64_t>() < 0 || uint64_t(it->get<int64_t>()) >= n)
      bad(name, "is " + it->dump().substr(0, 40) + ", but the file's " + target + " are 0.." + std::to_string(n - 1));
  }

  void extensions() const {
    auto it = doc_.find("extensionsRequired");
    if (it == doc_.end() || !it->is_array()) return;
    for (const json& e : *it) {
      if (!e.is_string()) bad("extensionsRequired", "holds a non-string entry");
      const std::string ext = e.get<std::string>();
      if (!listed(kHonoured, ext) && !listed(kNoEffectOnVoxels, ext) && !materialShadingOnly(ext))
        throwBadInput(path_ + ": requires the extension " + ext + ", which vox does not support and which could "
                      "change the voxels; convert the file without it (e.g. with gltf-transform)");
    }
  }

  void bufferView(size_t i) const {
    const json& v = doc_["bufferViews"][i];
    const std::string el = "bufferViews[" + std::to_string(i) + "]";
    if (!v.is_object()) bad(el, "is not an object");
    reference(v, "buffer", el, "buffers");
    const int64_t offset = integer(v, "byteOffset", el, 0, INT64_MAX).value_or(0);
    const std::optional<int64_t> length = integer(v, "byteLength", el, 1, INT64_MAX);
    // Inside its buffer (tinygltf hands image bufferViews to the image reader unchecked).
    auto buffer = v.find("buffer");
    if (length && buffer != v.end() && buffer->is_number_unsigned() && buffer->get<uint64_t>() < size("buffers")) {
      const json& b = doc_["buffers"][size_t(buffer->get<uint64_t>())];
      auto bl = b.is_object() ? b.find("byteLength") : b.end();
      if (b.is_object() && bl != b.end() && bl->is_number_unsigned() &&
          (uint64_t(offset) > bl->get<uint64_t>() || uint64_t(*length) > bl->get<uint64_t>() - uint64_t(offset)))
        bad(el, "spans bytes " + std::to_string(offset) + ".." + std::to_string(uint64_t(offset) + uint64_t(*length)) +
                    ", past the end of buffer " + std::to_string(buffer->get<uint64_t>()) + " (" +
                    counted(bl->get<uint64_t>(), "byte", "bytes") + ")");
    }
    if (auto stride = integer(v, "byteStride", el, 4, 252); stride && *stride % 4 != 0)
      bad(el + ".byteStride", "is " + std::to_string(*stride) + ", not a multiple of 4");
  }

  void accessor(size_t i) const {
    const json& a = doc_["accessors"][i];
    const std::string el = "accessors[" + std::to_string(i) + "]";
    if (!a.is_object()) bad(el, "is not an object");
    reference(a, "bufferView", el, "bufferViews");
    integer(a, "byteOffset", el, 0, INT64_MAX);
    integer(a, "count", el, 1, INT32_MAX);
    auto sparse = a.find("sparse");
    if (sparse != a.end() && sparse->is_object()) {
      const int64_t count = integer(a, "count", el, 1, INT32_MAX).value_or(0);
      integer(*sparse, "count", el + ".sparse", 1, std::max<int64_t>(count, 1));
      for (const char* part : {"indices", "values"}) {
        auto p = sparse->find(part);
        if (p == sparse->end() || !p->is_object()) continue;
        const std::string pel = el + ".sparse." + part;
        reference(*p, "bufferView", pel, "bufferViews");
        integer(*p, "byteOffset", pel, 0, INT64_MAX);
      }
    }
  }

  void mesh(size_t i) const {
    const json& m = doc_["meshes"][i];
    auto prims = m.find("primitives");
    if (prims == m.end() || !prims->is_array()) return;
    for (size_t p = 0; p < prims->size(); ++p) {
      const json& prim = (*prims)[p];
      const std::string el = "meshes[" + std::to_string(i) + "].primitives[" + std::to_string(p) + "]";
      if (!prim.is_object()) bad(el, "is not an object");
      reference(prim, "material", el, "materials");
      reference(prim, "indices", el, "accessors");
      const int64_t mode = integer(prim, "mode", el, 0, 6).value_or(4);
      auto attrs = prim.find("attributes");
      if (attrs != prim.end() && attrs->is_object())
        for (auto it = attrs->begin(); it != attrs->end(); ++it) reference(*attrs, it.key().c_str(), el + ".attributes", "accessors");
      const json* position = nullptr;
      if (attrs != prim.end() && attrs->is_object() && attrs->contains("POSITION")) {
        position = &accessorAt((*attrs)["POSITION"]);
        positionAccessor(*position, el + ".attributes.POSITION", (*attrs)["POSITION"].get<int64_t>());
      }
      // TRIANGLES takes 3 vertices per triangle: a count that is not a
      // multiple of 3 is not a list of triangles (the specification says it
      // must be), and reading it would drop or invent a vertex.
      const json* counted = prim.contains("indices") ? &accessorAt(prim["indices"]) : position;
      if (mode == 4 && counted && counted->is_object() && counted->contains("count") &&
          (*counted)["count"].is_number_unsigned() && (*counted)["count"].get<uint64_t>() % 3 != 0)
        bad(el, "is in mode TRIANGLES but its " + std::string(prim.contains("indices") ? "indices" : "POSITION") +
                    " accessor " + (prim.contains("indices") ? prim["indices"] : (*attrs)["POSITION"]).dump() +
                    " has " + (*counted)["count"].dump() + " elements, not a multiple of 3");
    }
  }

  /// The accessor an index checked by reference() names.
  const json& accessorAt(const json& index) const { return doc_["accessors"][size_t(index.get<int64_t>())]; }

  /// A POSITION accessor is a VEC3 of floats, or with KHR_mesh_quantization of
  /// (normalized or not) 8- or 16-bit integers too (glTF 2.0, "Meshes"; the
  /// extension's table). Another type would be read as what it is not: a VEC2
  /// as pairs, bytes as if the file had asked for quantization.
  void positionAccessor(const json& a, const std::string& el, int64_t index) const {
    if (!a.is_object()) return;
    const std::string which = el + " (accessor " + std::to_string(index) + ")";
    auto type = a.find("type");
    if (type == a.end() || !type->is_string() || type->get<std::string>() != "VEC3")
      bad(which, "has type " + (type == a.end() ? std::string("(none)") : type->dump().substr(0, 40)) +
                     ", but positions are VEC3");
    auto component = a.find("componentType");
    if (component == a.end() || !component->is_number_integer()) return;  // tinygltf refuses it
    const int64_t c = component->get<int64_t>();
    if (c == 5126) return;  // FLOAT
    const bool integer = c == 5120 || c == 5121 || c == 5122 || c == 5123;
    if (integer && usesExtension("KHR_mesh_quantization")) return;
    bad(which, "has componentType " + std::to_string(c) +
                   (integer ? " (an 8- or 16-bit integer), which positions may have only in a file that uses "
                              "KHR_mesh_quantization (extensionsUsed and extensionsRequired); positions are "
                              "otherwise FLOAT (5126)"
                            : ", but positions are FLOAT (5126), or with KHR_mesh_quantization 5120-5123"));
  }

  bool usesExtension(const char* name) const {
    for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
      auto it = doc_.find(list);
      if (it == doc_.end() || !it->is_array()) continue;
      for (const json& e : *it)
        if (e.is_string() && e.get<std::string>() == name) return true;
    }
    return false;
  }

  /// obj[key], when present, is an array of `n` numbers (a node's matrix,
  /// translation, rotation or scale: tinygltf leaves out any other, and the
  /// node would silently keep the identity there).
  const json* numbers(const json& obj, const char* key, const std::string& element, size_t n) const {
    auto it = obj.find(key);
    if (it == obj.end()) return nullptr;
    const std::string name = element + "." + key;
    if (!it->is_array() || it->size() != n)
      bad(name, "is " + it->dump().substr(0, 60) + ", not an array of " + std::to_string(n) + " numbers");
    for (size_t k = 0; k < n; ++k)
      if (!(*it)[k].is_number())
        bad(name + "[" + std::to_string(k) + "]", "is " + (*it)[k].dump().substr(0, 40) + ", not a number");
    return &*it;
  }

  void node(size_t i) const {
    const json& n = doc_["nodes"][i];
    const std::string el = "nodes[" + std::to_string(i) + "]";
    if (!n.is_object()) bad(el, "is not an object");
    reference(n, "mesh", el, "meshes");
    numbers(n, "matrix", el, 16);
    numbers(n, "translation", el, 3);
    numbers(n, "scale", el, 3);
    if (const json* r = numbers(n, "rotation", el, 4)) {
      double squared = 0;
      for (const json& c : *r) squared += c.get<double>() * c.get<double>();
      if (!(std::fabs(std::sqrt(squared) - 1) <= kUnitQuaternionTolerance)) {
        char length[64];
        std::snprintf(length, sizeof length, "%.6g", std::sqrt(squared));
        char tolerance[32];
        std::snprintf(tolerance, sizeof tolerance, "%g", kUnitQuaternionTolerance);
        bad(el + ".rotation", "is " + r->dump().substr(0, 80) + ", of length " + length +
                                  ", not a unit quaternion as the specification requires (vox normalises one within " +
                                  tolerance + " of length 1)");
      }
    }
    auto children = n.find("children");
    if (children != n.end() && children->is_array())
      for (size_t c = 0; c < children->size(); ++c) {
        const json& child = (*children)[c];
        if (!child.is_number_integer() || child.get<int64_t>() < 0 || child.get<int64_t>() >= int64_t(size("nodes")))
          bad(el + ".children[" + std::to_string(c) + "]", "is " + child.dump().substr(0, 40) + ", not a node index");
      }
  }

  /// "scene" names one of "scenes" (tinygltf keeps any number, and the reader
  /// would walk every root node instead of the scene the file names).
  void defaultScene() const {
    auto it = doc_.find("scene");
    if (it == doc_.end()) return;
    const size_t n = size("scenes");
    if (!it->is_number_integer() || it->get<int64_t>() < 0 || uint64_t(it->get<int64_t>()) >= n)
      bad("scene", "is " + it->dump().substr(0, 40) + ", but " +
                       (n == 0 ? std::string("the file has no scenes")
                               : "the file's scenes are 0.." + std::to_string(n - 1)));
  }

  void scene(size_t i) const {
    const json& s = doc_["scenes"][i];
    auto nodes = s.find("nodes");
    if (nodes == s.end() || !nodes->is_array()) return;
    for (size_t c = 0; c < nodes->size(); ++c) {
      const json& n = (*nodes)[c];
      if (!n.is_number_integer() || n.get<int64_t>() < 0 || n.get<int64_t>() >= int64_t(size("nodes")))
        bad("scenes[" + std::to_string(i) + "].nodes[" + std::to_string(c) + "]",
            "is " + n.dump().substr(0, 40) + ", not a node index");
    }
  }

  void material(size_t i) const {
    const json& m = doc_["materials"][i];
    const std::string el = "materials[" + std::to_string(i) + "]";
    if (!m.is_object()) bad(el, "is not an object");
    auto pbr = m.find("pbrMetallicRoughness");
    if (pbr != m.end() && pbr->is_object())
      for (const char* t : {"baseColorTexture", "metallicRoughnessTexture"}) {
        auto tex = pbr->find(t);
        if (tex != pbr->end() && tex->is_object()) reference(*tex, "index", el + ".pbrMetallicRoughness." + t, "textures");
      }
    for (const char* t : {"normalTexture", "occlusionTexture", "emissiveTexture"}) {
      auto tex = m.find(t);
      if (tex != m.end() && tex->is_object()) reference(*tex, "index", el + "." + t, "textures");
    }
  }

  void texture(size_t i) const {
    const json& t = doc_["textures"][i];
    const std::string el = "textures[" + std::to_string(i) + "]";
    if (!t.is_object()) bad(el, "is not an object");
    reference(t, "source", el, "images");
    reference(t, "sampler", el, "samplers");
  }

  const json& doc_;
  const std::string& path_;
};

}  // namespace

// The .glb header is checked here only as far as finding the JSON chunk needs;
// tinygltf checks the rest.
std::string_view gltfJsonText(std::string_view bytes, bool isBinary) {
  if (!isBinary) return bytes;
  uint32_t header[5] = {};
  if (bytes.size() < sizeof header) return {};
  std::memcpy(header, bytes.data(), sizeof header);
  if (header[0] != 0x46546C67u || header[4] != 0x4E4F534Au) return {};  // "glTF", chunk type "JSON"
  const uint64_t length = header[3];
  if (length > bytes.size() - sizeof header) return {};  // tinygltf reports the truncation
  return bytes.substr(sizeof header, size_t(length));
}

void checkGltfJson(const std::string& path) {
  checkGltfJsonBytes(readFileBytes(path), path, hasExtension(path, ".glb"));
}

void checkGltfJsonBytes(std::string_view bytes, const std::string& path, bool isBinary) {
  const std::string_view text = gltfJsonText(bytes, isBinary);
  const json doc = parseJsonInputOrDiscarded(text, path);  // glTF forbids duplicate keys: refused here
  if (!doc.is_object()) return;  // tinygltf names the parse error
  Checker(doc, path).run();
}

}  // namespace vox
