#!/bin/sh
# Error against run time of `vox voxelize`: method (exact, sdf) x fill (surface,
# solid) x resolution, on third-party meshes from ../shared/data. Writes
# docs/voxelize-study.md (table) and docs/voxelize-study.png (plot).
# Usage: scripts/study_voxelize.sh [BUILD_DIR]
set -eu
cd "$(dirname "$0")/.."
root=$(pwd)
VOX=$root/${1:-build}/bin/vox
DATA=$root/../shared/data
[ -d "$DATA" ] || { echo "study_voxelize.sh: ../shared/data is absent; nothing to study" >&2; exit 0; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
rows=$work/rows.tsv
: > "$rows"
for mesh in common-3d-test-models/spot.obj common-3d-test-models/fandisk.obj common-3d-test-models/stanford-bunny.obj common-3d-test-models/teapot.obj; do
  for fill in surface solid; do
    for method in exact sdf; do
      for res in 64 128 256 512; do
        "$VOX" voxelize "$DATA/$mesh" --res $res --fill $fill --method $method --check --threads 2 \
          --report "$work/r.json" -o "$work/o.vdb" -q || continue
        python3 - "$work/r.json" "$mesh" "$fill" "$method" "$res" >> "$rows" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
ph = {p['name']: p['seconds'] for p in d['phases']}
e = d['error']
if 'surface' in e:
    s = e['surface']
    extra = s['extra'] if s['extra'] is not None else 0
    err = (s['missed'] + extra) / max(1, s['oracle_voxels'])
    detail = f"missed {s['missed']}, extra {extra} of {s['oracle_voxels']}"
else:
    s = e['solid']
    err = 1 - s['iou']
    detail = f"volume {s['relative_volume_error']*100:+.2f}%, IoU {s['iou']:.4f}"
print("\t".join([sys.argv[2].split('/')[-1], sys.argv[3], sys.argv[4], sys.argv[5],
                 f"{ph['voxelize']:.4f}", f"{d['total_seconds'] - ph.get('check', 0):.4f}", f"{err:.6f}", detail]))
PY
      done
    done
  done
done
{
  echo "# Voxelization: error against run time"
  echo
  echo "Produced by \`scripts/study_voxelize.sh\` on this 2-core machine ($(date -u +%Y-%m-%d)), 2 threads."
  echo "Error: for surface fill, (voxels missed + extra) / voxels of the brute-force oracle (every"
  echo "triangle against every voxel of its box, exact SAT); for solid fill, 1 - IoU against the"
  echo "generalised winding number at sampled voxel centres (relative volume error beside it)."
  echo "Time: the voxelize phase alone, and the whole run (parse, voxelize, write, without the check)."
  echo
  echo "![error against run time](voxelize-study.png)"
  echo
  echo "| mesh | fill | method | res | voxelize s | total s | error | detail |"
  echo "|---|---|---|---:|---:|---:|---:|---|"
  awk -F'\t' '{printf "| %s | %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6, $7, $8}' "$rows"
} > docs/voxelize-study.md
if command -v gnuplot >/dev/null; then
  for f in surface solid; do
    for m in exact sdf; do
      awk -F'\t' -v f=$f -v m=$m '$2==f && $3==m {print $5, $7 + 1e-6}' "$rows" > "$work/$f-$m.dat"
    done
  done
  gnuplot <<GP
set terminal png size 1000,600
set output "docs/voxelize-study.png"
set logscale xy
set xlabel "voxelize time (s), 2 threads"
set ylabel "error (+1e-6 so zero shows)"
set title "vox voxelize: error against run time (4 meshes x 64..512)"
set key outside
plot "$work/surface-exact.dat" title "surface, exact" pt 7, \
     "$work/surface-sdf.dat" title "surface, sdf (OpenVDB)" pt 5, \
     "$work/solid-exact.dat" title "solid, exact" pt 9, \
     "$work/solid-sdf.dat" title "solid, sdf (OpenVDB)" pt 11
GP
fi
echo "wrote docs/voxelize-study.md and docs/voxelize-study.png"
