#!/usr/bin/env bash
# End-to-end tests of `vox export`. Usage: export_test.sh GROUP VOX DATA_DIR TOOLS_DIR
# (DATA_DIR: tests/cli, for map_small.json; TOOLS_DIR: where tests/export/setup.sh
# installed the npm readers). Each group is one CTest test; expectations are
# computed by hand next to each command. Every .glb/.gltf a group writes is
# checked by the Khronos glTF validator at the end of the group (0 errors, 0 warnings).
set -u
group=$1 vox=$2 data=$3 tools=$4
here=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=../cli/test_lib.sh
. "$here/../cli/test_lib.sh"
# summary FILE: gltf_summary.py's JSON of FILE in FILE.summary.json
summary() { python3 "$here/gltf_summary.py" "$1" >"$1.summary.json" || fail "cannot read $1 back"; }
# nothing_but LIST: the work dir holds only these files (besides logs), e.g. after a failed run.
nothing_but() {
  local extra
  extra=$(ls -A | grep -v -x -F -e out.txt -e err.txt $(printf -- '-e %s ' "$@") || true)
  [ -z "$extra" ] || fail "unexpected files: $extra"
}
# Debian's python3 has Debian's numpy (scripts/install-deps.sh); another python3 may not.
numpy_python=python3
/usr/bin/python3 -c 'import numpy' 2>/dev/null && numpy_python=/usr/bin/python3
read_ply() { "$numpy_python" "$here/read_ply.py" "$@"; }
read_vox() { NODE_PATH="$tools/node_modules" node "$here/read_vox.mjs" "$1"; }
# A triangle whose vertex colours blend red, green and blue: many distinct voxel colours.
rgb_triangle() {
  printf 'v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nv 0 0 1 1 1 0\nf 1 2 3\nf 1 2 4\nf 1 3 4\n' >tri.obj
  expect_exit 0 "$vox" voxelize tri.obj --res "$1" -o tri.vdb
  rm tri.obj
}
# rename_class SRC.vpk DST.vpk OLD NEW: DST is SRC with the class table's text OLD
# replaced by NEW (same length) and the metadata and header CRC32Cs made good
# again: a page file whose voxels name a class its table no longer has.
rename_class() {
  python3 - "$@" <<'EOF2' || fail "cannot rewrite the class table of $1"
import struct, sys
def crc32c(data):
    crc = 0xFFFFFFFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ (0x82F63B78 if crc & 1 else 0)
    return crc ^ 0xFFFFFFFF
assert crc32c(b"123456789") == 0xE3069283
src, dst, old, new = sys.argv[1], sys.argv[2], sys.argv[3].encode(), sys.argv[4].encode()
b = bytearray(open(src, "rb").read())
off, n = struct.unpack_from("<QQ", b, 80)  # metadata offset and bytes (PAGEFILE.md "Header")
meta = bytes(b[off:off + n])
assert meta.count(old) == 1 and len(old) == len(new), old
b[off:off + n] = meta.replace(old, new)
struct.pack_into("<I", b, 112, crc32c(bytes(b[off:off + n])))
struct.pack_into("<I", b, 124, crc32c(bytes(b[:124])))
open(dst, "wb").write(b)
EOF2
}
validate_gltf() {
  local files=()
  mapfile -t files < <(find . -name '*.glb' -o -name '*.gltf' | sort)  # names may hold spaces
  [ ${#files[@]} -gt 0 ] || return 0
  NODE_PATH="$tools/node_modules" node "$here/validate_gltf.mjs" "${files[@]}" >validator.txt 2>&1 ||
    fail "glTF validator: $(cat validator.txt)"
}

case $group in
gltf)
  expect_exit 0 "$vox" voxelize "$data/map_small.json" -o small.vdb
  # map_small: Stone (0,0,0) (1,0,0), Grass (2,0,0), Water (0,1,0), Plank (3,2,1).
  # Visible faces: the row of three shows 14, Water on Stone hides 2 more and adds 5,
  # Plank alone shows 6: 24 faces, 48 triangles, 6 vertices per face unindexed.
  expect_exit 0 "$vox" export small.vdb -o small.glb --report r.json --depfile small.d
  expect_stderr "24 faces, 48 triangles"
  jcheck r.json "c=d['counts']; assert (c['faces'],c['triangles'],c['vertices'],c['indices'],c['voxels'])==(24,48,144,0,5)"
  jcheck r.json "c=d['counts']; assert c['buffer_bytes']==144*44 and c['bytes']>c['buffer_bytes'] and c['input_kind']=='scene'"
  jcheck r.json "assert [p['name'] for p in d['phases']]==['read','volume','mesh','write']"
  grep -q 'small.vdb' small.d || fail "depfile lacks the input"
  summary small.glb
  # Voxel size 2, origin (-64, 0, -64) (the block world 64 x 48 x 64): world bounds of blocks 0..3, 0..2, 0..1.
  jcheck small.glb.summary.json "p=d['primitives']; assert len(p)==1 and p[0]['vertices']==144 and p[0]['indices'] is None"
  jcheck small.glb.summary.json "p=d['primitives'][0]; assert p['min']==[-64,0,-64] and p['max']==[-56,6,-60]"
  # --dedup: 4 vertices and 6 UNSIGNED_SHORT indices per face.
  expect_exit 0 "$vox" export small.vdb -o dedup.glb --dedup --report rd.json
  jcheck rd.json "c=d['counts']; assert (c['vertices'],c['indices'])==(96,144) and c['buffer_bytes']==96*44+144*2"
  jcheck rd.json "c=d['counts']; assert c['buffer_bytes_without_dedup']==144*44 and abs(c['dedup_size_cut']-(1-(96*44+288)/(144*44)))<1e-12"
  summary dedup.glb
  jcheck dedup.glb.summary.json "p=d['primitives'][0]; assert p['indices']==144 and p['index_type']==5123"
  # --split classes: one primitive and material per class, by class id: Grass 5, Stone 8, Plank 6, Water 5 faces.
  expect_exit 0 "$vox" export small.vdb -o split.gltf --split classes
  [ -s split.bin ] || fail "split.bin not written beside split.gltf"
  summary split.gltf
  jcheck split.gltf.summary.json "assert d['materials']==['Grass','Stone','Plank','Water']"
  jcheck split.gltf.summary.json "assert [p['vertices'] for p in d['primitives']]==[30,48,36,30]"
  # --format overrides the extension; output bytes do not depend on --threads.
  expect_exit 0 "$vox" export small.vdb -o fmt.bin.out --format glb
  cmp -s fmt.bin.out small.glb || fail "--format glb differs from .glb"
  rm fmt.bin.out
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o h.vdb
  expect_exit 0 "$vox" export h.vdb -o h1.glb --threads 1
  expect_exit 0 "$vox" export h.vdb -o h2.glb --threads 2
  cmp -s h1.glb h2.glb || fail "glb differs between --threads 1 and 2"
  # --greedy: the two Stone faces below, in front and behind merge pairwise: 24 - 3 = 21 quads.
  expect_exit 0 "$vox" export small.vdb -o greedy.glb --greedy --report rg.json
  jcheck rg.json "c=d['counts']; assert (c['faces'],c['quads'],c['triangles'],c['culled_triangles'])==(24,21,42,48)"
  jcheck rg.json "c=d['counts']; assert abs(c['greedy_triangle_ratio']-48/42)<1e-12 and 'merge' in [p['name'] for p in d['phases']]"
  expect_exit 0 "$vox" export h.vdb -o g1.glb --greedy --dedup --split classes --threads 1 --report rh.json
  expect_exit 0 "$vox" export h.vdb -o g2.glb --greedy --dedup --split classes --threads 2
  cmp -s g1.glb g2.glb || fail "greedy glb differs between --threads 1 and 2"
  jcheck rh.json "c=d['counts']; assert c['greedy_triangle_ratio']>3 and c['faces']>c['quads']"
  # A .gltf names its .bin by a relative URI, percent-encoded: '#' would start a
  # fragment, '%' and ' ' are not URI characters, UTF-8 is encoded byte by byte.
  # Decoding it gives the .bin's name; the validator below reads the buffer through it.
  for name in 'a#b' 'c%d' 'e f' 'été'; do
    expect_exit 0 "$vox" export small.vdb -o "$name.gltf"
    [ -s "$name.bin" ] || fail "$name.bin not written beside $name.gltf"
    python3 - "$name" <<'EOF2' || fail "$name.gltf: the buffer URI is not its .bin's name percent-encoded"
import json, os, re, sys, urllib.parse
name = sys.argv[1]
uri = json.load(open(name + ".gltf", encoding="utf-8"))["buffers"][0]["uri"]
assert re.fullmatch(r"([A-Za-z0-9._~!*'()-]|%[0-9A-F]{2})+", uri), uri  # a '%' starts an escape
assert urllib.parse.unquote_to_bytes(uri) == os.fsencode(name + ".bin"), uri
EOF2
  done
  validate_gltf
  ;;
inputs)
  expect_exit 0 "$vox" voxelize "$data/map_small.json" -o small.vdb
  # --region (index box, inclusive) 0,0,0 .. 1,1,0: Stone, Stone, Water. Outside counts as
  # empty, so the +x face of (1,0,0) shows: 2 x 6 - 2 + 6 - 2 = 14 faces.
  expect_exit 0 "$vox" export small.vdb -o region.glb --region 0,0,0,1,1,0 --report rr.json
  jcheck rr.json "c=d['counts']; assert c['faces']==14 and c['voxels']==3 and c['region']=={'min':[0,0,0],'max':[1,1,0]}"
  # A page file of the same scene gives the same file (same stem, same blocks and placement).
  mkdir pages && expect_exit 0 "$vox" pack-chunks small.vdb -o pages/small.vpk --chunk 8
  expect_exit 0 "$vox" export pages/small.vpk -o pages/small.glb --report rp.json
  jcheck rp.json "assert d['counts']['input_kind']=='pages' and d['counts']['faces']==24"
  expect_exit 0 "$vox" export small.vdb -o small.glb
  cmp -s small.glb pages/small.glb || fail "page file and scene exports differ"
  # Levels: a pyramid's level 1 and a page file's level 1 are the same blocks.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 32 -o h.vdb
  expect_exit 0 "$vox" mip h.vdb -o p.vdb --levels 2
  expect_exit 0 "$vox" pack-chunks p.vdb -o p.vpk --mips
  expect_exit 0 "$vox" export p.vdb -o p1.glb --level 1 --report rl.json
  expect_exit 0 "$vox" export p.vpk -o q1.glb --level 1 --report rq.json
  jcheck rl.json "c=d['counts']; assert c['input_kind']=='pyramid' and c['dims']==[16,16,16] and abs(c['voxel_size']-1.6)<1e-12 and c['faces']>0"
  python3 -c "import json; a=json.load(open('rl.json'))['counts']; b=json.load(open('rq.json'))['counts']; assert (a['faces'],a['voxels'])==(b['faces'],b['voxels'])" ||
    fail "pyramid and page file level 1 differ"
  summary p1.glb && summary q1.glb
  cmp -s p1.glb.summary.json q1.glb.summary.json || fail "pyramid and page file level 1 meshes differ"
  # An empty region: a valid empty file and a warning.
  expect_exit 0 "$vox" export small.vdb -o empty.glb --region 0,2,0,0,2,0
  expect_stderr "warning"
  summary empty.glb
  jcheck empty.glb.summary.json "assert d['primitives']==[] and d['nodes']==0 and d['buffer_bytes']==0"
  expect_exit 0 "$vox" export small.vdb -o empty.gltf --region 0,2,0,0,2,0
  [ ! -e empty.bin ] || fail "an empty .gltf has no buffer file"
  # The other formats of an empty region: each a valid empty file, with the
  # warning, read back by the same outside readers as a full one.
  for out in "empty.ply" "empty.vox" "empty_fog.vdb --fog" "empty_ls.vdb --level-set"; do
    # shellcheck disable=SC2086
    expect_exit 0 "$vox" export small.vdb -o $out --region 0,2,0,0,2,0
    expect_stderr "no occupied voxel in the region"
  done
  read_ply empty.ply --points >eply.json || fail "numpy cannot read empty.ply"
  jcheck eply.json "assert d['count']==0 and d['points']==[] and d['properties']==['x','y','z','red','green','blue','class']"
  read_vox empty.vox >evox.json || fail "vox-reader cannot read empty.vox"
  jcheck evox.json "assert d['voxels']==[] and d['models']>=1 and len(d['palette'])==256"
  for f in empty_fog empty_ls; do
    vdb_print -l $f.vdb >$f.txt || fail "vdb_print cannot read $f.vdb"
    grep -q 'Number of active voxels: *0$' $f.txt || fail "$f.vdb is not empty: $(grep -i 'active voxels' $f.txt)"
  done
  grep -q 'class: fog volume' empty_fog.txt && grep -q 'class: level set' empty_ls.txt ||
    fail "the empty volumes lost their grid class"
  # --color voxel on a solid 16^3 cube whose surface is coloured (red) and whose
  # 14^3 interior is not (voxelize --fill solid), from the scene and its page
  # file alike: glTF counts the faces drawn with the palette colour (none; cut
  # by --region at w = 7, the 14 x 14 interior faces of that plane), PLY and
  # .vox every voxel they write (the 2744 interior ones). Warnings name the input.
  python3 - >cube.obj <<'EOF2'
corners = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
for c in corners: print('v %d %d %d 1 0 0' % c)
for a, b, c, d in [(1, 4, 3, 2), (5, 6, 7, 8), (1, 2, 6, 5), (2, 3, 7, 6), (3, 4, 8, 7), (4, 1, 5, 8)]:
    print('f %d %d %d\nf %d %d %d' % (a, b, c, a, c, d))
EOF2
  expect_exit 0 "$vox" voxelize cube.obj --res 16 --fill solid -o cube.vdb
  expect_exit 0 "$vox" pack-chunks cube.vdb -o cube.vpk
  for in in cube.vdb cube.vpk; do
    expect_exit 0 "$vox" export $in -o cube.glb --color voxel --report rc.json
    jcheck rc.json "c=d['counts']; assert (c['voxels'],c['faces'],c['faces_without_voxel_colour'])==(4096,1536,0), c"
    ! grep -q warning err.txt || fail "$in: a warning although every face drawn is coloured: $(cat err.txt)"
    expect_exit 0 "$vox" export $in -o half.glb --color voxel --region 0,0,0,15,15,7 --report rh.json
    jcheck rh.json "c=d['counts']; assert (c['faces'],c['faces_without_voxel_colour'])==(1024,196), c"
    expect_stderr "warning: $in: 196 faces of voxels without a baked colour take their class's palette colour"
    for f in ply vox; do
      expect_exit 0 "$vox" export $in -o cube.$f --color voxel --report r$f.json
      jcheck r$f.json "assert d['counts']['voxels_without_colour']==2744"
      expect_stderr "warning: $in: 2744 voxels have no baked colour; they have their class's display colour"
    done
  done
  validate_gltf
  ;;
usage)
  expect_exit 0 "$vox" voxelize "$data/map_small.json" -o small.vdb
  expect_exit 2 "$vox" export small.vdb
  expect_exit 2 "$vox" export small.vdb -o x.obj
  expect_stderr ".glb"
  expect_exit 2 "$vox" export small.vdb -o x.glb --format fbx
  expect_exit 2 "$vox" export small.vdb -o x.glb --color rainbow
  expect_exit 2 "$vox" export small.vdb -o x.glb --split nodes
  expect_exit 2 "$vox" export small.vdb -o x.glb --region 1,2,3
  expect_stderr "six integers"
  expect_exit 2 "$vox" export small.vdb -o x.glb --region 2,0,0,1,1,1
  expect_exit 2 "$vox" export missing.vdb -o x.glb --region 1,2   # the command line first
  expect_exit 2 "$vox" export small.vdb -o x.glb --level 1
  expect_stderr "single scene"
  expect_exit 2 "$vox" export small.vdb -o x.glb --level -1
  # Options of another format or mode are refused, even at their default value,
  # naming the option and what it belongs to.
  refused() { local want=$1; shift; expect_exit 2 "$vox" export small.vdb "$@"; expect_stderr "$want"; }
  refused "--half-width is an option of OpenVDB level sets (.vdb --level-set), but -o x.glb writes glTF (.glb): drop --half-width" \
    -o x.glb --half-width 5
  refused "--half-width is an option of OpenVDB level sets (.vdb --level-set), but -o x.vdb writes an OpenVDB fog volume (.vdb --fog)" \
    -o x.vdb --fog --half-width 3
  refused "--quantize is an option of MagicaVoxel palettes of baked colours (.vox --color voxel), but -o x.vox writes MagicaVoxel (.vox) with the class palette: add --color voxel" \
    -o x.vox --quantize
  refused "--quantize is an option of MagicaVoxel palettes of baked colours (.vox --color voxel), but -o x.ply writes PLY (.ply)" \
    -o x.ply --quantize --color voxel
  refused "--split is an option of glTF block meshes (.glb, .gltf), but -o x.ply writes PLY (.ply)" -o x.ply --split none
  refused "--dedup is an option of glTF block meshes" -o x.vox --dedup
  refused "--greedy is an option of glTF block meshes" -o x.vdb --level-set --greedy
  refused "--fog is an option of OpenVDB volumes (.vdb), but -o x.gltf writes glTF (.gltf)" -o x.gltf --fog
  refused "--level-set is an option of OpenVDB volumes (.vdb)" -o x.ply --level-set
  refused "--color is an option of coloured exports (.glb, .gltf, .ply, .vox), but -o x.vdb writes an OpenVDB level set" \
    -o x.vdb --level-set --color palette
  refused "give only one of --fog and --level-set" -o x.vdb --fog --level-set
  refused "give --fog or --level-set" -o x.vdb
  # --format names the format of an output without a known extension
  # (export.gltf: fmt.bin.out); it may repeat a known one, not contradict it.
  refused "--format ply contradicts -o out.glb, a .glb name: name the output .ply or drop --format" -o out.glb --format ply
  refused "--format glb contradicts -o out.gltf, a .gltf name: name the output .glb or drop --format" -o out.gltf --format glb
  refused "--format vox contradicts -o OUT.PLY, a .ply name" -o OUT.PLY --format vox
  nothing_but small.vdb
  expect_exit 0 "$vox" export small.vdb -o same.GLB --format glb
  expect_exit 0 "$vox" export small.vdb -o ls.vdb --level-set --half-width 2
  expect_exit 3 "$vox" export small.vdb -o q.vox --quantize --color voxel  # the options fit; the scene has no colours
  expect_stderr "small.vdb: the scene has no baked colours"
  ;;
bad_input)
  expect_exit 0 "$vox" voxelize "$data/map_small.json" -o small.vdb
  echo 'keep' >keep.glb
  expect_exit 3 "$vox" export missing.vdb -o keep.glb
  expect_stderr "no such file"
  echo 'not a scene' >notes.txt
  expect_exit 3 "$vox" export notes.txt -o keep.glb
  expect_stderr "not a scene"
  # dims 4 x 3 x 2: index box (0,0,0) .. (3,2,1)
  expect_exit 3 "$vox" export small.vdb -o keep.glb --region 0,0,0,4,2,1
  expect_stderr "not inside the scene's index box (0, 0, 0) .. (3, 2, 1)"
  expect_exit 3 "$vox" export small.vdb -o keep.glb --color voxel
  expect_stderr "small.vdb: the scene has no baked colours"
  # A page file packed from that scene has no colour channel: refused the same way, by every format.
  expect_exit 0 "$vox" pack-chunks small.vdb -o small.vpk
  for out in keep.glb keep.ply keep.vox; do
    expect_exit 3 "$vox" export small.vpk -o $out --color voxel
    expect_stderr "small.vpk: the page file has no baked colours; export the class palette (--color palette)"
  done
  # A voxel whose class the page file's table lacks (Water renamed from 7 to 9):
  # the file, the level when not 0, the chunk and the voxel are named, and the fix.
  rename_class small.vpk damaged.vpk '"id":7,"name":"Water"' '"id":9,"name":"Water"'
  for out in keep.glb keep.ply keep.vox; do
    expect_exit 3 "$vox" export damaged.vpk -o $out
    expect_stderr "damaged.vpk: chunk (0, 0, 0), voxel (0, 1, 0): class 7 has no entry in the file's class table"
    expect_stderr "damaged or was written by another tool: check it with 'vox pack-chunks --verify damaged.vpk' and pack it again from its scene"
  done
  # The check the message suggests finds the same voxel (exit 1: a check that failed).
  expect_exit 1 "$vox" pack-chunks --verify damaged.vpk
  expect_stderr "damaged.vpk: chunk 0 (level 0, chunk (0, 0, 0)): voxel (0, 1, 0) of level 0: field 'summary': class 7 is not in the metadata's class table"
  # Outside --region the voxel is not read: Stone, Stone, Grass export.
  expect_exit 0 "$vox" export damaged.vpk -o region.ply --region 0,0,0,3,0,1
  rm region.ply
  # Stone (3) renamed in a page file with levels: at level 1 it wins the block (0, 0, 0).
  expect_exit 0 "$vox" pack-chunks small.vdb -o mips.vpk --mips
  rename_class mips.vpk damaged_mips.vpk '"id":3,"name":"Stone"' '"id":9,"name":"Stone"'
  expect_exit 3 "$vox" export damaged_mips.vpk -o keep.glb --level 1
  expect_stderr "damaged_mips.vpk: level 1, chunk (0, 0, 0), voxel (0, 0, 0): class 3 has no entry"
  [ "$(cat keep.glb)" = keep ] || fail "a failed export touched the existing output"
  expect_exit 4 "$vox" export small.vdb -o no/such/dir/x.glb
  nothing_but small.vdb small.vpk damaged.vpk mips.vpk damaged_mips.vpk keep.glb notes.txt
  ;;
ply)
  expect_exit 0 "$vox" voxelize "$data/map_small.json" -o small.vdb
  expect_exit 0 "$vox" export small.vdb -o small.ply --report rp.json
  jcheck rp.json "c=d['counts']; assert c['points']==5 and c['bytes']==len(open('small.ply','rb').read())"
  read_ply small.ply --points >ply.json || fail "numpy cannot read small.ply"
  # Centres (index + 0.5) * 2 + (-64, 0, -64); colours are the classes' display colours.
  jcheck ply.json "assert d['properties']==['x','y','z','red','green','blue','class'] and d['count']==5"
  jcheck ply.json "assert d['points']==[[-63,1,-63,148,153,163,3],[-63,3,-63,56,102,168,7],[-61,1,-63,148,153,163,3],[-59,1,-63,87,173,92,1],[-57,5,-61,199,173,128,4]], d['points']"
  # The hamlet: every occupied voxel once, classes counted as vox info counts the winners.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o h.vdb
  expect_exit 0 "$vox" export h.vdb -o h.ply --threads 2
  expect_exit 0 "$vox" info --json h.vdb
  cp out.txt hinfo.json
  read_ply h.ply >hply.json || fail "numpy cannot read h.ply"
  python3 -c "
import json
i = json.load(open('hinfo.json')); p = json.load(open('hply.json'))
assert p['count'] == i['occupied'], (p['count'], i['occupied'])
assert p['classes'] == {str(c['id']): c['mode_voxels'] for c in i['classes'] if c['mode_voxels']}, p['classes']
lo = [o + (b + 0.5) * i['voxel_size'] for o, b in zip(i['origin'], i['bounds']['min'])]
assert all(abs(a - b) < 1e-4 for a, b in zip(p['min'], lo)), (p['min'], lo)
" || fail "h.ply disagrees with vox info"
  # --color voxel: the baked colour (sRGB); uncoloured voxels keep their class colour.
  rgb_triangle 16
  expect_exit 0 "$vox" export tri.vdb -o tri.ply --color voxel --report rc.json
  read_ply tri.ply --points >tply.json || fail "numpy cannot read tri.ply"
  jcheck tply.json "assert len(set(tuple(p[3:6]) for p in d['points']))>20"
  jcheck rc.json "assert d['counts']['voxels_without_colour']==0"
  ;;
vox)
  expect_exit 0 "$vox" voxelize "$data/map_small.json" -o small.vdb
  expect_exit 0 "$vox" export small.vdb -o small.vox --report rv.json
  jcheck rv.json "c=d['counts']; assert (c['models'],c['points'],c['size'],c['palette'])==(1,5,[4,2,3],'classes')"
  read_vox small.vox >vox.json || fail "vox-reader cannot read small.vox"
  # MagicaVoxel (x, y, z) = (u, wmax - w, v) - floor((4, 2, 3) / 2); palette index = class id.
  jcheck vox.json "assert d['models']==1 and d['voxels']==[[-2,0,-1,3],[-2,0,0,7],[-1,0,-1,3],[0,0,-1,1],[1,-1,1,4]], d['voxels']"
  jcheck vox.json "p=d['palette']; assert p[0]==[87,173,92,255] and p[2]==[148,153,163,255] and p[6]==[56,102,168,255] and len(p)==256"
  # Over 256 per axis: 301 x 6 x 271 blocks are 2 x 2 tiles of MagicaVoxel's (x, y) = (u, w):
  # four models, placed by the scene graph so the voxels land where they belong.
  printf '{"worldScale": 1.0, "blocks": [{"position": [0, 0, 0], "blockType": "Stone"}, {"position": [300, 0, 0], "blockType": "Grass"}, {"position": [0, 0, 270], "blockType": "Dirt"}, {"position": [300, 5, 270], "blockType": "Sand"}]}' >wide.json
  expect_exit 0 "$vox" voxelize wide.json --grid-size 400,48,400 -o wide.vdb
  expect_exit 0 "$vox" export wide.vdb -o wide.vox --report rw.json
  jcheck rw.json "c=d['counts']; assert (c['models'],c['points'],c['size'])==(4,4,[301,271,6])"
  read_vox wide.vox >wide_vox.json || fail "vox-reader cannot read wide.vox"
  jcheck wide_vox.json "assert d['models']==4 and d['voxels']==[[-150,-135,-3,2],[-150,135,-3,3],[150,-135,2,6],[150,135,-3,1]], d['voxels']"
  # The hamlet: the same voxels and classes as its point cloud.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o h.vdb
  expect_exit 0 "$vox" export h.vdb -o h.vox
  expect_exit 0 "$vox" export h.vdb -o h.ply
  read_vox h.vox >hvox.json && read_ply h.ply --points >hply.json || fail "cannot read the hamlet back"
  python3 -c "
import json
v = json.load(open('hvox.json')); p = json.load(open('hply.json'))
s, o = 25.6 / 64, (-12.8, 0.0, -12.8)  # the 64^3 hamlet's voxel size and origin; MagicaVoxel centres 64^3 at 32
want = []
for x, y, z, r, g, b, c in p['points']:
    u, vv, w = (round((a - oo) / s - 0.5) for a, oo in zip((x, y, z), o))
    want.append([u - 32, 63 - w - 32, vv - 32, c])
assert sorted(want) == v['voxels'], 'voxels differ'
" || fail "h.vox and h.ply disagree"
  # Baked colours: exact when at most 255, refused beyond unless quantised (error reported).
  rgb_triangle 32
  expect_exit 3 "$vox" export tri.vdb -o tri.vox --color voxel
  expect_stderr "--quantize"
  [ ! -e tri.vox ] || fail "a refused .vox was written"
  expect_exit 0 "$vox" export tri.vdb -o tri.vox --color voxel --quantize --report rq.json
  jcheck rq.json "c=d['counts']; q=d['error']['quantization']; assert c['distinct_colours']>255 and c['palette_colours']==255 and not q['exact'] and 0<q['mean_srgb8_distance']<12 and q['mean_srgb8_distance']<=q['max_srgb8_distance']<40"
  read_vox tri.vox >tvox.json || fail "vox-reader cannot read tri.vox"
  jcheck tvox.json "assert len(d['voxels'])==json.load(open('rq.json'))['counts']['points'] and max(x[3] for x in d['voxels'])<=255"
  ;;
vdb)
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o h.vdb
  expect_exit 0 "$vox" export h.vdb -o fog.vdb --fog --report rf.json
  expect_exit 0 "$vox" export h.vdb -o ls.vdb --level-set --report rl.json
  expect_exit 0 "$vox" info --json h.vdb
  cp out.txt hinfo.json
  # Bounds: the fog's active voxels are the scene's; the level set's band reaches
  # half width - 1 = 2 voxels past them on every side.
  python3 -c "
import json
i = json.load(open('hinfo.json')); f = json.load(open('rf.json'))['counts']; l = json.load(open('rl.json'))['counts']
assert f['active_voxels'] == i['occupied'] and f['active_box'] == i['bounds'], (f, i['bounds'])
assert l['active_box']['min'] == [m - 2 for m in i['bounds']['min']] and l['active_box']['max'] == [m + 2 for m in i['bounds']['max']], l
" || fail "exported volume bounds differ from the scene's"
  vdb_print -l fog.vdb >fog.txt && grep -q 'class: fog volume' fog.txt || fail "vdb_print: fog.vdb is not a fog volume"
  vdb_print -l ls.vdb >ls.txt && grep -q 'class: level set' ls.txt || fail "vdb_print: ls.vdb is not a level set"
  # vdb_render draws both: a non-empty image over a black background.
  for f in fog ls; do
    vdb_render $f.vdb $f.ppm -res 160x120 -translate 0,15,30 -lookat 0,2,0 -fov 60 -cpus 2 || fail "vdb_render failed on $f.vdb"
    python3 -c "
d = open('$f.ppm', 'rb').read().split(b'\\n', 3); px = d[3]
lit = sum(1 for i in range(0, len(px), 3) if px[i] or px[i + 1] or px[i + 2])
assert lit > 0.2 * len(px) / 3, lit
" || fail "vdb_render drew (almost) nothing for $f.vdb"
  done
  expect_exit 2 "$vox" export h.vdb -o x.vdb
  expect_exit 2 "$vox" export h.vdb -o x.vdb --fog --level-set
  expect_exit 2 "$vox" export h.vdb -o x.glb --fog
  ;;
pixel_match)
  # The exported .glb drawn by a real rasterizer (headless Chromium, WebGL2 on its
  # software GPU) with the terrain shader against render-canonical --mode shaded.
  chromium=$(command -v chromium || command -v chromium-browser || true)
  [ -n "$chromium" ] || { fail "chromium not found (scripts/install-deps.sh installs it)"; chromium=chromium; }
  python3 - <<'EOF2'
import json, math
# A 24 x 10 x 20 block world: hills of grass over dirt and stone, a pond, a snowy
# peak, a sand strip and a plank hut, in the block-map format.
blocks = []
for x in range(24):
    for z in range(20):
        h = 2 + int(3 + 2.5 * math.sin(x / 4.0) * math.cos(z / 5.0))
        for y in range(h):
            kind = "Stone" if y < h - 3 else "Dirt" if y < h - 1 else ("Snow" if h >= 7 else "Sand" if x < 3 else "Grass")
            blocks.append({"position": [x, y, z], "blockType": kind})
        if h < 4 and 8 <= x < 14: blocks.append({"position": [x, h, z], "blockType": "Water"})
for x in range(16, 20):
    for z in range(3, 6):
        for y in range(6, 8):
            blocks.append({"position": [x, y, z], "blockType": "Plank"})
json.dump({"worldScale": 2.0, "blocks": blocks}, open("world.json", "w"))
def lookat(eye, c, up):
    z = [eye[i] - c[i] for i in range(3)]; l = math.sqrt(sum(a * a for a in z)); z = [a / l for a in z]
    x = [up[1]*z[2]-up[2]*z[1], up[2]*z[0]-up[0]*z[2], up[0]*z[1]-up[1]*z[0]]; l = math.sqrt(sum(a * a for a in x)); x = [a / l for a in x]
    y = [z[1]*x[2]-z[2]*x[1], z[2]*x[0]-z[0]*x[2], z[0]*x[1]-z[1]*x[0]]
    d = lambda a, b: sum(a[i] * b[i] for i in range(3))
    return [x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0, -d(x, eye), -d(y, eye), -d(z, eye), 1]
def persp(fovy, aspect, n, f):
    t = 1 / math.tan(fovy / 2); nf = 1 / (n - f)
    return [t / aspect, 0, 0, 0, 0, t, 0, 0, 0, 0, (f + n) * nf, -1, 0, 0, 2 * f * n * nf, 0]
# World grid 32 x 16 x 32 at scale 2: blocks at x, z = (position - 16) * 2, centre about (-8, 6, -12).
views = []
for i, eye in enumerate([[30, 40, 30], [-60, 25, 15], [0, 55, -65]]):
    views.append({"id": "view_%03d" % i, "index": i, "position": eye, "viewMatrix": lookat(eye, [-8, 6, -12], [0, 1, 0]),
                  "projectionMatrix": persp(math.radians(60), 400 / 300, 0.1, 500.0)})
json.dump({"formatVersion": "1.0", "imageSize": {"width": 400, "height": 300}, "viewCount": 3, "views": views},
          open("metadata.json", "w"))
EOF2
  expect_exit 0 "$vox" voxelize world.json --grid-size 32,16,32 -o world.vdb
  expect_exit 0 "$vox" export world.vdb -o world.glb
  expect_exit 0 "$vox" export world.vdb -o world_dedup.glb --dedup
  expect_exit 0 "$vox" render-canonical world.vdb -o ref.png --camera metadata.json --mode shaded,canonical,normal
  for glb in world world_dedup; do
    python3 "$here/pixel_match.py" $glb.glb metadata.json ref "$chromium" "$vox" >$glb.match.jsonl 2>match.err ||
      fail "$glb.glb does not match render-canonical: $(cat $glb.match.jsonl match.err)"
    cat $glb.match.jsonl
    [ "$(grep -c '"pass": true' $glb.match.jsonl)" = 3 ] || fail "$glb.glb: not every view was compared"
    python3 -c "
import json
for line in open('$glb.match.jsonl'):
    r = json.loads(line); assert r['hits'] > 0.1 * r['pixels'], r
    assert r['differing_inside_faces'] == [], r  # every differing pixel lies on an edge
" || fail "$glb.glb: a view shows (almost) no blocks, or differs inside a face"
  done
  validate_gltf
  ;;
*)
  echo "unknown group $group" >&2
  exit 2
  ;;
esac

if [ "$failures" -gt 0 ]; then
  echo "export.$group: $failures failure(s)" >&2
  exit 1
fi
echo "export.$group: ok"
