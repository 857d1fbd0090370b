#!/usr/bin/env bash
# End-to-end tests of `vox export`. Usage: export_test.sh GROUP VOX DATA_DIR TOOLS_DIR
# (DATA_DIR: tests/cli, for map_small.json; TOOLS_DIR: where tests/export/setup.sh
# installed the npm readers). Each group is one CTest test; expectations are
# computed by hand next to each command. Every .glb/.gltf a group writes is
# checked by the Khronos glTF validator at the end of the group (0 errors, 0 warnings).
set -u
group=$1 vox=$2 data=$3 tools=$4
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
expect_exit() {
  local want=$1; shift
  "$@" >out.txt 2>err.txt
  local got=$?
  [ "$got" = "$want" ] || fail "exit $got, expected $want: $* (stderr: $(head -c 400 err.txt))"
}
expect_stderr() { grep -qF -- "$1" err.txt || fail "stderr lacks '$1': $(head -c 400 err.txt)"; }
jcheck() { python3 -c "import json,sys; d=json.load(open('$1')); $2" || fail "json check failed on $1: $2"; }
# summary FILE: gltf_summary.py's JSON of FILE in FILE.summary.json
summary() { python3 "$here/gltf_summary.py" "$1" >"$1.summary.json" || fail "cannot read $1 back"; }
# nothing_but LIST: the work dir holds only these files (besides logs), e.g. after a failed run.
nothing_but() {
  local extra
  extra=$(ls -A | grep -v -x -F -e out.txt -e err.txt $(printf -- '-e %s ' "$@") || true)
  [ -z "$extra" ] || fail "unexpected files: $extra"
}
validate_gltf() {
  local files
  files=$(find . -name '*.glb' -o -name '*.gltf' | sort)
  [ -n "$files" ] || return 0
  # shellcheck disable=SC2086
  NODE_PATH="$tools/node_modules" node "$here/validate_gltf.mjs" $files >validator.txt 2>&1 ||
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
  expect_exit 2 "$vox" export small.vdb -o x.glb --level 1
  expect_stderr "single scene"
  expect_exit 2 "$vox" export small.vdb -o x.glb --level -1
  nothing_but small.vdb
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
  expect_stderr "no baked colours"
  [ "$(cat keep.glb)" = keep ] || fail "a failed export touched the existing output"
  expect_exit 4 "$vox" export small.vdb -o no/such/dir/x.glb
  nothing_but small.vdb keep.glb notes.txt
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
