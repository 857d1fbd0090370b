// Progress reporting from long-running libvox work. libvox never prints: it
// calls the function it is given with the fraction done (0..1), from any worker
// thread; the CLI decides whether and how to draw it (tools/cli/cli.h ProgressBar).
#pragma once

#include <functional>

namespace vox {

/// Must be thread-safe and cheap; may be empty (no reporting).
using ProgressFn = std::function<void(double fraction)>;

}  // namespace vox
