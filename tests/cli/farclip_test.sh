#!/usr/bin/env bash
# A small crop of a large scene: `vox voxelize --bounds` on a city-like OBJ
# whose ground plane reaches 1e8 voxels from the grid and with a stray
# triangle 6e10 voxels away bakes (the far triangles are clipped or dropped,
# docs/voxelize.md "Range"), to the scene of the same city cropped by hand,
# the same at --threads 1 and 2 and as 3 region bakes merged; --fill solid refuses it, naming the vertex
# and the fixes.
# Usage: farclip_test.sh VOX
set -u
vox=$1
# shellcheck source=test_lib.sh
. "$(cd "$(dirname "$0")" && pwd)/test_lib.sh"  # works in a fresh temporary directory

# Buildings: axis-aligned boxes as 12 triangles each (OBJ, 1-based, offset by the vertices so far).
box() {  # xmin ymin zmin xmax ymax zmax first_vertex
  local x0=$1 y0=$2 z0=$3 x1=$4 y1=$5 z1=$6 o=$7
  for z in "$z0" "$z1"; do for y in "$y0" "$y1"; do for x in "$x0" "$x1"; do echo "v $x $y $z"; done; done; done
  local f
  for f in "1 3 2" "2 3 4" "5 6 7" "6 8 7" "1 2 5" "2 6 5" "3 7 4" "4 7 8" "1 5 3" "3 5 7" "2 4 6" "4 8 6"; do
    set -- $f
    echo "f $(($1 + o)) $(($2 + o)) $(($3 + o))"
  done
}
city() {  # ground half-size, with the stray triangle (1) or not (0)
  local g=$1
  echo "o ground"
  printf 'v -%s -%s 0\nv %s -%s 0\nv %s %s 0\nv -%s %s 0\nf 1 2 3\nf 1 3 4\n' "$g" "$g" "$g" "$g" "$g" "$g" "$g" "$g"
  echo "o towers"
  box 1 1 0 3.3 2.7 9.1 4
  box -6.2 -5 0 -2.15 -1.1 4.4 12
  box -20 3 0 5 6.6 22 20  # reaches past the bounds on two sides
  if [ "$2" = 1 ]; then
    echo "o stray"
    printf 'v 3e9 1 0\nv 3e9 2 0\nv 3e9 1 1\nf 29 30 31\n'
  fi
}
city 2000000 1 > far_city.obj
city 8 0 > cropped_city.obj
bounds=-8,-8,-1,8,8,12

expect_exit 0 "$vox" voxelize far_city.obj --bounds $bounds --voxel-size 0.05 -o far1.vdb --threads 1 --report far1.json
expect_exit 0 "$vox" voxelize far_city.obj --bounds $bounds --voxel-size 0.05 -o far2.vdb --threads 2 --report far2.json
expect_exit 0 "$vox" voxelize cropped_city.obj --bounds $bounds --voxel-size 0.05 -o cropped.vdb --report cropped.json
# The ground alone is 2 x 320 x 320 voxels (z = 0 lies on a voxel face); with the towers more.
jcheck far1.json "c=d['counts']; assert c['dims']==[320,320,260] and c['occupied_voxels'] > 204800, c"
jcheck cropped.json "c=d['counts']; f=json.load(open('far1.json'))['counts']; assert (c['occupied_voxels'], c['surface_voxels']) == (f['occupied_voxels'], f['surface_voxels']), (c, f)"
# Bit for bit at either thread count; the same voxels and classes as the
# city cropped by hand, votes within a few per voxel (the clip's fans round
# their areas on their own).
cmp -s far1.vdb far2.vdb || fail "--threads 1 and 2 differ"
expect_exit 0 "$vox" diff far1.vdb cropped.vdb --ignore-sources --votes-tolerance 4
# A region bake clips the same way: its 3 parts merge into the whole bake, byte for byte.
parts=()
for i in 0 1 2; do
  expect_exit 0 "$vox" voxelize far_city.obj --bounds $bounds --voxel-size 0.05 --region "$i/3" -o "part$i.vdb" -q
  parts+=("part$i.vdb")
done
expect_exit 0 "$vox" merge "${parts[@]}" -o merged.vdb -q
cmp -s far1.vdb merged.vdb || fail "the merge of 3 region bakes differs from the whole bake"
# --check's oracle sees the clipped triangles the bake saw: nothing missed or extra.
expect_exit 0 "$vox" voxelize far_city.obj --bounds $bounds --voxel-size 0.05 -o far3.vdb --check --report far3.json
jcheck far3.json "s=d['error']['surface']; assert (s['missed'], s['extra']) == (0, 0), s"
# A solid fill needs every triangle whole: refused, naming the vertex and the fixes.
expect_exit 3 "$vox" voxelize far_city.obj --bounds $bounds --voxel-size 0.05 -o solid.vdb --fill solid
expect_stderr "far_city.obj: vertex 1 (as its 'f' lines number them) lies 39999840 voxels from the grid along x, beyond the 2^20 a solid fill reaches"
expect_stderr "voxels at least 39 times larger, or fill only the surface (--fill)"
[ ! -e solid.vdb ] || fail "a refused bake left solid.vdb"

if [ "$failures" -ne 0 ]; then
  echo "farclip: $failures failure(s)" >&2
  exit 1
fi
echo "farclip: ok"
