// Block maps (`map.json`, the block-map format) to scenes.
//
//   { "worldScale": 2.0,
//     "blocks": [ {"position": [10, 5, 10], "blockType": "Stone"}, ... ] }
//
// * Index coordinates are the block positions; the scene's dims run from 0 to the
//   largest position + 1 on each axis (no padding).
// * Class ids follow the block-map format's material order: Grass 1, Dirt 2, Stone 3, Plank 4,
//   Snow 5, Sand 6, Water 7 (Air = 0: an "Air" block is accepted and stays empty).
//   The class table is vox::blockPalette() with each face's colour.
// * Each block is one vote for its class; a block is a surface voxel when one of
//   its 6 neighbours is not a block (the faces a face-culling block mesher draws).
// * World placement is the block-map format's block_to_world: block (x, y, z) covers world
//   [(x - X/2) s, (x + 1 - X/2) s] x [y s, (y + 1) s] x [(z - Z/2) s, (z + 1 - Z/2) s]
//   with s = worldScale and (X, Y, Z) the world grid size; so voxel size = s and
//   origin = (-X/2 s, 0, -Z/2 s). The placement is stored in the scene
//   (SceneHeader::blockWorld) so renders can line up the format's cameras (`metadata.json`).
// * Refused, with the block's index in the array: unknown block types, positions
//   that are not 3 integers, negative, or outside the world grid, and duplicate
//   positions. Other top-level keys (e.g. "sequence") are ignored.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "libvox/scene/scene.h"

namespace vox {

/// The largest block world side: positions pack into 21 bits per axis.
inline constexpr uint32_t kMaxBlockWorldSide = 1u << 21;

struct BlockMapOptions {
  std::array<uint32_t, 3> gridSize = kDefaultBlockWorldGrid;  // 1..kMaxBlockWorldSide per axis
};

/// Reads `path`. Throws vox::Error (BadInput) naming the file and the block.
Scene readBlockMap(const std::string& path, const BlockMapOptions& options = {});

/// Same, from JSON text already in memory (`path` is used in messages only).
Scene parseBlockMap(const std::string& text, const std::string& path, const BlockMapOptions& options = {});

}  // namespace vox
