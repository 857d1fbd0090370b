#!/usr/bin/env bash
# Growth tables (docs/growth.md): how each subcommand's CPU time and peak
# memory grow with the scene, so a user can predict a bake. Every command runs
# once per resolution under /usr/bin/time (CPU = user + system, peak = max
# RSS) on two scenes per resolution: the demo hamlet at RES^3 (solid: its
# occupied voxels grow with the volume, as RES^3) and, when ../shared/data is
# there, the Stanford bunny's surface (its voxels grow as RES^2, so a stage
# whose cost follows the volume stands out). Each table gives the CPU time per
# occupied voxel and the growth exponent between consecutive rows:
#     exponent = log(CPU ratio) / log(occupied-voxel ratio)
# 1 means the cost follows the occupied voxels; on the bunny's surface a
# stage that follows the volume shows about 1.5.
# Usage: scripts/growth.sh [VOX] [DATA_DIR]     -> Markdown on stdout
# Env: RESOLUTIONS (default "128 256 512 1024"), THREADS (default 2).
set -u
vox=$(realpath "${1:-build/bin/vox}")
data=$(realpath "${2:-../shared/data}" 2>/dev/null || echo /nonexistent)
resolutions=${RESOLUTIONS:-128 256 512 1024}
threads=${THREADS:-2}
[ -x "$vox" ] || { echo "growth.sh: build vox first ($vox)" >&2; exit 4; }
command -v python3 >/dev/null || { echo "growth.sh: needs python3" >&2; exit 4; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 4
bunny=$data/common-3d-test-models/stanford-bunny.obj

# run LABEL RES SCENE ARGS...: one measurement appended to rows.tsv as
#   label, res, occupied voxels of SCENE, CPU s, wall s, peak KiB
run() {
  local label=$1 res=$2 scene=$3
  shift 3
  local extra=(--threads "$threads" -q)
  [ "$1" = info ] && extra=()  # info is serial and prints only what it is asked
  if ! /usr/bin/time -f '%U %S %e %M' -o t.txt "$vox" "$@" "${extra[@]}" >/dev/null 2>err.txt; then
    echo "growth.sh: vox $* failed: $(head -c 300 err.txt)" >&2
    return
  fi
  local occ
  occ=$("$vox" info "$scene" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["occupied"])')
  read -r user sys wall rss <t.txt
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$label" "$res" "$occ" "$(python3 -c "print($user + $sys)")" "$wall" "$rss" >>rows.tsv
}

: >rows.tsv
for r in $resolutions; do
  echo "growth.sh: res $r" >&2
  run "voxelize demo:hamlet" "$r" h$r.vdb voxelize demo:hamlet --res "$r" -o h$r.vdb
  if [ -f "$bunny" ]; then
    run "voxelize bunny (surface)" "$r" b$r.vdb voxelize "$bunny" --res "$r" -o b$r.vdb
    run "voxelize bunny --fill solid" "$r" bs$r.vdb voxelize "$bunny" --res "$r" --fill solid -o bs$r.vdb
  fi
  for scene in h b; do
    [ -f $scene$r.vdb ] || continue
    name=hamlet
    [ $scene = b ] && name="bunny surface"
    s=$scene$r
    run "info ($name)" "$r" $s.vdb info $s.vdb
    run "diff, same scene ($name)" "$r" $s.vdb diff $s.vdb $s.vdb
    run "mip ($name)" "$r" $s.vdb mip $s.vdb -o m$s.vdb
    run "pack-chunks --mips ($name)" "$r" $s.vdb pack-chunks m$s.vdb -o p$s.vpk --mips
    run "build-atlas --summary ($name)" "$r" $s.vdb build-atlas $s.vdb -o atlas$s --summary
    run "build-atlas --occupancy ($name)" "$r" $s.vdb build-atlas $s.vdb -o occ$s --occupancy
    run "render-canonical 1024x1024 iso ($name)" "$r" $s.vdb render-canonical $s.vdb -o iso$s.png --view iso --size 1024x1024
    run "render-canonical 8 views, depth+class ($name)" "$r" $s.vdb render-canonical $s.vdb -o o$s.png --orbit 8 \
      --size 512x512 --mode depth,class
    python3 - "$s" <<'PY'
import json, sys
s = sys.argv[1]
json.dump({'views': [{'depth': 'o%s_%03d.depth.exr' % (s, i), 'label': 'o%s_%03d.class.png' % (s, i)} for i in range(8)]},
          open('views%s.json' % s, 'w'))
PY
    run "fuse 8 views of 512x512 ($name)" "$r" f$s.vdb fuse views$s.json -o f$s.vdb
    run "export .glb, culled ($name)" "$r" $s.vdb export $s.vdb -o $s.glb
    run "export .glb --greedy ($name)" "$r" $s.vdb export $s.vdb -o g$s.glb --greedy
    rm -rf atlas$s occ$s ./*.glb ./*.exr ./*.png m$s.vdb p$s.vpk f$s.vdb
  done
  rm -f bs$r.vdb
done

python3 - "$(cut -d' ' -f1-3 /proc/loadavg)" "$threads" <<'PY'
import math, sys
from collections import OrderedDict
load, threads = sys.argv[1], sys.argv[2]
rows = OrderedDict()
for line in open('rows.tsv'):
    label, res, occ, cpu, wall, rss = line.rstrip('\n').split('\t')
    rows.setdefault(label, []).append((int(res), int(occ), float(cpu), float(wall), int(rss)))
print(f"`--threads {threads}`; load average at the end: {load}\n")
for label, rs in rows.items():
    print(f"#### `vox {label}`\n")
    print("| res | occupied voxels | CPU [s] | wall [s] | peak [MiB] | CPU ns / voxel | exponent |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    prev = None
    for res, occ, cpu, wall, rss in rs:
        exp = ""
        if prev and occ != prev[1] and prev[2] > 0.05 and cpu > 0:
            exp = f"{math.log(cpu / prev[2]) / math.log(occ / prev[1]):.2f}"
        print(f"| {res} | {occ:,} | {cpu:.2f} | {wall:.2f} | {rss / 1024:,.0f} | {cpu * 1e9 / max(occ, 1):.0f} | {exp} |")
        prev = (res, occ, cpu)
    print()
PY
