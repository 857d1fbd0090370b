#!/usr/bin/env bash
# vox fuse end to end (docs/fuse.md): renders of a known scene fused back give
# exactly its visible voxels (the fused scene's renders equal the truth's, pixel
# for pixel, and it holds as many voxels as the renders touched), carving
# removes a floating block the views see through, several runs add up like
# one, bad inputs exit 3 naming the view and the file with nothing written,
# and extreme views (missing the grid, camera inside it, 1x1) work.
# Usage: fuse_test.sh GROUP VOX_BINARY REPO_ROOT
set -u
group=$1 vox=$2 root=$3
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

# views.json for STEM_000 ... STEM_(N-1) written by render-canonical --orbit N
# (depth, class, and normal when $3 = normal, normal and c_NNN.png colour when $3 = color).
views_json() {
  python3 - "$1" "$2" "${3:-}" <<'EOF'
import json, sys
stem, n, extra = sys.argv[1], int(sys.argv[2]), sys.argv[3]
views = []
for i in range(n):
    v = {'depth': '%s_%03d.depth.exr' % (stem, i), 'label': '%s_%03d.class.png' % (stem, i)}
    if extra in ('normal', 'color'): v['normal'] = '%s_%03d.normal.png' % (stem, i)
    if extra == 'color': v['color'] = 'c_%03d.png' % i
    views.append(v)
print(json.dumps({'views': views}))
EOF
}

# same_renders TRUTH FUSED CAMS N: renders of FUSED from the camera file equal the truth's (canonical and class).
same_renders() {
  local truth=$1 fused=$2 cams=$3 n=$4
  expect_exit 0 "$vox" render-canonical "$truth" -o t.png --camera "$cams" --mode canonical,class --quiet
  expect_exit 0 "$vox" render-canonical "$fused" -o g.png --camera "$cams" --mode canonical,class --quiet
  local i mode
  for ((i = 0; i < n; i++)); do
    for mode in canonical class; do
      if [ "$n" = 1 ]; then a=t.$mode.png b=g.$mode.png; else a=t.view$i.$mode.png b=g.view$i.$mode.png; fi
      expect_exit 0 "$vox" diff "$a" "$b"
    done
  done
}

case $group in
roundtrip)
  # The demo hamlet and a block map, rendered from 6 and 4 orbit cameras.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o h.vdb --quiet
  expect_exit 0 "$vox" render-canonical h.vdb -o o.png --orbit 6 --size 160x120 --mode depth,class,normal \
    --touched touched.json --camera-out cams.json --quiet
  views_json o 6 normal >views.json
  expect_exit 0 "$vox" fuse views.json -o f.vdb --report r.json --threads 2
  expect_stderr "6 views"
  jcheck r.json "t=d['counts']['totals']; tv=json.load(open('touched.json'))['voxels_touched']; \
assert t['occupied_after'] == tv, (t['occupied_after'], tv); assert t['ambiguous'] == 0; \
assert t['occupied_before'] == 0 and t['removed'] == 0 and t['created'] == tv; \
assert t['used'] == json.load(open('touched.json'))['hits'] and t['skipped']['outside_grid'] == 0, t; \
assert len(d['counts']['views']) == 6 and sum(v['used'] for v in d['counts']['views']) == t['used']; \
assert t['used'] + t['skipped']['no_depth'] + t['skipped']['no_class'] + t['skipped']['outside_grid'] == t['pixels']"
  same_renders h.vdb f.vdb cams.json 6
  # Colour images: the fused voxels carry the rendered colours back (render --mode color equal, pixel for pixel).
  expect_exit 0 "$vox" render-canonical h.vdb -o c.png --orbit 6 --size 160x120 --mode color --quiet
  views_json o 6 color >views_color.json
  expect_exit 0 "$vox" fuse views_color.json -o fc.vdb --report rc.json --quiet
  jcheck rc.json "t=d['counts']['totals']; assert t['colored'] == t['occupied_after'] > 0"
  expect_exit 0 "$vox" render-canonical fc.vdb -o gc.png --camera cams.json --mode color --quiet
  for i in 0 1 2 3 4 5; do expect_exit 0 "$vox" diff c_00$i.png gc.view$i.png; done
  # Votes only (no free-space walk): the same scene from noise-free renders, no free counts.
  expect_exit 0 "$vox" fuse views.json -o fn.vdb --carve none --report rn.json --quiet
  expect_exit 0 "$vox" diff f.vdb fn.vdb
  jcheck rn.json "t=d['counts']['totals']; assert t['free_voxels'] == 0 and t['free_counts'] == 0 and t['carve'] == 'none'"
  # The same scene at any thread count, byte for byte (the file's UUID is made
  # from its content, not drawn at random as OpenVDB's writer does).
  expect_exit 0 "$vox" fuse views.json -o f1.vdb --threads 1 --quiet
  expect_exit 0 "$vox" diff f.vdb f1.vdb
  cmp f.vdb f1.vdb || fail "fusing the same views twice gave different bytes"
  # Depth alone (no normal images): exact up to the pixels the report calls ambiguous.
  views_json o 6 >views_depth.json
  expect_exit 0 "$vox" fuse views_depth.json -o fd.vdb --report rd.json --quiet
  jcheck rd.json "t=d['counts']['totals']; tv=json.load(open('touched.json'))['voxels_touched']; \
assert abs(t['occupied_after'] - tv) <= t['ambiguous'], (t['occupied_after'], tv, t['ambiguous'])"
  # A block map in the block world's placement.
  python3 - <<'EOF'
import json
blocks = [{'position': [x, 0, z], 'blockType': 'Grass' if (x + z) % 3 else 'Dirt'} for x in range(12) for z in range(10)]
blocks += [{'position': [2, y, 3], 'blockType': 'Stone'} for y in range(1, 6)]
blocks += [{'position': [x, 1, 7], 'blockType': 'Plank'} for x in range(5, 10)]
json.dump({'worldScale': 1.0, 'blocks': blocks}, open('map.json', 'w'))
EOF
  expect_exit 0 "$vox" voxelize map.json -o m.vdb --quiet
  expect_exit 0 "$vox" render-canonical m.vdb -o mo.png --orbit 4 --size 200x150 --mode depth,class,normal \
    --touched mtouched.json --camera-out mcams.json --quiet
  views_json mo 4 normal >mviews.json
  expect_exit 0 "$vox" fuse mviews.json -o mf.vdb --report mr.json --quiet
  jcheck mr.json "t=d['counts']['totals']; assert t['occupied_after'] == json.load(open('mtouched.json'))['voxels_touched']"
  same_renders m.vdb mf.vdb mcams.json 4
  ;;
carving)
  # truth: a floor and a pillar; dirty: the same plus a floating block that the
  # truth's views see through. Fusing the truth's views into dirty removes it.
  python3 - <<'EOF'
import json
blocks = [{'position': [x, 0, z], 'blockType': 'Grass'} for x in range(12) for z in range(12)]
blocks += [{'position': [1, y, 1], 'blockType': 'Stone'} for y in range(1, 7)]
json.dump({'worldScale': 1.0, 'blocks': blocks}, open('truth.json', 'w'))
blocks.append({'position': [6, 3, 6], 'blockType': 'Plank'})
json.dump({'worldScale': 1.0, 'blocks': blocks}, open('dirty.json', 'w'))
EOF
  expect_exit 0 "$vox" voxelize truth.json -o truth.vdb --quiet
  expect_exit 0 "$vox" voxelize dirty.json -o dirty.vdb --quiet
  expect_exit 0 "$vox" render-canonical truth.vdb -o o.png --orbit 6 --size 120x90 --mode depth,class,normal \
    --camera-out cams.json --quiet
  views_json o 6 normal >views.json
  expect_exit 0 "$vox" fuse views.json -i dirty.vdb -o clean.vdb --report r.json --quiet
  jcheck r.json "t=d['counts']['totals']; assert t['removed'] == 1, t; assert t['occupied_after'] == t['occupied_before'] - 1"
  # Every voxel the views saw is still there; the floating block is gone: renders equal the truth's.
  same_renders truth.vdb clean.vdb cams.json 6
  # --carve off keeps it (free counts are still written).
  expect_exit 0 "$vox" fuse views.json -i dirty.vdb -o kept.vdb --carve off --report rk.json --quiet
  jcheck rk.json "t=d['counts']['totals']; assert t['removed'] == 0 and t['occupied_after'] == t['occupied_before'] and t['free_voxels'] > 0"
  expect_exit 0 "$vox" render-canonical kept.vdb -o k.png --camera cams.json --view 0 --mode class --quiet
  expect_exit 1 "$vox" diff t.view0.class.png k.png
  # The free counts kept.vdb stored carve on a later run that adds nothing (every pixel beyond "far").
  python3 -c "import json; d=json.load(open('views.json')); json.dump({'far': 0.001, 'views': d['views'][:1]}, open('nothing.json','w'))"
  expect_exit 0 "$vox" fuse nothing.json -i kept.vdb -o later.vdb --report rl.json --quiet
  jcheck rl.json "t=d['counts']['totals']; assert t['used'] == 0 and t['removed'] == 1, t"
  expect_exit 0 "$vox" diff clean.vdb later.vdb
  ;;
refine)
  # Fusing views 0-2 then 3-5 with -i gives the scene of fusing all six at once.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 48 -o h.vdb --quiet
  expect_exit 0 "$vox" render-canonical h.vdb -o o.png --orbit 6 --size 96x72 --mode depth,class,normal --quiet
  views_json o 6 normal >all.json
  python3 -c "import json; d=json.load(open('all.json')); json.dump({'views': d['views'][:3]}, open('a.json','w')); json.dump({'views': d['views'][3:]}, open('b.json','w'))"
  expect_exit 0 "$vox" fuse all.json -o all.vdb --quiet
  expect_exit 0 "$vox" fuse a.json -o a.vdb --quiet
  expect_exit 0 "$vox" fuse b.json -i a.vdb -o ab.vdb --report r.json --quiet
  expect_exit 0 "$vox" diff all.vdb ab.vdb
  # In place (-i S -o S), the documented way to refine a scene: the same scene.
  cp a.vdb inplace.vdb
  expect_exit 0 "$vox" fuse b.json -i inplace.vdb -o ./inplace.vdb --quiet
  expect_exit 0 "$vox" diff all.vdb inplace.vdb
  jcheck r.json "t=d['counts']['totals']; assert t['occupied_before'] > 0 and t['occupied_after'] >= t['occupied_before']"
  # The free grid is read back: a voxel's free counts add up across runs (vdb_print shows the grid).
  if command -v vdb_print >/dev/null; then
    vdb_print ab.vdb >print.txt 2>&1 && grep -q "free" print.txt || fail "ab.vdb has no 'free' grid: $(head -c 300 print.txt)"
  else
    echo "note: vdb_print not installed; the free grid's presence is not checked here"
  fi
  ;;
bad_input)
  expect_exit 0 "$vox" voxelize demo:hamlet --res 32 -o h.vdb --quiet
  expect_exit 0 "$vox" render-canonical h.vdb -o o.png --orbit 2 --size 40x30 --mode depth,class --quiet
  expect_exit 0 "$vox" render-canonical h.vdb -o small.png --view front --size 20x10 --mode class --quiet
  views_json o 2 >good.json
  # refused FILE JSON TEXT...: a views file that fuse refuses (exit 3), its
  # stderr holding every TEXT.
  refused() {
    local file=$1 text=$2
    shift 2
    printf '%s\n' "$text" >"$file"
    expect_exit 3 "$vox" fuse "$file" -o f.vdb
    for needle in "$@"; do expect_stderr "$needle"; done
  }
  refused broken.json '{"views": [' "broken.json"
  refused noviews.json '{"cameras": []}' 'no "views"'
  # Mismatched image sizes.
  refused size.json '{"views": [{"depth": "o_000.depth.exr", "label": "small.png"}]}' "views[0]" "small.png is 20x10"
  # A label not in the map.
  refused label.json '{"labels": {"#000000": null}, "views": [{"depth": "o_000.depth.exr", "label": "o_000.class.png"}]}' \
    "not in the label map" "o_000.class.png"
  # A render cropped after rendering (an EXR crop keeps its data window, with
  # the vox:canonical entry of the whole image): its camera no longer gives
  # the pixels' rays, so it is refused rather than fused into wrong voxels.
  oiiotool o_000.depth.exr --crop 20x10+5+5 -o crop.depth.exr || fail "oiiotool could not write crop.depth.exr"
  oiiotool o_000.class.png --cut 20x10+5+5 -o crop.class.png || fail "oiiotool could not write crop.class.png"
  refused crop.json '{"views": [{"depth": "crop.depth.exr", "label": "crop.class.png"}]}' \
    'views[0]: depth crop.depth.exr is 20x10 but its vox:canonical camera was made for 40x30'
  # Two keys that spell one label: refused naming both (one would be dropped).
  refused case.json '{"labels": {"#57ad5c": "Grass", "#57AD5C": "Dirt"}, "views": [{"depth": "o_000.depth.exr", "label": "o_000.class.png"}]}' \
    'views[0]: labels["#57ad5c"] and labels["#57AD5C"] are the same label; keep one of them'
  # A class the map names that the table lacks.
  refused lava.json '{"labels": {"#000000": "Lava"}, "views": [{"depth": "o_000.depth.exr", "label": "o_000.class.png"}]}' \
    "no class named 'Lava'"
  # A depth image of the wrong type.
  refused type.json '{"views": [{"depth": "o_000.class.png", "label": "o_000.class.png"}]}' \
    "a depth PNG has one 16-bit channel"
  # A depth EXR with a second channel (oiiotool names an added one after its
  # source): which one is the depth? Refused, naming the channels; its only
  # channel is read whatever its name (Z, as depth renderers write it).
  oiiotool o_000.depth.exr --ch R=R,Z=R -o rz.exr || fail "oiiotool could not write rz.exr"
  refused rz.json '{"views": [{"depth": "rz.exr", "label": "o_000.class.png"}]}' \
    "views[0]: depth rz.exr: a depth EXR has one float channel" "2 channels (R, Z)" "--ch Z"
  oiiotool o_000.depth.exr --ch Z=R -o z.exr || fail "oiiotool could not write z.exr"
  printf '%s\n' '{"views": [{"depth": "z.exr", "label": "o_000.class.png"}]}' >z.json
  printf '%s\n' '{"views": [{"depth": "o_000.depth.exr", "label": "o_000.class.png"}]}' >r.json
  expect_exit 0 "$vox" fuse z.json -o z.vdb --quiet
  expect_exit 0 "$vox" fuse r.json -o r.vdb --quiet
  expect_exit 0 "$vox" diff z.vdb r.vdb
  rm -f z.vdb r.vdb
  # Singular matrices.
  refused singular.json '{"views": [{"depth": "o_000.depth.exr", "label": "o_000.class.png", "camera": {"viewMatrix": [0,0,0,0, 0,0,0,0, 0,0,0,0, 0,0,0,0], "projectionMatrix": [1,0,0,0, 0,1,0,0, 0,0,-1,-1, 0,0,-0.2,0]}}]}' \
    "views[0].camera"
  # A look-at or intrinsics camera's keys are all read: a misspelt one is refused.
  refused fvo.json '{"views": [{"depth": "o_000.depth.exr", "label": "o_000.class.png", "camera": {"eye": [0, 5, 40], "target": [0, 0, 0], "fvo": 20}}]}' \
    'views[0]: camera has no key "fvo" (its keys: eye, target, up, fov, size, view)'
  refused skew.json '{"views": [{"depth": "o_000.depth.exr", "label": "o_000.class.png", "camera": {"intrinsics": {"fx": 30, "fy": 30, "cx": 19.5, "cy": 14.5, "skew": 0}, "pose": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}}]}' \
    'camera.intrinsics has no key "skew" (its keys: fx, fy, cx, cy)'
  # A missing image; a grid that differs from -i's; classes with -i.
  echo '{"views": [{"depth": "nope.exr", "label": "o_000.class.png"}]}' >missing.json
  expect_exit 3 "$vox" fuse missing.json -o f.vdb
  expect_stderr "views[0]: depth image nope.exr: no such file"
  # An unreadable image is named with the reason, not as "neither PNG nor
  # EXR". Root reads anything: as root this runs as nobody (setpriv) when
  # nobody can run the binary.
  cp o_000.depth.exr unread.exr && chmod 000 unread.exr
  echo '{"views": [{"depth": "unread.exr", "label": "o_000.class.png"}]}' >unread.json
  as=()
  [ "$(id -u)" = 0 ] && command -v setpriv >/dev/null && as=(setpriv --reuid=65534 --regid=65534 --clear-groups)
  mkdir -p out && chmod 777 out
  if [ "$(id -u)" != 0 ] || { [ ${#as[@]} -gt 0 ] && chmod 755 . && "${as[@]}" test -x "$vox"; }; then
    expect_exit 3 "${as[@]}" "$vox" fuse unread.json -o out/f.vdb
    expect_stderr "views[0]: depth image unread.exr: cannot open the file: Permission denied"
    [ -z "$(ls -A out)" ] || fail "a failed fuse left $(ls -A out) behind"
  fi
  # A directory where an image should be is named as one, not as missing.
  mkdir -p adir
  echo '{"views": [{"depth": "o_000.depth.exr", "label": "adir"}]}' >dirlabel.json
  expect_exit 3 "$vox" fuse dirlabel.json -o f.vdb
  expect_stderr "views[0]: label image adir: is a directory, expected a regular file"
  [ ! -e f.vdb ] || fail "f.vdb written by a failed run"
  echo '{"grid": {"dims": [8, 8, 8], "voxel_size": 1, "origin": [0, 0, 0]}, "views": [{"depth": "o_000.depth.exr", "label": "o_000.class.png"}]}' >grid.json
  expect_exit 3 "$vox" fuse grid.json -i h.vdb -o f.vdb
  expect_stderr "differs from -i"
  # Keys nothing reads: a warning naming each (a misspelt "colour" would drop
  # the colours silently), once per key however many views give it; the
  # fusion runs as without them.
  echo '{"extra": 1, "views": [{"depth": "o_000.depth.exr", "label": "o_000.class.png", "colour": "c.png"},
    {"depth": "o_001.depth.exr", "label": "o_001.class.png", "colour": "c.png"}]}' >unread.json
  expect_exit 0 "$vox" fuse unread.json -o unread.vdb --report unread_r.json
  expect_stderr 'warning: unread.json: "extra" is not a key of a views file'
  expect_stderr 'views[0] and 1 more view: "colour" is not a key of a view (depth, label, camera, normal, color,'
  python3 -c "import json, sys; w = json.load(open('unread_r.json'))['counts']['warnings']; sys.exit(0 if len(w) == 2 else 1)" ||
    fail "the report does not list the two unread keys: $(cat unread_r.json | head -c 600)"
  expect_exit 0 "$vox" fuse good.json -o good.vdb
  expect_exit 0 "$vox" diff good.vdb unread.vdb
  rm -f good.vdb unread.vdb
  # The same images twice: fused (votes twice), with a warning naming both views.
  echo '{"views": [{"depth": "o_000.depth.exr", "label": "o_000.class.png"}, {"depth": "./o_000.depth.exr", "label": "o_000.class.png"}]}' >dup.json
  expect_exit 0 "$vox" fuse dup.json -o dup.vdb --report dup_r.json
  expect_stderr "warning: dup.json: views[1] has the depth and label images of views[0]"
  jcheck dup_r.json "assert len(d['counts']['warnings']) == 1, d['counts']['warnings']"
  # Views that reach no voxel of the grid: an empty scene, said.
  echo '{"grid": {"dims": [4, 4, 4], "voxel_size": 0.1, "origin": [100, 100, 100]}, "views": [{"depth": "o_000.depth.exr", "label": "o_000.class.png"}]}' >miss.json
  expect_exit 0 "$vox" fuse miss.json -o miss.vdb
  expect_stderr "warning: no pixel of 1 view reached a voxel of the grid (dims 4 x 4 x 4, voxel size 0.1, origin (100, 100, 100))"
  rm -f dup.vdb miss.vdb
  # A named view at an odd size: its middle row and column run along grid planes; counted and said.
  expect_exit 0 "$vox" render-canonical h.vdb -o top.png --view top --size 41x31 --mode depth,class --quiet
  echo '{"views": [{"depth": "top.depth.exr", "label": "top.class.png"}]}' >top.json
  expect_exit 0 "$vox" fuse top.json -o top.vdb --report top_r.json
  expect_stderr "rays run along a grid plane or through a voxel edge (ambiguous)"
  jcheck top_r.json "assert d['counts']['totals']['ambiguous'] > 0 and any('ambiguous' in w for w in d['counts']['warnings']), d['counts']['totals']"
  rm -f top.vdb
  # Usage.
  expect_exit 2 "$vox" fuse good.json -o f.vdb --carve none --free all
  expect_stderr "--carve none counts none"
  expect_exit 2 "$vox" fuse good.json -o f.png
  expect_exit 2 "$vox" fuse good.json -o f.vdb --carve maybe
  [ -e f.vdb ] && fail "a failed fuse left f.vdb behind"
  expect_exit 0 "$vox" fuse good.json -o f.vdb --quiet
  ;;
extremes)
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o h.vdb --quiet
  # A camera inside the grid (above the ground, among the houses), a 1x1 view, and a view that misses the grid.
  cat >cams.json <<'EOF'
{"cameras": [
  {"eye": [1.3, 1.7, 2.1], "target": [-6, 0.5, -4], "fov": 100, "size": [160, 120]},
  {"eye": [3.1, 20, 2.9], "target": [3.0, 0, 3.05], "up": [0, 0, -1], "fov": 20, "size": [1, 1]},
  {"eye": [40, 10, 40], "target": [80, 10, 80], "fov": 30, "size": [64, 48]}
]}
EOF
  expect_exit 0 "$vox" render-canonical h.vdb -o o.png --camera cams.json --mode depth,class,normal --touched touched.json --quiet
  python3 -c "import json; json.dump({'views': [{'depth': 'o.view%d.depth.exr' % i, 'label': 'o.view%d.class.png' % i, 'normal': 'o.view%d.normal.png' % i} for i in range(3)]}, open('views.json','w'))"
  expect_exit 0 "$vox" fuse views.json -o f.vdb --report r.json --quiet
  jcheck r.json "v=d['counts']['views']; t=d['counts']['totals']; \
assert v[1]['pixels'] == 1 and v[1]['used'] == 1, v[1]; \
assert v[2]['used'] == 0 and v[2]['skipped']['no_depth'] == 64 * 48, v[2]; \
assert t['occupied_after'] == json.load(open('touched.json'))['voxels_touched'] and t['ambiguous'] == 0"
  same_renders h.vdb f.vdb cams.json 3
  # Depth beyond the grid and before it: skipped as outside, no vote.
  python3 - <<'EOF'
import json
json.dump({'grid': {'dims': [4, 4, 4], 'voxel_size': 1, 'origin': [100, 100, 100]},
           'views': [{'depth': 'o.view0.depth.exr', 'label': 'o.view0.class.png', 'camera': {'eye': [1.3, 1.7, 2.1], 'target': [-6, 0.5, -4], 'fov': 100}}]},
          open('away.json', 'w'))
EOF
  expect_exit 0 "$vox" fuse away.json -o away.vdb --report ra.json --quiet
  jcheck ra.json "t=d['counts']['totals']; assert t['used'] == 0 and t['occupied_after'] == 0 and t['skipped']['outside_grid'] > 0"
  ;;
png_depth)
  # 16-bit PNG depth with a scale, a gray label image, a look-at camera in the
  # views file, straight down at a floor whose top face is the plane y = 2:
  # z depth 8 lands exactly on that face, so every pixel votes for the floor
  # voxel behind it (v = 1); read as distances, the slanted rays stop short,
  # above the floor (v >= 2).
  python3 - <<'EOF2'
import struct, zlib, json
def png(path, w, h, depth, ctype, rows):
    raw = b''.join(b'\0' + r for r in rows)
    def chunk(k, b): return struct.pack('>I', len(b)) + k + b + struct.pack('>I', zlib.crc32(k + b) & 0xffffffff)
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, depth, ctype, 0, 0, 0))
                           + chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b''))
W, H = 24, 16
png('depth.png', W, H, 16, 0, [struct.pack('>' + 'H' * W, *([16] * W)) for _ in range(H)])   # 16 * 0.5 = 8
png('label.png', W, H, 8, 0, [bytes([1] * W) for _ in range(H)])                             # class 1
png('depth8.png', W, H, 8, 0, [bytes([16] * W) for _ in range(H)])
cam = {'eye': [8.3, 10, 8.2], 'target': [8.3, 0, 8.2], 'up': [0, 0, -1], 'fov': 60}
grid = {'dims': [16, 8, 16], 'voxel_size': 1, 'origin': [0, 0, 0]}
view = {'depth': 'depth.png', 'depth_scale': 0.5, 'label': 'label.png', 'camera': cam}
json.dump({'grid': grid, 'depth_kind': 'z', 'views': [view]}, open('z.json', 'w'))
json.dump({'grid': grid, 'views': [view]}, open('dist.json', 'w'))
json.dump({'grid': grid, 'depth_kind': 'z', 'far': 7.5, 'views': [view]}, open('far.json', 'w'))
json.dump({'grid': grid, 'views': [dict(view, depth='depth8.png')]}, open('d8.json', 'w'))
json.dump({'grid': grid, 'labels': {'1': None}, 'views': [view]}, open('null.json', 'w'))
png('conf.png', W, H, 8, 0, [bytes([3 if x < W // 2 else 0 for x in range(W)]) for _ in range(H)])  # left half: 3 votes
json.dump({'grid': grid, 'depth_kind': 'z', 'views': [dict(view, confidence='conf.png')]}, open('conf.json', 'w'))
# Labels outside the map where there is no depth (a segmenter's "unknown" where the depth estimator gave
# nothing): left half depth 8 and class 1, right half depth 0 and label 9, which no map holds.
png('holes.png', W, H, 16, 0, [struct.pack('>' + 'H' * W, *([16] * (W // 2) + [0] * (W // 2))) for _ in range(H)])
png('unknown.png', W, H, 8, 0, [bytes([1] * (W // 2) + [9] * (W // 2)) for _ in range(H)])
hole = dict(view, depth='holes.png', label='unknown.png')
json.dump({'grid': grid, 'depth_kind': 'z', 'views': [hole]}, open('hole_id.json', 'w'))
json.dump({'grid': grid, 'depth_kind': 'z', 'labels': {'1': 1}, 'views': [hole]}, open('hole_map.json', 'w'))
json.dump({'grid': grid, 'depth_kind': 'z', 'far': 7.5, 'labels': {'1': 1}, 'views': [dict(hole, depth='depth.png')]},
          open('hole_far.json', 'w'))
json.dump({'grid': grid, 'depth_kind': 'z', 'labels': {'1': 1}, 'views': [dict(view, label='unknown.png')]},
          open('hole_refused.json', 'w'))
# RGBA: red (class 1) with depth, then blue (unmapped) without depth, then blue again with depth on row 3 only:
# the blue pixel (18, 3) after a run of blue without depth must still be refused.
red, blue = bytes([255, 0, 0, 255]), bytes([0, 0, 255, 255])
png('unknown_rgba.png', W, H, 8, 6, [red * (W // 2) + blue * (W // 2) for _ in range(H)])
png('holes3.png', W, H, 16, 0, [struct.pack('>' + 'H' * W, *([16] * (W // 2) + [0] * (W // 4 if y == 3 else W // 2)
                                                              + [16] * (W // 4 if y == 3 else 0))) for y in range(H)])
rgba = dict(view, depth='holes.png', label='unknown_rgba.png')
json.dump({'grid': grid, 'depth_kind': 'z', 'labels': {'#ff0000': 1}, 'views': [rgba]}, open('hole_rgba.json', 'w'))
json.dump({'grid': grid, 'depth_kind': 'z', 'labels': {'#ff0000': 1}, 'views': [dict(rgba, depth='holes3.png')]},
          open('hole_rgba_refused.json', 'w'))
EOF2
  expect_exit 0 "$vox" fuse z.json -o z.vdb --report rz.json --quiet
  expect_exit 0 "$vox" info --json z.vdb
  jcheck out.txt "assert d['bounds']['min'][1] == 1 and d['bounds']['max'][1] == 1, d['bounds']; assert d['occupied'] > 100"
  # The default --free voted keeps free counts only at voted voxels: none here (only the floor is voted, and
  # no ray crosses it before its depth). --free all counts the cells in front of the floor; same scene.
  jcheck rz.json "t=d['counts']['totals']; assert t['used'] == 24 * 16 and t['free_counts'] == 0 and t['ambiguous'] == 0 and t['free'] == 'voted'"
  expect_exit 0 "$vox" fuse z.json -o za.vdb --free all --report rza.json --quiet
  jcheck rza.json "t=d['counts']['totals']; assert t['used'] == 24 * 16 and t['free_counts'] > 0 and t['ambiguous'] == 0 and t['free'] == 'all'"
  expect_exit 0 "$vox" diff z.vdb za.vdb
  expect_exit 0 "$vox" fuse dist.json -o dist.vdb --quiet
  expect_exit 0 "$vox" info --json dist.vdb
  jcheck out.txt "assert d['bounds']['min'][1] >= 1 and d['bounds']['max'][1] >= 2, d['bounds']"
  # --depth-kind on the command line wins over the file.
  expect_exit 0 "$vox" fuse z.json -o zd.vdb --depth-kind distance --quiet
  expect_exit 0 "$vox" diff dist.vdb zd.vdb
  # Beyond "far": skipped; a label mapped to null: skipped.
  expect_exit 0 "$vox" fuse far.json -o far.vdb --report rf.json --quiet
  jcheck rf.json "t=d['counts']['totals']; assert t['used'] == 0 and t['skipped']['no_depth'] == 24 * 16"
  expect_exit 0 "$vox" fuse null.json -o null.vdb --report rn.json --quiet
  jcheck rn.json "t=d['counts']['totals']; assert t['used'] == 0 and t['skipped']['no_class'] == 24 * 16"
  # A confidence image multiplies the votes (times --weight); 0 skips the pixel.
  expect_exit 0 "$vox" fuse conf.json -o conf.vdb --weight 2 --report rw.json --quiet
  jcheck rw.json "t=d['counts']['totals']; assert t['used'] == 12 * 16 and t['skipped']['zero_confidence'] == 12 * 16, t"
  expect_exit 0 "$vox" info --json conf.vdb
  jcheck out.txt "assert sum(c['votes'] for c in d['classes']) == 6 * 12 * 16, d['classes']"
  # A label outside the map (or, without a map, not a class id) where the pixel has no depth (0, or beyond
  # "far") is skipped and counted as no_depth, not refused; with depth it is refused (exit 3), naming the pixel.
  for f in hole_id hole_map hole_rgba; do
    expect_exit 0 "$vox" fuse $f.json -o $f.vdb --report r$f.json --quiet
    jcheck r$f.json "t=d['counts']['totals']; assert t['used'] == 12 * 16 and t['skipped']['no_depth'] == 12 * 16, t"
  done
  expect_exit 0 "$vox" diff hole_id.vdb hole_map.vdb
  expect_exit 0 "$vox" fuse hole_far.json -o hole_far.vdb --report rhf.json --quiet
  jcheck rhf.json "t=d['counts']['totals']; assert t['used'] == 0 and t['skipped']['no_depth'] == 24 * 16, t"
  expect_exit 3 "$vox" fuse hole_refused.json -o bad.vdb
  expect_stderr "label unknown.png: label 9 at pixel (12, 0) is not in the label map"
  expect_exit 3 "$vox" fuse hole_rgba_refused.json -o bad.vdb
  expect_stderr "label #0000ff at pixel (18, 3) is not in the label map"
  [ -e bad.vdb ] && fail "a refused fuse wrote bad.vdb"
  # An 8-bit depth PNG is refused.
  expect_exit 3 "$vox" fuse d8.json -o d8.vdb
  expect_stderr "depth8.png"
  expect_stderr "one 16-bit channel"
  ;;
image8k)
  # An 8K view (7680x4320, 33 M pixels): the fused scene is the voxels the render touched.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o h.vdb --quiet
  expect_exit 0 "$vox" render-canonical h.vdb -o o.png --view iso --size 7680x4320 --mode depth,class,normal \
    --touched touched.json --quiet
  echo '{"views": [{"depth": "o.depth.exr", "label": "o.class.png", "normal": "o.normal.png"}]}' >views.json
  expect_exit 0 "$vox" fuse views.json -o f.vdb --report r.json --quiet
  jcheck r.json "t=d['counts']['totals']; assert t['pixels'] == 7680 * 4320 and t['ambiguous'] == 0; \
assert t['occupied_after'] == json.load(open('touched.json'))['voxels_touched'], t"
  ;;
*)
  echo "unknown group $group" >&2
  exit 2
  ;;
esac
[ "$failures" = 0 ] || { echo "$failures failure(s) in fuse.$group" >&2; exit 1; }
echo "fuse.$group: ok"
