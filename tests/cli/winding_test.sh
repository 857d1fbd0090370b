#!/usr/bin/env bash
# A fuzzed open soup whose caps pass through voxel centres: --check finds no
# voxel missed or extra. Real open meshes from ../shared/data: vox voxelize
# --fill solid --check reports the interior IoU against the winding-number
# oracle; >= 0.995 expected.
# Usage: winding_test.sh VOX TESTS_DIR
set -euo pipefail
VOX=$1
DATA="$2/../../shared/data"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail=0
printf 'v 3 6 4\nv 3 0 0\nv 8 4 7\nv 4 1 5\nv 6 1 8\nv 3 6 5\nv 6 0 7\nv 1 0 4\nv 3 1 5\nv 7 2 7\nv 2 0 4\nv 2 3 5\nf 1 2 3\nf 4 5 6\nf 7 8 9\nf 10 11 12\n' >"$T/soup.obj"
for vs in 1 0.5; do
  "$VOX" voxelize "$T/soup.obj" -o "$T/s.vdb" --voxel-size $vs --fill solid --check --report "$T/s.json" >/dev/null 2>"$T/err" \
    || { echo "FAIL: soup: vox exited non-zero"; cat "$T/err"; fail=1; continue; }
  counts=$(python3 -c "import json; s=json.load(open('$T/s.json'))['error']['solid']; print(s['missed'], s['extra'])")
  echo "fuzzed soup at --voxel-size $vs: missed, extra $counts"
  [ "$counts" = "0 0" ] || { echo "FAIL: fuzzed soup at --voxel-size $vs: missed, extra $counts"; fail=1; }
done
if [ ! -f "$DATA/MANIFEST.md" ]; then echo "SKIP: $DATA absent: real meshes not checked"; exit $fail; fi
for m in mesh-misc/assimp/sphereWithHole.stl common-3d-test-models/suzanne.obj common-3d-test-models/teapot.obj \
         common-3d-test-models/beetle.obj mesh-misc/assimp/WusonOBJ.obj cgal-data/pig.stl; do
  if [ ! -f "$DATA/$m" ]; then echo "SKIP: $m absent"; continue; fi
  "$VOX" voxelize "$DATA/$m" --res 48 --fill solid --ignore-missing-materials --check --report "$T/r.json" -o "$T/o.vdb" --threads 2 >/dev/null 2>"$T/err" \
    || { echo "FAIL: $m: vox exited non-zero"; cat "$T/err"; fail=1; continue; }
  iou=$(python3 -c "import json,sys; print(json.load(open('$T/r.json'))['error']['solid']['iou'])")
  echo "$m interior IoU $iou"
  python3 -c "import sys; sys.exit(0 if $iou >= 0.995 else 1)" || { echo "FAIL: $m IoU $iou < 0.995"; fail=1; }
done
exit $fail
