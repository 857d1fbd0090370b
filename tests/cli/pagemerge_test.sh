#!/usr/bin/env bash
# vox pack-chunks --merge: the page files of a region bake's parts join into
# exactly the bytes of the single-process pack (cmp), for the hamlet, a mesh
# with vertex colours and a solid-filled mesh whose interior lies in few
# tiles, at N = 1, 2, 3, 7, parts in any order, with and without --mips; bad
# sets of parts exit 3 naming the part, and nothing is written.
# Usage: pagemerge_test.sh VOX_BINARY
set -u
vox=$1
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

# --- usage and whole files: no region bake needed -----------------------------
expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o h64.vdb -q
expect_exit 0 "$vox" pack-chunks h64.vdb -o h64.vpk -q
expect_exit 3 "$vox" pack-chunks --merge h64.vpk -o w.vpk
expect_stderr "h64.vpk"
expect_stderr "region"
[ -e w.vpk ] && fail "a refused merge wrote w.vpk"
expect_exit 2 "$vox" pack-chunks --merge h64.vpk --chunk 8 -o w.vpk
expect_exit 2 "$vox" pack-chunks --merge h64.vpk
expect_exit 2 "$vox" pack-chunks h64.vdb --merge h64.vpk -o w.vpk
expect_exit 3 "$vox" pack-chunks --merge missing.vpk -o w.vpk
expect_stderr "missing.vpk"

if ! "$vox" voxelize --help 2>&1 | grep -q -- "--region"; then
  echo "SKIP: this vox has no 'voxelize --region'; the byte-identity checks need it (the unit tests PageMerge.* crop parts themselves)"
  [ "$failures" = 0 ] || exit 1
  exit 0
fi

# --- scenes -------------------------------------------------------------------
# A mesh with vertex colours over the whole width (colour in every tile).
python3 - <<'EOF'
import math
v, f = [], []
def quad(a, b, c, d, col):
    base = len(v)
    for p in (a, b, c, d):
        v.append((p, col(p)))
    f.append((base + 1, base + 2, base + 3))
    f.append((base + 1, base + 3, base + 4))
# A wavy ribbon of quads with colours varying along x.
n = 24
for i in range(n):
    x0, x1 = i / n * 10, (i + 1) / n * 10
    y0, y1 = math.sin(i * 0.7), math.sin((i + 1) * 0.7)
    col = lambda p: (p[0] / 10, 0.5 + 0.4 * math.sin(p[2]), 1 - p[0] / 10)
    quad((x0, y0, 0), (x1, y1, 0), (x1, y1 + 1, 4), (x0, y0 + 1, 4), col)
with open("ribbon.obj", "w") as out:
    for p, c in v:
        out.write("v %g %g %g %g %g %g\n" % (p + c))
    for t in f:
        out.write("f %d %d %d\n" % t)
# A closed box near one corner (solid interior) and an open sheet across the
# rest: with --fill solid only the tiles at the box have interior voxels.
def box(x0, y0, z0, x1, y1, z1):
    base = len(w)
    for x in (x0, x1):
        for y in (y0, y1):
            for z in (z0, z1):
                w.append((x, y, z))
    # faces outward (vertex index = 1 + base + 4*ix + 2*iy + iz)
    q = lambda a, b, c, d: g.extend([(base + a, base + b, base + c), (base + a, base + c, base + d)])
    q(1, 2, 4, 3); q(5, 7, 8, 6); q(1, 5, 6, 2); q(3, 4, 8, 7); q(1, 3, 7, 5); q(2, 6, 8, 4)
w, g = [], []
box(0, 0, 0, 2, 1.5, 2)
base = len(w)
w += [(0, 3, 0), (10, 3, 0), (10, 3.5, 6), (0, 3.5, 6)]
g += [(base + 1, base + 2, base + 3), (base + 1, base + 3, base + 4)]
with open("solid.obj", "w") as out:
    for p in w:
        out.write("v %g %g %g\n" % p)
    for t in g:
        out.write("f %d %d %d\n" % t)
EOF

# scene NAME VOXELIZE-ARGS...: the whole scene NAME.vdb and its parts NAME.N.I.vdb.
scene() {
  local name=$1; shift
  expect_exit 0 "$vox" voxelize "$@" -o "$name.vdb" -q
  for n in 1 2 3 7; do
    for ((i = 0; i < n; i++)); do
      expect_exit 0 "$vox" voxelize "$@" --region "$i/$n" -o "$name.$n.$i.vdb" -q
    done
  done
}
scene hamlet demo:hamlet --res 128
scene ribbon ribbon.obj --res 160
scene solid solid.obj --res 140 --fill solid

# check NAME PACK-ARGS...: parts packed and merged (in a shuffled order) equal
# the whole scene packed.
check() {
  local name=$1; shift
  local tag
  tag=$(echo "$*" | tr -c 'a-z0-9' '_')
  expect_exit 0 "$vox" pack-chunks "$name.vdb" -o "whole.$tag.vpk" "$@" -q
  for n in 1 2 3 7; do
    local parts=()
    for ((i = 0; i < n; i++)); do
      expect_exit 0 "$vox" pack-chunks "$name.$n.$i.vdb" -o "$name.$n.$i.$tag.vpk" "$@" -q
      parts+=("$name.$n.$i.$tag.vpk")
    done
    # Any order: the parts reversed.
    local order=()
    for ((i = n - 1; i >= 0; i--)); do order+=("${parts[$i]}"); done
    expect_exit 0 "$vox" pack-chunks --merge "${order[@]}" -o "merged.$tag.vpk" --threads $((1 + n % 2)) -q
    cmp -s "merged.$tag.vpk" "whole.$tag.vpk" || fail "$name $*: N = $n merged differs from the whole pack"
  done
}
for s in hamlet ribbon solid; do
  check $s --layout bricks --chunk 16
  check $s --layout svo --chunk 32 --mips
  check $s --layout columns --chunk 8 --mips --occupancy majority
done
check hamlet --layout svo --chunk 8
check hamlet --layout bricks --chunk 32 --mips --levels 6

# --- bad sets of parts ----------------------------------------------------------
p() { echo "hamlet.3.$1.__layout_bricks___chunk_16_.vpk"; }
[ -e "$(p 0)" ] || fail "the parts' names changed: $(ls | head -5)"
expect_exit 3 "$vox" pack-chunks --merge "$(p 0)" "$(p 2)" -o bad.vpk
expect_stderr "1 of 3"
expect_exit 3 "$vox" pack-chunks --merge "$(p 0)" "$(p 1)" "$(p 1)" "$(p 2)" -o bad.vpk
expect_exit 3 "$vox" pack-chunks --merge "$(p 0)" "$(p 1)" ribbon.3.2.__layout_bricks___chunk_16_.vpk -o bad.vpk
expect_stderr "ribbon.3.2"
expect_exit 0 "$vox" pack-chunks hamlet.3.2.vdb -o other.vpk --chunk 8 -q
expect_exit 3 "$vox" pack-chunks --merge "$(p 0)" "$(p 1)" other.vpk -o bad.vpk
expect_stderr "other.vpk"
expect_stderr "chunk side"
# A flipped payload byte: the CRC names the part and the chunk.
cp "$(p 1)" corrupt.vpk
size=$(stat -c %s corrupt.vpk)
python3 -c "
import sys
b = bytearray(open('corrupt.vpk', 'rb').read())
b[$size - 10] ^= 0x40
open('corrupt.vpk', 'wb').write(b)"
expect_exit 3 "$vox" pack-chunks --merge "$(p 0)" corrupt.vpk "$(p 2)" -o bad.vpk
expect_stderr "corrupt.vpk"
expect_stderr "chunk"
[ -e bad.vpk ] && fail "a refused merge wrote bad.vpk"

# A corrupt chunk of a level the merge rebuilds (never read otherwise, here the
# last payload: the coarsest level) is refused as --verify refuses it.
for i in 0 1 2; do expect_exit 0 "$vox" pack-chunks hamlet.3.$i.vdb -o m.$i.vpk --mips -q; done
python3 -c "
b = bytearray(open('m.1.vpk', 'rb').read())
b[-1] ^= 0x01
open('mcorrupt.vpk', 'wb').write(b)"
expect_exit 1 "$vox" pack-chunks --verify mcorrupt.vpk
expect_exit 3 "$vox" pack-chunks --merge m.0.vpk mcorrupt.vpk m.2.vpk -o bad.vpk
expect_stderr "mcorrupt.vpk: chunk"
expect_stderr "field 'crc32c'"
[ -e bad.vpk ] && fail "a refused merge wrote bad.vpk"
# A part packed without --mips among parts with mips is named as such.
expect_exit 3 "$vox" pack-chunks --merge m.0.vpk "$(p 1)" m.2.vpk -o bad.vpk
expect_stderr "$(p 1): packed without --mips, but m.0.vpk has mip levels (occupancy 'any')"
[ -e bad.vpk ] && fail "a refused merge wrote bad.vpk"

# Parts baked from two spellings of the same mesh (./solid.obj, solid.obj) share the world key: merged in
# either order they give the same bytes, with tile 0's source path (the whole pack of the bake run as tile 0 was).
expect_exit 0 "$vox" voxelize ./solid.obj --res 60 --fill solid --region 0/2 -o sp.0.vdb -q
expect_exit 0 "$vox" voxelize solid.obj --res 60 --fill solid --region 1/2 -o sp.1.vdb -q
expect_exit 0 "$vox" voxelize ./solid.obj --res 60 --fill solid -o sp.vdb -q
for f in sp.0 sp.1 sp; do expect_exit 0 "$vox" pack-chunks $f.vdb -o $f.vpk --chunk 16 -q; done
expect_exit 0 "$vox" pack-chunks --merge sp.0.vpk sp.1.vpk -o sp.m01.vpk -q
expect_exit 0 "$vox" pack-chunks --merge sp.1.vpk sp.0.vpk -o sp.m10.vpk -q
cmp sp.m01.vpk sp.m10.vpk || fail "page merges of the same parts in two orders differ (paths spelled differently)"
cmp sp.m01.vpk sp.vpk || fail "a page merge does not keep tile 0's source path"

# --report: phases, bytes and MB/s.
expect_exit 0 "$vox" pack-chunks --merge "$(p 0)" "$(p 1)" "$(p 2)" -o r.vpk --report r.json -q
jcheck r.json "c = d['counts']; assert c['parts'] == 3 and c['merge_mb_per_s'] > 0 and set(c['seconds']) >= {'read', 'check', 'copy', 'reencode', 'mips', 'write'}"

[ "$failures" = 0 ] || exit 1
echo "pagemerge: all checks passed"
