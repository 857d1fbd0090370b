#include "formats/mesh/gltf_reader.h"

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <tuple>

#include <nlohmann/json.hpp>

#include "formats/core/file_kinds.h"
#include "formats/core/file_util.h"
#include "formats/mesh/gltf_draco.h"
#include "formats/mesh/gltf_images.h"
#include "formats/mesh/gltf_meshopt.h"
#include "formats/mesh/gltf_json_check.h"
#include "libvox/core/counted.h"
#include "libvox/core/error.h"

namespace vox {

namespace {

using Mat4 = std::array<double, 16>;  // column-major, like glTF

Mat4 identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }

Mat4 mul(const Mat4& a, const Mat4& b) {
  Mat4 r{};
  for (int c = 0; c < 4; ++c)
    for (int rI = 0; rI < 4; ++rI) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[k * 4 + rI] * b[c * 4 + k];
      r[c * 4 + rI] = s;
    }
  return r;
}

/// A node's matrix, or T * R * S. `normalizeRotation`: a rotation off unit
/// length by more than float rounding leaves (1e-6; the JSON checks refuse one
/// off by more than kUnitQuaternionTolerance) is normalised first, as loaders
/// do; a unit one to that precision is used as written, as it always was.
Mat4 localMatrix(const tinygltf::Node& n, bool normalizeRotation = false) {
  if (n.matrix.size() == 16) {
    Mat4 m;
    for (int i = 0; i < 16; ++i) m[i] = n.matrix[i];
    return m;
  }
  Mat4 t = identity(), r = identity(), s = identity();
  if (n.translation.size() == 3) t[12] = n.translation[0], t[13] = n.translation[1], t[14] = n.translation[2];
  if (n.rotation.size() == 4) {
    double x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
    const double length = std::sqrt(x * x + y * y + z * z + w * w);
    if (normalizeRotation && std::fabs(length - 1) > 1e-6 && length > 0) x /= length, y /= length, z /= length, w /= length;
    r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),     0,
         2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),     0,
         2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y), 0,
         0,                       0,                       0,                       1};
  }
  if (n.scale.size() == 3) s[0] = n.scale[0], s[5] = n.scale[1], s[10] = n.scale[2];
  return mul(t, mul(r, s));
}

class Accessors {
 public:
  Accessors(const tinygltf::Model& m, const std::string& name) : m_(m), name_(name) {}

  /// Every element of accessor `index` as up to 4 doubles (normalized when the accessor says so).
  std::vector<std::array<double, 4>> read(int index, const char* role) const {
    if (index < 0 || size_t(index) >= m_.accessors.size())
      throwBadInput(name_ + ": accessor " + std::to_string(index) + " (" + role + ") does not exist");
    const tinygltf::Accessor& a = m_.accessors[size_t(index)];
    const int comps = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    const int csize = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (comps < 1 || comps > 4 || csize <= 0)
      throwBadInput(name_ + ": accessor " + std::to_string(index) + " (" + role + ") has an unsupported type");
    // A count the file cannot hold is refused before anything is allocated: an
    // accessor with a bufferView needs count elements inside it; one without
    // (all zeros plus sparse values) is capped at 2^31 elements.
    const uint64_t maxCount = a.bufferView >= 0 && size_t(a.bufferView) < m_.bufferViews.size()
                                  ? uint64_t(m_.bufferViews[size_t(a.bufferView)].byteLength) / uint64_t(csize * comps)
                                  : uint64_t(1) << 31;
    if (uint64_t(a.count) > maxCount)
      throwBadInput(name_ + ": accessor " + std::to_string(index) + " (" + role + ") has count " + std::to_string(a.count) +
                    ", more than its bufferView can hold (" + std::to_string(maxCount) + ")");
    if (a.sparse.isSparse && (a.sparse.count < 0 || uint64_t(a.sparse.count) > uint64_t(a.count)))
      throwBadInput(name_ + ": accessor " + std::to_string(index) + " (" + role + ") has sparse count " +
                    std::to_string(a.sparse.count) + " for " + counted(uint64_t(a.count), "element", "elements"));
    std::vector<std::array<double, 4>> out(a.count, std::array<double, 4>{0, 0, 0, 0});
    if (a.bufferView >= 0) readView(a.bufferView, a.byteOffset, a.count, a.componentType, comps, a.normalized, 0, out,
                                    index, role, nullptr);
    if (a.sparse.isSparse) {
      std::vector<std::array<double, 4>> idx(size_t(a.sparse.count)), vals(size_t(a.sparse.count));
      readView(a.sparse.indices.bufferView, a.sparse.indices.byteOffset, size_t(a.sparse.count),
               a.sparse.indices.componentType, 1, false, 0, idx, index, role, "sparse indices");
      readView(a.sparse.values.bufferView, a.sparse.values.byteOffset, size_t(a.sparse.count), a.componentType, comps,
               a.normalized, 0, vals, index, role, "sparse values");
      for (size_t i = 0; i < idx.size(); ++i) {
        const double k = idx[i][0];
        if (k < 0 || k >= double(a.count))
          throwBadInput(name_ + ": accessor " + std::to_string(index) + " (" + role + ") sparse index " +
                        std::to_string(int64_t(k)) + " is past its " + counted(uint64_t(a.count), "element", "elements"));
        out[size_t(k)] = vals[i];
      }
    }
    return out;
  }

 private:
  void readView(int viewIndex, size_t offset, size_t count, int componentType, int comps, bool normalized, int,
                std::vector<std::array<double, 4>>& out, int accessor, const char* role, const char* part) const {
    const std::string who = name_ + ": accessor " + std::to_string(accessor) + " (" + role + ")" +
                            (part ? std::string(" ") + part : std::string());
    if (viewIndex < 0 || size_t(viewIndex) >= m_.bufferViews.size()) throwBadInput(who + " has no valid bufferView");
    const tinygltf::BufferView& v = m_.bufferViews[size_t(viewIndex)];
    if (v.buffer < 0 || size_t(v.buffer) >= m_.buffers.size()) throwBadInput(who + ": bufferView has no valid buffer");
    const std::vector<unsigned char>& buf = m_.buffers[size_t(v.buffer)].data;
    const int csize = tinygltf::GetComponentSizeInBytes(uint32_t(componentType));
    const size_t elem = size_t(csize) * size_t(comps);
    const size_t stride = v.byteStride ? v.byteStride : elem;
    if (stride < elem)
      throwBadInput(who + ": bufferView " + std::to_string(viewIndex) + " has byteStride " + std::to_string(stride) +
                    ", less than the " + std::to_string(elem) + "-byte element it holds");
    const size_t start = v.byteOffset + offset;
    if (v.byteOffset > buf.size() || v.byteLength > buf.size() - v.byteOffset)
      throwBadInput(who + ": bufferView " + std::to_string(viewIndex) + " overruns its buffer (" +
                    counted(buf.size(), "byte", "bytes") + ")");
    // count and stride are now bounded by real buffer sizes, so the products below cannot overflow.
    if (count > v.byteLength || stride > 4096) throwBadInput(who + " reads past the end of its bufferView");
    if (count > 0 && (start + (count - 1) * stride + elem > buf.size() || start + (count - 1) * stride + elem > v.byteOffset + v.byteLength))
      throwBadInput(who + " reads past the end of its buffer");
    for (size_t i = 0; i < count; ++i) {
      const unsigned char* p = buf.data() + start + i * stride;
      for (int c = 0; c < comps; ++c) {
        const unsigned char* q = p + size_t(c) * size_t(csize);
        double x = 0;
        switch (componentType) {
          case TINYGLTF_COMPONENT_TYPE_BYTE: { int8_t t; std::memcpy(&t, q, 1); x = normalized ? std::max(t / 127.0, -1.0) : t; break; }
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: { uint8_t t = *q; x = normalized ? t / 255.0 : t; break; }
          case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t t; std::memcpy(&t, q, 2); x = normalized ? std::max(t / 32767.0, -1.0) : t; break; }
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t t; std::memcpy(&t, q, 2); x = normalized ? t / 65535.0 : t; break; }
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t t; std::memcpy(&t, q, 4); x = t; break; }
          case TINYGLTF_COMPONENT_TYPE_FLOAT: { float t; std::memcpy(&t, q, 4); x = t; break; }
          default: throwBadInput(who + " has an unsupported component type " + std::to_string(componentType));
        }
        out[i][size_t(c)] = x;
      }
    }
  }
  const tinygltf::Model& m_;
  const std::string& name_;
};

MeshTexture::Wrap wrapOf(int mode) {
  if (mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return MeshTexture::Wrap::ClampToEdge;
  if (mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return MeshTexture::Wrap::MirroredRepeat;
  return MeshTexture::Wrap::Repeat;
}

/// tinygltf's file reader for external buffers and images, through the one
/// input-file check: a URI naming a directory or a device is refused by name
/// (tinygltf's own reader asks a directory for 2^63 bytes).
bool readWholeGltfFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  try {
    const std::string bytes = readFileBytes(path);
    out->assign(bytes.begin(), bytes.end());
    return true;
  } catch (const Error& e) {
    if (err) *err += std::string(e.what()) + "\n";
    return false;
  }
}

/// What tinygltf would refuse in a valid compressed file, rewritten:
/// * a primitive whose indices accessor has no bufferView, as every
///   Draco-compressed primitive's has (its indices are in the Draco data):
///   "indices" is removed from such primitives;
/// * an EXT_meshopt_compression fallback buffer without data (no "uri"):
///   it becomes a one-byte data URI (its bytes are never read: the views
///   that use it are decoded from the compressed buffer, gltf_meshopt.h).
/// Returns the file's bytes rewritten (the .glb container rebuilt around the
/// new JSON chunk), or nullopt when nothing needs it.
std::optional<std::string> tinygltfReadable(std::string_view bytes, bool isBinary) {
  // Only the JSON can name an extension (a binary chunk may hold the words by chance).
  const std::string_view text = gltfJsonText(bytes, isBinary);
  if (text.find("KHR_draco_mesh_compression") == std::string_view::npos &&
      text.find("EXT_meshopt_compression") == std::string_view::npos)
    return std::nullopt;
  nlohmann::json doc = nlohmann::json::parse(text.data(), text.data() + text.size(), nullptr, /*allow_exceptions=*/false);
  if (!doc.is_object()) return std::nullopt;
  bool changed = false;
  auto hasExtension = [](const nlohmann::json& o, const char* name) {
    return o.is_object() && o.contains("extensions") && o["extensions"].is_object() && o["extensions"].contains(name);
  };
  if (doc.contains("meshes") && doc["meshes"].is_array())
    for (auto& m : doc["meshes"]) {
      if (!m.is_object() || !m.contains("primitives") || !m["primitives"].is_array()) continue;
      for (auto& p : m["primitives"])
        if (p.is_object() && p.contains("indices") && hasExtension(p, "KHR_draco_mesh_compression")) {
          p.erase("indices");
          changed = true;
        }
    }
  // Buffers that hold an image's bufferView are left alone (tinygltf reads
  // images from them, so they need their real length; it then reports the missing data).
  std::vector<char> holdsImage(doc.contains("buffers") && doc["buffers"].is_array() ? doc["buffers"].size() : 0, 0);
  if (doc.contains("images") && doc["images"].is_array() && doc.contains("bufferViews") && doc["bufferViews"].is_array())
    for (const auto& im : doc["images"])
      if (im.is_object() && im.contains("bufferView") && im["bufferView"].is_number_unsigned() &&
          im["bufferView"].get<uint64_t>() < doc["bufferViews"].size()) {
        const auto& v = doc["bufferViews"][size_t(im["bufferView"].get<uint64_t>())];
        if (v.is_object() && v.contains("buffer") && v["buffer"].is_number_unsigned() &&
            v["buffer"].get<uint64_t>() < holdsImage.size())
          holdsImage[size_t(v["buffer"].get<uint64_t>())] = 1;
      }
  if (doc.contains("buffers") && doc["buffers"].is_array())
    for (size_t i = 0; i < doc["buffers"].size(); ++i) {
      auto& b = doc["buffers"][i];
      // In a .glb, buffer 0 without a uri is the BIN chunk.
      if (hasExtension(b, "EXT_meshopt_compression") && !b.contains("uri") && !(isBinary && i == 0) && !holdsImage[i]) {
        b["uri"] = "data:application/octet-stream;base64,AA==";
        b["byteLength"] = 1;
        changed = true;
      }
    }
  if (!changed) return std::nullopt;
  std::string json = doc.dump();
  if (!isBinary) return json;
  while (json.size() % 4) json.push_back(' ');
  uint32_t oldLength;
  std::memcpy(&oldLength, bytes.data() + 12, 4);
  const std::string_view rest = bytes.substr(20 + size_t(oldLength));
  const uint32_t header[5] = {0x46546C67u, 2, uint32_t(20 + json.size() + rest.size()), uint32_t(json.size()), 0x4E4F534Au};
  std::string out(reinterpret_cast<const char*>(header), sizeof header);
  out += json;
  out += rest;
  return out;
}

/// Loads the container (tinygltf: JSON or GLB, buffers; images kept encoded in `images`) from
/// the file's bytes; external buffers and images are read beside `path`.
/// Checks the JSON first (gltf_json_check.h): unsupported required extensions, malformed ranges and indices are refused by name.
tinygltf::Model loadModel(std::string_view bytes, const std::string& path, bool isBinary, EncodedImages& images,
                          std::vector<std::string>& warnings) {
  tinygltf::TinyGLTF loader;
  deferImageDecoding(loader, images);
  loader.SetFsCallbacks({&tinygltf::FileExists, &tinygltf::ExpandFilePath, &readWholeGltfFile,
                         &tinygltf::WriteWholeFile, nullptr});
  tinygltf::Model model;
  std::string err, warn;
  checkGltfJsonBytes(bytes, path, isBinary);
  const std::optional<std::string> rewritten = tinygltfReadable(bytes, isBinary);
  const std::string_view input = rewritten ? std::string_view(*rewritten) : bytes;
  // tinygltf's base directory of a path (its GetBaseDir): external URIs resolve
  // against it exactly as LoadASCIIFromFile / LoadBinaryFromFile resolve them.
  const size_t slash = path.find_last_of("/\\");
  const std::string baseDir = slash == std::string::npos ? std::string() : path.substr(0, slash);
  if (input.size() > uint64_t(std::numeric_limits<unsigned int>::max()))
    throwBadInput(path + ": cannot read the glTF file: larger than 4 GiB");
  bool ok = false;
  if (input.empty())
    err = "Empty file.";  // as tinygltf's file loaders say (its binary one would index past the end)
  else if (isBinary)
    ok = loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(input.data()),
                                     static_cast<unsigned int>(input.size()), baseDir);
  else
    ok = loader.LoadASCIIFromString(&model, &err, &warn, input.data(), static_cast<unsigned int>(input.size()), baseDir);
  if (!ok) {
    std::string why = (err.empty() ? warn : err).substr(0, 300);
    while (!why.empty() && std::isspace(static_cast<unsigned char>(why.back()))) why.pop_back();
    throwBadInput(path + ": cannot read the glTF file: " + why);
  }
  if (!warn.empty()) warnings.push_back(path + ": " + warn.substr(0, 300));
  decodeMeshoptViews(model, path);
  return model;
}

/// The file itself, then its external buffers and images (data: URIs are not files).
void listFilesRead(const tinygltf::Model& model, const std::string& path, Mesh& mesh) {
  mesh.filesRead.push_back(path);
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  for (const tinygltf::Buffer& b : model.buffers)
    if (!b.uri.empty() && b.uri.rfind("data:", 0) != 0) mesh.filesRead.push_back((dir / b.uri).string());
  for (const tinygltf::Image& im : model.images)
    if (!im.uri.empty() && im.uri.rfind("data:", 0) != 0) mesh.filesRead.push_back((dir / im.uri).string());
}

/// The image texture `tex` samples: its EXT_texture_webp source when it has
/// one (vox decodes WebP), else its `source` (the PNG or JPEG fallback, or the
/// only one); -1 when there is none or the index names no image.
int imageOf(const tinygltf::Model& model, const tinygltf::Texture& tex) {
  auto webp = tex.extensions.find("EXT_texture_webp");
  int src = tex.source;
  if (webp != tex.extensions.end() && webp->second.Has("source") && webp->second.Get("source").IsInt())
    src = webp->second.Get("source").GetNumberAsInt();
  return src >= 0 && size_t(src) < model.images.size() ? src : -1;
}

/// An external image that a texture uses and that could not be read is an
/// error, as a missing OBJ map_Kd is (tinygltf only warns and leaves it
/// empty); with ignoreMissingMaterials it is a warning and the texture is left out.
void refuseMissingImages(const tinygltf::Model& model, const EncodedImages& encoded, const std::string& path,
                         const MeshReadOptions& options, std::vector<std::string>& warnings) {
  std::vector<bool> used(model.images.size(), false);
  for (const tinygltf::Texture& t : model.textures)
    if (const int src = imageOf(model, t); src >= 0) used[size_t(src)] = true;
  for (size_t i = 0; i < model.images.size(); ++i) {
    const tinygltf::Image& im = model.images[i];
    const bool received = i < encoded.received.size() && encoded.received[i];
    if (!used[i] || received || im.uri.empty() || im.uri.rfind("data:", 0) == 0) continue;
    const std::string file = (std::filesystem::path(path).parent_path() / im.uri).string();
    if (options.ignoreMissingMaterials) {
      warnings.push_back(path + ": image " + std::to_string(i) + " (" + im.uri + ") could not be read; its textures are left out");
      continue;
    }
    std::string why = "cannot be read or decoded";
    try {
      requireRegularFile(file);
    } catch (const Error& e) {
      why = e.what();
    }
    throwBadInput(path + ": image " + std::to_string(i) + " '" + im.uri + "': " + why +
                      "; restore the file, or leave its textures out",
                  Setting::IgnoreMissingMaterials);
  }
}

/// glTF texture `ti` as a MeshTexture (its image as 8-bit RGBA, its sampler),
/// or nullopt with a warning when its image was not decoded. `lastUse`: no
/// other texture needs the image's pixels, so they are moved, not copied.
/// `decodingLater`: its image is being decoded by a DeferredTextures, which
/// puts the pixels in afterwards (none yet).
std::optional<MeshTexture> convertTexture(tinygltf::Model& model, size_t ti, bool lastUse, bool decodingLater,
                                          const std::string& path, std::vector<std::string>& warnings) {
  const tinygltf::Texture& tex = model.textures[ti];
  const int src = imageOf(model, tex);
  if (src < 0) return std::nullopt;
  tinygltf::Image& im = model.images[size_t(src)];
  MeshTexture t;
  if (!decodingLater) {
    if (!(im.width > 0 && im.height > 0 && im.component == 4 && im.bits == 8 &&
          im.image.size() == size_t(im.width) * size_t(im.height) * 4)) {
      warnings.push_back(path + ": texture " + std::to_string(ti) + " could not be decoded to 8-bit RGBA; ignored");
      return std::nullopt;
    }
    t.width = uint32_t(im.width);
    t.height = uint32_t(im.height);
    if (lastUse) t.rgba = std::move(im.image);
    else t.rgba = im.image;
  }
  t.source = im.uri.empty() ? "image " + std::to_string(src) : im.uri;
  if (tex.sampler >= 0 && size_t(tex.sampler) < model.samplers.size()) {
    const tinygltf::Sampler& s = model.samplers[size_t(tex.sampler)];
    t.wrapS = wrapOf(s.wrapS);
    t.wrapT = wrapOf(s.wrapT);
    t.nearest = s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
  }
  return t;
}

/// Where a material's base colour comes from: baseColorFactor and
/// baseColorTexture, or, for KHR_materials_pbrSpecularGlossiness (which
/// replaces the metallic-roughness model), diffuseFactor and diffuseTexture.
struct ColourSource {
  std::array<float, 4> factor{1, 1, 1, 1};
  int texture = -1;  // textures[] index, or -1
  int texCoord = 0;
  const tinygltf::Value* transform = nullptr;  // the texture's KHR_texture_transform, if any
  const char* element = "pbrMetallicRoughness.baseColorTexture";
};

ColourSource colourSource(const tinygltf::Material& m) {
  ColourSource c;
  auto sg = m.extensions.find("KHR_materials_pbrSpecularGlossiness");
  if (sg != m.extensions.end() && sg->second.IsObject()) {
    const tinygltf::Value& e = sg->second;
    c.element = "KHR_materials_pbrSpecularGlossiness.diffuseTexture";
    if (e.Has("diffuseFactor") && e.Get("diffuseFactor").IsArray())
      for (int k = 0; k < 4 && k < int(e.Get("diffuseFactor").ArrayLen()); ++k)
        if (e.Get("diffuseFactor").Get(k).IsNumber()) c.factor[size_t(k)] = float(e.Get("diffuseFactor").Get(k).GetNumberAsDouble());
    if (e.Has("diffuseTexture") && e.Get("diffuseTexture").IsObject()) {
      const tinygltf::Value& t = e.Get("diffuseTexture");
      if (t.Has("index") && t.Get("index").IsInt()) c.texture = t.Get("index").GetNumberAsInt();
      if (t.Has("texCoord") && t.Get("texCoord").IsInt()) c.texCoord = t.Get("texCoord").GetNumberAsInt();
      if (t.Has("extensions") && t.Get("extensions").Has("KHR_texture_transform"))
        c.transform = &t.Get("extensions").Get("KHR_texture_transform");
    }
    return c;
  }
  const auto& f = m.pbrMetallicRoughness.baseColorFactor;
  for (size_t k = 0; k < 4 && k < f.size(); ++k) c.factor[k] = float(f[k]);
  c.texture = m.pbrMetallicRoughness.baseColorTexture.index;
  c.texCoord = m.pbrMetallicRoughness.baseColorTexture.texCoord;
  auto tt = m.pbrMetallicRoughness.baseColorTexture.extensions.find("KHR_texture_transform");
  if (tt != m.pbrMetallicRoughness.baseColorTexture.extensions.end()) c.transform = &tt->second;
  return c;
}

/// The images the materials' colour textures use (the only ones decoded).
std::vector<char> colourImages(const tinygltf::Model& model) {
  std::vector<char> needed(model.images.size(), 0);
  for (const tinygltf::Material& m : model.materials) {
    const int ti = colourSource(m).texture;
    if (ti < 0 || size_t(ti) >= model.textures.size()) continue;
    const int src = imageOf(model, model.textures[size_t(ti)]);
    if (src >= 0 && size_t(src) < needed.size()) needed[size_t(src)] = 1;
  }
  return needed;
}

/// The base colour texture's KHR_texture_transform of material `mi` as the
/// affine map uv' = (a*u + b*v + c, d*u + e*v + f) = T * R * S * uv (the
/// extension's order: scale, then rotation counter-clockwise in UV space, then
/// offset), or nullopt when it has none. The voxelizer applies it to the
/// interpolated UVs (MeshMaterial::uvTransform): affine maps commute with
/// barycentric interpolation, so this is the transform of each vertex's UVs,
/// without rounding the transformed UVs to float.
std::optional<std::array<double, 6>> uvTransform(const tinygltf::Model& model, size_t mi, const std::string& path) {
  const ColourSource cs = colourSource(model.materials[mi]);
  if (!cs.transform || cs.texture < 0) return std::nullopt;
  const tinygltf::Value& t = *cs.transform;
  const std::string who = path + ": materials[" + std::to_string(mi) + "] " + cs.element + " KHR_texture_transform";
  auto pair = [&](const char* key, double fallback) -> std::array<double, 2> {
    if (!t.Has(key)) return {fallback, fallback};
    const tinygltf::Value& v = t.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber())
      throwBadInput(who + ": \"" + key + "\" is not an array of two numbers; the file is malformed (re-export it)");
    return {v.Get(0).GetNumberAsDouble(), v.Get(1).GetNumberAsDouble()};
  };
  if (!t.IsObject()) throwBadInput(who + " is not an object; the file is malformed (re-export it)");
  const std::array<double, 2> offset = pair("offset", 0), scale = pair("scale", 1);
  double rotation = 0;
  if (t.Has("rotation")) {
    if (!t.Get("rotation").IsNumber())
      throwBadInput(who + ": \"rotation\" is not a number; the file is malformed (re-export it)");
    rotation = t.Get("rotation").GetNumberAsDouble();
  }
  const double c = std::cos(rotation), s = std::sin(rotation);
  return std::array<double, 6>{c * scale[0], s * scale[1], offset[0], -s * scale[0], c * scale[1], offset[1]};
}

/// Every material (base colour factor and texture; each texture converted
/// once), then the white material of primitives without one, whose index is
/// returned. With `deferred`, the images of jobOf's indices are decoded by
/// the bake from there: their textures are named to it.
uint32_t addMaterials(tinygltf::Model& model, const std::string& path, Mesh& mesh, std::vector<std::string>& warnings,
                      DeferredTextures* deferred = nullptr, const std::vector<int>& jobOf = {}) {
  std::vector<int> meshTextureOf(model.textures.size(), -1);
  // How many base colour textures still need each image's pixels.
  std::vector<int> usesLeft(model.images.size(), 0);
  {
    std::vector<char> counted(model.textures.size(), 0);
    for (const tinygltf::Material& src : model.materials) {
      const int ti = colourSource(src).texture;
      if (ti < 0 || size_t(ti) >= model.textures.size() || counted[size_t(ti)]++) continue;
      const int img = imageOf(model, model.textures[size_t(ti)]);
      if (img >= 0 && size_t(img) < usesLeft.size()) ++usesLeft[size_t(img)];
    }
  }
  for (size_t mi = 0; mi < model.materials.size(); ++mi) {
    const tinygltf::Material& src = model.materials[mi];
    MeshMaterial m;
    m.name = src.name;
    const ColourSource cs = colourSource(src);
    m.baseColorFactor = cs.factor;
    const int ti = cs.texture;
    if (ti >= 0 && size_t(ti) < model.textures.size()) {
      const int img = imageOf(model, model.textures[size_t(ti)]);
      const int job = deferred && img >= 0 && size_t(img) < jobOf.size() ? jobOf[size_t(img)] : -1;
      if (meshTextureOf[size_t(ti)] < 0)
        if (std::optional<MeshTexture> t =
                convertTexture(model, size_t(ti), img >= 0 && --usesLeft[size_t(img)] == 0, job >= 0, path, warnings)) {
          mesh.textures.push_back(std::move(*t));
          meshTextureOf[size_t(ti)] = int(mesh.textures.size() - 1);
          if (job >= 0) deferred->addTexture(size_t(job), mesh.textures.size() - 1);
        }
      m.texture = meshTextureOf[size_t(ti)];
      m.texCoordSet = cs.texCoord;
      // KHR_texture_transform's texCoord overrides the textureInfo's.
      if (cs.transform && cs.transform->Has("texCoord") && cs.transform->Get("texCoord").IsInt())
        m.texCoordSet = cs.transform->Get("texCoord").GetNumberAsInt();
      // Applied where the texture is sampled, as an MTL map's placement is.
      if (const auto t = uvTransform(model, mi, path)) m.uvTransform = *t;
    }
    mesh.materials.push_back(m);
  }
  mesh.materials.push_back({"", {1, 1, 1, 1}, -1, 0});
  return uint32_t(mesh.materials.size() - 1);
}

/// The nodes to walk: the default scene's (else scene 0's), else every node
/// that is no other node's child.
std::vector<int> rootNodes(const tinygltf::Model& model) {
  const int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : (model.scenes.empty() ? -1 : 0);
  if (sceneIndex >= 0 && size_t(sceneIndex) < model.scenes.size()) return model.scenes[size_t(sceneIndex)].nodes;
  std::vector<int> roots;
  std::vector<char> isChild(model.nodes.size(), 0);
  for (const auto& n : model.nodes)
    for (int c : n.children)
      if (c >= 0 && size_t(c) < isChild.size()) isChild[size_t(c)] = 1;
  for (size_t i = 0; i < model.nodes.size(); ++i)
    if (!isChild[i]) roots.push_back(int(i));
  return roots;
}

/// Does `world` mirror (negative determinant of its 3x3 part)?
bool mirrors(const Mat4& world) {
  const double det3 = world[0] * (world[5] * world[10] - world[9] * world[6]) -
                      world[4] * (world[1] * world[10] - world[9] * world[2]) +
                      world[8] * (world[1] * world[6] - world[5] * world[2]);
  return det3 < 0;
}

/// Walks the node hierarchy and appends every triangle primitive to the mesh,
/// positions in world space.
class NodeWalker {
 public:
  NodeWalker(const tinygltf::Model& model, const std::string& path, uint32_t defaultMaterial, Mesh& mesh,
             std::vector<std::string>& warnings)
      : model_(model), path_(path), defaultMaterial_(defaultMaterial), mesh_(mesh), warnings_(warnings),
        acc_(model, path), visited_(model.nodes.size(), 0) {}

  /// Node `ni` under the world matrix `parent`, then its children.
  void visit(int ni, const Mat4& parent, const std::string& parentPath, int depth) {
    if (ni < 0 || size_t(ni) >= model_.nodes.size() || depth > 256)
      throwBadInput(path_ + ": node " + std::to_string(ni) + " is invalid or the hierarchy is cyclic");
    // glTF nodes have at most one parent: a node reached twice is a cycle or a
    // shared child (which could also multiply the work exponentially).
    if (visited_[size_t(ni)]++)
      throwBadInput(path_ + ": node " + std::to_string(ni) + " is reached twice in the node hierarchy (a cycle, or a node "
                    "with two parents, which glTF forbids); fix the file's \"children\" lists");
    const tinygltf::Node& node = model_.nodes[size_t(ni)];
    const Mat4 world = mul(parent, localMatrix(node, /*normalizeRotation=*/true));
    const std::string nodePath = parentPath.empty() ? node.name : parentPath + "/" + node.name;
    if (node.mesh >= 0 && size_t(node.mesh) < model_.meshes.size()) {
      const tinygltf::Mesh& gm = model_.meshes[size_t(node.mesh)];
      mesh_.parts.push_back({nodePath, gm.name});
      const uint32_t part = uint32_t(mesh_.parts.size() - 1);
      const std::vector<Mat4> instances = instanceMatrices(node, ni);
      if (instances.empty())
        for (size_t pi = 0; pi < gm.primitives.size(); ++pi) addPrimitive(gm, pi, world, part);
      for (const Mat4& instance : instances)
        for (size_t pi = 0; pi < gm.primitives.size(); ++pi) addPrimitive(gm, pi, mul(world, instance), part);
    }
    for (int child : node.children) visit(child, world, nodePath, depth + 1);
  }

  /// Refuses NaN or infinite positions, naming the first accessor that has
  /// them, unless they are to be dropped.
  void refuseInvalidPositions(const MeshReadOptions& options) const {
    if (invalidPositions_ && !options.dropInvalid)
      throwBadInput(path_ + ": " + firstInvalid_ + "; fix the file or drop their triangles", Setting::DropInvalid);
  }

 private:
  using Values = std::vector<std::array<double, 4>>;

  /// EXT_mesh_gpu_instancing: one matrix T * R * S per instance of node
  /// `ni`'s mesh (applied before the node's world matrix), or none when the
  /// node has no such extension. Children are not instanced (the extension
  /// instances the node's mesh only).
  std::vector<Mat4> instanceMatrices(const tinygltf::Node& node, int ni) const {
    auto it = node.extensions.find("EXT_mesh_gpu_instancing");
    if (it == node.extensions.end()) return {};
    const std::string who = path_ + ": nodes[" + std::to_string(ni) + "] EXT_mesh_gpu_instancing";
    const tinygltf::Value& ext = it->second;
    if (!ext.IsObject() || !ext.Has("attributes") || !ext.Get("attributes").IsObject())
      throwBadInput(who + " has no \"attributes\" object; the file is malformed (re-export it)");
    const tinygltf::Value& attrs = ext.Get("attributes");
    Values t, r, s;
    size_t count = 0;
    bool any = false;
    for (const auto& [name, dst, comps] : {std::tuple<const char*, Values*, int>{"TRANSLATION", &t, 3},
                                            {"ROTATION", &r, 4}, {"SCALE", &s, 3}}) {
      if (!attrs.Has(name)) continue;
      if (!attrs.Get(name).IsInt()) throwBadInput(who + ": " + name + " is not an accessor index");
      const int a = attrs.Get(name).GetNumberAsInt();
      *dst = acc_.read(a, name);
      if (tinygltf::GetNumComponentsInType(uint32_t(model_.accessors[size_t(a)].type)) != comps)
        throwBadInput(who + ": accessor " + std::to_string(a) + " (" + name + ") is not a VEC" + std::to_string(comps));
      if (any && dst->size() != count)
        throwBadInput(who + ": accessor " + std::to_string(a) + " (" + name + ") has " +
                      counted(dst->size(), "instance", "instances") + ", the other attributes " + std::to_string(count));
      count = dst->size();
      any = true;
    }
    if (!any) throwBadInput(who + " names no TRANSLATION, ROTATION or SCALE accessor; the file is malformed (re-export it)");
    std::vector<Mat4> out(count);
    for (size_t i = 0; i < count; ++i) {
      tinygltf::Node trs;
      if (!t.empty()) trs.translation = {t[i][0], t[i][1], t[i][2]};
      if (!r.empty()) trs.rotation = {r[i][0], r[i][1], r[i][2], r[i][3]};
      if (!s.empty()) trs.scale = {s[i][0], s[i][1], s[i][2]};
      out[i] = localMatrix(trs);
    }
    return out;
  }

  /// What one primitive holds for vox, read from accessors or decoded from
  /// its compressed data.
  struct PrimitiveData {
    Values positions, uv0, uv1, colors;
    int colorComponents = 0;
    std::string positionSource;  // names the positions in messages
    std::vector<uint32_t> indices;
    bool indexed = false;
  };

  void addPrimitive(const tinygltf::Mesh& gm, size_t pi, const Mat4& world, uint32_t part) {
    const tinygltf::Primitive& prim = gm.primitives[pi];
    int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    const std::string who = path_ + ": mesh '" + gm.name + "' primitive " + std::to_string(pi);
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      warnings_.push_back(who + " has mode " + std::to_string(mode) + " (points or lines); skipped");
      return;
    }
    auto posIt = prim.attributes.find("POSITION");
    if (posIt == prim.attributes.end()) {
      warnings_.push_back(who + " has no POSITION; skipped");
      return;
    }
    PrimitiveData d;
    auto draco = prim.extensions.find("KHR_draco_mesh_compression");
    if (draco != prim.extensions.end()) {
      d = readDraco(prim, draco->second, who);
      mode = TINYGLTF_MODE_TRIANGLES;  // Draco decodes to triangle faces
    } else {
      d = readAccessors(prim);
    }
    const uint32_t base = uint32_t(mesh_.positions.size());
    mesh_.vertexRuns.push_back({base, path_,
                                draco != prim.extensions.end()
                                    ? d.positionSource + " point"
                                    : "mesh '" + gm.name + "' primitive " + std::to_string(pi) + ", " + d.positionSource + " element",
                                0, " (counted from 0)"});
    appendPositions(d.positions, d.positionSource, world);
    const size_t count = d.positions.size();
    appendVertexAttributes(d, base, count);
    if (!d.indexed)
      for (uint32_t i = 0; i < count; ++i) d.indices.push_back(i);
    const uint32_t material =
        prim.material >= 0 && size_t(prim.material) < model_.materials.size() ? uint32_t(prim.material) : defaultMaterial_;
    appendTriangles(mode, d.indices, base, material, part, mirrors(world));
  }

  /// The primitive's attributes and indices from its accessors.
  PrimitiveData readAccessors(const tinygltf::Primitive& prim) const {
    PrimitiveData d;
    const int posAccessor = prim.attributes.at("POSITION");
    d.positions = acc_.read(posAccessor, "POSITION");
    d.positionSource = "accessor " + std::to_string(posAccessor) + " (POSITION)";
    auto attr = [&](const char* n) -> Values {
      auto it = prim.attributes.find(n);
      return it == prim.attributes.end() ? Values{} : acc_.read(it->second, n);
    };
    d.uv0 = attr("TEXCOORD_0");
    d.uv1 = attr("TEXCOORD_1");
    auto colIt = prim.attributes.find("COLOR_0");
    if (colIt != prim.attributes.end()) {
      d.colors = acc_.read(colIt->second, "COLOR_0");
      d.colorComponents = tinygltf::GetNumComponentsInType(uint32_t(model_.accessors[size_t(colIt->second)].type));
    }
    if (prim.indices >= 0) {
      d.indexed = true;
      d.indices = vertexIndices(prim.indices, d.positions.size());
    }
    return d;
  }

  /// The primitive's attributes and indices decoded from its
  /// KHR_draco_mesh_compression bufferView (the accessors only describe them).
  PrimitiveData readDraco(const tinygltf::Primitive& prim, const tinygltf::Value& ext, const std::string& primitive) const {
    const std::string who = primitive + " (KHR_draco_mesh_compression)";
    if (!ext.IsObject() || !ext.Has("bufferView") || !ext.Get("bufferView").IsInt() || !ext.Has("attributes") ||
        !ext.Get("attributes").IsObject())
      throwBadInput(who + ": the extension needs an integer \"bufferView\" and an \"attributes\" object; the file "
                    "is malformed (re-export it)");
    const int view = ext.Get("bufferView").GetNumberAsInt();
    if (view < 0 || size_t(view) >= model_.bufferViews.size())
      throwBadInput(who + ": bufferView " + std::to_string(view) + " does not exist (the file has " +
                    std::to_string(model_.bufferViews.size()) + ")");
    const tinygltf::BufferView& v = model_.bufferViews[size_t(view)];
    if (v.buffer < 0 || size_t(v.buffer) >= model_.buffers.size())
      throwBadInput(who + ": bufferView " + std::to_string(view) + " has no valid buffer");
    const std::vector<unsigned char>& buf = model_.buffers[size_t(v.buffer)].data;
    if (v.byteOffset > buf.size() || v.byteLength > buf.size() - v.byteOffset)
      throwBadInput(who + ": bufferView " + std::to_string(view) + " overruns its buffer (" +
                    counted(buf.size(), "byte", "bytes") + ")");
    // The attributes vox reads, each mapped to a Draco unique id; an attribute
    // the primitive has but the extension does not compress is refused rather
    // than mixed with decoded points it need not match.
    const tinygltf::Value& ids = ext.Get("attributes");
    std::vector<DracoAttributeRequest> requests;
    std::vector<std::pair<std::string, int>> plain;  // attributes stored uncompressed beside the Draco data
    for (const char* name : {"POSITION", "TEXCOORD_0", "TEXCOORD_1", "COLOR_0"}) {
      auto it = prim.attributes.find(name);
      if (it == prim.attributes.end()) continue;
      if (!ids.Has(name) || !ids.Get(name).IsInt()) {
        // The extension lets other attributes be stored as usual, one value per decoded point.
        if (std::string(name) == "POSITION")
          throwBadInput(who + ": POSITION is not among the extension's compressed attributes; the file is "
                        "malformed (re-export it)");
        plain.emplace_back(name, it->second);
        continue;
      }
      const bool normalized = it->second >= 0 && size_t(it->second) < model_.accessors.size() &&
                              model_.accessors[size_t(it->second)].normalized;
      requests.push_back({name, ids.Get(name).GetNumberAsInt(), normalized});
    }
    DracoDecoded dec = decodeDraco(buf.data() + v.byteOffset, v.byteLength, requests, who);
    PrimitiveData d;
    for (size_t r = 0; r < requests.size(); ++r) {
      const std::string& n = requests[r].semantic;
      if (n == "POSITION") d.positions = std::move(dec.values[r]);
      if (n == "TEXCOORD_0") d.uv0 = std::move(dec.values[r]);
      if (n == "TEXCOORD_1") d.uv1 = std::move(dec.values[r]);
      if (n == "COLOR_0") d.colors = std::move(dec.values[r]), d.colorComponents = dec.components[r];
    }
    for (const auto& [n, accessor] : plain) {
      Values values = acc_.read(accessor, n.c_str());
      if (values.size() != dec.points)
        throwBadInput(who + ": " + n + " is stored uncompressed in accessor " + std::to_string(accessor) + " with " +
                      counted(values.size(), "value", "values") + ", but the Draco data has " +
                      counted(dec.points, "point", "points") + "; the file is malformed (re-export it)");
      if (n == "TEXCOORD_0") d.uv0 = std::move(values);
      if (n == "TEXCOORD_1") d.uv1 = std::move(values);
      if (n == "COLOR_0") {
        d.colors = std::move(values);
        d.colorComponents = tinygltf::GetNumComponentsInType(uint32_t(model_.accessors[size_t(accessor)].type));
      }
    }
    d.positionSource = "Draco attribute " + std::to_string(requests[0].uniqueId) + " (POSITION) of " + primitive.substr(path_.size() + 2);
    d.indices = std::move(dec.indices);
    d.indexed = true;
    return d;
  }

  /// The positions `pos` transformed by `world`; counts the non-finite ones
  /// (`source` names them in the message).
  void appendPositions(const Values& pos, const std::string& source, const Mat4& world) {
    size_t bad = 0;
    for (const auto& p : pos)
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) ++bad;
    if (bad) {
      invalidPositions_ += bad;
      if (firstInvalid_.empty()) firstInvalid_ = source + " has " + std::to_string(bad) + " NaN or infinite values";
    }
    for (const auto& p : pos) {
      std::array<double, 3> w;
      for (int r = 0; r < 3; ++r) w[size_t(r)] = world[size_t(r)] * p[0] + world[size_t(4 + r)] * p[1] + world[size_t(8 + r)] * p[2] + world[size_t(12 + r)];
      mesh_.positions.push_back(w);
    }
  }

  /// TEXCOORD_0, TEXCOORD_1 and COLOR_0 of the `count` vertices from `base` on;
  /// arrays that exist are kept parallel to the positions (zeros, white).
  void appendVertexAttributes(const PrimitiveData& d, uint32_t base, size_t count) {
    auto fill2 = [&](std::vector<std::array<float, 2>>& dst, const Values& src) {
      if (src.empty() && dst.empty()) return;
      dst.resize(base, {0, 0});
      for (size_t i = 0; i < count; ++i)
        dst.push_back(i < src.size() ? std::array<float, 2>{float(src[i][0]), float(src[i][1])} : std::array<float, 2>{0, 0});
    };
    fill2(mesh_.uv0, d.uv0);
    fill2(mesh_.uv1, d.uv1);
    const Values& col = d.colors;
    if (!col.empty() || !mesh_.colors.empty()) {
      mesh_.colors.resize(base, {1, 1, 1, 1});
      for (size_t i = 0; i < count; ++i)
        mesh_.colors.push_back(i < col.size() ? std::array<float, 4>{float(col[i][0]), float(col[i][1]), float(col[i][2]),
                                                                     d.colorComponents == 4 ? float(col[i][3]) : 1.0f}
                                              : std::array<float, 4>{1, 1, 1, 1});
    }
  }

  /// The indices of accessor `accessor`, checked against the primitive's `count` vertices.
  std::vector<uint32_t> vertexIndices(int accessor, size_t count) const {
    std::vector<uint32_t> idx;
    for (const auto& v : acc_.read(accessor, "indices")) {
      if (v[0] < 0 || v[0] >= double(count))
        throwBadInput(path_ + ": accessor " + std::to_string(accessor) + " (indices) refers to vertex " +
                      (v[0] > -1e18 && v[0] < 1e18 ? std::to_string(int64_t(v[0])) : std::to_string(v[0])) + " of " +
                      std::to_string(count));
      idx.push_back(uint32_t(v[0]));
    }
    return idx;
  }

  /// Triangles, strips or fans of `idx` (relative to `base`). A node whose
  /// world matrix mirrors the mesh makes its triangles wind clockwise: they are
  /// flipped, so every output triangle is counter-clockwise (the solid fill
  /// relies on consistent orientation).
  void appendTriangles(int mode, const std::vector<uint32_t>& idx, uint32_t base, uint32_t material, uint32_t part,
                       bool mirrored) {
    auto addTri = [&](uint32_t a, uint32_t b, uint32_t c) {
      if (mirrored) std::swap(b, c);
      mesh_.triangles.push_back({base + a, base + b, base + c});
      mesh_.triangleMaterial.push_back(material);
      mesh_.trianglePart.push_back(part);
    };
    if (mode == TINYGLTF_MODE_TRIANGLES)
      for (size_t i = 0; i + 2 < idx.size(); i += 3) addTri(idx[i], idx[i + 1], idx[i + 2]);
    else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)
      for (size_t i = 0; i + 2 < idx.size(); ++i)
        (i % 2 == 0) ? addTri(idx[i], idx[i + 1], idx[i + 2]) : addTri(idx[i + 1], idx[i], idx[i + 2]);
    else
      for (size_t i = 1; i + 1 < idx.size(); ++i) addTri(idx[0], idx[i], idx[i + 1]);
  }

  const tinygltf::Model& model_;
  const std::string& path_;
  const uint32_t defaultMaterial_;
  Mesh& mesh_;
  std::vector<std::string>& warnings_;
  const Accessors acc_;
  std::vector<uint8_t> visited_;
  size_t invalidPositions_ = 0;
  std::string firstInvalid_;  // names the first accessor with non-finite positions
};

/// Per-vertex arrays that exist cover every vertex (uv zeros, colour white).
void padVertexAttributes(Mesh& mesh) {
  if (!mesh.uv0.empty()) mesh.uv0.resize(mesh.positions.size(), {0, 0});
  if (!mesh.uv1.empty()) mesh.uv1.resize(mesh.positions.size(), {0, 0});
  if (!mesh.colors.empty()) mesh.colors.resize(mesh.positions.size(), {1, 1, 1, 1});
}

}  // namespace

Mesh readGltf(const std::string& path, const MeshReadOptions& options, std::vector<std::string>& warnings,
              DeferredTextures* deferred) {
  // Mapped, not read: the file's bytes are not copied (tinygltf copies the
  // .glb's binary chunk once, and the images stay in that copy).
  const FileView file(path);
  return readGltfMemory(std::string_view(file.data(), file.size()), path, hasExtension(path, ".glb"), options, warnings,
                        deferred);
}

Mesh readGltfMemory(std::string_view bytes, const std::string& path, bool isBinary, const MeshReadOptions& options,
                    std::vector<std::string>& warnings, DeferredTextures* deferred) {
  EncodedImages encoded;
  // Shared: images left to `deferred` are read from the model's buffers after this returns.
  const auto modelPtr = std::make_shared<tinygltf::Model>(loadModel(bytes, path, isBinary, encoded, warnings));
  tinygltf::Model& model = *modelPtr;
  Mesh mesh;
  listFilesRead(model, path, mesh);
  refuseMissingImages(model, encoded, path, options, warnings);
  // An undecodable image is a warning with ignoreMissingMaterials, which must
  // be known when the read returns: those files decode here.
  if (options.ignoreMissingMaterials) deferred = nullptr;
  std::vector<int> jobOf;
  if (deferred) jobOf = decodeImagesLater(modelPtr, encoded, colourImages(model), path, *deferred);
  else decodeImages(model, encoded, colourImages(model), path, options, warnings);
  const uint32_t defaultMaterial = addMaterials(model, path, mesh, warnings, deferred, jobOf);
  NodeWalker walker(model, path, defaultMaterial, mesh, warnings);
  for (int root : rootNodes(model)) walker.visit(root, identity(), "", 0);
  if (mesh.parts.empty()) mesh.parts.push_back({"", std::filesystem::path(path).filename().string()});
  walker.refuseInvalidPositions(options);
  checkFinite(mesh, path, options, warnings);
  padVertexAttributes(mesh);
  return mesh;
}

}  // namespace vox
