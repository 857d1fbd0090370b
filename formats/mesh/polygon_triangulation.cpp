#include "formats/mesh/polygon_triangulation.h"

#include <algorithm>
#include <cmath>

namespace vox {

namespace {

using P2 = std::array<double, 2>;

/// a + b = s + e exactly (Knuth's TwoSum).
inline void twoSum(double a, double b, double& s, double& e) {
  s = a + b;
  const double bv = s - a, av = s - bv;
  e = (a - av) + (b - bv);
}

/// The sign of the exact sum of `n` doubles: Shewchuk's growing expansion
/// keeps the sum exact as non-overlapping components in increasing magnitude,
/// and its sign is its largest component's.
int exactSumSign(const double* terms, int n) {
  double e[16];
  int m = 0;
  for (int i = 0; i < n; ++i) {
    double q = terms[i];
    int k = 0;
    for (int j = 0; j < m; ++j) {
      double s, err;
      twoSum(q, e[j], s, err);
      if (err != 0) e[k++] = err;
      q = s;
    }
    if (q != 0) e[k++] = q;
    m = k;
  }
  return m == 0 ? 0 : e[m - 1] > 0 ? 1 : -1;
}

/// The sign of the turn a -> b -> c (+1: counter-clockwise), exact for
/// coordinates within [1e-150, 1e150] in magnitude (or 0): Shewchuk's error
/// bound decides the clear cases in double; the rest are summed exactly from
/// the six products of the determinant's expansion, each split exactly by fma.
int orient(const P2& a, const P2& b, const P2& c) {
  const double left = (a[0] - c[0]) * (b[1] - c[1]), right = (a[1] - c[1]) * (b[0] - c[0]);
  const double det = left - right;
  double sum;
  if (left > 0) {
    if (right <= 0) return det > 0 ? 1 : det < 0 ? -1 : 0;
    sum = left + right;
  } else if (left < 0) {
    if (right >= 0) return det > 0 ? 1 : det < 0 ? -1 : 0;
    sum = -left - right;
  } else {
    return right > 0 ? -1 : right < 0 ? 1 : 0;
  }
  constexpr double kEps = 1.1102230246251565e-16;  // 2^-53
  const double bound = (3 + 16 * kEps) * kEps * sum;
  if (det >= bound || -det >= bound) return det > 0 ? 1 : -1;
  // det = ax by - ax cy + bx cy - bx ay + cx ay - cx by
  const double f[6][2] = {{a[0], b[1]}, {-a[0], c[1]}, {b[0], c[1]}, {-b[0], a[1]}, {c[0], a[1]}, {-c[0], b[1]}};
  double terms[12];
  for (int k = 0; k < 6; ++k) {
    terms[2 * k] = f[k][0] * f[k][1];
    terms[2 * k + 1] = std::fma(f[k][0], f[k][1], -terms[2 * k]);
  }
  return exactSumSign(terms, 12);
}

/// Within the range where orient's products and their fma errors are exact.
bool inExactRange(double v) {
  const double m = std::fabs(v);
  return m == 0 || (m >= 1e-150 && m <= 1e150);  // also false for NaN
}

/// b -> c goes back along a -> b (a spike): collinear corners whose edges point
/// opposite ways on some axis.
bool turnsBack(const P2& a, const P2& b, const P2& c) {
  for (int k = 0; k < 2; ++k) {
    const double d1 = b[k] - a[k], d2 = c[k] - b[k];
    if ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) return true;
  }
  return false;
}

void fan(size_t n, std::vector<std::array<uint32_t, 3>>& out) {
  for (size_t k = 1; k + 1 < n; ++k) out.push_back({0, uint32_t(k), uint32_t(k + 1)});
}

/// Convex as seen in 2D: no two corners turn opposite ways, none turns back,
/// and the edges' x direction changes sign at most twice (the boundary goes
/// round once: a pentagram turns one way at every corner but twice round).
bool isConvex(const std::vector<P2>& at) {
  const size_t n = at.size();
  int turn = 0, changes = 0, firstDx = 0, lastDx = 0;
  for (size_t i = 0; i < n; ++i) {
    const P2& a = at[i == 0 ? n - 1 : i - 1];
    const P2& b = at[i];
    const P2& c = at[i + 1 == n ? 0 : i + 1];
    const int o = orient(a, b, c);
    if (o == 0) {
      if (turnsBack(a, b, c)) return false;
    } else if (turn == 0) {
      turn = o;
    } else if (o != turn) {
      return false;
    }
    const int dx = c[0] > b[0] ? 1 : c[0] < b[0] ? -1 : 0;
    if (dx == 0) continue;
    if (firstDx == 0) firstDx = dx;
    else if (dx != lastDx) ++changes;
    lastDx = dx;
  }
  if (lastDx != 0 && lastDx != firstDx) ++changes;  // round the corner from the last edge to the first
  return changes <= 2;
}

/// Ear clipping over `s.at` (the polygon in 2D), `sign` its winding (+1
/// counter-clockwise): see the header.
void clipEars(PolygonScratch& s, int sign, std::vector<std::array<uint32_t, 3>>& out) {
  const uint32_t n = uint32_t(s.at.size());
  s.prev.resize(n), s.next.resize(n), s.convex.assign(n, 0), s.removed.assign(n, 0);
  s.reflex.clear();
  for (uint32_t i = 0; i < n; ++i) s.prev[i] = (i + n - 1) % n, s.next[i] = (i + 1) % n;
  auto turnOf = [&](uint32_t i) { return orient(s.at[s.prev[i]], s.at[i], s.at[s.next[i]]) * sign; };
  // Corners that do not turn the polygon's way are the only ones that can lie
  // in an ear of a simple polygon. Those of the start are bucketed in a grid of
  // about one per cell over the polygon's box, so an ear looks only at the
  // cells along it (a corner that turns back later, which happens only in
  // self-intersecting polygons, goes to a list looked at whole); entries go
  // stale as corners are cut or turn convex, and are skipped. Whether a corner
  // blocks an ear is decided by the exact tests alone: the grid changes how
  // many corners are looked at, never the answer.
  for (uint32_t i = 0; i < n; ++i) {
    s.convex[i] = turnOf(i) > 0;
    if (!s.convex[i]) s.reflex.push_back(i);
  }
  double lo[2] = {s.at[0][0], s.at[0][1]}, hi[2] = {lo[0], lo[1]};
  for (const P2& p : s.at)
    for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], p[size_t(k)]), hi[k] = std::max(hi[k], p[size_t(k)]);
  const int cells = std::max(1, int(std::sqrt(double(s.reflex.size()))));
  double scale[2];
  for (int k = 0; k < 2; ++k) {
    scale[k] = hi[k] > lo[k] ? cells / (hi[k] - lo[k]) : 0;
    if (!std::isfinite(scale[k])) scale[k] = 0;
  }
  // Monotone in the coordinate, so a point inside a box is in a cell of the box's range.
  auto cellOf = [&](double v, int k) {
    const double c = (v - lo[k]) * scale[k];
    return c <= 0 ? 0 : c >= cells - 1 ? cells - 1 : int(c);
  };
  s.cellStart.assign(size_t(cells) * size_t(cells) + 1, 0);
  for (const uint32_t q : s.reflex) ++s.cellStart[size_t(cellOf(s.at[q][1], 1)) * size_t(cells) + size_t(cellOf(s.at[q][0], 0)) + 1];
  for (size_t c = 1; c < s.cellStart.size(); ++c) s.cellStart[c] += s.cellStart[c - 1];
  s.cellItems.resize(s.reflex.size());
  s.cellFill.assign(s.cellStart.begin(), s.cellStart.end() - 1);
  for (const uint32_t q : s.reflex)
    s.cellItems[s.cellFill[size_t(cellOf(s.at[q][1], 1)) * size_t(cells) + size_t(cellOf(s.at[q][0], 0))]++] = q;
  s.reflex.clear();  // from here on: the corners that turned back later
  auto classify = [&](uint32_t i) {
    const bool was = s.convex[i];
    s.convex[i] = turnOf(i) > 0;
    if (was && !s.convex[i]) s.reflex.push_back(i);
  };
  auto isEar = [&](uint32_t i) {
    if (!s.convex[i]) return false;
    const P2 &a = s.at[s.prev[i]], &b = s.at[i], &c = s.at[s.next[i]];
    auto blocks = [&](uint32_t q) {
      if (s.removed[q] || s.convex[q] || q == s.prev[i] || q == s.next[i]) return false;
      const P2& p = s.at[q];
      if (p == a || p == b || p == c) return false;  // a repeated corner of the ear itself
      return orient(a, b, p) * sign >= 0 && orient(b, c, p) * sign >= 0 && orient(c, a, p) * sign >= 0;
    };
    // Each row of cells the triangle's box covers, from the cell left of the
    // triangle's extent within the row (grown by half a row up and down,
    // against rounding) to the cell right of it: a long thin ear looks at the
    // cells along it, not at its whole box.
    const int y0 = cellOf(std::min({a[1], b[1], c[1]}), 1), y1 = cellOf(std::max({a[1], b[1], c[1]}), 1);
    const P2* corner[3] = {&a, &b, &c};
    for (int y = y0; y <= y1; ++y) {
      double ya = -INFINITY, yb = INFINITY;
      if (scale[1] > 0) ya = lo[1] + (y - 0.5) / scale[1], yb = lo[1] + (y + 1.5) / scale[1];
      double xlo = INFINITY, xhi = -INFINITY;
      for (int e = 0; e < 3; ++e) {
        const P2& p = *corner[e];
        const P2& q = *corner[(e + 1) % 3];
        if (p[1] >= ya && p[1] <= yb) xlo = std::min(xlo, p[0]), xhi = std::max(xhi, p[0]);
        for (const double edge : {ya, yb})
          if ((p[1] < edge && q[1] > edge) || (p[1] > edge && q[1] < edge)) {
            const double x = p[0] + (q[0] - p[0]) * ((edge - p[1]) / (q[1] - p[1]));
            xlo = std::min(xlo, x), xhi = std::max(xhi, x);
          }
      }
      if (!(xlo <= xhi)) continue;
      const int x0 = std::max(0, cellOf(xlo, 0) - 1), x1 = std::min(cells - 1, cellOf(xhi, 0) + 1);
      for (size_t k = s.cellStart[size_t(y) * size_t(cells) + size_t(x0)];
           k < s.cellStart[size_t(y) * size_t(cells) + size_t(x1) + 1]; ++k)
        if (blocks(s.cellItems[k])) return false;
    }
    for (const uint32_t q : s.reflex)
      if (blocks(q)) return false;
    return true;
  };
  auto cut = [&](uint32_t i) {
    const uint32_t p = s.prev[i], nx = s.next[i];
    out.push_back({p, i, nx});
    s.removed[i] = 1;
    s.next[p] = nx, s.prev[nx] = p;
    classify(p), classify(nx);
    return p;  // the walk goes on from the corner before: its ear changed
  };
  // Going on from the corner before each cut, a simple polygon takes 1.5 to 2
  // n ear tests (a comb, a random star, a 20-turn spiral); a self-intersecting
  // one can take n per triangle (whole walks without an ear). Past 32 n + 1024
  // tests the corners left are fanned from the walk's corner: n - 2 triangles
  // still, in O(n) instead of hours for a scrambled 100,000-corner face.
  uint64_t budget = 32 * uint64_t(n) + 1024;
  uint32_t i = 0;
  for (uint32_t left = n; left > 3; --left) {
    uint32_t steps = 0;
    bool ear = false;
    for (; steps < left && budget > 0; i = s.next[i], ++steps) {
      --budget;
      if ((ear = isEar(i))) break;
    }
    if (ear) {
      i = cut(i);
      continue;
    }
    if (budget == 0) {
      for (uint32_t j = s.next[i]; s.next[j] != i; j = s.next[j]) out.push_back({i, j, s.next[j]});
      return;
    }
    // No ear: the first corner that does not turn, else the first turning the
    // polygon's way, else this one.
    uint32_t pick = i, j = i;
    bool found = false;
    for (uint32_t k = 0; k < left && !found; ++k, j = s.next[j])
      if (turnOf(j) == 0) pick = j, found = true;
    j = i;
    for (uint32_t k = 0; k < left && !found; ++k, j = s.next[j])
      if (s.convex[j]) pick = j, found = true;
    i = cut(pick);
  }
  out.push_back({s.prev[i], i, s.next[i]});
}

}  // namespace

void triangulatePolygon(const std::array<double, 3>* corners, size_t n, std::vector<std::array<uint32_t, 3>>& out,
                        PolygonScratch& scratch) {
  if (n < 3) return;
  if (n == 3) {
    out.push_back({0, 1, 2});
    return;
  }
  // Newell's normal: twice the polygon's area projected on each axis plane.
  double normal[3] = {0, 0, 0};
  for (size_t i = 0; i < n; ++i) {
    const auto& a = corners[i];
    const auto& b = corners[i + 1 == n ? 0 : i + 1];
    if (!inExactRange(a[0]) || !inExactRange(a[1]) || !inExactRange(a[2])) return fan(n, out);
    normal[0] += (a[1] - b[1]) * (a[2] + b[2]);
    normal[1] += (a[2] - b[2]) * (a[0] + b[0]);
    normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::fabs(normal[k]) > std::fabs(normal[axis])) axis = k;
  if (!(normal[axis] != 0) || !std::isfinite(normal[axis])) return fan(n, out);
  // Seen along `axis`, (u, v) cyclic after it: counter-clockwise where that
  // component of the normal is positive.
  const size_t u = size_t(axis + 1) % 3, v = size_t(axis + 2) % 3;
  scratch.at.resize(n);
  for (size_t i = 0; i < n; ++i) scratch.at[i] = {corners[i][u], corners[i][v]};
  if (isConvex(scratch.at)) return fan(n, out);
  const int sign = normal[axis] > 0 ? 1 : -1;
  if (n == 4) {  // a dart: cut along the diagonal through its reflex corner, the fan's where that is 0 or 2
    const auto& p = scratch.at;
    if (orient(p[0], p[1], p[2]) * sign >= 0 && orient(p[0], p[2], p[3]) * sign >= 0) return fan(n, out);
    if (orient(p[1], p[2], p[3]) * sign >= 0 && orient(p[1], p[3], p[0]) * sign >= 0) {
      out.push_back({1, 2, 3});
      out.push_back({1, 3, 0});
      return;
    }
  }
  clipEars(scratch, sign, out);
}

}  // namespace vox
