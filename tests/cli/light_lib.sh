# Shared by the tests of the light command modules against vox-cmds.so
# (lightmip_test.sh, lightexport_test.sh), sourced after test_lib.sh.
# Sourcing it, in the test's work directory:
#   full/vox   the launcher beside vox-cmds.so alone, so every command runs
#              in the full module ($fullvox);
#   sphere.obj a sphere with vertex colours, its upper and lower halves of
#              two materials (so two classes), closed (so --fill solid has
#              an inside); tiny.obj, one small triangle;
#   norm.py    REPORT: the report without what differs run to run (timings,
#              rates and resident memory) or by the reader (the grids read
#              and the working copies scaled by them: the light modules keep
#              packed leaves, vox-cmds.so OpenVDB trees; the mapped file; a
#              pyramid's levels and writer, blocks and the direct writer in
#              the light module, trees and OpenVDB's writer in vox-cmds.so);
#              the memory checks' other parts must agree; argv[0] dropped.
# Uses $vox (the launcher under test), $work (test_lib.sh), and $command and
# $light_module (e.g. mip, vox-pack.so), set before sourcing.

mkdir full && cp "$(dirname "$vox")/vox" "$(dirname "$vox")/vox-cmds.so" full/
fullvox=$work/full/vox

python3 - >sphere.obj <<'PY'
import math
rings, segs = 14, 20
for r in range(rings + 1):
    th = math.pi * r / rings
    for k in range(segs):
        ph = 2 * math.pi * k / segs
        x, y, z = math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph)
        print('v %.6f %.6f %.6f %.4f %.4f %.4f' % (x, y + 1.2, z, 0.5 + 0.5 * x, 0.5 + 0.5 * y, 0.5 + 0.5 * z))
for r in range(rings):
    print('usemtl ' + ('upper' if r < rings // 2 else 'lower'))
    for k in range(segs):
        p, q = r * segs + k + 1, r * segs + (k + 1) % segs + 1
        print('f %d %d %d' % (p, q, q + segs))
        print('f %d %d %d' % (p, q + segs, p + segs))
PY
printf 'v 0 0 0\nv 0.01 0 0\nv 0 0.01 0\nf 1 2 3\n' >tiny.obj

cat >norm.py <<'PY'
import json, sys
def clean(x):
    if isinstance(x, dict):
        return {k: clean(v) for k, v in x.items() if 'seconds' not in k and 'per_second' not in k and k != 'memory'}
    return [clean(v) for v in x] if isinstance(x, list) else x
d = json.load(open(sys.argv[1]))
out = clean(d)
out['argv'] = d['argv'][1:]
by_reader = ('grids', 'working copies', 'the file, mapped', 'pyramid levels', 'scene writer')
out['memory_parts'] = [{k: v for k, v in c['parts'].items() if not k.startswith('resident') and k not in by_reader}
                       for c in d['memory']['checks']]
print(json.dumps(out, sort_keys=True))
PY

# bake_small_scenes: colored.vdb (the sphere, two classes, colours), solid.vdb
# (--fill solid, odd dims), one.vdb (one voxel), empty.vdb (no voxel), each
# checked for what it is there to have.
bake_small_scenes() {
  expect_exit 0 "$vox" voxelize sphere.obj --res 50 -o colored.vdb --ignore-missing-materials --quiet
  expect_exit 0 "$vox" voxelize sphere.obj --res 37 --fill solid -o solid.vdb --ignore-missing-materials --quiet
  expect_exit 0 "$vox" voxelize tiny.obj --voxel-size 1 --bounds -3.5,-3.5,-3.5,4.5,4.5,4.5 -o one.vdb --quiet
  expect_exit 0 "$vox" voxelize tiny.obj --voxel-size 1 --bounds 10,10,10,15,15,17 -o empty.vdb --quiet
  "$vox" info colored.vdb >info.txt 2>&1
  grep -q "colour .* voxels coloured" info.txt || fail "colored.vdb has no colour: $(cat info.txt)"
  "$vox" info solid.vdb >info.txt 2>&1
  grep -q "surface (.*), [1-9][0-9,]* interior" info.txt || fail "solid.vdb has no interior voxels: $(cat info.txt)"
}

# modules LOGFILE: the command modules a run loaded (LD_DEBUG=files in
# LOGFILE), and OpenVDB when it was among its libraries.
modules() { grep -o 'file=[^ ]*\(vox-[a-z]*\.so\|libopenvdb[^ ]*\)' "$1" | sed 's|.*/||; s|file=||' | sort -u | tr '\n' ' '; }

# same_outcome NAME ARGS...: `vox $command ARGS` exits, prints and writes as
# the full module alone does, each in its own directory (L/, F/).
same_outcome() {
  local name=$1; shift
  rm -rf L F && mkdir L F
  (cd L && "$vox" "$command" "$@" >out.txt 2>err.txt; echo $? >rc)
  (cd F && "$fullvox" "$command" "$@" >out.txt 2>err.txt; echo $? >rc)
  [ "$(cat L/rc)" = "$(cat F/rc)" ] || fail "$name: exit $(cat L/rc) vs $(cat F/rc)"
  cmp -s L/err.txt F/err.txt || fail "$name: messages differ: $(diff L/err.txt F/err.txt | head -4)"
  [ "$(cd L && ls)" = "$(cd F && ls)" ] || fail "$name: files differ: $(ls L) / $(ls F)"
}

# deferred NAME ARGS...: also, the light module leaves the run to vox-cmds.so.
deferred() {
  same_outcome "$@"
  local name=$1; shift
  (cd L && LD_DEBUG=files "$vox" "$command" "$@" 2>ld.txt >/dev/null)
  modules L/ld.txt | grep -q "vox-cmds.so $light_module" || fail "$name: not deferred: loaded $(modules L/ld.txt)"
}
