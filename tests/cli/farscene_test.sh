#!/usr/bin/env bash
# Wide, sparse scenes (tests/cmake/farscene.cmake). Usage: farscene_test.sh GROUP VOX
set -u
group=$1 vox=$2
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

# far_map NAME X Y Z BLOCKS...: a block map NAME.json with Stone at each "x,y,z"
# and its scene NAME.vdb on a grid X x Y x Z.
far_map() {
  local name=$1 grid=$2,$3,$4 blocks="" b
  shift 4
  for b in "$@"; do blocks="$blocks${blocks:+, }{\"position\": [$b], \"blockType\": \"Stone\"}"; done
  printf '{"worldScale": 1.0, "blocks": [%s]}' "$blocks" >"$name.json"
  expect_exit 0 "$vox" voxelize "$name.json" --grid-size "$grid" -o "$name.vdb"
}

# measured CMD...: runs CMD; sets $peak (maximum resident set size, bytes) and $code.
measured() {
  python3 - "$@" >out.txt 2>err.txt <<'PY'
import resource, subprocess, sys
p = subprocess.run(sys.argv[1:], stdout=sys.stdout, stderr=sys.stderr)
r = resource.getrusage(resource.RUSAGE_CHILDREN)
open("rusage.txt", "w").write("%d %d\n" % (r.ru_maxrss * 1024, p.returncode))
PY
  read -r peak code <rusage.txt
}

# nothing_but LIST: the work dir holds only these files (besides logs).
nothing_but() {
  local extra
  extra=$(ls -A | grep -v -x -F -e out.txt -e err.txt -e rusage.txt $(printf -- '-e %s ' "$@") || true)
  [ -z "$extra" ] || fail "unexpected files: $extra"
}

case $group in
export_vox)
  # 2^21 x 4 x 2^21 blocks, three at opposite corners: the box is 8192 x 8192
  # x 1 tiles of 256^3 (a model each, 4.7 GB, before tiles were kept sparse),
  # of which two hold voxels.
  far_map far 2097152 4 2097152 "0,0,0" "2097151,3,2097151" "1,0,0"
  measured "$vox" export far.vdb -o far.vox --report r.json
  [ "$code" = 0 ] || fail "export far.vox: exit $code (stderr: $(head -c 400 err.txt))"
  echo "export of the far scene: peak RSS $((peak / 1048576)) MiB"
  # A few voxels: well under 200 MiB (the binary, OpenVDB and the scene's read).
  [ "$peak" -lt $((200 * 1048576)) ] || fail "export far.vox peaked at $((peak / 1048576)) MiB"
  jcheck r.json "c=d['counts']; assert (c['models'],c['points'],c['size'])==(2,3,[2097152,2097152,4]), c"
  jcheck r.json "m=[x for x in d['memory']['checks'] if 'MagicaVoxel model' in x['what']]; assert len(m)==1 and m[0]['parts']['MagicaVoxel models']<10000, m"
  # Read back by the spec (not voxbake's code): voxel (x, y, z) of a model is
  # at translation + (x, y, z) - floor(size / 2); MagicaVoxel (x, y, z) = (u,
  # wmax - w, v) - floor(box / 2), box (2^21, 2^21, 4).
  python3 - <<'PY' || fail "far.vox does not place its voxels where they belong"
import struct
b = open("far.vox", "rb").read()
assert b[:4] == b"VOX " and struct.unpack_from("<i", b, 4)[0] == 150
assert b[8:12] == b"MAIN" and struct.unpack_from("<ii", b, 12) == (0, len(b) - 20)
def string(p):
    n, = struct.unpack_from("<i", b, p); return b[p + 4:p + 4 + n].decode(), p + 4 + n
def dict_(p):
    n, = struct.unpack_from("<i", b, p); p += 4; d = {}
    for _ in range(n):
        k, p = string(p); v, p = string(p); d[k] = v
    return d, p
sizes, models, trn, shp = [], [], {}, {}
p = 20
while p < len(b):
    cid = b[p:p + 4]; n, m = struct.unpack_from("<ii", b, p + 4); c = p + 12
    if cid == b"SIZE": sizes.append(struct.unpack_from("<3i", b, c))
    elif cid == b"XYZI":
        k, = struct.unpack_from("<i", b, c); models.append([tuple(b[c + 4 + 4 * i:c + 8 + 4 * i]) for i in range(k)])
    elif cid == b"nTRN":
        node, = struct.unpack_from("<i", b, c); _, q = dict_(c + 4); child, = struct.unpack_from("<i", b, q)
        frame, _ = dict_(q + 16); trn[child] = [int(t) for t in frame.get("_t", "0 0 0").split()]
    elif cid == b"nSHP":
        node, = struct.unpack_from("<i", b, c); _, q = dict_(c + 4); shp[struct.unpack_from("<i", b, q + 4)[0]] = node
    p = c + n + m
assert len(sizes) == 2 and sizes == [(256, 256, 4), (256, 256, 4)], sizes
got = []
for k, voxels in enumerate(models):
    t = trn[shp[k]]
    got += [tuple(t[a] + (x, y, z)[a] - sizes[k][a] // 2 for a in range(3)) + (i,) for x, y, z, i in voxels]
H = 1048576
want = [(u - H, (2097151 - w) - H, v - 2, 3) for u, v, w in [(0, 0, 0), (2097151, 3, 2097151), (1, 0, 0)]]
assert sorted(got) == sorted(want), (got, want)
PY
  # An ordinary scene: one model, the same as before (its voxels and placement
  # are pinned by the export tests).
  far_map near 64 48 64 "0,0,0" "63,47,63"
  expect_exit 0 "$vox" export near.vdb -o near.vox --report rn.json
  jcheck rn.json "c=d['counts']; assert (c['models'],c['points'],c['size'])==(1,2,[64,64,48]), c"
  ;;
pack_chunks)
  # Past 2^20 along x (block 1048576): refused before the work, naming the
  # axis, the size and the limit; nothing written. The light path (a scene
  # voxbake wrote) and the full one (--mips, before the mips are built).
  far_map wide 2097152 4 16 "0,0,0" "1048576,3,15"
  for mips in "" --mips; do
    expect_exit 3 "$vox" pack-chunks wide.vdb -o wide.vpk $mips
    expect_stderr "wide.vdb: the scene is 1048577 voxels along x (dims 1048577 x 4 x 16) and a page file holds at most 1048576 (2^20) per axis"
    expect_stderr "a block map's positions along x below 1048576"
    nothing_but wide.json wide.vdb
  done
  # Along y and z too, each named.
  far_map tall 8 2097152 8 "0,1048576,0"
  expect_exit 3 "$vox" pack-chunks tall.vdb -o tall.vpk
  expect_stderr "the scene is 1048577 voxels along y (dims 1 x 1048577 x 1)"
  far_map deep 8 8 2097152 "0,0,2097151"
  expect_exit 3 "$vox" pack-chunks deep.vdb -o deep.vpk --report r.json
  expect_stderr "the scene is 2097152 voxels along z (dims 1 x 1 x 2097152)"
  [ ! -e deep.vpk ] && [ ! -e r.json ] || fail "a refused pack wrote a file"
  # 2^20 exactly is packed, verified and read back.
  far_map edge 2097152 4 16 "0,0,0" "1048575,3,15"
  expect_exit 0 "$vox" pack-chunks edge.vdb -o edge.vpk --mips
  expect_exit 0 "$vox" pack-chunks --verify edge.vpk
  expect_exit 0 "$vox" info --json edge.vpk
  grep -q '1048576' out.txt || fail "info does not show the 2^20 dims: $(head -c 400 out.txt)"
  ;;
*)
  echo "unknown group $group" >&2
  exit 2
  ;;
esac
[ "$failures" = 0 ] || exit 1
