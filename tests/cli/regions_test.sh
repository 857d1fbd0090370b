#!/usr/bin/env bash
# Region bakes end to end (docs/scale.md "Regions", "Merging scenes"): for
# N = 1, 2, 3, 7 every part of `vox voxelize --region I/N` is the single-process
# scene cropped to its tile (checked through vox diff against the merge), and
# `vox merge` of the parts writes exactly the single-process bake's bytes (cmp),
# for meshes (surface with vertex colours, solid open and closed, both rules),
# demo:hamlet, demo:city, a block map and an OpenVDB level set. Bad command lines exit 2, bad sets of parts exit
# 3 with nothing written; empty tiles merge; bytes equal at --threads 1 and 2.
set -u
vox=$1
here=$(cd "$(dirname "$0")" && pwd)
source "$here/test_lib.sh"

# A lumpy sphere with vertex colours (closed) and the same with its top cut away (open).
python3 - <<'PY'
import math
def sphere(open_):
    vs, fs = [], []
    nu, nv = 37, 23
    for j in range(nv + 1):
        th = math.pi * j / nv
        for i in range(nu):
            ph = 2 * math.pi * i / nu
            r = 1 + 0.15 * math.sin(3 * ph) * math.sin(2 * th)
            x, y, z = r * math.sin(th) * math.cos(ph), r * math.cos(th), 1.3 * r * math.sin(th) * math.sin(ph)
            vs.append((x, y, z, (x + 1.2) / 2.4, (y + 1.2) / 2.4, (z + 1.6) / 3.2))
    for j in range(nv):
        for i in range(nu):
            a, b, c, d = j * nu + i, j * nu + (i + 1) % nu, (j + 1) * nu + i, (j + 1) * nu + (i + 1) % nu
            if open_ and j < 3: continue
            fs += [(a, c, b), (b, c, d)]
    return vs, fs
for name, op in (("closed.obj", False), ("open.obj", True)):
    vs, fs = sphere(op)
    with open(name, "w") as f:
        for v in vs: f.write("v %.6f %.6f %.6f %.4f %.4f %.4f\n" % v)
        for t in fs: f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))
# A block map of 100 x 12 x 90 blocks: terrain of varied heights and types, holes.
types = ["Grass", "Dirt", "Stone", "Plank", "Snow", "Sand", "Water"]
blocks = []
for x in range(100):
    for z in range(90):
        h = 2 + int(4 + 3 * math.sin(x / 7.0) + 3 * math.cos(z / 5.0))
        if (x * 7 + z * 13) % 29 == 0: continue
        for y in range(h):
            blocks.append('{"position":[%d,%d,%d],"blockType":"%s"}' % (x, y, z, types[(x // 9 + y + z // 11) % 7]))
open("map.json", "w").write('{"worldScale": 1.0, "blocks": [' + ",".join(blocks) + "]}")
PY

# bake_parts NAME N ARGS...: the N parts of a bake and their merge, compared with the single-process bake.
bake_parts() {
  local name=$1 n=$2; shift 2
  local parts=() i
  for ((i = 0; i < n; i++)); do
    expect_exit 0 "$vox" voxelize "$@" --region "$i/$n" -o "$name.$n.$i.vdb" --threads $((1 + i % 2)) -q
    parts+=("$name.$n.$i.vdb")
  done
  expect_exit 0 "$vox" merge "${parts[@]}" -o "$name.merged$n.vdb" -q --report "$name.merge$n.json"
  # The merge refuses a part with a voxel outside its box and the tiles are
  # disjoint, so a merge equal to the whole bake means every part is the whole
  # bake cropped to its tile.
  cmp -s "$name.whole.vdb" "$name.merged$n.vdb" || fail "$name: merge of $n parts differs from the single-process bake"
}

run_case() {
  local name=$1; shift
  expect_exit 0 "$vox" voxelize "$@" -o "$name.whole.vdb" -q
  for n in 1 2 3 7; do bake_parts "$name" "$n" "$@"; done
}

run_case surface closed.obj --res 90
run_case solid_closed closed.obj --res 90 --fill solid
run_case solid_open open.obj --res 90 --fill solid
run_case parity_open open.obj --res 70 --fill solid --solid-rule parity
run_case hamlet demo:hamlet --res 128
run_case blockmap map.json --grid-size 100,12,90
run_case city demo:city --extent 512,96,384
# An OpenVDB level set (written by OpenVDB's own tool, when it is installed).
if command -v vdb_tool >/dev/null; then
  vdb_tool -sphere r=8 dim=64 voxel=0.25 name=ball -write ball_ls.vdb >/dev/null 2>&1 || fail "vdb_tool failed"
  run_case grid ball_ls.vdb --res 100
else
  echo "regions: vdb_tool not installed: the OpenVDB grid input case is skipped"
fi

# Colour made it into the parts (the mesh has vertex colours).
"$vox" info surface.2.0.vdb > info.txt && grep -q "voxels coloured" info.txt || fail "surface part has no colour"
jcheck hamlet.merge7.json "c=d['counts']; assert c['parts']==7 and c['tiles']==7 and c['occupied_voxels']==c['part_voxels']"

# The part's region record, as vox info shows it.
"$vox" info hamlet.3.1.vdb > info.txt; grep -q "tile 1 of 3" info.txt || fail "vox info does not show the region"

# --region-box: an aligned box is tile 0 of 1 with that box; an unaligned one exits 2 naming the nearest.
expect_exit 0 "$vox" voxelize demo:hamlet --res 128 --region-box 32,0,0,127,127,63 -o box.vdb -q
expect_exit 2 "$vox" voxelize demo:hamlet --res 128 --region-box 30,0,0,127,127,63 -o bad.vdb
expect_stderr "--region-box 0,0,0,127,127,63"
[ -e bad.vdb ] && fail "an unaligned --region-box wrote its output"

# Bad command lines: exit 2, nothing written.
for r in 5/4 0/0 1/x; do
  expect_exit 2 "$vox" voxelize demo:hamlet --res 64 --region "$r" -o bad.vdb
  expect_stderr "--region $r"
done
expect_exit 2 "$vox" voxelize demo:hamlet --res 64 --region 0/2 --region-box 0,0,0,31,63,31 -o bad.vdb
expect_stderr "not both"
expect_exit 2 "$vox" voxelize closed.obj --res 64 --region 0/2 --check -o bad.vdb
expect_exit 2 "$vox" voxelize closed.obj --res 64 --region 0/2 --method sdf -o bad.vdb
[ -e bad.vdb ] && fail "a refused command line wrote its output"

# Bad sets of parts: exit 3 naming the part, nothing written.
expect_exit 3 "$vox" merge hamlet.3.0.vdb hamlet.3.2.vdb -o bad.vdb
expect_stderr "tile 1 of 3 is missing"
expect_exit 3 "$vox" merge hamlet.3.0.vdb hamlet.3.1.vdb hamlet.3.1.vdb hamlet.3.2.vdb -o bad.vdb
expect_stderr "hamlet.3.1.vdb"
expect_exit 0 "$vox" voxelize demo:hamlet --res 64 --region 1/3 -o other_res.vdb -q
expect_exit 3 "$vox" merge hamlet.3.0.vdb other_res.vdb hamlet.3.2.vdb -o bad.vdb
expect_stderr "other_res.vdb"
expect_exit 3 "$vox" merge surface.2.0.vdb solid_closed.2.1.vdb -o bad.vdb
expect_stderr "solid_closed.2.1.vdb"
expect_exit 3 "$vox" merge hamlet.2.0.vdb hamlet.whole.vdb -o bad.vdb
expect_stderr "hamlet.whole.vdb: not a part"
expect_exit 3 "$vox" merge hamlet.3.0.vdb hamlet.2.1.vdb -o bad.vdb
expect_stderr "hamlet.2.1.vdb"
expect_exit 0 "$vox" mip hamlet.2.0.vdb -o pyramid.vdb -q
expect_exit 3 "$vox" merge pyramid.vdb hamlet.2.1.vdb -o bad.vdb
expect_stderr "pyramid"
[ -e bad.vdb ] && fail "a refused merge wrote its output"
ls .bad.vdb.tmp* >/dev/null 2>&1 && fail "a refused merge left a temporary"

# Empty tiles (N larger than the 4 x 4 cells of a 128^3 world): valid empty parts that merge.
parts=()
for ((i = 0; i < 20; i++)); do
  expect_exit 0 "$vox" voxelize demo:hamlet --res 128 --region "$i/20" -o "e.$i.vdb" -q
  parts+=("e.$i.vdb")
done
empties=0
for ((i = 0; i < 20; i++)); do "$vox" info "e.$i.vdb" | grep -q "empty tile" && empties=$((empties + 1)); done
[ "$empties" = 4 ] || fail "$empties of 20 tiles of 16 cells are empty, expected 4"
expect_exit 0 "$vox" merge "${parts[@]}" -o e.merged.vdb -q
cmp -s hamlet.whole.vdb e.merged.vdb || fail "merge with empty tiles differs from the single-process bake"

# Determinism: parts and merges byte-identical at --threads 1 and 2.
for t in 1 2; do
  expect_exit 0 "$vox" voxelize open.obj --res 90 --fill solid --region 1/3 -o "t$t.vdb" --threads $t -q
  expect_exit 0 "$vox" merge solid_open.3.2.vdb solid_open.3.0.vdb "t$t.vdb" -o "tm$t.vdb" --threads $t -q
done
cmp -s t1.vdb t2.vdb || fail "a part differs between --threads 1 and 2"
cmp -s tm1.vdb tm2.vdb || fail "a merge differs between --threads 1 and 2"
cmp -s tm1.vdb solid_open.whole.vdb || fail "a merge of parts given out of order differs"

# Parts baked from different spellings of the same mesh (./closed.obj, closed.obj, from another directory)
# share the world key (it holds the file's digest, not its path): any order of the parts merges to the same
# bytes, with tile 0's source path, i.e. the single-process bake run as tile 0 was.
mkdir -p spell
expect_exit 0 "$vox" voxelize ./closed.obj --res 40 --region 0/3 -o sp.0.vdb -q
expect_exit 0 "$vox" voxelize closed.obj --res 40 --region 1/3 -o sp.1.vdb -q
(cd spell && "$vox" voxelize ../closed.obj --res 40 --region 2/3 -o ../sp.2.vdb -q) || fail "bake from spell/ failed"
expect_exit 0 "$vox" voxelize ./closed.obj --res 40 -o sp.whole.vdb -q
expect_exit 0 "$vox" merge sp.0.vdb sp.1.vdb sp.2.vdb -o sp.m012.vdb -q
expect_exit 0 "$vox" merge sp.2.vdb sp.1.vdb sp.0.vdb -o sp.m210.vdb -q
expect_exit 0 "$vox" merge sp.1.vdb sp.2.vdb sp.0.vdb -o sp.m120.vdb -q
cmp sp.m012.vdb sp.m210.vdb || fail "merges of the same parts in two orders differ (paths spelled differently)"
cmp sp.m012.vdb sp.m120.vdb || fail "merges of the same parts in two orders differ (paths spelled differently)"
cmp sp.m012.vdb sp.whole.vdb || fail "a merge does not keep tile 0's source path"

# A class whose triangles all lie outside --bounds: the whole bake leaves it
# out, and so does every part (it was an internal error, exit 4, in parts).
python3 - <<'PY'
def cube(x0, out, base):
    for x in (x0, x0 + 1):
        for y in (0, 1):
            for z in (0, 1):
                out.append("v %g %g %g" % (x, y, z))
    for f in ((1, 2, 4), (1, 4, 3), (5, 7, 8), (5, 8, 6), (1, 5, 6), (1, 6, 2),
              (3, 4, 8), (3, 8, 7), (1, 3, 7), (1, 7, 5), (2, 6, 8), (2, 8, 4)):
        out.append("f %d %d %d" % tuple(base + i for i in f))
lines = ["usemtl A"]
cube(0, lines, 0)
lines.append("usemtl B")
cube(5, lines, 8)
open("ab.obj", "w").write("\n".join(lines) + "\n")
PY
expect_exit 0 "$vox" voxelize ab.obj --res 16 --bounds 0,0,0,1,1,1 -o ab.whole.vdb -q
expect_exit 0 "$vox" voxelize ab.obj --res 16 --bounds 0,0,0,1,1,1 --region 0/2 -o ab.0.vdb -q
expect_exit 0 "$vox" voxelize ab.obj --res 16 --bounds 0,0,0,1,1,1 --region 1/2 -o ab.1.vdb -q
expect_exit 0 "$vox" merge ab.0.vdb ab.1.vdb -o ab.merged.vdb -q
cmp -s ab.whole.vdb ab.merged.vdb || fail "parts of a bake with a class outside --bounds merge to another scene"

# vox mip on a part: levels inside the part, region record kept (its box in each level's voxels).
expect_exit 0 "$vox" mip hamlet.3.1.vdb --split -o partmip -q
"$vox" info partmip.mip2.vdb > info.txt; grep -q "tile 1 of 3, box (8, 0, 0) .. (31, 31, 15)" info.txt ||
  fail "mip level 2 of a part lacks its region: $(grep region info.txt)"

echo "regions: $failures failures"
[ "$failures" = 0 ]
