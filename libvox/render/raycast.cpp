// Why castRay equals castRayBruteForce, bit for bit:
//
// Work in a mirrored frame where every moving axis has dir > 0 (index i' = -i-1,
// origin' = -origin, plane p' = -p). Negation is exact and IEEE rounding is
// symmetric, so time'(p') = (p' - o') * (1/d') is bit-identical to the
// brute force's (p - o) * (1/d) for the same plane: both casters see the same
// numbers, monotone in the plane index.
//
// An "event" is a time T at which the DDA tests every voxel whose per-axis
// intervals all contain T (the product of one index range per axis: one index,
// or two or more when T is a plane crossing on that axis). Events are the
// start time and every plane crossing of a moving axis, except those inside a
// box the DDA jumps over. A jump goes from event T, where the voxels ahead of T
// all lie in one empty 8^3/64^3/512^3 box (on every axis, including the
// 1-2 indices of an axis the ray does not move along), to the first time T' the
// ray reaches a far face of that box. For t strictly between T and T' the
// voxels touched lie inside the box (monotonicity), so none is occupied.
//
// An occupied voxel V with key k touches the ray at k, and k is an event: it is
// the start time or V's entry plane time on some axis, and it cannot lie inside
// a jump (V would be inside an empty box). So the first event with an occupied
// voxel is min key, and the voxels found there are exactly the occupied voxels
// with that key (voxels touched at T whose key is below T were tested at an
// earlier event and are empty). The tie rule is applied to those candidates.
#include "libvox/render/raycast.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vox {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool better(double exitA, const Coord3& a, double exitB, const Coord3& b) {
  if (exitA != exitB) return exitA > exitB;
  if (a.w != b.w) return a.w < b.w;
  if (a.v != b.v) return a.v < b.v;
  return a.u < b.u;
}

int at(const Coord3& c, int a) { return a == 0 ? c.u : a == 1 ? c.v : c.w; }

// The face the ray entered `voxel` through at time `key`: among moving axes
// whose entry plane time equals key, the one the ray is most head-on to
// (largest |dir|), then the lowest axis.
void entryFace(const Ray& ray, const Coord3& voxel, double key, RayHit& hit) {
  hit.faceAxis = -1;
  hit.faceSign = 0;
  double best = -1;
  for (int a = 0; a < 3; ++a) {
    const double d = ray.dir[size_t(a)];
    if (d == 0) continue;
    const double inv = 1.0 / d;
    const double plane = d > 0 ? double(at(voxel, a)) : double(at(voxel, a)) + 1.0;
    const double t = (plane - ray.origin[size_t(a)]) * inv;
    if (t == key && std::fabs(d) > best) {
      best = std::fabs(d);
      hit.faceAxis = a;
      hit.faceSign = d > 0 ? -1 : 1;
    }
  }
}

struct Frame {
  bool moving[3]{};
  bool flip[3]{};
  double o[3]{}, d[3]{}, inv[3]{};
  int64_t dlo[3]{}, dhi[3]{};  // mirrored domain [dlo, dhi)

  double time(int a, int64_t p) const { return (double(p) - o[a]) * inv[a]; }
  int64_t real(int a, int64_t i) const { return flip[a] ? -i - 1 : i; }

  // Indices (mirrored) whose interval on moving axis a contains T, from a guess.
  void range(int a, double T, int64_t guess, int64_t& lo, int64_t& hi) const {
    int64_t i = guess;
    while (time(a, i) > T) --i;
    while (time(a, i + 1) <= T) ++i;
    hi = i;
    lo = i;
    while (time(a, lo) >= T) --lo;
  }
  int64_t guess(int a, double T, int64_t minI, int64_t maxI) const {
    const double g = std::floor(o[a] + T * d[a]);
    if (!(g >= double(minI))) return minI;
    if (!(g <= double(maxI))) return maxI;
    return int64_t(g);
  }
};

}  // namespace

namespace {
inline Ray sanitized(const Ray& ray) {
  Ray r = ray;
  double m = 0;
  for (double d : r.dir) m = std::max(m, std::fabs(d));
  for (double& d : r.dir)
    if (std::fabs(d) < m * 1e-200 || std::fabs(d) < 1e-290) d = 0;
  return r;
}
}  // namespace

Ray sanitizeRay(const Ray& ray) { return sanitized(ray); }

bool rayVoxelInterval(const Ray& ray, const Coord3& voxel, double& enter, double& exit) {
  enter = -kInf;
  exit = kInf;
  for (int a = 0; a < 3; ++a) {
    const double o = ray.origin[size_t(a)], d = ray.dir[size_t(a)];
    const double c = double(at(voxel, a));
    if (d == 0) {
      if (o < c || o > c + 1.0) return false;
      continue;
    }
    const double inv = 1.0 / d;
    const double t0 = (c - o) * inv, t1 = (c + 1.0 - o) * inv;
    enter = std::max(enter, std::min(t0, t1));
    exit = std::min(exit, std::max(t0, t1));
  }
  return enter <= exit && exit >= 0;
}

RayHit castRayBruteForce(std::span<const Coord3> occupied, const Ray& rayIn) {
  const Ray ray = sanitized(rayIn);
  RayHit best;
  for (const Coord3& c : occupied) {
    double enter, exit;
    if (!rayVoxelInterval(ray, c, enter, exit)) continue;
    const double key = std::max(enter, 0.0);
    if (!best.hit || key < best.t || (key == best.t && better(exit, c, best.exit, best.voxel))) {
      best.hit = true;
      best.t = key;
      best.exit = exit;
      best.voxel = c;
    }
  }
  if (best.hit) entryFace(ray, best.voxel, best.t, best);
  return best;
}

RayHit castRay(const RayGrid& grid, const Ray& rayIn) {
  RayGrid::Cursor cursor(grid);
  return castRay(grid, rayIn, cursor);
}

RayHit castRay(const RayGrid& grid, const Ray& rayIn, RayGrid::Cursor& cursor) {
  const Ray ray = sanitized(rayIn);
  RayHit result;
  // The ray is clipped to the box of non-empty bricks rather than the whole
  // domain: voxels outside it are empty, so the answer is the same and rays
  // that pass beside the content stop at once.
  if (grid.occupiedCount() == 0) return result;
  const std::array<int64_t, 3>& b0 = grid.contentMin();
  const std::array<int64_t, 3>& b1 = grid.contentEnd();
  Frame f;
  int64_t lo[3], hi[3];
  int movingCount = 0;
  for (int a = 0; a < 3; ++a) {
    const double o = ray.origin[size_t(a)], d = ray.dir[size_t(a)];
    if (d == 0) {
      // Not moving on this axis: the indices i with i <= o <= i + 1, clipped to the box.
      if (!(o >= double(b0[a]) && o <= double(b1[a]))) return result;
      const double fl = std::floor(o);
      hi[a] = std::min<int64_t>(int64_t(fl), b1[a] - 1);
      lo[a] = (fl == o) ? std::max<int64_t>(int64_t(fl) - 1, b0[a]) : int64_t(fl);
      f.o[a] = o;
      f.dlo[a] = b0[a];
      f.dhi[a] = b1[a];
      continue;
    }
    ++movingCount;
    f.moving[a] = true;
    f.flip[a] = d < 0;
    f.o[a] = f.flip[a] ? -o : o;
    f.d[a] = f.flip[a] ? -d : d;
    f.inv[a] = 1.0 / f.d[a];  // == -(1.0 / d) when flipped, bit for bit
    f.dlo[a] = f.flip[a] ? -b1[a] : b0[a];
    f.dhi[a] = f.flip[a] ? -b0[a] : b1[a];
  }
  if (movingCount == 0) return result;

  // Clip to the domain box.
  double T = 0, tEnd = kInf;
  for (int a = 0; a < 3; ++a) {
    if (!f.moving[a]) continue;
    T = std::max(T, f.time(a, f.dlo[a]));
    tEnd = std::min(tEnd, f.time(a, f.dhi[a]));
  }
  if (!(T <= tEnd)) return result;
  for (int a = 0; a < 3; ++a)
    if (f.moving[a]) f.range(a, T, f.guess(a, T, f.dlo[a] - 1, f.dhi[a]), lo[a], hi[a]);

  auto probe = [&](int64_t u, int64_t v, int64_t w, bool& occ) { return cursor.probe(u, v, w, occ); };

  for (;;) {
    ++result.steps;
    for (int a = 0; a < 3; ++a)
      if (f.moving[a] && lo[a] >= f.dhi[a]) return result;

    // Test every voxel touched at T; note the emptiness level of those ahead.
    int64_t clo[3], chi[3];
    for (int a = 0; a < 3; ++a) {
      clo[a] = std::max(lo[a], f.dlo[a]);
      chi[a] = std::min(hi[a], f.dhi[a] - 1);
    }
    bool found = false;
    Coord3 bestVoxel;
    double bestExit = 0;
    int minLevel = 3;
    for (int64_t i = clo[0]; i <= chi[0]; ++i)
      for (int64_t j = clo[1]; j <= chi[1]; ++j)
        for (int64_t k = clo[2]; k <= chi[2]; ++k) {
          const int64_t m[3] = {i, j, k};
          const Coord3 c{int32_t(f.real(0, i)), int32_t(f.real(1, j)), int32_t(f.real(2, k))};
          bool occ;
          const int level = probe(c.u, c.v, c.w, occ);
          bool ahead = true;
          for (int a = 0; a < 3; ++a)
            if (f.moving[a] && m[a] != hi[a]) ahead = false;
          if (ahead) minLevel = std::min(minLevel, level);
          if (!occ) continue;
          double exit = kInf;
          for (int a = 0; a < 3; ++a)
            if (f.moving[a]) exit = std::min(exit, f.time(a, m[a] + 1));
          if (!found || better(exit, c, bestExit, bestVoxel)) {
            found = true;
            bestVoxel = c;
            bestExit = exit;
          }
        }
    if (found) {
      result.hit = true;
      result.voxel = bestVoxel;
      result.t = T;
      result.exit = bestExit;
      entryFace(ray, bestVoxel, T, result);
      return result;
    }

    // Advance: past the voxel ahead, or past the empty box around it.
    for (int a = 0; a < 3; ++a)
      if (f.moving[a] && hi[a] >= f.dhi[a]) return result;  // the ray leaves the domain at T
    bool stationarySingle = true;
    for (int a = 0; a < 3; ++a)
      if (!f.moving[a] && clo[a] != chi[a]) stationarySingle = false;
    if (minLevel == 0 && stationarySingle) {
      // Inside a non-empty brick: step voxel by voxel while each event crosses
      // exactly one plane (then the voxels touched are the one left, already
      // tested, and the one entered). Anything else goes back to the general
      // event above.
      int64_t idx[3], rc[3], rs[3], bk[3];  // mirrored index, real index, real step, real brick
      double tN[3];
      for (int a = 0; a < 3; ++a) {
        idx[a] = f.moving[a] ? hi[a] : clo[a];
        tN[a] = f.moving[a] ? f.time(a, idx[a] + 1) : kInf;
        rc[a] = f.real(a, idx[a]);
        rs[a] = f.flip[a] ? -1 : 1;
        bk[a] = rc[a] >> 3;
      }
      bool occStart;
      probe(rc[0], rc[1], rc[2], occStart);  // the brick ahead is non-empty (minShift == 0)
      const RayGrid::Mask512* brick = cursor.lastBrick();
      for (;;) {
        const int a0 = tN[0] <= tN[1] ? (tN[0] <= tN[2] ? 0 : 2) : (tN[1] <= tN[2] ? 1 : 2);
        const double Tn = tN[a0];
        const int64_t next = idx[a0] + 1;
        const double tAfter = f.time(a0, next + 1);
        const int crossing = int(tN[0] == Tn) + int(tN[1] == Tn) + int(tN[2] == Tn);
        if (crossing > 1 || tAfter == Tn || next >= f.dhi[a0]) {
          for (int a = 0; a < 3; ++a) {
            if (!f.moving[a]) continue;
            if (tN[a] == Tn) f.range(a, Tn, idx[a] + 1, lo[a], hi[a]);
            else lo[a] = hi[a] = idx[a];
          }
          T = Tn;
          break;
        }
        ++result.steps;
        idx[a0] = next;
        tN[a0] = tAfter;
        rc[a0] += rs[a0];
        bool occ;
        int level = 0;
        if ((rc[a0] >> 3) == bk[a0]) {  // same brick: one bit test
          const int bit = RayGrid::bitOf(uint32_t(rc[0] & 7), uint32_t(rc[1] & 7), uint32_t(rc[2] & 7));
          occ = ((*brick)[size_t(bit >> 6)] >> (bit & 63)) & 1;
        } else {
          bk[a0] = rc[a0] >> 3;
          level = probe(rc[0], rc[1], rc[2], occ);
          brick = cursor.lastBrick();
        }
        const Coord3 c{int32_t(rc[0]), int32_t(rc[1]), int32_t(rc[2])};
        if (occ) {
          result.hit = true;
          result.voxel = c;
          result.t = Tn;
          result.exit = std::min(tN[0], std::min(tN[1], tN[2]));
          entryFace(ray, c, Tn, result);
          return result;
        }
        if (level > 0) {  // left the brick for an empty one: jump from the general event
          for (int a = 0; a < 3; ++a) {
            if (!f.moving[a]) continue;
            lo[a] = hi[a] = idx[a];
          }
          lo[a0] = next - 1;
          T = Tn;
          break;
        }
      }
      continue;
    }
    if (stationarySingle) {
      // In empty space: move from cell to cell of the coarsest empty level
      // (8^3, 64^3 or 512^3 voxels) while each event crosses exactly one cell
      // face; the voxels touched there lie in the cell left (empty) and the
      // cell entered, so while the entered cell is empty too no voxel index is
      // needed. Where the brick distance field says the k-cell box around the
      // current cell is empty, jump to that box's exit instead. A non-empty
      // cell, or a tie, goes back to an exact general event.
      int L = minLevel;
      int64_t cur[3], cell[3];
      double tN[3];
      for (int a = 0; a < 3; ++a) cur[a] = f.moving[a] ? hi[a] : clo[a];
      auto setLevel = [&](int level) {
        L = level;
        for (int a = 0; a < 3; ++a) {
          cell[a] = cur[a] >> (3 * L);
          tN[a] = f.moving[a] ? f.time(a, (cell[a] + 1) << (3 * L)) : kInf;
        }
      };
      // Cells of level L around `voxel`'s cell known empty on every side: the
      // brick distance kb covers k cells of m = 8^(L-1) bricks when k m <= kb.
      auto jumpCells = [&](const int64_t* voxel) -> int64_t {
        const uint32_t kb = grid.emptyBricksAround(f.real(0, voxel[0]) >> 3, f.real(1, voxel[1]) >> 3,
                                                   f.real(2, voxel[2]) >> 3);
        const int64_t k = int64_t(kb) >> (3 * (L - 1));
        return k < 1 ? 1 : k;
      };
      setLevel(L);
      int64_t k = jumpCells(cur);
      // The exact voxels touched at Tn (cells known on every axis), for a general event.
      auto exactAt = [&](double Tn, const int64_t* far, const double* tFar) {
        for (int a = 0; a < 3; ++a) {
          if (!f.moving[a]) continue;
          const int64_t first = cell[a] << (3 * L);
          f.range(a, Tn, tFar[a] == Tn ? far[a] : f.guess(a, Tn, first, far[a] - 1), lo[a], hi[a]);
        }
        T = Tn;
      };
      for (;;) {
        int64_t far[3] = {0, 0, 0};
        double tFar[3] = {kInf, kInf, kInf};
        if (k == 1) {
          for (int a = 0; a < 3; ++a) {
            far[a] = (cell[a] + 1) << (3 * L);
            tFar[a] = tN[a];
          }
        } else {
          for (int a = 0; a < 3; ++a) {
            if (!f.moving[a]) continue;
            far[a] = (cell[a] + k) << (3 * L);
            tFar[a] = f.time(a, far[a]);
          }
        }
        const int a0 = tFar[0] <= tFar[1] ? (tFar[0] <= tFar[2] ? 0 : 2) : (tFar[1] <= tFar[2] ? 1 : 2);
        const double Tn = tFar[a0];
        const int64_t P = far[a0];  // the plane crossed at Tn
        const int crossing = int(tFar[0] == Tn) + int(tFar[1] == Tn) + int(tFar[2] == Tn);
        if (crossing > 1 || !(f.time(a0, P - 1) < Tn) || !(f.time(a0, P + 1) > Tn)) {
          exactAt(Tn, far, tFar);
          break;
        }
        if (P >= f.dhi[a0]) return result;  // out of the domain; the box left was empty
        if (k > 1) {
          // Which cell of the box each other axis is in at Tn; a cell face
          // exactly at Tn is a tie.
          bool tie = false;
          int64_t moved[3];
          for (int a = 0; a < 3; ++a) {
            moved[a] = cell[a];
            if (!f.moving[a] || a == a0) continue;
            const int64_t shift = 3 * L;
            int64_t c = f.guess(a, Tn, cell[a] << shift, far[a] - 1) >> shift;
            while (c > cell[a] && f.time(a, c << shift) > Tn) --c;
            while (c < cell[a] + k - 1 && f.time(a, (c + 1) << shift) <= Tn) ++c;
            if (f.time(a, c << shift) == Tn) tie = true;
            moved[a] = c;
          }
          if (tie) {
            exactAt(Tn, far, tFar);
            break;
          }
          for (int a = 0; a < 3; ++a) {
            if (!f.moving[a] || a == a0) continue;
            cell[a] = moved[a];
            cur[a] = cell[a] << (3 * L);  // any voxel of the cell will do for setLevel
            tN[a] = f.time(a, (cell[a] + 1) << (3 * L));
          }
        }
        ++result.steps;
        cur[a0] = P;
        cell[a0] = P >> (3 * L);
        tN[a0] = f.time(a0, (cell[a0] + 1) << (3 * L));
        // The entered cell's emptiness, from any of its voxels inside the domain.
        int64_t rep[3];
        for (int a = 0; a < 3; ++a)
          rep[a] = a == a0 ? P : std::clamp<int64_t>(cell[a] << (3 * L), f.dlo[a], f.dhi[a] - 1);
        bool occ;
        const int level = probe(f.real(0, rep[0]), f.real(1, rep[1]), f.real(2, rep[2]), occ);
        if (level > L) {
          setLevel(level);
        } else if (level < L) {
          // Not empty: the exact voxels touched at Tn, then a general event.
          for (int a = 0; a < 3; ++a) {
            if (!f.moving[a]) continue;
            if (a == a0) {
              lo[a] = P - 1;
              hi[a] = P;
            } else {
              f.range(a, Tn, f.guess(a, Tn, cell[a] << (3 * L), ((cell[a] + 1) << (3 * L)) - 1), lo[a], hi[a]);
            }
          }
          T = Tn;
          break;
        }
        k = jumpCells(rep);
      }
      continue;
    }
    const int shift = 3 * minLevel;
    double Tn = kInf;
    int64_t far[3] = {0, 0, 0};
    double tFar[3] = {kInf, kInf, kInf};
    for (int a = 0; a < 3; ++a) {
      if (!f.moving[a]) continue;
      far[a] = ((hi[a] >> shift) + 1) << shift;
      tFar[a] = f.time(a, far[a]);
      Tn = std::min(Tn, tFar[a]);
    }
    for (int a = 0; a < 3; ++a) {
      if (!f.moving[a]) continue;
      const int64_t g = tFar[a] == Tn ? far[a] : shift == 0 ? hi[a] : f.guess(a, Tn, hi[a], far[a] - 1);
      f.range(a, Tn, g, lo[a], hi[a]);
    }
    T = Tn;
  }
}

}  // namespace vox
