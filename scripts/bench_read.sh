#!/usr/bin/env bash
# Reading scene files: `vox info`, `vox pack-chunks`, `vox mip` and
# `vox export -o x.glb` of two builds (BEFORE and AFTER) on the same scenes,
# one hyperfine run per scene so every before/after ratio comes from one run,
# then the `read` phase of each command's --report (best of 3 per build), and,
# when nanovdb_convert (Debian libnanovdb-tools) is installed, OpenVDB to
# NanoVDB conversion of the same file in the same hyperfine run.
# Scenes: `vox voxelize demo:hamlet --res 256` and MESH (default: the Stanford
# bunny of ../shared/data) at --res 1024 (surface), made by AFTER.
#
# Usage: scripts/bench_read.sh BEFORE_VOX AFTER_VOX [MESH]
# Env: THREADS (default 2), RUNS (default 5). Prints markdown on stdout.
set -euo pipefail
before=$(realpath "$1") after=$(realpath "$2")
cd "$(dirname "$0")/.."
scripts=$(pwd)/scripts
mesh=${3:-$(pwd)/../shared/data/common-3d-test-models/stanford-bunny.obj}
threads=${THREADS:-2}
runs=${RUNS:-5}
for tool in hyperfine python3; do
  command -v $tool >/dev/null || { echo "bench_read.sh: needs $tool" >&2; exit 4; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
. "$scripts/bench_scenes.sh"
nano=""
command -v nanovdb_convert >/dev/null && nano=1

echo "# Reading scenes: before and after ($(nproc) cores, --threads $threads, $runs runs)"
echo
for s in $scenes; do
  levels=$("$after" info --json $s.vdb | python3 -c "import json,sys,math; d=json.load(sys.stdin); print(math.ceil(math.log2(max(d['dims']))))")
  args=()
  for side in before after; do
    v=${!side}
    args+=(-n "$side: vox info" "$v info $s.vdb")
    args+=(-n "$side: vox pack-chunks" "$v pack-chunks $s.vdb -o p_$side.vpk --threads $threads --quiet")
    args+=(-n "$side: vox mip" "$v mip $s.vdb -o m_$side.vdb --levels $levels --threads $threads --quiet")
    args+=(-n "$side: vox export -o x.glb" "$v export $s.vdb -o x_$side.glb --threads $threads --quiet")
  done
  [ -n "$nano" ] && args+=(-n "nanovdb_convert" "nanovdb_convert -f $s.vdb n.nvdb")
  load0=$(cut -d' ' -f1-3 /proc/loadavg)
  hyperfine -N -w 1 -r "$runs" --export-json $s.json "${args[@]}" >&2
  load1=$(cut -d' ' -f1-3 /proc/loadavg)
  for side in before after; do
    v=${!side}
    for i in 1 2 3; do
      "$v" pack-chunks $s.vdb -o p.vpk --threads "$threads" --quiet --report pack_${side}_$i.json
      "$v" mip $s.vdb -o m.vdb --levels "$levels" --threads "$threads" --quiet --report mip_${side}_$i.json
      "$v" export $s.vdb -o x.glb --threads "$threads" --quiet --report export_${side}_$i.json
    done
  done
  echo "## $s ($(stat -c %s $s.vdb) bytes; load average $load0 before the run, $load1 after)"
  echo
  python3 - "$s" <<'PY'
import json, sys
s = sys.argv[1]
res = {r["command"]: r for r in json.load(open(f"{s}.json"))["results"]}
print("| command | before: mean ± sd (s) | before: user+sys (s) | after: mean ± sd (s) | after: user+sys (s) | after / before |")
print("| --- | ---: | ---: | ---: | ---: | ---: |")
for c in ["vox info", "vox pack-chunks", "vox mip", "vox export -o x.glb"]:
    b, a = res["before: " + c], res["after: " + c]
    print(f"| `{c}` | {b['mean']:.3f} ± {b['stddev']:.3f} | {b['user'] + b['system']:.3f} | "
          f"{a['mean']:.3f} ± {a['stddev']:.3f} | {a['user'] + a['system']:.3f} | **{a['mean'] / b['mean']:.2f}x** |")
if "nanovdb_convert" in res:
    n = res["nanovdb_convert"]
    p = res["after: vox pack-chunks"]
    print(f"| `nanovdb_convert -f` | | | {n['mean']:.3f} ± {n['stddev']:.3f} | {n['user'] + n['system']:.3f} | "
          f"pack-chunks (after) / nanovdb_convert: **{p['mean'] / n['mean']:.2f}x** |")
print()
print("`read` phase of `--report` (best of 3, seconds) and its share of the command's total:")
print()
print("| command | before: read | before: share | after: read | after: share |")
print("| --- | ---: | ---: | ---: | ---: |")
for c in ["pack", "mip", "export"]:
    row = []
    for side in ["before", "after"]:
        reps = []
        for i in (1, 2, 3):
            phases = {}
            for ph in json.load(open(f"{c}_{side}_{i}.json"))["phases"]:
                phases[ph["name"]] = phases.get(ph["name"], 0) + ph["seconds"]
            reps.append(phases)
        best = min(reps, key=lambda r: r["read"])
        row += [f"{best['read']:.3f}", f"{100 * best['read'] / sum(best.values()):.0f}%"]
    print(f"| `vox {c}` | " + " | ".join(row) + " |")
print()
PY
done
