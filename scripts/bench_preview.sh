#!/bin/sh
# What `vox build-atlas --preview` costs: the 256^3 demo's default atlases
# (summary + occupancy) and every atlas (--all), with and without previews, in
# one hyperfine run (so the ratios come from one run), and the previews' share
# of the CPU time (user + system, from hyperfine's JSON).
# Usage: scripts/bench_preview.sh [BUILD_DIR]   -> prints Markdown
set -eu
cd "$(dirname "$0")/.."
VOX=$(pwd)/${1:-build}/bin/vox
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$VOX" voxelize demo:hamlet --res 256 -o hamlet.vdb -q
hyperfine -N --warmup 1 --runs "${RUNS:-5}" --export-markdown preview.md --export-json preview.json \
  -n "build-atlas (summary, occupancy)" "$VOX build-atlas hamlet.vdb -o a -q --threads 2" \
  -n "build-atlas --preview" "$VOX build-atlas hamlet.vdb -o b -q --threads 2 --preview" \
  -n "build-atlas --all" "$VOX build-atlas hamlet.vdb -o c -q --threads 2 --all" \
  -n "build-atlas --all --preview" "$VOX build-atlas hamlet.vdb -o d -q --threads 2 --all --preview" >/dev/null
cat preview.md
echo
python3 - <<'PY'
import json
r = {x['command']: x for x in json.load(open('preview.json'))['results']}
cpu = lambda n: r[n]['user'] + r[n]['system']
for base, prev in [("build-atlas (summary, occupancy)", "build-atlas --preview"), ("build-atlas --all", "build-atlas --all --preview")]:
    print(f"- {base}: wall {r[base]['mean']:.2f} s -> {r[prev]['mean']:.2f} s with previews "
          f"(+{100 * (r[prev]['mean'] / r[base]['mean'] - 1):.0f}%); CPU {cpu(base):.2f} s -> {cpu(prev):.2f} s "
          f"(previews {cpu(prev) - cpu(base):.2f} s = {100 * (cpu(prev) - cpu(base)) / cpu(base):.0f}% of the data atlases' CPU)")
PY
du -k a b c d | sort -k2
