// Block meshes: the visible faces of a ClassVolume as the block-map format's
// renderer builds them, and the same surface with coplanar faces merged.
//
// Culled mesh (meshVisibleFaces): every face of an occupied voxel whose
// neighbour across it is empty (or outside the volume's box) becomes one quad,
// visited in the renderer's order: v (its y) outermost, then w (z), then u (x),
// and for each block the faces in BlockFace order (block_faces.h). A quad's
// four vertices are the face's corners in drawing order, placed at
//     world = (index + corner) * voxelSize + origin
// with the face's normal and texture coordinates; the two triangles are
// kQuadTriangles (0-1-2, 0-2-3).
//
// Merged mesh (mergeCoplanarFaces): faces with the same direction, the same
// plane, the same class and the same colour are merged into rectangles: runs
// along the first in-plane axis, then runs of equal extent stacked along the
// second. The covered surface is exactly the culled one (tests/test_block_mesh.cpp
// rasterizes both). Texture coordinates grow with the rectangle (a w x h
// rectangle spans w x h texture tiles), so a repeating texture keeps one tile
// per block.
//
// Colours are linear-light RGB (glTF's COLOR_0 convention): a face's palette
// colour is the class's top/bottom/side colour (its display colour when the
// class has no face palette; libvox/render/render_modes.h facePaletteColor), decoded
// from sRGB; FaceColor::Voxel uses the voxel's own colour instead, and the
// palette colour for voxels without one (counted in uncoloredFaces).
//
// Deterministic: the quads and their order do not depend on `threads`.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "libvox/core/block_faces.h"
#include "libvox/core/class_volume.h"
#include "libvox/core/classes.h"
#include "libvox/render/render.h"
#include "libvox/render/render_modes.h"

namespace vox {

enum class FaceColor { Palette, Voxel };

/// One quad: a face of a block, or a rectangle of coplanar faces.
struct BlockQuad {
  Coord3 block;                     // index of the block at the rectangle's min corner
  std::array<uint32_t, 2> extent{1, 1};  // blocks along the two in-plane axes, lower axis first
  BlockFace face = BlockFace::PosX;
  uint8_t classId = 0;
  RgbLinear color;
  bool operator==(const BlockQuad&) const = default;
};

struct BlockMesh {
  std::vector<BlockQuad> quads;
  uint64_t unitFaces = 0;       // block faces covered (= quads for a culled mesh)
  uint64_t uncoloredFaces = 0;  // FaceColor::Voxel: faces of voxels without a colour (palette used)
  uint64_t triangles() const { return 2 * uint64_t(quads.size()); }
};

struct BlockMeshSettings {
  FaceColor color = FaceColor::Palette;
  unsigned threads = 1;
  /// Called once by meshVisibleFaces with the exact number of quads, after
  /// counting them and before allocating them: a caller's memory guard
  /// (libvox/core/memory_budget.h) throws here to refuse the mesh. Optional.
  std::function<void(uint64_t quads)> beforeAllocating;
};

/// The culled mesh of `volume`. Throws vox::Error (BadInput) when a voxel's
/// class is not in `classes` (a face cannot be coloured), and (Usage) for
/// FaceColor::Voxel on a volume without colour.
BlockMesh meshVisibleFaces(const ClassVolume& volume, const ClassTable& classes, const BlockMeshSettings& settings);

/// The merged mesh of a culled mesh (quads of extent 1 x 1). Quads come out
/// by face direction, then plane, then the rectangle's min corner (second
/// in-plane axis, then first).
BlockMesh mergeCoplanarFaces(const BlockMesh& culled, unsigned threads = 1);

/// The mesh's quads grouped by class id (ascending), each group in mesh order.
std::vector<std::vector<BlockQuad>> quadsByClass(const BlockMesh& mesh);

/// One vertex as written to glTF (interleaved, 44 bytes, no padding).
struct BlockVertex {
  std::array<float, 3> position;  // world
  std::array<float, 3> normal;
  std::array<float, 3> color;     // linear RGB
  std::array<float, 2> uv;
  bool operator==(const BlockVertex&) const = default;
};
static_assert(sizeof(BlockVertex) == 44);

/// The two in-plane axes of a face (0 = u/x, 1 = v/y, 2 = w/z), lower first.
std::array<int, 2> inPlaneAxes(BlockFace face);

/// The four vertices of `quad` in drawing order. Positions are computed in
/// double and rounded once to float.
std::array<BlockVertex, 4> quadVertices(const BlockQuad& quad, const GridFrame& frame);

}  // namespace vox
