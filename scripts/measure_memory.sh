#!/usr/bin/env bash
# The memory guard's estimates against measured peaks (docs/reliability.md
# "Memory"): runs each command once under /usr/bin/time, reads the estimate
# from its --report ("memory"."estimate_bytes", the largest estimate the run
# checked) and prints one Markdown table row per run:
#   input | command | estimate | measured peak (max RSS) | estimate / peak
# Usage: scripts/measure_memory.sh [VOX] [DATA_DIR] [--large]
#   VOX       default build/bin/vox
#   DATA_DIR  default ../shared/data (rows that need it are skipped without it)
#   --large   adds the 12-triangle cube at --res 4096 (~40 s, ~4.5 GB)
set -u
vox=$(realpath "${1:-build/bin/vox}")
data=$(realpath "${2:-../shared/data}" 2>/dev/null || echo /nonexistent)
large=0
for a in "$@"; do [ "$a" = --large ] && large=1; done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 4

printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n' >cube.obj
printf 'f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n' >>cube.obj
printf '{"worldScale": 1.0, "blocks": [{"position": [0, 0, 0], "blockType": "Stone"}, {"position": [511, 511, 511], "blockType": "Grass"}, {"position": [100, 200, 300], "blockType": "Sand"}]}\n' >three.json

echo "| input | command | estimate | measured peak | estimate / peak |"
echo "|---|---|---:|---:|---:|"
# row INPUT-LABEL ARGS...: runs `vox ARGS --report r.json`, prints the row.
row() {
  local label=$1; shift
  rm -f r.json
  if ! /usr/bin/time -f %M -o rss.txt "$vox" "$@" --report r.json -q >/dev/null 2>err.txt; then
    echo "| $label | \`vox $*\` | failed: $(head -c 200 err.txt) | | |"
    return
  fi
  python3 - "$label" "vox $*" "$(tail -1 rss.txt)" <<'EOF'
import json, sys
label, cmd, rss_kb = sys.argv[1], sys.argv[2], int(sys.argv[3])
est = json.load(open("r.json"))["memory"]["estimate_bytes"]
peak = rss_kb * 1024
mib = lambda b: f"{b / 2**20:,.0f} MiB" if b >= 2**20 * 10 else f"{b / 2**20:.1f} MiB"
print(f"| {label} | `{cmd}` | {mib(est)} | {mib(peak)} | {est / peak:.2f} |")
EOF
}

row "12-triangle cube" voxelize cube.obj --res 2048 -o c.vdb
row "12-triangle cube" voxelize cube.obj --res 512 --fill solid -o cs.vdb
row "12-triangle cube" voxelize cube.obj --res 512 --method sdf -o csdf.vdb
[ $large = 1 ] && row "12-triangle cube" voxelize cube.obj --res 4096 -o c4096.vdb
row "demo:hamlet" voxelize demo:hamlet --res 512 -o h512.vdb
row "demo:hamlet" voxelize demo:hamlet --res 256 -o h256.vdb
m=$data/common-3d-test-models
if [ -d "$m" ]; then
  row "fandisk.obj (12,946 triangles)" voxelize "$m/fandisk.obj" --res 1024 -o f.vdb
  row "stanford-bunny.obj (69,451 triangles, open)" voxelize "$m/stanford-bunny.obj" --res 512 --fill solid -o b.vdb
  row "spot.obj (5,856 triangles)" voxelize "$m/spot.obj" --res 768 --fill solid --solid-rule parity -o s.vdb
  row "teapot.obj (6,320 triangles, open)" voxelize "$m/teapot.obj" --res 512 --check -o t.vdb
fi
[ -f "$data/derived/armadillo_ls128.vdb" ] && row "armadillo_ls128.vdb (level set)" voxelize "$data/derived/armadillo_ls128.vdb" --res 384 -o a.vdb
row "3 blocks in a 512^3 grid" voxelize three.json --grid-size 512,512,512 -o three.vdb
row "3 blocks in a 512^3 grid" build-atlas three.vdb -o atlas3
row "3 blocks in a 512^3 grid" build-atlas three.vdb -o atlas3p --max-side 4096 --preview
row "hamlet 512^3 scene" build-atlas h512.vdb -o atlas --all
row "hamlet 512^3 scene" mip h512.vdb -o h512m.vdb
row "hamlet 512^3 pyramid" pack-chunks h512m.vdb -o h512.vpk --mips
row "hamlet 512^3 scene" render-canonical h512.vdb -o r.png --view iso --size 1024x1024
row "hamlet 256^3 scene" export h256.vdb -o h256.glb
