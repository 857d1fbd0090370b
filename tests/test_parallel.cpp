// The parallel-for every kernel uses: the fixed split and the serial path.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

#include "libvox/core/ordered_pipeline.h"
#include "libvox/core/parallel.h"

TEST(Parallel, PiecesCoverTheRangeInAFixedSplit) {
  for (unsigned threads : {1u, 2u, 3u, 8u}) {
    for (size_t n : {size_t(0), size_t(1), size_t(5), size_t(1000)}) {
      std::vector<int> hits(n, 0);
      std::vector<std::pair<size_t, size_t>> ranges(7, {~size_t(0), 0});
      vox::parallelPieces(n, threads, 7, [&](size_t b, size_t e, size_t p) {
        ranges[p] = {b, e};
        for (size_t i = b; i < e; ++i) hits[i]++;
      });
      for (size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i], 1) << "n " << n << " threads " << threads;
      const size_t pieces = std::max<size_t>(1, std::min<size_t>(7, n));
      for (size_t p = 0; p < pieces; ++p) {
        EXPECT_EQ(ranges[p].first, n * p / pieces);
        EXPECT_EQ(ranges[p].second, n * (p + 1) / pieces);
      }
    }
  }
}

TEST(Parallel, ForEachVisitsEveryIndexOnce) {
  for (unsigned threads : {0u, 1u, 2u, 4u}) {
    std::vector<std::atomic<int>> hits(10007);
    vox::parallelForEach(hits.size(), threads, 64, [&](size_t i) { hits[i]++; });
    for (size_t i = 0; i < hits.size(); ++i) ASSERT_EQ(hits[i].load(), 1) << i;
  }
}

TEST(Parallel, OneThreadRunsInOrderOnTheCaller) {
  std::vector<size_t> order;
  const auto caller = std::this_thread::get_id();
  vox::parallelForEach(100, 1, 8, [&](size_t i) {
    EXPECT_EQ(std::this_thread::get_id(), caller);
    order.push_back(i);
  });
  for (size_t i = 0; i < order.size(); ++i) ASSERT_EQ(order[i], i);
  std::vector<size_t> pieces;
  vox::parallelPieces(100, 1, 5, [&](size_t, size_t, size_t p) { pieces.push_back(p); });
  EXPECT_EQ(pieces, (std::vector<size_t>{0, 1, 2, 3, 4}));
}

TEST(Parallel, ExceptionsReachTheCaller) {
  EXPECT_THROW(vox::parallelForEach(1000, 2, 1, [](size_t i) { if (i == 500) throw std::runtime_error("x"); }),
               std::runtime_error);
  EXPECT_THROW(vox::parallelPieces(1000, 2, 4, [](size_t, size_t, size_t p) { if (p == 3) throw std::runtime_error("y"); }),
               std::runtime_error);
}

TEST(Parallel, WorkerCount) {
  EXPECT_EQ(vox::workerCount(3), 3u);
  EXPECT_GE(vox::workerCount(0), 1u);
}

TEST(Parallel, OrderedPipelineConsumesInOrderWithinItsWindow) {
  for (unsigned threads : {1u, 2u, 4u}) {
    const size_t n = 500, window = 3;
    std::vector<std::atomic<int>> produced(n);
    std::atomic<size_t> ahead{0}, mostAhead{0};
    std::vector<size_t> order;
    vox::orderedPipeline(
        n, threads, window,
        [&](size_t i) {
          ++produced[i];
          const size_t now = ++ahead;
          for (size_t seen = mostAhead; now > seen && !mostAhead.compare_exchange_weak(seen, now);) {
          }
        },
        [&](size_t i) {
          ASSERT_EQ(produced[i].load(), 1) << "consumed before (or without) being produced";
          --ahead;
          order.push_back(i);
        });
    ASSERT_EQ(order.size(), n) << threads << " threads";
    for (size_t i = 0; i < n; ++i) ASSERT_EQ(order[i], i) << threads << " threads";
    for (size_t i = 0; i < n; ++i) EXPECT_EQ(produced[i].load(), 1);
    EXPECT_LE(mostAhead.load(), window) << "items produced but not consumed at once, " << threads << " threads";
  }
  EXPECT_THROW(vox::orderedPipeline(
                   100, 2, 4, [](size_t) {}, [](size_t i) { if (i == 40) throw std::runtime_error("z"); }),
               std::runtime_error);
  EXPECT_THROW(vox::orderedPipeline(
                   100, 2, 4, [](size_t i) { if (i == 60) throw std::runtime_error("w"); }, [](size_t) {}),
               std::runtime_error);
}
