#!/bin/bash
# glTF colour textures read by rows after the geometry (formats/mesh/deferred_textures.h):
# the scene is byte-identical to the bake that decodes them while reading the
# file (--ignore-missing-materials keeps that path) at --threads 1 and 2, for
# PNG textures (decoded whole, then handed out by rows) and JPEG ones
# (decoded row by row, baseline and progressive), the report counts the
# images decoded during the bake, an image that does not decode is
# refused as before (exit 3, its name on stderr, nothing written), and a
# damaged JPEG decodes with a warning naming it.
# Usage: texoverlap_test.sh VOX TESTS_DIR
set -u
vox=$1
tests=$(cd "$2" && pwd)
. "$tests/cli/test_lib.sh"

# Five 64 x 64 noise PNGs (bilinear samples between different texels) on the
# banded sphere of the textured benchmark, and the textured box of the glTF
# extension tests (a 4 x 4 nearest-filtered texture, one image).
python3 - <<'EOF' || fail "could not write the PNG textures"
import random, struct, zlib
def png(path, w, h, seed):
    rnd = random.Random(seed)
    raw = b"".join(b"\0" + bytes(rnd.randrange(256) if c % 4 != 3 else 255 for c in range(4 * w)) for _ in range(h))
    chunk = lambda k, d: struct.pack(">I", len(d)) + k + d + struct.pack(">I", zlib.crc32(k + d) & 0xFFFFFFFF)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)) +
                           chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
for i in range(5):
    png(f"t{i}.png", 64, 64, i)
png("big.png", 301, 211, 9)  # JPEG below: 14 bands of rows, the last partial
EOF
python3 "$tests/../bench/make_textured_glb.py" sphere.glb plain.glb t0.png t1.png t2.png t3.png t4.png ||
  fail "make_textured_glb.py failed"
inputs="sphere.glb box.gltf"
if command -v oiiotool >/dev/null; then
  oiiotool big.png -o big.jpg && oiiotool t1.png -o t1.jpg && oiiotool t2.png --attrib jpeg:progressive 1 -o t2p.jpg ||
    fail "oiiotool could not write the JPEGs"
  python3 "$tests/../bench/make_textured_glb.py" sphere-jpeg.glb plain-jpeg.glb big.jpg t1.jpg t2p.jpg t3.png t4.png ||
    fail "make_textured_glb.py failed (JPEG)"
  python3 -c "import sys; d = open('t2p.jpg', 'rb').read(); sys.exit(0 if b'\xff\xc2' in d else 1)" ||
    fail "t2p.jpg is not a progressive JPEG"
  inputs="$inputs sphere-jpeg.glb"
else
  echo "SKIP: oiiotool (openimageio-tools) not found: JPEG textures not tested"
fi
python3 "$tests/gltfext/make_gltf.py" required "" box.gltf || fail "make_gltf.py failed"

for f in $inputs; do
  for t in 1 2; do
    expect_exit 0 "$vox" voxelize "$f" --res 48 --threads $t -o "later$t.vdb" --report "later$t.json"
    jcheck "later$t.json" "assert d['counts']['texture_decode']['images'] == (1 if '$f' == 'box.gltf' else 5), d['counts']"
  done
  # The reference: the same images decoded while the file is read.
  expect_exit 0 "$vox" voxelize "$f" --res 48 --threads 2 --ignore-missing-materials -o first.vdb --report first.json
  jcheck first.json "assert 'texture_decode' not in d['counts'], d['counts']"
  cmp -s later1.vdb first.vdb || fail "$f: decoded during the bake (--threads 1) differs from decoded first"
  cmp -s later2.vdb first.vdb || fail "$f: decoded during the bake (--threads 2) differs from decoded first"
  expect_exit 0 "$vox" voxelize "$f" --res 48 --threads 2 --fill solid -o solid2.vdb
  expect_exit 0 "$vox" voxelize "$f" --res 48 --threads 1 --fill solid -o solid1.vdb
  cmp -s solid1.vdb solid2.vdb || fail "$f: solid fill differs between --threads 1 and 2"
  rm -f later*.vdb first.vdb solid*.vdb
done
# The textures make the colours: the untextured model bakes other ones.
expect_exit 0 "$vox" voxelize sphere.glb --res 48 -o a.vdb
expect_exit 0 "$vox" voxelize plain.glb --res 48 -o b.vdb
expect_exit 1 "$vox" diff a.vdb b.vdb --ignore-sources

# An image that does not decode: refused at the end of the bake as it was while reading.
python3 - <<'EOF' || fail "could not write bad.gltf"
import base64, json
d = json.load(open("box.gltf"))
d["images"][0] = {"uri": "data:image/png;base64," + base64.b64encode(b"not an image at all").decode()}
json.dump(d, open("bad.gltf", "w"))
EOF
for t in 1 2; do
  expect_exit 3 "$vox" voxelize bad.gltf --res 32 --threads $t -o refused.vdb --report refused.json
  expect_stderr "bad.gltf: image 0 cannot be decoded"
  expect_stderr "re-export it, or leave its textures out"
  [ ! -e refused.vdb ] || fail "--threads $t: refused but refused.vdb was written"
done
# With --ignore-missing-materials it is a warning and the box bakes untextured.
expect_exit 0 "$vox" voxelize bad.gltf --res 32 --ignore-missing-materials -o lenient.vdb
expect_stderr "cannot be decoded"

# A JPEG cut short: decoded as far as its data go (as viewers show it), with
# a warning naming the image, the same whether decoded during the bake or
# while reading, and in the report's warnings; a sound JPEG gives none.
if [ -e big.jpg ]; then
  python3 -c "d = open('big.jpg', 'rb').read(); open('cut.jpg', 'wb').write(d[:len(d) * 2 // 3])" || fail "could not cut big.jpg"
  python3 "$tests/../bench/make_textured_glb.py" cut.glb cutplain.glb cut.jpg t1.png t2.png t3.png t4.png ||
    fail "make_textured_glb.py failed (cut JPEG)"
  for how in later first; do
    extra=""
    [ $how = first ] && extra=--ignore-missing-materials
    expect_exit 0 "$vox" voxelize cut.glb --res 32 $extra -o "cut-$how.vdb" --report "cut-$how.json"
    expect_stderr "warning: cut.glb: image 0: damaged image data, decoded as far as they go (JPEG: "
    jcheck "cut-$how.json" "w = d['counts']['warnings']; assert len(w) == 1 and w[0].startswith('cut.glb: image 0: damaged image data'), w"
    cp err.txt "cut-$how.err"
  done
  cmp -s cut-later.vdb cut-first.vdb || fail "a damaged JPEG bakes differently during the bake and while reading"
  [ "$(grep -c 'damaged image data' cut-later.err)" = 1 ] || fail "the damaged image is not warned about once"
  expect_exit 0 "$vox" voxelize sphere-jpeg.glb --res 32 -o sound.vdb
  if grep -q "damaged image data" err.txt; then fail "a sound JPEG was called damaged"; fi
fi

[ "$failures" = 0 ] && echo "texoverlap: all passed" || { echo "texoverlap: $failures failure(s)"; exit 1; }
