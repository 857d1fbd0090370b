#!/bin/bash
# glTF extensions end to end (docs/gltf.md): each extension's file, written by
# tests/gltfext/make_gltf.py (or compressed by Debian's draco_transcoder),
# voxelizes to exactly the voxels of the same model without the extension.
# Usage: gltfext_test.sh VOX TESTS_DIR
set -u
vox=$1
tests=$(cd "$2" && pwd)
make="python3 $tests/gltfext/make_gltf.py"
. "$tests/cli/test_lib.sh"

same_voxels() {  # same_voxels A B [diff options...]: both voxelize (res 64) to the same scene
  local a=$1 b=$2; shift 2
  expect_exit 0 "$vox" voxelize "$a" --res 64 -o a.vdb
  expect_exit 0 "$vox" voxelize "$b" --res 64 -o b.vdb
  expect_exit 0 "$vox" diff a.vdb b.vdb --ignore-sources "$@"
  rm -f a.vdb b.vdb
}

refused() {  # refused FILE TEXT...: exit 3, each TEXT on stderr, no output written
  local f=$1; shift
  expect_exit 3 "$vox" voxelize "$f" --res 32 -o refused.vdb
  for t in "$@"; do expect_stderr "$t"; done
  [ ! -e refused.vdb ] || fail "$f: refused but refused.vdb was written"
}

# --- KHR_draco_mesh_compression ---------------------------------------------
# Positions on the integer grid spanning 0..2047 are exact at Draco's 11-bit
# position quantization (step 1); every triangle has one UV at a texel-block
# centre and one colour, so the texture and colour quantization cannot change
# a voxel either: the voxels must be identical, colours included.
if command -v draco_transcoder >/dev/null; then
  $make draco-source grid.gltf
  draco_transcoder -i grid.gltf -o grid_draco.glb >transcode.txt 2>&1 || fail "draco_transcoder: $(cat transcode.txt)"
  grep -q KHR_draco_mesh_compression grid_draco.glb || fail "grid_draco.glb is not Draco-compressed"
  same_voxels grid.gltf grid_draco.glb
  $make corrupt truncated grid_draco.glb truncated.glb
  refused truncated.glb "mesh 'grid' primitive 0 (KHR_draco_mesh_compression)" "does not decode"
  $make corrupt attribute-id grid_draco.glb attrid.glb
  refused attrid.glb "mesh 'grid' primitive 0 (KHR_draco_mesh_compression)" "POSITION names Draco attribute 9"
  $make corrupt bufferview grid_draco.glb view.glb
  refused view.glb "mesh 'grid' primitive 0 (KHR_draco_mesh_compression)" "bufferView 7 does not exist"
else
  fail "draco_transcoder not found: install Debian's draco package (scripts/install-deps.sh)"
fi
# A real Draco file when the shared data is there, against its uncompressed
# original: Draco's default 14-bit positions move vertices by up to 1/2^15 of
# the model's extent, which may move a boundary voxel or two (the bounds, and
# so the voxel size, change by as much); at most 0.1% of the voxels may be
# occupied in one scene only.
data=$tests/../../shared/data/gltf/assimp
if [ -f "$data/draco/2CylinderEngine.gltf" ]; then
  expect_exit 0 "$vox" voxelize "$data/draco/2CylinderEngine.gltf" --res 64 -o engine_draco.vdb
  expect_exit 0 "$vox" voxelize "$data/2CylinderEngine-glTF-Binary/2CylinderEngine.glb" --res 64 -o engine.vdb
  expect_exit 1 "$vox" diff engine_draco.vdb engine.vdb --ignore-sources --json
  jcheck out.txt "assert d['only_in_a'] + d['only_in_b'] <= 0.001 * d['voxels_b'], (d['only_in_a'], d['only_in_b'])"
else
  echo "gltfext_test: ../shared/data absent; the real Draco file is skipped"
fi

if [ "$failures" = 0 ]; then echo "gltfext_test: all passed"; else echo "gltfext_test: $failures failed"; fi
exit $((failures > 0))
