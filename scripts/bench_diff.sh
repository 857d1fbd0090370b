#!/usr/bin/env bash
# Benchmarks `vox diff` (docs/diff.md, "Performance") with hyperfine, every
# ratio from one hyperfine run:
#   * two 4096^2 RGBA8 atlases (the 256^3 hamlet's summary atlas, and the same
#     with salt noise on 1% of the pixels by oiiotool) against OpenImageIO's
#     `idiff` on the same two files, and the atlas against an identical copy;
#   * two 1024^3 scenes against `vox info` reading both: an identical pair (a
#     golden file and today's bake) and a pair that differs everywhere (the
#     hamlet at 1024 and at 1023 voxels: every shared voxel's votes differ).
# Prints a markdown table on stdout.
#
# Usage: scripts/bench_diff.sh   Env: BUILD_DIR (default build), RUNS (default 5), RES (default 1024).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
vox=$root/${BUILD_DIR:-build}/bin/vox
runs=${RUNS:-5}
res=${RES:-1024}
for tool in hyperfine idiff oiiotool python3; do
  command -v $tool >/dev/null || { echo "bench_diff.sh: needs $tool (apt-get install hyperfine openimageio-tools)" >&2; exit 4; }
done
[ -x "$vox" ] || { echo "bench_diff.sh: build vox first ($vox)" >&2; exit 4; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

echo "== atlases" >&2
"$vox" voxelize demo:hamlet --res 256 -o h256.vdb --quiet
"$vox" build-atlas h256.vdb -o at --summary --quiet
cp at/h256.summary.png a.png
cp a.png same.png
oiiotool a.png --noise:type=salt:value=1:portion=0.01:mono=1:seed=7 -d uint8 -o b.png
echo "== scenes at $res^3" >&2
"$vox" voxelize demo:hamlet --res "$res" -o s1.vdb --quiet
cp s1.vdb s1copy.vdb
"$vox" voxelize demo:hamlet --res $((res - 1)) -o s2.vdb --quiet

ratio() {  # ratio JSON: mean of command 0 / mean of command 1, and both means
  python3 - "$1" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["results"]
a, b = r[0]["mean"], r[1]["mean"]
# CPU seconds (user + system, as hyperfine measures them): steadier than wall
# time on a machine shared with other jobs.
ca, cb = r[0]["user"] + r[0]["system"], r[1]["user"] + r[1]["system"]
print(f"{a:.3f} s | {b:.3f} s | {a / b:.2f} | {ca:.2f} s | {cb:.2f} s | {ca / cb:.2f}")
PY
}
bench() {  # bench NAME CMD_VOX CMD_REF
  hyperfine --warmup 1 --runs "$runs" -i --export-json "$1.json" "$2" "$3" >&2
  echo "| $1 | \`${2//$vox/vox}\` | \`${3//$vox/vox}\` | $(ratio "$1.json") |"
}
echo "| case | vox diff | reference | vox diff wall | reference wall | ratio | vox diff CPU | reference CPU | CPU ratio |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
bench "atlases 4096^2, 1% salt noise" "$vox diff a.png b.png" "idiff a.png b.png"
bench "atlases 4096^2, identical" "$vox diff a.png same.png" "idiff a.png same.png"
bench "scenes $res^3, identical" "$vox diff s1.vdb s1copy.vdb" "sh -c '$vox info s1.vdb >/dev/null && $vox info s1copy.vdb >/dev/null'"
bench "scenes $res^3 vs $((res - 1))^3" "$vox diff s1.vdb s2.vdb" "sh -c '$vox info s1.vdb >/dev/null && $vox info s2.vdb >/dev/null'"
echo "(hyperfine, $runs runs after 1 warm-up, $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the end, $(date -u +%Y-%m-%d))"
