#!/usr/bin/env bash
# Benchmarks `vox export` (face-culled .glb, --greedy, --dedup; the culled one
# also in the full module alone, with OpenVDB loaded) against reading
# the same scene (`vox info`) and against reading it plus writing as many bytes
# as the .glb has, durably, as every vox output is committed (`vox info` + dd
# of N zero bytes with conv=fsync: vox fsyncs each output before renaming it
# into place, so a baseline without the fsync would time only the page
# cache on the 1024^3 mesh's 1.9 GB), each scene in one
# hyperfine run so the ratios come from one run; and the mesh phase of a
# 1,000-block map. Prints markdown (docs/export.md "Performance" holds a run).
#
# Usage: scripts/bench_export.sh [MESH]   (default: the Stanford bunny of ../shared/data, at 1024^3)
# Env: BUILD_DIR (default build), THREADS (default: all cores), RUNS (default 5).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
vox=$root/${BUILD_DIR:-build}/bin/vox
mesh=${1:-$root/../shared/data/common-3d-test-models/stanford-bunny.obj}
threads=${THREADS:-$(nproc)}
runs=${RUNS:-5}
for tool in hyperfine python3; do
  command -v $tool >/dev/null || { echo "bench_export.sh: needs $tool" >&2; exit 4; }
done
[ -x "$vox" ] || { echo "bench_export.sh: build vox first ($vox)" >&2; exit 4; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
# The same build without its light export module: `vox export` then runs in
# vox-cmds.so, with OpenVDB loaded (the export before vox-export.so).
mkdir full && cp "$vox" "$(dirname "$vox")/vox-cmds.so" full/

echo "== scenes" >&2
"$vox" voxelize demo:hamlet --res 256 -o hamlet256.vdb --quiet
scenes="hamlet256"
if [ -f "$mesh" ]; then
  "$vox" voxelize "$mesh" --res 1024 -o mesh1024.vdb --quiet
  scenes="$scenes mesh1024"
fi

echo "# vox export benchmark ($(nproc) cores, --threads $threads, $runs runs)"
echo
for s in $scenes; do
  "$vox" export $s.vdb -o probe.glb --threads "$threads" --report probe.json --quiet
  bytes=$(stat -c %s probe.glb)
  python3 -c "import json; c=json.load(open('probe.json'))['counts']; print(f\"$s: {c['voxels']} voxels, {c['faces']} visible faces, .glb {c['bytes']} bytes\")"
  echo
  hyperfine -N -w 1 -r "$runs" --export-markdown $s.md \
    -n "vox info" "$vox info $s.vdb" \
    -n "vox info + write $bytes bytes (fsync)" "sh -c '$vox info $s.vdb >/dev/null && head -c $bytes /dev/zero | dd of=zeros.bin bs=4M iflag=fullblock conv=fsync status=none'" \
    -n "vox export (culled .glb)" "$vox export $s.vdb -o out.glb --threads $threads --quiet" \
    -n "vox export (culled .glb), full module" "full/vox export $s.vdb -o out.glb --threads $threads --quiet" \
    -n "vox export --greedy" "$vox export $s.vdb -o out.glb --greedy --threads $threads --quiet" \
    -n "vox export --dedup" "$vox export $s.vdb -o out.glb --dedup --threads $threads --quiet" >&2
  cat $s.md
  echo
done

# 1,000 blocks of a block map (a 10 x 10 x 10 checkerboard-ish pattern in a
# 20^3 world): the mesh phase of the report, best of the runs.
python3 - <<'EOF'
import json
blocks = [{"position": [x * 2, y, z * 2], "blockType": ["Grass", "Stone", "Sand"][(x + y + z) % 3]}
          for x in range(10) for y in range(10) for z in range(10)]
json.dump({"worldScale": 1.0, "blocks": blocks}, open("map1000.json", "w"))
EOF
"$vox" voxelize map1000.json -o map1000.vdb --grid-size 20,10,20 --quiet
best=""
for i in $(seq "$runs"); do
  "$vox" export map1000.vdb -o m.glb --threads "$threads" --report m.json --quiet
  best=$(python3 -c "import json; d=json.load(open('m.json')); t=[p['seconds'] for p in d['phases'] if p['name'] in ('volume','mesh')]; b='$best'; print(min(sum(t), float(b)) if b else sum(t))")
done
python3 -c "import json; c=json.load(open('m.json'))['counts']; print(f\"1,000 blocks ({c['faces']} visible faces): blocks and mesh (phases volume + mesh) in {1000*$best:.2f} ms, best of $runs\")"
