#!/usr/bin/env bash
# End-to-end tests of `vox info` on every artefact, build-atlas --preview,
# class tables of mesh bakes, and mip --split / empty references.
# Usage: info_test.sh GROUP VOX_BINARY DATA_DIR
# Golden texts (tests/cli/info_golden/*.txt) are the exact text output with
# byte sizes masked (they follow the zlib / OpenVDB versions, not vox).
set -u
group=$1 vox=$2 data=$3
golden=$data/info_golden
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

# masked FILE: the text with byte counts ("51.8 kB", "363 B") replaced by <bytes>.
masked() { sed -E 's/[0-9]+(\.[0-9]+)? (B|kB|MB|GB)\b/<bytes>/g' "$1"; }
# golden NAME: out.txt (masked) equals info_golden/NAME.txt; VOX_UPDATE_GOLDEN=1 rewrites it.
golden() {
  if [ "${VOX_UPDATE_GOLDEN:-0}" = 1 ]; then masked out.txt >"$golden/$1.txt"; return; fi
  masked out.txt | diff -u "$golden/$1.txt" - >golden.diff || fail "info text differs from $1.txt: $(head -c 1500 golden.diff)"
}
# width.py: display columns as a terminal shows them (East Asian Wide and
# Fullwidth characters take two, combining marks and format characters none).
cat >width.py <<'PY'
import unicodedata as u
def width(s):
    def one(c):
        cat = u.category(c)
        if cat in ('Mn', 'Me') or (cat == 'Cf' and c != '\xad') or '\u1160' <= c <= '\u11ff':
            return 0
        return 2 if u.east_asian_width(c) in ('W', 'F') else 1
    return sum(one(c) for c in s)
PY
# fits: every line of out.txt fits an 80-column terminal.
fits() {
  local long
  long=$(python3 -c "from width import width; print('\n'.join(l for l in open('out.txt', encoding='utf-8').read().splitlines() if width(l) > 80))")
  [ -z "$long" ] || fail "lines of '$*' pass 80 columns: $(echo "$long" | head -3)"
}
small_scene() {
  cp "$data/map_small.json" map_small.json
  expect_exit 0 "$vox" voxelize map_small.json -o small.vdb
}
cube_obj() {
  cat >keep_cube.obj <<'OBJ'
mtllib keep_cube.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
usemtl Wall
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
usemtl Roof
f 4 1 5 8
OBJ
  printf 'newmtl Wall\nKd 0.5 0.5 0.5\nnewmtl Roof\nKd 1 0 0\nnewmtl Unused\nKd 0 1 0\n' >keep_cube.mtl
}

case $group in
scene)
  small_scene
  expect_exit 0 "$vox" info small.vdb
  golden scene; fits info small.vdb
  # The two memory forms: a leaf of 5 voxels packed is far below its OpenVDB tree (internal nodes, 512 values a leaf).
  expect_exit 0 "$vox" info small.vdb --json
  jcheck out.txt "assert 0 < d['packed_leaf_bytes'] < d['memory_bytes'] / 100, (d['packed_leaf_bytes'], d['memory_bytes'])"
  # --json keeps every digit: a voxel size of 1/3 is 1/3 to the last bit, the text rounds it.
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >keep_tri.obj
  expect_exit 0 "$vox" voxelize keep_tri.obj --res 3 -o third.vdb
  expect_exit 0 "$vox" info third.vdb --json
  jcheck out.txt "assert d['voxel_size']==1/3 and d['kind']=='scene' and d['classes'][0]['name']=='default', d['voxel_size']"
  jcheck out.txt "assert set(d)>={'file','kind','file_bytes','dims','voxel_size','origin','world_bounds','mip_level','occupied','surface','interior','colored','has_color','bounds','classes','memory_bytes','packed_leaf_bytes','sources'}"
  expect_exit 0 "$vox" info third.vdb
  expect_stdout "voxel size    0.333333 world units"
  fits info third.vdb
  # A pyramid: the levels as a table.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 16 -o h.vdb
  expect_exit 0 "$vox" mip h.vdb -o p.vdb --levels 2
  expect_exit 0 "$vox" info p.vdb
  golden pyramid; fits info p.vdb
  ;;
artefacts)
  small_scene
  expect_exit 0 "$vox" build-atlas small.vdb -o a --all
  expect_exit 0 "$vox" info a/small.summary.png --pixel 0,0
  golden summary_atlas; fits info summary
  # The summary bytes explained: Stone wins voxel (0,0,0) with its one vote.
  expect_stdout "meaning       Stone (class 3)"
  expect_stdout "confidence 100% (255/255)"
  expect_stdout "observations 16 (total votes 1)"
  expect_exit 0 "$vox" info a/small.votes.3.png
  golden votes_atlas; fits info votes
  expect_stdout "votes atlas (r8) of Stone (class 3)"
  expect_exit 0 "$vox" info a/small.occupancy.png --pixel 1,0
  golden occupancy; fits info occupancy
  expect_exit 0 "$vox" info a/small.occupancy2.png
  fits info occupancy2
  expect_stdout "2 bits per voxel"
  # The scene is found beside the atlas when the atlas is read from elsewhere.
  (cd a && "$vox" info small.votes.7.png >../out.txt 2>../err.txt) || fail "info from the atlas directory"
  expect_stdout "of class 7"
  expect_exit 0 "$vox" info a/small.votes.7.png --scene small.vdb
  expect_stdout "of Water (class 7)"
  # Page file, render, touched set.
  expect_exit 0 "$vox" pack-chunks small.vdb -o small.vpk --chunk 8
  expect_exit 0 "$vox" info small.vpk
  golden pagefile; fits info small.vpk
  expect_exit 0 "$vox" render-canonical small.vdb -o r.png --eye -48,12,-48 --target -60,2,-62 --size 32x24 --touched t.json
  expect_exit 0 "$vox" info r.png
  golden render; fits info r.png
  expect_exit 0 "$vox" info t.json
  golden touched; fits info t.json
  ;;
json)
  small_scene
  expect_exit 0 "$vox" build-atlas small.vdb -o a --report rep.json
  expect_exit 0 "$vox" info rep.json
  fits info rep.json
  expect_stdout "report of \`vox build-atlas\`, exit 0"
  expect_stdout "occupied_voxels"
  expect_exit 0 "$vox" info rep.json --json
  jcheck out.txt "assert d['kind']=='report' and d['command']=='build-atlas' and d['file']=='rep.json'"
  expect_exit 0 "$vox" render-canonical small.vdb -o r.png --eye -48,12,-48 --target -60,2,-62 --size 32x24 --touched t.json
  expect_exit 0 "$vox" info t.json --json
  jcheck out.txt "assert d['kind']=='touched' and d['format']=='voxbake-touched' and d['summary']['chunks_touched']==len(d['chunks'])"
  expect_exit 0 "$vox" info a/small.summary.png --json --pixel 0,0
  jcheck out.txt "p=d['pixel']; assert d['kind']=='atlas' and p['voxel']==[0,0,0] and p['summary']=={'cls':3,'conf':255,'obs':16,'mrg':255,'class_name':'Stone'}, p"
  jcheck out.txt "t=d['texels']; assert t['nonzero']==5 and [c['id'] for c in t['per_class']]==[1,3,4,7] and t['per_class'][1]['texels']==2"
  # The atlas sidecar: the files of the run.
  expect_exit 0 "$vox" info a/small.atlas.json
  fits info small.atlas.json
  expect_stdout "atlas sidecar"
  expect_stdout "small.occupancy.png"
  expect_exit 0 "$vox" info a/small.atlas.json --json
  jcheck out.txt "assert d['kind']=='atlas_sidecar' and len(d['files'])==2"
  # Unsupported files: the error lists every kind vox info reads.
  echo '{"hello": 1}' >keep_other.json
  expect_exit 3 "$vox" info keep_other.json
  for kind in ".vdb" ".png" ".exr" ".vpk" "touched set" "run report" "canonical render" "occupancy bitmap" "atlas sidecar"; do
    expect_stderr "$kind"
  done
  echo 'plain text' >keep_text.txt
  expect_exit 3 "$vox" info keep_text.txt
  for kind in ".vdb" ".png" ".vpk" "touched set" "run report"; do expect_stderr "$kind"; done
  expect_exit 2 "$vox" info rep.json --pixel 1,1
  ;;
preview)
  small_scene
  expect_exit 0 "$vox" build-atlas small.vdb -o a --all --preview --report rep.json
  jcheck rep.json "assert d['counts']['previews']==d['counts']['files']//2 and d['counts']['files']==2*d['counts']['previews']+1"
  for f in summary identity occupancy occupancy2 votes.1 votes.3 votes.4 votes.7; do
    [ -f "a/small.$f.preview.png" ] || fail "no preview of small.$f.png"
  done
  grep -q preview a/small.atlas.json && fail "previews are not atlases: the sidecar lists data files only"
  # Pixels, decoded with zlib: voxel (0,0,0) is Stone (#9499a3), (2,0,0) Grass (#57ad5c); 4 x 3 tiles of 2.
  python3 - <<'PY' || fail "preview pixels"
import struct, zlib, json
def png(path):
    b = open(path, 'rb').read(); i = 8; idat = b''; hdr = None; text = {}; plte = None
    while i < len(b):
        n, t = struct.unpack('>I', b[i:i+4])[0], b[i+4:i+8]; d = b[i+8:i+8+n]
        if t == b'IHDR': hdr = struct.unpack('>IIBBBBB', d)
        if t == b'PLTE': plte = [tuple(d[k:k+3]) for k in range(0, len(d), 3)]
        if t == b'IDAT': idat += d
        if t == b'tEXt': k, v = d.split(b'\0', 1); text[k.decode()] = v.decode()
        i += 12 + n
    w, h, depth, ctype = hdr[:4]; ch = {0: 1, 2: 3, 3: 1, 6: 4}[ctype]; bpp = ch; raw = zlib.decompress(idat)
    rows = []; prev = bytearray(w * bpp); p = 0
    for y in range(h):
        f = raw[p]; line = bytearray(raw[p+1:p+1+w*bpp]); p += 1 + w * bpp
        for x in range(len(line)):
            a = line[x-bpp] if x >= bpp else 0; up = prev[x]; c = prev[x-bpp] if x >= bpp else 0
            if f == 1: line[x] = (line[x] + a) & 255
            elif f == 2: line[x] = (line[x] + up) & 255
            elif f == 3: line[x] = (line[x] + (a + up) // 2) & 255
            elif f == 4:
                pa, pb, pc = abs(up - c), abs(a - c), abs(a + up - 2 * c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else up if pb <= pc else c)) & 255
        rows.append(line); prev = line
    if ctype == 3:  # indexed colour: expand through the palette to RGB
        rows = [bytearray(c for v in r for c in plte[v]) for r in rows]; ch = 3
    return w, h, ch, rows, text
atlas = json.load(open('a/small.atlas.json'))['layout']
W, H = atlas['width'], atlas['height']
X, Y, T = atlas['dims'][0], atlas['dims'][1], atlas['tiles_per_row']
def texel(u, v, w): return (w % T) * X + u, (w // T) * Y + v
w, h, ch, rows, text = png('a/small.summary.preview.png')
assert (w, h, ch) == (3 * W, H, 3), (w, h, ch)
def rgb(x, y): return tuple(rows[y][x*3:x*3+3])
x, y = texel(0, 0, 0); assert rgb(x, y) == (0x94, 0x99, 0xa3), rgb(x, y)
x, y = texel(2, 0, 0); assert rgb(x, y) == (0x57, 0xad, 0x5c), rgb(x, y)
# One vote each: confidence 255 -> the ramp's end (253, 231, 37); observations 16 -> (70, 23, 104).
assert rgb(W + x, y) == (253, 231, 37) and rgb(2 * W + x, y) == (70, 23, 104), (rgb(W + x, y), rgb(2 * W + x, y))
x, y = texel(1, 1, 0); assert rgb(x, y) == (0, 0, 0), 'an empty voxel (Air) is black'
assert 'small.summary.png' in text['vox:preview']
w, h, ch, rows, _ = png('a/small.occupancy.preview.png')
assert (w, h, ch) == (W, H, 1)
lit = sorted((x, y) for y in range(h) for x in range(w) if rows[y][x])
assert all(rows[y][x] == 255 for x, y in lit) and lit == sorted(texel(*v) for v in [(0,0,0),(1,0,0),(2,0,0),(0,1,0),(3,2,1)]), lit
w, h, ch, rows, _ = png('a/small.occupancy2.preview.png')
assert sorted(set(v for r in rows for v in r)) == [0, 170], 'occupied, never touched: 170'
w, h, ch, rows, text = png('a/small.votes.3.preview.png')
x, y = texel(0, 0, 0); assert ch == 1 and rows[y][x] == 255 and 'Stone' in text['vox:preview']
PY
  # Determinism: the same previews at any thread count.
  expect_exit 0 "$vox" build-atlas small.vdb -o b --all --preview --threads 1
  for f in a/*.preview.png; do cmp -s "$f" "b/$(basename "$f")" || fail "$f differs between --threads 2 and 1"; done
  expect_exit 0 "$vox" info a/small.summary.preview.png
  expect_stdout "preview of small.summary.png"
  ;;
classes)
  cube_obj
  # Two inputs with the same materials: one class per name, no "Wall #2".
  expect_exit 0 "$vox" voxelize keep_cube.obj keep_cube.obj --res 8 -o two.vdb
  expect_exit 0 "$vox" info two.vdb --json
  jcheck out.txt "assert [(c['id'],c['name']) for c in d['classes']]==[(1,'Wall'),(2,'Roof')], d['classes']"
  # "Unused" is in the MTL but no face uses it: left out.
  jcheck out.txt "assert all(c['voxels']>0 for c in d['classes'])"
  # --bounds leaves the Roof face (x = 0) outside: Roof has no voxel and is left out after voxelizing.
  expect_exit 0 "$vox" voxelize keep_cube.obj --res 8 --bounds 0.5,0,0,1,1,1 -o cut.vdb
  expect_exit 0 "$vox" info cut.vdb --json
  jcheck out.txt "assert [(c['id'],c['name']) for c in d['classes']]==[(1,'Wall')], d['classes']"
  expect_exit 0 "$vox" build-atlas cut.vdb -o cuta --summary
  expect_exit 0 "$vox" info cuta/cut.summary.png --json
  jcheck out.txt "assert [c['id'] for c in d['texels']['per_class']]==[1], 'the summary atlas uses the renumbered ids'"
  # The same scene through the OpenVDB path (--check) and the direct path.
  expect_exit 0 "$vox" voxelize keep_cube.obj keep_cube.obj --res 8 -o two_full.vdb --check
  expect_exit 0 "$vox" diff two.vdb two_full.vdb
  # The OpenVDB paths (--check, --method sdf) leave the emptied class out as well.
  expect_exit 0 "$vox" voxelize keep_cube.obj --res 8 --bounds 0.5,0,0,1,1,1 -o cut_full.vdb --check
  expect_exit 0 "$vox" diff cut.vdb cut_full.vdb
  expect_exit 0 "$vox" voxelize keep_cube.obj --res 8 --bounds 0.5,0,0,1,1,1 -o cut_sdf.vdb --method sdf
  expect_exit 0 "$vox" info cut_sdf.vdb --json
  jcheck out.txt "assert [(c['id'],c['name']) for c in d['classes']]==[(1,'Wall')], d['classes']"
  # A mesh without materials: the grey default class.
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >keep_plain.obj
  expect_exit 0 "$vox" voxelize keep_plain.obj --res 4 -o plain.vdb
  expect_exit 0 "$vox" info plain.vdb --json
  jcheck out.txt "assert [(c['name'],c['color']) for c in d['classes']]==[('default',[150,150,150])], d['classes']"
  # Ids of a --classes file are the user's: kept, only unused classes go.
  printf '{"classes":[{"name":"roof","id":9,"match":["material:Roof"]},{"name":"spare","id":5,"match":["material:Nothing"]},{"name":"rest","id":3}],"default":"rest"}' >keep_classes.json
  expect_exit 0 "$vox" voxelize keep_cube.obj --res 8 -o c.vdb --classes keep_classes.json
  expect_exit 0 "$vox" info c.vdb --json
  jcheck out.txt "assert [(c['id'],c['name']) for c in d['classes']]==[(3,'rest'),(9,'roof')], d['classes']"
  ;;
atlas_inputs)
  # Atlases whose metadata was changed after vox wrote them (tests/cli/png_text.py).
  small_scene
  expect_exit 0 "$vox" build-atlas small.vdb -o a --summary
  retext() { python3 "$(dirname "$0")/png_text.py" "$@" || fail "png_text.py $*"; }
  # A layout of 2^32 - 1 slices with a maximum side of 2^32 - 1: refused at
  # once (the layout search divided by zero there after 14 s).
  retext a/small.summary.png huge.png vox:atlas '{"content":"summary","format":"rgba8","layer":0,"layout":{"dims":[1,1,4294967295],"height":1,"layers":1,"max_side":4294967295,"rows_per_layer":1,"tiles_per_row":0,"width":1},"scene":"small.vdb"}'
  expect_exit 3 timeout 20 "$vox" info huge.png
  expect_stderr "huge.png: atlas layout field 'tiles_per_row' must be >= 1"
  retext a/small.summary.png huge1.png vox:atlas '{"content":"summary","format":"rgba8","layer":0,"layout":{"dims":[1,1,4294967295],"height":1,"layers":1,"max_side":4294967295,"rows_per_layer":1,"tiles_per_row":1,"width":1},"scene":"small.vdb"}'
  expect_exit 3 timeout 20 "$vox" info huge1.png
  expect_stderr "huge1.png: inconsistent atlas layout"
  expect_exit 3 timeout 20 "$vox" diff huge1.png a/small.summary.png
  expect_stderr "huge1.png: inconsistent atlas layout"
  # --scene must be the scene the atlas was built from: other dims are refused
  # (its votes would be another scene's), as verify-bijection refuses them.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 8 -o h8.vdb
  expect_exit 3 "$vox" info a/small.summary.png --pixel 0,0 --scene h8.vdb
  expect_stderr "a/small.summary.png: built for dims 4 x 3 x 2 but h8.vdb has 8 x 8 x 8"
  expect_exit 3 "$vox" info a/small.summary.png --scene h8.vdb --json
  [ ! -s out.txt ] || fail "info printed the atlas with another scene's class names"
  expect_exit 0 "$vox" info a/small.summary.png --pixel 0,0 --scene small.vdb
  # A directory or a FIFO as --scene is refused up front, like any input.
  expect_exit 3 "$vox" info a/small.summary.png --scene .
  expect_stderr ".: is a directory, expected a regular file (--scene)"
  mkfifo keep_fifo
  expect_exit 3 timeout 20 "$vox" info a/small.summary.png --scene keep_fifo
  expect_stderr "keep_fifo: is a FIFO"
  # The scene the atlas names, found with other dims: not used, and said so.
  mkdir other && cp a/small.summary.png other/ && cp h8.vdb other/small.vdb
  (cd other && "$vox" info small.summary.png --json >../out.txt 2>../err.txt) || fail "info with a stale scene beside it"
  jcheck out.txt "assert 'classes_from' not in d and d['scene_not_used']==\"small.vdb has dims 8 x 8 x 8, not the atlas's\", d"
  # Renders: the scene must be the rendered grid, the same dims and placement.
  expect_exit 0 "$vox" render-canonical small.vdb -o r.png --eye -48,12,-48 --target -60,2,-62 --size 32x24
  expect_exit 0 "$vox" info r.png --pixel 16,12 --scene small.vdb --json
  jcheck out.txt "assert d['pixel']['hit'] and d['pixel']['scene_voxel'] is not None, d['pixel']"
  expect_exit 3 "$vox" info r.png --pixel 16,12 --scene h8.vdb
  expect_stderr "r.png: rendered from a grid of 4 x 3 x 2 but h8.vdb has 8 x 8 x 8"
  sed 's/"worldScale": 2.0/"worldScale": 1.0/' map_small.json > keep_scale1.json
  expect_exit 0 "$vox" voxelize keep_scale1.json -o scale1.vdb
  expect_exit 3 "$vox" info r.png --pixel 16,12 --scene scale1.vdb
  expect_stderr "with voxel size 2.0 but scale1.vdb is at"
  expect_exit 3 "$vox" info r.png --pixel 0,0 --scene h8.vdb
  expect_stderr "rendered from a grid of 4 x 3 x 2"
  # --pixel is x,y in whole numbers: anything else is refused, not truncated
  # ("1.5,2" was read as 1,2) or passed over ("" was ignored).
  for bad in 1.5,2 " 1,2" "1 ,2" 1,2,3 -1,2 +1,2 1e0,2 0x1,2 4294967296,0; do
    expect_exit 2 "$vox" info a/small.summary.png --pixel "$bad"
    expect_stderr "--pixel '$bad': expected x,y, two whole numbers"
  done
  # An empty value or entry is named as every comma-list option names it.
  expect_exit 2 "$vox" info a/small.summary.png --pixel ""
  expect_stderr "--pixel '': an empty value; expected x,y, two whole numbers"
  expect_exit 2 "$vox" info a/small.summary.png --pixel 1,
  expect_stderr "--pixel 1,: entry 2 of 2 is empty (a trailing comma); expected x,y, two whole numbers"
  expect_exit 2 "$vox" info a/small.summary.png --pixel ,2
  expect_stderr "--pixel ,2: entry 1 of 2 is empty (a leading comma)"
  expect_exit 2 "$vox" info a/small.summary.png --pixel 4,0
  expect_stderr "--pixel 4,0: outside the 4 x 6 atlas (x 0..3, y 0..5)"
  expect_exit 0 "$vox" info a/small.summary.png --pixel 003,5
  expect_exit 2 "$vox" info r.png --pixel 1.5,2
  expect_exit 2 "$vox" info a/small.summary.png --scene ""
  # --pixel and --scene decode atlases and canonical renders (--scene with a
  # render: with --pixel); on any other file they are refused, not ignored.
  expect_exit 0 "$vox" build-atlas small.vdb -o p --summary --preview
  expect_exit 0 "$vox" pack-chunks small.vdb -o small.vpk --chunk 8
  expect_exit 0 "$vox" build-atlas small.vdb -o rep --summary --report rep.json
  for file in p/small.summary.preview.png small.vdb small.vpk rep.json a/small.atlas.json; do
    expect_exit 2 "$vox" info "$file" --pixel 0,0
    expect_stderr "--pixel applies to atlases and canonical renders, not to"
    expect_exit 2 "$vox" info "$file" --scene small.vdb
    expect_stderr "--scene applies to atlases and canonical renders, not to"
  done
  expect_exit 2 "$vox" info r.png --scene small.vdb
  expect_stderr "--scene with a render goes with --pixel x,y"
  expect_exit 0 "$vox" info a/small.summary.png --scene small.vdb
  # Counts and units in the singular where one.
  printf '{"worldScale": 1.0, "blocks": [{"position": [0, 0, 0], "blockType": "Stone"}]}' > keep_one.json
  expect_exit 0 "$vox" voxelize keep_one.json -o one.vdb
  expect_exit 0 "$vox" info one.vdb
  expect_stdout "dims          1 x 1 x 1 (1 voxel)"
  expect_stdout "voxel size    1 world unit"
  expect_stdout "occupied      1 voxel (100% of the domain)"
  expect_exit 0 "$vox" build-atlas one.vdb -o o --summary --occupancy --threads 1 --report o.json
  expect_exit 0 "$vox" info o/one.summary.png
  expect_stdout "1 texel in use"
  expect_stdout "1 tile of 1 x 1 per row, 1 tile row"
  expect_exit 0 "$vox" info o/one.occupancy.png
  expect_stdout "1 bit set"
  expect_exit 0 "$vox" info o/one.atlas.json
  expect_stdout "1 x 1 texels, 1 tile per row, 1 layer"
  expect_exit 0 "$vox" info o.json
  expect_stdout "s on 1 thread"
  expect_exit 0 "$vox" verify-bijection --dims 1,1,1 --threads 1
  expect_stdout "1 voxel, 1 texel (0 padding), 0 failures"
  expect_stdout "on 1 thread ("
  expect_exit 0 "$vox" verify-bijection --atlas o/one.summary.png --scene one.vdb
  expect_stdout "1 texel checked, 0 differ"
  # A malformed entry is named in words, not by the JSON library's exception.
  retext o/one.summary.png nocontent.png vox:atlas '{"format":"rgba8","layer":0,"layout":{"dims":[1,1,1],"height":1,"layers":1,"max_side":16384,"rows_per_layer":1,"tiles_per_row":1,"width":1},"scene":"one.vdb"}'
  expect_exit 3 "$vox" info nocontent.png
  expect_stderr "nocontent.png: malformed \"vox:atlas\" metadata: no \"content\" key"
  grep -q "json.exception" err.txt && fail "nlohmann's exception text in a message: $(cat err.txt)"
  ;;
mip)
  expect_exit 0 "$vox" voxelize demo:hamlet --res 16 -o h.vdb
  # --split takes the stem its help promises, or OUT.vdb.
  expect_exit 0 "$vox" mip h.vdb -o lod --split --levels 2
  [ -f lod.mip1.vdb ] && [ -f lod.mip2.vdb ] || fail "--split -o lod: no lod.mipN.vdb"
  expect_exit 0 "$vox" mip h.vdb -o lod2.vdb --split --levels 1
  [ -f lod2.mip1.vdb ] || fail "--split -o lod2.vdb: no lod2.mip1.vdb"
  expect_exit 2 "$vox" mip h.vdb -o lod
  expect_stderr "--split"
  expect_exit 2 "$vox" mip h.vdb -o dir/ --split
  # An empty reference: no IoU, the reason instead (not 0.0).
  printf 'v 100 100 100\nv 101 100 100\nv 100 101 100\nf 1 2 3\n' >keep_far.obj
  expect_exit 0 "$vox" mip h.vdb -o m.vdb --source keep_far.obj --report m.json
  jcheck m.json "E=d['error']['levels']; assert E and all(e['iou'] is None and e['iou_reason']=='no reference voxels' and e['reference_voxels']==0 for e in E), E"
  expect_stderr "no reference voxels"
  expect_exit 0 "$vox" mip h.vdb -o m2.vdb --source demo:hamlet --report m2.json
  # The hamlet at --res 2 and 1 is empty (nothing of the design covers a voxel centre): levels 3 and 4.
  jcheck m2.json "E=d['error']['levels']; assert [e['level'] for e in E]==[1,2,3,4] and all(0<e['iou']<=1 and e['iou_reason'] is None for e in E[:2]), E"
  jcheck m2.json "E=d['error']['levels']; assert all(e['iou'] is None and e['iou_reason']=='no reference voxels' and e['mip_voxels']>0 for e in E[2:]), E"
  expect_stderr "IoU"
  # The report, read by a person: tables too wide for 80 columns become wrapped lines.
  expect_exit 0 "$vox" info m2.json
  fits info m2.json
  expect_stdout "iou_reason no reference voxels"
  ;;
wide)
  # Class names in CJK, fullwidth and with combining marks: aligned by the
  # columns a terminal gives them, cut with an ellipsis to fit 80.
  cube_obj
  long=$(printf '非常に長い材料の名前はこの表の幅に収まらないので省略記号で切られます')
  sed -i "s/usemtl Wall/usemtl 石头/; s/usemtl Roof/usemtl $long/" keep_cube.obj
  printf 'f 1 2 3\nusemtl Ｃａｆｅ\xcc\x81\nf 1 3 4\n' >>keep_cube.obj
  printf 'newmtl 石头\nKd 0.5 0.5 0.5\nnewmtl %s\nKd 1 0 0\nnewmtl Ｃａｆｅ\xcc\x81\nKd 0 1 0\n' "$long" >keep_cube.mtl
  expect_exit 0 "$vox" voxelize keep_cube.obj --res 8 -o w.vdb
  expect_exit 0 "$vox" info w.vdb
  fits info w.vdb
  expect_stdout "石头"
  expect_stdout "…"
  python3 - <<'PY' || fail "the class table of w.vdb is not aligned: $(grep -A4 ' id  name' out.txt)"
from width import width
lines = open('out.txt', encoding='utf-8').read().splitlines()
start = next(i for i, l in enumerate(lines) if l.startswith('    id  name'))
rows = [l for l in lines[start + 1:] if l.startswith('    ') and '#' in l]
assert len(rows) == 3, rows
names = ' '.join(rows)
assert '石头' in names and 'Ｃａｆｅ\u0301' in names, names
# the colour column starts at one display column in the header and every row; rows end together
header = lines[start]
col = width(header[:header.index('colour')])
assert all(width(r[:r.index('#')]) == col for r in rows), [width(r[:r.index('#')]) for r in rows]
assert len({width(r) for r in rows + [header]}) == 1, [width(r) for r in rows + [header]]
PY
  # A fused scene's free-grid line is wrapped within 80 columns at the value's column.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 16 -o h.vdb --quiet
  expect_exit 0 "$vox" render-canonical h.vdb -o o.png --orbit 2 --size 40x30 --mode depth,class --quiet
  python3 -c "import json; json.dump({'views': [{'depth': 'o_%03d.depth.exr' % i, 'label': 'o_%03d.class.png' % i} for i in range(2)]}, open('views.json', 'w'))"
  expect_exit 0 "$vox" fuse views.json -o f.vdb --quiet
  expect_exit 0 "$vox" info f.vdb
  fits info f.vdb
  grep -A1 "^  free grid     'free' (" out.txt >free.txt || fail "no free grid line: $(cat out.txt)"
  python3 - <<'PY' || fail "the free grid line is not wrapped at the value's column: $(cat free.txt)"
lines = open('free.txt', encoding='utf-8').read().splitlines()
assert len(lines) == 2 and lines[1].startswith(' ' * 16) and lines[1][16] != ' ', lines
assert 'read back by vox fuse -i (docs/fuse.md)' in ' '.join(l.strip() for l in lines), lines
PY
  ;;
*)
  echo "unknown group $group" >&2
  exit 2
  ;;
esac
[ "$failures" = 0 ] || exit 1
