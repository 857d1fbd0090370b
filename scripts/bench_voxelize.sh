#!/bin/sh
# `vox voxelize` against vdb_tool's mesh2ls on the same mesh, same machine, one
# hyperfine run: surface and solid fill at 256 and 512, peak memory from
# /usr/bin/time, and parse throughput from --report.
# Usage: scripts/bench_voxelize.sh [BUILD_DIR] [MESH]   -> Markdown on stdout
set -eu
cd "$(dirname "$0")/.."
VOX=$(pwd)/${1:-build}/bin/vox
MESH=${2:-$(pwd)/../shared/data/common-3d-test-models/stanford-bunny.obj}
[ -f "$MESH" ] || { echo "bench_voxelize.sh: $MESH is absent" >&2; exit 0; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
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
# Parse throughput on one core: bytes / parse phase (OBJ here; binary STL and PLY below if present).
for f in "$MESH" "$(dirname "$MESH")/../cgal-data/pig.stl"; do
  [ -f "$f" ] || continue
  "$VOX" voxelize "$f" --res 64 -o p.vdb -q --threads 1 --report p.json
  python3 -c "
import json,os,sys
d=json.load(open('p.json')); ph={p['name']:p['seconds'] for p in d['phases']}
b=os.path.getsize('$f'); print(f'parse {os.path.basename(\"$f\")}: {b/1e6:.2f} MB in {ph[\"parse\"]*1000:.1f} ms = {b/1e6/ph[\"parse\"]:.0f} MB/s')"
done
