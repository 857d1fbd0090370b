#!/usr/bin/env bash
# `vox pack-chunks` of two builds (BEFORE and AFTER) against `nanovdb_convert -f`
# (Debian libnanovdb-tools) on the same .vdb, all three in ONE hyperfine run
# per scene, so every ratio comes from one run. First checks that both builds
# write the same .vpk bytes (every layout, --chunk 8 and 16, --threads 1 and
# 2, and --mips, all at --align 4096, which every build has: the default
# alignment became `auto` on 2026-11-29), then times each build's default, then prints the `read`/`pack`/`write` phases of
# AFTER's --report (best of 3).
# Scenes: `vox voxelize demo:hamlet --res 256` and MESH (default: the Stanford
# bunny of ../shared/data) at --res 1024 (surface), made by AFTER.
#
# Usage: scripts/bench_pack_nanovdb.sh BEFORE_VOX AFTER_VOX [MESH]
# Env: THREADS (default 2), RUNS (default 10). Prints markdown on stdout.
set -euo pipefail
before=$(realpath "$1") after=$(realpath "$2")
cd "$(dirname "$0")/.."
scripts=$(pwd)/scripts
mesh=${3:-$(pwd)/../shared/data/common-3d-test-models/stanford-bunny.obj}
threads=${THREADS:-2}
runs=${RUNS:-10}
for tool in hyperfine python3 nanovdb_convert; do
  command -v $tool >/dev/null || { echo "bench_pack_nanovdb.sh: needs $tool" >&2; exit 4; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
. "$scripts/bench_scenes.sh"

echo "# pack-chunks against nanovdb_convert ($(nproc) cores, --threads $threads, $runs runs)"
echo
for s in $scenes; do
  same=0
  for args in "--layout bricks" "--layout svo" "--layout columns" "--chunk 8" "--mips" "--mips --chunk 8 --layout svo"; do
    for t in 1 2; do
      # shellcheck disable=SC2086
      "$before" pack-chunks $s.vdb -o b.vpk $args --align 4096 --threads $t --quiet 2>/dev/null || continue
      # shellcheck disable=SC2086
      "$after" pack-chunks $s.vdb -o a.vpk $args --align 4096 --threads $t --quiet
      cmp -s b.vpk a.vpk || { echo "bench_pack_nanovdb.sh: $s $args --threads $t: the builds differ" >&2; exit 1; }
      same=$((same + 1))
    done
  done
  load0=$(cut -d' ' -f1-3 /proc/loadavg)
  hyperfine -N -w 2 -r "$runs" --export-json $s.json \
    -n "before: vox pack-chunks" "$before pack-chunks $s.vdb -o b.vpk --threads $threads --quiet" \
    -n "after: vox pack-chunks" "$after pack-chunks $s.vdb -o a.vpk --threads $threads --quiet" \
    -n "nanovdb_convert -f" "nanovdb_convert -f $s.vdb n.nvdb" >&2
  load1=$(cut -d' ' -f1-3 /proc/loadavg)
  for i in 1 2 3; do "$after" pack-chunks $s.vdb -o a.vpk --threads "$threads" --quiet --report r$i.json; done
  echo "## $s ($(stat -c %s $s.vdb) bytes; load average $load0 before the run, $load1 after; $same byte comparisons passed)"
  echo
  python3 - "$s" <<'PY'
import json, sys
s = sys.argv[1]
res = {r["command"]: r for r in json.load(open(f"{s}.json"))["results"]}
n = res["nanovdb_convert -f"]
print("| command | mean ± sd (s) | user+sys (s) | / nanovdb_convert (wall) | / nanovdb_convert (CPU) |")
print("| --- | ---: | ---: | ---: | ---: |")
for c in ["before: vox pack-chunks", "after: vox pack-chunks", "nanovdb_convert -f"]:
    r = res[c]
    cpu, ncpu = r["user"] + r["system"], n["user"] + n["system"]
    print(f"| `{c}` | {r['mean']:.3f} ± {r['stddev']:.3f} | {cpu:.3f} | **{r['mean'] / n['mean']:.2f}x** | {cpu / ncpu:.2f}x |")
b, a = res["before: vox pack-chunks"], res["after: vox pack-chunks"]
print()
print(f"after / before: {a['mean'] / b['mean']:.2f}x wall, "
      f"{(a['user'] + a['system']) / (b['user'] + b['system']):.2f}x CPU")
best = {}
for i in (1, 2, 3):
    d = json.load(open(f"r{i}.json"))
    for p in d["phases"]:
        best[p["name"]] = min(best.get(p["name"], 1e9), p["seconds"])
    best["total (report)"] = min(best.get("total (report)", 1e9), d["total_seconds"])
print()
print("after, `--report` phases (best of 3, s): " + ", ".join(f"{k} {v:.3f}" for k, v in best.items()))
print()
PY
done
