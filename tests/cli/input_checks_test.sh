#!/usr/bin/env bash
# Inputs that are not what they claim and numbers at the edge of what a scene
# can hold: each gets a clear message naming the file or option and element,
# its documented exit code (2 usage, 3 bad input), and no output.
# Usage: input_checks_test.sh GROUP VOX_BINARY DATA_DIR
set -u
group=$1 vox=$2 data=$3
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

no_output() { [ ! -e "$1" ] || fail "$1 was written by a failed run"; }

case "$group" in
numbers)
  # NaN and infinities pass CLI11's own range checks; these options refuse them.
  for v in nan inf -1 0; do
    expect_exit 2 "$vox" voxelize demo:hamlet --voxel-size "$v" -o x.vdb
    expect_stderr "--voxel-size"
    no_output x.vdb
  done
  expect_exit 2 "$vox" voxelize demo:hamlet --res 16 --fov nan -o x.vdb 2>/dev/null || true
  expect_exit 0 "$vox" voxelize demo:hamlet --res 16 -o h.vdb
  expect_exit 2 "$vox" render-canonical h.vdb -o r.png --eye 0,5,40 --target 0,0,0 --fov nan
  expect_stderr "--fov"
  no_output r.png
  printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' > t.stl
  expect_exit 2 "$vox" voxelize t.stl --bounds 0,0,0,nan,1,1 -o x.vdb
  expect_stderr "--bounds expects six finite numbers"
  # Cameras: one limit (1e15 world units) with one exit code, however far.
  expect_exit 2 "$vox" render-canonical h.vdb -o r.png --eye 0,0,1e16 --target 0,0,0
  expect_stderr "within +-1e15 world units"
  expect_exit 2 "$vox" render-canonical h.vdb -o r.png --eye 0,0,1e300 --target 0,0,0
  expect_stderr "within +-1e15 world units"
  no_output r.png
  # Placements a scene cannot hold: block-map worldScale and tiny meshes.
  for s in 1e308 1e-300 1e-7; do
    printf '{"worldScale":%s,"blocks":[{"position":[0,0,0],"blockType":"Stone"}]}' "$s" > w.json
    expect_exit 3 "$vox" voxelize w.json -o x.vdb
    expect_stderr "w.json: 'worldScale' "
    expect_stderr "use a worldScale near 1"
    no_output x.vdb
  done
  printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1e-4 0 0\nvertex 0 1e-4 0\nendloop\nendfacet\nendsolid t\n' > tiny.stl
  expect_exit 2 "$vox" voxelize tiny.stl --res 64 -o x.vdb
  expect_stderr "below 1.5e-5 world units"
  no_output x.vdb
  expect_exit 0 "$vox" voxelize tiny.stl --res 4 -o ok.vdb
  ;;
files)
  # Only regular files are inputs: directories, FIFOs and devices are refused up front.
  mkdir d.obj
  expect_exit 3 "$vox" voxelize d.obj -o x.vdb
  expect_stderr "d.obj: is a directory"
  mkfifo p.stl
  expect_exit 3 timeout 10 "$vox" voxelize p.stl -o x.vdb
  expect_stderr "p.stl"
  expect_exit 3 "$vox" info /dev/zero
  printf 'mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > m.obj
  expect_exit 3 timeout 10 "$vox" voxelize m.obj -o x.vdb
  expect_stderr "/dev/zero"
  no_output x.vdb
  # A truncated ASCII STL: refused, not read short.
  printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n' > cut.stl
  expect_exit 3 "$vox" voxelize cut.stl -o x.vdb
  expect_stderr "truncated"
  no_output x.vdb
  # A canonical render whose metadata chunk was dropped cannot pass a check it cannot make.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 16 -o h.vdb
  expect_exit 0 "$vox" render-canonical h.vdb -o c.png --eye 20,20,20 --target 0,0,0 --size 32x24
  python3 - <<'PY' || fail "could not strip the PNG's text chunks"
import struct
data = open("c.png", "rb").read()
out, pos = bytearray(data[:8]), 8
while pos < len(data):
    n, = struct.unpack(">I", data[pos:pos + 4])
    kind = data[pos + 4:pos + 8]
    if kind not in (b"tEXt", b"iTXt", b"zTXt"):
        out += data[pos:pos + 12 + n]
    pos += 12 + n
open("stripped.png", "wb").write(bytes(out))
PY
  expect_exit 0 "$vox" verify-bijection --canonical c.png --scene h.vdb
  expect_exit 3 "$vox" verify-bijection --canonical stripped.png --scene h.vdb
  expect_stderr "stripped.png: has no render metadata"
  expect_exit 0 "$vox" verify-bijection --canonical stripped.png --scene h.vdb --eye 20,20,20 --target 0,0,0
  # The same dims placed elsewhere (a block map at another worldScale): named once, not a failure per ray.
  printf '{"worldScale":%s,"blocks":[{"position":[0,0,0],"blockType":"Stone"},{"position":[3,2,1],"blockType":"Dirt"}]}' 1 > m1.json
  printf '{"worldScale":%s,"blocks":[{"position":[0,0,0],"blockType":"Stone"},{"position":[3,2,1],"blockType":"Dirt"}]}' 2 > m2.json
  expect_exit 0 "$vox" voxelize m1.json -o m1.vdb
  expect_exit 0 "$vox" voxelize m2.json -o m2.vdb
  expect_exit 0 "$vox" render-canonical m1.vdb -o mc.png --view front --size 16x16
  expect_exit 0 "$vox" verify-bijection --canonical mc.png --scene m1.vdb
  expect_exit 3 "$vox" verify-bijection --canonical mc.png --scene m2.vdb
  expect_stderr "mc.png: rendered from a grid at origin"
  expect_stderr "but m2.vdb is at origin"
  ;;
outputs)
  # An output that is not a regular file (a FIFO here; /dev/null or /dev/stdout
  # alike) cannot be replaced whole: refused before the work, left as it was.
  mkfifo fifo.vdb fifo.json
  expect_exit 4 "$vox" voxelize demo:hamlet --res 16 -o fifo.vdb
  expect_stderr "fifo.vdb: cannot write: it is not a regular file"
  expect_exit 4 "$vox" voxelize demo:hamlet --res 16 -o ok.vdb --report fifo.json
  expect_stderr "fifo.json: cannot write: it is not a regular file"
  [ -p fifo.vdb ] && [ -p fifo.json ] || fail "a FIFO given as an output was replaced"
  no_output ok.vdb
  rm -f fifo.vdb fifo.json
  # '-' is no file: nothing goes to standard output, and no file named '-' appears.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 16 -o dash.vdb --quiet
  expect_exit 2 "$vox" export dash.vdb -o - --format ply
  expect_stderr "'-' names no file: vox writes every output, --report and --depfile to a file"
  expect_exit 2 "$vox" diff dash.vdb dash.vdb --report -
  expect_stderr "'-' names no file"
  expect_exit 2 "$vox" build-atlas dash.vdb -o -
  expect_stderr "-o -: build-atlas writes a directory of files, never standard output"
  [ ! -e - ] || fail "a file or directory named '-' was written"
  [ ! -s out.txt ] || fail "something went to standard output: $(head -c 100 out.txt)"
  rm -f dash.vdb
  # Failed runs leave nothing behind and nothing escapes -o.
  echo "not a scene" > bad.vdb
  expect_exit 3 "$vox" build-atlas bad.vdb -o atlases/deep
  [ ! -e atlases ] || fail "build-atlas left the directory it created: $(find atlases)"
  mkdir kept
  expect_exit 3 "$vox" build-atlas bad.vdb -o kept/new
  [ -d kept ] && [ ! -e kept/new ] || fail "build-atlas removed a directory it did not create, or kept its own"
  expect_exit 0 "$vox" voxelize demo:hamlet --res 16 -o h.vdb
  mkdir sub
  for stem in ../x x/y .. .; do
    expect_exit 2 "$vox" build-atlas h.vdb -o sub --stem "$stem"
    expect_stderr "--stem"
  done
  [ -z "$(ls -A sub)" ] && [ ! -e x.summary.png ] || fail "build-atlas --stem wrote outside -o: $(ls -A sub .)"
  expect_exit 0 "$vox" build-atlas h.vdb -o sub --stem ok
  [ -e sub/ok.summary.png ] || fail "build-atlas --stem ok wrote no sub/ok.summary.png"
  expect_exit 2 "$vox" pack-chunks h.vdb -o a.vdb
  expect_stderr "name it *.vpk"
  no_output a.vdb
  ;;
*)
  echo "unknown group $group" >&2
  exit 2
  ;;
esac
[ "$failures" = 0 ] || { echo "$failures failure(s) in input_checks.$group" >&2; exit 1; }
echo "input_checks.$group: ok"
