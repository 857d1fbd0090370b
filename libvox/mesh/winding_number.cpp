#include "libvox/mesh/winding_number.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <tuple>
#include <queue>
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

/// A closed walk along the boundary: vertex[i] -> vertex[i + 1] (cyclic) is a
/// boundary edge owned by mesh triangle source[i].
struct Walk {
  std::vector<uint32_t> vertex, source;
};

/// Joins walks that come within one voxel of each other into one walk each,
/// through bridges: an edge x -> y and its reverse y -> x between vertices of
/// two walks, which cancel, so the caps' boundary stays the mesh's. Why: an
/// unwelded seam between two patches of a mesh leaves two loops side by side
/// running in opposite directions; capped one by one they give two large caps
/// whose fields cancel almost everywhere but whose bounds add up, so every
/// block near them needs evaluating voxel by voxel. Joined, the ears cut
/// shortest first zip the seam with triangles as wide as its gap. Walks are
/// joined along a minimum spanning forest of their closest vertex pairs
/// (shortest first, ties by walk order: deterministic); a joined walk starts
/// as its first walk did.
std::vector<Walk> bridgeWalks(std::vector<Walk>& walks, const std::vector<LatticePoint>& points) {
  if (walks.size() < 2) return std::move(walks);
  constexpr int64_t kReach = 65536;  // one voxel in lattice steps (libvox/mesh/voxelize.h)
  auto cellOf = [](const LatticePoint& p) {
    LatticePoint c;
    for (int k = 0; k < 3; ++k) c[k] = p[k] >= 0 ? p[k] / kReach : -((-p[k] + kReach - 1) / kReach);
    return c;
  };
  // cell -> its walk vertices, with their positions inline: the pair loop
  // below reads every neighbour of every vertex.
  struct Entry {
    uint32_t walk, pos;
    LatticePoint at;
  };
  std::unordered_map<LatticePoint, std::vector<Entry>, PointHash> grid;
  for (uint32_t w = 0; w < walks.size(); ++w)
    for (uint32_t i = 0; i < walks[w].vertex.size(); ++i) {
      const LatticePoint& p = points[walks[w].vertex[i]];
      grid[cellOf(p)].push_back({w, i, p});
    }
  struct Bridge {
    double length2;
    uint32_t walkA, posA, walkB, posB;  // walkA < walkB
    bool operator<(const Bridge& o) const {
      return std::tie(length2, walkA, walkB, posA, posB) < std::tie(o.length2, o.walkA, o.walkB, o.posA, o.posB);
    }
  };
  // The closest pair of every two walks within reach, gathered walk by walk:
  // one walk's candidates (its vertices' neighbours on higher walks) sorted by
  // the other walk, the first of each kept. Why not a map keyed by the pair
  // of walks: a soup of separate triangles has a walk per triangle and
  // millions of pairs within a voxel at a coarse --res, and the map's nodes
  // were a third of a 30,000-triangle soup's solid fill at --res 16.
  std::vector<Bridge> bridges, near;
  auto byOtherWalk = [](const Bridge& a, const Bridge& b) { return a.walkB != b.walkB ? a.walkB < b.walkB : a < b; };
  auto keepClosest = [&](std::vector<Bridge>& v) {  // sorted by byOtherWalk, the first per walk kept
    std::sort(v.begin(), v.end(), byOtherWalk);
    v.erase(std::unique(v.begin(), v.end(), [](const Bridge& a, const Bridge& b) { return a.walkB == b.walkB; }), v.end());
  };
  constexpr size_t kCompactAt = size_t(1) << 16;  // a long rim beside a dense soup: keep `near` bounded
  for (uint32_t w = 0; w < walks.size(); ++w) {
    near.clear();
    for (uint32_t i = 0; i < walks[w].vertex.size(); ++i) {
      const LatticePoint& p = points[walks[w].vertex[i]];
      const LatticePoint c = cellOf(p);
      for (int64_t dx = -1; dx <= 1; ++dx)
        for (int64_t dy = -1; dy <= 1; ++dy)
          for (int64_t dz = -1; dz <= 1; ++dz) {
            const auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
            if (it == grid.end()) continue;
            for (const Entry& e : it->second) {
              if (e.walk <= w) continue;  // each pair once, from its lower walk
              double d2 = 0;
              for (int k = 0; k < 3; ++k) d2 += double(e.at[k] - p[k]) * double(e.at[k] - p[k]);
              if (d2 > double(kReach) * double(kReach)) continue;
              near.push_back({d2, w, i, e.walk, e.pos});
            }
          }
      if (near.size() >= kCompactAt) keepClosest(near);
    }
    keepClosest(near);
    bridges.insert(bridges.end(), near.begin(), near.end());
  }
  if (bridges.empty()) return std::move(walks);
  std::sort(bridges.begin(), bridges.end());
  std::vector<uint32_t> root(walks.size());
  std::iota(root.begin(), root.end(), 0u);
  auto find = [&](uint32_t w) {
    while (root[w] != w) w = root[w] = root[root[w]];
    return w;
  };
  // Children hung on a walk's positions: (position, child walk, child's position).
  std::vector<std::vector<std::array<uint32_t, 3>>> links(walks.size());
  for (const Bridge& b : bridges) {
    const uint32_t ra = find(b.walkA), rb = find(b.walkB);
    if (ra == rb) continue;
    root[std::max(ra, rb)] = std::min(ra, rb);
    links[b.walkA].push_back({b.posA, b.walkB, b.posB});
    links[b.walkB].push_back({b.posB, b.walkA, b.posA});
  }
  for (auto& l : links) std::sort(l.begin(), l.end());
  // Each tree of walks as one walk, depth first from its lowest walk: at a
  // position with a child, x -> y (bridge), the child's loop from y back to
  // y, y -> x (bridge), then on along the parent. Bridges take their owner
  // from the edge they start beside (they cancel: any owner will do).
  std::vector<Walk> joined;
  std::vector<bool> emitted(walks.size(), false);
  struct Frame {
    uint32_t walk, start, step, link;
    bool child;
  };
  for (uint32_t w0 = 0; w0 < walks.size(); ++w0) {
    if (emitted[w0]) continue;
    Walk out;
    std::vector<Frame> stack{{w0, 0, 0, 0, false}};
    emitted[w0] = true;
    while (!stack.empty()) {
      Frame& f = stack.back();
      const Walk& w = walks[f.walk];
      const uint32_t n = uint32_t(w.vertex.size());
      if (f.step == n) {  // back at the start: a child returns over its bridge
        if (f.child) out.vertex.push_back(w.vertex[f.start]), out.source.push_back(w.source[f.start]);
        stack.pop_back();
        continue;
      }
      const uint32_t k = (f.start + f.step) % n;
      // x on entry, and again on return from each child (then x -> y or x -> next).
      out.vertex.push_back(w.vertex[k]), out.source.push_back(w.source[k]);
      // The next child hung here that is not emitted yet (its parent edge is this one).
      const auto& l = links[f.walk];
      auto it = std::lower_bound(l.begin(), l.end(), std::array<uint32_t, 3>{k, 0, 0});
      it += f.link;
      while (it != l.end() && (*it)[0] == k && emitted[(*it)[1]]) ++it, ++f.link;
      if (it != l.end() && (*it)[0] == k) {
        ++f.link;
        emitted[(*it)[1]] = true;
        stack.push_back({(*it)[1], (*it)[2], 0, 0, true});
        continue;
      }
      f.link = 0, ++f.step;
    }
    joined.push_back(std::move(out));
  }
  return joined;
}

/// Triangulates one closed walk (cycle[i] -> cycle[i + 1] is a boundary edge
/// owned by mesh triangle source[i]) by cutting ears, shortest new edge first
/// (ties by position in the walk: deterministic), each ear (p, q, r) emitted
/// as (p, r, q): reversed, so the caps run against the mesh's boundary and the
/// edges cancel. Why shortest first: the cap's triangles then grow only as far
/// as the hole is wide. A narrow slit is zipped across with triangles about as
/// large as its width, and a round hole is cut in rounds that double inwards;
/// cutting in fixed rounds instead left, along a slit, slivers as long as the
/// slit beside the rim, which every evaluation near the rim had to open.
void cutEars(const std::vector<uint32_t>& cycle, const std::vector<uint32_t>& source,
             const std::vector<LatticePoint>& points, std::vector<CapTriangle>& caps) {
  const size_t n = cycle.size();
  if (n < 3) return;  // a walk of two edges (a -> b -> a) cancels itself: no cap
  std::vector<uint32_t> prev(n), next(n), version(n, 0);
  for (size_t i = 0; i < n; ++i) prev[i] = uint32_t((i + n - 1) % n), next[i] = uint32_t((i + 1) % n);
  auto diagonal = [&](uint32_t i) {  // squared length of the edge an ear at i leaves, in lattice steps
    const LatticePoint &a = points[cycle[prev[i]]], &b = points[cycle[next[i]]];
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += double(b[k] - a[k]) * double(b[k] - a[k]);
    return d2;
  };
  struct Ear {
    double length2;
    uint32_t at, version;
    bool operator>(const Ear& o) const { return length2 != o.length2 ? length2 > o.length2 : at > o.at; }
  };
  std::priority_queue<Ear, std::vector<Ear>, std::greater<Ear>> ears;
  for (uint32_t i = 0; i < n; ++i) ears.push({diagonal(i), i, 0});
  for (size_t left = n; left > 3;) {
    const Ear e = ears.top();
    ears.pop();
    if (e.version != version[e.at]) continue;  // its neighbours changed since: a newer entry exists
    const uint32_t q = e.at, p = prev[q], r = next[q];
    // The ear's first edge p -> q owns it, and the new edge p -> r inherits that owner.
    caps.push_back({{points[cycle[p]], points[cycle[r]], points[cycle[q]]}, source[p]});
    next[p] = r, prev[r] = p, version[q] = UINT32_MAX, --left;
    ears.push({diagonal(p), p, ++version[p]});
    ears.push({diagonal(r), r, ++version[r]});
  }
  uint32_t a = 0;
  while (version[a] == UINT32_MAX) ++a;
  const uint32_t b = next[a], c = next[b];
  caps.push_back({{points[cycle[a]], points[cycle[c]], points[cycle[b]]}, source[a]});
}

}  // namespace

std::vector<LatticePoint> weldNearVertices(const std::vector<LatticePoint>& lattice, int64_t steps) {
  // Distinct positions, in order of first appearance (equal positions are one
  // vertex already).
  std::unordered_map<LatticePoint, uint32_t, PointHash> idOf;
  std::vector<LatticePoint> points;
  std::vector<uint32_t> pointOf(lattice.size());
  for (size_t v = 0; v < lattice.size(); ++v) {
    auto [it, fresh] = idOf.emplace(lattice[v], uint32_t(points.size()));
    if (fresh) points.push_back(lattice[v]);
    pointOf[v] = it->second;
  }
  // Cells of side `steps`: two points within `steps` on every axis are in the
  // same or neighbouring cells.
  auto cellOf = [&](const LatticePoint& p) {
    LatticePoint c;
    for (int k = 0; k < 3; ++k) c[k] = p[k] >= 0 ? p[k] / steps : -((-p[k] + steps - 1) / steps);
    return c;
  };
  constexpr size_t kCrowd = 1024;  // a UV sphere's pole in a soup: one copy per triangle
  std::unordered_map<LatticePoint, std::vector<uint32_t>, PointHash> cells;
  for (uint32_t i = 0; i < points.size(); ++i) cells[cellOf(points[i])].push_back(i);
  std::vector<uint32_t> parent(points.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  auto near = [&](const LatticePoint& a, const LatticePoint& b) {
    for (int k = 0; k < 3; ++k)
      if (std::abs(a[k] - b[k]) > steps) return false;
    return true;
  };
  bool any = false;
  for (uint32_t i = 0; i < points.size(); ++i) {
    const LatticePoint c = cellOf(points[i]);
    const auto& own = cells[c];
    if (own.size() > kCrowd) continue;  // a crowd: too dense to weld by distance
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dz = -1; dz <= 1; ++dz) {
          auto it = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == cells.end() || it->second.size() > kCrowd) continue;
          for (uint32_t j : it->second) {
            if (j <= i || !near(points[i], points[j])) continue;
            const uint32_t a = find(i), b = find(j);
            if (a != b) parent[std::max(a, b)] = std::min(a, b), any = true;
          }
        }
  }
  if (!any) return {};
  // Each cluster's extent; wide ones (a chain of near vertices) stay apart.
  std::vector<LatticePoint> lo(points.size()), hi(points.size());
  for (uint32_t i = 0; i < points.size(); ++i) lo[i] = hi[i] = points[i];
  for (uint32_t i = 0; i < points.size(); ++i) {
    const uint32_t r = find(i);
    for (int k = 0; k < 3; ++k) lo[r][k] = std::min(lo[r][k], points[i][k]), hi[r][k] = std::max(hi[r][k], points[i][k]);
  }
  std::vector<LatticePoint> out(lattice.size());
  bool moved = false;
  for (size_t v = 0; v < lattice.size(); ++v) {
    const uint32_t r = find(pointOf[v]);  // the root is the cluster's lowest index
    bool narrow = true;
    for (int k = 0; k < 3; ++k) narrow = narrow && hi[r][k] - lo[r][k] <= 4 * steps;
    out[v] = narrow ? points[r] : lattice[v];
    moved = moved || out[v] != lattice[v];
  }
  if (!moved) return {};
  return out;
}

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
  // Boundary edges, directed as the mesh runs them (an edge used m more times
  // one way than the other counts m times), split into closed walks: the net
  // boundary has as many edges into as out of every vertex, so following
  // unused outgoing edges from a start always returns to it.
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> out(points.size());  // vertex -> (to, triangle)
  std::vector<uint32_t> starts;
  for (const auto& [key, c] : edges) {
    if (c.net == 0) continue;
    const uint32_t lo = uint32_t(key >> 32), hi = uint32_t(key & 0xffffffffu);
    const uint32_t from = c.net > 0 ? lo : hi, to = c.net > 0 ? hi : lo;
    for (int64_t m = 0; m < std::abs(c.net); ++m) out[from].push_back({to, c.firstTriangle});
    starts.push_back(from);
  }
  std::vector<uint32_t> used(points.size(), 0);  // outgoing edges used per vertex
  std::vector<Walk> walks;
  for (uint32_t s : starts) {
    while (used[s] < out[s].size()) {
      Walk w;
      uint32_t v = s;
      do {
        const auto [to, tri] = out[v][used[v]++];
        w.vertex.push_back(v), w.source.push_back(tri);
        v = to;
      } while (v != s);
      walks.push_back(std::move(w));
    }
  }
  std::vector<CapTriangle> caps;
  for (const Walk& w : bridgeWalks(walks, points)) cutEars(w.vertex, w.source, points, caps);
  return caps;
}

namespace {

double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
void sub3(const double a[3], const double b[3], double out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = a[k] - b[k];
}
void cross3(const double a[3], const double b[3], double out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

/// Distance from p to the segment a + t d, t in [0, 1].
double segmentDistance(const double p[3], const double a[3], const double d[3]) {
  double ap[3];
  sub3(p, a, ap);
  const double dd = dot3(d, d);
  const double t = dd > 0 ? std::clamp(dot3(ap, d) / dd, 0.0, 1.0) : 0.0;
  const double q[3] = {ap[0] - t * d[0], ap[1] - t * d[1], ap[2] - t * d[2]};
  return std::sqrt(dot3(q, q));
}

/// Distance from p to the triangle (a, b, c) (Ericson, Real-Time Collision
/// Detection 5.1.5: the closest point by Voronoi regions).
double triangleDistance(const double p[3], const double a[3], const double b[3], const double c[3]) {
  double ab[3], ac[3], ap[3], q[3];
  sub3(b, a, ab), sub3(c, a, ac), sub3(p, a, ap);
  auto at = [&](double v, double w) {
    for (int k = 0; k < 3; ++k) q[k] = p[k] - (a[k] + v * ab[k] + w * ac[k]);
    return std::sqrt(dot3(q, q));
  };
  const double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
  if (d1 <= 0 && d2 <= 0) return at(0, 0);
  double bp[3];
  sub3(p, b, bp);
  const double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
  if (d3 >= 0 && d4 <= d3) return at(1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return at(d1 / (d1 - d3), 0);
  double cp[3];
  sub3(p, c, cp);
  const double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
  if (d6 >= 0 && d5 <= d6) return at(0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return at(0, d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return at(1 - w, w);
  }
  const double den = 1 / (va + vb + vc);
  return at(vb * den, vc * den);
}

// Points closer than this (voxels) to a cap plane or edge get no jump count:
// far above the rounding of the coordinates (< 2^-30 voxel at any --res the
// voxelizer accepts), far below the lattice step that separates real points.
constexpr double kPlaneTolerance = 1e-9;

// grad Omega = kGradientSign * (Biot-Savart sum over the caps' boundary edges
// v1 -> v2 as written in ballField); checked against finite differences of
// the exact field (test Winding.BallBoundHolds).
constexpr double kGradientSign = 1.0;

}  // namespace

// A tree node is far from a ball when the gap between them exceeds kFar times
// the node's radius: its dipole's error then falls as (r / gap)^2 per area.
constexpr double CapField::kFar;

namespace {

using i128 = __int128;

int sign128(i128 x) { return (x > 0) - (x < 0); }

/// The lattice point at p (voxel units), when p is one: the voxel and block
/// centres the solid fill evaluates are.
bool latticeAt(const double p[3], LatticePoint& out) {
  for (int k = 0; k < 3; ++k) {
    const double s = p[k] * kLatticeStepsPerVoxel;
    if (!(std::abs(s) < 0x1p62) || s != std::nearbyint(s)) return false;
    out[k] = int64_t(s);
  }
  return true;
}

// Where a centre lies on a cap, the field jumps there, and its value must be
// the one on the side the crossing count takes: a crossing at the centre's
// height counts as above it (the centre is approached from -z), and rays
// through a triangle's edge or vertex are owned by the top-left rule, which
// is the ray moved by -delta along x, then by -delta' along y. So the count W
// is the capped mesh's winding number at p + eta, eta = -(eps z + delta x +
// delta' y), eps >> delta >> delta' > 0, and w_caps is taken at p + eta too
// (w_mesh itself is continuous there: no mesh triangle is within half a voxel
// of a centre the fill decides). Evaluated at p itself, Van Oosterom-Strackee
// gives each cap through p half a jump or none by the sign of a rounded zero.

/// Solid angle, in the limit at p + eta, of the infinite sector {p + a u + b v :
/// a, b >= 0} (u x v != 0, lattice vectors): the tangent cone at p of a
/// triangle in whose plane p lies (the rest of it subtends nothing in the
/// limit, being in that plane and away from p).
double sectorAsCounted(const int64_t u[3], const int64_t v[3]) {
  const i128 n[3] = {i128(u[1]) * v[2] - i128(u[2]) * v[1], i128(u[2]) * v[0] - i128(u[0]) * v[2],
                     i128(u[0]) * v[1] - i128(u[1]) * v[0]};
  if (n[2] != 0) {
    // -z leaves the plane: Van Oosterom-Strackee with unit vectors (+z, u, v),
    // scale-free, so the sector's value seen from direction -z.
    const double du[3] = {double(u[0]), double(u[1]), double(u[2])}, dv[3] = {double(v[0]), double(v[1]), double(v[2])};
    const double lu = std::sqrt(du[0] * du[0] + du[1] * du[1] + du[2] * du[2]);
    const double lv = std::sqrt(dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]);
    const double uv = du[0] * dv[0] + du[1] * dv[1] + du[2] * dv[2];
    return 2 * std::atan2(double(n[2]) / (lu * lv), 1 + du[2] / lu + dv[2] / lv + uv / (lu * lv));
  }
  // -z lies in the plane. The side delta then takes: the sign of n . eta.
  const int side = n[0] != 0 ? -sign128(n[0]) : -sign128(n[1]);
  // -z strictly inside the cone: (u x -z) . n > 0 and (-z x v) . n > 0.
  const i128 a1 = n[1] * u[0] - n[0] * u[1], a2 = n[0] * v[1] - n[1] * v[0];
  if (a1 > 0 && a2 > 0) return -2 * M_PI * side;
  // -z along a ray (u or v pointing down): p - eps z is on that edge, where
  // the sector is the half-plane towards the other ray w; else outside.
  const int64_t* w = u[0] == 0 && u[1] == 0 && u[2] < 0 ? v : v[0] == 0 && v[1] == 0 && v[2] < 0 ? u : nullptr;
  if (!w) return 0;
  if (n[0] != 0) {
    // Seen from direction -x (across the vertical edge): height y along the
    // unit normal, x along the in-plane normal towards w (w's horizontal
    // part); a half-plane subtends 2 (pi - theta), theta = atan2(|y|, x),
    // positive from its back.
    const double y = -double(n[0]) / std::hypot(double(n[0]), double(n[1]));
    const double x = -double(w[0]) / std::hypot(double(w[0]), double(w[1]));
    return (y > 0 ? -2 : 2) * (M_PI - std::atan2(std::abs(y), x));
  }
  // -x lies in the plane too (n along y): inside the half-plane or not, then off it by delta'.
  return w[0] < 0 ? -2 * M_PI * side : 0;
}

/// The solid angle of triangle v (lattice) at the lattice point p as the
/// crossing count sees it: at p + eta (above). Off the triangle's plane that
/// is its value at p (the determinant's sign exact); in the plane, 0 outside
/// the triangle, -2pi sign(n . eta) inside, and on an edge or at a vertex the
/// sum over the sectors the triangle has at p.
double solidAngleAsCounted(const LatticePoint v[3], const LatticePoint& p) {
  int64_t a[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) a[i][k] = v[i][k] - p[k];
  const int64_t e1[3] = {a[1][0] - a[0][0], a[1][1] - a[0][1], a[1][2] - a[0][2]};
  const int64_t e2[3] = {a[2][0] - a[0][0], a[2][1] - a[0][1], a[2][2] - a[0][2]};
  const i128 n[3] = {i128(e1[1]) * e2[2] - i128(e1[2]) * e2[1], i128(e1[2]) * e2[0] - i128(e1[0]) * e2[2],
                     i128(e1[0]) * e2[1] - i128(e1[1]) * e2[0]};
  if (n[0] == 0 && n[1] == 0 && n[2] == 0) return 0;  // no area: no solid angle anywhere
  const i128 det = n[0] * a[0][0] + n[1] * a[0][1] + n[2] * a[0][2];  // det(a0, a1, a2)
  if (det != 0) {
    // Off the plane: Van Oosterom-Strackee with the exact determinant (its
    // sign decides between +-2pi just off the triangle).
    double d[3][3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) d[i][k] = double(a[i][k]);
    const double la = std::sqrt(dot3(d[0], d[0])), lb = std::sqrt(dot3(d[1], d[1])), lc = std::sqrt(dot3(d[2], d[2]));
    const double den = la * lb * lc + dot3(d[0], d[1]) * lc + dot3(d[1], d[2]) * la + dot3(d[2], d[0]) * lb;
    return 2 * std::atan2(double(det), den);
  }
  // In the plane: which side of each edge, in the projection along n's
  // largest axis (the ax component of (b - a) x (p - a), signed like n's).
  const int ax = std::abs(double(n[0])) >= std::max(std::abs(double(n[1])), std::abs(double(n[2])))
                     ? 0
                     : std::abs(double(n[1])) >= std::abs(double(n[2])) ? 1 : 2;
  const int i = (ax + 1) % 3, j = (ax + 2) % 3, s = sign128(n[ax]);
  int zeros = 0;
  for (int k = 0; k < 3; ++k) {
    const int64_t* A = a[k];
    const int64_t* B = a[(k + 1) % 3];
    const i128 e = (i128(B[i]) - A[i]) * (-i128(A[j])) - (i128(B[j]) - A[j]) * (-i128(A[i]));
    const int side = sign128(e) * s;
    if (side < 0) return 0;  // outside the triangle: nothing in the limit
    zeros += side == 0;
  }
  if (zeros == 0) {  // inside: a full hemisphere, on the side eta takes
    const int side = n[2] != 0 ? -sign128(n[2]) : n[0] != 0 ? -sign128(n[0]) : -sign128(n[1]);
    return -2 * M_PI * side;
  }
  // On an edge or at a vertex: the triangle is the sectors (p, v_k, v_k+1) of
  // non-zero area (those through p's edge have none), all oriented like it.
  double total = 0;
  for (int k = 0; k < 3; ++k) {
    const int64_t* u = a[k];
    const int64_t* w = a[(k + 1) % 3];
    if (i128(u[1]) * w[2] - i128(u[2]) * w[1] == 0 && i128(u[2]) * w[0] - i128(u[0]) * w[2] == 0 &&
        i128(u[0]) * w[1] - i128(u[1]) * w[0] == 0)
      continue;
    total += sectorAsCounted(u, w);
  }
  return total;
}

/// A cap triangle's corners in voxels and its normal (v1 - v0) x (v2 - v0);
/// returns the normal's length (twice the area). The field and reachOf both
/// take the area from here, so the box's growth matches the field's bit for bit.
double capInVoxels(const CapTriangle& c, double v[3][3], double n[3]) {
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) v[i][k] = double(c.v[i][k]) / kLatticeStepsPerVoxel;
  double e1[3], e2[3];
  sub3(v[1], v[0], e1), sub3(v[2], v[0], e2);
  cross3(e1, e2, n);
  return std::sqrt(dot3(n, n));
}

}  // namespace

CapField::CapField(const std::vector<CapTriangle>& caps) {
  // The caps' boundary: the edges the cap triangles do not share in both
  // directions (the mesh's boundary edges, reversed), with multiplicity, in
  // the order of their (lower, upper) endpoints. A sorted array of the signed
  // half-edges, not a map: a soup's caps are as many as its triangles, and
  // a node per edge was a fifth of a 30,000-triangle soup's solid fill at
  // --res 16.
  {  // scoped: the half-edges are freed before the triangles' tree is built
    struct HalfEdge {
      LatticePoint lo, hi;
      int sign;  // +1 from lo to hi, -1 from hi to lo
    };
    std::vector<HalfEdge> halfEdges;
    halfEdges.reserve(3 * caps.size());
    for (const CapTriangle& c : caps)
      for (int i = 0; i < 3; ++i) {
        const LatticePoint &a = c.v[i], &b = c.v[(i + 1) % 3];
        if (a == b) continue;
        if (a < b) halfEdges.push_back({a, b, 1});
        else halfEdges.push_back({b, a, -1});
      }
    std::sort(halfEdges.begin(), halfEdges.end(), [](const HalfEdge& x, const HalfEdge& y) {
      return std::tie(x.lo, x.hi) < std::tie(y.lo, y.hi);
    });
    for (size_t first = 0; first < halfEdges.size();) {
      size_t last = first;
      int64_t count = 0;
      for (; last < halfEdges.size() && halfEdges[last].lo == halfEdges[first].lo &&
             halfEdges[last].hi == halfEdges[first].hi;
           ++last)
        count += halfEdges[last].sign;
      const HalfEdge& ab = halfEdges[first];
      first = last;
      for (int64_t m = 0; m < std::abs(count); ++m) {
        const LatticePoint& from = count > 0 ? ab.lo : ab.hi;
        const LatticePoint& to = count > 0 ? ab.hi : ab.lo;
        Edge e;
        for (int k = 0; k < 3; ++k) e.a[k] = double(from[k]) / kLatticeStepsPerVoxel, e.d[k] = double(to[k] - from[k]) / kLatticeStepsPerVoxel;
        e.len = std::sqrt(dot3(e.d, e.d));
        edges_.push_back(e);
      }
    }
  }
  tris_.reserve(caps.size());
  for (const CapTriangle& c : caps) {
    double v[3][3];
    Tri t;
    const double nLen = capInVoxels(c, v, t.n);
    std::memcpy(t.v, v, sizeof v);
    if (nLen == 0) continue;  // no solid angle anywhere
    area_ += 0.5 * nLen;
    t.invN = 1 / nLen;
    for (int i = 0; i < 3; ++i) {
      double ei[3];
      sub3(v[(i + 1) % 3], v[i], ei);
      t.invEdgeN[i] = 1 / (nLen * std::sqrt(dot3(ei, ei)));
    }
    for (int k = 0; k < 3; ++k) t.s[k] = (v[0][k] + v[1][k] + v[2][k]) / 3.0;
    t.r = 0;
    for (int i = 0; i < 3; ++i) t.r = std::max(t.r, std::hypot(v[i][0] - t.s[0], v[i][1] - t.s[1], v[i][2] - t.s[2]));
    t.r = t.r * (1 + 1e-12) + 1e-9;  // rounding of the centroid and distances
    tris_.push_back(t);
  }
  triTree_ = buildTree(tris_, [](const Tri& t, double out[3][3]) {
    std::memcpy(out, t.v, sizeof t.v);
    return 3;
  });
  edgeTree_ = buildTree(edges_, [](const Edge& e, double out[3][3]) {
    for (int k = 0; k < 3; ++k) out[0][k] = e.a[k], out[1][k] = e.a[k] + e.d[k];
    return 2;
  });
  for (Node& n : triTree_) {  // area and area vector
    n.size = 0, n.vec[0] = n.vec[1] = n.vec[2] = 0;
    for (uint32_t i = n.begin; i < n.end; ++i) {
      n.size += 0.5 / tris_[i].invN;
      for (int k = 0; k < 3; ++k) n.vec[k] += 0.5 * tris_[i].n[k];
    }
  }
  for (Node& n : edgeTree_) {  // length and vector sum
    n.size = 0, n.vec[0] = n.vec[1] = n.vec[2] = 0;
    for (uint32_t i = n.begin; i < n.end; ++i) {
      n.size += edges_[i].len;
      for (int k = 0; k < 3; ++k) n.vec[k] += edges_[i].d[k];
    }
  }
}

template <class Item, class Points>
std::vector<CapField::Node> CapField::buildTree(std::vector<Item>& items, Points points) {
  std::vector<Node> nodes;
  if (items.empty()) return nodes;
  auto centroid = [&](const Item& it, int axis) {
    double v[3][3];
    const int n = points(it, v);
    double c = 0;
    for (int i = 0; i < n; ++i) c += v[i][axis];
    return c / n;
  };
  // Build breadth-first; nodes[i] covers [begin, end), split at the median of
  // the longest axis of its box (ties by position in the list: deterministic).
  nodes.push_back({{0, 0, 0}, 0, 0, uint32_t(items.size()), 0, 0, 0, {0, 0, 0}});
  for (size_t ni = 0; ni < nodes.size(); ++ni) {
    const uint32_t b = nodes[ni].begin, e = nodes[ni].end;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = b; i < e; ++i) {
      double v[3][3];
      const int n = points(items[i], v);
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], v[j][k]), hi[k] = std::max(hi[k], v[j][k]);
    }
    Node& node = nodes[ni];
    for (int k = 0; k < 3; ++k) node.m[k] = 0.5 * (lo[k] + hi[k]);
    double r = 0;
    for (uint32_t i = b; i < e; ++i) {
      double v[3][3];
      const int n = points(items[i], v);
      for (int j = 0; j < n; ++j) {
        double d[3];
        sub3(v[j], node.m, d);
        r = std::max(r, std::sqrt(dot3(d, d)));
      }
    }
    node.r = r * (1 + 1e-12) + 1e-9;
    if (e - b <= kLeafSize) continue;
    const int axis = hi[0] - lo[0] >= std::max(hi[1] - lo[1], hi[2] - lo[2]) ? 0 : hi[1] - lo[1] >= hi[2] - lo[2] ? 1 : 2;
    std::vector<std::pair<double, uint32_t>> keys;
    for (uint32_t i = b; i < e; ++i) keys.push_back({centroid(items[i], axis), i});
    const uint32_t mid = b + (e - b) / 2;
    std::nth_element(keys.begin(), keys.begin() + (mid - b), keys.end());
    std::vector<Item> part;
    for (const auto& k : keys) part.push_back(items[k.second]);
    std::copy(part.begin(), part.end(), items.begin() + b);
    const uint32_t left = uint32_t(nodes.size());
    nodes[ni].left = left, nodes[ni].right = left + 1;
    nodes.push_back({{0, 0, 0}, 0, b, mid, 0, 0, 0, {0, 0, 0}});
    nodes.push_back({{0, 0, 0}, 0, mid, e, 0, 0, 0, {0, 0, 0}});
  }
  return nodes;
}

double CapField::reach() const { return std::sqrt(area_ / (2.0 * M_PI)); }

double CapField::reachOf(const std::vector<CapTriangle>& caps) {
  double area = 0;  // as the constructor sums area_, in the same order
  for (const CapTriangle& c : caps) {
    double v[3][3], n[3];
    area += 0.5 * capInVoxels(c, v, n);
  }
  return std::sqrt(area / (2.0 * M_PI));
}

double CapField::countedAngle(const Tri& t, const LatticePoint& p) {
  LatticePoint v[3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) v[i][k] = std::llround(t.v[i][k] * kLatticeStepsPerVoxel);  // exact: read back
  return solidAngleAsCounted(v, p);
}

double CapField::winding(const double p[3]) const {
  LatticePoint lp;
  const bool onLattice = latticeAt(p, lp);
  double total = 0;
  for (const Tri& t : tris_) {
    double a[3], b[3], c[3];
    sub3(t.v[0], p, a), sub3(t.v[1], p, b), sub3(t.v[2], p, c);
    double det;
    const double omega = triangleSolidAngle(a, b, c, det);
    // Near a cap's plane (det / |n| is p's distance from it), the side the
    // crossing count takes, by exact integers.
    total += onLattice && std::abs(det) * t.invN <= kPlaneTolerance ? countedAngle(t, lp) : omega;
  }
  return total / (4.0 * M_PI);
}

bool CapField::ballField(const double centre[3], double radius, Ball& ball) const {
  ball.cut.clear();
  for (int k = 0; k < 3; ++k) ball.centre[k] = centre[k], ball.gradient[k] = 0;
  ball.radius = radius;
  const double reachR = radius * (1 + 1e-12) + kPlaneTolerance;
  // A lattice point (a voxel centre) takes the caps it lies on (or within
  // kPlaneTolerance of) as the crossing count does (winding): no jumps to count.
  LatticePoint lattice;
  const bool point = radius == 0 && latticeAt(centre, lattice);
  double s1 = 0, s2 = 0;  // sum_e len_e / gap_e^2, sum_e len_e / gap_e^3
  double g[3] = {0, 0, 0}, gErr = 0;
  bool rimsClear = true;
  uint32_t stack[128];
  int top = 0;
  // A point (radius 0) needs the value alone: slope and curvature multiply
  // distances from the centre, all 0. A point on a rim is still refused: the
  // cap triangle on that rim edge has it on its plane (below).
  if (!edgeTree_.empty() && radius > 0) stack[top++] = 0;
  while (top > 0) {
    const Node& n = edgeTree_[stack[--top]];
    double mc[3];
    sub3(n.m, centre, mc);
    const double dist = std::sqrt(dot3(mc, mc)), clear = dist - n.r;
    if (clear - reachR > kFar * n.r) {
      // Far: every edge at least `gap` from the ball; Biot-Savart of the
      // edges ~ K(m) x (sum of edges), K(x) = (x - centre) / |x - centre|^3,
      // off by at most len * r * 2 / clear^3 (K's derivative <= 2 / |x|^3).
      const double gap = clear - reachR;
      s1 += n.size / (gap * gap);
      s2 += n.size / (gap * gap * gap);
      double kx[3], c[3];
      for (int k = 0; k < 3; ++k) kx[k] = mc[k] / (dist * dist * dist);
      cross3(kx, n.vec, c);
      for (int k = 0; k < 3; ++k) g[k] += c[k];
      gErr += n.size * n.r * 2 / (clear * clear * clear);
      continue;
    }
    if (n.left) {
      stack[top++] = n.right;
      stack[top++] = n.left;
      continue;
    }
    for (uint32_t i = n.begin; i < n.end; ++i) {
      const Edge& e = edges_[i];
      const double gap = segmentDistance(centre, e.a, e.d) - reachR;
      if (gap <= 0) {  // the ball reaches a rim: no slope, only the magnitude bound
        rimsClear = false;
        top = 0;
        break;
      }
      s1 += e.len / (gap * gap);
      s2 += e.len / (gap * gap * gap);
      // Biot-Savart over the edge a -> b: (ra x rb) (|ra| + |rb|) / (|ra| |rb| (|ra| |rb| + ra . rb)),
      // ra = a - centre, rb = b - centre (the denominator is 0 only on the edge itself).
      double ra[3], rb[3], c[3];
      sub3(e.a, centre, ra);
      for (int k = 0; k < 3; ++k) rb[k] = ra[k] + e.d[k];
      cross3(ra, rb, c);
      const double la = std::sqrt(dot3(ra, ra)), lb = std::sqrt(dot3(rb, rb));
      const double f = (la + lb) / (la * lb * (la * lb + dot3(ra, rb)));
      for (int k = 0; k < 3; ++k) g[k] += c[k] * f;
    }
  }
  // The same bounds from the caps' area, where the ball stays off every cap:
  // |grad Omega| <= sum over the area of 2 / D^3 and the Hessian's half <=
  // 3 / D^4 (K's derivatives, D: distance from the ball). Why both: the rims'
  // terms add up along both sides of a narrow slit whose fields cancel, while
  // the thin cap zipped across it has little area, so far from the slit this
  // bound is smaller by about the slit's width over the distance.
  double value = 0, vErr = 0, t0 = 0, t1 = 0, t2 = 0;
  bool areaBound = true;
  if (!triTree_.empty()) stack[top++] = 0;
  while (top > 0) {
    const Node& n = triTree_[stack[--top]];
    double mc[3];
    sub3(n.m, centre, mc);
    const double dist = std::sqrt(dot3(mc, mc)), clear = dist - n.r;
    if (clear - reachR > kFar * n.r) {
      // Far (and out of the ball's reach): solid angle ~ (area vector) . K(m),
      // off by at most area * r * 2 / clear^3.
      value += dot3(n.vec, mc) / (dist * dist * dist);
      vErr += n.size * n.r * 2 / (clear * clear * clear);
      const double gap = clear - reachR;
      t0 += n.size / (gap * gap);
      t1 += 2 * n.size / (gap * gap * gap);
      t2 += 3 * n.size / (gap * gap * gap * gap);
      continue;
    }
    if (n.left) {
      stack[top++] = n.right;
      stack[top++] = n.left;
      continue;
    }
    for (uint32_t i = n.begin; i < n.end; ++i) {
      const Tri& t = tris_[i];
      double a[3], b[3], c[3];
      sub3(t.v[0], centre, a), sub3(t.v[1], centre, b), sub3(t.v[2], centre, c);
      const double omega = triangleSolidAngle(a, b, c);
      const double dc[3] = {centre[0] - t.s[0], centre[1] - t.s[1], centre[2] - t.s[2]};
      double gap = std::sqrt(dot3(dc, dc)) - t.r - reachR;
      if (gap <= 0) gap = triangleDistance(centre, t.v[0], t.v[1], t.v[2]) - reachR;
      if (gap > 0) {
        value += omega;
        const double area = 0.5 / t.invN;
        t0 += std::min(2 * M_PI, area / (gap * gap));
        t1 += 2 * area / (gap * gap * gap);
        t2 += 3 * area / (gap * gap * gap * gap);
        continue;
      }
      areaBound = false;
      t0 += 2 * M_PI;  // a triangle's solid angle is below a hemisphere's
      if (point) {
        value += countedAngle(t, lattice);
        continue;
      }
      value += omega;
      double cv[3];
      sub3(centre, t.v[0], cv);
      if (std::abs(dot3(t.n, cv)) * t.invN <= kPlaneTolerance) return false;  // the centre on a cap plane
      ball.cut.push_back(i);
    }
  }
  ball.magnitude = t0 / (4.0 * M_PI) * (1 + 1e-9) + 1e-9;
  ball.rimsClear = rimsClear;
  if (!rimsClear) {  // the rims' sums stopped part way: no gradient, the area's slope at most
    s1 = areaBound ? t1 : INFINITY, s2 = INFINITY, gErr = INFINITY;
    g[0] = g[1] = g[2] = 0;
  } else if (areaBound) {
    s1 = std::min(s1, t1), s2 = std::min(s2, t2);
  }
  ball.value = value / (4.0 * M_PI);
  for (int k = 0; k < 3; ++k) ball.gradient[k] = kGradientSign * g[k] / (4.0 * M_PI);
  ball.slope = s1 / (4.0 * M_PI) * (1 + 1e-9);
  ball.curvature = s2 / (4.0 * M_PI) * (1 + 1e-9);
  ball.valueError = vErr / (4.0 * M_PI) * (1 + 1e-9);
  ball.gradientError = gErr / (4.0 * M_PI) * (1 + 1e-9);
  ball.slack = 1e-9 + 1e-12 * (radius * (std::sqrt(dot3(ball.gradient, ball.gradient)) + ball.slope) + std::abs(ball.value));
  return true;
}

double CapField::magnitudeBound(const double centre[3], double radius, double limit) const {
  // Any cluster off the ball bounds its triangles' sum of A / D^2 by its area
  // over its gap^2: no solid angle is evaluated, and clusters are taken whole
  // as soon as they clear the ball by their own radius.
  const double reachR = radius * (1 + 1e-12) + kPlaneTolerance;
  const double budget = limit * 4.0 * M_PI / (1 + 1e-9);
  double sum = 0;
  uint32_t stack[128];
  int top = 0;
  if (!triTree_.empty()) stack[top++] = 0;
  while (top > 0) {
    const Node& n = triTree_[stack[--top]];
    double mc[3];
    sub3(n.m, centre, mc);
    const double gap = std::sqrt(dot3(mc, mc)) - n.r - reachR;
    if (gap > n.r) {
      sum += n.size / (gap * gap);
    } else if (n.left) {
      stack[top++] = n.right;
      stack[top++] = n.left;
      continue;
    } else {
      for (uint32_t i = n.begin; i < n.end; ++i) {
        const Tri& t = tris_[i];
        const double dc[3] = {centre[0] - t.s[0], centre[1] - t.s[1], centre[2] - t.s[2]};
        double d = std::sqrt(dot3(dc, dc)) - t.r - reachR;
        if (d <= 0) d = triangleDistance(centre, t.v[0], t.v[1], t.v[2]) - reachR;
        sum += d > 0 ? std::min(2 * M_PI, 0.5 / (t.invN * d * d)) : 2 * M_PI;
      }
    }
    if (sum >= budget) return limit;
  }
  return sum / (4.0 * M_PI) * (1 + 1e-9) + 1e-9;
}

bool CapField::jumps(const Ball& ball, const double p[3], int& jump) const {
  jump = 0;
  for (uint32_t i : ball.cut) {
    const Tri& t = tris_[i];
    double cv[3], pv[3];
    sub3(ball.centre, t.v[0], cv), sub3(p, t.v[0], pv);
    const double sc = dot3(t.n, cv) * t.invN, sp = dot3(t.n, pv) * t.invN;  // signed distances to the plane
    if (std::abs(sp) <= kPlaneTolerance) return false;
    if ((sc > 0) == (sp > 0)) continue;  // same side (sc is clear of the plane: ballField)
    const double f = sc / (sc - sp);
    double x[3];
    for (int k = 0; k < 3; ++k) x[k] = ball.centre[k] + f * (p[k] - ball.centre[k]);
    bool outside = false, onEdge = false;
    for (int e = 0; e < 3; ++e) {
      double ei[3], xv[3], c[3];
      sub3(t.v[(e + 1) % 3], t.v[e], ei), sub3(x, t.v[e], xv);
      cross3(ei, xv, c);
      const double d = dot3(c, t.n) * t.invEdgeN[e];  // signed distance of x to the edge's line, in the plane
      outside = outside || d < -kPlaneTolerance;
      onEdge = onEdge || std::abs(d) <= kPlaneTolerance;
    }
    if (outside) continue;
    if (onEdge) return false;
    jump += sc < 0 ? -1 : 1;
  }
  return true;
}

}  // namespace vox
