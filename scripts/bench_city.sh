#!/bin/sh
# Measures `vox voxelize demo:city` (docs/city.md): per extent, the voxels
# produced, the generate and write phases (--report), wall and CPU time and
# the peak resident memory (/usr/bin/time) against the memory guard's
# estimate; then one hyperfine run with the 1024^2 city at two heights
# (16x the volume, the same voxels) and at 2048^2 (4x the voxels), so the
# ratios come from one run; then boxes of one city against the voxels they
# produce (vox_bench_city_boxes); last, what the guard says of a
# 16384 x 1024 x 16384 city. Nice'd; --threads 2.
# Usage: scripts/bench_city.sh [BUILD_DIR] [EXTENT...]  -> Markdown on stdout
#        (default extents: 1024,256,1024 2048,256,2048 4096,512,4096)
set -eu
cd "$(dirname "$0")/.."
BUILD=$(pwd)/${1:-build}
[ $# -gt 0 ] && shift
VOX=$BUILD/bin/vox
[ $# -gt 0 ] || set -- 1024,256,1024 2048,256,2048 4096,512,4096
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

echo "| extent | occupied voxels | blocks | file | generate [s] | ns / voxel (generate) | write [s] | wall [s] | CPU user+sys [s] | peak RSS | estimate | estimate / peak |"
echo "|:---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for e in "$@"; do
  nice /usr/bin/time -v "$VOX" voxelize demo:city --extent "$e" -o city.vdb --threads 2 --report r.json -q 2>time.txt
  python3 - "$e" r.json time.txt <<'PY'
import json, re, sys
e, report, timing = sys.argv[1], json.load(open(sys.argv[2])), open(sys.argv[3]).read()
c = report["counts"]
ph = {p["name"]: p["seconds"] for p in report["phases"]}
field = lambda name: re.search(re.escape(name) + r":\s*(\S+)", timing).group(1)
wall = field("Elapsed (wall clock) time (h:mm:ss or m:ss)")
parts = [float(x) for x in wall.split(":")]
wall_s = sum(p * 60 ** i for i, p in enumerate(reversed(parts)))
cpu = float(field("User time (seconds)")) + float(field("System time (seconds)"))
peak = int(field("Maximum resident set size (kbytes)")) * 1024
est = report["memory"]["estimate_bytes"]
gib = lambda b: "%.2f GiB" % (b / 2**30) if b >= 2**30 else "%.0f MiB" % (b / 2**20)
print("| %s | %d | %d | %s | %.2f | %.0f | %.2f | %.2f | %.2f | %s | %s | %.2f |" % (
    e.replace(",", " x "), c["occupied_voxels"], c["blocks"], gib(c["file_bytes"]), ph["generate"],
    ph["generate"] * 1e9 / max(1, c["occupied_voxels"]), ph["write"], wall_s, cpu, gib(peak), gib(est), est / peak))
PY
done
echo

hyperfine -N --warmup 1 --runs "${RUNS:-5}" --export-json h.json \
  -n "1024 x 256 x 1024" "nice $VOX voxelize demo:city --extent 1024,256,1024 -o a.vdb --threads 2 -q" \
  -n "1024 x 4096 x 1024 (16x the volume)" "nice $VOX voxelize demo:city --extent 1024,4096,1024 -o b.vdb --threads 2 -q" \
  -n "2048 x 256 x 2048" "nice $VOX voxelize demo:city --extent 2048,256,2048 -o c.vdb --threads 2 -q" >/dev/null
occ() { "$VOX" info "$1" --json | python3 -c "import json,sys; print(json.load(sys.stdin)['occupied'])"; }
python3 - h.json "$(occ a.vdb)" "$(occ b.vdb)" "$(occ c.vdb)" <<'PY'
import json, statistics, sys
rs = json.load(open(sys.argv[1]))["results"]
occ = [int(x) for x in sys.argv[2:5]]
cpu = lambda r: statistics.mean(u + s for u, s in zip(r["user"], r["system"])) if isinstance(r.get("user"), list) else r["user"] + r["system"]
print("| vox voxelize demo:city (whole run, --threads 2) | occupied voxels | mean wall [s] | CPU user+sys [s] | CPU ns / voxel | wall / first row |")
print("|:---|---:|---:|---:|---:|---:|")
for r, n in zip(rs, occ):
    print("| %s | %d | %.3f ± %.3f | %.3f | %.0f | %.2f |" % (r["command"], n, r["mean"], r["stddev"], cpu(r), cpu(r) * 1e9 / n,
                                                       r["mean"] / rs[0]["mean"]))
PY
echo

nice "$BUILD/bin/vox_bench_city_boxes" 2048,512,2048 2
echo

echo '```'
"$VOX" voxelize demo:city --extent 16384,1024,16384 -o big.vdb 2>&1 | fold -s -w 100 || true
echo '```'
