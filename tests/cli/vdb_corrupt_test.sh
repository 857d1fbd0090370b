#!/usr/bin/env bash
# Corrupt .vdb inputs end to end: a scene and a pyramid written by vox, and a
# level set and a fog volume written by OpenVDB (tests/fuzz/vdb_seeds/), each
# with a leaf block's stored size made negative (OpenVDB would copy that many
# bytes into a 512-value leaf), made huge, the Blosc header's compressed size
# enlarged, and the file cut in half. Every command that reads a .vdb must exit
# 3 with one message naming the file (and the grid, where the damage is inside
# one), and leave no output behind.
# Usage: vdb_corrupt_test.sh VOX_BINARY TESTS_DIR
set -u
vox=$1 tests=$2
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

# corrupt IN OUT KIND: OUT is IN with the last Blosc block (a leaf's values)
# damaged: KIND negative, huge or header; or IN cut in half (KIND cut).
corrupt() {
  python3 - "$1" "$2" "$3" <<'EOF'
import struct, sys
src, dst, kind = sys.argv[1:4]
b = bytearray(open(src, 'rb').read())
if kind == 'cut':
    b = b[:len(b) // 2]
else:
    last = None
    for p in range(0, len(b) - 24):
        n = struct.unpack_from('<q', b, p)[0]
        if 16 <= n <= len(b) - p - 8 and b[p + 8] == 2 and struct.unpack_from('<I', b, p + 20)[0] == n:
            last = p
    assert last is not None, 'no Blosc block found'
    if kind == 'negative':
        struct.pack_into('<q', b, last, -(1 << 20))
    elif kind == 'huge':
        struct.pack_into('<q', b, last, 1 << 40)
    else:
        struct.pack_into('<I', b, last + 20, struct.unpack_from('<I', b, last + 20)[0] + 4096)
open(dst, 'wb').write(b)
EOF
}

# refused FILE CMD...: CMD exits 3 with one line on stderr naming FILE.
refused() {
  local file=$1; shift
  expect_exit 3 "$@"
  expect_stderr "$file"
  [ "$(wc -l <err.txt)" = 1 ] || fail "expected one line on stderr: $(head -c 400 err.txt)"
}

"$vox" voxelize demo:hamlet --res 16 -o scene.vdb --quiet || fail "cannot make the scene"
"$vox" mip scene.vdb -o pyramid.vdb --quiet || fail "cannot make the pyramid"
cp "$tests/fuzz/vdb_seeds/levelset.vdb" "$tests/fuzz/vdb_seeds/fog.vdb" .

for kind in negative huge header cut; do
  for f in scene pyramid; do
    bad=${f}_$kind.vdb
    corrupt $f.vdb "$bad" $kind
    refused "$bad" "$vox" info "$bad"
    [ $kind = cut ] || expect_stderr "grid '"
    refused "$bad" "$vox" info "$bad" --json
    [ -s out.txt ] && fail "info --json printed on a refused file: $(head -c 200 out.txt)"
    refused "$bad" "$vox" build-atlas "$bad" -o atlas_$bad
    [ -z "$(ls -A atlas_$bad 2>/dev/null)" ] || fail "build-atlas left files: $(ls atlas_$bad)"
    refused "$bad" "$vox" pack-chunks "$bad" -o p_$bad.vpk
    [ -e p_$bad.vpk ] && fail "pack-chunks left p_$bad.vpk"
    refused "$bad" "$vox" mip "$bad" -o m_$bad
    [ -e m_$bad ] && fail "mip left m_$bad"
    refused "$bad" "$vox" diff "$bad" scene.vdb
    refused "$bad" "$vox" diff scene.vdb "$bad"
    refused "$bad" "$vox" render-canonical "$bad" --eye 30,30,30 --target 8,8,8 -o r_$bad.png
    [ -e r_$bad.png ] && fail "render-canonical left r_$bad.png"
    refused "$bad" "$vox" export "$bad" -o e_$bad.ply
    [ -e e_$bad.ply ] && fail "export left e_$bad.ply"
  done
  for f in levelset fog; do
    bad=${f}_$kind.vdb
    corrupt $f.vdb "$bad" $kind
    refused "$bad" "$vox" voxelize "$bad" --res 8 --threshold 0.5 -o v_$bad
    [ $kind = cut ] || expect_stderr "grid '"
    [ -e v_$bad ] && fail "voxelize left v_$bad"
    refused "$bad" "$vox" info "$bad"
  done
done

# The intact files still work.
expect_exit 0 "$vox" info pyramid.vdb
expect_exit 0 "$vox" voxelize levelset.vdb --res 8 -o ls.vdb
expect_exit 0 "$vox" voxelize fog.vdb --res 8 --threshold 0.5 -o fog_scene.vdb
expect_exit 0 "$vox" diff scene.vdb scene.vdb

[ "$failures" = 0 ] || { echo "$failures failure(s)" >&2; exit 1; }
echo "vdb_corrupt_test: ok"
