#!/usr/bin/env bash
# `vox mip` in the light module (vox-pack.so, docs/startup.md) must write what
# vox-cmds.so writes.
#   matrix  hamlet 256 and 64, a coloured two-class mesh scene, a solid one
#           (interior voxels, odd dims), one voxel, no voxel, and a --split
#           level (mip level 1) as input; any/majority, automatic and given
#           --levels, --split, threads 1 and 2. Every file written: the full
#           module's bytes but for the UUID and OpenVDB's `file_delayed_load`
#           entries (vdb_same.py), no difference for `vox diff` (every level),
#           the same bytes at threads 1 and 2; exit codes, messages and
#           reports (but for timings and resident memory) equal.
#   path    the light path is taken (the loader's log, LD_DEBUG=files:
#           vox-pack.so alone, no libopenvdb); --source, pyramid inputs, too
#           many --levels and a scene whose grids carry metadata voxbake does
#           not write run in vox-cmds.so; truncated, non-VDB and missing files
#           are refused with its messages and exit codes; help and usage
#           errors are the full module's.
# The full module alone runs from a directory holding only vox and vox-cmds.so.
# Usage: lightmip_test.sh GROUP VOX_BINARY
set -u
group=$1 vox=$2
same_bytes=$(dirname "$(realpath "$0")")/vdb_same.py
here=$(dirname "$(realpath "$0")")
# shellcheck source=test_lib.sh
. "$here/test_lib.sh"

command=mip light_module=vox-pack.so
# shellcheck source=light_lib.sh
. "$here/light_lib.sh"
[ -e "$(dirname "$vox")/vox-pack.so" ] || fail "no vox-pack.so beside $vox"

case $group in
matrix)
  compared=0
  # same NAME ARGS...: `vox mip ARGS` in L1/ and L2/ (the launcher, light
  # module; --threads 1 and 2) and F/ (full module only); compares exit codes,
  # messages, every file written and the reports.
  same() {
    local name=$1; shift
    rm -rf L1 L2 F && mkdir L1 L2 F
    (cd L1 && "$vox" mip "$@" --threads 1 --report rep.json >out.txt 2>err.txt; echo $? >rc)
    (cd L2 && "$vox" mip "$@" --threads 2 --report rep.json >out.txt 2>err.txt; echo $? >rc)
    (cd F && "$fullvox" mip "$@" --threads 1 --report rep.json >out.txt 2>err.txt; echo $? >rc)
    [ "$(cat L1/rc)" = 0 ] || fail "$name: light exit $(cat L1/rc): $(head -c 300 L1/err.txt)"
    [ "$(cat L1/rc)" = "$(cat F/rc)" ] || fail "$name: exit $(cat L1/rc) vs $(cat F/rc)"
    cmp -s L1/err.txt F/err.txt || fail "$name: stderr differs: $(diff L1/err.txt F/err.txt | head -5)"
    local files
    files=$(cd F && ls | grep -v '^rep.json$\|^rc$\|^out.txt$\|^err.txt$')
    [ "$(cd L1 && ls | grep -v '^rep.json$\|^rc$\|^out.txt$\|^err.txt$')" = "$files" ] ||
      fail "$name: files differ: $(ls L1) / $(ls F)"
    for f in $files; do
      cmp -s "L1/$f" "L2/$f" || fail "$name: $f differs between threads 1 and 2"
      python3 "$same_bytes" "L1/$f" "F/$f" >cmp.txt 2>&1 || fail "$name: $f: not OpenVDB's bytes: $(cat cmp.txt)"
      "$vox" diff "L1/$f" "F/$f" >diff.txt 2>&1 || fail "$name: vox diff $f: $(head -c 300 diff.txt)"
      compared=$((compared + 1))
    done
    [ "$(python3 norm.py L1/rep.json)" = "$(python3 norm.py F/rep.json)" ] ||
      fail "$name: reports differ: $(diff <(python3 norm.py L1/rep.json | tr ',' '\n') <(python3 norm.py F/rep.json | tr ',' '\n') | head -6)"
  }
  expect_exit 0 "$vox" voxelize demo:hamlet --res 256 -o hamlet256.vdb --quiet
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o hamlet64.vdb --quiet
  expect_exit 0 "$fullvox" mip hamlet64.vdb -o level --split --levels 1 --quiet  # level.mip1.vdb: mip level 1
  bake_small_scenes

  for occ in any majority; do
    same "hamlet256 $occ" ../hamlet256.vdb -o m.vdb --levels 8 --occupancy $occ
    for in in hamlet64 colored solid one empty level.mip1; do
      for levels in "" "--levels 1" "--levels 3"; do
        # shellcheck disable=SC2086
        same "$in $occ $levels" ../$in.vdb -o m.vdb --occupancy $occ $levels
      done
      same "$in $occ split" ../$in.vdb -o parts.vdb --split --occupancy $occ
    done
  done
  same "hamlet64 all levels" ../hamlet64.vdb -o m.vdb --levels 6 --occupancy majority
  same "hamlet256 split" ../hamlet256.vdb -o parts --split --levels 2
  echo "lightmip.matrix: $compared files compared" >&2
  [ $compared -ge 80 ] || fail "only $compared files compared"
  ;;
path)
  expect_exit 0 "$vox" voxelize demo:hamlet --res 40 -o h.vdb --quiet
  for args in "-o m.vdb" "-o m.vdb --levels 2 --occupancy majority" "-o parts --split"; do
    # shellcheck disable=SC2086
    LD_DEBUG=files "$vox" mip h.vdb $args --quiet 2>ld.txt
    [ "$(modules ld.txt)" = "vox-pack.so " ] || fail "'$args': loaded $(modules ld.txt), expected vox-pack.so alone"
    ! grep -q libopenvdb ld.txt || fail "'$args': libopenvdb was loaded"
  done
  [ -e m.vdb ] && [ -e parts.mip1.vdb ] || fail "the light runs wrote nothing"

  expect_exit 0 "$vox" mip h.vdb -o pyramid.vdb --levels 2 --quiet
  head -c 3000 h.vdb >cut.vdb
  echo "not a scene" >text.vdb
  # The same scene with a grid metadata key voxbake does not write (a
  # same-length rename of "file_compression"): a rewrite keeps it.
  python3 -c "
b = open('h.vdb', 'rb').read(); i = b.index(b'file_compression')
open('foreign_meta.vdb', 'wb').write(b[:i] + b'user_compression' + b[i + 16:])"
  deferred "--source" ../h.vdb -o m.vdb --source demo:hamlet --quiet
  deferred "pyramid input" ../pyramid.vdb -o m.vdb --quiet
  deferred "too many levels" ../h.vdb -o m.vdb --levels 7
  # Files the walk refuses: the light module's error is the full module's (the same walk).
  same_outcome "truncated" ../cut.vdb -o m.vdb
  same_outcome "not a VDB" ../text.vdb -o m.vdb
  same_outcome "missing" ../missing.vdb -o m.vdb
  deferred "foreign grid metadata" ../foreign_meta.vdb -o m.vdb --quiet
  # Both written by OpenVDB (random UUIDs): the same pyramid.
  "$vox" diff L/m.vdb F/m.vdb >diff.txt 2>&1 || fail "foreign grid metadata: outputs differ: $(head -c 300 diff.txt)"

  # What the pyramid holds, in words: its levels, the smallest size and the
  # occupancy rule; a scene of one occupied voxel has no coarser level and is
  # written all the same.
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >tri.obj
  expect_exit 0 "$vox" voxelize tri.obj --res 1 -o one.vdb --quiet
  "$vox" mip one.vdb -o one_m.vdb 2>one.txt || fail "one voxel: exit $?"
  grep -q "wrote one_m.vdb: no coarser level: the scene has one occupied voxel" one.txt || fail "one voxel: $(cat one.txt)"
  [ -e one_m.vdb ] || fail "one voxel: nothing written"
  "$vox" mip h.vdb -o words.vdb --levels 2 --occupancy majority 2>words.txt || fail "levels: exit $?"
  grep -q "wrote words.vdb: 2 levels coarser than the input, down to 10 x 10 x 10; a coarse voxel is occupied where most of its children are" words.txt ||
    fail "levels: $(cat words.txt)"

  # Help and usage errors, as the full module prints them.
  for args in "--help" "h.vdb -o x.txt" "h.vdb -o x.vdb --levels -1" "h.vdb -o / --split" \
              "h.vdb -o x.vdb --occupancy most" "h.vdb" "h.vdb -o x.vdb --bogus"; do
    # shellcheck disable=SC2086
    "$vox" mip $args >l_out.txt 2>l_err.txt
    lrc=$?
    # shellcheck disable=SC2086
    "$fullvox" mip $args >f_out.txt 2>f_err.txt
    frc=$?
    [ $lrc = $frc ] || fail "'$args': exit $lrc vs $frc"
    cmp -s l_out.txt f_out.txt && cmp -s l_err.txt f_err.txt || fail "'$args': output differs: $(diff l_err.txt f_err.txt | head -4)"
  done
  [ ! -e x.vdb ] && [ ! -e x.txt ] || fail "a usage error left an output"
  ;;
*) echo "unknown group $group" >&2; exit 2 ;;
esac
[ $failures = 0 ] || { echo "$failures failure(s) in lightmip.$group" >&2; exit 1; }
echo "lightmip.$group: ok"
