#!/usr/bin/env bash
# Benchmarks `vox pack-chunks --merge` (docs/scale.md, "Merging page files"):
# a large scene baked as N region parts, each packed, then the parts' page
# files merged, timed with hyperfine against the single-process pack of the
# whole scene and against the floor of any tool that writes the file: a
# durable copy of it (`dd conv=fsync`); MB/s = merged file bytes / mean wall
# time (the commit's fsync included, as in every vox output).
# Every merged file is checked byte-identical (cmp) to the whole pack.
#
# Usage: scripts/bench_pagemerge.sh
# Env: SCENE (default demo:hamlet), RES (default 1024), N (default 8),
#      RUNS (default 5), BUILD_DIR (default build), LAYOUTS (default "bricks svo"),
#      PARTS_DIR: a directory with world.vdb and part0.vdb .. part{N-1}.vdb made
#      elsewhere (when this vox has no `voxelize --region`).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
vox=$root/${BUILD_DIR:-build}/bin/vox
scene=${SCENE:-demo:hamlet}
res=${RES:-1024}
n=${N:-8}
runs=${RUNS:-5}
layouts=${LAYOUTS:-bricks svo}
for tool in hyperfine python3 cmp; do
  command -v $tool >/dev/null || { echo "bench_pagemerge.sh: needs $tool (apt-get install hyperfine)" >&2; exit 4; }
done
[ -x "$vox" ] || { echo "bench_pagemerge.sh: build vox first ($vox)" >&2; exit 4; }
work=$(mktemp -d -p "${TMPDIR:-/tmp}")
trap 'rm -rf "$work"' EXIT
cd "$work"

echo "== scene and $n parts" >&2
if [ -n "${PARTS_DIR:-}" ]; then
  for ((i = 0; i < n; i++)); do ln -s "$PARTS_DIR/part$i.vdb" "part$i.vdb"; done
  ln -s "$PARTS_DIR/world.vdb" world.vdb
elif "$vox" voxelize --help 2>&1 | grep -q -- "--region"; then
  "$vox" voxelize "$scene" --res "$res" -o world.vdb -q
  for ((i = 0; i < n; i++)); do "$vox" voxelize "$scene" --res "$res" --region "$i/$n" -o "part$i.vdb" -q; done
else
  echo "bench_pagemerge.sh: this vox has no 'voxelize --region'; give PARTS_DIR" >&2
  exit 4
fi

echo "| layout | mips | merged file | merge (mean +- sd) | MB/s of output | merge CPU (user + sys) | MB per CPU second | durable copy (dd conv=fsync) | merge / copy | single-process pack | pack / merge |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for layout in $layouts; do
  for mips in "" "--mips"; do
    tag=$layout${mips:+-mips}
    "$vox" pack-chunks world.vdb -o "whole-$tag.vpk" --layout "$layout" $mips -q
    parts=()
    for ((i = 0; i < n; i++)); do
      "$vox" pack-chunks "part$i.vdb" -o "part$i-$tag.vpk" --layout "$layout" $mips -q
      parts+=("part$i-$tag.vpk")
    done
    "$vox" pack-chunks --merge "${parts[@]}" -o "merged-$tag.vpk" -q --report "report-$tag.json"
    cmp "merged-$tag.vpk" "whole-$tag.vpk" || { echo "bench_pagemerge.sh: $tag merged differs from the whole pack" >&2; exit 1; }
    # Each run writes a new file, as a bake does: replacing an existing
    # 300 MB file would add the file system's freeing of the old one (the
    # removal is synced before the run starts).
    hyperfine --warmup 1 --runs "$runs" --export-json "$tag.json" -N \
      --prepare "sh -c 'rm -f merged-$tag.vpk copy-$tag.vpk; sync'" \
      -n merge "$vox pack-chunks --merge ${parts[*]} -o merged-$tag.vpk -q" \
      -n copy "dd if=whole-$tag.vpk of=copy-$tag.vpk bs=4M conv=fsync status=none" \
      -n pack "$vox pack-chunks world.vdb -o whole-$tag.vpk --layout $layout $mips -q" >&2
    bytes=$(stat -c %s "whole-$tag.vpk")  # the merged file is the same bytes (checked above)
    python3 -c "import json,sys; c=json.load(open('report-$tag.json'))['counts']; print('$tag phases (s):', {k: round(v, 3) for k, v in c['seconds'].items()}, 'copied', c['copied_chunks'], 're-encoded', c['reencoded_chunks'], 'rebuilt', c['rebuilt_chunks'], file=sys.stderr)"
    python3 - "$tag.json" "$bytes" "$layout" "${mips:-no}" <<'EOF'
import json, sys
r = {x["command"]: x for x in json.load(open(sys.argv[1]))["results"]}
b = int(sys.argv[2])
m, c, p = r["merge"], r["copy"], r["pack"]
cpu = m["user"] + m["system"]
print(f"| {sys.argv[3]} | {sys.argv[4]} | {b / 1e6:.1f} MB | {m['mean']:.3f} +- {m['stddev']:.3f} s | "
      f"{b / 1e6 / m['mean']:.0f} | {cpu:.3f} s | {b / 1e6 / cpu:.0f} | "
      f"{c['mean']:.3f} s ({b / 1e6 / c['mean']:.0f} MB/s) | {m['mean'] / c['mean']:.2f} | "
      f"{p['mean']:.2f} s | {p['mean'] / m['mean']:.1f}x |")
EOF
  done
done
echo
echo "Scene: $scene at --res $res, N = $n parts; $(nproc) cores; load average $(cut -d' ' -f1-3 /proc/loadavg)."
