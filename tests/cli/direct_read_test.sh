#!/usr/bin/env bash
# The one-pass scene reader against OpenVDB's on scenes made by `vox`: a
# coloured mesh (surface), a solid fill, a --check bake (written through
# OpenVDB), a block map, demo:hamlet at two resolutions, a demo:city box,
# region parts (one of them empty) and their merge, a pyramid and its split
# levels, and the Stanford bunny when ../shared/data has it. The unit test
# binary reads each both ways and compares every grid (DirectRead.*).
# Usage: direct_read_test.sh VOX_BINARY UNIT_TEST_BINARY TESTS_DIR
set -u
vox=$1 unit=$2 tests=$3
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

mkdir scenes
# A cube with sRGB vertex colours (OBJ `v x y z r g b`), and a tetrahedron inside.
cat > cube.obj <<'OBJ'
v 0 0 0 1 0 0
v 1 0 0 0 1 0
v 1 1 0 0 0 1
v 0 1 0 1 1 0
v 0 0 1 0 1 1
v 1 0 1 1 0 1
v 1 1 1 0.5 0.5 0.5
v 0 1 1 0.2 0.8 0.1
v 0.3 0.3 0.3
v 0.7 0.3 0.3
v 0.5 0.7 0.3
v 0.5 0.5 0.7
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
f 9 10 11
f 9 12 10
f 10 12 11
f 11 12 9
OBJ
expect_exit 0 "$vox" voxelize cube.obj --res 61 -o scenes/mesh_colour.vdb -q
expect_exit 0 "$vox" voxelize cube.obj --res 40 --fill solid -o scenes/solid.vdb -q
expect_exit 0 "$vox" voxelize cube.obj --res 24 --fill solid --check -o scenes/checked.vdb -q
expect_exit 0 "$vox" voxelize "$tests/cli/map_small.json" -o scenes/blockmap.vdb -q
expect_exit 0 "$vox" voxelize demo:hamlet --res 32 -o scenes/hamlet32.vdb -q
expect_exit 0 "$vox" voxelize demo:hamlet --res 200 -o scenes/hamlet200.vdb -q --threads 2
expect_exit 0 "$vox" voxelize demo:city --extent 256,128,256 --region-box 32,0,32,191,127,159 -o scenes/citybox.vdb -q
for i in 0 1 2; do
  expect_exit 0 "$vox" voxelize demo:hamlet --res 96 --region "$i/3" -o part$i.vdb -q
done
cp part1.vdb scenes/region_part.vdb
expect_exit 0 "$vox" merge part0.vdb part1.vdb part2.vdb -o scenes/merged.vdb -q
# A part whose box holds no voxel: an empty scene.
expect_exit 0 "$vox" voxelize demo:hamlet --res 64 --region-box 0,32,0,31,63,31 -o scenes/empty_part.vdb -q
expect_exit 0 "$vox" mip scenes/hamlet32.vdb -o scenes/pyramid.vdb -q
expect_exit 0 "$vox" mip scenes/mesh_colour.vdb --split -o split.vdb -q
cp split.mip1.vdb scenes/split_mip1.vdb
bunny=$tests/../../shared/data/common-3d-test-models/stanford-bunny.obj
if [ -f "$bunny" ]; then
  expect_exit 0 "$vox" voxelize "$bunny" --res 160 -o scenes/bunny160.vdb -q
else
  echo "SKIP bunny: $bunny absent"
fi
[ "$failures" = 0 ] || { echo "$failures failure(s) making the scenes" >&2; exit 1; }

VOX_DIRECT_READ_DIR=$work/scenes "$unit" --gtest_filter='DirectRead.ScenesMadeByTheCommandLine' >unit.txt 2>&1 ||
  fail "the unit test failed: $(tail -c 3000 unit.txt)"
grep -q "compared \]" unit.txt || fail "the unit test compared nothing: $(tail -c 1000 unit.txt)"
grep "compared \]" unit.txt
[ "$failures" = 0 ] || { echo "$failures failure(s)" >&2; exit 1; }
echo "direct_read_test: ok"
