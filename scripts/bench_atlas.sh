#!/bin/sh
# Benchmarks `vox build-atlas` against oiiotool writing an image of the same
# size and content (the summary atlas of the 256^3 demo, RGBA8 4096 x 4096 PNG,
# zlib level 6 for both), and exhaustive bijection proofs, with hyperfine.
# Usage: scripts/bench_atlas.sh [BUILD_DIR]   -> prints a Markdown table
set -eu
cd "$(dirname "$0")/.."
VOX=$(pwd)/${1:-build}/bin/vox
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$VOX" voxelize demo:hamlet --res 256 -o hamlet.vdb -q
"$VOX" build-atlas hamlet.vdb -o ref --summary -q
# oiiotool's input: the same texels, uncompressed, so it pays no decoding cost.
oiiotool ref/hamlet.summary.png --compression none -o summary_raw.tif
hyperfine -N --warmup 1 --runs 5 --export-markdown atlas.md \
  -n "vox build-atlas (read .vdb, summarize, write PNG)" "$VOX build-atlas hamlet.vdb -o out --summary -q --threads 2" \
  -n "oiiotool (read raw TIFF, write PNG)" "oiiotool summary_raw.tif --attrib png:compressionLevel 6 -o oiio.png" >/dev/null
hyperfine -N --warmup 2 --runs 10 --export-markdown proof.md \
  -n "vox verify-bijection --res 256 (2^24 pairs)" "$VOX verify-bijection --res 256 --threads 2" \
  -n "vox --version" "$VOX --version" >/dev/null
cat atlas.md
echo
cat proof.md
echo
"$VOX" verify-bijection --res 256 --threads 2 | grep pairs
ls -l out/hamlet.summary.png oiio.png | awk '{print $5, $9}'
