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
//
// Starting at tStart > 0 (castRay's last argument) changes nothing in this:
// the caller guarantees that every voxel touched before tStart is empty, so
// the stretch [0, tStart) is one more jump over empty voxels, and tStart is
// the start time.
#include "libvox/render/raycast.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vox {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The tie rule between occupied voxels touched at the same time: the larger
// exit, then the smallest (w, v, u).
bool winsTie(double exitA, const Coord3& a, double exitB, const Coord3& b) {
  if (exitA != exitB) return exitA > exitB;
  if (a.w != b.w) return a.w < b.w;
  if (a.v != b.v) return a.v < b.v;
  return a.u < b.u;
}

// The axis of the smallest of t[0..2], ties to the lower axis (as the nested
// comparison it replaces), written as selects so that the compiler need not
// branch on it: the DDA's next axis is hard for a branch predictor.
inline int argMin3(const double* t) {
  const int a01 = int(t[1] < t[0]);
  const double m = t[1] < t[0] ? t[1] : t[0];
  return t[2] < m ? 2 : a01;
}

int component(const Coord3& c, int axis) { return axis == 0 ? c.u : axis == 1 ? c.v : c.w; }

// The face the ray entered `voxel` through at time `key`: among moving axes
// whose entry plane time equals key, the one the ray is most head-on to
// (largest |dir|), then the lowest axis.
void setEntryFace(const Ray& ray, const Coord3& voxel, double key, RayHit& hit) {
  hit.faceAxis = -1;
  hit.faceSign = 0;
  double best = -1;
  for (int a = 0; a < 3; ++a) {
    const double d = ray.dir[size_t(a)];
    if (d == 0) continue;
    const double inv = 1.0 / d;
    const double plane = d > 0 ? double(component(voxel, a)) : double(component(voxel, a)) + 1.0;
    const double t = (plane - ray.origin[size_t(a)]) * inv;
    if (t == key && std::fabs(d) > best) {
      best = std::fabs(d);
      hit.faceAxis = a;
      hit.faceSign = d > 0 ? -1 : 1;
    }
  }
}

RayHit& setHit(const Ray& ray, const Coord3& voxel, double key, double exit, RayHit& result) {
  result.hit = true;
  result.voxel = voxel;
  result.t = key;
  result.exit = exit;
  setEntryFace(ray, voxel, key, result);
  return result;
}

// Grid space mirrored on every axis the ray moves down (mirrored index
// i' = -i - 1, plane p' = -p), so that the ray moves up every axis it moves
// along; the ray's other axes ("fixed" axes) are left as they are. Voxel
// indices in this frame are "mirrored"; gridIndex() maps them back.
struct MirroredFrame {
  bool moving[3]{};
  bool flipped[3]{};
  int64_t flipMask[3]{};  // -1 (all bits) on flipped axes, else 0: -i - 1 == i ^ -1
  double origin[3]{}, dir[3]{}, invDir[3]{};
  int64_t domainBegin[3]{}, domainEnd[3]{};  // the content box, mirrored: [begin, end)
  // On every fixed axis the ray lies inside one voxel slab rather than on the
  // plane between two (so each event touches one index there).
  bool oneSlabOnFixedAxes = true;
  // Neighbouring planes of every moving axis are crossed at distinct times
  // (planeTime strictly increasing in the plane), so a step never has to ask
  // whether the plane before or after the one crossed is crossed at the same
  // time. True when |origin| <= 2^39 and 2^-900 <= 1/dir <= 2^900 on every
  // moving axis: then |p - o| < 2^40 for every plane p of the index range
  // (|p| < 2^32), so p - o and p + 1 - o round to distinct doubles at least
  // 1/2 apart, a relative gap above 2^-41, which the multiplication by 1/dir
  // (no overflow, and no underflow that could merge two of them) keeps.
  bool strictPlaneTimes = true;

  // When the ray crosses plane `plane` (mirrored) of moving axis `axis`: the
  // brute force's (p - o) * (1 / d), bit for bit.
  double planeTime(int axis, int64_t plane) const { return (double(plane) - origin[axis]) * invDir[axis]; }
  int64_t gridIndex(int axis, int64_t mirrored) const { return mirrored ^ flipMask[axis]; }

  // The mirrored indices [first, last] of moving axis `axis` whose interval
  // contains time t, searched from `guess`.
  void indicesAt(int axis, double t, int64_t guess, int64_t& first, int64_t& last) const {
    int64_t i = guess;
    while (planeTime(axis, i) > t) --i;
    while (planeTime(axis, i + 1) <= t) ++i;
    last = i;
    first = i;
    while (planeTime(axis, first) >= t) --first;
  }
  // A starting point for indicesAt: the index the ray is near at time t, clamped.
  // floor(x) clamped, without a floor call: floor(x) >= m iff x >= m, and
  // floor(x) <= M iff x < M + 1 (m, M integers); in between, truncation
  // corrected for negative x.
  int64_t indexGuess(int axis, double t, int64_t minIndex, int64_t maxIndex) const {
    const double x = origin[axis] + t * dir[axis];
    if (!(x >= double(minIndex))) return minIndex;
    if (!(x < double(maxIndex) + 1.0)) return maxIndex;
    const int64_t i = int64_t(x);
    return double(i) > x ? i - 1 : i;
  }
};

// A time the caster tests every voxel the ray touches: on each axis the
// mirrored indices [first, last] whose interval contains `time` (one index, or
// more where `time` is a plane crossing). On a moving axis `last` is the index
// the ray goes on into.
struct Event {
  double time = 0;
  int64_t first[3]{}, last[3]{};
};

// The frame of `ray` clipped to the box of non-empty bricks, and the indices
// of the fixed axes (constant for the whole ray). False when the ray cannot
// touch the box.
bool makeFrame(const RayGrid& grid, const Ray& ray, MirroredFrame& frame, Event& event) {
  // Clipping to the content box rather than the whole domain gives the same
  // answer (voxels outside it are empty) and stops rays that pass beside the
  // content at once.
  const std::array<int64_t, 3>& contentBegin = grid.contentMin();
  const std::array<int64_t, 3>& contentEnd = grid.contentEnd();
  int movingAxes = 0;
  for (int a = 0; a < 3; ++a) {
    const double o = ray.origin[size_t(a)], d = ray.dir[size_t(a)];
    if (d == 0) {
      // The indices i with i <= o <= i + 1, clipped to the box.
      if (!(o >= double(contentBegin[a]) && o <= double(contentEnd[a]))) return false;
      const double slab = std::floor(o);
      event.last[a] = std::min<int64_t>(int64_t(slab), contentEnd[a] - 1);
      event.first[a] = (slab == o) ? std::max<int64_t>(int64_t(slab) - 1, contentBegin[a]) : int64_t(slab);
      if (event.first[a] != event.last[a]) frame.oneSlabOnFixedAxes = false;
      frame.origin[a] = o;
      frame.domainBegin[a] = contentBegin[a];
      frame.domainEnd[a] = contentEnd[a];
      continue;
    }
    ++movingAxes;
    frame.moving[a] = true;
    frame.flipped[a] = d < 0;
    frame.flipMask[a] = frame.flipped[a] ? -1 : 0;
    frame.origin[a] = frame.flipped[a] ? -o : o;
    frame.dir[a] = frame.flipped[a] ? -d : d;
    frame.invDir[a] = 1.0 / frame.dir[a];  // == -(1.0 / d) when flipped, bit for bit
    if (!(std::fabs(o) <= 0x1p39 && frame.invDir[a] >= 0x1p-900 && frame.invDir[a] <= 0x1p900))
      frame.strictPlaneTimes = false;
    frame.domainBegin[a] = frame.flipped[a] ? -contentEnd[a] : contentBegin[a];
    frame.domainEnd[a] = frame.flipped[a] ? -contentBegin[a] : contentEnd[a];
  }
  return movingAxes > 0;
}

// The first event: where the ray enters the content box (or its origin, when
// inside), or tStart when later (everything before it is known empty). False
// when the ray misses the box (or leaves it before tStart).
bool enterContentBox(const MirroredFrame& frame, double tStart, Event& event) {
  double tEnter = tStart, tLeave = kInf;
  for (int a = 0; a < 3; ++a) {
    if (!frame.moving[a]) continue;
    tEnter = std::max(tEnter, frame.planeTime(a, frame.domainBegin[a]));
    tLeave = std::min(tLeave, frame.planeTime(a, frame.domainEnd[a]));
  }
  if (!(tEnter <= tLeave)) return false;
  for (int a = 0; a < 3; ++a)
    if (frame.moving[a])
      frame.indicesAt(a, tEnter, frame.indexGuess(a, tEnter, frame.domainBegin[a] - 1, frame.domainEnd[a]),
                      event.first[a], event.last[a]);
  event.time = tEnter;
  return true;
}

// What testing an event's voxels found.
struct EventTest {
  bool found = false;  // an occupied voxel: the best by the tie rule
  Coord3 voxel;
  double exit = 0;
  int aheadLevel = 3;  // the emptiness level (RayGrid::probe) of the voxels the ray goes on into
};

// Tests every voxel of the event inside the content box. (Every voxel castRay
// probes lies inside the content box, hence inside the domain: probeInDomain.)
EventTest testEventVoxels(const MirroredFrame& frame, const Event& event, RayGrid::Cursor& cursor) {
  int64_t begin[3], last[3];
  for (int a = 0; a < 3; ++a) {
    begin[a] = std::max(event.first[a], frame.domainBegin[a]);
    last[a] = std::min(event.last[a], frame.domainEnd[a] - 1);
  }
  EventTest test;
  // One voxel of the event: its level when it is the one ahead (the event's
  // last index on every moving axis), and the hit with the earliest exit.
  auto testVoxel = [&](const int64_t mirrored[3]) {
    const Coord3 voxel{int32_t(frame.gridIndex(0, mirrored[0])), int32_t(frame.gridIndex(1, mirrored[1])),
                       int32_t(frame.gridIndex(2, mirrored[2]))};
    bool occupied;
    const int level = cursor.probeInDomain(voxel.u, voxel.v, voxel.w, occupied);
    bool ahead = true;
    for (int a = 0; a < 3; ++a)
      if (frame.moving[a] && mirrored[a] != event.last[a]) ahead = false;
    if (ahead) test.aheadLevel = std::min(test.aheadLevel, level);
    if (!occupied) return;
    double exit = kInf;
    for (int a = 0; a < 3; ++a)
      if (frame.moving[a]) exit = std::min(exit, frame.planeTime(a, mirrored[a] + 1));
    if (!test.found || winsTie(exit, voxel, test.exit, test.voxel)) {
      test.found = true;
      test.voxel = voxel;
      test.exit = exit;
    }
  };
  // One voxel is the usual event away from ties: no loops.
  if (begin[0] == last[0] && begin[1] == last[1] && begin[2] == last[2]) {
    testVoxel(begin);
    return test;
  }
  for (int64_t i = begin[0]; i <= last[0]; ++i)
    for (int64_t j = begin[1]; j <= last[1]; ++j)
      for (int64_t k = begin[2]; k <= last[2]; ++k) {
        const int64_t mirrored[3] = {i, j, k};
        testVoxel(mirrored);
      }
  return test;
}

// How a walk between events ended.
enum class WalkEnd {
  NextEvent,  // `event` holds the next general event
  Hit,        // the result holds the hit
  Miss,       // the ray left the content box
};

// Inside a non-empty brick: steps voxel by voxel while each step crosses
// exactly one plane (the voxels touched are then the one left, already
// tested, and the one entered). Anything else (a tie, the box's end, an empty
// brick) goes back to a general event.
//
// The step's dependency chain is kept short: the time the ray leaves the
// voxel it is about to enter (`tAfter`) is computed one step ahead, so a step
// only compares and selects times already known; the voxel's bit in the brick
// mask moves by a fixed stride per axis, and one index limit per axis (the
// brick's far face) says when a step needs more than a bit test. The times are the same planeTime() values as
// before, so the walk visits the same voxels in the same order.
WalkEnd walkVoxelsInBrick(const MirroredFrame& frame, const Ray& ray, Event& event, RayGrid::Cursor& cursor,
                          RayHit& result) {
  int64_t mirrored[3], gridVoxel[3], gridStep[3], limit[3];
  double tLeave[3];  // when the ray leaves the current voxel on each axis
  double tAfter[3];  // when it leaves the next voxel along each axis
  int bitStep[3];
  static constexpr int kBitStride[3] = {64, 8, 1};
  for (int a = 0; a < 3; ++a) {
    mirrored[a] = event.last[a];
    tLeave[a] = frame.moving[a] ? frame.planeTime(a, mirrored[a] + 1) : kInf;
    tAfter[a] = frame.moving[a] ? frame.planeTime(a, mirrored[a] + 2) : kInf;
    gridVoxel[a] = frame.gridIndex(a, mirrored[a]);
    gridStep[a] = frame.flipped[a] ? -1 : 1;
    bitStep[a] = frame.flipped[a] ? -kBitStride[a] : kBitStride[a];
  }
  auto setLimits = [&]() {
    for (int a = 0; a < 3; ++a) {
      // The last mirrored index of the current brick along the ray's direction.
      const int64_t inBrick = frame.flipped[a] ? (gridVoxel[a] & 7) : 7 - (gridVoxel[a] & 7);
      limit[a] = mirrored[a] + inBrick + 1;
    }
  };
  setLimits();
  bool occupiedStart;
  cursor.probeInDomain(gridVoxel[0], gridVoxel[1], gridVoxel[2], occupiedStart);  // the brick ahead (level 0)
  const RayGrid::Mask512* brickMask = cursor.lastBrick();
  int bit = RayGrid::bitOf(uint32_t(gridVoxel[0] & 7), uint32_t(gridVoxel[1] & 7), uint32_t(gridVoxel[2] & 7));
  for (;;) {
    const int axis = argMin3(tLeave);
    const double tCross = tLeave[axis];
    const int64_t entered = mirrored[axis] + 1;
    const double tLeaveEntered = tAfter[axis];
    const int o1 = axis == 0 ? 1 : 0, o2 = axis == 2 ? 1 : 2;  // the other two axes
    // A tie (another plane crossed at tCross, or the entered voxel left at
    // once) or the content box's end: a general event. The others' times are
    // >= tCross, so a tie is one of them <= tCross.
    if (std::min(std::min(tLeave[o1], tLeave[o2]), tLeaveEntered) <= tCross ||
        entered >= frame.domainEnd[axis]) {
      for (int a = 0; a < 3; ++a) {
        if (!frame.moving[a]) continue;
        if (tLeave[a] == tCross) frame.indicesAt(a, tCross, mirrored[a] + 1, event.first[a], event.last[a]);
        else event.first[a] = event.last[a] = mirrored[a];
      }
      event.time = tCross;
      return WalkEnd::NextEvent;
    }
    ++result.steps;
    const bool sameBrick = entered < limit[axis];
    mirrored[axis] = entered;
    tLeave[axis] = tLeaveEntered;
    tAfter[axis] = frame.planeTime(axis, entered + 2);
    gridVoxel[axis] += gridStep[axis];
    bool occupied;
    int level = 0;
    if (sameBrick) {  // same brick: one bit test at the brick-local position
      bit += bitStep[axis];
      occupied = ((*brickMask)[size_t(bit >> 6)] >> (bit & 63)) & 1;
    } else {
      level = cursor.probeInDomain(gridVoxel[0], gridVoxel[1], gridVoxel[2], occupied);
      brickMask = cursor.lastBrick();
      bit = RayGrid::bitOf(uint32_t(gridVoxel[0] & 7), uint32_t(gridVoxel[1] & 7), uint32_t(gridVoxel[2] & 7));
      setLimits();
    }
    if (occupied) {
      const Coord3 voxel{int32_t(gridVoxel[0]), int32_t(gridVoxel[1]), int32_t(gridVoxel[2])};
      setHit(ray, voxel, tCross, std::min(tLeave[0], std::min(tLeave[1], tLeave[2])), result);
      return WalkEnd::Hit;
    }
    if (level > 0) {  // left the brick for an empty one: jump from a general event
      for (int a = 0; a < 3; ++a)
        if (frame.moving[a]) event.first[a] = event.last[a] = mirrored[a];
      event.first[axis] = entered - 1;
      event.time = tCross;
      return WalkEnd::NextEvent;
    }
  }
}

// In empty space: moves from cell to cell of the coarsest empty level `level`
// (8^3, 64^3 or 512^3 voxels) while each step crosses exactly one cell face;
// the voxels touched there lie in the cell left (empty) and the cell entered,
// so while the entered cell is empty too no voxel index is needed. Where the
// brick distance field says the box of k cells around the current cell is
// empty, jumps to that box's exit instead. A non-empty cell, or a tie, goes
// back to an exact general event.
WalkEnd walkEmptyCells(const RayGrid& grid, const MirroredFrame& frame, int level, Event& event,
                       RayGrid::Cursor& cursor, RayHit& result) {
  int64_t voxelInCell[3], cell[3];  // mirrored: any voxel of the current cell, and the cell at `level`
  double tLeave[3];                 // when the ray leaves the current cell on each axis
  for (int a = 0; a < 3; ++a) voxelInCell[a] = event.last[a];
  auto setLevel = [&](int newLevel) {
    level = newLevel;
    for (int a = 0; a < 3; ++a) {
      cell[a] = voxelInCell[a] >> (3 * level);
      tLeave[a] = frame.moving[a] ? frame.planeTime(a, (cell[a] + 1) << (3 * level)) : kInf;
    }
  };
  // Cells of the current level around the one holding `mirroredVoxel` known
  // empty on every side: the brick distance kb covers k cells of m = 8^(level-1)
  // bricks when k m <= kb.
  auto emptyCellsAround = [&](const int64_t* mirroredVoxel) -> int64_t {
    const uint32_t kb = grid.emptyBricksAround(frame.gridIndex(0, mirroredVoxel[0]) >> 3,
                                               frame.gridIndex(1, mirroredVoxel[1]) >> 3,
                                               frame.gridIndex(2, mirroredVoxel[2]) >> 3);
    const int64_t k = int64_t(kb) >> (3 * (level - 1));
    return k < 1 ? 1 : k;
  };
  // The exact voxels touched at tCross (cells known on every axis): a general event.
  auto eventAt = [&](double tCross, const int64_t* farPlane, const double* tFar) {
    for (int a = 0; a < 3; ++a) {
      if (!frame.moving[a]) continue;
      const int64_t cellFirst = cell[a] << (3 * level);
      frame.indicesAt(a, tCross, tFar[a] == tCross ? farPlane[a] : frame.indexGuess(a, tCross, cellFirst, farPlane[a] - 1),
                      event.first[a], event.last[a]);
    }
    event.time = tCross;
  };
  setLevel(level);
  int64_t k = emptyCellsAround(voxelInCell);
  for (;;) {
    // The far planes of the box of k cells, and when the ray crosses them.
    int64_t farPlane[3] = {0, 0, 0};
    double tFar[3] = {kInf, kInf, kInf};
    if (k == 1) {
      for (int a = 0; a < 3; ++a) {
        farPlane[a] = (cell[a] + 1) << (3 * level);
        tFar[a] = tLeave[a];
      }
    } else {
      for (int a = 0; a < 3; ++a) {
        if (!frame.moving[a]) continue;
        farPlane[a] = (cell[a] + k) << (3 * level);
        tFar[a] = frame.planeTime(a, farPlane[a]);
      }
    }
    const int axis = argMin3(tFar);
    const double tCross = tFar[axis];
    const int64_t plane = farPlane[axis];  // the plane crossed at tCross
    const int planesCrossed = int(tFar[0] == tCross) + int(tFar[1] == tCross) + int(tFar[2] == tCross);
    if (planesCrossed > 1 || (!frame.strictPlaneTimes && (!(frame.planeTime(axis, plane - 1) < tCross) ||
                                                          !(frame.planeTime(axis, plane + 1) > tCross)))) {
      eventAt(tCross, farPlane, tFar);
      return WalkEnd::NextEvent;
    }
    if (plane >= frame.domainEnd[axis]) return WalkEnd::Miss;  // the box left was empty
    if (k > 1) {
      // Which cell of the box each other axis is in at tCross; a cell face
      // exactly at tCross is a tie.
      bool tie = false;
      int64_t cellAtCross[3];
      const int64_t shift = 3 * level;
      for (int a = 0; a < 3; ++a) {
        cellAtCross[a] = cell[a];
        if (!frame.moving[a] || a == axis) continue;
        int64_t c = frame.indexGuess(a, tCross, cell[a] << shift, farPlane[a] - 1) >> shift;
        while (c > cell[a] && frame.planeTime(a, c << shift) > tCross) --c;
        while (c < cell[a] + k - 1 && frame.planeTime(a, (c + 1) << shift) <= tCross) ++c;
        if (frame.planeTime(a, c << shift) == tCross) tie = true;
        cellAtCross[a] = c;
      }
      if (tie) {
        eventAt(tCross, farPlane, tFar);
        return WalkEnd::NextEvent;
      }
      for (int a = 0; a < 3; ++a) {
        if (!frame.moving[a] || a == axis) continue;
        cell[a] = cellAtCross[a];
        voxelInCell[a] = cell[a] << shift;
        tLeave[a] = frame.planeTime(a, (cell[a] + 1) << shift);
      }
    }
    ++result.steps;
    voxelInCell[axis] = plane;
    cell[axis] = plane >> (3 * level);
    tLeave[axis] = frame.planeTime(axis, (cell[axis] + 1) << (3 * level));
    // The entered cell's emptiness, from any of its voxels inside the box.
    int64_t probeVoxel[3];
    for (int a = 0; a < 3; ++a)
      probeVoxel[a] = a == axis ? plane
                                : std::clamp<int64_t>(cell[a] << (3 * level), frame.domainBegin[a], frame.domainEnd[a] - 1);
    bool occupied;
    const int enteredLevel = cursor.probeInDomain(frame.gridIndex(0, probeVoxel[0]), frame.gridIndex(1, probeVoxel[1]),
                                          frame.gridIndex(2, probeVoxel[2]), occupied);
    if (enteredLevel > level) {
      setLevel(enteredLevel);
    } else if (enteredLevel < level) {
      // Not empty: the exact voxels touched at tCross, then a general event.
      for (int a = 0; a < 3; ++a) {
        if (!frame.moving[a]) continue;
        if (a == axis) {
          event.first[a] = plane - 1;
          event.last[a] = plane;
        } else {
          frame.indicesAt(a, tCross,
                          frame.indexGuess(a, tCross, cell[a] << (3 * level), ((cell[a] + 1) << (3 * level)) - 1),
                          event.first[a], event.last[a]);
        }
      }
      event.time = tCross;
      return WalkEnd::NextEvent;
    }
    k = emptyCellsAround(probeVoxel);
  }
}

// A ray inside a grid plane of a fixed axis (two slabs there): from the
// current event to the far face of the empty box of `level` ahead (one voxel
// at level 0), as one general event.
void jumpPastEmptyBox(const MirroredFrame& frame, int level, Event& event) {
  const int shift = 3 * level;
  double tCross = kInf;
  int64_t farPlane[3] = {0, 0, 0};
  double tFar[3] = {kInf, kInf, kInf};
  for (int a = 0; a < 3; ++a) {
    if (!frame.moving[a]) continue;
    farPlane[a] = ((event.last[a] >> shift) + 1) << shift;
    tFar[a] = frame.planeTime(a, farPlane[a]);
    tCross = std::min(tCross, tFar[a]);
  }
  for (int a = 0; a < 3; ++a) {
    if (!frame.moving[a]) continue;
    const int64_t guess = tFar[a] == tCross ? farPlane[a]
                          : shift == 0      ? event.last[a]
                                            : frame.indexGuess(a, tCross, event.last[a], farPlane[a] - 1);
    frame.indicesAt(a, tCross, guess, event.first[a], event.last[a]);
  }
  event.time = tCross;
}

// On a fixed axis the event's indices lie inside the box (makeFrame clips
// them), so every axis can be compared.
bool pastContentBox(const MirroredFrame& frame, const int64_t* index) {
  return (index[0] >= frame.domainEnd[0]) | (index[1] >= frame.domainEnd[1]) | (index[2] >= frame.domainEnd[2]);
}

Ray sanitized(const Ray& ray) { return sanitizeRay(ray); }

}  // namespace


bool rayVoxelInterval(const Ray& ray, const Coord3& voxel, double& enter, double& exit) {
  enter = -kInf;
  exit = kInf;
  for (int a = 0; a < 3; ++a) {
    const double o = ray.origin[size_t(a)], d = ray.dir[size_t(a)];
    const double c = double(component(voxel, a));
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
    if (!best.hit || key < best.t || (key == best.t && winsTie(exit, c, best.exit, best.voxel))) {
      best.hit = true;
      best.t = key;
      best.exit = exit;
      best.voxel = c;
    }
  }
  if (best.hit) setEntryFace(ray, best.voxel, best.t, best);
  return best;
}

RayHit castRay(const RayGrid& grid, const Ray& rayIn) {
  RayGrid::Cursor cursor(grid);
  return castRay(grid, rayIn, cursor);
}

RayHit castRay(const RayGrid& grid, const Ray& rayIn, RayGrid::Cursor& cursor) {
  return castRay(grid, rayIn, cursor, 0.0);
}

RayHit castRay(const RayGrid& grid, const Ray& rayIn, RayGrid::Cursor& cursor, double tStart) {
  const Ray ray = sanitized(rayIn);
  RayHit result;
  if (grid.occupiedCount() == 0) return result;
  MirroredFrame frame;
  Event event;
  if (!makeFrame(grid, ray, frame, event) || !enterContentBox(frame, tStart, event)) return result;
  for (;;) {
    ++result.steps;
    if (pastContentBox(frame, event.first)) return result;
    const EventTest test = testEventVoxels(frame, event, cursor);
    if (test.found) return setHit(ray, test.voxel, event.time, test.exit, result);
    if (pastContentBox(frame, event.last)) return result;  // the ray leaves the box at this event
    if (!frame.oneSlabOnFixedAxes) {
      jumpPastEmptyBox(frame, test.aheadLevel, event);
      continue;
    }
    const WalkEnd end = test.aheadLevel == 0 ? walkVoxelsInBrick(frame, ray, event, cursor, result)
                                             : walkEmptyCells(grid, frame, test.aheadLevel, event, cursor, result);
    if (end != WalkEnd::NextEvent) return result;
  }
}

}  // namespace vox
