#!/usr/bin/env bash
# End-to-end tests of the `vox` binary. Usage: cli_test.sh GROUP VOX_BINARY DATA_DIR
# Each group is one CTest test. Expectations are written out by hand next to
# each command; JSON is checked with python3.
set -u
group=$1 vox=$2 data=$3
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"
# no_outputs: nothing but the test's own files in the work dir (no partial or temp files).
no_outputs() {
  local extra
  extra=$(ls -A | grep -v -E '^(out.txt|err.txt|.*\.json|keep.*)$' || true)
  [ -z "$extra" ] || fail "files left behind after a failed run: $extra"
}

case $group in
version)
  expect_exit 0 "$vox" --version
  expect_stdout "vox 0.1.0 (scene format 1)"
  expect_stdout "page file .vpk 1"
  expect_exit 0 "$vox" -V
  expect_exit 0 "$vox" --help
  expect_stdout "voxelize"
  expect_stdout "Exit codes"
  expect_exit 0 "$vox" voxelize --help
  expect_stdout "demo:hamlet"
  ;;
usage)
  expect_exit 2 "$vox"
  expect_stderr "vox: error: give a command first: voxelize, info, diff,"
  expect_exit 2 "$vox" no-such-command
  expect_stderr "vox: error: unknown command 'no-such-command'; the commands are voxelize, info,"
  expect_exit 2 "$vox" voxelise demo:hamlet -o x.vdb
  expect_stderr "unknown command 'voxelise' (did you mean 'voxelize'?)"
  expect_exit 2 "$vox" rendr x.vdb
  expect_stderr "(did you mean 'render-canonical'?)"
  expect_exit 2 "$vox" voxelize demo:hamlet            # no -o
  expect_stderr "vox voxelize: error: --output is required: scene file to write (*.vdb); see 'vox voxelize --help'"
  [ "$(wc -l < err.txt)" = 1 ] || fail "a usage error is one line, like every other error: $(cat err.txt)"
  # A missing positional is named, with the usage line (CLI11 alone says "a is required").
  expect_exit 2 "$vox" diff only-one.vdb
  expect_stderr "vox diff: error: missing the argument 'b': second file (the golden / reference one); usage: vox diff [OPTIONS] a b; see 'vox diff --help'"
  expect_exit 2 "$vox" voxelize -o x.vdb
  expect_stderr "missing the argument 'inputs': meshes (.obj"
  [ "$(wc -l < err.txt)" = 1 ] || fail "a usage error is one line, like every other error: $(cat err.txt)"
  expect_exit 2 "$vox" voxelize demo:hamlet -o x.vdb --res 0
  expect_stderr "vox voxelize: error: --res"
  # Options of another input kind would do nothing: refused by name.
  expect_exit 2 "$vox" voxelize demo:hamlet -o x.vdb --res 8 --fill solid
  expect_stderr "--fill applies to meshes, and demo:hamlet is the built-in demo:hamlet: drop --fill"
  expect_exit 2 "$vox" voxelize demo:hamlet -o x.vdb --res 8 --check
  expect_stderr "--check applies to meshes"
  expect_exit 2 "$vox" voxelize demo:hamlet -o x.vdb --res 8 --threshold 0.5
  expect_stderr "--threshold applies to .vdb grid inputs"
  expect_exit 2 "$vox" voxelize demo:hamlet -o x.vdb --res 8 --grid-size 4,4,4
  expect_stderr "--grid-size applies to block maps"
  [ -e x.vdb ] && fail "a refused voxelize wrote x.vdb"
  expect_exit 2 "$vox" voxelize demo:hamlet -o x.vdb --res abc
  expect_exit 2 "$vox" voxelize demo:hamlet -o x.png
  expect_stderr "*.vdb"
  expect_exit 2 "$vox" voxelize demo:castle -o x.vdb
  expect_stderr "demo:hamlet"
  expect_exit 2 "$vox" voxelize "$data/map_small.json" -o x.vdb --grid-size 1,2
  expect_stderr "--grid-size"
  expect_exit 2 "$vox" voxelize "$data/map_small.json" -o x.vdb --res 64
  expect_exit 2 "$vox" info
  expect_exit 2 "$vox" info a b
  no_outputs
  ;;
voxelize_map)
  expect_exit 0 "$vox" voxelize "$data/map_small.json" -o small.vdb
  [ -s small.vdb ] || fail "small.vdb not written"
  expect_exit 0 "$vox" info --json small.vdb
  cp out.txt info.json
  # Hand-computed: 5 solid blocks (Air ignored); dims = max position + 1 = 4,3,2;
  # worldScale 2, grid 64,48,64 -> origin (-64, 0, -64); all blocks have an empty neighbour.
  jcheck info.json "assert d['dims']==[4,3,2]; assert d['voxel_size']==2.0; assert d['origin']==[-64.0,0.0,-64.0]"
  jcheck info.json "assert d['occupied']==5 and d['surface']==5 and d['interior']==0 and d['colored']==0"
  jcheck info.json "assert d['bounds']=={'min':[0,0,0],'max':[3,2,1]}"
  jcheck info.json "c={x['name']:x for x in d['classes']}; assert c['Stone']['id']==3 and c['Stone']['voxels']==2 and c['Stone']['votes']==2; assert c['Grass']['voxels']==1 and c['Water']['voxels']==1 and c['Plank']['voxels']==1 and c['Sand']['voxels']==0"
  jcheck info.json "assert d['block_world']=={'world_scale':2.0,'grid_size':[64,48,64]}"
  jcheck info.json "s=d['sources'][0]; assert s['kind']=='blockmap' and len(s['sha256'])==64 and s['bytes']>0"
  jcheck info.json "assert d['world_bounds']['max']==[-56.0,6.0,-60.0]"
  # --grid-size moves the origin.
  expect_exit 0 "$vox" voxelize "$data/map_small.json" -o g.vdb --grid-size 10,10,20
  expect_exit 0 "$vox" info --json g.vdb
  cp out.txt g.json
  jcheck g.json "assert d['origin']==[-10.0,0.0,-20.0]"
  expect_exit 3 "$vox" voxelize "$data/map_small.json" -o g.vdb --grid-size 3,3,3
  expect_stderr "block 4"
  expect_stderr "outside the world grid 3,3,3"
  ;;
voxelize_demo)
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o a.vdb --threads 1
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o b.vdb --threads 2
  expect_exit 0 "$vox" info --json a.vdb
  cp out.txt a.json
  expect_exit 0 "$vox" info --json b.vdb
  sed 's/"b.vdb"/"a.vdb"/' out.txt > b.json
  python3 - <<'PY' || fail "demo info differs between --threads 1 and 2"
import json
a, b = json.load(open('a.json')), json.load(open('b.json'))
for d in (a, b): d.pop('file_bytes')
assert a == b, (a, b)
assert a['dims'] == [64, 64, 64] and a['occupied'] > 10000
assert len([c for c in a['classes'] if c['voxels'] > 0]) == 7
PY
  expect_exit 0 "$vox" info a.vdb
  expect_stdout "voxbake scene"
  expect_stdout "Water"
  ;;
bad_input)
  # Missing input, not JSON, missing fields, duplicate: exit 3, one line, nothing written.
  expect_exit 3 "$vox" voxelize nothere.json -o x.vdb
  expect_stderr "nothere.json"
  echo '{"worldScale": 1, "blocks": [' > keep_bad.json
  expect_exit 3 "$vox" voxelize keep_bad.json -o x.vdb
  expect_stderr "keep_bad.json: not valid JSON"
  [ "$(wc -l < err.txt)" = 1 ] || fail "expected one line on stderr, got: $(cat err.txt)"
  echo '{"blocks": []}' > keep_nofield.json
  expect_exit 3 "$vox" voxelize keep_nofield.json -o x.vdb
  expect_stderr "missing 'worldScale'"
  echo '{"worldScale":1,"blocks":[{"position":[0,0,0],"blockType":"Dirt"},{"position":[0,0,0],"blockType":"Sand"}]}' > keep_dup.json
  expect_exit 3 "$vox" voxelize keep_dup.json -o x.vdb
  expect_stderr "block 1: position [0, 0, 0] is already used by block 0"
  expect_exit 3 "$vox" voxelize mesh.obj -o x.vdb
  no_outputs
  # A failed run does not replace an existing output either.
  expect_exit 0 "$vox" voxelize "$data/map_small.json" -o keep_prev.vdb
  before=$(sha256sum keep_prev.vdb)
  expect_exit 3 "$vox" voxelize keep_dup.json -o keep_prev.vdb
  [ "$(sha256sum keep_prev.vdb)" = "$before" ] || fail "failed run modified an existing output"
  # Unwritable output directory: I/O error, exit 4.
  expect_exit 4 "$vox" voxelize "$data/map_small.json" -o /nonexistent-dir/x.vdb
  expect_stderr "/nonexistent-dir/x.vdb"
  # Bad .vdb inputs for info: missing, not a vdb, truncated, not a voxbake scene.
  expect_exit 3 "$vox" info missing.vdb
  expect_stderr "missing.vdb"
  echo "plain text" > keep_text.vdb
  expect_exit 3 "$vox" info keep_text.vdb
  head -c 1000 keep_prev.vdb > keep_cut.vdb
  expect_exit 3 "$vox" info keep_cut.vdb
  expect_stderr "truncated"
  [ "$(wc -l < err.txt)" = 1 ] || fail "expected one line on stderr, got: $(cat err.txt)"
  chmod 000 keep_prev.vdb
  if [ "$(id -u)" != 0 ]; then
    expect_exit 3 "$vox" info keep_prev.vdb
    expect_stderr "unreadable"
  fi
  chmod 644 keep_prev.vdb
  expect_exit 3 "$vox" info .
  ;;
info)
  expect_exit 0 "$vox" voxelize "$data/map_small.json" -o s.vdb
  expect_exit 0 "$vox" info s.vdb
  expect_stdout "dims          4 x 3 x 2 (24 voxels)"
  expect_stdout "occupied      5 voxels (20.8% of the domain)"
  expect_stdout "5 surface (100%), 0 interior"
  expect_stdout "block world   worldScale 2, grid 64,48,64"
  [ ! -s err.txt ] || fail "info printed on stderr: $(cat err.txt)"
  if command -v vdb_print >/dev/null; then
    vdb_print s.vdb > vp.txt 2>&1 || fail "vdb_print cannot read a scene"
    grep -q "occupancy" vp.txt || fail "vdb_print does not list the occupancy grid"
    grep -q "votes.3" vp.txt || fail "vdb_print does not list votes.3"
  else
    echo "SKIP: vdb_print not installed (package libopenvdb-tools)"
  fi
  ;;
depfile_report)
  expect_exit 0 "$vox" voxelize "$data/map_small.json" -o "out dir.vdb" --depfile d.d --report r.json
  printf '%s' "out\\ dir.vdb: \\" > want.d
  printf '\n  %s\n' "$data/map_small.json" >> want.d
  diff -u want.d d.d || fail "depfile content"
  jcheck r.json "assert d['command']=='voxelize' and d['exit_code']==0 and d['threads']>=1"
  jcheck r.json "assert [p['name'] for p in d['phases']]==['parse','write'] and all(p['seconds']>=0 for p in d['phases'])"
  # A ':' in a file name is escaped, so make reads the rule (a bare one ended the target list).
  cp "$data/map_small.json" "co:lon.json"
  expect_exit 0 "$vox" voxelize "co:lon.json" -o "c:out.vdb" --depfile colon.d -q
  grep -qF 'c\:out.vdb: \' colon.d && grep -qF 'co\:lon.json' colon.d || fail "':' not escaped: $(cat colon.d)"
  if command -v make >/dev/null; then
    printf 'all: c\\:out.vdb\ninclude colon.d\n' >colon.mk
    make -q -f colon.mk 2>mk_err.txt || [ $? = 1 ] || fail "make cannot read the depfile: $(cat mk_err.txt)"
  fi
  # A report or depfile whose directory is missing is refused before the work, nothing written.
  for opt in --report --depfile; do
    expect_exit 4 "$vox" voxelize "$data/map_small.json" -o nodir_out.vdb $opt nodir/x
    expect_stderr "nodir/x: cannot write: directory 'nodir' does not exist"
    [ -e nodir_out.vdb ] && fail "$opt in a missing directory: the output was written"
    grep -qF "wrote" err.txt && fail "$opt in a missing directory: the work ran first"
  done
  # --threads past its bound is a usage error (70000 crashed the thread pool).
  expect_exit 2 "$vox" voxelize "$data/map_small.json" -o t.vdb --threads 70000
  expect_stderr "--threads"
  jcheck r.json "assert d['counts']['occupied_voxels']==5 and d['counts']['dims']==[4,3,2]"
  jcheck r.json "assert d['outputs']==['out dir.vdb'] and d['inputs']==['$data/map_small.json']"
  expect_exit 0 "$vox" voxelize demo:hamlet --res 16 -o h.vdb --depfile h.d --threads 2 --report h.json
  grep -q "^h.vdb:" h.d || fail "demo depfile: $(cat h.d)"
  jcheck h.json "assert d['threads']==2 and d['phases'][0]['name']=='generate'"
  # A failed run writes neither report nor depfile.
  rm -f r.json d.d
  expect_exit 3 "$vox" voxelize missing.json -o y.vdb --depfile d.d --report r.json
  [ ! -e d.d ] && [ ! -e r.json ] && [ ! -e y.vdb ] || fail "failed run left depfile/report/output"
  # A run never writes over a file it reads or writes twice: refused before the work (exit 2), every file as it was.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 8 -o s.vdb -q
  cp s.vdb s.keep; ln -sf s.vdb s_link.vdb
  expect_exit 2 "$vox" export s.vdb -o ./s.vdb --fog
  expect_stderr "./s.vdb: this run would write it as an output and it is also an input (s.vdb)"
  expect_exit 2 "$vox" export s_link.vdb -o s.vdb --level-set
  expect_stderr "also an input (s_link.vdb)"
  expect_exit 2 "$vox" mip s.vdb -o p.vdb --report s.vdb
  expect_stderr "s.vdb: this run reads it and would also write it as its --report"
  expect_exit 2 "$vox" mip s.vdb -o p.vdb --report p.vdb
  expect_stderr "it is also the --report file; give --report another name"
  expect_exit 2 "$vox" mip s.vdb -o p.vdb --report r.json --depfile ./r.json
  expect_stderr "given as both --report and --depfile"
  expect_exit 2 "$vox" voxelize "$data/map_small.json" -o m.vdb --depfile "$data/../cli/map_small.json"
  expect_stderr "this run reads it and would also write it as its --depfile"
  cmp s.vdb s.keep || fail "a refused run changed its input"
  [ ! -e p.vdb ] && [ ! -e r.json ] && [ ! -e m.vdb ] || fail "a refused run wrote a file"
  # Updating in place is what fuse -i S -o S and mip S -o S (level 0 is S) are for.
  expect_exit 0 "$vox" mip s.vdb -o s.vdb -q
  expect_exit 0 "$vox" diff s.vdb s.keep --level 0
  # --split writes level files, which are not the scene: one may not replace it.
  cp s.keep s.mip1.vdb
  expect_exit 2 "$vox" mip s.mip1.vdb -o s.vdb --split -q
  cmp s.mip1.vdb s.keep || fail "mip --split replaced its input"
  # --quiet silences the note; --progress with a non-terminal still works.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 8 -o q.vdb --quiet
  [ ! -s err.txt ] || fail "--quiet printed: $(cat err.txt)"
  # Progress bars: none when stderr is not a terminal, unless --progress; never with --quiet.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 8 -o q.vdb
  ! grep -q "%" err.txt || fail "progress bar drawn on a non-terminal: $(cat err.txt)"
  expect_exit 0 "$vox" voxelize demo:hamlet --res 8 -o q.vdb --progress
  grep -q "100%" err.txt || fail "--progress drew no bar: $(cat err.txt)"
  [ ! -s out.txt ] || fail "progress went to stdout"
  expect_exit 0 "$vox" voxelize demo:hamlet --res 8 -o q.vdb --progress --quiet
  [ ! -s err.txt ] || fail "--quiet --progress printed: $(cat err.txt)"
  ;;
diff)
  # Determinism voxel for voxel through the CLI: the same scene for --threads 1 and 2, twice.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 48 -o t1.vdb --threads 1
  expect_exit 0 "$vox" voxelize demo:hamlet --res 48 -o t2.vdb --threads 2
  expect_exit 0 "$vox" voxelize demo:hamlet --res 48 -o t2b.vdb --threads 2
  expect_exit 0 "$vox" diff t1.vdb t2.vdb
  expect_stdout "same"
  expect_exit 0 "$vox" diff t2.vdb t2b.vdb --json
  cp out.txt same.json
  jcheck same.json "assert d['same'] and d['voxels_differing']==0 and d['voxels_compared']>1000"
  # Different scenes: exit 1 and the first difference.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 47 -o other.vdb
  expect_exit 1 "$vox" diff t1.vdb other.vdb
  expect_stdout "DIFFERENT"
  expect_stdout "first difference at voxel"
  expect_exit 3 "$vox" diff t1.vdb missing.vdb
  ;;
vdb_input)
  # A level set written by OpenVDB's own tool, when it is installed.
  if command -v vdb_tool >/dev/null; then
    vdb_tool -sphere r=8 dim=64 voxel=0.25 name=ball -write keep_ball.vdb >/dev/null 2>&1 || fail "vdb_tool failed"
    expect_exit 0 "$vox" voxelize keep_ball.vdb --voxel-size 0.5 -o ball.vdb --depfile ball.d
    expect_exit 0 "$vox" info --json ball.vdb
    cp out.txt ball.json
    # (4/3) pi 8^3 / 0.5^3 = 17157 voxels, within 4%.
    jcheck ball.json "assert abs(d['occupied']-17157) < 0.04*17157, d['occupied']"
    grep -q "keep_ball.vdb" ball.d || fail "depfile lacks the .vdb input"
    expect_exit 0 "$vox" info keep_ball.vdb
    expect_stdout "not a voxbake scene"
    expect_stdout "ball"
    expect_exit 0 "$vox" info --json keep_ball.vdb
    cp out.txt foreign.json
    jcheck foreign.json "assert d['kind']=='openvdb' and d['grids'][0]['name']=='ball'"
    expect_exit 2 "$vox" voxelize keep_ball.vdb --voxel-size 0.5 --res 10 -o x.vdb
    expect_exit 3 "$vox" voxelize keep_ball.vdb --grid nothere -o x.vdb
    expect_stderr "no grid named 'nothere'"
  else
    echo "SKIP: vdb_tool not installed (package libopenvdb-tools)"
  fi
  ;;
atlas)
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o g.vdb
  # Default outputs: the summary atlas, the 1-bit bitmap and the sidecar, nothing else.
  expect_exit 0 "$vox" build-atlas g.vdb -o def
  [ "$(ls def | tr '\n' ' ')" = "g.atlas.json g.occupancy.png g.summary.png " ] || fail "default outputs: $(ls def)"
  jcheck def/g.atlas.json "assert d['layout']['width']==512 and d['layout']['height']==512 and len(d['files'])==2"
  # Golden bytes, identical at 1 and 2 threads (Debian 12's zlib and libpng).
  expect_exit 0 "$vox" build-atlas g.vdb -o a1 --all --threads 1
  expect_exit 0 "$vox" build-atlas g.vdb -o a2 --all --threads 2
  (cd a1 && sha256sum *.png) > got.sum
  diff -u "$data/../golden/demo64_atlas.sha256" got.sum || fail "demo atlases differ from the golden hashes"
  (cd a2 && sha256sum *.png) | diff -q - got.sum >/dev/null || fail "atlases differ between --threads 1 and 2"
  # Every atlas checks out against its scene, through the inverse mapping.
  for f in a1/*.png; do
    expect_exit 0 "$vox" verify-bijection --atlas "$f" --scene g.vdb
  done
  expect_exit 0 "$vox" verify-bijection --atlas a1/g.summary.png --scene g.vdb --json
  cp out.txt v.json
  jcheck v.json "assert d['ok'] and d['texels_checked']==512*512 and d['failures']==0"
  # An atlas of a scene that differs in one block fails at that block's texel.
  expect_exit 0 "$vox" voxelize "$data/map_small.json" -o m.vdb
  sed 's/"position": \[3, 2, 1\], "blockType": "Plank"/"position": [3, 2, 1], "blockType": "Snow"/' "$data/map_small.json" > keep_m2.json
  expect_exit 0 "$vox" voxelize keep_m2.json -o m2.vdb
  expect_exit 0 "$vox" build-atlas m2.vdb -o bad --all
  expect_exit 1 "$vox" verify-bijection --atlas bad/m2.summary.png --scene m.vdb --json
  cp out.txt f.json
  python3 - <<'PY' || fail "flipped texel not reported at the right place"
import json
d = json.load(open('f.json'))
assert d['failures'] == 1, d
f = d['first_failure']
assert f['voxel'] == [3, 2, 1], f
assert f['expected'][0] == 4 and f['actual'][0] == 5, f   # Plank (4) expected, Snow (5) found
# 4 x 3 tiles, one per row (4 x 6 is squarer than 8 x 3): tile w = 1 starts at y = 3,
# so voxel (3, 2, 1) is texel (3, 3 + 2).
assert f['texel'] == [0, 3, 5], f
PY
  expect_exit 0 "$vox" verify-bijection --atlas bad/m2.occupancy2.png --scene m.vdb
  expect_exit 0 "$vox" verify-bijection --atlas bad/m2.votes.3.png --scene m.vdb
  expect_exit 1 "$vox" verify-bijection --atlas bad/m2.votes.5.png --scene m.vdb
  expect_stdout "first: texel"
  # Picking: a texel decodes to its voxel and summary.
  expect_exit 0 "$vox" info a1/g.summary.png --pixel 100,20 --scene g.vdb --json
  cp out.txt p.json
  jcheck p.json "p=d['pixel']; assert p['voxel'] is not None and p['texel']==[0,100,20]"
  expect_exit 0 "$vox" info a1/g.summary.png
  expect_stdout "summary atlas (rgba8)"
  # What cannot be written is refused before anything is written.
  expect_exit 2 "$vox" build-atlas g.vdb -o nocolor --color
  expect_stderr "no colour"
  [ ! -e nocolor/g.summary.png ] || fail "a refused run wrote files"
  expect_exit 0 "$vox" voxelize demo:hamlet --res 300 -o big.vdb
  expect_exit 2 "$vox" build-atlas big.vdb -o idf --identity --format rgba8
  expect_stderr "cannot hold coordinate 256"
  expect_stderr "rgba16 would"
  expect_exit 0 "$vox" build-atlas big.vdb -o idf --identity --format rgba16f
  expect_exit 0 "$vox" verify-bijection --atlas idf/big.identity.exr --scene big.vdb
  expect_exit 3 "$vox" verify-bijection --atlas g.vdb --scene g.vdb
  expect_exit 2 "$vox" verify-bijection --atlas a1/g.summary.png
  # An atlas that is not there, or a directory, is named as such.
  expect_exit 3 "$vox" verify-bijection --atlas missing.png --scene g.vdb
  expect_stderr "missing.png: no such file"
  expect_exit 3 "$vox" verify-bijection --atlas a1 --scene g.vdb
  expect_stderr "a1: is a directory"
  # The output directory: an empty path is a usage error; a file in its way is named.
  expect_exit 2 "$vox" build-atlas g.vdb -o ""
  expect_stderr "--output '': an empty path"
  : > keep_afile
  expect_exit 4 "$vox" build-atlas g.vdb -o keep_afile
  expect_stderr "keep_afile: cannot create the output directory: it is a file"
  expect_exit 4 "$vox" build-atlas g.vdb -o keep_afile/sub
  expect_stderr "keep_afile/sub: cannot create the output directory: keep_afile is a file"
  # --format is the identity atlas's: with other contents only it would be ignored.
  expect_exit 2 "$vox" build-atlas g.vdb -o fmt --summary --format rgba16
  expect_stderr "--format applies to the identity atlas"
  [ ! -e fmt ] || fail "a refused build-atlas made its directory"
  expect_exit 0 "$vox" build-atlas g.vdb -o fmt --identity --format rgba16
  # A --max-side past libpng's 1000000 is refused before the work (it failed at the write, exit 4, or wrote a
  # PNG vox could not read back); 1000000 itself is fine.
  expect_exit 2 "$vox" build-atlas g.vdb -o wide --max-side 2000000
  expect_stderr "--max-side 2000000: past 1000000, the largest PNG side vox writes and reads back"
  [ ! -e wide ] || fail "a refused build-atlas made its directory"
  expect_exit 0 "$vox" build-atlas g.vdb -o wide --max-side 1000000
  ;;
bijection)
  expect_exit 0 "$vox" verify-bijection --res 256
  expect_stdout "exhaustive"
  expect_stdout "OK"
  expect_exit 0 "$vox" verify-bijection --dims 1,1,4097 --json
  cp out.txt b.json
  jcheck b.json "assert d['ok'] and d['voxels_checked']==4097 and d['method']=='exhaustive'"
  expect_exit 0 "$vox" verify-bijection --dims 100000,100000,100000 --max-side 200000
  expect_stdout "by-parts"
  expect_exit 0 "$vox" verify-bijection --format rgba16f --dims 2049,1,1
  expect_exit 1 "$vox" verify-bijection --format rgba16f --dims 2050,1,1
  expect_stdout "cannot hold coordinate 2049"
  expect_exit 0 "$vox" verify-bijection --format rgba32f --json
  cp out.txt f.json
  jcheck f.json "assert d['max_exact_integer']==2**24"
  expect_exit 2 "$vox" verify-bijection
  expect_exit 2 "$vox" verify-bijection --dims 0,1,1
  expect_exit 2 "$vox" verify-bijection --format rgba12
  expect_exit 2 "$vox" verify-bijection --dims 40000,1,1
  expect_stderr "--max-side"
  # A maximum side past what an image can have is refused at once (a 32-bit
  # search counter wrapped there: 14 s, then a division by zero).
  expect_exit 2 timeout 20 "$vox" verify-bijection --dims 1,1,4294967295 --max-side 4294967295
  expect_stderr "past 2147483647"
  expect_exit 0 "$vox" verify-bijection --res 64 --report r.json
  jcheck r.json "assert d['command']=='verify-bijection' and d['error']['failures']==0"
  ;;
mesh)
  # A unit cube of two materials, written here.
  cat > keep_cube.obj <<'OBJ'
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
  printf 'newmtl Wall\nKd 0.5 0.5 0.5\nnewmtl Roof\nKd 1 0 0\n' > keep_cube.mtl
  expect_exit 0 "$vox" voxelize keep_cube.obj --res 8 -o s.vdb --check --report s.json --depfile s.d
  jcheck s.json "e=d['error']['surface']; assert e['missed']==0 and e['extra']==0 and e['oracle_voxels']==d['counts']['occupied_voxels']"
  jcheck s.json "assert d['counts']['triangles']==12 and d['counts']['dims']==[8,8,8] and [p['name'] for p in d['phases']]==['parse','prepare','voxelize','write','check']"
  grep -q keep_cube.mtl s.d || fail "depfile lacks the mtl"
  expect_exit 0 "$vox" info --json s.vdb
  cp out.txt s_info.json
  # Surface of an 8^3 cube whose faces lie on grid planes: the 8^3 shell (closed boxes) = 8^3 - 6^3.
  jcheck s_info.json "assert d['occupied']==8**3-6**3 and [c['name'] for c in d['classes']]==['Wall','Roof'] and d['has_color']"
  expect_exit 0 "$vox" voxelize keep_cube.obj --res 8 -o solid.vdb --fill solid --check --report solid.json
  jcheck solid.json "e=d['error']['solid']; assert abs(e['mesh_volume']-1.0)<1e-9 and abs(e['voxel_volume']-1.0)<1e-9 and e['iou']==1.0"
  expect_exit 0 "$vox" voxelize keep_cube.obj --res 8 -o sdf.vdb --fill solid --method sdf
  # --classes maps materials; several inputs combine; --pad grows the grid.
  printf '{"classes":[{"name":"roof","id":9,"match":["material:Roof"]},{"name":"rest"}],"default":"rest"}' > keep_classes.json
  expect_exit 0 "$vox" voxelize keep_cube.obj keep_cube.obj --res 8 --pad 2 -o c.vdb --classes keep_classes.json
  expect_exit 0 "$vox" info --json c.vdb
  cp out.txt c.json
  jcheck c.json "assert d['dims']==[14,14,14] and sorted(c['name'] for c in d['classes'])==['rest','roof'] and len(d['sources'])==2"
  # --pad 2 leaves 2 empty layers on every side (the cube's faces lie on voxel faces and touch the layer outside them).
  jcheck c.json "b=d['bounds']; assert b['min']==[2,2,2] and b['max']==[11,11,11], b"
  # Resolution 1: one voxel.
  expect_exit 0 "$vox" voxelize keep_cube.obj --res 1 -o one.vdb
  # Bad inputs: empty mesh, NaN, unknown options.
  : > keep_empty.obj
  expect_exit 3 "$vox" voxelize keep_empty.obj -o e.vdb
  expect_stderr "no triangles"
  printf 'v 0 0 0\nv 1 0 nan\nv 0 1 0\nv 1 1 1\nf 1 2 3\nf 1 3 4\n' > keep_nan.obj
  expect_exit 3 "$vox" voxelize keep_nan.obj -o e.vdb
  expect_stderr "--drop-invalid"
  expect_exit 0 "$vox" voxelize keep_nan.obj -o e.vdb --drop-invalid
  expect_stderr "dropped 1 triangle touching 1 vertex"
  # A concave polygon fills only its own voxels (the fan filled 61 here), as
  # the same U written as triangles does; every solid of an STL is read.
  printf 'v 0 0 0\nv 8 0 0\nv 8 8 0\nv 6 8 0\nv 6 2 0\nv 2 2 0\nv 2 8 0\nv 0 8 0\nf 1 2 3 4 5 6 7 8\n' > keep_u.obj
  expect_exit 0 "$vox" voxelize keep_u.obj -o u.vdb --voxel-size 1
  expect_stderr "54 occupied voxels from 6 triangles"
  printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\nsolid u\nfacet normal 0 0 1\nouter loop\nvertex 0 0 5\nvertex 1 0 5\nvertex 0 1 5\nendloop\nendfacet\nendsolid u\n' > keep_two.stl
  expect_exit 0 "$vox" voxelize keep_two.stl -o two.vdb --res 4
  expect_stderr "from 2 triangles"
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 40000000 0 0\nf 1 2 3\nf 1 2 4\n' > keep_far.obj
  # A triangle reaching 4e7 voxels from the grid (here a segment along x) is
  # clipped near the grid by a surface fill: voxels (0..3, 0, 0) and (0, 1, 0);
  # a solid fill refuses it, naming the vertex.
  expect_exit 0 "$vox" voxelize keep_far.obj -o keep_far.vdb --voxel-size 1 --bounds 0,0,0,4,4,4
  expect_stderr "5 occupied voxels from 2 triangles"
  expect_exit 3 "$vox" voxelize keep_far.obj -o keep_far.vdb --voxel-size 1 --bounds 0,0,0,4,4,4 --fill solid
  expect_stderr "keep_far.obj: vertex 4 (as its 'f' lines number them) lies 40000000 voxels from the grid"
  expect_exit 2 "$vox" voxelize keep_cube.obj -o x.vdb --fill hollow
  expect_exit 2 "$vox" voxelize keep_cube.obj -o x.vdb --bounds 1,2,3
  # Names and paths that are not UTF-8 (a Windows-1252 material name, Latin-1
  # file names) are written transcoded in every JSON, never an internal error.
  latin=$(printf 'caf\xe9')
  printf 'newmtl Mat\xe9riau\nKd 1 0 0\n' > "keep_$latin.mtl"
  printf 'mtllib keep_%s.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl Mat\xe9riau\nf 1 2 3\n' "$latin" > "keep_$latin.obj"
  expect_exit 0 "$vox" voxelize "keep_$latin.obj" --res 8 -o "keep_$latin.vdb" --report latin.json
  jcheck latin.json "assert d['inputs'][0].endswith('keep_caf\u00e9.obj') and d['outputs'][0].endswith('keep_caf\u00e9.vdb'), d"
  expect_exit 0 "$vox" info "keep_$latin.vdb" --json
  jcheck out.txt "assert [c['name'] for c in d['classes']]==['Mat\u00e9riau'], d['classes']"
  expect_exit 0 "$vox" build-atlas "keep_$latin.vdb" -o "keep_atlas_$latin" --summary --report "atlas_$latin.json"
  expect_exit 0 "$vox" export "keep_$latin.vdb" -o "keep_$latin.gltf"
  python3 -c "import json,sys; json.load(open(sys.argv[1], encoding='utf-8'))" "keep_$latin.gltf" || fail "the glTF is not UTF-8 JSON"
  # Its buffer URI is the .bin's name byte for byte, percent-encoded (keep_caf%E9.bin).
  python3 -c "
import json, os, sys, urllib.parse
uri = json.load(open(sys.argv[1], encoding='utf-8'))['buffers'][0]['uri']
assert uri == 'keep_caf%E9.bin' and urllib.parse.unquote_to_bytes(uri) == os.fsencode(sys.argv[2]), uri
" "keep_$latin.gltf" "keep_$latin.bin" || fail "the glTF's buffer URI does not name keep_$latin.bin"
  # A report or depfile that cannot be written stops the run before any output
  # is made (it used to fail after the scene had been renamed into place).
  mkdir -p keep_report_dir.json
  expect_exit 4 "$vox" voxelize keep_cube.obj --res 8 -o keep_not_made.vdb --report keep_report_dir.json
  expect_stderr "keep_report_dir.json: cannot write: it is a directory"
  [ ! -e keep_not_made.vdb ] || fail "the scene was written although its report could not be"
  expect_exit 4 "$vox" voxelize keep_cube.obj --res 8 -o keep_not_made.vdb --depfile no_such_dir/d.d
  [ ! -e keep_not_made.vdb ] || fail "the scene was written although its depfile could not be"
  # ... but a directory the command itself makes may take them (the demo's atlas report).
  expect_exit 0 "$vox" voxelize keep_cube.obj --res 8 -o keep_for_atlas.vdb
  expect_exit 0 "$vox" build-atlas keep_for_atlas.vdb -o keep_new_dir/atlas --summary \
    --report keep_new_dir/atlas/report.json --depfile keep_new_dir/atlas/atlas.d
  [ -s keep_new_dir/atlas/report.json ] && [ -s keep_new_dir/atlas/atlas.d ] || fail "the atlas's report or depfile is missing"
  # A --bounds box beside the mesh: the empty scene is written, with a warning.
  expect_exit 0 "$vox" voxelize keep_cube.obj --voxel-size 0.25 --bounds 5,5,5,6,6,6 -o keep_empty_scene.vdb --report empty.json
  expect_stderr "the scene is empty"
  expect_stderr "--bounds 5,5,5,6,6,6"
  jcheck empty.json "assert d['counts']['occupied_voxels']==0 and any('scene is empty' in w for w in d['counts']['warnings'])"
  expect_exit 2 "$vox" voxelize keep_cube.obj demo:hamlet -o x.vdb
  # A missing MTL file: an error naming it, or with --ignore-missing-materials a warning.
  printf 'mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl Roof\nf 1 2 3\n' > keep_nomtl.obj
  expect_exit 3 "$vox" voxelize keep_nomtl.obj --res 8 -o nomtl.vdb
  expect_stderr "gone.mtl"
  expect_exit 0 "$vox" voxelize keep_nomtl.obj --res 8 -o nomtl.vdb --ignore-missing-materials
  expect_stderr "gone.mtl"
  expect_exit 0 "$vox" info nomtl.vdb --json
  jcheck out.txt "assert [c['name'] for c in d['classes']]==['Roof'], d['classes']"
  # OBJ vertex colours (v x y z r g b) colour the voxels.
  printf 'v 0 0 0 1 0 0\nv 1 0 0 1 0 0\nv 0 1 0 1 0 0\nf 1 2 3\n' > keep_red.obj
  expect_exit 0 "$vox" voxelize keep_red.obj --res 8 -o red.vdb
  expect_exit 0 "$vox" info red.vdb --json
  jcheck out.txt "assert d['colored']>0, d"
  # Mesh bakes run in the light module (no OpenVDB) and write the .vdb directly:
  # the same scene as the OpenVDB path (--check runs in vox-cmds.so), the same
  # bytes at any thread count and on every run (the UUID comes from the content).
  expect_exit 0 "$vox" voxelize keep_cube.obj keep_red.obj --res 16 -o light1.vdb --threads 1 --report light.json
  jcheck light.json "assert d['counts']['occupied_voxels']>0 and d['counts']['classes_present']==3, d['counts']"
  expect_exit 0 "$vox" voxelize keep_cube.obj keep_red.obj --res 16 -o light2.vdb --threads 2
  cmp -s light1.vdb light2.vdb || fail "light bake: bytes differ between --threads 1 and 2"
  expect_exit 0 "$vox" voxelize keep_cube.obj keep_red.obj --res 16 -o full.vdb --check
  expect_exit 0 "$vox" diff light1.vdb full.vdb
  # Voxels below what an OpenVDB transform holds: a usage error from both paths, no output.
  printf 'v 0 0 0\nv 0.0001 0 0\nv 0 0.0001 0\nf 1 2 3\n' > keep_micro.obj
  expect_exit 2 "$vox" voxelize keep_micro.obj --res 64 -o micro.vdb
  expect_stderr "below 1.5e-5 world units"
  expect_stderr "scale the input up"
  expect_exit 2 "$vox" voxelize keep_micro.obj --res 64 -o micro.vdb --check
  [ -e micro.vdb ] && fail "micro.vdb written despite the error"
  # Without the light module, vox falls back to the full one.
  mkdir -p nolight && cp "$(dirname "$vox")/vox" "$(dirname "$vox")/vox-cmds.so" nolight/
  expect_exit 0 nolight/vox voxelize keep_cube.obj keep_red.obj --res 16 -o fallback.vdb --threads 2
  cmp -s light1.vdb fallback.vdb || fail "the full module's mesh bake differs from the light module's"
  ;;
mip_pack)
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o h.vdb
  # Pyramid in one file; error against the hamlet voxelized directly at 32, 16, ...
  expect_exit 0 "$vox" mip h.vdb -o p.vdb --source demo:hamlet --report mip.json --depfile mip.d
  jcheck mip.json "L=d['counts']['levels']; assert [l['dims'] for l in L]==[[32]*3,[16]*3,[8]*3,[4]*3,[2]*3,[1]*3]; assert L[-1]['occupied']==1"
  jcheck mip.json "L0=d['counts']['levels'][0]['occupied']; E=d['error']['levels']; assert len(E)==6 and E[0]['level']==1 and 0<E[0]['iou']<=1 and E[0]['both']+E[0]['only_mip']==L0 and 0<=E[0]['class_disagreement']<=1"
  grep -q 'h.vdb' mip.d || fail "depfile lacks the input"
  expect_exit 0 "$vox" info --json p.vdb
  cp out.txt pinfo.json
  jcheck pinfo.json "assert d['dims']==[64,64,64] and len(d['pyramid']['levels'])==6 and d['pyramid']['occupancy']=='any'"
  expect_exit 0 "$vox" info p.vdb
  expect_stdout "pyramid       6 levels"
  # The pyramid file is still a scene (level 0); diff compares it level by level,
  # so against the plain scene only the extra levels differ.
  expect_exit 1 "$vox" diff p.vdb h.vdb
  expect_stdout "level 0 (64 x 64 x 64): same"
  # --split: one scene per level; the same content at any thread count.
  expect_exit 0 "$vox" mip h.vdb -o s.vdb --split --levels 2 --occupancy majority --threads 1
  expect_exit 0 "$vox" info --json s.mip2.vdb
  cp out.txt s2.json
  jcheck s2.json "assert d['dims']==[16,16,16] and d['mip_level']==2 and abs(d['voxel_size']-1.6)<1e-12"
  expect_exit 0 "$vox" mip h.vdb -o t.vdb --split --levels 2 --occupancy majority --threads 2
  expect_exit 0 "$vox" diff s.mip2.vdb t.mip2.vdb
  [ ! -e s.mip3.vdb ] || fail "--levels 2 wrote a third level"
  # Fewer levels over an earlier split: its level files past the last are named in a warning.
  expect_exit 0 "$vox" mip h.vdb -o u.vdb --split --levels 4 -q
  expect_exit 0 "$vox" mip h.vdb -o u.vdb --split --levels 2 --report u.json
  expect_stderr "warning: 2 level files of an earlier run remain beside this pyramid of 2 levels: u.mip3.vdb .. u.mip4.vdb"
  jcheck u.json "assert d['counts']['stale_level_files'] == ['u.mip3.vdb', 'u.mip4.vdb'], d['counts']"
  expect_exit 2 "$vox" mip h.vdb -o x.vdb --levels 7
  expect_stderr "at most 6"
  expect_exit 2 "$vox" mip h.vdb -o x.vdb --occupancy most
  expect_exit 3 "$vox" mip missing.vdb -o x.vdb
  # Page files: byte-identical at any thread count, verified, described.
  expect_exit 0 "$vox" pack-chunks h.vdb -o a.vpk --mips --threads 1 --report pack.json
  expect_exit 0 "$vox" pack-chunks h.vdb -o b.vpk --mips --threads 2
  cmp -s a.vpk b.vpk || fail "page files differ between --threads 1 and 2"
  jcheck pack.json "c=d['counts']; assert c['chunk']==16 and c['levels'][0]['voxels']>0 and len(c['levels'])==7 and c['bytes_per_voxel']>0"
  expect_exit 0 "$vox" pack-chunks --verify a.vpk
  expect_exit 0 "$vox" info --json a.vpk
  cp out.txt ainfo.json
  jcheck ainfo.json "assert d['kind']=='pagefile' and d['layout']=='bricks' and d['chunk']==16 and d['align'] in (64, 4096) and len(d['levels'])==7 and d['channels']==['occupancy','summary','surface']"
  # --align auto is the default and the report names what it chose; a number is kept.
  python3 -c "import json; a=json.load(open('ainfo.json'))['align']; c=json.load(open('pack.json'))['counts']['align']; assert a == c, (a, c)" ||
    fail "info and the pack report disagree on the alignment"
  expect_exit 0 "$vox" pack-chunks h.vdb -o auto.vpk --mips --align auto
  cmp -s a.vpk auto.vpk || fail "--align auto differs from the default"
  expect_exit 0 "$vox" pack-chunks h.vdb -o page.vpk --mips --align 4096 --report page.json
  jcheck page.json "assert d['counts']['align']==4096"
  for bad in 0 100 abc 4k; do
    expect_exit 2 "$vox" pack-chunks h.vdb -o bad.vpk --align $bad
    expect_stderr "auto"
    [ ! -e bad.vpk ] || fail "--align $bad wrote bad.vpk"
  done
  expect_exit 0 "$vox" info a.vpk
  expect_stdout "bytes per voxel"
  # From the stored pyramid, chunk 8, small alignment.
  expect_exit 0 "$vox" pack-chunks p.vdb -o c.vpk --mips --chunk 8 --align 64
  expect_exit 0 "$vox" pack-chunks --verify c.vpk
  # Corruption: a flipped payload byte fails --verify (exit 1) naming the chunk and the field;
  # a truncated file is refused (exit 3).
  python3 -c "
import struct
b=bytearray(open('a.vpk','rb').read()); off=struct.unpack_from('<Q',b,128+16)[0]; b[off+5]^=0x40
open('keep_bad.vpk','wb').write(b); open('keep_cut.vpk','wb').write(b[:len(b)-7])"
  expect_exit 1 "$vox" pack-chunks --verify keep_bad.vpk
  expect_stderr "chunk 0 (level 0"
  expect_stderr "crc32c"
  expect_exit 3 "$vox" pack-chunks --verify keep_cut.vpk
  expect_stderr "truncated"
  expect_exit 3 "$vox" info keep_cut.vpk
  expect_exit 2 "$vox" pack-chunks h.vdb -o x.vpk --chunk 12
  expect_exit 2 "$vox" pack-chunks h.vdb
  expect_exit 2 "$vox" pack-chunks h.vdb -o a.vdb
  expect_stderr "name it *.vpk"
  [ -e a.vdb ] && fail "pack-chunks wrote a page file named a.vdb"
  expect_exit 2 "$vox" pack-chunks h.vdb -o x.vpk --layout octree
  expect_stderr "expected bricks|svo|columns"
  expect_exit 2 "$vox" pack-chunks h.vdb -o x.vpk --chunk -8
  expect_stderr "--chunk: -8: expected 8, 16 or 32"
  # Options that do not apply are refused like their neighbours, nothing written.
  expect_exit 2 "$vox" pack-chunks h.vdb -o x.vpk --occupancy majority
  expect_stderr "--occupancy requires --mips"
  expect_exit 2 "$vox" pack-chunks --verify a.vpk --chunk 8
  expect_stderr "--verify excludes --chunk"
  [ ! -e x.vpk ] || fail "a refused pack-chunks wrote x.vpk"
  # A pyramid's stored levels are packed as they are: --occupancy and --levels may
  # select them (the first N), and a conflict is a usage error naming the fix.
  expect_exit 0 "$vox" mip h.vdb -o maj.vdb --levels 2 --occupancy majority -q
  expect_exit 0 "$vox" pack-chunks maj.vdb -o maj.vpk --mips -q
  expect_exit 0 "$vox" pack-chunks maj.vdb -o maj2.vpk --mips --levels 2 --occupancy majority -q
  cmp -s maj.vpk maj2.vpk || fail "--levels 2 --occupancy majority of a 2-level majority pyramid differs from its stored levels"
  expect_exit 0 "$vox" pack-chunks maj.vdb -o maj1.vpk --mips --levels 1 -q
  expect_exit 0 "$vox" info --json maj1.vpk
  jcheck out.txt "assert len(d['levels'])==2 and d['mip_occupancy']=='from maj.vdb', d.get('mip_occupancy')"
  expect_exit 2 "$vox" pack-chunks maj.vdb -o bad.vpk --mips --levels 3
  expect_stderr "--levels 3: maj.vdb is a vox mip pyramid with 2 stored levels"
  expect_stderr "run vox mip again with --levels 3"
  expect_exit 2 "$vox" pack-chunks maj.vdb -o bad.vpk --mips --occupancy any
  expect_stderr "occupancy 'majority'"
  expect_exit 2 "$vox" pack-chunks p.vdb -o bad.vpk --mips --occupancy majority
  expect_stderr "--occupancy majority: p.vdb is a vox mip pyramid whose stored levels have occupancy 'any'"
  expect_stderr "omit --occupancy"
  [ ! -e bad.vpk ] || fail "a refused pack of a pyramid wrote bad.vpk"
  # --verify reads what info and export read: the metadata as JSON, every
  # voxel's class in the class table (each layout; svo's mip bricks too), the
  # header's reserved field and the zero padding. The corruptions come with
  # good CRCs, recomputed here.
  cat > keep_corrupt.py <<'PY'
import struct, sys
def crc32c(data):
    c = 0xFFFFFFFF
    for x in data:
        c ^= x
        for _ in range(8): c = (c >> 1) ^ 0x82F63B78 if c & 1 else c >> 1
    return c ^ 0xFFFFFFFF
what, src, dst = sys.argv[1:4]
b = bytearray(open(src, 'rb').read())
n, _, mo, mb = struct.unpack_from('<QQQQ', b, 64)
layout, clog, flags = b[12], b[13], struct.unpack_from('<I', b, 16)[0]
C = 1 << clog; N = C ** 3
_, eflags, _, occ, key, off, size, _ = struct.unpack_from('<BBHIQQII', b, 128)
if what == 'class':  # chunk 0's first summary record gets class 40
    full = eflags & 1
    if layout == 1: s = off + (0 if full else N // 8)
    elif layout == 2:
        B, M = struct.unpack_from('<II', b, off); s = off + 16 + 16 * B + 64 * M
    else:
        ladder = sum(4 * (((C >> m) ** 3 + 31) // 32) for m in range(1, clog))
        s = off + 8 + (0 if full else N // 8 + ladder) + (N // 8 if flags & 2 else 0)
    assert b[s] != 0
    b[s] = 40
    struct.pack_into('<I', b, 128 + 28, crc32c(b[off:off + size]))
    struct.pack_into('<I', b, 116, crc32c(b[128:128 + 32 * n]))
elif what == 'meta':  # the closing brace of the metadata becomes a space
    b[mo + mb - 1] = 32
    struct.pack_into('<I', b, 112, crc32c(b[mo:mo + mb]))
elif what == 'reserved':
    struct.pack_into('<I', b, 120, 7)
elif what == 'padding':  # the first byte between two payloads (no CRC covers it)
    ends = [struct.unpack_from('<Q', b, 128 + 32 * i + 16)[0] + struct.unpack_from('<I', b, 128 + 32 * i + 24)[0] for i in range(n)]
    starts = [struct.unpack_from('<Q', b, 128 + 32 * i + 16)[0] for i in range(n)]
    i = next(i for i in range(n - 1) if starts[i + 1] > ends[i])
    b[ends[i]] = 1
    print(i + 1)
struct.pack_into('<I', b, 124, crc32c(b[:124]))
open(dst, 'wb').write(b)
PY
  python3 keep_corrupt.py meta a.vpk keep_meta.vpk || fail "corrupt meta"
  expect_exit 1 "$vox" pack-chunks --verify keep_meta.vpk
  expect_stderr "keep_meta.vpk: metadata is not valid JSON"
  expect_exit 3 "$vox" info keep_meta.vpk
  expect_exit 0 "$vox" pack-chunks h.vdb -o svo16.vpk --layout svo --chunk 16 -q
  expect_exit 0 "$vox" pack-chunks h.vdb -o col16.vpk --layout columns --chunk 16 -q
  for f in a svo16 col16; do  # bricks, svo, columns
    python3 keep_corrupt.py class $f.vpk keep_cls_$f.vpk || fail "corrupt class $f"
    expect_exit 1 "$vox" pack-chunks --verify keep_cls_$f.vpk
    expect_stderr "keep_cls_$f.vpk: chunk 0 (level 0"
    expect_stderr "class 40 is not in the metadata's class table"
    # svo at C = 16: the first record is the root's mip brick.
    [ $f != svo16 ] || expect_stderr "mip brick of node 0"
  done
  expect_exit 3 "$vox" export keep_cls_a.vpk -o keep_cls.glb
  python3 keep_corrupt.py reserved a.vpk keep_res.vpk || fail "corrupt reserved"
  expect_exit 3 "$vox" pack-chunks --verify keep_res.vpk
  expect_stderr "header field 'reserved' (offset 120): 7, must be 0"
  gap=$(python3 keep_corrupt.py padding a.vpk keep_pad.vpk) || fail "corrupt padding"
  expect_exit 1 "$vox" pack-chunks --verify keep_pad.vpk
  expect_stderr "keep_pad.vpk: padding before chunk $gap ("
  # The svo and columns layouts: byte-identical at --threads 1 and 2, verified, described, every chunk size.
  for layout in svo columns; do
    expect_exit 0 "$vox" pack-chunks h.vdb -o l1.vpk --layout $layout --mips --threads 1 --report l.json
    expect_exit 0 "$vox" pack-chunks h.vdb -o l2.vpk --layout $layout --mips --threads 2
    cmp -s l1.vpk l2.vpk || fail "$layout page files differ between --threads 1 and 2"
    jcheck l.json "c=d['counts']; assert c['layout']=='$layout' and len(c['levels'])==7 and c['voxels']==sum(l['voxels'] for l in c['levels']) and c['bytes_per_voxel']>0"
    # Same voxel counts per level as the bricks file of the same scene.
    jcheck l.json "import json; a=json.load(open('pack.json'))['counts']; assert [l['voxels'] for l in d['counts']['levels']]==[l['voxels'] for l in a['levels']] and [l['chunks'] for l in d['counts']['levels']]==[l['chunks'] for l in a['levels']]"
    expect_exit 0 "$vox" pack-chunks --verify l1.vpk
    grep -qF "every CRC32C, bound, class and padding byte checked" out.txt err.txt || fail "--verify $layout: no summary line"
    expect_exit 0 "$vox" info --json l1.vpk
    cp out.txt linfo.json
    jcheck linfo.json "assert d['kind']=='pagefile' and d['layout']=='$layout' and len(d['levels'])==7 and d['channels']==['occupancy','summary','surface']"
    expect_exit 0 "$vox" info l1.vpk
    expect_stdout "$layout layout"
    for c in 8 32; do
      expect_exit 0 "$vox" pack-chunks p.vdb -o lc.vpk --mips --layout $layout --chunk $c --align 64
      expect_exit 0 "$vox" pack-chunks --verify lc.vpk
    done
    # A flipped payload byte fails --verify naming the chunk and the field.
    python3 -c "
import struct
b=bytearray(open('l1.vpk','rb').read()); off=struct.unpack_from('<Q',b,128+16)[0]; b[off+9]^=0x02
open('keep_bad_$layout.vpk','wb').write(b)"
    expect_exit 1 "$vox" pack-chunks --verify keep_bad_$layout.vpk
    expect_stderr "chunk 0 (level 0"
    expect_stderr "crc32c"
  done
  # Colour: a coloured mesh scene in every layout.
  cat > keep_tri.obj <<'OBJ'
mtllib keep_tri.mtl
v 0 0 0
v 4 0 0
v 0 4 0
v 0 0 4
usemtl red
f 1 3 2
f 1 2 4
usemtl blue
f 1 4 3
f 2 3 4
OBJ
  printf 'newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n' > keep_tri.mtl
  expect_exit 0 "$vox" voxelize keep_tri.obj --res 24 --fill solid -o tri.vdb
  for layout in bricks svo columns; do
    expect_exit 0 "$vox" pack-chunks tri.vdb -o t_$layout.vpk --layout $layout --mips --chunk 8 --align 8
    expect_exit 0 "$vox" pack-chunks --verify t_$layout.vpk
    expect_exit 0 "$vox" info --json t_$layout.vpk
    cp out.txt tinfo.json
    jcheck tinfo.json "assert d['layout']=='$layout' and d['channels']==['occupancy','summary','color','surface']"
  done
  # A reader written from formats/pagefile/PAGEFILE.md alone (no vox code) decodes the same voxels
  # (summary, colour, surface at every level) from every layout and chunk size.
  cat > keep_specreader.py <<'PY'
import struct, sys
# A page file reader written from formats/pagefile/PAGEFILE.md alone: decodes every chunk of
# any layout into {(level, x, y, z): (summary, colour, surface)}.
def read(path):
    b = open(path, 'rb').read()
    assert b[:8] == b'VOXPAGES'
    layout, clog, levels, alog = b[12], b[13], b[14], b[15]
    flags = struct.unpack_from('<I', b, 16)[0]
    color, surf = bool(flags & 1), bool(flags & 2)
    n = struct.unpack_from('<Q', b, 64)[0]
    C = 1 << clog; N = C ** 3
    out = {}
    def bit(buf, off, k): return (buf[off + (k >> 3)] >> (k & 7)) & 1
    for i in range(n):
        e = 128 + 32 * i
        lvl, eflags = b[e], b[e + 1]
        occ, key, off, size = struct.unpack_from('<IQQI', b, e + 4)
        cx = cy = cz = 0
        for j in range(21):
            cx |= ((key >> (3 * j)) & 1) << j; cy |= ((key >> (3 * j + 1)) & 1) << j; cz |= ((key >> (3 * j + 2)) & 1) << j
        full = eflags & 1
        vox = []  # (x, y, z, summary, colour, surface)
        if layout == 1:
            p = off
            idx = list(range(N)) if full else [k for k in range(N) if bit(b, off, k)]
            if not full: p += N // 8
            sp, cp = p, p + 4 * occ
            fp = cp + (4 * occ if color else 0)
            for r, k in enumerate(idx):
                vox.append((k % C, (k // C) % C, k // (C * C), b[sp + 4 * r:sp + 4 * r + 4],
                            b[cp + 4 * r:cp + 4 * r + 4] if color else b'\0' * 4, bit(b, fp, r) if surf else 1))
        elif layout == 2:
            B, M, T, _ = struct.unpack_from('<IIII', b, off)
            nodes = off + 16; bricks = nodes + 8 * B; bms = bricks + 8 * B
            sp = bms + 64 * M; cp = sp + 4 * T; fp = cp + (4 * T if color else 0)
            org = {0: (0, 0, 0)}
            for ni in range(B):
                raw = struct.unpack_from('<Q', b, nodes + 8 * ni)[0]
                mask, level, ptr = raw & 255, (raw >> 24) & 255, raw >> 32
                ox, oy, oz = org[ni]
                if level > 0:
                    h = 8 << (level - 1); c = ptr
                    for o in range(8):
                        if mask >> o & 1:
                            org[c] = (ox + h * (o & 1), oy + h * ((o >> 1) & 1), oz + h * (o >> 2)); c += 1
                    continue
                first, slot = struct.unpack_from('<II', b, bricks + 8 * ni)
                r = first
                for k in range(512):
                    if slot != 0xFFFFFFFF and not bit(b, bms + 64 * slot, k): continue
                    vox.append((ox + (k & 7), oy + ((k >> 3) & 7), oz + (k >> 6), b[sp + 4 * r:sp + 4 * r + 4],
                                b[cp + 4 * r:cp + 4 * r + 4] if color else b'\0' * 4, bit(b, fp, r) if surf else 1))
                    r += 1
        elif layout == 3:
            S = struct.unpack_from('<I', b, off)[0]
            p = off + 8
            solid = None if full else p
            if not full: p += N // 8
            smask = p if surf else None
            if surf: p += N // 8
            if not full:
                s = C // 2
                while s >= 2: p += 4 * ((s ** 3 + 31) // 32); s //= 2
            sp = p; op = sp + 4 * occ; cp = op + 4 * (C * C + 1)
            r = 0
            for col in range(C * C):
                cr = struct.unpack_from('<I', b, op + 4 * col)[0] if color else 0
                for z in range(C):
                    k = z + C * col
                    if solid is not None and not bit(b, solid, k): continue
                    isf = bit(b, smask, k) if surf else 1
                    c4 = b'\0' * 4
                    if color and isf:
                        c4 = b[cp + 4 * cr:cp + 4 * cr + 4]; cr += 1
                    vox.append((col % C, col // C, z, b[sp + 4 * r:sp + 4 * r + 4], c4, isf))
                    r += 1
        assert len(vox) == occ, (path, i, len(vox), occ)
        for x, y, z, s4, c4, f in vox:
            out[(lvl, cx * C + x, cy * C + y, cz * C + z)] = (bytes(s4), bytes(c4), f)
    return out
maps = [read(p) for p in sys.argv[1:]]
assert maps[0] and all(m == maps[0] for m in maps[1:]), [len(m) for m in maps]
print(len(maps[0]), "voxels, the same in", len(maps), "files")
PY
  for layout in bricks svo columns; do
    for c in 8 16 32; do
      expect_exit 0 "$vox" pack-chunks tri.vdb -o s_${layout}_$c.vpk --layout $layout --mips --chunk $c --align 8
    done
  done
  python3 keep_specreader.py t_bricks.vpk s_*.vpk > out.txt 2> err.txt || fail "spec reader: $(tail -c 400 err.txt)"
  expect_stdout "voxels, the same in 10 files"
  python3 keep_specreader.py a.vpk l1.vpk > out.txt 2> err.txt || fail "spec reader (hamlet): $(tail -c 400 err.txt)"
  # vox mip --source MESH: the any-pyramid of an exact surface voxelization is exact
  # (IoU 1, no class disagreement) at every level against voxelizing the mesh directly.
  expect_exit 0 "$vox" voxelize keep_tri.obj --res 32 -o tris.vdb
  expect_exit 0 "$vox" mip tris.vdb -o trip.vdb --source keep_tri.obj --report tmip.json
  jcheck tmip.json "E=d['error']['levels']; assert len(E)==5 and [e['level'] for e in E]==[1,2,3,4,5]; assert all(e['iou']==1.0 and e['class_disagreement']==0 and e['only_mip']==0 and e['only_reference']==0 for e in E), E"
  # ... and the solid one is not exact against a solid reference (interior votes differ), but close.
  expect_exit 0 "$vox" mip tri.vdb -o trq.vdb --source keep_tri.obj --source-fill solid --report tsol.json
  jcheck tsol.json "E=d['error']['levels']; assert len(E)>=3 and all(0.5<e['iou']<=1.0 for e in E[:2]), E"
  expect_exit 2 "$vox" mip tris.vdb -o x.vdb --source keep_tri.obj --source keep_tri.obj
  expect_stderr "give one mesh"
  ;;
render)
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o h.vdb
  cam="--eye 20,15,20 --target 0,2,0 --size 96x64"
  # Exact against the brute force on every pixel; report has rays/s and steps.
  expect_exit 0 "$vox" render-canonical h.vdb -o c.png $cam --check --report r.json --threads 1
  jcheck r.json "c=d['counts']; e=d['error']; assert c['rays']==6144 and 0<c['hits']<6144 and c['mean_steps_per_ray']>0 and c['rays_per_second']>0, c; assert e['pixels_checked']==6144 and e['pixels_differing']==0, e"
  expect_exit 0 "$vox" render-canonical h.vdb -o c2.png $cam --threads 2
  cmp -s c.png c2.png || fail "canonical render differs between --threads 1 and 2"
  sha256sum c.png > got.sum
  diff -u "$data/../golden/render_demo64.sha256" got.sum || fail "the demo render differs from its golden hash"
  # verify-bijection: every hit decodes to an occupied voxel and equals the ray (camera from the image).
  expect_exit 0 "$vox" verify-bijection --canonical c.png --scene h.vdb
  expect_stdout "0 pixels differ from the exact ray"
  expect_stdout "OK"
  # A render from another camera fails the check against this camera, naming a pixel.
  expect_exit 0 "$vox" render-canonical h.vdb -o d.png --eye 21,15,20 --target 0,2,0 --size 96x64
  expect_exit 1 "$vox" verify-bijection --canonical d.png --scene h.vdb $cam --json
  jcheck out.txt "assert d['ok'] is False and d['pixels_differing_from_ray']>0 and d['first_failures'][0]['pixel'], d"
  # Picking: the centre pixel is a voxel of the scene, with its class.
  expect_exit 0 "$vox" info c.png --pixel 48,40 --scene h.vdb --json
  jcheck out.txt "p=d['pixel']; assert d['kind']=='render' and p['hit'] and len(p['voxel'])==3 and p['values'][:3]==p['voxel'] and p['values'][3]==255, p; assert p['scene_voxel']['class_name'] and p['scene_voxel']['summary']['cls']>=1, p"
  expect_exit 0 "$vox" info c.png --pixel 0,0 --json
  jcheck out.txt "assert d['pixel']['hit'] is False and d['pixel']['values']==[0,0,0,0]"
  expect_exit 2 "$vox" info c.png --pixel 96,0
  # Every mode from one pass; the names carry the mode.
  expect_exit 0 "$vox" render-canonical h.vdb -o m.png $cam --mode canonical,class,shaded,depth,normal
  for f in m.canonical.png m.class.png m.shaded.png m.depth.exr m.normal.png; do [ -s $f ] || fail "$f not written"; done
  sha256sum m.shaded.png m.class.png m.normal.png > got_modes.sum
  diff -u "$data/../golden/render_demo64_modes.sha256" got_modes.sum || fail "shaded/class/normal renders differ from their golden hashes"
  expect_exit 0 "$vox" info m.depth.exr --json
  jcheck out.txt "assert d['mode']=='depth' and d['image']['sample']=='float' and d['image']['channels']==1, d"
  expect_exit 0 "$vox" info m.shaded.png --json
  jcheck out.txt "assert d['mode']=='shaded' and d['image']['channels']==3, d"
  # Touched set: chunks sorted by Morton key, counts adding up; the 2-bit bitmap checks against the scene.
  expect_exit 0 "$vox" render-canonical h.vdb $cam --touched t.json --chunk-size 16 --touched-bitmap tb.png --report rt.json
  jcheck t.json "C=d['chunks']; assert d['chunk_size']==16 and C and sum(c['voxels'] for c in C)==d['voxels_touched']>0; assert [c['morton'] for c in C]==sorted(c['morton'] for c in C); assert all(0<=x<4 for c in C for x in c['chunk'])"
  expect_exit 0 "$vox" verify-bijection --atlas tb.png --scene h.vdb
  expect_exit 0 "$vox" info c.png --pixel 48,40 --json
  python3 -c "import json; p=json.load(open('out.txt'))['pixel']['voxel']; print(p[0], p[1], p[2])" > picked.txt
  read -r pu pv pw < picked.txt
  tx=$(( (pw % 8) * 64 + pu )); ty=$(( (pw / 8) * 64 + pv ))
  expect_exit 0 "$vox" info tb.png --pixel $tx,$ty --json
  jcheck out.txt "p=d['pixel']; assert p['occupied'] and p['touched'], p"
  # Page file input: the same voxels, checked against the scene by the exact ray.
  expect_exit 0 "$vox" pack-chunks h.vdb -o h.vpk
  expect_exit 0 "$vox" render-canonical h.vpk -o p.png $cam
  expect_exit 0 "$vox" verify-bijection --canonical p.png --scene h.vdb $cam
  # A mip level of a page file, exact against the brute force and verified from the page file.
  expect_exit 0 "$vox" mip h.vdb -o hp.vdb
  expect_exit 0 "$vox" pack-chunks hp.vdb -o hp.vpk --mips
  expect_exit 0 "$vox" render-canonical hp.vpk --level 1 -o l1.png $cam --check --report rl1.json
  jcheck rl1.json "assert d['error']['pixels_differing']==0 and d['counts']['hits']>0, d['counts']"
  expect_exit 0 "$vox" verify-bijection --canonical l1.png --scene hp.vpk
  expect_exit 2 "$vox" render-canonical hp.vpk --level 9 -o l9.png $cam
  expect_stderr "holds levels 0.."
  # Hard cameras, each checked pixel by pixel against the brute force: straight down
  # an axis (rays in grid planes), inside the scene, and 1e6 voxels away.
  expect_exit 0 "$vox" render-canonical h.vdb -o top.png --eye 0,30,0 --target 0,0,0 --up 0,0,-1 --fov 40 --size 40x40 --check --report rtop.json
  jcheck rtop.json "e=d['error']; assert e['pixels_differing']==0 and e['pixels_checked']==1600 and d['counts']['hits']==1600, e"
  expect_exit 0 "$vox" render-canonical h.vdb -o in.png --eye 0.05,1.0,0.05 --target 5,1,3 --fov 100 --size 40x30 --check --report rin.json
  jcheck rin.json "e=d['error']; assert e['pixels_differing']==0 and d['counts']['hits']>0, e"
  expect_exit 0 "$vox" render-canonical h.vdb -o far.png --eye 100000,70000,80000 --target 0,1,0 --fov 0.004 --size 40x30 --check --report rfar.json
  jcheck rfar.json "e=d['error']; assert e['pixels_differing']==0 and d['counts']['hits']>0, (e, d['counts'])"
  # Block-map cameras: a metadata.json with matrices computed here (gl-matrix lookAt /
  # perspective, column-major) on the map scene; every view renders and verifies.
  expect_exit 0 "$vox" voxelize "$data/map_small.json" -o map.vdb
  python3 - <<'EOF'
import json, math
def lookat(eye, c, up):
    z=[eye[i]-c[i] for i in range(3)]; l=math.sqrt(sum(x*x for x in z)); z=[x/l for x in z]
    x=[up[1]*z[2]-up[2]*z[1], up[2]*z[0]-up[0]*z[2], up[0]*z[1]-up[1]*z[0]]; l=math.sqrt(sum(a*a for a in x)); x=[a/l for a in x]
    y=[z[1]*x[2]-z[2]*x[1], z[2]*x[0]-z[0]*x[2], z[0]*x[1]-z[1]*x[0]]
    d=lambda a,b: sum(a[i]*b[i] for i in range(3))
    return [x[0],y[0],z[0],0, x[1],y[1],z[1],0, x[2],y[2],z[2],0, -d(x,eye),-d(y,eye),-d(z,eye),1]
def persp(fovy, aspect, n, f):
    t=1/math.tan(fovy/2); nf=1/(n-f)
    return [t/aspect,0,0,0, 0,t,0,0, 0,0,(f+n)*nf,-1, 0,0,2*f*n*nf,0]
views=[]
# The map's blocks sit at world x, z = (position - 32) * 2 (the block world's centring): around (-60, 2, -62).
for i,eye in enumerate([[-80,20,-90],[-45,12,-40]]):
    views.append({"id":"view_%03d"%i,"index":i,"position":eye,"viewMatrix":lookat(eye,[-60,2,-62],[0,1,0]),"projectionMatrix":persp(math.radians(60),1.0,0.1,500.0)})
json.dump({"formatVersion":"1.0","imageSize":{"width":64,"height":64},"viewCount":2,"views":views}, open("metadata.json","w"))
bad=json.load(open("metadata.json")); bad["views"][1]["projectionMatrix"]=[1,2,3]; json.dump(bad, open("bad_metadata.json","w"))
EOF
  expect_exit 0 "$vox" render-canonical map.vdb -o v.png --camera metadata.json --check --report rv.json
  jcheck rv.json "assert d['counts']['views']==2 and d['counts']['hits']>0 and d['error']['pixels_differing']==0, d['counts']"
  for i in 0 1; do
    [ -s v.view$i.png ] || fail "v.view$i.png not written"
    expect_exit 0 "$vox" verify-bijection --canonical v.view$i.png --scene map.vdb --camera metadata.json --view $i
  done
  expect_exit 1 "$vox" verify-bijection --canonical v.view0.png --scene map.vdb --camera metadata.json --view 1
  # Bad input and usage: clear errors, documented codes, no partial outputs.
  mkdir -p bad && cd bad
  expect_exit 3 "$vox" render-canonical ../map.vdb -o x.png --camera ../bad_metadata.json
  expect_stderr "views[1].projectionMatrix"
  expect_exit 2 "$vox" render-canonical ../map.vdb -o x.png --camera ../metadata.json --view 2
  expect_stderr "0..1"
  expect_exit 2 "$vox" render-canonical ../map.vdb -o x.jpg $cam
  expect_stderr ".png"
  expect_exit 2 "$vox" render-canonical ../map.vdb -o x.png
  expect_stderr "--eye"
  expect_exit 2 "$vox" render-canonical ../map.vdb -o x.png $cam --mode canonical,sketch
  expect_stderr "sketch"
  expect_exit 2 "$vox" render-canonical ../map.vdb -o x.png --eye 1,2,3 --target 1,2,3
  # A camera file's problems are bad input named by file and element, once ("camera:" not doubled).
  echo '{"eye": [1e13, 0, 0], "target": [0, 0, 0]}' >far.json
  expect_exit 3 "$vox" render-canonical ../map.vdb -o x.png --camera far.json
  expect_stderr "far.json: camera: the eye is "
  expect_stderr " voxels from the grid on one axis"
  echo '{"cameras": [{"eye": [1, 2, 3], "target": [0, 0, 0], "fov": 180}]}' >fov.json
  expect_exit 3 "$vox" render-canonical ../map.vdb -o x.png --camera fov.json
  expect_stderr "fov.json: cameras[0]: the vertical field of view must be in (0, 180) degrees"
  grep -qF "camera: camera:" err.txt && fail "doubled camera: prefix"
  expect_exit 3 "$vox" render-canonical ../nothing.vdb -o x.png $cam
  expect_exit 3 "$vox" verify-bijection --canonical ../m.depth.exr --scene ../h.vdb
  expect_stderr "RGBA"
  no_outputs
  cd ..
  ;;
disk_full)
  # A write that fails (here: a file-size limit with SIGXFSZ ignored, so writes
  # return EFBIG as they return ENOSPC on a full disk) is exit 4 with the
  # system's reason, leaves an existing output untouched and no temporary file.
  # Every kind of writer: OpenVDB (demo, pyramid), the direct scene writer,
  # page files, atlases, renders, and the report.
  limited() { ( trap '' XFSZ; ulimit -f 48; exec "$@" ); }   # 48 KiB
  limited16() { ( trap '' XFSZ; ulimit -f 16; exec "$@" ); }
  expect_exit 0 "$vox" voxelize demo:hamlet --res 32 -o keep_old.vdb
  cp keep_old.vdb keep_copy.vdb
  expect_exit 4 limited "$vox" voxelize demo:hamlet --res 128 -o keep_old.vdb
  expect_stderr "not written completely"
  cmp -s keep_old.vdb keep_copy.vdb || fail "a failed write replaced the existing scene"
  expect_exit 0 "$vox" voxelize demo:hamlet --res 128 -o keep_h.vdb
  expect_exit 4 limited "$vox" mip keep_h.vdb -o p.vdb
  expect_exit 4 limited "$vox" pack-chunks keep_h.vdb -o p.vpk --mips
  expect_stderr "File too large"
  # The 128^3 identity atlas deflates to about 46 KiB: a 16 KiB limit cuts it.
  expect_exit 4 limited16 "$vox" build-atlas keep_h.vdb -o atl --identity
  expect_exit 4 limited "$vox" render-canonical keep_h.vdb -o r.png --eye 20,15,20 --target 0,2,0 --size 800x600 --mode canonical,depth
  printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' > keep_tri.stl
  expect_exit 4 limited "$vox" voxelize keep_tri.stl --res 512 --fill solid -o m.vdb
  # Volume exports go through OpenVDB's unchecked stream too (they once exited 0 with a cut file).
  expect_exit 4 limited16 "$vox" export keep_h.vdb -o fog.vdb --fog
  expect_stderr "fog.vdb: the volume was not written completely"
  expect_exit 4 limited16 "$vox" export keep_h.vdb -o ls.vdb --level-set
  expect_stderr "ls.vdb: the volume was not written completely"
  # A report that cannot be written fails the run before any output is committed.
  expect_exit 4 "$vox" voxelize demo:hamlet --res 16 -o small.vdb --report no_such_dir/r.json
  [ -e small.vdb ] && fail "the scene was committed although its report failed"
  [ ! -e atl ] || fail "the failed build-atlas left the directory it made: $(ls -A atl)"
  no_outputs
  ;;
no_effect)
  # Options that would do nothing for the input at hand: exit 2 before any work,
  # naming the option, why, and the fix; nothing written.
  # refused WANT_MESSAGE OUTPUT CMD...: exit 2, the message, OUTPUT not written.
  refused() {
    local want=$1 out=$2; shift 2
    expect_exit 2 "$@"
    expect_stderr "$want"
    [ "$(wc -l < err.txt)" = 1 ] || fail "a usage error is one line: $(cat err.txt)"
    [ ! -e "$out" ] || fail "$out was written by a refused run: $*"
  }
  printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' > keep_t.stl
  cp keep_t.stl keep_u.stl
  # Meshes refuse the grid and block-map options (--threshold would also split a
  # region bake's world key), symmetric to a grid refusing --fill.
  refused "--threshold applies to .vdb grid inputs, and keep_t.stl is a mesh: drop --threshold" x.vdb \
    "$vox" voxelize keep_t.stl --threshold 0.5 -o x.vdb
  refused "--threshold applies to .vdb grid inputs, and keep_t.stl is a mesh: drop --threshold" x.vdb \
    "$vox" voxelize keep_t.stl --res 64 --region 0/2 --threshold 0.5 -o x.vdb
  refused "--grid applies to .vdb grid inputs, and keep_t.stl is a mesh: drop --grid" x.vdb \
    "$vox" voxelize keep_t.stl --grid density -o x.vdb
  refused "--grid-size applies to block maps, and the inputs are meshes: drop --grid-size" x.vdb \
    "$vox" voxelize keep_t.stl keep_u.stl --grid-size 64,48,64 -o x.vdb
  # --solid-rule: only --fill solid fills an inside, and only the exact method has rules.
  refused "--solid-rule decides the inside of --fill solid, and this bake is --fill surface" x.vdb \
    "$vox" voxelize keep_t.stl --solid-rule parity -o x.vdb
  expect_stderr "add --fill solid, or drop --solid-rule"
  refused "--solid-rule is the exact voxelizer's; --method sdf fills OpenVDB's inside mask" x.vdb \
    "$vox" voxelize keep_t.stl --fill solid --solid-rule parity --method sdf -o x.vdb
  expect_exit 0 "$vox" voxelize keep_t.stl --fill solid --solid-rule parity -o keep_solid.vdb -q
  # Block maps: one block is one voxel; the hamlet is sized by --res.
  refused "--voxel-size does not apply to block maps: one block is one voxel, of the map's worldScale; drop --voxel-size" \
    x.vdb "$vox" voxelize "$data/map_small.json" --voxel-size 2 -o x.vdb
  refused "--res does not apply to block maps" x.vdb "$vox" voxelize "$data/map_small.json" --res 4 -o x.vdb
  refused "--voxel-size does not apply to demo:hamlet" x.vdb "$vox" voxelize demo:hamlet --voxel-size 0.5 -o x.vdb
  expect_stderr "drop --voxel-size, or give --res"
  # A level set's inside is its sign: --threshold is refused where the grid is
  # read (its class is in the file), a fog volume still needs one.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 16 -o keep_h.vdb -q
  expect_exit 0 "$vox" export keep_h.vdb -o keep_ls.vdb --level-set -q
  expect_exit 0 "$vox" export keep_h.vdb -o keep_fog.vdb --fog -q
  # Written by OpenVDB's writer, the same bytes every time (a UUID from the content).
  expect_exit 0 "$vox" export keep_h.vdb -o keep_fog2.vdb --fog -q
  cmp keep_fog.vdb keep_fog2.vdb || fail "two exports of one scene differ"
  refused "keep_ls.vdb: grid 'surface' is a level set, inside where its value <= 0, so a density threshold does not apply to it; drop the threshold (--threshold)" \
    x.vdb "$vox" voxelize keep_ls.vdb --res 16 --threshold 0.5 -o x.vdb
  expect_exit 0 "$vox" voxelize keep_ls.vdb --res 16 -o keep_ls_scene.vdb -q
  expect_exit 0 "$vox" voxelize keep_fog.vdb --res 16 --threshold 0.5 -o keep_fog_scene.vdb -q
  expect_exit 0 "$vox" voxelize keep_fog.vdb --res 16 --threshold 0.5 -o keep_fog_scene2.vdb -q --threads 1
  cmp keep_fog_scene.vdb keep_fog_scene2.vdb || fail "two bakes of one grid differ"

  # render-canonical: a camera file gives every view's fov and up.
  echo '{"eye": [20, 15, 20], "target": [0, 2, 0], "size": [40, 30]}' > cam.json
  refused "--fov does nothing with --camera cam.json: the file gives each view's field of view and up vector" r.png \
    "$vox" render-canonical keep_h.vdb -o r.png --camera cam.json --fov 30
  expect_stderr "drop --fov, or set \"fov\" in the file"
  refused "--up does nothing with --camera cam.json" r.png \
    "$vox" render-canonical keep_h.vdb -o r.png --camera cam.json --up 0,0,1
  expect_stderr "drop --up, or set \"up\" in the file"
  refused "--fov and --up do nothing with --camera cam.json" r.png \
    "$vox" render-canonical keep_h.vdb -o r.png --camera cam.json --view 0 --fov 30 --up 0,0,1
  # --check's settings without --check, the brute force's budget with the walk, --chunk-size without --touched.
  cam="--eye 20,15,20 --target 0,2,0 --size 40x30"
  for opt in "--check-reference brute-force" "--check-seconds 1" "--check-budget 1e6"; do
    # shellcheck disable=SC2086
    refused "${opt%% *} sets how --check compares pixels, and --check is not given: add --check, or drop ${opt%% *}" r.png \
      "$vox" render-canonical keep_h.vdb -o r.png $cam $opt
  done
  # shellcheck disable=SC2086
  refused "--check-budget limits the brute-force reference, and this check uses the voxel walk" r.png \
    "$vox" render-canonical keep_h.vdb -o r.png $cam --check --check-budget 1e6
  expect_stderr "add --check-reference brute-force, or drop --check-budget"
  for v in nan inf -inf -1 0; do
    # shellcheck disable=SC2086
    refused "--check-budget: expected a finite number > 0, got '$v'" r.png \
      "$vox" render-canonical keep_h.vdb -o r.png $cam --check --check-reference brute-force --check-budget "$v"
  done
  # shellcheck disable=SC2086
  refused "--chunk-size sets the chunks of --touched FILE.json" tb.png \
    "$vox" render-canonical keep_h.vdb $cam --touched-bitmap tb.png --chunk-size 16
  expect_stderr "add --touched FILE.json, or drop --chunk-size"
  # Each takes effect where it applies.
  # shellcheck disable=SC2086
  expect_exit 0 "$vox" render-canonical keep_h.vdb -o keep_r.png $cam --check --check-reference brute-force \
    --check-budget 1e6 --check-seconds 5 --touched t.json --chunk-size 16 -q
  jcheck t.json "assert d['chunk_size']==16, d"
  expect_exit 0 "$vox" render-canonical keep_h.vdb -o keep_rc.png --camera cam.json -q

  # verify-bijection: the budget is --canonical's, a bare --fov/--up/--size has no camera to shape.
  refused "--check-budget limits the brute force of --canonical, and --canonical is not given: add --canonical IMG --scene S, or drop --check-budget" \
    x.json "$vox" verify-bijection --res 8 --check-budget 100
  for v in nan inf -1; do
    refused "--check-budget: expected a finite number > 0, got '$v'" x.json \
      "$vox" verify-bijection --canonical keep_r.png --scene keep_h.vdb --check-budget "$v"
  done
  for opt in "--fov 30" "--up 0,0,1" "--size 40x30"; do
    # shellcheck disable=SC2086
    refused "${opt%% *} shapes a camera given on the command line, and none is" x.json \
      "$vox" verify-bijection --canonical keep_r.png --scene keep_h.vdb $opt
    expect_stderr "add --eye X,Y,Z --target X,Y,Z (or --camera FILE), or drop ${opt%% *}"
  done
  refused "--up does nothing with --camera cam.json" x.json \
    "$vox" verify-bijection --canonical keep_rc.png --scene keep_h.vdb --camera cam.json --up 0,0,1
  expect_exit 0 "$vox" verify-bijection --canonical keep_r.png --scene keep_h.vdb --check-budget 1e6
  expect_exit 0 "$vox" verify-bijection --canonical keep_rc.png --scene keep_h.vdb --camera cam.json
  no_outputs
  ;;
*) echo "unknown group $group" >&2; exit 2 ;;
esac

if [ "$failures" -gt 0 ]; then
  echo "$group: $failures failure(s)" >&2
  exit 1
fi
echo "$group: ok"
