#include "libvox/mesh/placement.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "libvox/core/error.h"

namespace vox {

void placeGrid(const std::array<double, 3>& meshMin, const std::array<double, 3>& meshMax, const PlacementOptions& o,
               SceneHeader& header) {
  if ((o.resolution == 0) == !(o.voxelSize > 0)) throwUsage("give exactly one of a resolution or a voxel size", Setting::VoxelSpacing);
  std::array<double, 3> lo = meshMin, hi = meshMax;
  if (o.bounds) {
    const auto& b = *o.bounds;
    for (int i = 0; i < 3; ++i) {
      if (!std::isfinite(b[i]) || !std::isfinite(b[i + 3]) || b[i] > b[i + 3])
        throwUsage("the bounds must be finite, xmin,ymin,zmin,xmax,ymax,zmax with min <= max", Setting::Bounds);
      lo[i] = b[i];
      hi[i] = b[i + 3];
    }
  }
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(lo[i]) || !std::isfinite(hi[i]) || lo[i] > hi[i])
      throwBadInput("the input has no finite bounding box (no triangles?)");
  const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  const double vs = o.voxelSize > 0 ? o.voxelSize : longest / o.resolution;
  if (!(vs > 0) || !std::isfinite(vs))
    throwBadInput("the input has zero extent on every axis (a point); give a voxel size", Setting::VoxelSize);
  // The layer the box's faces touch, then `pad` empty ones (placement.h).
  const double layers = o.pad > 0 ? double(o.pad) + 1 : 0;
  Dims d;
  uint32_t* out[3] = {&d.x, &d.y, &d.z};
  for (int i = 0; i < 3; ++i) {
    // The longest axis under a resolution gets exactly `resolution` voxels: side / vs == N up to rounding.
    const double inside = std::max(1.0, std::ceil((hi[i] - lo[i]) / vs * (1 - 1e-12)));
    const double n = inside + 2.0 * layers;
    if (n > kMaxGridAxis) {
      // A count past 2^53 (a voxel size of 1e-300 on a unit mesh) has no
      // integer text worth printing, and would overflow uint64_t.
      auto count = [](double v) {
        if (v < 1e15) return std::to_string(uint64_t(v));
        char text[32];
        std::snprintf(text, sizeof text, "%.3g", v);
        return std::string(text);
      };
      // Name the padding when it alone makes the axis too long (the voxel size is not the problem then).
      if (inside <= kMaxGridAxis && 2.0 * layers > inside)
        throwUsage("the grid would have " + count(n) + " voxels on an axis (limit " +
                   std::to_string(kMaxGridAxis) + "), " + count(2.0 * layers) +
                   " of them the padding; lower --pad");
      throwUsage("the grid would have " + count(n) + " voxels on an axis (limit " +
                 std::to_string(kMaxGridAxis) + "); use fewer, larger voxels",
                 Setting::VoxelSpacing);
    }
    *out[i] = uint32_t(n);
  }
  header.dims = d;
  header.voxelSize = vs;
  header.origin = {lo[0] - layers * vs, lo[1] - layers * vs, lo[2] - layers * vs};
  const std::string problem = placementProblem(header.voxelSize, header.origin, header.dims);
  if (!problem.empty())
    throwUsage("cannot place the grid: " + problem + "; use a lower --res or a larger --voxel-size, or scale the input up (e.g. export it in millimetres)",
               Setting::VoxelSpacing);
}

}  // namespace vox
