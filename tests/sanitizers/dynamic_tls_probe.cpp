// Places the dynamic TLS block of a dlopen'd library 16 bytes into a page, the
// layout where GCC 12's sanitizer runtime, when it intercepts __tls_get_addr,
// reads the block's bounds from ASan's chunk header and LeakSanitizer's exit
// check then dies (google/sanitizers#1409; docs/reliability.md "Sanitizers in
// CI"). Run by dynamic_tls_test.sh without ASan's quarantine
// (quarantine_size_mb=0, thread_local_quarantine_size_kb=0), so that a freed
// chunk is the next one its size class hands out.
// Usage: dynamic_tls_probe MODULE hold|leak
//   hold  the module keeps a 77-byte block in its thread_local only: reachable
//   leak  and main drops a 77-byte block of its own: a leak to report
#include <dlfcn.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

// The leak is made in a frame of its own, which is then overwritten, so that
// no register or stack slot still points at the block when LeakSanitizer's
// exit-time check scans: with the pointer in main's frame, a build at -Og
// kept it reachable and the leak went unreported.
static __attribute__((noinline)) void dropBlock() {
  void* lost = std::malloc(77);
  std::memset(lost, 2, 77);
  asm volatile("" : : "r"(lost) : "memory");  // the block is written, then forgotten
}

static __attribute__((noinline)) void scrubStack() {
  volatile char scratch[4096];
  for (std::size_t i = 0; i < sizeof scratch; ++i) scratch[i] = 0;
}

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: dynamic_tls_probe MODULE hold|leak\n");
    return 2;
  }
  const bool leak = std::strcmp(argv[2], "leak") == 0;
  // Loaded first: dlopen's own small allocations must not take the slot.
  void* module = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
  if (!module) {
    std::fprintf(stderr, "dynamic_tls_probe: %s\n", dlerror());
    return 2;
  }
  using Touch = void* (*)(bool);
  auto touch = reinterpret_cast<Touch>(dlsym(module, "voxDynamicTlsTouch"));
  if (!touch) {
    std::fprintf(stderr, "dynamic_tls_probe: %s has no voxDynamicTlsTouch\n", argv[1]);
    return 2;
  }
  // 24-byte blocks (the module's TLS block's size class) until one starts 16
  // bytes into a page; that one is freed for the TLS block to reuse.
  std::vector<void*> kept;
  kept.reserve(1 << 16);
  void* slot = nullptr;
  for (int i = 0; i < (1 << 16) && !slot; ++i) {
    void* p = std::malloc(24);
    if (reinterpret_cast<std::uintptr_t>(p) % 4096 == 16)
      slot = p;
    else
      kept.push_back(p);
  }
  if (!slot) {
    std::fprintf(stderr, "dynamic_tls_probe: no 24-byte block 16 bytes into a page\n");
    return 2;
  }
  std::free(slot);
  void* block = touch(true);
  const unsigned long offset = reinterpret_cast<std::uintptr_t>(block) % 4096;
  std::printf("dynamic TLS block at %p, page offset %lu\n", block, offset);
  std::fflush(stdout);  // the control run dies in the exit-time check
  for (void* p : kept) std::free(p);
  if (offset != 16) {
    std::fprintf(stderr, "dynamic_tls_probe: the TLS block did not reuse the freed slot\n");
    return 3;
  }
  if (leak) {
    dropBlock();
    scrubStack();
    std::printf("dropped a 77-byte block\n");
  }
  return 0;
}
