#!/usr/bin/env bash
# The error of `vox fuse` against depth noise and label flips: runs
# tests/fuse/noise_study.cpp (built as vox_fuse_noise_study with the tests)
# and writes docs/fuse-noise.md (or $OUT).
# Usage: scripts/study_fuse_noise.sh [RES] [SIZE]   (defaults 128, 192)
# Env: BUILD_DIR (default build).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
study=$root/${BUILD_DIR:-build}/bin/vox_fuse_noise_study
res=${1:-128}
size=${2:-192}
out=${OUT:-$root/docs/fuse-noise.md}
[ -x "$study" ] || { echo "study_fuse_noise.sh: build the tests first (-DVOX_BUILD_TESTS=ON: $study)" >&2; exit 4; }
{
  echo "# \`vox fuse\`: error against depth noise and label flips"
  echo
  echo "Produced by \`scripts/study_fuse_noise.sh $res $size\` (\`tests/fuse/noise_study.cpp\`). The demo hamlet is"
  echo "rendered by render-canonical's caster from orbit cameras (elevation 35.26 degrees, fov 50). Gaussian noise of"
  echo "standard deviation sigma voxels is added to each depth, and a fraction of the labels is flipped to"
  echo "another of the 7 classes (fixed seeds). The views are fused with carving into an empty grid and compared with"
  echo "the voxels the noise-free rays hit (the visible voxels): occupancy IoU, class accuracy (the winning class"
  echo "against the truth's, on fused voxels occupied in the truth) and precision (fused voxels occupied in the truth)."
  echo
  "$study" "$res" "$size"
} >"$out.tmp"
mv "$out.tmp" "$out"
cat "$out"
