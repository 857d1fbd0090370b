#!/bin/sh
# `vox voxelize` against vdb_tool's mesh2ls on the same meshes, same machine,
# one run: a generated high-polygon mesh (a bumpy sphere of 100 k triangles,
# always) and the Stanford bunny (when ../shared/data is present). Per mesh:
# surface and solid fill at 256 and 512 in one hyperfine run with vdb_tool,
# peak memory from /usr/bin/time; then surface time and memory at 128..2048
# (cost grows with the surface, not the volume), and parse throughput (end to
# end per file, and a Google Benchmark over the parsers: bench/bench_parse.cpp).
# Usage: scripts/bench_voxelize.sh [BUILD_DIR] [MESH]   -> Markdown on stdout
#        scripts/bench_voxelize.sh [BUILD_DIR] [MESH] winding
#   the last: only the solid fill by the winding number on MESH (default the
#   bunny, open) against vdb_tool mesh2ls, 256 and 512, one hyperfine run each
#   (parity rule alongside), and peak memory at 512 (/usr/bin/time -v).
#        scripts/bench_voxelize.sh [BUILD_DIR] [MESH] against OLD_VOX
#   the last: this build's surface bake (votes, 2 threads) against another
#   build's vox (e.g. an older commit's) on MESH at 256, both in one hyperfine
#   run (10 runs, with user and system CPU), the scenes compared byte for
#   byte, and both peaks at 512 (/usr/bin/time -v).
set -eu
cd "$(dirname "$0")/.."
root=$(pwd)
VOX=$root/${1:-build}/bin/vox
BUNNY=${2:-$(pwd)/../shared/data/common-3d-test-models/stanford-bunny.obj}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

if [ "${3:-}" = against ]; then
  OLD=${4:?usage: bench_voxelize.sh BUILD_DIR MESH against OLD_VOX}
  [ -f "$BUNNY" ] || { echo "MESH $BUNNY not found"; exit 2; }
  echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
  hyperfine -N --warmup 2 --runs 10 --export-markdown ab.md --export-json ab.json \
    -n "old vox 256" "$OLD voxelize $BUNNY --res 256 -o a.vdb" \
    -n "new vox 256" "$VOX voxelize $BUNNY --res 256 -o b.vdb" >/dev/null
  echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
  cat ab.md
  python3 -c "
import json
for r in json.load(open('ab.json'))['results']:
    print(f\"{r['command']}: wall {r['mean']*1e3:.1f} ms, user {r['user']*1e3:.1f} ms, system {r['system']*1e3:.1f} ms\")"
  cmp -s a.vdb b.vdb && echo "scenes identical" || echo "scenes differ (byte compare)"
  for v in "$OLD" "$VOX"; do
    /usr/bin/time -v "$v" voxelize "$BUNNY" --res 512 -o m.vdb -q 2> mem.txt > /dev/null || true
    echo "peak RSS $(sed -n 's/.*Maximum resident set size (kbytes): //p' mem.txt) KB at 512: $v"
  done
  exit 0
fi

if [ "${3:-}" = winding ]; then
  [ -f "$BUNNY" ] || { echo "MESH $BUNNY not found"; exit 2; }
  echo "### solid fill by the winding number: $(basename "$BUNNY") ($(grep -c '^f ' "$BUNNY") triangles)"
  echo
  for n in 256 512; do
    runs=5; [ $n = 512 ] && runs=3
    hyperfine -N --warmup 1 --runs $runs --export-markdown "w$n.md" \
      -n "vox solid $n" "$VOX voxelize $BUNNY --res $n --fill solid -o wv.vdb -q --threads 2" \
      -n "vox solid parity $n" "$VOX voxelize $BUNNY --res $n --fill solid --solid-rule parity -o wp.vdb -q --threads 2" \
      -n "vdb_tool mesh2ls $n" "vdb_tool -read $BUNNY -mesh2ls d=$n -write wl.vdb" >/dev/null
    cat "w$n.md"
    echo
  done
  for c in "$VOX voxelize $BUNNY --res 512 --fill solid -o wv.vdb -q --threads 2" \
           "vdb_tool -read $BUNNY -mesh2ls d=512 -write wl.vdb"; do
    /usr/bin/time -v $c 2> mem.txt > /dev/null || true
    echo "peak RSS $(sed -n 's/.*Maximum resident set size (kbytes): //p' mem.txt) KB: $c" | sed "s|$VOX|vox|; s|$BUNNY|MESH|"
  done
  exit 0
fi

# A sphere of radius 1 with a ripple of 4% (so no face lies on a grid plane),
# 316 x 158 quads = 99 856 triangles, as OBJ.
python3 - > bumpy-sphere.obj <<'PY'
import math
S, R = 316, 158
out = []
for j in range(R + 1):
    th = math.pi * j / R
    for i in range(S):
        ph = 2 * math.pi * i / S
        r = 1 + 0.04 * math.sin(7 * th) * math.cos(5 * ph)
        out.append("v %.7f %.7f %.7f" % (r * math.sin(th) * math.cos(ph), r * math.cos(th), r * math.sin(th) * math.sin(ph)))
for j in range(R):
    for i in range(S):
        a, b = j * S + i + 1, j * S + (i + 1) % S + 1
        c, d = a + S, b + S
        out.append("f %d %d %d" % (a, c, b))
        out.append("f %d %d %d" % (b, c, d))
print("\n".join(out))
PY
meshes="$work/bumpy-sphere.obj"
[ -f "$BUNNY" ] && meshes="$meshes $BUNNY" || echo "(the bunny is absent: ../shared/data not found; generated mesh only)"

for MESH in $meshes; do
  echo "### $(basename "$MESH") ($(grep -c '^f ' "$MESH") triangles, $(du -k "$MESH" | cut -f1) KB)"
  echo
  for n in 256 512; do
    hyperfine -N --warmup 1 --runs 5 --export-markdown "t$n.md" \
      -n "vox surface $n" "$VOX voxelize $MESH --res $n --fill surface -o s.vdb -q --threads 2" \
      -n "vox solid $n" "$VOX voxelize $MESH --res $n --fill solid -o v.vdb -q --threads 2" \
      -n "vdb_tool mesh2ls $n" "vdb_tool -read $MESH -mesh2ls d=$n -write l.vdb" >/dev/null
    cat "t$n.md"
    echo
    for c in "$VOX voxelize $MESH --res $n --fill surface -o s.vdb -q --threads 2" \
             "$VOX voxelize $MESH --res $n --fill solid -o v.vdb -q --threads 2" \
             "vdb_tool -read $MESH -mesh2ls d=$n -write l.vdb"; do
      /usr/bin/time -f "%M" $c 2> mem.txt > /dev/null || true
      echo "peak RSS $(tail -1 mem.txt) KB: $c" | sed "s|$VOX|vox|; s|$MESH|MESH|"
    done
    echo
  done
done

# Growth with resolution, surface fill, last mesh of the list: one run each.
echo "| --res | surface voxels | wall [ms] | voxelize phase [ms] | peak RSS [MB] | file [MB] |"
echo "|---:|---:|---:|---:|---:|---:|"
for n in 128 256 512 1024 2048; do
  /usr/bin/time -f "%e %M" "$VOX" voxelize "$MESH" --res $n --fill surface -o g.vdb -q --threads 2 --report g.json 2> tm.txt
  python3 - "$n" <<'PY'
import json, os, sys
d = json.load(open('g.json')); ph = {p['name']: p['seconds'] for p in d['phases']}
wall, rss = open('tm.txt').read().split()[-2:]
print(f"| {sys.argv[1]} | {d['counts']['surface_voxels']} | {float(wall)*1000:.0f} | {ph['voxelize']*1000:.0f} | {int(rss)/1024:.1f} | {os.path.getsize('g.vdb')/1e6:.2f} |")
PY
done
echo

# Parse throughput on one core: bytes / parse phase.
for f in $meshes "$(dirname "$BUNNY")/../cgal-data/pig.stl"; do
  [ -f "$f" ] || continue
  "$VOX" voxelize "$f" --res 64 -o p.vdb -q --threads 1 --report p.json
  python3 -c "
import json,os,sys
d=json.load(open('p.json')); ph={p['name']:p['seconds'] for p in d['phases']}
b=os.path.getsize('$f'); print(f'parse {os.path.basename(\"$f\")}: {b/1e6:.2f} MB in {ph[\"parse\"]*1000:.1f} ms = {b/1e6/ph[\"parse\"]:.0f} MB/s')"
done

# The parsers alone, one core, from memory (Google Benchmark; builds build-bench).
echo
cmake -S "$root" -B "$root/build-bench" -DCMAKE_BUILD_TYPE=Release -DVOX_BUILD_BENCHMARKS=ON -DVOX_BUILD_TESTS=OFF >/dev/null
cmake --build "$root/build-bench" -j"$(nproc)" --target vox_bench_parse >/dev/null
echo '```'
"$root/build-bench/bin/vox_bench_parse" 2>/dev/null | grep -E "^(BM_|Benchmark|-)"
echo '```'
