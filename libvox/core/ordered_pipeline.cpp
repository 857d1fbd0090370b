#include "libvox/core/ordered_pipeline.h"

#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>

#include "libvox/core/parallel.h"

namespace vox {

void orderedPipeline(size_t n, unsigned threads, size_t window, const std::function<void(size_t)>& produce,
                     const std::function<void(size_t)>& consume) {
  const unsigned workers = workerCount(threads);
  if (workers == 1 || n <= 1) {
    for (size_t i = 0; i < n; ++i) produce(i), consume(i);
    return;
  }
  tbb::task_arena arena(static_cast<int>(workers));
  arena.execute([&] {
    size_t next = 0;
    tbb::parallel_pipeline(
        std::max<size_t>(1, window),
        tbb::make_filter<void, size_t>(tbb::filter_mode::serial_in_order,
                                       [&](tbb::flow_control& fc) -> size_t {
                                         if (next == n) {
                                           fc.stop();
                                           return 0;
                                         }
                                         return next++;
                                       }) &
            tbb::make_filter<size_t, size_t>(tbb::filter_mode::parallel,
                                             [&](size_t i) {
                                               produce(i);
                                               return i;
                                             }) &
            tbb::make_filter<size_t, void>(tbb::filter_mode::serial_in_order, [&](size_t i) { consume(i); }));
  });
}

}  // namespace vox
