// Snapping, and the clip of far-reaching triangles (contract in lattice_triangles.h).
#include "libvox/mesh/lattice_triangles.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "libvox/core/error.h"
#include "libvox/mesh/voxelize.h"

namespace vox {

namespace {

using ld = long double;

/// A vertex of a triangle's clipped polygon: grid coordinates, barycentric
/// coordinates in the triangle, and the mesh vertex it is (-1: made by the clip).
struct ClipVertex {
  ld p[3];
  ld w[3];
  int64_t vertex;
};

struct ClipPolygon {
  int n = 0;
  ClipVertex v[12];  // a triangle clipped by 6 planes has at most 9 vertices
};

/// Whether `a` precedes `b` (grid coordinates, lexicographic): which end of
/// an edge the crossing is measured from when both lie as near the plane.
bool before(const ClipVertex& a, const ClipVertex& b) {
  return std::lexicographical_compare(a.p, a.p + 3, b.p, b.p + 3);
}

/// The part of `src` with p[axis] >= bound (keepAbove) or <= bound. A
/// crossing is measured from the edge's end nearer the plane, whichever way
/// the polygon runs, so an edge two triangles share is cut at the same point
/// in both, and the rounding scales with that end's distance to the plane
/// (the far end may lie 1e12 voxels away).
void clipPlane(const ClipPolygon& src, ClipPolygon& dst, int axis, bool keepAbove, ld bound) {
  ld d[12];
  for (int i = 0; i < src.n; ++i) d[i] = keepAbove ? src.v[i].p[axis] - bound : bound - src.v[i].p[axis];
  dst.n = 0;
  for (int i = 0; i < src.n; ++i) {
    const int j = i + 1 == src.n ? 0 : i + 1;
    if (d[i] >= 0) dst.v[dst.n++] = src.v[i];
    // A crossing at an end on the plane is that end itself, kept where it is (d = 0).
    if ((d[i] >= 0) != (d[j] >= 0) && d[i] != 0 && d[j] != 0) {
      const bool fromI = std::abs(d[i]) < std::abs(d[j]) || (std::abs(d[i]) == std::abs(d[j]) && before(src.v[i], src.v[j]));
      const ClipVertex& n = fromI ? src.v[i] : src.v[j];
      const ClipVertex& f = fromI ? src.v[j] : src.v[i];
      const ld dn = fromI ? d[i] : d[j], df = fromI ? d[j] : d[i];
      const ld t = dn / (dn - df);  // in [0, 1/2]: the signs differ and |dn| <= |df|
      ClipVertex& q = dst.v[dst.n++];
      for (int k = 0; k < 3; ++k) {
        q.p[k] = n.p[k] + (f.p[k] - n.p[k]) * t;
        q.w[k] = n.w[k] + (f.w[k] - n.w[k]) * t;
      }
      q.p[axis] = bound;
      q.vertex = -1;
    }
  }
}

std::string distanceText(ld g) {
  char text[32];  // llround is undefined past int64's range
  std::snprintf(text, sizeof text, std::abs(g) < 1e15L ? "%.0Lf" : "%.3Lg", std::abs(g));
  return text;
}

}  // namespace

LatticeTriangles latticeTriangles(const Mesh& mesh, const SceneHeader& header, FarTriangles far) {
  LatticeTriangles out;
  const size_t nv = mesh.positions.size();
  out.lattice.resize(nv);
  std::vector<uint8_t> beyond;  // per vertex, once one is: 1 beyond the range
  for (size_t i = 0; i < nv; ++i)
    for (int k = 0; k < 3; ++k) {
      const double world = mesh.positions[i][k];
      // The vertex named as its file numbers it (the mesh records where its vertices came from).
      if (!std::isfinite(world))
        throwBadInput(mesh.describeVertex(i) + " has a non-finite coordinate; drop the triangles that touch it",
                      Setting::DropInvalid);
      const double grid = (world - header.origin[k]) / header.voxelSize;  // may overflow to infinity: beyond too
      if (!(std::abs(grid) <= kMaxLatticeDistance)) {
        if (far == FarTriangles::Refuse) {
          const ld g = (ld(world) - header.origin[k]) / header.voxelSize;
          const double times = std::ceil(double(std::abs(g) / ld(kMaxLatticeDistance)));
          char larger[48];
          std::snprintf(larger, sizeof larger, times < 1e15 ? "%.0f" : "%.3g", times);
          throwBadInput(mesh.describeVertex(i) + " lies " + distanceText(g) + " voxels from the grid along " +
                            "xyz"[k] + ", beyond the 2^20 a solid fill reaches (whether a voxel is inside depends "
                            "on every triangle, so far ones cannot be clipped away as a surface fill clips them); "
                            "remove the far geometry, use voxels at least " + larger +
                            " times larger, or fill only the surface",
                        Setting::FillMode);
        }
        if (beyond.empty()) beyond.assign(nv, 0);
        beyond[i] = 1;
        continue;
      }
      out.lattice[i][k] = snapToLattice(grid);
    }
  if (beyond.empty()) return out;
  for (size_t i = 0; i < nv; ++i)
    if (beyond[i]) out.lattice[i] = {0, 0, 0};  // no triangle below refers to it

  // The clip box, within the range: the grid grown by the margin.
  const double dimv[3] = {double(header.dims.x), double(header.dims.y), double(header.dims.z)};
  for (int k = 0; k < 3; ++k)
    if (dimv[k] + kFarClipMargin > kMaxLatticeDistance)
      throwUsage("the grid's " + std::to_string(uint64_t(dimv[k])) + " voxels along " + "xyz"[k] +
                     " leave no room to clip the triangles that reach more than 2^20 voxels from it; use fewer, "
                     "larger voxels",
                 Setting::VoxelSpacing);
  const ld lo[3] = {-kFarClipMargin, -kFarClipMargin, -kFarClipMargin};
  const ld hi[3] = {dimv[0] + kFarClipMargin, dimv[1] + kFarClipMargin, dimv[2] + kFarClipMargin};

  out.clipped = true;
  const size_t nt = mesh.triangles.size();
  size_t kept = 0;
  for (const auto& tri : mesh.triangles) kept += !beyond[tri[0]] && !beyond[tri[1]] && !beyond[tri[2]];
  out.triangles.reserve(kept);
  out.source.reserve(kept);
  struct Fan {
    std::array<uint32_t, 3> corners;
    uint32_t source;
    std::array<std::array<double, 3>, 3> weights;
  };
  std::vector<Fan> fans;
  std::vector<std::array<int64_t, 3>> made;  // the clip's vertices, appended to `lattice` at their count
  for (size_t t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    if (!beyond[tri[0]] && !beyond[tri[1]] && !beyond[tri[2]]) {
      out.triangles.push_back(tri);
      out.source.push_back(uint32_t(t));
      continue;
    }
    ClipPolygon a, b;
    a.n = 3;
    bool misses = false;
    for (int c = 0; c < 3; ++c) {
      ClipVertex& v = a.v[c];
      const uint32_t vi = tri[size_t(c)];
      for (int k = 0; k < 3; ++k) {
        // A vertex within the range keeps the grid coordinate it is snapped
        // from; a far one is converted in long double (a double may overflow).
        const double world = mesh.positions[vi][k];
        v.p[k] = beyond[vi] ? (ld(world) - header.origin[k]) / header.voxelSize
                            : ld((world - header.origin[k]) / header.voxelSize);
        v.w[k] = c == k ? 1 : 0;
      }
      v.vertex = beyond[vi] ? -1 : int64_t(vi);
    }
    for (int k = 0; k < 3; ++k) {
      const ld mn = std::min({a.v[0].p[k], a.v[1].p[k], a.v[2].p[k]}), mx = std::max({a.v[0].p[k], a.v[1].p[k], a.v[2].p[k]});
      misses = misses || mx < lo[k] || mn > hi[k];
    }
    if (!misses)
      for (int k = 0; k < 3 && a.n > 0; ++k) {
        clipPlane(a, b, k, true, lo[k]);
        clipPlane(b, a, k, false, hi[k]);
      }
    if (misses || a.n < 3) {
      ++out.dropped;
      continue;
    }
    uint32_t index[12];
    for (int i = 0; i < a.n; ++i) {
      const ClipVertex& v = a.v[i];
      if (v.vertex >= 0) {
        index[i] = uint32_t(v.vertex);
        continue;
      }
      if (nv + made.size() >= size_t(UINT32_MAX))
        throwUsage("clipping the far triangles made more than 2^32 vertices; crop the mesh before the bake");
      index[i] = uint32_t(nv + made.size());
      std::array<int64_t, 3> q;
      for (int k = 0; k < 3; ++k) q[size_t(k)] = snapToLattice(double(v.p[k]));
      made.push_back(q);
    }
    auto weights = [&](int i) {
      return std::array<double, 3>{double(a.v[i].w[0]), double(a.v[i].w[1]), double(a.v[i].w[2])};
    };
    for (int i = 1; i + 1 < a.n; ++i)
      fans.push_back({{index[0], index[i], index[i + 1]}, uint32_t(t), {weights(0), weights(i), weights(i + 1)}});
  }
  // Exact sizes (a growth by doubling would keep up to twice the bytes for
  // the whole bake: voxelize_memory.h counts these copies as they are).
  out.lattice.reserve(nv + made.size());
  out.lattice.insert(out.lattice.end(), made.begin(), made.end());
  made = {};
  out.firstFan = out.triangles.size();
  out.triangles.reserve(out.firstFan + fans.size());
  out.source.reserve(out.firstFan + fans.size());
  out.fanWeights.reserve(fans.size());
  for (const Fan& f : fans) {
    out.triangles.push_back(f.corners);
    out.source.push_back(f.source);
    out.fanWeights.push_back(f.weights);
  }
  return out;
}

}  // namespace vox
