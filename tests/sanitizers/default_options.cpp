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

extern "C" const char* __asan_default_options() {
  return "detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1";
}

extern "C" const char* __ubsan_default_options() {
  return "halt_on_error=1:print_stacktrace=1:suppressions=" VOX_UBSAN_SUPPRESSIONS;
}
