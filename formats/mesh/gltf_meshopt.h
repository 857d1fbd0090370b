// EXT_meshopt_compression: every bufferView the extension compresses is
// decoded with Debian's libmeshoptimizer (the extension's bitstream: vertex
// codec version 0, triangle and index-sequence codecs, OCTAHEDRAL / QUATERNION /
// EXPONENTIAL filters) into a buffer of its own, so the accessors then read it
// as they read any uncompressed view. The fallback buffer, if any, is never read.
#pragma once

#include <string>

namespace tinygltf {
class Model;
}

namespace vox {

/// Decodes every EXT_meshopt_compression bufferView of `model` in place (the
/// view then points at a new buffer holding its decoded bytes). Throws
/// BadInput naming `path` and the bufferView when the extension's fields are
/// out of the specification's ranges or the data does not decode.
void decodeMeshoptViews(tinygltf::Model& model, const std::string& path);

}  // namespace vox
