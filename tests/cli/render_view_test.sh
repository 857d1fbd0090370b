#!/usr/bin/env bash
# render-canonical, seeing a scene end to end: --mode color and --shade-color
# (against class renders and against the page file's stored colours), named
# views and orbits (the camera printed, in the metadata, --camera-out giving a
# byte-identical re-render), --check's verdict and sampling, and progress bars
# that never go backwards.
# Usage: render_view_test.sh GROUP VOX_BINARY REPO_ROOT
set -u
group=$1 vox=$2 root=$3
data=$(realpath -m "${VOX_DATA:-$root/../shared/data}")
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

# png.py: pixels and text entries of a PNG (8/16-bit greyscale, RGB, RGBA) with the standard library only.
cat >png.py <<'EOF'
import struct, sys, zlib, hashlib, json
def read(path):
    data = open(path, 'rb').read()
    assert data[:8] == b'\x89PNG\r\n\x1a\n', path
    pos, idat, text = 8, b'', {}
    while pos < len(data):
        n, kind = struct.unpack('>I4s', data[pos:pos + 8]); body = data[pos + 8:pos + 8 + n]; pos += 12 + n
        if kind == b'IHDR': w, h, depth, ctype = struct.unpack('>IIBB', body[:10])
        elif kind == b'IDAT': idat += body
        elif kind == b'tEXt': k, v = body.split(b'\0', 1); text[k.decode()] = v.decode('latin-1')
    ch = {0: 1, 2: 3, 4: 2, 6: 4}[ctype]; bpp = ch * depth // 8; stride = w * bpp
    raw, out, prev = zlib.decompress(idat), bytearray(), bytearray(stride)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0; b = prev[i]; c = prev[i - bpp] if i >= bpp else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c; pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out += line; prev = line
    return w, h, ch, bytes(out), text
if __name__ == '__main__':
    w, h, ch, px, text = read(sys.argv[2])
    if sys.argv[1] == 'hash': print(hashlib.sha256(px).hexdigest())
    elif sys.argv[1] == 'meta': print(text.get('vox:canonical', ''))
EOF
pixels() { python3 png.py hash "$1"; }
meta() { python3 png.py meta "$1"; }

case $group in
color)
  expect_exit 0 "$vox" voxelize demo:hamlet --res 32 -o h.vdb
  cam="--eye 20,15,20 --target 0,2,0 --fov 40 --size 96x64"
  # A scene without colour: every hit shows its class colour, as the class mode does.
  expect_exit 0 "$vox" render-canonical h.vdb -o r.png $cam --mode class,color,shaded
  [ "$(pixels r.color.png)" = "$(pixels r.class.png)" ] || fail "color differs from class on a scene without colour"
  meta r.color.png | grep -q '"mode":"color"' || fail "color render's metadata: $(meta r.color.png)"
  expect_exit 0 "$vox" render-canonical h.vdb -o v.png $cam --mode shaded --shade-color voxel
  [ "$(pixels v.png)" = "$(pixels r.shaded.png)" ] || fail "--shade-color voxel differs on a scene without colour"
  expect_exit 2 "$vox" render-canonical h.vdb -o v.png $cam --mode shaded --shade-color texture
  expect_stderr "class|voxel"
  expect_exit 2 "$vox" render-canonical h.vdb -o v.png $cam --mode colour
  expect_stderr "color"
  mesh=$data/mesh-misc/assimp/cube_with_vertexcolors.obj
  if [ ! -e "$mesh" ]; then
    echo "SKIP: $mesh absent: the coloured-scene checks need ../shared/data" >&2
  else
    expect_exit 0 "$vox" voxelize "$mesh" --res 24 -o c.vdb
    expect_exit 0 "$vox" pack-chunks c.vdb -o c.vpk
    ccam="--view iso --size 80x60"
    expect_exit 0 "$vox" render-canonical c.vdb -o c.png $ccam --mode class,color,shaded
    expect_exit 0 "$vox" render-canonical c.vpk -o p.png $ccam --mode color
    # The scene's linear colours encoded here equal the sRGB bytes the page file stores.
    [ "$(pixels c.color.png)" = "$(pixels p.png)" ] || fail "color of the scene and of its page file differ"
    [ "$(pixels c.color.png)" != "$(pixels c.class.png)" ] || fail "a coloured scene's color render equals its class render"
    expect_exit 0 "$vox" render-canonical c.vdb -o cv.png $ccam --mode shaded --shade-color voxel
    [ "$(pixels cv.png)" != "$(pixels c.shaded.png)" ] || fail "--shade-color voxel ignored the voxel colours"
  fi
  ;;
views)
  expect_exit 0 "$vox" voxelize demo:hamlet --res 32 -o h.vdb
  for v in front back right side left top bottom iso; do
    expect_exit 0 "$vox" render-canonical h.vdb -o $v.png --view $v --size 64x48 --camera-out $v.json
    if [ "$v" = side ]; then expect_stderr "right: --eye "; else expect_stderr "$v: --eye "; fi
    meta $v.png | grep -q '"look_at":{' || fail "$v: no look_at in the metadata: $(meta $v.png)"
    # Re-rendering from the camera file gives the same bytes, metadata included.
    expect_exit 0 "$vox" render-canonical h.vdb -o again_$v.png --camera $v.json
    cmp -s $v.png again_$v.png || fail "$v: the render from --camera-out differs"
    # The framed camera: the whole occupied box within |NDC| <= 0.9, touching it.
    jcheck $v.json "import math; e=d['eye']; t=d['target']; assert d['size']==[64,48] and d['fov']==60 and math.dist(e,t)>0"
  done
  python3 - h.vdb <<'EOF' || fail "the hamlet is not framed within 0.9 in every view"
import json, sys
sys.path.insert(0, '.')
import png
for v in ['front', 'back', 'right', 'left', 'top', 'bottom', 'iso']:
    w, h, ch, px, text = png.read(v + '.png')
    m = json.loads(text['vox:canonical'])
    # hit pixels (alpha 255): none in the outer 5 % of the image, some near the 0.9 frame on some side
    xs = [i % w for i in range(w * h) if px[i * 4 + 3]]; ys = [i // w for i in range(w * h) if px[i * 4 + 3]]
    assert xs, v
    nx = [abs(2 * (x + 0.5) / w - 1) for x in xs]; ny = [abs(1 - 2 * (y + 0.5) / h) for y in ys]
    assert max(nx) <= 0.9 + 2.0 / w and max(ny) <= 0.9 + 2.0 / h, (v, max(nx), max(ny))
    assert max(max(nx), max(ny)) > 0.75, (v, max(nx), max(ny))
EOF
  # Orbits: NAME_000.png ..., one camera file, each view re-rendered byte for byte.
  expect_exit 0 "$vox" render-canonical h.vdb -o orbit.png --orbit 4 --size 48x32 --camera-out orbit.json --mode canonical,shaded
  for i in 000 001 002 003; do
    [ -e orbit_$i.canonical.png ] && [ -e orbit_$i.shaded.png ] || fail "orbit: no orbit_$i.*.png: $(ls)"
  done
  expect_stderr "orbit 3/4: --eye "
  jcheck orbit.json "assert len(d['cameras'])==4 and d['cameras'][2]['view']=='orbit 2/4'"
  expect_exit 0 "$vox" render-canonical h.vdb -o o1.png --orbit 1 --size 48x32
  [ -e o1_000.png ] || fail "--orbit 1 did not write o1_000.png"
  expect_exit 0 "$vox" render-canonical h.vdb -o again.png --camera orbit.json --view 2 --mode canonical
  cmp -s again.png orbit_002.canonical.png || fail "orbit view 2 from --camera-out differs"
  # The image's own camera checks out.
  expect_exit 0 "$vox" verify-bijection --canonical iso.png --scene h.vdb
  expect_exit 0 "$vox" verify-bijection --canonical iso.png --scene h.vdb --view iso --size 64x48
  # One image, one camera: several are refused naming the option given (it said "--camera  holds 2 views").
  expect_exit 2 "$vox" verify-bijection --canonical iso.png --scene h.vdb --orbit 2
  expect_stderr "--orbit 2 makes 2 cameras, but iso.png is one image"
  expect_exit 2 "$vox" verify-bijection --canonical iso.png --scene h.vdb --camera orbit.json
  expect_stderr "--camera orbit.json holds 4 views, but iso.png is one image; pick the one it was rendered from with --view INDEX"
  # A missing image is named as such (it said "not a PNG or EXR image").
  expect_exit 3 "$vox" verify-bijection --canonical nonexistent.png --scene h.vdb
  expect_stderr "nonexistent.png: no such file"
  # Usage errors name the options.
  expect_exit 2 "$vox" render-canonical h.vdb -o x.png --view diagonal
  expect_stderr "front, back, right, left, top, bottom, iso"
  expect_exit 2 "$vox" render-canonical h.vdb -o x.png --view top --eye 1,2,3
  expect_stderr "drop --camera/--eye/--target/--up"
  expect_exit 2 "$vox" render-canonical h.vdb -o x.png --orbit 3 --view top
  for n in 0 1001; do  # 0 was read as no orbit: "give --eye ... or --camera"
    expect_exit 2 "$vox" render-canonical h.vdb -o x.png --orbit $n
    expect_stderr "--orbit: Value $n not in range 1 to 1000"
  done
  expect_exit 2 "$vox" render-canonical h.vdb -o x.png --view 1
  expect_stderr "needs --camera"
  printf '{"views":[{"viewMatrix":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,-50,1],"projectionMatrix":[1,0,0,0,0,1,0,0,0,0,-1,-1,0,0,-0.2,0]}],"imageSize":{"width":8,"height":8}}' >meta.json
  expect_exit 2 "$vox" render-canonical h.vdb -o x.png --camera meta.json --camera-out m.json
  expect_stderr "look-at cameras only"
  [ ! -e x.png ] && [ ! -e m.json ] || fail "a refused run left files"
  # A refused run prints its error alone: the camera a named view or an orbit
  # frames is printed once every check has passed (it came before the output
  # name's check and the memory check, after the scene was read).
  only_error() { [ ! -s out.txt ] && [ "$(wc -l <err.txt)" = 1 ] || fail "$1: more than the error: $(cat out.txt err.txt)"; }
  expect_exit 2 "$vox" render-canonical h.vdb --view iso --mode depth,depth -o x.png
  expect_stderr "error: -o x.png: a depth render is written as .exr; name the file *.exr"
  only_error "--mode depth -o x.png"
  expect_exit 2 "$vox" render-canonical h.vdb --view iso -o x.exr
  expect_stderr "error: -o x.exr: a canonical render is written as .png"
  only_error "-o x.exr"
  # (1500M: the scene's reading fits even under ASan, whose shadow memory
  # makes the process 600 MiB resident; the 3 GiB of images do not.)
  expect_exit 4 "$vox" render-canonical h.vdb --orbit 2 --size 8000x8000 -o o.png --max-memory 1500M
  expect_stderr "error: rendering h.vdb needs about"
  only_error "--max-memory 1500M"
  # The names that do not depend on the scene are checked before it is read.
  expect_exit 2 "$vox" render-canonical nonexistent.vdb --view iso --mode class -o x.jpg
  expect_stderr "error: -o x.jpg: a class render is written as .png"
  # A camera given by hand: no look_at (the metadata is as before), its camera file re-renders the same bytes.
  expect_exit 0 "$vox" render-canonical h.vdb -o hand.png --eye 20,15,20 --target 0,2,0 --size 40x30 --camera-out hand.json
  ! meta hand.png | grep -q look_at || fail "a hand-given camera got a look_at entry"
  expect_exit 0 "$vox" render-canonical h.vdb -o hand2.png --camera hand.json
  cmp -s hand.png hand2.png || fail "the hand-given camera's --camera-out render differs"
  ;;
check)
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o h.vdb
  expect_exit 0 "$vox" render-canonical h.vdb -o r.png --view iso --size 120x90 --check --report r.json
  expect_stderr "check: all 10800 pixels checked against the voxel-walk reference"
  expect_stderr "none differ"
  jcheck r.json "c=d['check']; assert c['checked']==10800 and c['differing']==0 and c['fraction']==1 and c['sampled_one_in']==1 and c['reference']=='voxel-walk', c; e=d['error']; assert e['pixels_checked']==10800 and e['fraction_checked']==1, e"
  # A tiny time budget samples: "sampled 1 in K", with the fraction.
  expect_exit 0 "$vox" render-canonical h.vdb -o r.png --view iso --size 120x90 --check --check-seconds 0.000001 --report s.json
  expect_stderr "pixels checked (sampled 1 in "
  jcheck s.json "c=d['check']; k=c['sampled_one_in']; assert k>1 and c['checked']==-(-10800//k) and abs(c['fraction']-c['checked']/10800)<1e-12, c"
  ! grep -q "th pixel" err.txt || fail "ordinal wording: $(cat err.txt)"
  # The brute force, within its budget of ray-voxel tests.
  expect_exit 0 "$vox" render-canonical h.vdb -o r.png --view iso --size 120x90 --check --check-reference brute-force --check-budget 1e7 --report b.json
  expect_stderr "against the brute-force reference"
  jcheck b.json "c=d['check']; assert c['sampled_one_in']>1 and c['differing']==0 and c['reference']=='brute-force', c"
  expect_exit 2 "$vox" render-canonical h.vdb -o r.png --view iso --check --check-reference oracle
  # --quiet keeps the verdict off stderr when nothing differs.
  expect_exit 0 "$vox" render-canonical h.vdb -o r.png --view iso --size 40x30 --check --quiet
  [ ! -s err.txt ] || fail "--quiet printed: $(cat err.txt)"
  ;;
progress)
  expect_exit 0 "$vox" voxelize demo:hamlet --res 128 -o h.vdb
  for run in 1 2 3; do
    expect_exit 0 "$vox" render-canonical h.vdb -o r.png --view iso --size 640x2048 --threads 2 --check --progress
    python3 - <<'EOF' || fail "progress went backwards (run $run): $(tr '\r' '\n' <err.txt | head -c 600)"
import re
last = {}
for piece in open('err.txt').read().replace('\n', '\r').split('\r'):
    m = re.match(r'(\S+)\s+\[[# ]*\]\s+(\d+)%', piece)
    if not m: continue
    label, pct = m.group(1), int(m.group(2))
    assert pct >= last.get(label, -1), (label, last.get(label), pct)
    last[label] = pct
assert last.get('render') == 100 and last.get('check') == 100, last
EOF
  done
  ;;
*) echo "unknown group $group" >&2; exit 2 ;;
esac
[ $failures = 0 ] || { echo "$failures failure(s) in render_view.$group" >&2; exit 1; }
echo "render_view.$group: ok"
