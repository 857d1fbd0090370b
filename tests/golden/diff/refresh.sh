#!/usr/bin/env bash
# Remakes the golden files of the diff.golden_demo test (tests/cli/diff_test.sh)
# with the given vox, after a deliberate change of the demo, the scene format,
# the summary bytes or the page-file format. Review `vox diff` of old and new first.
# Usage: tests/golden/diff/refresh.sh build/bin/vox
set -euo pipefail
vox=$(realpath "$1")
cd "$(dirname "$0")"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$vox" voxelize demo:hamlet --res 16 -o hamlet16.vdb --quiet
"$vox" build-atlas hamlet16.vdb -o "$tmp" --summary --quiet
cp "$tmp/hamlet16.summary.png" .
"$vox" pack-chunks hamlet16.vdb -o hamlet16.vpk --chunk 8 --quiet
