// Loaded with dlopen by dynamic_tls_probe.cpp: one thread_local of 24 bytes,
// which glibc (>= 2.25) allocates with malloc on the first access from a
// thread, through __tls_get_addr, like libstb's in vox's command modules.
#include <cstdlib>
#include <cstring>

namespace {
thread_local void* held[3];
}

// Touches the thread_local (allocating its block) and returns its address;
// with `hold`, stores a fresh 77-byte block in it, so that the only pointer to
// that block lives in dynamic TLS.
extern "C" void* voxDynamicTlsTouch(bool hold) {
  if (hold) {
    held[0] = std::malloc(77);
    std::memset(held[0], 1, 77);
  }
  return static_cast<void*>(held);
}
