#!/bin/sh
# Benchmarks `vox build-atlas` against oiiotool writing an image of the same
# size and content (the summary atlas of the 256^3 demo, RGBA8 4096 x 4096 PNG,
# zlib level 6 for both), and exhaustive bijection proofs, with hyperfine.
# Every ratio comes from one hyperfine run: vox at --threads 2 (and 1), the
# previous build when BASE_VOX names its binary, and oiiotool, side by side.
# CPU time (user + system) is printed beside wall time: on a shared, loaded
# machine it is the steadier figure.
# Usage: [BASE_VOX=/path/to/old/vox] scripts/bench_atlas.sh [BUILD_DIR]
#        -> prints Markdown tables
set -eu
cd "$(dirname "$0")/.."
VOX=$(pwd)/${1:-build}/bin/vox
BASE_VOX=${BASE_VOX:-}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$VOX" voxelize demo:hamlet --res 256 -o hamlet.vdb -q
"$VOX" build-atlas hamlet.vdb -o ref --summary -q
# oiiotool's input: the same texels, uncompressed, so it pays no decoding cost.
oiiotool ref/hamlet.summary.png --compression none -o summary_raw.tif
set -- -n "vox build-atlas --threads 2 (read .vdb, summarize, write PNG)" \
  "$VOX build-atlas hamlet.vdb -o out --summary -q --threads 2" \
  -n "vox build-atlas --threads 1" "$VOX build-atlas hamlet.vdb -o out1 --summary -q --threads 1"
if [ -n "$BASE_VOX" ]; then
  set -- "$@" -n "previous vox build-atlas --threads 2" "$BASE_VOX build-atlas hamlet.vdb -o base --summary -q --threads 2"
fi
hyperfine -N --warmup 1 --runs "${RUNS:-10}" --export-json atlas.json "$@" \
  -n "oiiotool (read raw TIFF, write PNG)" "oiiotool summary_raw.tif --attrib png:compressionLevel 6 -o oiio.png" >/dev/null
python3 - atlas.json <<'PY'
import json, statistics, sys
rs = json.load(open(sys.argv[1]))["results"]
oiio = rs[-1]
cpu = lambda r: statistics.mean(u + s for u, s in zip(r["user"], r["system"])) if "user" in r and isinstance(r["user"], list) else r["user"] + r["system"]
print("| Command | Mean wall [s] | Median wall [s] | Min wall [s] | CPU user+sys [s] | oiiotool wall / this |")
print("|:---|---:|---:|---:|---:|---:|")
for r in rs:
    print("| `%s` | %.3f ± %.3f | %.3f | %.3f | %.3f | %.2f |" % (r["command"], r["mean"], r["stddev"], r["median"], r["min"],
          cpu(r), oiio["mean"] / r["mean"]))
PY
cmp -s out/hamlet.summary.png out1/hamlet.summary.png && echo "threads 1 and 2: identical bytes" || echo "threads 1 and 2: DIFFERENT bytes"
hyperfine -N --warmup 2 --runs 10 --export-markdown proof.md \
  -n "vox verify-bijection --res 256 (2^24 pairs)" "$VOX verify-bijection --res 256 --threads 2" \
  -n "vox --version" "$VOX --version" >/dev/null
echo
cat proof.md
echo
"$VOX" verify-bijection --res 256 --threads 2 | grep pairs
ls -l out/hamlet.summary.png oiio.png | awk '{print $5, $9}'
