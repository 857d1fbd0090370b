#!/usr/bin/env bash
# vox fuse --free voted (the default) against --free all (docs/fuse.md, "Where
# free counts are kept"): on a dirty input scene whose floating block the
# views see through, both carve the same scene; voted keeps free counts only
# at tracked voxels (fewer); a later run on each output
# gives the same scene; vox info names the `free` grid of a fused scene.
# Usage: fusefast_test.sh GROUP VOX_BINARY REPO_ROOT
set -u
group=$1 vox=$2 root=$3
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

case $group in
scopes)
  python3 - <<'EOF'
import json
blocks = [{'position': [x, 0, z], 'blockType': 'Grass'} for x in range(8) for z in range(8)]
blocks += [{'position': [1, y, 1], 'blockType': 'Stone'} for y in range(1, 7)]
json.dump({'worldScale': 1.0, 'blocks': blocks}, open('truth.json', 'w'))
blocks.append({'position': [6, 3, 6], 'blockType': 'Plank'})
json.dump({'worldScale': 1.0, 'blocks': blocks}, open('dirty.json', 'w'))
json.dump({'views': [{'depth': 'o_%03d.depth.exr' % i, 'label': 'o_%03d.class.png' % i,
                      'normal': 'o_%03d.normal.png' % i} for i in range(6)]}, open('views.json', 'w'))
EOF
  expect_exit 0 "$vox" voxelize truth.json -o truth.vdb --quiet
  expect_exit 0 "$vox" voxelize dirty.json -o dirty.vdb --quiet
  expect_exit 0 "$vox" render-canonical truth.vdb -o o.png --orbit 6 --size 120x90 --mode depth,class,normal --quiet
  expect_exit 0 "$vox" fuse views.json -i dirty.vdb -o v.vdb --report rv.json --quiet
  expect_exit 0 "$vox" fuse views.json -i dirty.vdb -o a.vdb --free all --report ra.json --quiet
  expect_exit 0 "$vox" diff v.vdb a.vdb
  jcheck rv.json "t=d['counts']['totals']; assert t['removed'] == 1 and t['free'] == 'voted', t"
  python3 -c "import json; v=json.load(open('rv.json'))['counts']['totals']; a=json.load(open('ra.json'))['counts']['totals']; assert 0 < v['free_voxels'] < a['free_voxels'], (v, a)" ||
    fail "voted keeps fewer free voxels than all"
  # The same views again on each output: the same scene.
  expect_exit 0 "$vox" fuse views.json -i v.vdb -o v2.vdb --quiet
  expect_exit 0 "$vox" fuse views.json -i a.vdb -o a2.vdb --free all --quiet
  expect_exit 0 "$vox" diff v2.vdb a2.vdb
  expect_exit 0 "$vox" info a.vdb
  expect_stdout "free grid"
  expect_exit 0 "$vox" info --json a.vdb
  jcheck out.txt "assert d['free_grid']['leaves'] > 0, d.get('free_grid')"
  expect_exit 0 "$vox" info truth.vdb
  if grep -q "free grid" out.txt; then fail "a scene without a free grid shows one"; fi
  expect_exit 2 "$vox" fuse views.json -o x.vdb --free some
  ;;
*)
  echo "unknown group $group" >&2
  exit 2
  ;;
esac
[ "$failures" = 0 ] || { echo "$failures failure(s) in fusefast.$group" >&2; exit 1; }
echo "fusefast.$group: ok"
