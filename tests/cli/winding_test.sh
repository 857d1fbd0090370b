#!/usr/bin/env bash
# Real open meshes from ../shared/data: vox voxelize --fill solid --check reports
# the interior IoU against the winding-number oracle; >= 0.995 expected.
# Usage: winding_test.sh VOX TESTS_DIR
set -euo pipefail
VOX=$1
DATA="$2/../../shared/data"
if [ ! -f "$DATA/MANIFEST.md" ]; then echo "SKIP: $DATA absent: real meshes not checked"; exit 0; fi
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail=0
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
