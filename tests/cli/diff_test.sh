#!/usr/bin/env bash
# End-to-end tests of `vox diff` (docs/diff.md), one group per kind of file.
# Usage: diff_test.sh GROUP VOX TESTS_DIR
set -u
group=$1
vox=$2
tests=$3
. "$tests/cli/test_lib.sh"

# Block maps that differ by exactly one block: m2 turns the block at (5, 5, 5)
# from Grass into Dirt (one voxel whose votes differ, class 1:1 -> 2:1); m3
# adds an isolated block at (0, 5, 0) (one voxel only in B, no neighbour whose
# surface flag could change); m4 one at (0, 6, 0), which makes the dims 6 x 7 x 6.
maps() {
  cat > m1.json <<'EOF'
{"worldScale": 1.0, "blocks": [{"position": [1, 1, 1], "blockType": "Stone"}, {"position": [2, 1, 1], "blockType": "Stone"},
 {"position": [5, 5, 5], "blockType": "Grass"}, {"position": [3, 4, 2], "blockType": "Plank"}]}
EOF
  sed 's/"Grass"/"Dirt"/' m1.json > m2.json
  sed 's/"blocks": \[/"blocks": [{"position": [0, 5, 0], "blockType": "Snow"}, /' m1.json > m3.json
  sed 's/"blocks": \[/"blocks": [{"position": [0, 6, 0], "blockType": "Snow"}, /' m1.json > m4.json
  for m in m1 m2 m3 m4; do
    "$vox" voxelize $m.json -o $m.vdb --grid-size 8,8,8 --quiet || fail "voxelize $m"
  done
}

jq_py() { python3 -c "import json,sys; d=json.load(open('out.txt')); $1" || fail "json check: $1 ($(head -c 300 out.txt))"; }

case $group in
scenes)
  maps
  expect_exit 0 "$vox" diff m1.vdb m1.vdb
  expect_stdout "same"
  # One voxel whose votes differ: a vote difference, not an occupancy one.
  expect_exit 1 "$vox" diff m1.vdb m2.vdb --ignore-sources
  expect_stdout "DIFFERENT: 4 voxels compared, 1 differ"
  expect_stdout "votes      1"
  expect_stdout "first voxel (5, 5, 5) world (1.5, 5.5, 1.5): A surface votes{1:1} | B surface votes{2:1}"
  expect_exit 1 "$vox" diff m1.vdb m2.vdb --ignore-sources --json
  jq_py "k=d['kinds']; assert d['voxels_differing']==1 and k['votes']['count']==1 and k['occupancy']['count']==0 and k['surface']['count']==0, d; assert k['votes']['first']['voxel']==[5,5,5] and k['votes']['first']['a']['votes']=={'1':1} and k['votes']['first']['b']['votes']=={'2':1}"
  # The tolerance at its boundary: the largest difference of one class is 1 vote.
  expect_exit 0 "$vox" diff m1.vdb m2.vdb --ignore-sources --votes-tolerance 1
  expect_exit 1 "$vox" diff m1.vdb m2.vdb --ignore-sources --votes-tolerance 0
  # Without --ignore-sources the map files' digests differ too.
  expect_exit 1 "$vox" diff m1.vdb m2.vdb --votes-tolerance 1
  expect_stdout "header sources"
  # Counts in the singular where one; numbers in their shortest exact form.
  printf '{"worldScale": 1.0, "blocks": [{"position": [0, 0, 0], "blockType": "Stone"}]}' > o1.json
  sed 's/Stone/Dirt/' o1.json > o2.json
  "$vox" voxelize o1.json -o o1.vdb --quiet && "$vox" voxelize o2.json -o o2.vdb --quiet
  expect_exit 1 "$vox" diff o1.vdb o2.vdb --ignore-sources
  expect_stdout "DIFFERENT: 1 voxel compared, 1 differ (scenes 1 x 1 x 1)"
  expect_exit 0 "$vox" diff o1.vdb o2.vdb --ignore-sources --votes-tolerance 1
  expect_stdout "same: 1 voxel compared, 0 differ"
  "$vox" voxelize demo:hamlet --res 8 -o h8.vdb --quiet
  "$vox" voxelize demo:hamlet --res 16 -o h16.vdb --quiet
  expect_exit 1 "$vox" diff h8.vdb h16.vdb
  expect_stdout "header voxel_size: 3.2 vs 1.6"
  # One voxel only in B.
  expect_exit 1 "$vox" diff m1.vdb m3.vdb --ignore-sources --json
  jq_py "assert d['voxels_differing']==1 and d['only_in_b']==1 and d['only_in_a']==0 and d['kinds']['occupancy']['first']['voxel']==[0,5,0], d"
  # Header differences are named (dims of the hamlet at two resolutions).
  "$vox" voxelize demo:hamlet --res 12 -o h12.vdb --quiet
  "$vox" voxelize demo:hamlet --res 11 -o h11.vdb --quiet
  expect_exit 1 "$vox" diff h12.vdb h11.vdb
  expect_stdout "header dims: 12 x 12 x 12 vs 11 x 11 x 11"
  expect_stdout "header voxel_size"
  expect_stdout "(scenes 12 x 12 x 12 vs 11 x 11 x 11)"
  # A voxel only in B is where B's header places it (A's voxel size and origin
  # put (11, 0, 0) elsewhere); one in both gives both positions.
  expect_exit 1 "$vox" diff h11.vdb h12.vdb --json
  cp out.txt d1112.json
  "$vox" info h12.vdb --json > i12.json
  "$vox" info h11.vdb --json > i11.json
  python3 - <<'EOF2' || fail "world positions of B's voxels"
import json
d, b, a = (json.load(open(f)) for f in ('d1112.json', 'i12.json', 'i11.json'))
assert d['dims_a'] == [11, 11, 11] and d['dims_b'] == [12, 12, 12], d
def world(h, v): return [h['origin'][k] + (v[k] + 0.5) * h['voxel_size'] for k in range(3)]
f = d['kinds']['occupancy']['first']
assert f['a'] is None and f['voxel'] == [11, 0, 0] and f['world'] == world(b, f['voxel']), f
v = d['kinds']['votes']['first']
assert v['world'] == world(a, v['voxel']) and v['world_b'] == world(b, v['voxel']), v
EOF2
  # Pyramids: per level, and a level count that differs.
  "$vox" mip h12.vdb -o p12.vdb --quiet
  "$vox" mip h12.vdb -o p12b.vdb --quiet --threads 1
  "$vox" mip h12.vdb -o p12c.vdb --quiet --levels 2
  expect_exit 0 "$vox" diff p12.vdb p12b.vdb
  expect_stdout "level 3"
  expect_exit 1 "$vox" diff p12.vdb p12c.vdb --json
  jq_py "assert d['kind']=='pyramid' and d['levels_a']==5 and d['levels_b']==3 and not d['same'], d['levels_a']"
  # --level: one level of each side; a plain scene (a --split file, the base scene) is taken as that level.
  "$vox" mip h12.vdb -o lod.vdb --split --levels 2 --quiet
  expect_exit 0 "$vox" diff p12.vdb lod.mip1.vdb --level 1
  expect_stdout "same: "
  expect_stdout "level 1"
  expect_exit 1 "$vox" diff p12.vdb lod.mip1.vdb --level 2
  expect_exit 0 "$vox" diff p12.vdb h12.vdb --level 0
  expect_exit 1 "$vox" diff p12.vdb h12.vdb
  expect_stdout "--level N compares one level"
  expect_stdout "pyramid metadata differs at the top level: "
  expect_exit 0 "$vox" diff p12.vdb p12c.vdb --level 2 --json
  jq_py "assert d['same'] and d['level']==2, d"
  expect_exit 2 "$vox" diff p12.vdb p12c.vdb --level 3
  expect_stderr "p12c.vdb has levels 0..2; --level 3 is not one of them"
  "$vox" pack-chunks h12.vdb -o h12.vpk --quiet
  expect_exit 2 "$vox" diff h12.vpk h12.vpk --level 1
  expect_stderr "--level applies to scenes and pyramids"
  # The same results at any thread count.
  "$vox" diff h12.vdb h11.vdb --json --threads 1 > t1.json
  "$vox" diff h12.vdb h11.vdb --json --threads 2 > t2.json
  cmp -s t1.json t2.json || fail "diff --json differs between --threads 1 and 2"
  ;;
images)
  maps
  "$vox" build-atlas m1.vdb -o a1 --summary --occupancy --quiet
  "$vox" build-atlas m2.vdb -o a2 --summary --occupancy --quiet
  "$vox" build-atlas m3.vdb -o a3 --summary --quiet
  expect_exit 0 "$vox" diff a1/m1.summary.png a1/m1.summary.png
  expect_stdout "PASS"
  # An EXR channel beside R, G, B, A is not compared, and the diff says so.
  oiiotool --create 4x4 2 --chnames R,Z -d float -o rz.exr || fail "oiiotool could not write rz.exr"
  expect_exit 0 "$vox" diff rz.exr rz.exr --report rz_report.json
  expect_stderr "warning: rz.exr: 1 channel not compared (Z)"
  jcheck rz_report.json "assert d['counts']['channels_not_compared'] == {'rz.exr': ['Z']}, d['counts']"
  # One texel: named by its pixel, channel and voxel.
  expect_exit 1 "$vox" diff a1/m1.summary.png a2/m2.summary.png --diff-image d.png
  expect_stdout "1 pixel (0.463%) differs"
  expect_stdout "1 pixel (0.463%) over 1e-06 (fail)"
  expect_stdout "= voxel (5, 5, 5)  values are 1, 255, 16, 255 vs 2, 255, 16, 255"
  expect_stdout "FAILURE"
  expect_exit 1 "$vox" diff a1/m1.summary.png a2/m2.summary.png --json
  jq_py "assert d['pixels_differing']==1 and d['max_error_at']['voxel']==[5,5,5] and d['max_error_at']['channel']=='R' and abs(d['max_error']-1/255)<1e-15, d"
  # The difference image: one pixel of 255 * |1 - 2| / 255 = 1 in red, x 50 with --diff-scale.
  python3 - <<'EOF' || fail "difference image"
import struct, zlib
def read(p):
    b = open(p, 'rb').read(); i = 8; idat = b''; w = h = 0
    while i < len(b):
        n, t = struct.unpack('>I4s', b[i:i + 8]); d = b[i + 8:i + 8 + n]
        if t == b'IHDR': w, h, depth, ctype = struct.unpack('>IIBB', d[:10]); assert depth == 8 and ctype == 2
        if t == b'IDAT': idat += d
        i += 12 + n
    raw = zlib.decompress(idat); stride = w * 3; rows = []; prev = bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]; line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - 3] if x >= 3 else 0; up = prev[x]; c = prev[x - 3] if x >= 3 else 0
            if f == 1: line[x] = (line[x] + a) & 255
            elif f == 2: line[x] = (line[x] + up) & 255
            elif f == 3: line[x] = (line[x] + (a + up) // 2) & 255
            elif f == 4:
                p = a + up - c; pa, pb, pc = abs(p - a), abs(p - up), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else up if pb <= pc else c)) & 255
        rows.append(line); prev = line
    return w, h, rows
w, h, rows = read('d.png')
nonzero = [(x, y, tuple(rows[y][3 * x:3 * x + 3])) for y in range(h) for x in range(w) if any(rows[y][3 * x:3 * x + 3])]
assert nonzero == [(11, 17, (1, 0, 0))], nonzero
EOF
  # --diff-image OUT.exr: an EXR of float differences, not rounded or clamped
  # (510 * 1/255 = 2); another extension is refused before the work.
  expect_exit 1 "$vox" diff a1/m1.summary.png a2/m2.summary.png --diff-image d.exr --diff-scale 510
  [ "$(head -c 4 d.exr | od -An -tx1 | tr -d ' ')" = 762f3101 ] || fail "d.exr is not an EXR file"
  iinfo --stats d.exr > stats.txt 2>&1 || fail "iinfo cannot read d.exr: $(cat stats.txt)"
  grep -q "Stats Max: 2.000000 0.000000 0.000000 (float)" stats.txt || fail "d.exr stats: $(cat stats.txt)"
  expect_exit 2 "$vox" diff a1/m1.summary.png a2/m2.summary.png --diff-image d.tif
  expect_stderr "--diff-image d.tif: the difference image is written as .png (RGB8) or .exr (float)"
  [ ! -e d.tif ] || fail "a refused --diff-image was written"
  # Images of other sizes have no pixel pairs to draw: an earlier difference
  # image under the name is said to be left as it was, not passed off as new.
  oiiotool --create 4x4 3 -o s4.png && oiiotool --create 5x5 3 -o s5.png || fail "oiiotool could not make images"
  echo OLD > old.png
  expect_exit 1 "$vox" diff s4.png s5.png --diff-image old.png
  expect_stderr "no difference image written"
  expect_stderr "old.png is an earlier run's, left as it was"
  [ "$(cat old.png)" = OLD ] || fail "the earlier difference image was touched"
  # idiff's thresholds: the error is 1/255 = 0.0039.
  expect_exit 0 "$vox" diff a1/m1.summary.png a2/m2.summary.png --fail 0.004
  expect_stdout "WARNING"
  expect_exit 0 "$vox" diff a1/m1.summary.png a2/m2.summary.png --fail 0.004 --warn 0.004
  expect_stdout "PASS"
  expect_exit 1 "$vox" diff a1/m1.summary.png a2/m2.summary.png --fail 0.0039
  expect_exit 0 "$vox" diff a1/m1.summary.png a2/m2.summary.png --failpercent 0.47 --warnpercent 0.47
  expect_exit 1 "$vox" diff a1/m1.summary.png a2/m2.summary.png --failpercent 0.46
  expect_exit 1 "$vox" diff a1/m1.summary.png a2/m2.summary.png --failpercent 1 --hardfail 0.0039
  # Bitmaps: the differing bit's voxel (m3's extra block at (0, 5, 0)).
  "$vox" build-atlas m3.vdb -o a3b --occupancy --quiet
  expect_exit 1 "$vox" diff a1/m1.occupancy.png a3b/m3.occupancy.png --json
  jq_py "assert d['max_error_at']['voxel']==[0,5,0], d['max_error_at']"
  # EXR, 32-bit integer samples: any difference fails by default (0 thresholds).
  "$vox" build-atlas m1.vdb -o x1 --identity --format rgba32ui --quiet
  "$vox" build-atlas m3.vdb -o x3 --identity --format rgba32ui --quiet
  expect_exit 0 "$vox" diff x1/m1.identity.exr x1/m1.identity.exr
  expect_exit 1 "$vox" diff x1/m1.identity.exr x3/m3.identity.exr --json
  jq_py "assert d['pixels_differing']==1 and d['fail']['threshold']==0 and d['max_error_at']['voxel']==[0,5,0] and d['max_error_at']['b']==[0,5,0,4294967295], d"
  # Depth renders (one float channel, +inf for misses): the class change of
  # m2 leaves the geometry alone; m3's extra block does not.
  for m in m1 m2 m3; do
    "$vox" render-canonical $m.vdb -o d$m.exr --mode depth --eye 4,9,12 --target 3,3,3 --size 24x20 --quiet
  done
  expect_exit 0 "$vox" diff dm1.exr dm2.exr
  expect_stdout "hit/miss mask agrees on 100.0000% of pixels (finite depth)"
  expect_exit 1 "$vox" diff dm1.exr dm3.exr --json
  jq_py "assert d['mask_source']=='finite depth' and d['mask_agreement']<1 and d['pixels_differing']>0, d"
  # Layouts must match (m4's dims are 6 x 7 x 6).
  "$vox" build-atlas m4.vdb -o a4 --summary --quiet
  expect_exit 1 "$vox" diff a1/m1.summary.png a4/m4.summary.png
  expect_stdout "atlas layouts differ"
  # An atlas whose image size contradicts its entry's layout (m1's image with
  # m4's layout) is refused as info and verify-bijection refuse it, even
  # against itself.
  python3 -c "
import json
entry = json.load(open('a1/m1.atlas.json'))
entry = {k: v for k, v in entry['files'][0].items() if k != 'file'}
entry['layout'] = json.load(open('a4/m4.atlas.json'))['layout']
entry['scene'] = 'm1.vdb'
open('entry.json', 'w').write(json.dumps(entry))" || fail "entry with m4's layout"
  python3 "$tests/cli/png_text.py" a1/m1.summary.png contra.png vox:atlas "$(cat entry.json)" || fail "png_text.py"
  for cmd in "diff contra.png contra.png" "diff a1/m1.summary.png contra.png" "info contra.png" \
             "verify-bijection --atlas contra.png --scene m4.vdb"; do
    expect_exit 3 "$vox" $cmd
    expect_stderr "contra.png: the image is 12 x 18 x 4 uint8 but its \"vox:atlas\" entry (summary, rgba8) says 18 x 14 x 4"
  done
  ;;
pages)
  maps
  "$vox" pack-chunks m1.vdb -o p1.vpk --chunk 8 --quiet
  "$vox" pack-chunks m1.vdb -o p1s.vpk --chunk 8 --layout svo --quiet
  "$vox" pack-chunks m2.vdb -o p2.vpk --chunk 8 --quiet
  "$vox" pack-chunks m3.vdb -o p3.vpk --chunk 8 --quiet
  expect_exit 0 "$vox" diff p1.vpk p1.vpk
  expect_stdout "same: page files"
  # One chunk, named by level and chunk coordinates, its voxel by both.
  expect_exit 1 "$vox" diff p1.vpk p2.vpk --json
  jq_py "assert d['chunks_differing']==1 and d['voxels_differing']==1 and d['voxel_kinds']['summary']==1; c=d['first_chunk']; assert c['level']==0 and c['chunk']==[0,0,0] and c['first_voxel']['voxel']==[5,5,5] and c['first_voxel']['a']['summary'][0]==1 and c['first_voxel']['b']['summary'][0]==2, c"
  expect_exit 1 "$vox" diff p1.vpk p3.vpk
  expect_stdout "first voxel (0, 5, 0) of level 0"
  expect_stdout "DIFFERENT: page files, 1 chunk compared, 1 differ, 1 voxel differs"
  expect_stdout "(key 0): 1 voxel differs (occupied 4 vs 5)"
  # Another layout of the same voxels: the header differs, no chunk does.
  expect_exit 1 "$vox" diff p1.vpk p1s.vpk --json
  jq_py "assert d['chunks_differing']==0 and [h['field'] for h in d['header']]==['layout'], d['header']"
  ;;
json)
  # A number past double's range is malformed JSON: exit 3 naming the file.
  printf '{"a": 1e999}' > huge.json
  printf '{"a": 1}' > one.json
  expect_exit 3 "$vox" diff huge.json one.json
  expect_stderr "huge.json: not valid JSON"
  maps
  "$vox" voxelize m1.json -o r1.vdb --grid-size 8,8,8 --report r1.json --quiet
  "$vox" voxelize m1.json -o r2.vdb --grid-size 8,8,8 --report r2.json --quiet
  # Timings and paths differ; they are ignored by default.
  expect_exit 0 "$vox" diff r1.json r2.json
  expect_stdout "same: JSON"
  expect_exit 1 "$vox" diff r1.json r2.json --no-default-ignores
  # One number: its JSON pointer and both values; the relative tolerance at its boundary.
  python3 -c "
import json
d = json.load(open('r1.json')); d['counts']['probe'] = 1000; json.dump(d, open('n1.json', 'w'))
d['counts']['probe'] = 1001; json.dump(d, open('n2.json', 'w'))"
  expect_exit 1 "$vox" diff n1.json n2.json
  expect_stdout "/counts/probe: 1000 vs 1001"
  printf '{"a": 2}' > a1.json
  printf '[1]' > top.json
  expect_exit 1 "$vox" diff a1.json one.json --rel-tolerance 0.25
  expect_stdout "DIFFERENT: JSON, 1 value compared, 1 differ (relative tolerance 0.25; 0 ignored keys skipped)"
  expect_exit 1 "$vox" diff a1.json top.json
  expect_stdout "  the top level: "
  expect_exit 1 "$vox" diff n1.json n2.json --json
  jq_py "assert d['values_differing']==1 and d['first_difference']['pointer']=='/counts/probe' and d['first_difference']['a']=='1000' and d['first_difference']['b']=='1001'"
  expect_exit 0 "$vox" diff n1.json n2.json --rel-tolerance 0.000999001
  expect_exit 1 "$vox" diff n1.json n2.json --rel-tolerance 0.000999
  expect_exit 0 "$vox" diff --ignore-key probe n1.json n2.json
  expect_exit 0 "$vox" diff n1.json --ignore-key 'pro*' --ignore-key x n2.json
  # Touched sets (a render's --touched output).
  "$vox" render-canonical m1.vdb -o r.png --eye 4,9,12 --target 3,3,3 --size 32x32 --touched t1.json --quiet
  python3 -c "
import json
d = json.load(open('t1.json')); d['chunks'][0]['voxels'] += 1; json.dump(d, open('t2.json', 'w'))"
  expect_exit 0 "$vox" diff t1.json t1.json
  expect_exit 1 "$vox" diff t1.json t2.json
  expect_stdout "/chunks/0/voxels"
  printf '{"a": 1' > broken.json
  expect_exit 3 "$vox" diff t1.json broken.json
  expect_stderr "broken.json: not valid JSON"
  ;;
render_reference)
  maps
  "$vox" render-canonical m1.vdb -o s1.png --mode shaded --eye 4,9,12 --target 3,3,3 --size 40x30 --quiet
  "$vox" render-canonical m2.vdb -o s2.png --mode shaded --eye 4,9,12 --target 3,3,3 --size 40x30 --quiet
  python3 -c "
import base64, json
def b64(p): return base64.b64encode(open(p, 'rb').read()).decode()
json.dump({'imageSize': {'width': 40, 'height': 30}, 'views': [
  {'index': 0, 'id': 'view_000', 'rgbBase64': b64('s1.png')},
  {'index': 1, 'id': 'view_001', 'rgbBase64': 'data:image/png;base64,' + b64('s2.png')},
  {'index': 2, 'id': 'view_002'}]}, open('metadata.json', 'w'))"
  expect_exit 0 "$vox" diff s1.png metadata.json --view 0
  expect_stdout "PASS"
  expect_stdout "hit/miss mask agrees on 100.0000% of pixels (background)"
  expect_exit 1 "$vox" diff s1.png metadata.json --view 1 --json
  jq_py "assert d['kind']=='render vs reference' and d['view']==1 and d['view_id']=='view_001' and d['pixels_differing']>0 and d['mask_agreement']==1.0 and d['psnr']>0 and d['ssim']<1, d"
  expect_exit 3 "$vox" diff s1.png metadata.json --view 2
  expect_stderr "carries no reference image"
  expect_exit 3 "$vox" diff s1.png metadata.json --view 7
  expect_exit 2 "$vox" diff s1.png metadata.json
  expect_stderr "choose one with --view N"
  ;;
kinds)
  maps
  "$vox" build-atlas m1.vdb -o a1 --summary --quiet
  "$vox" pack-chunks m1.vdb -o p1.vpk --quiet
  expect_exit 2 "$vox" diff m1.vdb a1/m1.summary.png
  expect_stderr "m1.vdb is a scene or pyramid (.vdb) but a1/m1.summary.png is an image"
  expect_exit 2 "$vox" diff p1.vpk m1.vdb
  expect_exit 2 "$vox" diff m1.vdb p1.vpk
  expect_exit 2 "$vox" diff m1.vdb m1.vdb --fail 0.1
  expect_exit 2 "$vox" diff m1.vdb m1.vdb --view 0
  expect_exit 3 "$vox" diff m1.vdb missing.vdb
  expect_stderr "missing.vdb: no such file"
  printf 'hello' > junk.bin
  expect_exit 3 "$vox" diff junk.bin junk.bin
  expect_stderr "not a file vox diff reads"
  head -c 100 m1.vdb > cut.vdb
  expect_exit 3 "$vox" diff m1.vdb cut.vdb
  # --json prints one object for refusals and unreadable inputs too, with the
  # error (also on stderr) and the exit code; "kind" is null until both files
  # are known to be of one kind.
  expect_exit 2 "$vox" diff m1.vdb a1/m1.summary.png --json
  jq_py "assert d['same'] is False and d['kind'] is None and d['exit_code']==2 and 'is an image' in d['error'], d"
  expect_exit 3 "$vox" diff m1.vdb missing.vdb --json
  jq_py "assert d['same'] is False and d['kind'] is None and d['exit_code']==3 and d['error']=='missing.vdb: no such file', d"
  expect_exit 3 "$vox" diff m1.vdb cut.vdb --json
  jq_py "assert d['same'] is False and d['kind']=='scene' and d['exit_code']==3 and d['b']=='cut.vdb', d"
  expect_exit 2 "$vox" diff m1.vdb m1.vdb --fail 0.1 --json
  jq_py "assert d['kind']=='scene' and d['exit_code']==2 and d['error'].startswith('--fail applies to images'), d"
  expect_stderr "--fail applies to images"
  # A command line that does not parse stops before vox diff runs: stderr only.
  expect_exit 2 "$vox" diff m1.vdb m1.vdb --fail nan --json
  [ ! -s out.txt ] || fail "a parse error printed on stdout: $(cat out.txt)"
  ;;
options)
  maps
  "$vox" build-atlas m1.vdb -o a1 --summary --quiet
  "$vox" build-atlas m2.vdb -o a2 --summary --quiet
  printf '{"a": 1}' > j1.json
  printf '{"a": 2}' > j2.json
  # NaN passes every comparison, so it would turn a gate off: refused for every
  # numeric option, whatever the kind of file.
  for opt in --fail --failpercent --warn --warnpercent --hardfail --hardwarn --diff-scale; do
    expect_exit 2 "$vox" diff a1/m1.summary.png a2/m2.summary.png $opt nan
    expect_stderr "$opt: expected a"
    expect_stderr "got 'nan'"
  done
  for opt in --color-tolerance --votes-tolerance; do
    expect_exit 2 "$vox" diff m1.vdb m2.vdb $opt nan
  done
  expect_exit 2 "$vox" diff j1.json j2.json --rel-tolerance nan
  expect_stderr "--rel-tolerance: expected a finite number >= 0, got 'nan'"
  # inf is the documented default of --hardfail and --hardwarn (off): accepted.
  expect_exit 1 "$vox" diff a1/m1.summary.png a2/m2.summary.png --hardfail inf --hardwarn inf
  expect_stdout "FAILURE"
  expect_exit 0 "$vox" diff a1/m1.summary.png a2/m2.summary.png --fail 0.004 --hardfail inf
  expect_exit 2 "$vox" diff a1/m1.summary.png a2/m2.summary.png --fail inf
  # Range errors print their bounds readably (not DBL_MAX's 309 digits).
  expect_exit 2 "$vox" diff a1/m1.summary.png a2/m2.summary.png --fail -1
  expect_stderr "--fail: expected a finite number >= 0, got '-1'"
  expect_exit 2 "$vox" diff a1/m1.summary.png a2/m2.summary.png --failpercent 101
  expect_stderr "--failpercent: expected a finite number in [0, 100], got '101'"
  [ "$(wc -c < err.txt)" -lt 200 ] || fail "a long range message: $(cat err.txt)"
  # An option of another kind is a usage error naming it and the kinds it
  # applies to, never silently without effect.
  "$vox" pack-chunks m1.vdb -o p1.vpk --chunk 8 --quiet
  "$vox" pack-chunks m2.vdb -o p2.vpk --chunk 8 --quiet
  img="a1/m1.summary.png a2/m2.summary.png"
  while read -r a b opt value kinds; do  # value "-": a flag
    if [ "$value" = - ]; then expect_exit 2 "$vox" diff "$a" "$b" "$opt"; else expect_exit 2 "$vox" diff "$a" "$b" "$opt" "$value"; fi
    expect_stderr "$opt applies to $kinds, not to"
  done <<EOF2
$img --votes-tolerance 1 scenes and pyramids (.vdb)
$img --color-tolerance 0.1 scenes and pyramids (.vdb) and page files (.vpk)
$img --ignore-sources - scenes and pyramids (.vdb)
$img --rel-tolerance 0.1 JSON files
$img --ignore-key x JSON files
$img --no-default-ignores - JSON files
m1.vdb m2.vdb --rel-tolerance 0.1 JSON files
m1.vdb m2.vdb --ignore-key x JSON files
m1.vdb m2.vdb --diff-scale 2 images (.png, .exr)
m1.vdb m2.vdb --background 0,0,0 images (.png, .exr)
p1.vpk p2.vpk --votes-tolerance 1 scenes and pyramids (.vdb)
p1.vpk p2.vpk --ignore-sources - scenes and pyramids (.vdb)
p1.vpk p2.vpk --rel-tolerance 0.1 JSON files
p1.vpk p2.vpk --ignore-key x JSON files
p1.vpk p2.vpk --fail 0.1 images (.png, .exr)
j1.json j2.json --votes-tolerance 1 scenes and pyramids (.vdb)
j1.json j2.json --ignore-sources - scenes and pyramids (.vdb)
j1.json j2.json --color-tolerance 0.1 scenes and pyramids (.vdb) and page files (.vpk)
j1.json j2.json --fail 0.1 images (.png, .exr)
j1.json j2.json --level 0 scenes and pyramids (.vdb)
EOF2
  # The options of a kind still apply to it.
  expect_exit 1 "$vox" diff p1.vpk p2.vpk --color-tolerance 0.1
  expect_exit 0 "$vox" diff m1.vdb m2.vdb --ignore-sources --votes-tolerance 1
  expect_exit 0 "$vox" diff j1.json j2.json --ignore-key a --rel-tolerance 0.5 --no-default-ignores
  # A render against a metadata.json takes the image options, and --view.
  "$vox" render-canonical m1.vdb -o s1.png --mode shaded --eye 4,9,12 --target 3,3,3 --size 20x16 --quiet
  python3 -c "
import base64, json
json.dump({'views': [{'index': 0, 'rgbBase64': base64.b64encode(open('s1.png', 'rb').read()).decode()}]}, open('metadata.json', 'w'))"
  expect_exit 0 "$vox" diff s1.png metadata.json --view 0 --fail 0.1 --hardfail inf
  expect_exit 2 "$vox" diff s1.png metadata.json --view 0 --rel-tolerance 0.1
  expect_stderr "--rel-tolerance applies to JSON files, not to a render compared with a metadata.json"
  expect_exit 2 "$vox" diff a1/m1.summary.png a2/m2.summary.png --view 0
  expect_stderr "--view applies to a render compared with a metadata.json"
  ;;
metrics_numpy)
  py=""
  for c in python3 /usr/bin/python3; do
    if command -v "$c" >/dev/null && "$c" -c "import numpy" 2>/dev/null; then py=$c; break; fi
  done
  if [ -z "$py" ]; then
    echo "SKIP: no python3 with numpy (scripts/install-deps.sh test installs python3-numpy)"
  else
    "$py" "$tests/diff/image_metrics.py" "$vox" "$work" || fail "image metrics differ from numpy's"
  fi
  ;;
golden_demo)
  # CI-style: today's bake of the demo against the committed golden files
  # (tests/golden/diff/, made by the same commands), then a perturbed bake
  # that must fail. Refresh the goldens with: tests/golden/diff/refresh.sh VOX
  golden=$tests/golden/diff
  "$vox" voxelize demo:hamlet --res 16 -o hamlet16.vdb --quiet
  "$vox" build-atlas hamlet16.vdb -o atlas --summary --quiet
  "$vox" pack-chunks hamlet16.vdb -o hamlet16.vpk --chunk 8 --quiet
  expect_exit 0 "$vox" diff hamlet16.vdb "$golden/hamlet16.vdb"
  expect_exit 0 "$vox" diff atlas/hamlet16.summary.png "$golden/hamlet16.summary.png"
  expect_exit 0 "$vox" diff hamlet16.vpk "$golden/hamlet16.vpk"
  # Perturbed: the hamlet at 15 voxels instead of 16.
  "$vox" voxelize demo:hamlet --res 15 -o bad.vdb --quiet
  "$vox" build-atlas bad.vdb -o badatlas --summary --quiet
  "$vox" pack-chunks bad.vdb -o bad.vpk --chunk 8 --quiet
  expect_exit 1 "$vox" diff bad.vdb "$golden/hamlet16.vdb"
  expect_stdout "header dims: 15 x 15 x 15 vs 16 x 16 x 16"
  expect_exit 1 "$vox" diff badatlas/bad.summary.png "$golden/hamlet16.summary.png"
  expect_exit 1 "$vox" diff bad.vpk "$golden/hamlet16.vpk"
  ;;
*)
  echo "unknown group $group" >&2
  exit 2
  ;;
esac
[ "$failures" = 0 ] || { echo "$failures failure(s) in diff.$group" >&2; exit 1; }
echo "diff.$group: ok"
