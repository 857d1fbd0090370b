#include "libvox/mesh/winding_number.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace vox {

namespace {

constexpr double kLatticeStepsPerVoxel = 65536.0;  // 2^kSubvoxelBits (libvox/mesh/voxelize.h)

struct PointHash {
  size_t operator()(const LatticePoint& p) const {
    uint64_t h = 1469598103934665603ull;
    for (int64_t c : p) h = (h ^ uint64_t(c)) * 1099511628211ull;
    return size_t(h ^ (h >> 29));
  }
};

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

std::vector<CapTriangle> capBoundaryLoops(const std::vector<std::array<uint32_t, 3>>& triangles,
                                          const std::vector<LatticePoint>& lattice) {
  // Weld by lattice position: soups that share positions but not indices are closed.
  std::unordered_map<LatticePoint, uint32_t, PointHash> idOf;
  std::vector<LatticePoint> points;
  std::vector<uint32_t> weld(lattice.size(), UINT32_MAX);
  auto welded = [&](uint32_t v) {
    if (weld[v] == UINT32_MAX) {
      auto [it, fresh] = idOf.emplace(lattice[v], uint32_t(points.size()));
      if (fresh) points.push_back(lattice[v]);
      weld[v] = it->second;
    }
    return weld[v];
  };
  // Net count of each undirected edge, signed along (low id -> high id).
  struct EdgeCount {
    int64_t net = 0;
    uint32_t firstTriangle = 0;
  };
  std::unordered_map<uint64_t, uint32_t> edgeIndex;
  std::vector<std::pair<uint64_t, EdgeCount>> edges;  // in order of first appearance
  for (uint32_t t = 0; t < triangles.size(); ++t) {
    const uint32_t id[3] = {welded(triangles[t][0]), welded(triangles[t][1]), welded(triangles[t][2])};
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = id[e], b = id[(e + 1) % 3];
      if (a == b) continue;  // degenerate edge: no boundary
      const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      auto [it, fresh] = edgeIndex.emplace(key, uint32_t(edges.size()));
      if (fresh) edges.push_back({key, EdgeCount{0, t}});
      edges[it->second].second.net += a < b ? 1 : -1;
    }
  }
  // Boundary edges, directed as the mesh runs them, grouped into loops
  // (connected components: each is a closed 1-cycle, so its fan is closed too).
  struct Boundary {
    uint32_t from, to, triangle;
    int64_t multiplicity;
  };
  std::vector<Boundary> boundary;
  std::vector<uint32_t> parent(points.size());
  std::iota(parent.begin(), parent.end(), 0u);
  for (const auto& [key, c] : edges) {
    if (c.net == 0) continue;
    const uint32_t lo = uint32_t(key >> 32), hi = uint32_t(key & 0xffffffffu);
    boundary.push_back(c.net > 0 ? Boundary{lo, hi, c.firstTriangle, c.net}
                                 : Boundary{hi, lo, c.firstTriangle, -c.net});
    const uint32_t ra = findRoot(parent, lo), rb = findRoot(parent, hi);
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
  }
  // Centroid of each loop's vertices (each vertex once), rounded to the lattice.
  std::unordered_map<uint32_t, std::array<long double, 4>> sums;
  std::vector<uint8_t> counted(points.size(), 0);
  for (const Boundary& b : boundary)
    for (uint32_t v : {b.from, b.to}) {
      if (counted[v]) continue;
      counted[v] = 1;
      auto& s = sums[findRoot(parent, v)];
      for (int k = 0; k < 3; ++k) s[k] += (long double)points[v][k];
      s[3] += 1;
    }
  std::vector<CapTriangle> caps;
  for (const Boundary& b : boundary) {
    const auto& s = sums[findRoot(parent, b.from)];
    LatticePoint apex;
    for (int k = 0; k < 3; ++k) apex[k] = int64_t(std::llround(s[k] / s[3]));
    // The mesh runs from -> to; the cap runs to -> from, so the edge cancels.
    for (int64_t m = 0; m < b.multiplicity; ++m) caps.push_back({{apex, points[b.to], points[b.from]}, b.triangle});
  }
  return caps;
}

double triangleSolidAngle(const double a[3], const double b[3], const double c[3]) {
  const double la = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  const double lb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
  const double lc = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  const double det =
      a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
  const double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const double bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
  const double ca = c[0] * a[0] + c[1] * a[1] + c[2] * a[2];
  const double den = la * lb * lc + ab * lc + bc * la + ca * lb;
  return 2.0 * std::atan2(det, den);
}

CapField::CapField(const std::vector<CapTriangle>& caps) {
  tris_.reserve(caps.size());
  for (const CapTriangle& c : caps) {
    Tri t;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) t.v[i][k] = double(c.v[i][k]) / kLatticeStepsPerVoxel;
    for (int k = 0; k < 3; ++k) t.s[k] = (t.v[0][k] + t.v[1][k] + t.v[2][k]) / 3.0;
    t.r = 0;
    for (int i = 0; i < 3; ++i)
      t.r = std::max(t.r, std::hypot(t.v[i][0] - t.s[0], t.v[i][1] - t.s[1], t.v[i][2] - t.s[2]));
    t.r = t.r * (1 + 1e-12) + 1e-9;  // rounding of the centroid and distances
    const double e1[3] = {t.v[1][0] - t.v[0][0], t.v[1][1] - t.v[0][1], t.v[1][2] - t.v[0][2]};
    const double e2[3] = {t.v[2][0] - t.v[0][0], t.v[2][1] - t.v[0][1], t.v[2][2] - t.v[0][2]};
    t.area = 0.5 * std::hypot(e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]);
    if (t.area == 0) continue;  // no solid angle anywhere
    tris_.push_back(t);
  }
}

double CapField::reach() const {
  double area = 0;
  for (const Tri& t : tris_) area += t.area;
  return std::sqrt(area / (2.0 * M_PI));
}

double CapField::winding(const double p[3], const std::vector<uint32_t>* which) const {
  double total = 0;
  auto add = [&](const Tri& t) {
    double a[3], b[3], c[3];
    for (int k = 0; k < 3; ++k) a[k] = t.v[0][k] - p[k], b[k] = t.v[1][k] - p[k], c[k] = t.v[2][k] - p[k];
    total += triangleSolidAngle(a, b, c);
  };
  if (which)
    for (uint32_t i : *which) add(tris_[i]);
  else
    for (const Tri& t : tris_) add(t);
  return total / (4.0 * M_PI);
}

void CapField::splitForBlock(const double centre[3], double radius, double& farValue, double& farBound,
                             std::vector<uint32_t>& near) const {
  near.clear();
  double value = 0, bound = 0;
  for (uint32_t i = 0; i < tris_.size(); ++i) {
    const Tri& t = tris_[i];
    const double d = std::hypot(centre[0] - t.s[0], centre[1] - t.s[1], centre[2] - t.s[2]) - t.r - radius;
    if (d <= 0) {  // the block reaches the triangle's bounding sphere: no bound
      near.push_back(i);
      continue;
    }
    double a[3], b[3], c[3];
    for (int k = 0; k < 3; ++k)
      a[k] = t.v[0][k] - centre[k], b[k] = t.v[1][k] - centre[k], c[k] = t.v[2][k] - centre[k];
    value += triangleSolidAngle(a, b, c);
    bound += 2.0 * t.area / (d * d * d);
  }
  farValue = value / (4.0 * M_PI);
  farBound = radius * bound / (4.0 * M_PI) + 1e-9;
}

}  // namespace vox
