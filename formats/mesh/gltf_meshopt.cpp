#include "formats/mesh/gltf_meshopt.h"

#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <cstdint>
#include <vector>

#include "libvox/core/counted.h"
#include "libvox/core/error.h"

namespace vox {

namespace {

/// The member `key` of the extension object: an integer, else `fallback`
/// (absent) or an error (present but not an integer).
int64_t integerField(const tinygltf::Value& ext, const char* key, int64_t fallback, const std::string& who) {
  if (!ext.Has(key)) {
    if (fallback < 0) throwBadInput(who + " lacks \"" + key + "\"; the file is malformed (re-export it)");
    return fallback;
  }
  const tinygltf::Value& v = ext.Get(key);
  if (!v.IsInt() && !(v.IsNumber() && v.GetNumberAsDouble() == double(int64_t(v.GetNumberAsDouble()))))
    throwBadInput(who + ": \"" + key + "\" is not an integer; the file is malformed (re-export it)");
  return int64_t(v.GetNumberAsDouble());
}

std::string stringField(const tinygltf::Value& ext, const char* key, const std::string& fallback) {
  return ext.Has(key) && ext.Get(key).IsString() ? ext.Get(key).Get<std::string>() : fallback;
}

}  // namespace

void decodeMeshoptViews(tinygltf::Model& model, const std::string& path) {
  const size_t views = model.bufferViews.size();
  for (size_t vi = 0; vi < views; ++vi) {
    auto it = model.bufferViews[vi].extensions.find("EXT_meshopt_compression");
    if (it == model.bufferViews[vi].extensions.end()) continue;
    const std::string who = path + ": bufferViews[" + std::to_string(vi) + "] (EXT_meshopt_compression)";
    const tinygltf::Value& ext = it->second;
    if (!ext.IsObject()) throwBadInput(who + " is not an object; the file is malformed (re-export it)");
    const int64_t buffer = integerField(ext, "buffer", -1, who);
    const int64_t offset = integerField(ext, "byteOffset", 0, who);
    const int64_t length = integerField(ext, "byteLength", -1, who);
    const int64_t stride = integerField(ext, "byteStride", -1, who);
    const int64_t count = integerField(ext, "count", -1, who);
    const std::string mode = stringField(ext, "mode", "");
    const std::string filter = stringField(ext, "filter", "NONE");
    if (buffer < 0 || uint64_t(buffer) >= model.buffers.size())
      throwBadInput(who + ": buffer " + std::to_string(buffer) + " does not exist");
    const std::vector<unsigned char>& src = model.buffers[size_t(buffer)].data;
    if (offset < 0 || length < 0 || uint64_t(offset) > src.size() || uint64_t(length) > src.size() - uint64_t(offset))
      throwBadInput(who + ": bytes " + std::to_string(offset) + ".." + std::to_string(offset + length) +
                    " are past the end of buffer " + std::to_string(buffer) + " (" + counted(src.size(), "byte", "bytes") + ")");
    // The specification's ranges; the decoders assume them.
    const bool attributes = mode == "ATTRIBUTES", triangles = mode == "TRIANGLES", indices = mode == "INDICES";
    if (!attributes && !triangles && !indices)
      throwBadInput(who + ": mode \"" + mode + "\" is not ATTRIBUTES, TRIANGLES or INDICES");
    if (attributes ? (stride < 4 || stride > 256 || stride % 4 != 0) : (stride != 2 && stride != 4))
      throwBadInput(who + ": byteStride " + std::to_string(stride) + " is not allowed in mode " + mode);
    if (count < 1 || (triangles && count % 3 != 0))
      throwBadInput(who + ": count " + std::to_string(count) + " is not allowed in mode " + mode);
    if (filter != "NONE" && (!attributes || (filter == "OCTAHEDRAL" && stride != 4 && stride != 8) ||
                             (filter == "QUATERNION" && stride != 8) ||
                             (filter != "OCTAHEDRAL" && filter != "QUATERNION" && filter != "EXPONENTIAL")))
      throwBadInput(who + ": filter \"" + filter + "\" is not allowed with mode " + mode + " and byteStride " +
                    std::to_string(stride));
    // No codec expands one byte to more than 64 (vertex blocks spend at least
    // 2 bits per 16 bytes; a triangle code or an index costs a byte): a larger
    // count is refused before its memory is allocated.
    const uint64_t bytes = uint64_t(count) * uint64_t(stride);
    if (bytes > 64 * uint64_t(length) + 65536)
      throwBadInput(who + ": count " + std::to_string(count) + " x byteStride " + std::to_string(stride) +
                    " cannot come from " + std::to_string(length) + " compressed bytes; the file is corrupt");
    tinygltf::Buffer decoded;
    decoded.data.resize(size_t(bytes));
    const unsigned char* in = src.data() + offset;
    int rc = 0;
    if (attributes) rc = meshopt_decodeVertexBuffer(decoded.data.data(), size_t(count), size_t(stride), in, size_t(length));
    else if (triangles) rc = meshopt_decodeIndexBuffer(decoded.data.data(), size_t(count), size_t(stride), in, size_t(length));
    else rc = meshopt_decodeIndexSequence(decoded.data.data(), size_t(count), size_t(stride), in, size_t(length));
    if (rc != 0)
      throwBadInput(who + ": the " + mode + " data does not decode (meshoptimizer error " + std::to_string(rc) +
                    "); the file is corrupt or uses a newer codec version (re-export it)");
    if (filter == "OCTAHEDRAL") meshopt_decodeFilterOct(decoded.data.data(), size_t(count), size_t(stride));
    if (filter == "QUATERNION") meshopt_decodeFilterQuat(decoded.data.data(), size_t(count), size_t(stride));
    if (filter == "EXPONENTIAL") meshopt_decodeFilterExp(decoded.data.data(), size_t(count), size_t(stride));
    model.buffers.push_back(std::move(decoded));
    tinygltf::BufferView& view = model.bufferViews[vi];
    view.buffer = int(model.buffers.size() - 1);
    view.byteOffset = 0;
    view.byteLength = size_t(bytes);
    if (attributes) view.byteStride = size_t(stride);
  }
}

}  // namespace vox
