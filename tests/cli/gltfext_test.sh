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

same_voxels() {  # same_voxels A B [voxelize options...]: both voxelize (res 64) to the same scene
  local a=$1 b=$2; shift 2
  expect_exit 0 "$vox" voxelize "$a" --res 64 "$@" -o a.vdb
  [ -s err.txt ] && grep -qi warn err.txt && fail "$a: unexpected warning: $(cat err.txt)"
  expect_exit 0 "$vox" voxelize "$b" --res 64 "$@" -o b.vdb
  expect_exit 0 "$vox" diff a.vdb b.vdb --ignore-sources
  [ "$(cat out.txt | head -c 5)" = "same:" ] || fail "$a vs $b: $(head -c 400 out.txt)"
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
if command -v draco_transcoder >/dev/null && command -v draco_encoder >/dev/null; then
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
  $make corrupt uncompressed-count grid_draco.glb count.glb
  refused count.glb "mesh 'grid' primitive 0 (KHR_draco_mesh_compression)" "COLOR_0 is stored uncompressed" "5 values"
  # A box encoded by Debian's draco_encoder with sequential connectivity and raw
  # indices: the same voxels as its OBJ; with one face index patched past the
  # points (what a corrupt or hostile encoder can store), refused by name.
  printf 'v 0 0 0\nv 2 0 0\nv 2 3 0\nv 0 3 0\nv 0 0 5\nv 2 0 5\nv 2 3 5\nv 0 3 5\n' >box.obj
  printf 'f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n' >>box.obj
  draco_encoder -i box.obj -o box.drc -cl 0 -qp 0 >encode.txt 2>&1 || fail "draco_encoder: $(cat encode.txt)"
  $make draco-box box.drc box_draco.glb
  same_voxels box_draco.glb box.obj --fill solid
  $make draco-box-oob box.drc oob.glb
  refused oob.glb "mesh 'box' primitive 0 (KHR_draco_mesh_compression)" "face 5" "point 200 of 8"
else
  fail "draco_transcoder or draco_encoder not found: install Debian's draco package (scripts/install-deps.sh)"
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

# --- KHR_mesh_quantization, KHR_texture_transform, EXT_mesh_gpu_instancing --
# Each file against the same model with the extension applied by
# make_gltf.py: integer and normalized accessors hold exactly the reference's
# floats; transformed UVs land on texel-block centres (nearest sampling); the
# instances are the reference's child nodes (one mirrored: --fill solid
# checks that its triangles still wind outward); the specular-glossiness
# diffuse colour is the reference's base colour.
for k in quantized transform instancing specgloss; do
  $make $k $k.gltf
  $make $k-ref ${k}_ref.gltf
  same_voxels $k.gltf ${k}_ref.gltf --fill solid
done
# Without the extension the transform file is another scene: the oracle can fail.
python3 -c "import json; d=json.load(open('transform.gltf')); d['extensionsRequired']=[]
del d['materials'][0]['pbrMetallicRoughness']['baseColorTexture']['extensions']; json.dump(d, open('plain.gltf', 'w'))"
expect_exit 0 "$vox" voxelize plain.gltf --res 64 --fill solid -o plain.vdb
expect_exit 0 "$vox" voxelize transform_ref.gltf --res 64 --fill solid -o ref.vdb
expect_exit 1 "$vox" diff plain.vdb ref.vdb --ignore-sources

# --- extensionsRequired -----------------------------------------------------
# Honoured or without effect on the voxels: read, and KHR_materials_* on the
# material are ignored without a warning.
$make required "" none.gltf
for ext in KHR_mesh_quantization KHR_texture_transform EXT_mesh_gpu_instancing KHR_draco_mesh_compression EXT_texture_webp \
           EXT_meshopt_compression KHR_materials_clearcoat KHR_materials_unlit KHR_materials_variants \
           KHR_materials_diffuse_transmission KHR_lights_punctual; do
  $make required "$ext" "req_$ext.gltf"
  same_voxels "req_$ext.gltf" none.gltf
done
# EXT_texture_webp: the quadrant texture as lossless WebP (Debian's cwebp)
# bakes the same voxels; with a black PNG fallback the WebP is still the one
# used; a truncated WebP is refused naming its image.
if command -v cwebp >/dev/null; then
  $make png quadrants.png
  cwebp -quiet -lossless quadrants.png -o quadrants.webp || fail "cwebp failed"
  for mode in only fallback; do
    $make webp $mode quadrants.webp webp_$mode.gltf
    grep -q '"image/webp"' webp_$mode.gltf || fail "webp_$mode.gltf has no WebP image"
    same_voxels webp_$mode.gltf none.gltf
  done
  $make webp corrupt quadrants.webp webp_corrupt.gltf
  refused webp_corrupt.gltf "webp_corrupt.gltf: image 1 cannot be decoded"
else
  fail "cwebp not found: install Debian's webp package (scripts/install-deps.sh)"
fi
# Anything else could change the voxels: refused by name, nothing written.
for ext in KHR_texture_basisu EXT_texture_avif EXT_future_extension; do
  $make required "KHR_mesh_quantization,$ext" "req_$ext.gltf"
  refused "req_$ext.gltf" "requires the extension $ext" "could change the voxels"
done

if [ "$failures" = 0 ]; then echo "gltfext_test: all passed"; else echo "gltfext_test: $failures failed"; fi
exit $((failures > 0))
