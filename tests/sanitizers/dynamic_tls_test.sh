#!/bin/bash
# vox's sanitizer defaults (tests/sanitizers/default_options.cpp, linked into
# the probe as into vox) against google/sanitizers#1409: a dlopen'd library's
# dynamic TLS block that starts 16 bytes into a page made LeakSanitizer's exit
# check die in CI ("Tracer caught signal 11"). dynamic_tls_probe puts the block
# there on purpose. Checked:
#   control   with __tls_get_addr intercepted (the runtime's own default), the
#             runtime takes the bad guess for that block;
#   defaults  the same run with vox's defaults exits 0, no sanitizer message:
#             a block held only in dynamic TLS is reachable, not a leak;
#   leak      a block dropped by the program is still reported.
# Usage: dynamic_tls_test.sh PROBE MODULE
set -u
probe=$1 module=$2
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
cd "$(mktemp -d)" && trap 'rm -rf "$PWD"' EXIT
export ASAN_OPTIONS=quarantine_size_mb=0:thread_local_quarantine_size_kb=0

ASAN_OPTIONS=$ASAN_OPTIONS:intercept_tls_get_addr=1:verbosity=2 "$probe" "$module" hold >out.txt 2>control.txt
control=$?
cat out.txt
grep -q "glibc >=2.19 suspected" control.txt ||
  fail "control: the runtime did not take the chunk header for TLS bounds (exit $control): $(grep -v '^==' control.txt | head -c 300)"
if grep -q "Tracer caught signal" control.txt; then
  echo "control (interception on): LeakSanitizer's exit check died, exit $control, as in CI"
else
  echo "control (interception on): exit $control; this runtime survived the bad guess"
fi

"$probe" "$module" hold >out.txt 2>err.txt
rc=$?
[ "$rc" = 0 ] || fail "defaults: exit $rc: $(head -c 400 err.txt)"
grep -q "Sanitizer\|Tracer caught" err.txt && fail "defaults: $(head -c 400 err.txt)"

"$probe" "$module" leak >out.txt 2>err.txt
rc=$?
[ "$rc" != 0 ] || fail "leak: exit 0"
grep -q "ERROR: LeakSanitizer: detected memory leaks" err.txt || fail "leak: not reported: $(head -c 400 err.txt)"
grep -q "Direct leak of 77 byte(s) in 1 object(s)" err.txt || fail "leak: not the dropped block: $(grep -i leak err.txt | head -3)"
grep -q "Direct leak of 77 byte(s) in 2" err.txt && fail "leak: the block held in dynamic TLS was reported too"

[ "$failures" = 0 ] || { echo "dynamic_tls_test: $failures failed" >&2; exit 1; }
echo "dynamic_tls_test: defaults survive a dynamic TLS block at page offset 16; leaks still reported"
