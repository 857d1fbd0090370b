// What a mesh bake (voxelizeMeshBlocks, then a scene writer) will need in
// memory, estimated before the work from the mesh and the placement.
//
// The model follows the data structures: surface voxels live in 8^3 VoxelBlocks
// (voxel_blocks.h), each with one vote block per class present (a count per
// voted voxel: ~100 bytes plus 4 per voxel) and a 6 KB colour block when the
// mesh has colour, so the surface costs memory in the
// number of 8^3 blocks the triangles touch (proportional to the surface area,
// not to the grid's volume; a region bake's in its box). That count is estimated by splitting every
// triangle into pieces no longer than a cell side and counting the distinct
// cells their bounding boxes touch (cells of 8 voxels, coarser for very large
// surfaces, where the blocks per cell come from the area inside it). A solid
// fill adds a bit per voxel of the mesh's box, the ray crossings, and a compact
// 8^3 block per 512 voxels of enclosed volume (the divergence theorem on the
// triangles; |volume| for inverted or open meshes).
//
// Cost: linear in the triangles plus at most `maxPieces` split pieces (a few
// tens of ms at the default). The cells are counted with a bit per cell and
// class where the mesh has at most four classes and the grid at most 2^24
// cells of one block (a bit set of at most 2 MB per class), else in a table
// of the cells touched: no allocation grows with the grid beyond that bound.
// Calibration against measured peaks: docs/reliability.md ("Memory").
#pragma once

#include <cstdint>
#include <vector>

#include "libvox/core/memory_budget.h"
#include "libvox/core/scene_header.h"
#include "libvox/mesh/mesh.h"
#include "libvox/mesh/voxelize.h"

namespace vox {

/// The shape of a mesh in a placement: what the memory of a bake depends on.
struct SurfaceFootprint {
  double blocks = 0;            // 8^3 blocks the surface touches
  double blockClasses = 0;      // sum over those blocks of the classes present (>= blocks)
  double surfaceVoxels = 0;     // voxels the surface touches (about)
  double area = 0;              // surface area, in voxel faces
  double crossings[3] = {0, 0, 0};  // ray crossings along x, y, z (projected areas)
  double enclosedVoxels = 0;    // |signed volume| in voxels
  double boxVoxels = 0;         // voxels of the mesh's bounding box (clamped to the grid)
  double boxColumns = 0;        // its columns along z (x extent times y extent)
  // With triangles reaching past the lattice's range (a surface bake clips
  // them, lattice_triangles.h): the clipped copy's triangles (the mesh's
  // kept ones and the clip's fans), of them the fans, and the vertices the
  // clip made. 0 when nothing is clipped.
  double clippedTriangles = 0;
  double fanTriangles = 0;
  double clipVertices = 0;
};

/// Measures the footprint of `mesh` placed by `header` (origin, voxel size,
/// dims): of the triangles a surface bake keeps (a triangle reaching more than
/// 2^20 voxels from the grid counts by its part near the grid,
/// lattice_triangles.h). A region bake's header (header.region) gives its
/// box's footprint: blocks counted in the box only, the surface sums by the
/// share of each split piece inside it (the crossings by the share across the
/// rays, which keep every crossing of their columns), the solid-fill box cut
/// to it; a large triangle spanning the world counts only its part in the box.
/// `maxPieces` bounds the work (coarser cells beyond it). Runs on up to
/// `threads` workers (0: every core); the result does not depend on them.
SurfaceFootprint surfaceFootprint(const Mesh& mesh, const std::vector<uint8_t>& triangleClass, const SceneHeader& header,
                                  uint64_t maxPieces = uint64_t(1) << 22, unsigned threads = 1);

/// The mesh's distinct vertex positions (equal coordinates counted once):
/// what the winding rule's weld and boundary tables grow with. An unindexed
/// soup (STL: three vertices per triangle) has about a sixth as many as
/// vertices when closed. Linear in the vertices, with a flat table of 32 to
/// 96 bytes per distinct position meanwhile; it does not depend on the
/// placement, so a caller estimating several resolutions counts once.
uint64_t distinctPositions(const Mesh& mesh);

/// The parts of a bake's peak beyond what is resident before it (the mesh is
/// counted by the caller): vote blocks, colour blocks, solid-fill bits and
/// crossings, interior blocks, and for the winding rule its weld and boundary
/// tables where they outweigh those (they are gone before the blocks grow),
/// and with settings.textureRows the textured pieces kept until they are read.
/// `weldedVertices`: distinctPositions(mesh) for a winding-rule solid fill
/// (the tables' size; at most the vertex count is used), else unused.
/// `besideBlocks`: what the caller adds beside the finished blocks (the scene
/// writer's part), which the tables, gone by then, do not meet either: they
/// count where they exceed the bake's parts and it together.
MemoryEstimate estimateMeshBake(const SurfaceFootprint& f, const Mesh& mesh, const VoxelizeSettings& settings,
                                uint64_t weldedVertices, double besideBlocks = 0);

}  // namespace vox
