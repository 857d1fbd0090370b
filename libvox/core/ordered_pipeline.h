// An ordered pipeline: items made in parallel, a bounded number ahead of one
// in-order consumer. For a serial step that must see the items in order (an
// OBJ's lines: index resolution, vertex numbering, the first error) after
// parallel work per item (parsing their numbers), without every item's
// intermediate data existing at once.
//
// Determinism: consume(i) runs for i = 0, 1, 2, ... in order, one at a time,
// on whichever thread; produce(i) runs once per item, concurrently with
// other produce calls and with consume. What the consumer builds does not
// depend on --threads.
//
// Threads: as libvox/core/parallel.h (`threads` caps the workers, 0 = every
// core the process may use; 1 = produce(i), consume(i) in order on the
// calling thread). An exception thrown by either function cancels the rest
// and is rethrown to the caller.
#pragma once

#include <cstddef>
#include <functional>

namespace vox {

/// produce(i) for every i in [0, n) on up to `threads` workers, at most
/// `window` items ahead of consume(i) (memory bounded by `window` items,
/// reused as they are consumed).
void orderedPipeline(size_t n, unsigned threads, size_t window, const std::function<void(size_t i)>& produce,
                     const std::function<void(size_t i)>& consume);

}  // namespace vox
