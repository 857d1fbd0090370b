#!/usr/bin/env bash
# build-atlas deflates its PNGs in row slices and its EXRs in scanline blocks
# on every thread: every file (atlases, 1- and 2-bit bitmaps, EXR identity
# atlases, previews, layers, the sidecar) is byte-identical at --threads 1, 2
# and 3, and every atlas and bitmap decodes to the scene's texels.
# Usage: atlasdeflate_test.sh VOX_BINARY
set -u
vox=$1
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

expect_exit 0 "$vox" voxelize demo:hamlet --res 96 -o h.vdb -q
# Two shapes: every content in one layer with previews, and an EXR identity
# atlas (rgba32f) over several layers.
for t in 1 2 3; do
  expect_exit 0 "$vox" build-atlas h.vdb -o all$t --all --preview --threads $t -q
  expect_exit 0 "$vox" build-atlas h.vdb -o exr$t --identity --format rgba32f --occupancy --occupancy2 \
    --max-side 512 --threads $t -q
done
for set in all exr; do
  n=$(ls $set"1" | wc -l)
  [ "$n" -ge 4 ] || fail "$set: only $n files written"
  for f in "$set"1/*; do
    name=$(basename "$f")
    for t in 2 3; do
      cmp -s "$f" "$set$t/$name" || fail "$set/$name differs between --threads 1 and --threads $t"
    done
  done
done
ls exr1/*.layer1.exr >/dev/null 2>&1 || fail "the EXR identity atlas was not split into layers"
ls all1/*.summary.png all1/*.occupancy.png all1/*.occupancy2.png all1/*.identity.png >/dev/null 2>&1 ||
  fail "--all lacks a summary, bitmap or identity PNG: $(ls all1)"
# Every atlas and bitmap decodes to exactly the scene's texels (each texel
# checked against its voxel through the inverse mapping).
for f in all3/*.png exr3/*.png exr3/*.exr; do
  case $f in *.preview.png) continue ;; esac
  expect_exit 0 "$vox" verify-bijection --atlas "$f" --scene h.vdb
done

[ "$failures" = 0 ] || { echo "$failures failure(s)" >&2; exit 1; }
echo "atlasdeflate: ok"
