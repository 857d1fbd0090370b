#include "libvox/mesh/winding_number.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
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
  std::vector<CapTriangle> caps;
  std::vector<uint32_t> cycle, source, level, levelSource;
  for (uint32_t s : starts) {
    while (used[s] < out[s].size()) {
      cycle.clear(), source.clear();
      uint32_t v = s;
      do {
        const auto [to, tri] = out[v][used[v]++];
        cycle.push_back(v), source.push_back(tri);
        v = to;
      } while (v != s);
      // Balanced triangulation of the walk, reversed (the caps run against the
      // mesh's boundary, so the edges cancel): each round cuts the triangles
      // (p0, p2, p1), (p2, p4, p3), ... off the polygon and keeps p0, p2, p4,
      // ...; triangles near the rim are as small as its edges, and each round
      // doubles their size (a fan's long slivers would defeat CapField's tree).
      while (cycle.size() >= 3) {
        const size_t n = cycle.size();
        level.clear(), levelSource.clear();
        for (size_t i = 0; i + 1 < n; i += 2) {
          caps.push_back({{points[cycle[i]], points[cycle[(i + 2) % n]], points[cycle[i + 1]]}, source[i]});
          level.push_back(cycle[i]), levelSource.push_back(source[i]);
        }
        if (n % 2) level.push_back(cycle[n - 1]), levelSource.push_back(source[n - 1]);
        if (n == 3) break;  // the last triangle closed it
        cycle.swap(level), source.swap(levelSource);
      }
      // A walk of two edges (a -> b -> a) cancels itself: no cap.
    }
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

}  // namespace

CapField::CapField(const std::vector<CapTriangle>& caps) {
  tris_.reserve(caps.size());
  // The caps' boundary: the edges the cap triangles do not share in both
  // directions (the mesh's boundary edges, reversed), with multiplicity.
  std::map<std::pair<LatticePoint, LatticePoint>, int64_t> net;
  for (const CapTriangle& c : caps)
    for (int i = 0; i < 3; ++i) {
      const LatticePoint &a = c.v[i], &b = c.v[(i + 1) % 3];
      if (a == b) continue;
      if (a < b) ++net[{a, b}];
      else --net[{b, a}];
    }
  for (const auto& [ab, count] : net)
    for (int64_t m = 0; m < std::abs(count); ++m) {
      const LatticePoint& from = count > 0 ? ab.first : ab.second;
      const LatticePoint& to = count > 0 ? ab.second : ab.first;
      Edge e;
      for (int k = 0; k < 3; ++k) e.a[k] = double(from[k]) / kLatticeStepsPerVoxel, e.d[k] = double(to[k] - from[k]) / kLatticeStepsPerVoxel;
      e.len = std::sqrt(dot3(e.d, e.d));
      edges_.push_back(e);
    }
  for (const CapTriangle& c : caps) {
    double v[3][3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) v[i][k] = double(c.v[i][k]) / kLatticeStepsPerVoxel;
    Tri t;
    std::memcpy(t.v, v, sizeof v);
    double e1[3], e2[3];
    sub3(v[1], v[0], e1), sub3(v[2], v[0], e2);
    cross3(e1, e2, t.n);
    const double nLen = std::sqrt(dot3(t.n, t.n));
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

double CapField::winding(const double p[3]) const {
  double total = 0;
  for (const Tri& t : tris_) {
    double a[3], b[3], c[3];
    sub3(t.v[0], p, a), sub3(t.v[1], p, b), sub3(t.v[2], p, c);
    total += triangleSolidAngle(a, b, c);
  }
  return total / (4.0 * M_PI);
}

bool CapField::ballField(const double centre[3], double radius, Ball& ball) const {
  ball.cut.clear();
  for (int k = 0; k < 3; ++k) ball.centre[k] = centre[k], ball.gradient[k] = 0;
  ball.radius = radius;
  const double reachR = radius * (1 + 1e-12) + kPlaneTolerance;
  double s1 = 0, s2 = 0;  // sum_e len_e / gap_e^2, sum_e len_e / gap_e^3
  double g[3] = {0, 0, 0}, gErr = 0;
  uint32_t stack[128];
  int top = 0;
  if (!edgeTree_.empty()) stack[top++] = 0;
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
      if (gap <= 0) return false;  // the ball reaches a rim: no bound
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
  double value = 0, vErr = 0;
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
      value += triangleSolidAngle(a, b, c);
      const double dc[3] = {centre[0] - t.s[0], centre[1] - t.s[1], centre[2] - t.s[2]};
      if (std::sqrt(dot3(dc, dc)) - t.r > reachR) continue;
      if (triangleDistance(centre, t.v[0], t.v[1], t.v[2]) > reachR) continue;
      double cv[3];
      sub3(centre, t.v[0], cv);
      if (std::abs(dot3(t.n, cv)) * t.invN <= kPlaneTolerance) return false;  // the centre on a cap plane
      ball.cut.push_back(i);
    }
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
