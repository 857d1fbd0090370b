// The six faces of a block as the block-map format's renderer draws them
// (docs/export.md, "The block mesh"): for each face its outward
// normal, the neighbour that hides it, its four corners in drawing order, the
// texture coordinates of those corners and the palette slot that colours it;
// and the split of a face's quad into two triangles.
//
// Corners are offsets from the block's min corner in index space (units of one
// voxel): a corner of block (u, v, w) sits at grid (u + cx, v + cy, w + cz).
// Every face's corners run counter-clockwise seen from outside the block, so
// triangles 0-1-2 and 0-2-3 are front faces under glTF's and WebGPU's default
// (counter-clockwise) rule; tests/test_block_mesh.cpp checks it.
//
// Header-only constant data: no dependencies, safe from any thread.
#pragma once

#include <array>
#include <cstdint>

namespace vox {

/// The face order of the block renderer (east, west, top, bottom, south, north).
enum class BlockFace : uint8_t { PosX = 0, NegX = 1, PosY = 2, NegY = 3, PosZ = 4, NegZ = 5 };
inline constexpr int kBlockFaceCount = 6;

/// Which entry of a class's top/bottom/side palette colours a face.
enum class PaletteSlot : uint8_t { Top, Bottom, Side };

struct BlockFaceDef {
  std::array<int8_t, 3> normal;                  // outward, = the neighbour offset
  std::array<std::array<uint8_t, 3>, 4> corners;  // drawing order
  std::array<std::array<uint8_t, 2>, 4> uvs;      // texture coordinates of the corners
  PaletteSlot slot;
  int axis() const { return normal[0] ? 0 : normal[1] ? 1 : 2; }  // 0 = x, 1 = y, 2 = z
};

inline constexpr std::array<BlockFaceDef, kBlockFaceCount> kBlockFaces{{
    {{1, 0, 0}, {{{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}}, {{{0, 1}, {0, 0}, {1, 0}, {1, 1}}}, PaletteSlot::Side},
    {{-1, 0, 0}, {{{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}}, {{{1, 1}, {0, 1}, {0, 0}, {1, 0}}}, PaletteSlot::Side},
    {{0, 1, 0}, {{{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}}}, {{{0, 1}, {0, 0}, {1, 0}, {1, 1}}}, PaletteSlot::Top},
    {{0, -1, 0}, {{{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}}, {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}, PaletteSlot::Bottom},
    {{0, 0, 1}, {{{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}}, {{{0, 1}, {1, 1}, {1, 0}, {0, 0}}}, PaletteSlot::Side},
    {{0, 0, -1}, {{{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}}, {{{1, 1}, {1, 0}, {0, 0}, {0, 1}}}, PaletteSlot::Side},
}};

/// The two triangles of a face's quad, as corner indices.
inline constexpr std::array<uint8_t, 6> kQuadTriangles{0, 1, 2, 0, 2, 3};

}  // namespace vox
