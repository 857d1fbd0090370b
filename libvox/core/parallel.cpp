#include "libvox/core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <thread>

namespace vox {

unsigned workerCount(unsigned threads) {
  if (threads != 0) return threads;
  return std::max(1u, unsigned(tbb::this_task_arena::max_concurrency()));
}

namespace {
// Runs `body` in an arena of `workers` threads (the calling thread included).
template <typename Body>
void inArena(unsigned workers, Body&& body) {
  tbb::task_arena arena(static_cast<int>(workers));
  arena.execute(body);
}
}  // namespace

void parallelPieces(size_t n, unsigned threads, size_t pieces,
                    const std::function<void(size_t, size_t, size_t)>& fn) {
  const unsigned workers = workerCount(threads);
  if (pieces == 0) pieces = workers;
  pieces = std::max<size_t>(1, std::min(pieces, std::max<size_t>(n, 1)));
  auto piece = [&](size_t p) { fn(n * p / pieces, n * (p + 1) / pieces, p); };
  if (workers == 1 || pieces == 1) {
    for (size_t p = 0; p < pieces; ++p) piece(p);
    return;
  }
  inArena(workers, [&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pieces, 1),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t p = r.begin(); p != r.end(); ++p) piece(p);
                      },
                      tbb::simple_partitioner());
  });
}

void parallelForEach(size_t n, unsigned threads, size_t grain, const std::function<void(size_t)>& fn) {
  const unsigned workers = workerCount(threads);
  grain = std::max<size_t>(1, grain);
  if (workers == 1 || n <= grain) {
    for (size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  inArena(workers, [&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t i = r.begin(); i != r.end(); ++i) fn(i);
                      },
                      tbb::simple_partitioner());
  });
}

}  // namespace vox
