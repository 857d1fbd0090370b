// Mesh -> scene voxelization, exact and deterministic.
//
// Spaces: the mesh is in world units; the scene's placement (SceneHeader origin
// and voxelSize) defines grid space g = (world - origin) / voxelSize, where voxel
// (u, v, w) covers the closed box [u, u+1] x [v, v+1] x [w, w+1].
//
// Exactness: vertices are snapped to a lattice of 2^-16 voxel (kSubvoxelBits) in
// grid space, then every decision is made with exact integer arithmetic on the
// snapped triangles (64-bit coordinates, 128-bit products). So results do not
// depend on evaluation order or thread count, shared edges and vertices give
// identical decisions on both sides (watertight), and vertices that lie exactly
// on voxel faces, edges or corners are treated exactly. Range: lattice points
// lie within 2^20 voxels of the grid's origin. A surface fill drops the
// triangles with a vertex beyond that which miss the grid (grown by 64
// voxels), and clips those that cross it to that box, fanning the clipped
// polygon: the grid's voxels are those of the whole triangle, within the
// snapping's own bound (libvox/mesh/lattice_triangles.h states it). A solid
// fill refuses such a vertex (vox::Error BadInput, Setting::FillMode): its
// inside depends on every triangle whole.
//
// Surface fill: a voxel is occupied exactly when its closed box intersects a
// (snapped) triangle: the separating-axis test with the 13 axes of a
// triangle/box pair, evaluated exactly. Degenerate triangles (zero area) occupy
// the voxels their segment or point touches.
//
// Votes: a voxel gets, for each class, the area of that class's triangles inside
// its box in units of 2^-16 voxel faces (voxelSize^2 / 65536), rounded to the
// nearest integer, and at least 1 for every triangle that touches it (so a
// voxel touched only along an edge still counts). Integer sums make the result
// independent of the thread count.
//
// Solid fill: surface voxels plus the voxels whose centre is inside the mesh,
// by one of two rules (SolidRule):
//
// Winding (default): a centre p is inside when |w(p)| > 0.5, w the generalised
// winding number (Jacobson et al. 2013: the sum of the triangles' solid angles
// / 4pi). Computed as w = W - w_caps (libvox/mesh/winding_number.h): the
// boundary loops of the mesh are closed by caps (fans around each loop's
// centroid), W is the exact integer winding number of the capped mesh along a
// +z ray (signed crossings, top-left rule: rays through shared edges and
// vertices count each crossing once), and w_caps, the caps' solid angle, is
// evaluated per 8^3 block at its centre with a rigorous bound on its variation
// over the block (|grad Omega| <= 2 A / d^3 per cap triangle whose bounding
// sphere the block does not reach); a block with a cap within reach, or where
// the bound leaves |w| on either side of 0.5, splits in 8, down to single
// voxels evaluated over every cap. On closed meshes
// (no boundary edge after welding equal lattice positions) there are no caps
// and w = W exactly: inside when W != 0 (inverted, nested and overlapping
// parts included). Cost beyond the surface: the +z crossings of the capped mesh
// plus (8^3 blocks) x (cap triangles).
//
// Parity: a centre is inside when at least two of three axis-parallel rays
// (+x, +y, +z) see a non-zero winding number (exact signed crossings as above).
// Exact (equal to the winding rule) on closed, consistently oriented meshes;
// on open meshes holes mislead the rays through them (leaks, or interiors left
// empty).
//
// Interior voxels get kInteriorVotes votes for the class of the triangle
// whose crossing last entered a part along +z (the part that encloses them; a
// crossing enters when it raises |winding number|, so parts with inverted
// winding are entered too; a cap crossing counts for the triangle owning its
// boundary edge), no colour, and surface flag false. Interior voxels with no
// entering crossing below them get the +x then +y rays' class (parity) or the
// first triangle's class (winding).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "libvox/mesh/mesh.h"
#include "libvox/core/progress.h"
#include "libvox/core/round_half_away.h"
#include "libvox/core/scene_header.h"
#include "libvox/mesh/class_compaction.h"
#include "libvox/mesh/texture_rows.h"
#include "libvox/mesh/voxel_blocks.h"

namespace vox {

inline constexpr int kSubvoxelBits = 16;
inline constexpr uint32_t kInteriorVotes = 65536;  // one full voxel face of area

enum class FillMode { Surface, Solid };
enum class SolidRule { Winding, Parity };

struct VoxelizeSettings {
  FillMode fill = FillMode::Surface;
  SolidRule solidRule = SolidRule::Winding;  // solid fill only
  unsigned threads = 1;  // 1 = serial; the result does not depend on it
  ProgressFn progress;
  /// Where a Scene is built (voxelizeMesh, voxelizeMeshSdf): when set, the
  /// classes of the header's table that received no vote (their triangles lie
  /// outside the domain or have no area) are left out of the scene's table,
  /// renumbered as ClassIds says. voxelizeMeshBlocks ignores it: its caller
  /// owns the table (leaveOutClassesWithoutVotes in class_compaction.h).
  std::optional<ClassIds> leaveOutClassesWithoutVotes;
  /// A region bake (libvox/core/regions.h): only the voxels inside this
  /// inclusive index box, each exactly as the whole bake makes it. The surface
  /// pass visits only the voxels of the box (a triangle straddling regions is
  /// voxelized by each region it touches, its per-voxel pieces clipped the same
  /// way); a solid fill works on the box only, with every triangle's crossings
  /// counted along whole rays (the winding number W of a column below the box
  /// is the sum of the crossings there, kept in their order), and the caps'
  /// solid angle of every cap: both rules are exact on a region. Memory and
  /// time: the box's, plus a pass over every triangle.
  std::optional<IndexBox> region;
  /// Texture images read row by row (libvox/mesh/texture_rows.h), for the
  /// mesh textures without pixels that it names: after the surface pass's
  /// geometry the bake reads every one of its images once, top to bottom, a
  /// band of rows at a time, on up to `threads` tasks, and the textured pieces
  /// (48 bytes each, plus 8 for their sorting) are kept with their voxels'
  /// colour sums until then. An image that cannot be read ends the bake with
  /// its error (the first in index order). The colours are those of a bake
  /// whose textures were decoded before: the sums are integers. Not owned;
  /// each image is opened once, so a source serves one bake.
  TextureRowSource* textureRows = nullptr;
};

/// How many tiles the surface pass cuts the domain into on `threads`
/// workers: a few per thread, taken as threads come free; a coloured mesh is
/// tiled on one thread too, since a tile's colour sums live only until its
/// colours are written (so `threads` tiles' sums at a time). For memory
/// estimates (voxelize_memory.h) as much as for the pass. Without colour one
/// tile on one thread saves clipping the triangles that straddle tiles
/// (stanford-bunny 256: 2.5% instructions); with colour tiles bound the sums
/// (box12 at 512: 298 -> 222 MB peak when they were introduced).
inline size_t surfaceTileCount(unsigned threads, bool color) {
  return threads > 1 || color ? size_t(4) * (threads > 2 ? threads : 2u) : 1;
}

/// Voxelizes `mesh` into blocks (no OpenVDB involved) with `header` (dims,
/// placement, class table); libvox/scene/voxelize_scene.h turns them into a
/// Scene, formats/scene/scene_vdb_direct.h writes them straight to a file.
/// `triangleClass[i]` is the class id (in header.classes) of triangle i.
/// Colour: when the mesh has colour, each surface voxel gets the vote-weighted
/// (area-weighted) average over the triangle pieces inside it of base colour
/// factor x vertex colour x texture (linear light; 8-bit sRGB texels decoded
/// exactly), evaluated at the centre of each piece (bilinear texture sampling
/// with the material's wrap modes, or nearest when the sampler says so).
/// Sums are integers, so colours do not depend on the thread count. Not yet validated
/// against the header: VoxelBlocks::validate() or SceneBuilder::build() does it.
VoxelBlocks voxelizeMeshBlocks(const Mesh& mesh, const std::vector<uint8_t>& triangleClass,
                               const SceneHeader& header, const VoxelizeSettings& settings);

/// Which class ids of `triangleClass` have a triangle touching the grid's
/// closed domain [0, dims] (index space): exactly the classes a surface bake
/// of the whole mesh gives a vote (every touching triangle gives each voxel it
/// touches at least one vote). A region bake keeps the whole bake's class
/// table with it without seeing the other regions.
std::array<bool, 256> classesTouchingDomain(const Mesh& mesh, const std::vector<uint8_t>& triangleClass,
                                            const SceneHeader& header);

/// Exact closed-box / triangle intersection on snapped grid coordinates (in
/// units of 2^-kSubvoxelBits voxel), exposed for tests and the brute-force
/// oracle. The box is voxel (u, v, w).
bool triangleTouchesVoxel(const std::array<int64_t, 3> tri[3], int32_t u, int32_t v, int32_t w);

/// Snaps a grid-space coordinate to the lattice (round to nearest, ties away
/// from 0). Inline and without libm: it runs for every vertex coordinate
/// before the surface pass, on one thread.
inline int64_t snapToLattice(double g) { return llroundHalfAway(g * double(int64_t(1) << kSubvoxelBits)); }

}  // namespace vox
