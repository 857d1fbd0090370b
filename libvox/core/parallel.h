// The one way voxbake runs work in parallel: TBB under a fixed partition.
//
// Determinism: outputs must not depend on --threads. Both entry points hand
// out work whose split does not depend on scheduling; callers keep per-piece
// or per-item results and merge them in index order (never in completion
// order), which is what makes `--threads 1` and `--threads N` byte-identical.
//
// Threads: `threads` caps the workers of one call (0 = every core the process
// may use). The CLI also caps TBB globally at --threads (tools/cli/cli.cpp), so
// OpenVDB's own loops obey it too. threads == 1 runs on the calling thread, in
// index order, without touching TBB: the serial path stays a plain loop.
//
// Thread safety: the calls are reentrant; `fn` runs concurrently with itself.
// An exception thrown by `fn` cancels the remaining work and is rethrown to
// the caller (the first one thrown).
#pragma once

#include <cstddef>
#include <functional>

namespace vox {

/// Workers that `threads` stands for: `threads`, or every core when 0.
unsigned workerCount(unsigned threads);

/// Splits [0, n) into `pieces` contiguous ranges [n*p/pieces, n*(p+1)/pieces)
/// and calls fn(begin, end, p) once for each p in [0, pieces), on up to
/// `threads` workers. Use it when each piece keeps an accumulator merged
/// afterwards in piece order. pieces == 0 means workerCount(threads) pieces
/// (bounded by n): the split then follows the thread count, so only use it
/// when the merged result does not depend on where the pieces end.
void parallelPieces(size_t n, unsigned threads, size_t pieces,
                    const std::function<void(size_t begin, size_t end, size_t piece)>& fn);

/// Calls fn(i) for every i in [0, n), `grain` consecutive indices per task,
/// on up to `threads` workers, in any order (load-balanced). Use it when every
/// index writes only its own outputs.
void parallelForEach(size_t n, unsigned threads, size_t grain, const std::function<void(size_t i)>& fn);

}  // namespace vox
