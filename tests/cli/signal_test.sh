#!/usr/bin/env bash
# Interrupted runs: SIGINT, SIGTERM and SIGHUP while a command computes and
# while it writes (caught by polling for its temporary file), SIGKILL followed
# by a rerun, and a `ulimit -f` smaller than the output. Each time: the
# documented exit code and message, no temporary file left, and an existing
# output byte for byte as it was.
# Usage: signal_test.sh GROUP VOX_BINARY DATA_DIR
set -u
set -m  # job control: background commands get SIGINT (a script's jobs otherwise ignore it)
shopt -s nullglob  # a glob that matches nothing is empty (the temporary-file poll)
group=$1 vox=$2 data=$3
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

# temporaries DIR: the temporary outputs (".NAME.tmp-HOST-PID-N") in DIR.
temporaries() { (cd "$1" && compgen -G '.*.tmp-*' || true); }

# handles_sigint PID: PID is vox (not yet the forked shell that will exec it:
# job-control bash catches SIGINT itself, so its SigCgt bit says nothing about
# vox) and its SIGINT handler is installed.
handles_sigint() {
  local caught comm
  read -r comm </proc/$1/comm 2>/dev/null || return 1
  [ "$comm" = vox ] || return 1
  caught=$(sed -n 's/^SigCgt:[[:space:]]*//p' /proc/$1/status 2>/dev/null) || return 1
  [ -n "$caught" ] && (( (16#$caught & 2) != 0 ))
}

# interrupt SIG WHEN OUT CMD...: runs CMD in the background with an existing
# OUT in place, sends SIG either after WHEN seconds or, for WHEN=write, as
# soon as a temporary file of OUT's directory exists, and checks the outcome.
# Returns 1 (without failing) when the command finished before the signal.
interrupt() {
  local sig=$1 when=$2 out=$3; shift 3
  local dir; dir=$(dirname "$out")
  printf 'previous output\n' >"$out"
  "$@" >out.txt 2>err.txt &
  local pid=$! waited=0
  # Wait until vox handles SIGINT (SigCgt bit 2 in /proc: its handlers are
  # installed), so the early signal tests the handler, not process start-up.
  while kill -0 $pid 2>/dev/null && ! handles_sigint $pid; do sleep 0.005; done
  if [ "$when" = write ]; then
    # Builtins only (no subshell, no sleep process): a write phase can be a few
    # milliseconds, shorter than one fork on a loaded machine.
    local pending=()
    while kill -0 $pid 2>/dev/null; do
      pending=("$dir"/.*.tmp-*)
      [ ${#pending[@]} -gt 0 ] && break
    done
  else
    sleep "$when"
  fi
  kill -"$sig" $pid 2>/dev/null
  wait $pid
  local got=$? want
  case $sig in INT) want=130 ;; TERM) want=143 ;; HUP) want=129 ;; esac
  if [ "$got" = 0 ]; then
    waited=1  # finished first: nothing to check but its success
  else
    [ "$got" = "$want" ] || fail "SIG$sig ($when): exit $got, expected $want: $* ($(head -c 300 err.txt))"
    grep -qF "interrupted by SIG$sig" err.txt || fail "SIG$sig ($when): no message from $*: $(head -c 300 err.txt)"
    if [ "$(head -c 15 "$out")" = "previous output" ]; then
      ! grep -qF "every output was already in place" err.txt || fail "SIG$sig ($when): says its outputs were in place, but $out was not replaced"
    else
      # Only a signal after the final rename may leave a new output, and it says so.
      grep -qF "every output was already in place" err.txt || fail "SIG$sig ($when): the existing $out was replaced"
    fi
  fi
  local left; left=$(temporaries "$dir")
  [ -z "$left" ] || fail "SIG$sig ($when): temporaries left in $dir: $left"
  return $waited
}

# each_moment OUT CMD...: SIGINT early, then SIGINT, SIGTERM and SIGHUP in the
# write phase (retried up to 6 times when the command outran the poll).
each_moment() {
  local out=$1; shift
  interrupt INT 0.05 "$out" "$@"
  local sig tries
  for sig in INT TERM HUP; do
    for tries in 1 2 3 4 5 6; do
      interrupt $sig write "$out" "$@" && break
      [ $tries = 6 ] && fail "SIG$sig: never caught $* writing (it finished first 6 times)"
    done
  done
}

case $group in
voxelize)
  each_moment scene.vdb "$vox" voxelize demo:hamlet --res 384 -o scene.vdb --threads 2
  mesh=$data/../../scripts/demo/house.obj
  each_moment mesh.vdb "$vox" voxelize "$mesh" --res 512 --fill solid -o mesh.vdb
  ;;
derived)
  "$vox" voxelize demo:hamlet --res 256 -o h.vdb --quiet || fail "setup bake"
  each_moment pyramid.vdb "$vox" mip h.vdb -o pyramid.vdb
  each_moment pages.vpk "$vox" pack-chunks h.vdb -o pages.vpk --mips
  mkdir -p atlas
  each_moment atlas/h.summary.png "$vox" build-atlas h.vdb -o atlas --all
  each_moment shot.png "$vox" render-canonical h.vdb -o shot.png --eye 40,30,40 --target 0,0,0 --size 1600x1200 --mode canonical,class,shaded,depth,normal
  each_moment h.glb "$vox" export h.vdb -o h.glb
  ;;
sigkill)
  # A run killed outright leaves its temporary; the next run of the same
  # command removes it and succeeds.
  printf 'previous output\n' >scene.vdb
  "$vox" voxelize demo:hamlet --res 384 -o scene.vdb >out.txt 2>err.txt &
  pid=$!
  while kill -0 $pid 2>/dev/null && [ -z "$(temporaries .)" ]; do sleep 0.005; done
  kill -KILL $pid 2>/dev/null
  wait $pid
  [ -n "$(temporaries .)" ] || echo "note: the killed run had not created its temporary yet"
  [ "$(cat scene.vdb)" = "previous output" ] || fail "SIGKILL replaced the existing output"
  expect_exit 0 "$vox" voxelize demo:hamlet --res 32 -o scene.vdb
  left=$(temporaries .)
  [ -z "$left" ] || fail "the rerun left the dead run's temporary: $left"
  expect_exit 0 "$vox" info scene.vdb
  ;;
file_size_limit)
  # ulimit -f (in 1024-byte blocks): the write fails with "File too large".
  printf 'previous output\n' >scene.vdb
  (ulimit -f 64; "$vox" voxelize demo:hamlet --res 128 -o scene.vdb >out.txt 2>err.txt)
  got=$?
  [ "$got" = 4 ] || fail "ulimit -f: exit $got, expected 4 ($(head -c 300 err.txt))"
  expect_stderr "scene.vdb"
  expect_stderr "File too large"
  [ "$(cat scene.vdb)" = "previous output" ] || fail "ulimit -f: the existing output was replaced"
  left=$(temporaries .)
  [ -z "$left" ] || fail "ulimit -f: temporaries left: $left"
  # The page file writer (not OpenVDB's) fails the same way.
  "$vox" voxelize demo:hamlet --res 128 -o small.vdb --quiet || fail "setup bake"
  (ulimit -f 64; "$vox" pack-chunks small.vdb -o pages.vpk >out.txt 2>err.txt)
  got=$?
  [ "$got" = 4 ] || fail "ulimit -f pack-chunks: exit $got, expected 4 ($(head -c 300 err.txt))"
  expect_stderr "pages.vpk"
  expect_stderr "File too large"
  [ ! -e pages.vpk ] && [ -z "$(temporaries .)" ] || fail "ulimit -f pack-chunks left files: $(ls -A)"
  ;;
many_outputs)
  # 300 outputs at once (render views): an interrupt while they are written
  # removes every temporary, not only the first few hundred.
  "$vox" voxelize demo:hamlet --res 64 -o h.vdb --quiet || fail "setup bake"
  mkdir views
  caught=0
  for tries in 1 2 3 4 5 6; do
    "$vox" render-canonical h.vdb -o views/v.png --orbit 300 --size 96x96 >out.txt 2>err.txt &
    pid=$!
    while kill -0 $pid 2>/dev/null && ! handles_sigint $pid; do sleep 0.005; done
    pending=()
    while kill -0 $pid 2>/dev/null; do
      pending=(views/.*.tmp-*)
      [ ${#pending[@]} -gt 270 ] && break
    done
    kill -INT $pid 2>/dev/null
    wait $pid
    got=$?
    rm -f views/v_*.png
    [ "$got" = 0 ] && continue  # finished first
    caught=1
    [ "$got" = 130 ] || fail "300 views: exit $got, expected 130 ($(head -c 300 err.txt))"
    [ ${#pending[@]} -gt 256 ] || echo "note: interrupted with ${#pending[@]} temporaries"
    left=$(temporaries views)
    [ -z "$left" ] || fail "300 views: $(echo "$left" | wc -l) temporaries left after SIGINT"
    break
  done
  [ $caught = 1 ] || fail "300 views: never caught the run writing (it finished first 6 times)"
  ;;
commit_window)
  # Several outputs replace old ones: a signal at any moment leaves either all
  # of the old files or all of the new ones, and says which.
  "$vox" voxelize demo:hamlet --res 96 -o h.vdb --quiet || fail "setup bake"
  render=("$vox" render-canonical h.vdb -o shot.png --eye 40,30,40 --target 0,0,0 --size 320x240
          --mode canonical,class,shaded,depth,normal --report shot.json)
  "${render[@]}" --quiet || fail "setup render"
  files=(shot*.png shot*.exr shot.json)
  [ ${#files[@]} -ge 5 ] || fail "expected 5 render outputs and a report, got: ${files[*]}"
  start=$(date +%s%N)
  "${render[@]}" --quiet || fail "timing render"
  span=$(( ($(date +%s%N) - start) / 1000 ))  # microseconds
  for step in $(seq 1 24); do
    for f in "${files[@]}"; do printf 'previous output\n' >"$f"; done
    "${render[@]}" >out.txt 2>err.txt &
    pid=$!
    while kill -0 $pid 2>/dev/null && ! handles_sigint $pid; do sleep 0.001; done
    # Spread the signals over the run, the end (the renames) included.
    sleep "$(awk -v s=$span -v k=$step 'BEGIN { printf "%.6f", s * (0.5 + k / 24.0) / 1e6 }')"
    kill -TERM $pid 2>/dev/null
    wait $pid
    got=$?
    old=0
    for f in "${files[@]}"; do [ "$(head -c 15 "$f" | tr -d '\0')" = "previous output" ] && old=$((old + 1)); done
    if [ "$old" != 0 ] && [ "$old" != ${#files[@]} ]; then
      fail "SIGTERM at step $step (exit $got): $old of ${#files[@]} outputs old, the rest new"
    fi
    if [ "$got" = 143 ]; then
      if [ "$old" = 0 ]; then
        grep -qF "every output was already in place" err.txt || fail "step $step: new outputs, but: $(head -c 300 err.txt)"
      else
        ! grep -qF "already in place" err.txt || fail "step $step: old outputs, but: $(head -c 300 err.txt)"
        ! grep -qF "wrote" err.txt || fail "step $step: says it wrote: $(head -c 300 err.txt)"
      fi
    else
      [ "$got" = 0 ] && [ "$old" = 0 ] || fail "step $step: exit $got with $old old outputs"
    fi
    left=$(temporaries .)
    [ -z "$left" ] || fail "step $step: temporaries left: $left"
  done
  ;;
atlas_directories)
  # build-atlas makes its output directory (and missing parents): an interrupt
  # while it writes removes the temporaries and then the directories the run
  # made, deepest first, never one it did not make or one holding other files.
  "$vox" voxelize demo:hamlet --res 256 -o h.vdb --quiet || fail "setup bake"
  for sig in INT TERM HUP; do
    caught=0
    for tries in 1 2 3 4 5 6; do
      rm -rf made && mkdir made
      if [ $sig = HUP ]; then mkdir made/new && printf 'mine\n' >made/new/keep.txt; fi  # not the run's to remove
      "$vox" build-atlas h.vdb -o made/new/deeper/atlas --all >out.txt 2>err.txt &
      pid=$!
      while kill -0 $pid 2>/dev/null && ! handles_sigint $pid; do sleep 0.005; done
      pending=()
      while kill -0 $pid 2>/dev/null; do
        pending=(made/new/deeper/atlas/.*.tmp-*)
        [ ${#pending[@]} -gt 0 ] && break
      done
      kill -$sig $pid 2>/dev/null
      wait $pid
      got=$?
      [ "$got" = 0 ] && continue  # finished first
      caught=1
      case $sig in INT) want=130 ;; TERM) want=143 ;; HUP) want=129 ;; esac
      [ "$got" = $want ] || fail "SIG$sig: exit $got, expected $want ($(head -c 300 err.txt))"
      grep -qF "interrupted by SIG$sig" err.txt || fail "SIG$sig: no message: $(head -c 300 err.txt)"
      [ -d made ] || fail "SIG$sig: removed made/, which the run did not make"
      if [ $sig = HUP ]; then
        [ "$(cat made/new/keep.txt 2>/dev/null)" = mine ] || fail "SIG$sig: the user's made/new/keep.txt is gone"
        [ ! -e made/new/deeper ] || fail "SIG$sig: left made/new/deeper: $(find made/new/deeper | head)"
      else
        [ ! -e made/new ] || fail "SIG$sig: left the directories it made: $(find made/new | head)"
      fi
      break
    done
    [ $caught = 1 ] || fail "SIG$sig: never caught build-atlas writing (it finished first 6 times)"
  done
  # A signal before the directory is made (reading the scene) leaves none.
  rm -rf made && mkdir made
  interrupt INT 0.05 made/previous "$vox" build-atlas h.vdb -o made/early/atlas --all && [ -e made/early ] &&
    fail "SIGINT (early): left made/early: $(find made/early | head)"
  ;;
rollback)
  # A rename that fails after others succeeded (here the report, immutable)
  # puts the outputs already moved back: the old file, or no file.
  touch probe && chattr +i probe 2>/dev/null || { echo "SKIP rollback: chattr +i is not supported here"; echo "ok: $group"; exit 0; }
  chattr -i probe
  trap 'chattr -i "$work"/* 2>/dev/null; rm -rf "$work"' EXIT
  printf 'previous output\n' >scene.vdb
  printf 'previous report\n' >r.json
  chattr +i r.json
  expect_exit 4 "$vox" voxelize demo:hamlet --res 32 -o scene.vdb --report r.json
  expect_stderr "r.json: cannot move the finished output into place"
  expect_stderr "put back as they were (scene.vdb)"
  ! grep -qF "wrote" err.txt || fail "a failed commit says it wrote: $(head -c 300 err.txt)"
  [ "$(cat scene.vdb)" = "previous output" ] || fail "the failed commit left a new scene.vdb"
  rm scene.vdb
  expect_exit 4 "$vox" voxelize demo:hamlet --res 32 -o scene.vdb --report r.json
  expect_stderr "put back as they were (scene.vdb)"
  [ ! -e scene.vdb ] || fail "the failed commit left a scene.vdb that did not exist before"
  left=$(temporaries .)
  [ -z "$left" ] || fail "rollback: temporaries left: $left"
  chattr -i r.json
  # A report directory that cannot be written is refused before the work.
  mkdir locked
  chattr +i locked
  expect_exit 4 "$vox" voxelize demo:hamlet --res 32 -o scene.vdb --report locked/r.json
  expect_stderr "locked/r.json: cannot write: directory 'locked' is not writable"
  [ ! -e scene.vdb ] || fail "an unwritable report directory still let the scene be written"
  chattr -i locked
  ;;
*)
  echo "unknown group $group" >&2
  exit 2
  ;;
esac
[ $failures = 0 ] || { echo "$failures failure(s) in $group" >&2; exit 1; }
echo "ok: $group"
