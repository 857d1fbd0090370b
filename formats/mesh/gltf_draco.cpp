#include "formats/mesh/gltf_draco.h"

#include <draco/compression/decode.h>

#include <algorithm>
#include <cstring>

#include "libvox/core/counted.h"
#include "libvox/core/error.h"

namespace vox {

namespace {

/// Component `c` of the raw value at `p` of Draco type `type`, as glTF reads
/// the same component type (normalized: the glTF 2.0 formulas, signed values
/// clamped at -1).
double component(const uint8_t* p, draco::DataType type, int c, bool normalized) {
  switch (type) {
    case draco::DT_INT8: { int8_t t; std::memcpy(&t, p + c, 1); return normalized ? std::max(t / 127.0, -1.0) : t; }
    case draco::DT_UINT8: { uint8_t t = p[c]; return normalized ? t / 255.0 : t; }
    case draco::DT_INT16: { int16_t t; std::memcpy(&t, p + 2 * c, 2); return normalized ? std::max(t / 32767.0, -1.0) : t; }
    case draco::DT_UINT16: { uint16_t t; std::memcpy(&t, p + 2 * c, 2); return normalized ? t / 65535.0 : t; }
    case draco::DT_INT32: { int32_t t; std::memcpy(&t, p + 4 * c, 4); return t; }
    case draco::DT_UINT32: { uint32_t t; std::memcpy(&t, p + 4 * c, 4); return t; }
    case draco::DT_FLOAT32: { float t; std::memcpy(&t, p + 4 * c, 4); return t; }
    case draco::DT_FLOAT64: { double t; std::memcpy(&t, p + 8 * c, 8); return t; }
    default: return 0;  // refused before (kinds glTF has no accessor for)
  }
}

bool supportedType(draco::DataType t) {
  return t == draco::DT_INT8 || t == draco::DT_UINT8 || t == draco::DT_INT16 || t == draco::DT_UINT16 ||
         t == draco::DT_INT32 || t == draco::DT_UINT32 || t == draco::DT_FLOAT32 || t == draco::DT_FLOAT64;
}

}  // namespace

DracoDecoded decodeDraco(const unsigned char* data, size_t size, const std::vector<DracoAttributeRequest>& requests,
                         const std::string& who) {
  const std::string fix = "; the compressed data is corrupt (re-export the file)";
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(data), size);
  auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok()) throwBadInput(who + ": not a Draco bitstream (" + type.status().error_msg_string() + ")" + fix);
  if (type.value() != draco::TRIANGULAR_MESH)
    throwBadInput(who + ": the Draco data is a point cloud, not a triangle mesh" + fix);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok() || !decoded.value())
    throwBadInput(who + ": the Draco data does not decode (" +
                  (decoded.ok() ? std::string("no mesh") : decoded.status().error_msg_string()) + ")" + fix);
  const draco::Mesh& mesh = *decoded.value();

  DracoDecoded out;
  out.points = mesh.num_points();
  for (const DracoAttributeRequest& r : requests) {
    const draco::PointAttribute* att = r.uniqueId >= 0 ? mesh.GetAttributeByUniqueId(uint32_t(r.uniqueId)) : nullptr;
    if (!att)
      throwBadInput(who + ": " + r.semantic + " names Draco attribute " + std::to_string(r.uniqueId) +
                    ", which the compressed mesh does not have" + fix);
    const int comps = att->num_components();
    if (!supportedType(att->data_type()) || comps < 1 || comps > 4)
      throwBadInput(who + ": Draco attribute " + std::to_string(r.uniqueId) + " (" + r.semantic +
                    ") has a data type or component count glTF has no accessor for" + fix);
    const bool normalized = r.normalized || att->normalized();
    const int64_t bytes = int64_t(draco::DataTypeLength(att->data_type())) * comps;
    const int64_t available = att->buffer() ? int64_t(att->buffer()->data_size()) : 0;
    std::vector<std::array<double, 4>> values(out.points, std::array<double, 4>{0, 0, 0, 0});
    for (uint32_t p = 0; p < out.points; ++p) {
      const draco::AttributeValueIndex avi = att->mapped_index(draco::PointIndex(p));
      const int64_t pos = avi.value() < att->size() ? att->GetBytePos(avi) : -1;
      if (pos < 0 || pos + bytes > available)
        throwBadInput(who + ": Draco attribute " + std::to_string(r.uniqueId) + " (" + r.semantic + ") of point " +
                      std::to_string(p) + " refers past its " + counted(att->size(), "value", "values") + fix);
      const uint8_t* src = att->buffer()->data() + pos;
      for (int c = 0; c < comps; ++c) values[p][size_t(c)] = component(src, att->data_type(), c, normalized);
    }
    out.values.push_back(std::move(values));
    out.components.push_back(comps);
  }
  out.indices.reserve(size_t(mesh.num_faces()) * 3);
  for (uint32_t f = 0; f < mesh.num_faces(); ++f)
    for (const draco::PointIndex& p : mesh.face(draco::FaceIndex(f))) {
      if (p.value() >= out.points)
        throwBadInput(who + ": Draco face " + std::to_string(f) + " refers to point " + std::to_string(p.value()) +
                      " of " + std::to_string(out.points) + fix);
      out.indices.push_back(p.value());
    }
  return out;
}

}  // namespace vox
