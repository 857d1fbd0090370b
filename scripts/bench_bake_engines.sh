#!/usr/bin/env bash
# What running a bake's regions under make or Slurm costs next to one process
# (docs/scale.md, "Running on Slurm and make"): one hyperfine run times
#   single  vox voxelize SOURCE -o w.vdb && vox pack-chunks w.vdb -o w.vpk
#   make    make -f scripts/bake.mk -j2 REGIONS=N (parts, vox merge, pack-chunks --merge)
#   slurm   scripts/bake-slurm.sh --regions N --wait on a one-node cluster on
#           localhost (tests/slurm/slurm_cluster.sh; root, slurm-wlm and munge)
# and checks that both merged page files equal the single-process one.
# Prints hyperfine's markdown table on stdout.
#
# Usage: scripts/bench_bake_engines.sh
# Env: BUILD_DIR (default build), REGIONS (default 3), RUNS (default 3),
#      SOURCE (voxelize arguments, default 'demo:hamlet --res 256').
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
vox=$root/${BUILD_DIR:-build}/bin/vox
regions=${REGIONS:-3}
runs=${RUNS:-3}
source=${SOURCE:-demo:hamlet --res 256}
command -v hyperfine >/dev/null || { echo "bench_bake_engines.sh: needs hyperfine" >&2; exit 4; }
[ -x "$vox" ] || { echo "bench_bake_engines.sh: build vox first ($vox)" >&2; exit 4; }
# shellcheck source=tests/slurm/slurm_cluster.sh disable=SC1091
. "$root/tests/slurm/slurm_cluster.sh"
if why=$(slurm_cluster_missing); then echo "bench_bake_engines.sh: $why" >&2; exit 4; fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
start_slurm_cluster || exit 4

# shellcheck disable=SC2086  # SOURCE is shell words
hyperfine --runs "$runs" --export-markdown table.md --style basic \
  --command-name single "rm -f w.vdb w.vpk; $vox voxelize $source -o w.vdb -q && $vox pack-chunks w.vdb -o w.vpk -q" \
  --command-name "make -j2, N=$regions" \
    "rm -rf m; make -s -f $root/scripts/bake.mk -j2 OUT=m REGIONS=$regions VOX=$vox SOURCE='$source' >/dev/null" \
  --command-name "slurm, N=$regions" \
    "rm -rf s; $root/scripts/bake-slurm.sh --regions $regions --out s --vox $vox --wait -- $source >/dev/null" >&2
for merged in m/world.vpk s/world.vpk; do
  cmp w.vpk $merged || { echo "bench_bake_engines.sh: $merged differs from the single-process page file" >&2; exit 1; }
done
# sbatch --wait polls the job after 2, 8, then every 32 s, so the time above
# is rounded up to 2, 10, 42, 74... s. Slurm's own clock (1 s steps) tells
# when the bake really ended: one more bake, from the regions' submission to
# the merge's end.
# shellcheck disable=SC2086
"$root/scripts/bake-slurm.sh" --regions "$regions" --out s2 --vox "$vox" --wait -- $source >ids.txt
region_job=$(sed -n 's/^regions job \([0-9]*\).*/\1/p' ids.txt)
merge_job=$(sed -n 's/^merge job \([0-9]*\).*/\1/p' ids.txt)
field() { scontrol show job -o "$1" | head -n 1 | sed -n "s/.* $2=\([^ ]*\).*/\1/p"; }
submitted=$(date -d "$(field "$region_job" SubmitTime)" +%s)
ended=$(date -d "$(field "$merge_job" EndTime)" +%s)
echo "SOURCE='$source', N=$regions, $(nproc) cores, hyperfine --runs $runs; merged page files equal the single one (cmp)"
echo
cat table.md
echo
echo "Slurm's clock, one more bake: regions submitted $(field "$region_job" SubmitTime)," \
  "merge ended $(field "$merge_job" EndTime): $((ended - submitted)) s"
