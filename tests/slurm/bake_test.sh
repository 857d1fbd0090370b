#!/usr/bin/env bash
# Region bakes on real engines (docs/scale.md, "Running on Slurm and make"):
#   cluster  a one-node Slurm cluster starts (tests/slurm/slurm_cluster.sh), runs
#            an sbatch --wait array, and its daemons are gone afterwards, also
#            when the shell that started it is killed; bake-slurm.sh's usage errors
#   bake     scripts/bake-slurm.sh at N=3 on that cluster: the merged page file
#            is byte-identical to the single-process bake, the merged scene equal
#            (vox diff); a task that fails once is requeued and the merge still
#            matches; a task that keeps failing leaves the merge unrun
#   make     scripts/bake.mk with make -j2 at N=3: the same bytes; interrupted
#            with SIGINT mid-run, no partial part is left, and the rerun bakes
#            only the missing parts and matches
# Usage: bake_test.sh GROUP VOX_BINARY SOURCE_DIR
# Exit 77 (ctest's skip code, SKIP_RETURN_CODE) with "SKIP: ..." when the Slurm
# groups cannot run here (not root, slurm-wlm or munge not installed).
set -u
group=$1 vox=$(realpath "$2") src=$(realpath "$3")
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=../cli/test_lib.sh
. "$here/../cli/test_lib.sh"
# shellcheck source=slurm_cluster.sh
. "$here/slurm_cluster.sh"
bake_slurm=$src/scripts/bake-slurm.sh
bake_mk=$src/scripts/bake.mk
N=3
# Tiny bakes: the machine is shared. One thread per vox; the regions of a
# bake run side by side.
PACK_ARGS="--chunk 16 --threads 1"

need_cluster() {
  local why
  if why=$(slurm_cluster_missing); then
    echo "SKIP: $why"
    exit 77
  fi
  start_slurm_cluster || { echo "FAIL: the Slurm cluster did not start" >&2; exit 1; }
}

# The source: the procedural city when vox bakes it by regions (its parts of
# a 256 x 64 x 256 city merge), else the hamlet, saying why; VOX_BAKE_TEST_SOURCE
# (voxelize arguments, shell words) overrides both.
pick_source() {
  if [ -n "${VOX_BAKE_TEST_SOURCE:-}" ]; then
    read -r -a SOURCE <<<"$VOX_BAKE_TEST_SOURCE"
  else
    local i ok=1 city=(demo:city --extent 256,64,256 --threads 1)
    for i in 0 1 2; do
      "$vox" voxelize "${city[@]}" --region $i/3 -o "probe-$i.vdb" -q >probe.txt 2>&1 || { ok=0; break; }
    done
    [ $ok = 1 ] && { "$vox" merge probe-0.vdb probe-1.vdb probe-2.vdb -o probe.vdb -q >probe.txt 2>&1 || ok=0; }
    if [ $ok = 1 ]; then
      SOURCE=(demo:city --extent 512,64,512 --threads 1)
    else
      echo "NOTE: demo:city does not bake by regions here ($(head -c 300 probe.txt | tr '\n' ' ')): the hamlet instead"
      SOURCE=(demo:hamlet --res 128 --threads 1)
    fi
    rm -f probe*.vdb probe.txt
  fi
  echo "source: ${SOURCE[*]}"
}

# The region bake needs `vox voxelize --region`, `vox merge` and
# `vox pack-chunks --merge` (issue 16); without them this test fails, saying so.
need_regions() {
  local missing=""
  "$vox" voxelize "${SOURCE[@]}" --region 0/1 -o probe.vdb -q >probe.txt 2>&1 ||
    missing="$missing vox voxelize --region ($(head -c 200 probe.txt | tr "\n" " "));"
  "$vox" --help 2>&1 | grep -q '^ *merge ' || missing="$missing vox merge (not among vox --help's subcommands);"
  "$vox" pack-chunks --help 2>&1 | grep -q -- --merge || missing="$missing vox pack-chunks --merge;"
  rm -f probe.vdb probe.txt
  if [ -n "$missing" ]; then
    echo "FAIL: this vox cannot bake regions yet:$missing the region bake cannot be tested" >&2
    exit 1
  fi
}

# The single-process bake every merge must equal: w.vdb and w.vpk.
reference() {
  expect_exit 0 "$vox" voxelize "${SOURCE[@]}" -o w.vdb -q
  # shellcheck disable=SC2086
  expect_exit 0 "$vox" pack-chunks w.vdb -o w.vpk $PACK_ARGS -q
  [ -s w.vpk ] || { echo "FAIL: no single-process bake to compare with" >&2; exit 1; }
}

# same_as_reference DIR WHAT: DIR/world.vpk byte-identical to w.vpk, DIR/world.vdb equal to w.vdb.
same_as_reference() {
  if [ ! -f "$1/world.vpk" ] || [ ! -f "$1/world.vdb" ]; then
    fail "$2: no merged world in $1: $(ls "$1" | tr '\n' ' ')"
    return
  fi
  cmp -s "$1/world.vpk" w.vpk || fail "$2: $1/world.vpk differs from the single-process page file ($(cmp "$1/world.vpk" w.vpk 2>&1 | head -c 200))"
  expect_exit 0 "$vox" diff "$1/world.vdb" w.vdb
}

# job_field JOB FIELD: FIELD of every record of JOB (an array: one per task).
job_field() { scontrol show job -o "$1" | sed -n "s/.*[ ^]$2=\([^ ]*\).*/\1/p"; }
task_field() {  # task_field ARRAY_JOB TASK FIELD
  scontrol show job -o "$1" | grep " ArrayTaskId=$2 " | sed -n "s/.* $3=\([^ ]*\).*/\1/p"
}

case $group in
cluster)
  # Usage errors need no cluster.
  expect_exit 2 "$bake_slurm" --regions 0 --out o -- demo:hamlet
  expect_stderr "--regions '0'"
  expect_exit 2 "$bake_slurm" --regions x3 --out o -- demo:hamlet
  expect_exit 2 "$bake_slurm" --regions 3 --out o
  expect_stderr "no voxelize arguments"
  expect_exit 2 "$bake_slurm" --regions 3 --out o -- demo:hamlet --region 1/3
  expect_stderr "sets the region"
  expect_exit 2 env PATH=/nonexistent /bin/bash "$bake_slurm" --regions 3 --out o --vox "$vox" -- demo:hamlet
  expect_stderr "sbatch not found on PATH"
  expect_exit 2 make -s -f "$bake_mk" REGIONS=0 OUT=m0
  grep -qF "REGIONS='0' is not a whole number" err.txt || fail "bake.mk REGIONS=0: $(head -c 300 err.txt)"

  need_cluster
  pids=$SLURM_CLUSTER_PIDS dir=$SLURM_CLUSTER_DIR
  [ "$(echo "$pids" | wc -w)" = 3 ] || fail "expected 3 daemon pids, got '$pids'"
  expect_exit 0 sbatch --wait --array=0-2 --output=/dev/null \
    --wrap "echo \$SLURM_ARRAY_TASK_ID > $work/task-\$SLURM_ARRAY_TASK_ID.txt"
  for i in 0 1 2; do
    [ "$(cat "task-$i.txt" 2>/dev/null)" = "$i" ] || fail "array task $i did not run (task-$i.txt: $(cat "task-$i.txt" 2>&1))"
  done
  # sbatch refuses a job (no such partition): exit 4, nothing left queued.
  expect_exit 4 "$bake_slurm" --regions 2 --out o --vox "$vox" --partition nosuch -- demo:hamlet --res 16
  expect_stderr "sbatch refused the region array"
  [ -z "$(squeue -h -o %A)" ] || fail "jobs queued after a refused submission: $(squeue 2>&1)"
  stop_slurm_cluster
  for p in $pids; do
    [ -e /proc/$p ] && fail "daemon pid $p still alive after stop_slurm_cluster ($(cat /proc/$p/comm))"
  done
  [ -e "$dir" ] && fail "$dir still exists after stop_slurm_cluster"
  [ -z "${SLURM_CONF:-}" ] || fail "SLURM_CONF still set after stop_slurm_cluster"

  # A shell that started a cluster and is killed stops it: its TERM trap at
  # once, the watcher within seconds when SIGKILL leaves no trap to run.
  for sig in TERM KILL; do
    rm -f started.txt sleeper.pid
    bash -c ". '$here/slurm_cluster.sh'; start_slurm_cluster || exit 1
             echo \"\$SLURM_CLUSTER_PIDS|\$SLURM_CLUSTER_DIR\" > '$work/started.txt'
             sleep 600 </dev/null >/dev/null 2>&1 &
             echo \$! > '$work/sleeper.pid'; wait \$!" &
    starter=$!
    for _ in $(seq 300); do [ -s started.txt ] && break; sleep 0.2; done
    [ -s started.txt ] || fail "SIG$sig: the cluster did not start"
    kill -$sig $starter
    wait $starter 2>/dev/null
    [ -s sleeper.pid ] && kill "$(cat sleeper.pid)" 2>/dev/null
    [ -s started.txt ] || continue
    IFS='|' read -r pids dir <started.txt
    for _ in $(seq 100); do
      alive=""
      for p in $pids; do [ -e /proc/$p ] && alive="$alive $p"; done
      [ -z "$alive" ] && [ ! -e "$dir" ] && break
      sleep 0.2
    done
    [ -z "$alive" ] || fail "SIG$sig to its shell: daemon pids$alive still alive after 20 s"
    [ -z "$alive" ] || kill -KILL $alive 2>/dev/null
    [ -n "$dir" ] && [ -e "$dir" ] && fail "SIG$sig to its shell: $dir still exists"
  done
  ;;

bake)
  need_cluster
  pick_source
  need_regions
  reference

  # The bake: three array tasks, then the merge.
  expect_exit 0 "$bake_slurm" --regions $N --out o1 --vox "$vox" --pack-args "$PACK_ARGS" --wait -- "${SOURCE[@]}"
  grep -q '^regions job [0-9]' out.txt && grep -q '^merge job [0-9]' out.txt ||
    fail "bake-slurm.sh did not print its job ids: $(head -c 300 out.txt)"
  same_as_reference o1 "slurm bake"
  echo "slurm bake at N=$N: matches (${SECONDS} s into the test)"

  # A task that fails once (exit 4, as an I/O error) is requeued by Slurm.
  cat >flaky-vox <<EOF
#!/bin/bash
case " \$* " in
  *" --region 1/$N "*)
    if [ ! -e "$work/failed-once" ]; then
      touch "$work/failed-once"; echo "flaky-vox: region 1 fails this once" >&2; exit 4
    fi ;;
esac
exec "$vox" "\$@"
EOF
  chmod +x flaky-vox
  expect_exit 0 "$bake_slurm" --regions $N --out o2 --vox "$work/flaky-vox" --pack-args "$PACK_ARGS" --wait -- "${SOURCE[@]}"
  [ -e failed-once ] || fail "requeue: the flaky vox never failed"
  job=$(sed -n 's/^regions job \([0-9]*\).*/\1/p' out.txt)
  restarts=$(task_field "$job" 1 Restarts)
  [ "$restarts" = 1 ] || fail "requeue: region task 1 restarted '${restarts}' times, expected 1"
  grep -q "requeued" o2/slurm/region-1.log || fail "requeue: region-1.log does not say requeued: $(head -c 300 o2/slurm/region-1.log)"
  same_as_reference o2 "slurm bake with a requeued task"
  echo "slurm bake with region 1 requeued once: matches (${SECONDS} s into the test)"

  # A task that keeps failing: retried, then failed; the merge never runs.
  cat >broken-vox <<EOF
#!/bin/bash
case " \$* " in
  *" --region 2/$N "*) echo "broken-vox: region 2 always fails" >&2; exit 4 ;;
esac
exec "$vox" "\$@"
EOF
  chmod +x broken-vox
  # (No --pack-args: the default pack of the parts that do complete.)
  expect_exit 1 "$bake_slurm" --regions $N --out o3 --vox "$work/broken-vox" --retries 1 --wait -- "${SOURCE[@]}"
  expect_stderr "did not run"
  expect_stderr " 2 (FAILED)"
  job=$(sed -n 's/^regions job \([0-9]*\).*/\1/p' out.txt)
  merge=$(sed -n 's/^merge job \([0-9]*\).*/\1/p' out.txt)
  [ "$(task_field "$job" 2 Restarts)" = 1 ] || fail "permanent failure: region 2 was not retried once"
  [ "$(task_field "$job" 2 JobState)" = FAILED ] || fail "permanent failure: region 2 is $(task_field "$job" 2 JobState)"
  state=$(job_field "$merge" JobState)
  [ "$state" = CANCELLED ] || fail "permanent failure: the merge job is $state, expected CANCELLED"
  [ -e o3/world.vpk ] && fail "permanent failure: o3/world.vpk was written"
  [ -e o3/world.vdb ] && fail "permanent failure: o3/world.vdb was written"
  [ -e o3/part-2.vpk ] && fail "permanent failure: o3/part-2.vpk exists"
  [ -s o3/part-0.vpk ] && [ -s o3/part-1.vpk ] || fail "permanent failure: regions 0 and 1 left no page files: $(tail -n 3 o3/slurm/region-0.log)"
  [ -s o3/slurm/merge.log ] && fail "permanent failure: the merge job ran: $(head -c 300 o3/slurm/merge.log)"
  echo "slurm bake with region 2 failing for good: merge cancelled (${SECONDS} s into the test)"
  ;;

make)
  pick_source
  need_regions
  reference
  mk=(make -f "$bake_mk" REGIONS="$N" SOURCE="${SOURCE[*]}" PACK_ARGS="$PACK_ARGS" VOX="$vox")

  expect_exit 0 "${mk[@]}" -j2 OUT=m1
  same_as_reference m1 "make -j2"
  echo "make -j2 at N=$N: matches"
  expect_exit 0 "${mk[@]}" -j2 OUT=m1 --question  # up to date: nothing to do

  # Ctrl-C mid-run: SIGINT to make's process group, as a terminal sends it,
  # as soon as the first part's page file exists (its scene part is then
  # done, its page file may be mid-rename). Job control (set -m) gives make its own
  # process group and leaves SIGINT handled (a script's background jobs
  # otherwise ignore it).
  shopt -s nullglob
  set -m
  "${mk[@]}" -j2 OUT=m2 >make.out 2>make.err &
  pgid=$!
  set +m
  parts=()
  while kill -0 $pgid 2>/dev/null; do
    parts=(m2/part-*.vpk)
    [ ${#parts[@]} -gt 0 ] && break
  done
  kill -INT -- -$pgid 2>/dev/null
  wait $pgid
  rc=$?
  if [ -e m2/world.vpk ]; then
    fail "make: the bake finished before SIGINT reached it (rc $rc); the test bake is too small to interrupt"
  else
    [ $rc != 0 ] || fail "make: exit 0 after SIGINT"
    tmps=(m2/.*.tmp-*)
    [ ${#tmps[@]} = 0 ] || fail "make: temporaries left after SIGINT: ${tmps[*]}"
    # Every part present is whole: it opens and checks out.
    kept=()
    for p in m2/part-*.vdb; do
      expect_exit 0 "$vox" info "$p"
      kept+=("$p:$(stat -c %.9Y "$p")")
    done
    for p in m2/part-*.vpk; do
      expect_exit 0 "$vox" pack-chunks --verify "$p"
      kept+=("$p:$(stat -c %.9Y "$p")")
    done
    echo "after SIGINT: ${#kept[@]} part files kept (rc $rc)"
    [ ${#kept[@]} -lt $((2 * N)) ] || echo "note: every part was done when SIGINT came; only the merge was interrupted"
    [ ${#kept[@]} -gt 0 ] || fail "make: no part survived SIGINT, so resuming is not tested"
    expect_exit 0 "${mk[@]}" -j2 OUT=m2
    for k in "${kept[@]}"; do
      p=${k%%:*}
      [ "$p:$(stat -c %.9Y "$p")" = "$k" ] || fail "make rerun: $p was rebaked (it was whole)"
    done
    same_as_reference m2 "make -j2 after SIGINT and a rerun"
    echo "make -j2 interrupted, then rerun: matches"
  fi
  ;;
*) echo "unknown group $group" >&2; exit 2 ;;
esac

[ $failures = 0 ] || { echo "$failures failure(s)" >&2; exit 1; }
echo "slurm/make $group: ok"
