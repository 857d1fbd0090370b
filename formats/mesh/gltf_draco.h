// KHR_draco_mesh_compression: one glTF primitive's Draco bitstream decoded
// with Debian's libdraco into the values vox reads from it. Draco itself
// dequantizes quantized attributes (positions, texture coordinates, colours)
// as the extension specifies (min + q * range / (2^bits - 1)); integer
// attributes are then normalized by the glTF accessor's rules, exactly as an
// uncompressed accessor of the same type is.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace vox {

/// An attribute wanted from the Draco mesh: the Draco unique id the
/// extension's "attributes" object maps it to, and the glTF accessor's
/// `normalized` flag (integer data is normalized when either that flag or
/// Draco's own says so).
struct DracoAttributeRequest {
  std::string semantic;  // "POSITION", "TEXCOORD_0", ... (for messages)
  int uniqueId = -1;
  bool normalized = false;
};

struct DracoDecoded {
  /// Per request, one value per Draco point (unused components 0), and the
  /// number of components the Draco attribute has.
  std::vector<std::vector<std::array<double, 4>>> values;
  std::vector<int> components;
  size_t points = 0;
  /// Three point indices per triangle, each < points.
  std::vector<uint32_t> indices;
};

/// Decodes the `size` bytes at `data`. Throws BadInput beginning with `who`
/// (e.g. "model.glb: mesh 'Body' primitive 0 (KHR_draco_mesh_compression)")
/// when the bitstream does not decode to a triangle mesh, a requested unique
/// id is not an attribute of it, or an attribute or face refers past the
/// decoded data.
DracoDecoded decodeDraco(const unsigned char* data, size_t size, const std::vector<DracoAttributeRequest>& requests,
                         const std::string& who);

}  // namespace vox
