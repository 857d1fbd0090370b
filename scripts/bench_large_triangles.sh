#!/bin/bash
# Large-triangle and coloured meshes against a scan, this build against
# another build's vox (docs/bench-voxelize.md, "Large triangles"): a
# 12-triangle vertex-coloured unit cube (written here), the textured
# BoxTextured.glb and the Stanford bunny (when ../shared/data is present), at
# 256 and 512, --threads 1 and 2, all in one hyperfine run (user and system
# CPU beside wall); then the voxelize phase per output voxel (--report, min and
# median of RUNS interleaved runs), peak memory (/usr/bin/time -v), and every
# scene compared byte for byte with OLD's at --threads 1.
# Usage: scripts/bench_large_triangles.sh OLD_VOX [BUILD_DIR] [RUNS]   -> Markdown on stdout
set -eu
cd "$(dirname "$0")/.."
root=$(pwd)
OLD=$(realpath "${1:?usage: bench_large_triangles.sh OLD_VOX [BUILD_DIR] [RUNS]}")
NEW=$root/${2:-build}/bin/vox
RUNS=${3:-7}
DATA=$root/../shared/data
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

# The unit cube, one colour per vertex (v x y z r g b), outward faces.
cat > box12.obj <<'EOF'
v 0 0 0 1 0 0
v 1 0 0 0 1 0
v 1 1 0 0 0 1
v 0 1 0 1 1 0
v 0 0 1 0 1 1
v 1 0 1 1 0 1
v 1 1 1 1 1 1
v 0 1 1 0.5 0.5 0.5
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 4 8 7
f 4 7 3
f 1 5 8
f 1 8 4
f 2 3 7
f 2 7 6
EOF
meshes=("box12.obj 256" "box12.obj 512")
TEX=$DATA/gltf/assimp/BoxTextured-glTF-Binary/BoxTextured.glb
BUNNY=$DATA/common-3d-test-models/stanford-bunny.obj
[ -f "$TEX" ] && meshes+=("$TEX 512") || echo "(BoxTextured.glb not found: skipped)"
[ -f "$BUNNY" ] && meshes+=("$BUNNY 256" "$BUNNY 512") || echo "(stanford-bunny.obj not found: skipped)"

echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
args=()
for c in "${meshes[@]}"; do
  m=${c% *} res=${c##* }
  for v in old new; do
    bin=$OLD; [ $v = new ] && bin=$NEW
    for t in 1 2; do args+=(-n "$v $(basename "$m") $res t$t" "$bin voxelize $m --res $res -o out.vdb -q --threads $t"); done
  done
done
nice -n 5 hyperfine -N --warmup 2 --runs 10 --style none --export-json hf.json "${args[@]}" >/dev/null
echo "load average after hyperfine: $(cut -d' ' -f1-3 /proc/loadavg)"
echo
python3 - <<'PY'
import json
d = json.load(open('hf.json'))
print("| command | wall mean ms | user + sys ms |")
print("|---|---:|---:|")
for r in d['results']:
    print(f"| {r['command']} | {r['mean']*1e3:.0f} ± {r['stddev']*1e3:.0f} | {(r['user']+r['system'])*1e3:.0f} |")
PY

: > phases.tsv
for i in $(seq "$RUNS"); do
  for c in "${meshes[@]}"; do
    m=${c% *} res=${c##* }
    for v in old new; do
      bin=$OLD; [ $v = new ] && bin=$NEW
      for t in 1 2; do
        nice -n 5 "$bin" voxelize "$m" --res "$res" -o ph.vdb -q --threads "$t" --report ph.json
        python3 -c "
import json; d = json.load(open('ph.json')); ph = {p['name']: p['seconds'] for p in d['phases']}
print('$v', '$(basename "$m")', $res, $t, d['counts']['occupied_voxels'], ph['voxelize'], d['total_seconds'], sep='\t')" >> phases.tsv
      done
    done
  done
done
echo
echo "load average after the phases: $(cut -d' ' -f1-3 /proc/loadavg)"
echo
python3 - <<'PY'
import collections, statistics
g = collections.defaultdict(list)
for line in open('phases.tsv'):
    v, m, r, t, n, vx, tot = line.split('\t')
    g[(m, int(r), t, v, int(n))].append((float(vx), float(tot)))
print("| mesh | res | threads | build | voxels | voxelize min / median ms | ns per voxel (median) | end to end min / median ms | ns per voxel (median) |")
print("|---|---:|---:|---|---:|---:|---:|---:|---:|")
for k in sorted(g, key=lambda k: (k[1], k[0], k[2], k[3] != 'old')):
    vx = [a for a, _ in g[k]]; tot = [b for _, b in g[k]]
    print(f"| {k[0]} | {k[1]} | {k[2]} | {k[3]} | {k[4]} | {min(vx)*1e3:.0f} / {statistics.median(vx)*1e3:.0f} | "
          f"{statistics.median(vx)/k[4]*1e9:.0f} | {min(tot)*1e3:.0f} / {statistics.median(tot)*1e3:.0f} | "
          f"{statistics.median(tot)/k[4]*1e9:.0f} |")
PY

echo
echo "| mesh | res | threads | old peak MB | new peak MB | bytes |"
echo "|---|---:|---:|---:|---:|---|"
for c in "${meshes[@]}"; do
  m=${c% *} res=${c##* }
  "$OLD" voxelize "$m" --res "$res" -o ref.vdb -q --threads 1
  for t in 1 2; do
    /usr/bin/time -v -o old.time "$OLD" voxelize "$m" --res "$res" -o old.vdb -q --threads "$t"
    /usr/bin/time -v -o new.time "$NEW" voxelize "$m" --res "$res" -o new.vdb -q --threads "$t"
    peak() { awk '/Maximum resident/ {printf "%.1f", $NF / 1024}' "$1"; }
    same=differ; cmp -s ref.vdb new.vdb && same="same as old at --threads 1"
    echo "| $(basename "$m") | $res | $t | $(peak old.time) | $(peak new.time) | $same |"
  done
done
