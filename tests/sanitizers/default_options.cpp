// Sanitizer defaults of a VOX_SANITIZE build, linked into vox and the unit
// tests (only in that build). Baked in so that a plain `ctest` in the ASan
// build is as strict as scripts/test-sanitizers.sh: every UBSan report is
// fatal, yet reports that come from Debian's library headers can still be
// suppressed (UBSan consults suppressions only for recoverable checks, so the
// build keeps checks recoverable and halts here instead of with
// -fno-sanitize-recover). ASAN_OPTIONS / UBSAN_OPTIONS in the environment
// override these.
#ifndef VOX_UBSAN_SUPPRESSIONS
#error "VOX_UBSAN_SUPPRESSIONS: the path of tests/sanitizers/ubsan.supp (CMakeLists.txt sets it)"
#endif

// intercept_tls_get_addr=0: GCC 12's runtime records each dynamic TLS block
// (thread_local in a dlopen'd library: libstb's, loaded with the command
// modules) and guesses its bounds from the 16 bytes before it whenever the
// block starts 16 bytes into a page, a layout of glibc 2.19 to 2.24. Since 2.25
// glibc mallocs those blocks, so that guess reads ASan's chunk header, and the
// exit-time leak check then scans from an address like 0x6b8 and dies ("Tracer
// caught signal 11", google/sanitizers#1409, fixed in LLVM 17). Where a block
// lands depends on every allocation before it, so the crash followed some
// command lines in one build and none in another. Without the interception the
// blocks are ordinary heap chunks, reachable through the thread's DTV: leaks in
// them are still reported. tests/sanitizers/dynamic_tls_test.sh places a block
// on that boundary and checks these defaults survive it.
extern "C" const char* __asan_default_options() {
  return "detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:intercept_tls_get_addr=0";
}

extern "C" const char* __ubsan_default_options() {
  return "halt_on_error=1:print_stacktrace=1:suppressions=" VOX_UBSAN_SUPPRESSIONS;
}
