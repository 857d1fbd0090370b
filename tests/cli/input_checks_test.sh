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
  # A render cut or resized after rendering keeps the whole render's entry,
  # whose camera no longer gives its pixels' rays (every ray "differed", exit
  # 1): refused naming both sizes. A camera given for the image is used: the
  # entry's, its projection scaled and shifted to the cut, checks every pixel.
  oiiotool c.png --cut 16x10+8+6 -o cut.png || fail "oiiotool could not write cut.png"
  oiiotool c.png --resize 64x48 -o big.png || fail "oiiotool could not write big.png"
  expect_exit 3 "$vox" verify-bijection --canonical cut.png --scene h.vdb
  expect_stderr "cut.png is 16x10 but its vox:canonical camera was made for 32x24 (cropped or resized after rendering?)"
  expect_stderr "give the camera for this image with --camera FILE or --eye/--target"
  expect_exit 3 "$vox" verify-bijection --canonical big.png --scene h.vdb
  expect_stderr "big.png is 64x48 but its vox:canonical camera was made for 32x24"
  python3 - c.png 16 10 8 6 cut.json <<'PY' || fail "could not write the cut's camera"
import json, struct, sys
src, w, h, ox, oy, out = sys.argv[1], *map(int, sys.argv[2:6]), sys.argv[6]
data, pos = open(src, "rb").read(), 8
while pos < len(data):
    n, = struct.unpack(">I", data[pos:pos + 4])
    if data[pos + 4:pos + 8] == b"tEXt" and data[pos + 8:pos + 8 + n].startswith(b"vox:canonical\0"):
        cam = json.loads(data[pos + 22:pos + 8 + n])["camera"]
    pos += 12 + n
W, H, p = cam["imageSize"]["width"], cam["imageSize"]["height"], cam["projectionMatrix"]
# Column-major, row 3 is clip w: the cut's x_ndc = x_ndc W / w + (W - 2 ox) / w - 1 (y likewise, rows downward).
for c in range(4):
    p[4 * c] = p[4 * c] * W / w + ((W - 2 * ox) / w - 1) * p[4 * c + 3]
    p[4 * c + 1] = p[4 * c + 1] * H / h + (1 - (H - 2 * oy) / h) * p[4 * c + 3]
json.dump({"imageSize": {"width": w, "height": h}, "views": [{"viewMatrix": cam["viewMatrix"], "projectionMatrix": p}]}, open(out, "w"))
PY
  expect_exit 0 "$vox" verify-bijection --canonical cut.png --scene h.vdb --camera cut.json --json
  jcheck out.txt "assert d['ok'] and d['camera'] == 'command line' and d['hit_pixels'] > 0 and d['pixels_differing_from_ray'] == 0"
  # A missing input is worded the same by every command ("no such file", exit 3),
  # verify-bijection's --scene included (it said "missing or unreadable").
  expect_exit 0 "$vox" build-atlas h.vdb -o at --stem a
  while IFS= read -r cmd; do
    # shellcheck disable=SC2086
    expect_exit 3 "$vox" $cmd
    expect_stderr "missing.vdb: no such file"
  done <<'CMDS'
info missing.vdb
verify-bijection --atlas at/a.summary.png --scene missing.vdb
verify-bijection --canonical c.png --scene missing.vdb
render-canonical missing.vdb -o r.png --view front
build-atlas missing.vdb -o at2
mip missing.vdb -o m.vdb
pack-chunks missing.vdb -o m.vpk
export missing.vdb -o m.ply
diff missing.vdb h.vdb
CMDS
  no_output r.png; no_output at2; no_output m.vdb; no_output m.vpk; no_output m.ply
  ;;
unreadable)
  # A file that exists but cannot be read is named with the system's reason by
  # every command and option that reads one (the shared check opens it): the
  # readers that tell the kind from the first bytes called it "not a file vox
  # info reads", "not a scene" or "not a PNG or EXR image". Root reads
  # anything: as root this runs as nobody (setpriv) when nobody can run vox.
  as=()
  if [ "$(id -u)" = 0 ]; then
    command -v setpriv >/dev/null || { echo "SKIP: unreadable: running as root without setpriv"; exit 0; }
    as=(setpriv --reuid=65534 --regid=65534 --clear-groups)
    chmod 755 .
    "${as[@]}" test -x "$vox" || { echo "SKIP: unreadable: user nobody cannot run $vox"; exit 0; }
  fi
  expect_exit 0 "$vox" voxelize demo:hamlet --res 16 -o h.vdb --quiet
  expect_exit 0 "$vox" mip h.vdb -o hm.vdb --quiet
  expect_exit 0 "$vox" pack-chunks h.vdb -o h.vpk --quiet
  expect_exit 0 "$vox" build-atlas h.vdb -o at --stem a --quiet
  expect_exit 0 "$vox" render-canonical h.vdb -o c.png --view front --size 16x12 --quiet
  printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' > t.stl
  printf '{"worldScale":1,"blocks":[{"position":[0,0,0],"blockType":"Stone"}]}' > m.json
  for f in h.vdb hm.vdb h.vpk c.png at/a.summary.png t.stl m.json; do
    cp "$f" "u_${f##*/}" && chmod 000 "u_${f##*/}"
  done
  chmod 755 at
  mkdir out && chmod 777 out
  while IFS='|' read -r file cmd; do
    # shellcheck disable=SC2086
    expect_exit 3 "${as[@]}" "$vox" $cmd
    expect_stderr "$file: cannot open the file: Permission denied"
  done <<'CMDS'
u_h.vdb|info u_h.vdb
u_c.png|info u_c.png
u_h.vpk|info u_h.vpk
u_a.summary.png|info u_a.summary.png
u_m.json|info u_m.json
u_h.vdb|info at/a.summary.png --pixel 0,0 --scene u_h.vdb
u_h.vdb|diff u_h.vdb h.vdb
u_c.png|diff c.png u_c.png
u_h.vpk|diff u_h.vpk h.vpk
u_h.vdb|build-atlas u_h.vdb -o out/at
u_h.vdb|mip u_h.vdb -o out/m.vdb
u_h.vdb|pack-chunks u_h.vdb -o out/p.vpk
u_hm.vdb|pack-chunks u_hm.vdb -o out/p.vpk
u_h.vdb|render-canonical u_h.vdb -o out/r.png --view front
u_h.vpk|render-canonical u_h.vpk -o out/r.png --view front
u_h.vdb|export u_h.vdb -o out/e.ply
u_h.vpk|export u_h.vpk -o out/e.ply
u_t.stl|voxelize u_t.stl --res 4 -o out/x.vdb
u_m.json|voxelize u_m.json -o out/x.vdb
u_h.vdb|voxelize u_h.vdb --res 4 -o out/x.vdb
u_c.png|verify-bijection --canonical u_c.png --scene h.vdb
u_h.vdb|verify-bijection --canonical c.png --scene u_h.vdb
u_a.summary.png|verify-bijection --atlas u_a.summary.png --scene h.vdb
u_h.vdb|merge u_h.vdb -o out/x.vdb
CMDS
  [ -z "$(ls -A out)" ] || fail "failed runs left $(ls -A out) behind"
  ;;
lists)
  # Comma lists refuse an empty entry (a leading or trailing comma, two in a
  # row, an empty value) as a usage error naming the option and the entry:
  # `--mode depth,class,` rendered two modes without a word.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 16 -o h.vdb --quiet
  cam="--eye 20,20,20 --target 0,0,0 --size 16x12"
  # shellcheck disable=SC2086
  {
    expect_exit 2 "$vox" render-canonical h.vdb -o r.png $cam --mode depth,class,
    expect_stderr "vox render-canonical: error: --mode depth,class,: entry 3 of 3 is empty (a trailing comma); expected a comma list of canonical, class, "
    expect_exit 2 "$vox" render-canonical h.vdb -o r.png $cam --mode depth,,class
    expect_stderr "--mode depth,,class: entry 2 of 3 is empty (two commas in a row)"
    expect_exit 2 "$vox" render-canonical h.vdb -o r.png $cam --mode ,depth
    expect_stderr "--mode ,depth: entry 1 of 2 is empty (a leading comma)"
    expect_exit 2 "$vox" render-canonical h.vdb -o r.png $cam --mode ""
    expect_stderr "--mode '': an empty value"
    expect_exit 2 "$vox" render-canonical h.vdb -o r.png $cam --mode depth --mode class,
    expect_stderr "--mode class,: entry 2 of 2 is empty (a trailing comma)"
    expect_exit 2 "$vox" render-canonical h.vdb -o r.png $cam --mode depth,sketch
    expect_stderr "--mode depth,sketch: 'sketch' is not one of canonical, class"
    for f in r.png r.depth.exr r.class.png r.canonical.png; do no_output "$f"; done
    # Lists without empty entries, given once or repeated: each mode once, in the order given.
    expect_exit 0 "$vox" render-canonical h.vdb -o ok.png $cam --mode depth,class --mode class,normal --quiet
    for f in ok.depth.exr ok.class.png ok.normal.png; do [ -e "$f" ] || fail "--mode depth,class --mode class,normal wrote no $f"; done
  }
  # Every other comma-list option, split by the same code, says the same.
  expect_exit 2 "$vox" verify-bijection --dims 4,,4
  expect_stderr "--dims 4,,4: entry 2 of 3 is empty (two commas in a row)"
  expect_exit 2 "$vox" verify-bijection --dims 4,4,4,
  expect_stderr "--dims 4,4,4,: entry 4 of 4 is empty (a trailing comma)"
  expect_exit 2 "$vox" render-canonical h.vdb -o r.png --eye 20,20,20, --target 0,0,0
  expect_stderr "--eye 20,20,20,: entry 4 of 4 is empty (a trailing comma); expected X,Y,Z (three finite numbers)"
  expect_exit 2 "$vox" render-canonical h.vdb -o r.png --eye 20,20,20 --target ,0,0,0
  expect_stderr "--target ,0,0,0: entry 1 of 4 is empty (a leading comma)"
  printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' > t.stl
  expect_exit 2 "$vox" voxelize t.stl --bounds 0,0,0,1,1,1, -o x.vdb
  expect_stderr "--bounds 0,0,0,1,1,1,: entry 7 of 7 is empty (a trailing comma)"
  expect_exit 2 "$vox" voxelize "$data/map_small.json" --grid-size 64,,64 -o x.vdb
  expect_stderr "--grid-size 64,,64: entry 2 of 3 is empty"
  no_output x.vdb
  expect_exit 2 "$vox" export h.vdb -o e.ply --region 0,0,0,,4,4
  expect_stderr "--region 0,0,0,,4,4: entry 4 of 6 is empty (two commas in a row)"
  no_output e.ply
  expect_exit 2 "$vox" info h.vdb --pixel 1,
  expect_stderr "--pixel 1,: entry 2 of 2 is empty (a trailing comma)"
  ;;
json_keys)
  # JSON leaves a key named twice in one object to the reader, and the parser
  # kept the last silently: every JSON input refuses it (exit 3), naming the
  # file, the key and the object.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 16 -o h.vdb --quiet
  printf '{"eye": [20, 20, 20], "target": [0, 0, 0], "fov": 30, "fov": 90}' > cam.json
  expect_exit 3 "$vox" render-canonical h.vdb -o r.png --camera cam.json
  expect_stderr 'cam.json: duplicate key "fov" in the top-level object: JSON keeps only one of the values; remove the other'
  no_output r.png
  printf '{"cameras": [{"eye": [20, 20, 20], "target": [0, 0, 0]}, {"eye": [1, 2, 3], "target": [0, 0, 0], "up": [0, 1, 0], "up": [1, 0, 0]}]}' > cams.json
  expect_exit 3 "$vox" render-canonical h.vdb -o r.png --camera cams.json
  expect_stderr 'cams.json: duplicate key "up" in cameras[1]'
  m16='[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,-40,1]'
  printf '{"imageSize": {"width": 16, "height": 12, "width": 32}, "views": [{"viewMatrix": %s, "projectionMatrix": [1,0,0,0, 0,1,0,0, 0,0,-1,-1, 0,0,-0.2,0]}]}' "$m16" > metadata.json
  expect_exit 3 "$vox" render-canonical h.vdb -o r.png --camera metadata.json
  expect_stderr 'metadata.json: duplicate key "width" in imageSize'
  no_output r.png
  expect_exit 0 "$vox" render-canonical h.vdb -o c.png --eye 20,20,20 --target 0,0,0 --size 16x12 --quiet
  expect_exit 3 "$vox" verify-bijection --canonical c.png --scene h.vdb --camera cam.json
  expect_stderr 'cam.json: duplicate key "fov" in the top-level object'
  # Block maps, fuse views files, class mappings, glTF, and the JSON files info and diff read.
  printf '{"worldScale": 1, "blocks": [{"position": [0, 0, 0], "blockType": "Stone", "blockType": "Dirt"}]}' > map.json
  expect_exit 3 "$vox" voxelize map.json -o m.vdb
  expect_stderr 'map.json: duplicate key "blockType" in blocks[0]'
  no_output m.vdb
  printf '{"views": [{"depth": "a.exr", "label": "a.png", "depth": "b.exr"}]}' > views.json
  expect_exit 3 "$vox" fuse views.json -o f.vdb
  expect_stderr 'views.json: duplicate key "depth" in views[0]'
  no_output f.vdb
  printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' > t.stl
  printf '{"classes": [], "classes": []}' > classes.json
  expect_exit 3 "$vox" voxelize t.stl --res 4 --classes classes.json -o t.vdb
  expect_stderr 'classes.json: duplicate key "classes" in the top-level object'
  no_output t.vdb
  printf '{"asset": {"version": "2.0", "version": "2.0"}}' > dup.gltf
  expect_exit 3 "$vox" voxelize dup.gltf --res 4 -o g.vdb
  expect_stderr 'dup.gltf: duplicate key "version" in asset'
  no_output g.vdb
  expect_exit 0 "$vox" voxelize demo:hamlet --res 8 -o r.vdb --report report.json --quiet
  python3 -c "import sys; t=open('report.json').read(); open('dup_report.json','w').write(t.replace('{', '{\"tool\": \"vox\", ', 1))"
  expect_exit 3 "$vox" info dup_report.json
  expect_stderr 'dup_report.json: duplicate key "tool" in the top-level object'
  expect_exit 3 "$vox" diff dup_report.json report.json
  expect_stderr 'dup_report.json: duplicate key "tool" in the top-level object'
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
