#!/usr/bin/env bash
# `vox voxelize demo:city` end to end (docs/city.md): the default and a given
# --extent, the header and counts in vox info and --report, bytes identical at
# any --threads, usage errors (exit 2, nothing written), the memory guard
# (exit 4 with the estimate and an --extent that fits, little CPU, nothing
# written; the suggested extent runs).
# Usage: city_test.sh VOX_BINARY
set -u
vox=$1
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

# The default extent: 1024 x 256 x 1024 voxels of 0.5 m, every class of the palette.
expect_exit 0 "$vox" voxelize demo:city -o city.vdb --threads 2 --report city.json
expect_stderr "wrote city.vdb: 1024 x 256 x 1024"
jcheck city.json "c = d['counts']; assert c['dims'] == [1024, 256, 1024] and c['classes_present'] == 7, c; \
assert c['occupied_voxels'] > 1024 * 1024 * 8 and 0 < c['surface_voxels'] < c['occupied_voxels'], c; \
assert [p['name'] for p in d['phases']] == ['estimate', 'generate', 'write'], d['phases']; \
assert d['memory']['checks'][0]['what'] == 'demo:city at --extent 1024,256,1024'"
expect_exit 0 "$vox" info city.vdb --json
jcheck out.txt "assert d['dims'] == [1024, 256, 1024] and d['voxel_size'] == 0.5, (d['dims'], d['voxel_size']); \
assert d['origin'] == [-256.0, 0.0, -256.0], d['origin']; \
assert [s['path'] for s in d['sources']] == ['demo:city'] and d['sources'][0]['kind'] == 'demo', d['sources']; \
assert [c['name'] for c in d['classes']] == ['Grass', 'Dirt', 'Stone', 'Plank', 'Snow', 'Sand', 'Water'], d['classes']"

# A given extent; the same bytes at any thread count.
expect_exit 0 "$vox" voxelize demo:city --extent 320,48,200 -o a.vdb --threads 1 --report a.json
expect_exit 0 "$vox" voxelize demo:city --extent 320,48,200 -o b.vdb --threads 2
cmp -s a.vdb b.vdb || fail "demo:city differs between --threads 1 and 2"
jcheck a.json "assert d['counts']['dims'] == [320, 48, 200], d['counts']"
# The header keeps the whole palette even where the box holds no water.
expect_exit 0 "$vox" info a.vdb --json
jcheck out.txt "assert len(d['classes']) == 7, d['classes']"
# The smallest city.
expect_exit 0 "$vox" voxelize demo:city --extent 1,1,1 -o one.vdb -q
expect_exit 0 "$vox" info one.vdb --json
jcheck out.txt "assert d['dims'] == [1, 1, 1] and d['occupied'] == 1, (d['dims'], d['occupied'])"

# Usage errors: exit 2, a message naming the option, nothing written.
bad_usage() {
  local needle=$1; shift
  expect_exit 2 "$vox" "$@"
  expect_stderr "$needle"
  [ ! -e bad.vdb ] || fail "a refused command line left bad.vdb: $*"
}
for extent in 65537,8,8 8,8,65537 8,4097,8; do
  bad_usage "--extent $extent" voxelize demo:city --extent "$extent" -o bad.vdb
done
for extent in 0,8,8 8,0,8 nan,8,8 8,8 a,b,c -1,8,8 +8,8,8 " 8,8,8" "8, 8,8" 8,8,8,8 "" 1e3,8,8 8,,8 99999999999,8,8; do
  bad_usage "--extent" voxelize demo:city --extent "$extent" -o bad.vdb
done
bad_usage "--extent applies to demo:city only" voxelize demo:hamlet --extent 64,64,64 -o bad.vdb
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >tri.obj
bad_usage "--extent applies to demo:city only" voxelize tri.obj --extent 64,64,64 -o bad.vdb
bad_usage "--res does not apply to demo:city" voxelize demo:city --res 128 -o bad.vdb
bad_usage "--voxel-size does not apply to demo:city" voxelize demo:city --voxel-size 0.25 -o bad.vdb
bad_usage "demo:hamlet and demo:city" voxelize demo:town -o bad.vdb

# The memory guard: a 65536 x 4096 x 65536 city is refused before the work
# (exit 4, the estimate, an --extent that fits), quickly, nothing written.
python3 - "$vox" <<'EOF' >out.txt 2>err.txt
import resource, subprocess, sys
p = subprocess.run([sys.argv[1], "voxelize", "demo:city", "--extent", "65536,4096,65536", "--max-memory", "1G",
                    "-o", "big.vdb"], capture_output=True, text=True)
r = resource.getrusage(resource.RUSAGE_CHILDREN)
sys.stderr.write(p.stderr)
print(p.returncode, r.ru_utime + r.ru_stime)
EOF
read -r code cpu <out.txt
[ "$code" = 4 ] || fail "the huge city: exit $code, expected 4 ($(head -c 400 err.txt))"
expect_stderr "demo:city at --extent 65536,4096,65536 needs about"
expect_stderr "--extent "
expect_stderr "would need about"
python3 -c "import sys; sys.exit(0 if $cpu < 2.0 else 1)" || fail "the refusal took $cpu s of CPU"
[ ! -e big.vdb ] || fail "a refused bake left big.vdb"
echo "refused: $(head -c 300 err.txt)"
fits=$(grep -o -- '--extent [0-9]*,[0-9]*,[0-9]* would' err.txt | head -1 | cut -d' ' -f2)
if [ -n "$fits" ]; then
  # The suggestion keeps the height and fits under the same limit (run on a
  # smaller limit's suggestion so the test stays quick).
  python3 -c "x, y, z = map(int, '$fits'.split(',')); assert y == 4096 and x == z and x < 65536, '$fits'" ||
    fail "odd suggestion $fits"
else
  fail "no --extent suggested: $(head -c 300 err.txt)"
fi
expect_exit 4 "$vox" voxelize demo:city --extent 2048,256,2048 --max-memory 150M -o big.vdb
fits=$(grep -o -- '--extent [0-9]*,[0-9]*,[0-9]* would' err.txt | head -1 | cut -d' ' -f2)
if [ -n "$fits" ]; then
  expect_exit 0 "$vox" voxelize demo:city --extent "$fits" --max-memory 150M -o fits.vdb -q
  [ -s fits.vdb ] || fail "the suggested --extent $fits wrote nothing"
else
  fail "no --extent suggested under 150M: $(head -c 300 err.txt)"
fi

[ "$failures" = 0 ] || { echo "$failures failure(s)" >&2; exit 1; }
echo "city: ok"
