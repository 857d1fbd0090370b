#!/usr/bin/env bash
# Bakes a scene on a Slurm cluster: one array task per region, then one merge
# job that runs only when every region task succeeded (docs/scale.md, "Running
# on Slurm and make").
#
#   scripts/bake-slurm.sh --regions N --out DIR [options] -- VOXELIZE-ARGS...
#
# Array task I (0 <= I < N) runs
#   vox voxelize VOXELIZE-ARGS --region I/N -o DIR/part-I.vdb
#   vox pack-chunks DIR/part-I.vdb -o DIR/part-I.vpk PACK-ARGS
# and the merge job (sbatch --dependency=afterok:<array job>) runs
#   vox merge DIR/part-0.vdb ... -o DIR/world.vdb
#   vox pack-chunks --merge DIR/part-0.vpk ... -o DIR/world.vpk
# DIR must be visible at the same path from every node (a shared filesystem).
# The batch scripts and the jobs' logs go to DIR/slurm/.
#
# Options:
#   --regions N        number of regions (1 <= N); required
#   --out DIR          where the parts and the world go; required
#   --vox PATH         the vox binary (default: build/bin/vox next to this
#                      script's directory, else vox on PATH)
#   --pack-args 'A'    arguments of every pack-chunks run, e.g. '--chunk 16'
#                      (split on spaces); the merged page file equals packing
#                      the single-process bake with the same arguments
#   --partition P      sbatch --partition for every job
#   --mem M            sbatch --mem for every job (e.g. 4G)
#   --time T           sbatch --time for every job (e.g. 1:00:00)
#   --max-parallel K   at most K region tasks at once (--array=0-(N-1)%K)
#   --retries R        a region task that fails with an exit code other than 2
#                      (usage) or 3 (bad input) requeues itself with scontrol
#                      requeue, at most R times (default 2); Slurm itself
#                      requeues tasks whose node fails (sbatch --requeue)
#   --sbatch-args 'A'  more sbatch arguments for every job (split on spaces),
#                      e.g. '--account=proj --qos=long'
#   --wait             wait for the merge job (sbatch --wait) and exit with its
#                      status: 0 when it completed, its exit code when it
#                      failed, 1 when it never ran (a region task failed)
#
# Prints the two job ids ("regions job ID", "merge job ID") on stdout.
# Exit codes: 0 submitted (or, with --wait, merged), 1 the merge failed or
# never ran, 2 usage (bad option, bad N, no sbatch, no vox), 4 DIR cannot be
# created or sbatch refused a job.
set -u

usage() {
  sed -n '2,/^set -u/{/^#/s/^# \{0,1\}//p}' "$0" >&2
}
die() { echo "bake-slurm: $2" >&2; exit "$1"; }

regions="" out="" vox="" pack_args="" partition="" mem="" time_limit=""
max_parallel="" retries=2 sbatch_extra="" wait=0
while [ $# -gt 0 ]; do
  case $1 in
    --regions) [ $# -ge 2 ] || die 2 "--regions needs a value"; regions=$2; shift 2 ;;
    --out) [ $# -ge 2 ] || die 2 "--out needs a value"; out=$2; shift 2 ;;
    --vox) [ $# -ge 2 ] || die 2 "--vox needs a value"; vox=$2; shift 2 ;;
    --pack-args) [ $# -ge 2 ] || die 2 "--pack-args needs a value"; pack_args=$2; shift 2 ;;
    --partition) [ $# -ge 2 ] || die 2 "--partition needs a value"; partition=$2; shift 2 ;;
    --mem) [ $# -ge 2 ] || die 2 "--mem needs a value"; mem=$2; shift 2 ;;
    --time) [ $# -ge 2 ] || die 2 "--time needs a value"; time_limit=$2; shift 2 ;;
    --max-parallel) [ $# -ge 2 ] || die 2 "--max-parallel needs a value"; max_parallel=$2; shift 2 ;;
    --retries) [ $# -ge 2 ] || die 2 "--retries needs a value"; retries=$2; shift 2 ;;
    --sbatch-args) [ $# -ge 2 ] || die 2 "--sbatch-args needs a value"; sbatch_extra=$2; shift 2 ;;
    --wait) wait=1; shift ;;
    -h|--help) usage; exit 0 ;;
    --) shift; break ;;
    *) die 2 "unknown option '$1' (the voxelize arguments come after --; see --help)" ;;
  esac
done
voxelize_args=("$@")

is_count() { [[ $1 =~ ^[0-9]+$ ]] && [ "$((10#$1))" -ge "$2" ]; }
[ -n "$regions" ] || die 2 "--regions N is required (the number of regions, 1 or more)"
is_count "$regions" 1 || die 2 "--regions '$regions' is not a whole number of regions >= 1"
regions=$((10#$regions))
[ -n "$out" ] || die 2 "--out DIR is required (where the parts and the world go)"
is_count "$retries" 0 || die 2 "--retries '$retries' is not a whole number >= 0"
[ -z "$max_parallel" ] || is_count "$max_parallel" 1 ||
  die 2 "--max-parallel '$max_parallel' is not a whole number >= 1"
[ ${#voxelize_args[@]} -gt 0 ] ||
  die 2 "no voxelize arguments: give the source after --, e.g. -- demo:city --extent 1024,256,1024"
for a in "${voxelize_args[@]}"; do
  case $a in
    --region|--region=*|--region-box|--region-box=*|-o|--output|--output=*)
      die 2 "'$a' in the voxelize arguments: bake-slurm.sh sets the region and the output itself" ;;
  esac
done
command -v sbatch >/dev/null 2>&1 ||
  die 2 "sbatch not found on PATH: run this on a Slurm submit host (or use scripts/bake.mk with make -j)"

if [ -z "$vox" ]; then
  here=$(cd "$(dirname "$0")" && pwd)
  if [ -x "$here/../build/bin/vox" ]; then vox=$here/../build/bin/vox
  else vox=$(command -v vox) || die 2 "no vox: not at $here/../build/bin/vox nor on PATH (give --vox PATH)"
  fi
fi
[ -x "$vox" ] || die 2 "--vox '$vox' is not an executable file"
vox=$(cd "$(dirname "$vox")" && pwd)/$(basename "$vox")

mkdir -p "$out/slurm" 2>/dev/null || die 4 "cannot create $out/slurm (check the path and its permissions)"
out=$(cd "$out" && pwd)
last=$((regions - 1))

# Arguments for every job.
common=(--requeue)
[ -z "$partition" ] || common+=(--partition="$partition")
[ -z "$mem" ] || common+=(--mem="$mem")
[ -z "$time_limit" ] || common+=(--time="$time_limit")
# shellcheck disable=SC2206  # split on spaces, as documented
[ -z "$sbatch_extra" ] || common+=($sbatch_extra)

# The batch scripts hold their arguments quoted (printf %q), so any path or
# argument survives; Slurm copies a batch script when it is submitted.
q() { printf ' %q' "$@"; }
# shellcheck disable=SC2206
pack=($pack_args)
# shellcheck disable=SC2016  # the single-quoted lines are the job's own code
{
  echo '#!/usr/bin/env bash'
  echo "# Region task of scripts/bake-slurm.sh: bakes region \$SLURM_ARRAY_TASK_ID of $regions."
  echo 'set -u'
  echo 'i=$SLURM_ARRAY_TASK_ID'
  echo "vox=$(printf %q "$vox") out=$(printf %q "$out")"
  echo "echo \"bake-slurm: region \$i/$regions on \$(hostname), attempt \$((\${SLURM_RESTART_COUNT:-0} + 1))\""
  echo "\"\$vox\" voxelize$(q "${voxelize_args[@]}") --region \"\$i/$regions\" -o \"\$out/part-\$i.vdb\" &&"
  echo "  \"\$vox\" pack-chunks \"\$out/part-\$i.vdb\" -o \"\$out/part-\$i.vpk\"$(q "${pack[@]}")"
  echo 'rc=$?'
  echo '[ $rc = 0 ] && exit 0'
  echo '# 2 (usage) and 3 (bad input) fail again on any node: final. Anything else'
  echo '# (4: I/O or resources, a signal) is worth another attempt, which Slurm'
  echo '# schedules: the task requeues itself (SLURM_RESTART_COUNT counts them).'
  echo "if [ \$rc != 2 ] && [ \$rc != 3 ] && [ \"\${SLURM_RESTART_COUNT:-0}\" -lt $retries ]; then"
  echo "  echo \"bake-slurm: region \$i failed (exit \$rc); requeued\" >&2"
  echo '  if scontrol requeue "${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}"; then'
  echo '    sleep 300  # the requeue ends this attempt; it never reaches the exit below'
  echo '  fi'
  echo 'fi'
  echo "echo \"bake-slurm: region \$i failed (exit \$rc), not retried: the merge will not run\" >&2"
  echo 'exit $rc'
} >"$out/slurm/region.sbatch"

parts_vdb=() parts_vpk=()
for ((i = 0; i < regions; i++)); do
  parts_vdb+=("$out/part-$i.vdb"); parts_vpk+=("$out/part-$i.vpk")
done
{
  echo '#!/usr/bin/env bash'
  echo "# Merge job of scripts/bake-slurm.sh: joins the $regions parts."
  echo 'set -u'
  echo "vox=$(printf %q "$vox")"
  echo "\"\$vox\" merge$(q "${parts_vdb[@]}") -o $(printf %q "$out/world.vdb") &&"
  echo "  \"\$vox\" pack-chunks --merge$(q "${parts_vpk[@]}") -o $(printf %q "$out/world.vpk")"
} >"$out/slurm/merge.sbatch"

array="0-$last"
[ -z "$max_parallel" ] || array="$array%$max_parallel"
region_job=$(sbatch --parsable "${common[@]}" --job-name=vox-region --array="$array" \
  --open-mode=append --output="$out/slurm/region-%a.log" "$out/slurm/region.sbatch") ||
  die 4 "sbatch refused the region array (see its message above)"
region_job=${region_job%%;*}  # --parsable prints "id;cluster" on multi-cluster setups
echo "regions job $region_job (array $array, parts in $out)"

merge_args=(--parsable "${common[@]}" --job-name=vox-merge --dependency="afterok:$region_job"
  --kill-on-invalid-dep=yes --open-mode=append --output="$out/slurm/merge.log")
if [ $wait = 0 ]; then
  merge_job=$(sbatch "${merge_args[@]}" "$out/slurm/merge.sbatch") ||
    die 4 "sbatch refused the merge job (see its message above); cancel the regions: scancel $region_job"
  merge_job=${merge_job%%;*}
  echo "merge job $merge_job (after every region task succeeded: $out/world.vdb, $out/world.vpk)"
  exit 0
fi

# sbatch --wait prints the id at once (--parsable flushes it), then exits with
# the job's exit code when it ends. A merge cancelled because a region failed
# also ends with 0 there, so its final state decides.
merge_job=""
{ read -r merge_job && merge_job=${merge_job%%;*} &&
    echo "merge job $merge_job (after every region task succeeded: $out/world.vdb, $out/world.vpk)"
  cat >/dev/null; } < <(sbatch --wait "${merge_args[@]}" "$out/slurm/merge.sbatch")
[ -n "$merge_job" ] || die 4 "sbatch refused the merge job; cancel the regions: scancel $region_job"
state=$(scontrol show job -o "$merge_job" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p')
exitcode=$(scontrol show job -o "$merge_job" 2>/dev/null | sed -n 's/.* ExitCode=\([0-9]*\):.*/\1/p')
case $state in
  COMPLETED) echo "bake-slurm: merged $out/world.vdb and $out/world.vpk"; exit 0 ;;
  FAILED) echo "bake-slurm: the merge job $merge_job failed (exit ${exitcode:-?}): $out/slurm/merge.log" >&2
    [ -n "$exitcode" ] && [ "$exitcode" != 0 ] && exit "$exitcode"; exit 1 ;;
  *) failed=$(scontrol show job -o "$region_job" 2>/dev/null |
      sed -n 's/.*ArrayTaskId=\([0-9]*\) .*JobState=\([A-Z_]*\).*/\1 \2/p' |
      awk '$2 != "COMPLETED" { printf " %s (%s)", $1, $2 }')
    echo "bake-slurm: the merge job $merge_job did not run (state ${state:-unknown}): region tasks" \
      "not completed:${failed:- unknown}; logs: $out/slurm/region-I.log" >&2
    exit 1 ;;
esac
