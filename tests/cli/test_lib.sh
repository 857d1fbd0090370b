# Shared helpers of the end-to-end test scripts (cli_test.sh, export_test.sh),
# sourced after `set -u`: each test group runs in a fresh temporary directory
# that is removed on exit, counts failures, and checks exit codes and messages.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 4
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }

# expect_exit CODE CMD...: runs CMD, checks its exit code, keeps stdout/stderr.
expect_exit() {
  local want=$1; shift
  "$@" >out.txt 2>err.txt
  local got=$?
  [ "$got" = "$want" ] || fail "exit $got, expected $want: $* (stderr: $(head -c 400 err.txt))"
}
expect_stderr() { grep -qF -- "$1" err.txt || fail "stderr lacks '$1': $(head -c 400 err.txt)"; }
expect_stdout() { grep -qF -- "$1" out.txt || fail "stdout lacks '$1': $(head -c 400 out.txt)"; }
jcheck() { python3 -c "import json,sys; d=json.load(open('$1')); $2" || fail "json check failed on $1: $2"; }
