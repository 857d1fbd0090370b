#!/usr/bin/env bash
# The light render module (vox-render.so, docs/startup.md): render-canonical
# of scenes voxbake wrote and of page files without OpenVDB must write exactly
# what vox-cmds.so writes.
#   matrix  every mode at once, three cameras (a named view, a hand-given
#           odd-sized one, an orbit), threads 1 and 2, over the demo hamlet at
#           256 and 61, its page file (levels 0 and 1), a mesh scene and, with
#           ../shared/data, a coloured mesh and the bunny: images, touched
#           sets, bitmaps and camera files compared with cmp, reports equal
#           but for timings and resident memory; the bench's 1080p view too.
#   path    the light path is taken (the loader's own log, LD_DEBUG=files: no
#           libopenvdb, no vox-cmds.so); foreign, missing, truncated and
#           non-VDB files are deferred to vox-cmds.so with the same message
#           and exit code; help and usage errors are the full module's.
# The full module alone runs from a directory holding only vox and vox-cmds.so.
# Usage: lightrender_test.sh GROUP VOX_BINARY REPO_ROOT
set -u
group=$1 vox=$2 root=$3
data=$(realpath -m "${VOX_DATA:-$root/../shared/data}")
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

mkdir full && cp "$(dirname "$vox")/vox" "$(dirname "$vox")/vox-cmds.so" full/
fullvox=$work/full/vox
[ -e "$(dirname "$vox")/vox-render.so" ] || fail "no vox-render.so beside $vox"

# Reports without what differs run to run (timings, rates and resident memory)
# or by the reader (the grids read and the working copies scaled by them: the
# light module keeps packed leaves, vox-cmds.so OpenVDB trees; the mapped
# file); the memory checks' other parts must agree; argv[0] and output names.
cat >norm.py <<'EOF'
import json, sys
def clean(x):
    if isinstance(x, dict):
        return {k: clean(v) for k, v in x.items() if 'seconds' not in k and 'per_second' not in k and k != 'memory'}
    if isinstance(x, list):
        return [clean(v) for v in x]
    return x
d = json.load(open(sys.argv[1]))
by_reader = ('grids', 'working copies', 'the file, mapped')
mem = [{k: v for k, v in c['parts'].items() if not k.startswith('resident') and k not in by_reader}
       for c in d['memory']['checks']]
d['argv'] = d['argv'][1:]
out = clean(d)
out['memory_parts'] = mem
print(json.dumps(out, sort_keys=True))
EOF

# same NAME ARGS...: runs render-canonical ARGS in L/ (the launcher: light
# module) and F/ (full module only), then compares exit codes, every file
# written and the reports.
same() {
  local name=$1; shift
  rm -rf L F && mkdir L F
  (cd L && "$vox" render-canonical "$@" --report rep.json >out.txt 2>err.txt; echo $? >rc)
  (cd F && "$fullvox" render-canonical "$@" --report rep.json >out.txt 2>err.txt; echo $? >rc)
  [ "$(cat L/rc)" = 0 ] || fail "$name: light exit $(cat L/rc): $(head -c 300 L/err.txt)"
  [ "$(cat L/rc)" = "$(cat F/rc)" ] || fail "$name: exit $(cat L/rc) vs $(cat F/rc)"
  # Messages alike but for the times and rates in them.
  local t='s/[0-9.]\+ \(s\|Mrays\/s\)\b/T \1/g'
  [ "$(sed "$t" L/err.txt)" = "$(sed "$t" F/err.txt)" ] || fail "$name: stderr differs: $(diff L/err.txt F/err.txt | head -5)"
  local files
  files=$(cd F && ls | grep -v '^rep.json$\|^rc$\|^out.txt$\|^err.txt$')
  [ "$(cd L && ls | grep -v '^rep.json$\|^rc$\|^out.txt$\|^err.txt$')" = "$files" ] || fail "$name: files differ: $(ls L) / $(ls F)"
  [ -n "$files" ] || fail "$name: nothing written"
  for f in $files; do
    cmp -s "L/$f" "F/$f" || fail "$name: $f differs"
    compared=$((compared + 1))
  done
  [ "$(python3 norm.py L/rep.json)" = "$(python3 norm.py F/rep.json)" ] ||
    fail "$name: reports differ: $(diff <(python3 norm.py L/rep.json | tr ',' '\n') <(python3 norm.py F/rep.json | tr ',' '\n') | head -6)"
}

case $group in
matrix)
  compared=0
  expect_exit 0 "$vox" voxelize demo:hamlet --res 256 -o hamlet256.vdb --quiet
  expect_exit 0 "$vox" voxelize demo:hamlet --res 61 -o hamlet61.vdb --quiet
  expect_exit 0 "$vox" pack-chunks hamlet61.vdb -o hamlet61.vpk --mips --quiet
  # A mesh scene made here, for runs without ../shared/data: a bumpy ground and
  # a sphere on it, two materials (so two classes).
  python3 - >mesh.obj <<'EOF'
import math
n, vs, fs = 24, [], []
for i in range(n + 1):
    for j in range(n + 1):
        x, z = 4.0 * i / n - 2, 4.0 * j / n - 2
        vs.append((x, 0.25 * math.sin(2.1 * x) * math.cos(1.7 * z), z))
for i in range(n):
    for j in range(n):
        a = i * (n + 1) + j + 1
        fs.append(('ground', (a, a + 1, a + n + 2)))
        fs.append(('ground', (a, a + n + 2, a + n + 1)))
rings, segs, base = 12, 18, len(vs)
for r in range(rings + 1):
    th = math.pi * r / rings
    for k in range(segs):
        ph = 2 * math.pi * k / segs
        vs.append((0.3 + 0.8 * math.sin(th) * math.cos(ph), 0.9 + 0.8 * math.cos(th), -0.2 + 0.8 * math.sin(th) * math.sin(ph)))
for r in range(rings):
    for k in range(segs):
        p, q = base + r * segs + k + 1, base + r * segs + (k + 1) % segs + 1
        fs.append(('rock', (p, q, q + segs)))
        fs.append(('rock', (p, q + segs, p + segs)))
for v in vs:
    print('v %.6f %.6f %.6f' % v)
last = None
for m, f in fs:
    if m != last:
        print('usemtl ' + m)
        last = m
    print('f %d %d %d' % f)
EOF
  expect_exit 0 "$vox" voxelize mesh.obj --res 90 -o mesh.vdb --ignore-missing-materials --quiet
  inputs="hamlet256.vdb hamlet61.vdb hamlet61.vpk mesh.vdb"
  colored=$data/mesh-misc/assimp/cube_with_vertexcolors.obj
  bunny=$data/common-3d-test-models/stanford-bunny.obj
  if [ -e "$colored" ] && [ -e "$bunny" ]; then
    expect_exit 0 "$vox" voxelize "$colored" --res 40 -o colored.vdb --quiet
    expect_exit 0 "$vox" pack-chunks colored.vdb -o colored.vpk --quiet
    expect_exit 0 "$vox" voxelize "$bunny" --res 200 -o bunny.vdb --quiet
    inputs="$inputs colored.vdb colored.vpk bunny.vdb"
  else
    echo "SKIP: $colored or $bunny absent: the coloured and bunny scenes need ../shared/data" >&2
  fi
  modes=canonical,class,color,shaded,depth,normal
  for in in $inputs; do
    # A hand-given camera off the scene's box: above, to the side, odd-sized.
    "$vox" info "$in" --json >info.json
    hand=$(python3 -c "
import json, math; d=json.load(open('info.json'))
lo, hi = (d['world_bounds']['min'], d['world_bounds']['max']) if 'world_bounds' in d else \\
    (d['origin'], [o + n * d['voxel_size'] for o, n in zip(d['origin'], d['dims'])])
c=[(a+z)/2 for a,z in zip(lo,hi)]; r=math.dist(lo,hi)/2
print('--eye %.6g,%.6g,%.6g --target %.6g,%.6g,%.6g' % (c[0]+0.5*r, c[1]+1.2*r, c[2]+1.6*r, c[0], c[1], c[2]))")
    for threads in 1 2; do
      same "$in iso t$threads" "../$in" -o r.png --view iso --size 120x90 --mode $modes --threads $threads \
        --touched t.json --touched-bitmap tb.png --camera-out cam.json
      # shellcheck disable=SC2086
      same "$in hand t$threads" "../$in" -o r.png $hand --fov 50 --size 97x61 --mode $modes \
        --shade-color voxel --threads $threads --check --check-seconds 0
      same "$in orbit t$threads" "../$in" -o o.png --orbit 2 --size 64x40 --mode canonical,depth --threads $threads
    done
  done
  same "hamlet61.vpk level 1" ../hamlet61.vpk -o r.png --level 1 --view top --size 80x60 --mode $modes
  # The bench's view (scripts/bench_render.sh): 1920x1080, canonical, 2 threads.
  same "hamlet256 1080p" ../hamlet256.vdb -o vox.png --eye 19.5736,28.8057,24.912 --target 0,12.8,0 --fov 35.9834 \
    --size 1920x1080 --threads 2
  # Nothing cast at all: a camera looking away.
  same "hamlet61 away" ../hamlet61.vdb -o r.png --eye 0,50,0 --target 0,100,0 --up 1,0,0 --size 32x32 --mode canonical,shaded
  echo "lightrender.matrix: $compared files compared" >&2
  [ $compared -ge 100 ] || fail "only $compared files compared"
  ;;
path)
  expect_exit 0 "$vox" voxelize demo:hamlet --res 40 -o h.vdb --quiet
  expect_exit 0 "$vox" pack-chunks h.vdb -o h.vpk --quiet
  # modules LOGFILE: the command modules the run loaded, and whether OpenVDB was among its libraries.
  modules() { grep -o 'file=[^ ]*\(vox-[a-z]*\.so\|libopenvdb[^ ]*\)' "$1" | sed 's|.*/||; s|file=||' | sort -u | tr '\n' ' '; }
  for in in h.vdb h.vpk; do
    LD_DEBUG=files "$vox" render-canonical $in -o r.png --view iso --size 64x48 --mode class,shaded --quiet 2>ld.txt
    [ "$(modules ld.txt)" = "vox-render.so " ] || fail "$in: loaded $(modules ld.txt), expected vox-render.so alone"
    ! grep -q libopenvdb ld.txt || fail "$in: libopenvdb was loaded"
  done
  # Inputs the light module cannot read: deferred, the full module's message and exit code.
  head -c 3000 h.vdb >cut.vdb
  echo "not a scene" >text.vdb
  deferred="cut.vdb text.vdb missing.vdb"
  pig=$data/vdb/Elyg-OpenVDB_Visualizer/pig.vdb
  if [ -e "$pig" ]; then deferred="$deferred $pig"; else echo "SKIP: $pig absent (a foreign .vdb)" >&2; fi
  for in in $deferred; do
    LD_DEBUG=files "$vox" render-canonical "$in" -o d.png --view iso --size 32x32 2>ld.txt >/dev/null
    modules ld.txt | grep -q "vox-cmds.so vox-render.so" || fail "$in: not deferred: loaded $(modules ld.txt)"
    expect_exit 3 "$vox" render-canonical "$in" -o d.png --view iso --size 32x32
    cp err.txt light_err.txt
    expect_exit 3 "$fullvox" render-canonical "$in" -o d.png --view iso --size 32x32
    cmp -s light_err.txt err.txt || fail "$in: messages differ: $(cat light_err.txt) / $(cat err.txt)"
    [ ! -e d.png ] || fail "$in: a refused render left d.png"
  done
  # Help and usage errors, as the full module prints them.
  for args in "--help" "h.vdb -o x.png --mode colour" "h.vdb -o x.jpg" "h.vdb -o x.png --level 1" \
              "h.vpk -o x.png --level 5" "h.vdb" "h.vdb -o x.png --view top --eye 1,2,3" "h.vdb -o x.png --bogus"; do
    # shellcheck disable=SC2086
    "$vox" render-canonical $args >l_out.txt 2>l_err.txt
    lrc=$?
    # shellcheck disable=SC2086
    "$fullvox" render-canonical $args >f_out.txt 2>f_err.txt
    frc=$?
    [ $lrc = $frc ] || fail "'$args': exit $lrc vs $frc"
    cmp -s l_out.txt f_out.txt && cmp -s l_err.txt f_err.txt || fail "'$args': output differs: $(diff l_err.txt f_err.txt | head -4)"
  done
  [ ! -e x.png ] || fail "a usage error left x.png"
  ;;
*) echo "unknown group $group" >&2; exit 2 ;;
esac
[ $failures = 0 ] || { echo "$failures failure(s) in lightrender.$group" >&2; exit 1; }
echo "lightrender.$group: ok"
