#!/usr/bin/env bash
# The memory guard (docs/reliability.md "Memory"): requests over --max-memory
# are refused before the work (exit 4, the estimate, the limit and a setting
# that fits; no output; little CPU time), --max-memory 0 disables the guard,
# the estimate is within 2x of the measured peak (maximum resident set size of
# the child, from /usr/bin/time or getrusage: a measurement, not a timing), and
# an allocation failure that still happens ends in exit 4 with a message.
# Usage: memory_guard_test.sh GROUP VOX_BINARY DATA_DIR
set -u
group=$1 vox=$2 data=$3
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

# A unit cube of 12 triangles, faces on the grid's faces.
cube() {
  printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n' >cube.obj
  printf 'f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n' >>cube.obj
}

# measured CMD...: runs CMD under getrusage; sets $peak (bytes), $cpu (user+sys
# seconds) and $code. stdout/stderr in out.txt/err.txt.
measured() {
  python3 - "$@" >out.txt 2>err.txt <<'EOF'
import resource, subprocess, sys
p = subprocess.run(sys.argv[1:], stdout=sys.stdout, stderr=sys.stderr)
r = resource.getrusage(resource.RUSAGE_CHILDREN)
open("rusage.txt", "w").write("%d %.3f %d\n" % (r.ru_maxrss * 1024, r.ru_utime + r.ru_stime, p.returncode))
EOF
  read -r peak cpu code <rusage.txt
}

# refused WHAT CMD...: exit 4 with the guard's message, quickly, nothing written.
refused() {
  local what=$1; shift
  measured "$@"
  [ "$code" = 4 ] || fail "$what: exit $code, expected 4 (stderr: $(head -c 400 err.txt))"
  expect_stderr "needs about"
  expect_stderr "but the memory limit is"
  # Up front means seconds, not the bake's minutes: the costliest refusal here
  # (the cube at 4096 counts 1.5 M blocks, then searches a --res that fits)
  # takes 0.7-0.9 s of CPU alone and up to 1.2 s beside ctest -j2 and a build.
  python3 -c "import sys; sys.exit(0 if $cpu < 2.0 else 1)" || fail "$what: the refusal took $cpu s of CPU (over 2 s)"
  echo "$what: refused in $cpu s CPU: $(head -c 300 err.txt)"
}

# within2x WHAT REPORT: the report's estimate against $peak.
within2x() {
  python3 - "$1" "$2" "$peak" <<'EOF' || fail "$1: estimate not within 2x of the measured peak"
import json, sys
what, report, peak = sys.argv[1], sys.argv[2], int(sys.argv[3])
est = json.load(open(report))["memory"]["estimate_bytes"]
ratio = est / peak
print(f"{what}: estimate {est/2**20:.1f} MiB, measured peak {peak/2**20:.1f} MiB, ratio {ratio:.2f}")
sys.exit(0 if 0.5 <= ratio <= 2.0 else 1)
EOF
}

case $group in
refusals)
  cube
  # A 4096^3 surface bake of the cube needs ~1.8 GiB: refused under 512 MiB, with a --res that fits
  # (under 1 GiB the suggestion, near 3000, takes the refusal over its second of CPU).
  refused "cube --res 4096" "$vox" voxelize cube.obj --res 4096 --max-memory 512M -o big.vdb
  expect_stderr "--res "
  expect_stderr "would need about"
  [ ! -e big.vdb ] || fail "a refused bake left big.vdb"
  # The suggested resolution does fit (and runs).
  res=$(grep -o -- '--res [0-9]*' err.txt | head -1 | cut -d' ' -f2)
  if [ -n "$res" ]; then
    expect_exit 0 "$vox" voxelize cube.obj --res "$res" --max-memory 512M -o fits.vdb -q
    [ -s fits.vdb ] || fail "the suggested --res $res wrote nothing"
  else
    fail "no --res suggested"
  fi
  # A render over the limit: refused with the largest --size of its aspect that fits, which runs
  # (its estimate was 2.6-4.7x high, so sizes that fit were refused).
  expect_exit 0 "$vox" voxelize cube.obj --res 64 -o c64.vdb -q
  refused "render-canonical 6000x3000" "$vox" render-canonical c64.vdb -o r.png --view iso --size 6000x3000 --max-memory 300M
  size=$(grep -o -- '--size [0-9]*x[0-9]* would fit' err.txt | cut -d' ' -f2)
  if [ -n "$size" ]; then
    expect_exit 0 "$vox" render-canonical c64.vdb -o r.png --view iso --size "$size" --max-memory 300M -q --report rr.json
    jcheck rr.json "w, h = map(int, '$size'.split('x')); assert w * 3000 // 6000 - 2 <= h <= w * 3000 // 6000 + 2 and w > 3000, (w, h)"
  else
    fail "no --size suggested: $(head -c 400 err.txt)"
  fi
  # A tiny voxel size: refused with a voxel size that fits.
  refused "cube --voxel-size 0.0002" "$vox" voxelize cube.obj --voxel-size 0.0002 --max-memory 512M -o big.vdb
  expect_stderr "--voxel-size "
  # Solid fill: the bit sets and the interior count.
  refused "cube --fill solid --res 4096" "$vox" voxelize cube.obj --res 4096 --fill solid --max-memory 2G -o big.vdb
  # --method sdf (OpenVDB's meshToVolume).
  refused "cube --method sdf --res 4096" "$vox" voxelize cube.obj --res 4096 --method sdf --max-memory 2G -o big.vdb
  # The hamlet at 4096 needs ~80 GB.
  refused "demo:hamlet --res 4096" "$vox" voxelize demo:hamlet --res 4096 --max-memory 16G -o big.vdb
  expect_stderr "--res "
  # The default limit is a share of physical memory: the hamlet at 4096 exceeds any machine below ~100 GB.
  mem=$(awk '/MemTotal/ {printf "%d", $2 * 1024}' /proc/meminfo)
  if [ "$mem" -lt 100000000000 ]; then
    refused "demo:hamlet --res 4096 (default limit)" "$vox" voxelize demo:hamlet --res 4096 -o big.vdb
    expect_stderr "% of "
  fi
  # A small bake under a tiny limit, then with the guard off.
  refused "cube --max-memory 1M" "$vox" voxelize cube.obj --res 32 --max-memory 1M -o small.vdb
  [ ! -e small.vdb ] || fail "a refused bake left small.vdb"
  expect_exit 0 "$vox" voxelize cube.obj --res 32 --max-memory 0 -o small.vdb -q
  [ -s small.vdb ] || fail "--max-memory 0 did not disable the guard"
  # Commands that read a scene are guarded at the read.
  refused "info --max-memory 1M" "$vox" info small.vdb --max-memory 1M
  refused "mip --max-memory 1M" "$vox" mip small.vdb -o m.vdb --max-memory 1M
  [ ! -e m.vdb ] || fail "a refused mip left m.vdb"
  # Bad sizes are usage errors.
  expect_exit 2 "$vox" voxelize cube.obj --res 32 --max-memory 12X -o bad.vdb
  expect_stderr "--max-memory"
  ;;
atlas)
  # A 3-voxel scene in a 512^3 grid: 16384 x 8192 texels per layer.
  printf '{"worldScale": 1.0, "blocks": [{"position": [0, 0, 0], "blockType": "Stone"}, {"position": [511, 511, 511], "blockType": "Grass"}, {"position": [100, 200, 300], "blockType": "Sand"}]}\n' >three.json
  expect_exit 0 "$vox" voxelize three.json --grid-size 512,512,512 -o three.vdb -q
  # Streamed (PNG files of a sparse scene: rows from the sorted occupied
  # texels): memory in the voxels, so it runs under 100M.
  measured "$vox" build-atlas three.vdb -o streamed --summary --occupancy --occupancy2 --identity --max-memory 100M --report s.json -q
  [ "$code" = 0 ] || fail "streamed build-atlas under 100M: exit $code ($(head -c 300 err.txt))"
  [ "$peak" -le $((100 * 1024 * 1024)) ] || fail "streamed build-atlas peaked at $peak bytes, over 100M"
  within2x "build-atlas 512^3, 3 voxels, streamed" s.json
  # --preview draws from whole images: the dense path, one layer at a time.
  # Refused under 256M with a --max-side that fits, which then runs within it.
  refused "build-atlas --preview 512^3 under 256M" "$vox" build-atlas three.vdb -o atlas --preview --max-memory 256M
  expect_stderr "--max-side "
  [ ! -e atlas ] || fail "a refused build-atlas left its directory"
  side=$(grep -o -- '--max-side [0-9]*' err.txt | head -1 | cut -d' ' -f2)
  measured "$vox" build-atlas three.vdb -o dense --summary --occupancy --occupancy2 --identity --preview \
    --max-memory 256M --max-side "${side:-4096}" --report d.json -q
  [ "$code" = 0 ] || fail "build-atlas --max-side ${side:-4096}: exit $code ($(head -c 300 err.txt))"
  [ "$peak" -le $((256 * 1024 * 1024)) ] || fail "build-atlas --max-side $side peaked at $peak bytes, over the 256M limit"
  within2x "build-atlas --preview 512^3, 3 voxels, --max-side $side" d.json
  # The streamed files hold the dense path's texels and text (same layout at the
  # same --max-side). Their bytes differ: the streamed path deflates one stream,
  # the dense one row slices in parallel; each is the same at any --threads.
  expect_exit 0 "$vox" build-atlas three.vdb -o streamed2 --summary --occupancy --occupancy2 --identity --max-side "${side:-4096}" -q
  for f in dense/*.png; do
    case $f in *.preview.png) continue ;; esac
    "$vox" diff "$f" "streamed2/$(basename "$f")" --fail 0 >diff.txt 2>&1 ||
      fail "streamed $(basename "$f") differs from the dense path's: $(head -c 300 diff.txt)"
  done
  expect_exit 0 "$vox" build-atlas three.vdb -o streamed3 --summary --occupancy --identity --threads 1 -q
  for f in streamed3/*.png; do
    cmp -s "$f" "streamed/$(basename "$f")" || fail "streamed $(basename "$f") differs between --threads 1 and 2"
  done
  layer=$(ls streamed/three.occupancy*.png | head -1)
  expect_exit 0 "$vox" verify-bijection --atlas "$layer" --scene three.vdb
  ;;
estimates)
  cube
  # Five shapes, estimate against the measured peak (bytes of the child's maximum resident set).
  measured "$vox" voxelize cube.obj --res 512 -o c.vdb --report c.json
  within2x "cube surface 512" c.json
  measured "$vox" voxelize cube.obj --res 256 --fill solid -o cs.vdb --report cs.json
  within2x "cube solid 256" cs.json
  measured "$vox" voxelize demo:hamlet --res 256 -o h.vdb --report h.json
  within2x "hamlet 256" h.json
  measured "$vox" build-atlas h.vdb -o ha --all --report ha.json
  within2x "build-atlas hamlet 256 --all" ha.json
  # The commands that read a scene as packed leaves, on a coloured surface
  # (12 bytes a voxel where an OpenVDB leaf holds 6 KB: estimated as OpenVDB
  # trees, a mip of it came out 3.5x its peak) and on the hamlet's classes.
  sed 's/^v \([01]\) \([01]\) \([01]\)$/v \1 \2 \3 \1 0.5 \3/' cube.obj >colour.obj
  measured "$vox" voxelize colour.obj --res 384 -o cc.vdb --report cc.json
  within2x "coloured cube surface 384" cc.json
  "$vox" info cc.vdb | grep -q "colour" || fail "cc.vdb has no colour: $("$vox" info cc.vdb 2>&1 | head -5)"
  for scene in cc h; do
    measured "$vox" mip $scene.vdb -o ${scene}m.vdb --report ${scene}m.json
    within2x "mip $scene" ${scene}m.json
    measured "$vox" pack-chunks $scene.vdb -o $scene.vpk --report ${scene}p.json
    within2x "pack-chunks $scene" ${scene}p.json
    measured "$vox" export $scene.vdb -o $scene.glb --report ${scene}e.json
    within2x "export $scene glb" ${scene}e.json
    measured "$vox" export $scene.vdb -o ${scene}g.glb --greedy --report ${scene}g.json
    within2x "export $scene glb --greedy" ${scene}g.json
    measured "$vox" render-canonical $scene.vdb -o $scene.png --view iso --size 512x512 --mode class --report ${scene}r.json
    within2x "render-canonical $scene" ${scene}r.json
  done
  # OpenVDB volumes: a level set's band grows with --half-width, not with the
  # grids read (estimated on those, the cube's half-width 40 came out 0.28x
  # its peak); an axis-aligned shell is the band's tightest case.
  measured "$vox" voxelize cube.obj --res 256 -o cu.vdb --report cu.json
  for hw in 3 40; do
    measured "$vox" export cu.vdb -o cul$hw.vdb --level-set --half-width $hw --report cul$hw.json
    within2x "export cube 256 --level-set --half-width $hw" cul$hw.json
    python3 -c "import json, sys; sys.exit(0 if json.load(open('cul$hw.json'))['memory']['estimate_bytes'] >= $peak else 1)" ||
      fail "level set --half-width $hw: estimate under the measured peak"
  done
  # Over the limit: refused, with the widest band that fits, which then runs within it.
  refused "export cube --level-set --half-width 40 under 200M" "$vox" export cu.vdb -o cur.vdb --level-set --half-width 40 --max-memory 200M
  expect_stderr "--half-width "
  [ ! -e cur.vdb ] || fail "a refused level-set export wrote its file"
  hw=$(grep -o -- '--half-width [0-9]*' err.txt | tail -1 | cut -d' ' -f2)
  measured "$vox" export cu.vdb -o cur.vdb --level-set --half-width "${hw:-1}" --max-memory 200M
  [ "$code" = 0 ] || fail "export --half-width $hw under 200M: exit $code ($(head -c 300 err.txt))"
  [ "$peak" -le $((200 * 1024 * 1024)) ] || fail "export --half-width $hw peaked at $peak bytes, over the 200M limit"
  measured "$vox" export h.vdb -o hf.vdb --fog --report hf.json
  within2x "export hamlet 256 --fog" hf.json
  if [ -d "$data/common-3d-test-models" ]; then
    measured "$vox" voxelize "$data/common-3d-test-models/fandisk.obj" --res 512 -o f.vdb --report f.json
    within2x "fandisk surface 512" f.json
    measured "$vox" voxelize "$data/common-3d-test-models/stanford-bunny.obj" --res 256 --fill solid -o b.vdb --report b.json
    within2x "bunny solid 256" b.json
  else
    echo "SKIP: $data/common-3d-test-models absent (fandisk, bunny estimates)"
  fi
  ;;
accuracy)
  # The estimates mended on 2026-12-02 (docs/reliability.md "Estimates
  # against measured peaks"), each against the measured peak: a region of a
  # world whose faces span it (the estimate followed the triangles meeting
  # the region, so it stayed near the world's: 2.7x at N = 8), a solid fill
  # of an STL soup (estimated unwelded: 3.8x), --method sdf (OpenVDB's
  # per-worker memory: 0.82x) and vox diff (each scene alone: 0.75x); then
  # (2026-12-02, later) whole bakes and regions with the writer counted,
  # --check, the hamlet and pyramid diffs.
  # ratio WHAT REPORT LO HI: the report's estimate over $peak within [LO, HI].
  ratio() {
    python3 - "$@" "$peak" <<'EOF2' || fail "$1: estimate over peak outside [$3, $4]"
import json, sys
what, report, lo, hi, peak = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
est = json.load(open(report))["memory"]["estimate_bytes"]
print(f"{what}: estimate {est/2**20:.1f} MiB, measured peak {peak/2**20:.1f} MiB, ratio {est/peak:.2f}")
sys.exit(0 if lo <= est / peak <= hi else 1)
EOF2
  }
  cube
  # The whole bake and its regions: the writer's buffers beyond the blocks
  # (strings of the whole grid grown by doubling) left them at 0.89-0.97.
  measured "$vox" voxelize cube.obj --res 1024 -o c1024.vdb --report c1024.json
  ratio "cube 1024" c1024.json 1.0 1.5
  measured "$vox" voxelize cube.obj --res 1024 --region 0/8 -o r8.vdb --report r8.json
  ratio "cube 1024 region 0/8" r8.json 1.0 1.5
  measured "$vox" voxelize cube.obj --res 1024 --region 0/2 --threads 1 -o r2.vdb --report r2.json
  ratio "cube 1024 region 0/2, 1 thread" r2.json 1.0 1.5
  measured "$vox" voxelize cube.obj --res 256 --fill solid -o cs.vdb --report cs.json
  ratio "cube solid 256" cs.json 1.0 1.5
  # --check: the scene's OpenVDB trees (interior vote leaves included) and the
  # surface check's voxel set (0.66-0.79 before).
  measured "$vox" voxelize cube.obj --res 512 --check -o ck.vdb --report ck.json
  ratio "cube 512 --check" ck.json 1.0 1.5
  measured "$vox" voxelize cube.obj --res 256 --fill solid --check --threads 1 -o cks.vdb --report cks.json
  ratio "cube solid 256 --check, 1 thread" cks.json 1.0 1.5
  if [ -d "$data/common-3d-test-models" ]; then
    # A small bake (the writer's fixed part counts: 0.78 before) and a large one.
    measured "$vox" voxelize "$data/common-3d-test-models/fandisk.obj" --res 256 -o f.vdb --report f.json
    ratio "fandisk 256" f.json 1.0 1.5
    measured "$vox" voxelize "$data/common-3d-test-models/stanford-bunny.obj" --res 1024 --threads 1 -o b.vdb --report b.json
    ratio "bunny 1024, 1 thread" b.json 1.0 1.5
  else
    echo "SKIP: $data/common-3d-test-models absent (fandisk, bunny accuracy)"
  fi
  # mip and merge write through the direct writer, a batch of leaves at a
  # time; their estimates counted its old grid-sized buffers (merge 2.0-2.4x,
  # mip up to 1.47x). Now the levels' blocks (from the base's origins) and
  # the writer's lists and batches; the merge from the parts' topology.
  measured "$vox" mip c1024.vdb -o cm.vdb --report cm.json
  ratio "mip cube 1024" cm.json 1.0 1.5
  measured "$vox" mip c1024.vdb --split -o cms --report cms.json
  ratio "mip --split cube 1024" cms.json 1.0 1.5
  for i in 0 1 2 3; do expect_exit 0 "$vox" voxelize cube.obj --res 1024 --region $i/4 -o part$i.vdb -q; done
  measured "$vox" merge part0.vdb part1.vdb part2.vdb part3.vdb -o cmerge.vdb --report cmerge.json
  [ "$code" = 0 ] || fail "merge of 4 parts: exit $code ($(head -c 300 err.txt))"
  ratio "merge cube 1024, 4 parts" cmerge.json 1.0 1.5
  rm -f cm.vdb cms.mip*.vdb part?.vdb cmerge.vdb
  rm -f c1024.vdb r8.vdb r2.vdb cs.vdb ck.vdb cks.vdb f.vdb b.vdb
  # A closed UV sphere as binary STL: 80,000 triangles, 240,000 vertices, 40,002 positions.
  python3 - <<'EOF2'
import math, struct
rings, segs = 201, 200
P = [(0, 0, 1)] + [(math.sin(math.pi * r / rings) * math.cos(2 * math.pi * s / segs),
                    math.sin(math.pi * r / rings) * math.sin(2 * math.pi * s / segs), math.cos(math.pi * r / rings))
                   for r in range(1, rings) for s in range(segs)] + [(0, 0, -1)]
T = [(0, 1 + s, 1 + (s + 1) % segs) for s in range(segs)]
for r in range(rings - 2):
    for s in range(segs):
        a, b = 1 + r * segs + s, 1 + r * segs + (s + 1) % segs
        T += [(a, a + segs, b), (b, a + segs, b + segs)]
T += [(1 + (rings - 2) * segs + s, len(P) - 1, 1 + (rings - 2) * segs + (s + 1) % segs) for s in range(segs)]
with open("sphere.stl", "wb") as f:
    f.write(bytes(80) + struct.pack("<I", len(T)))
    for t in T:
        f.write(struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *P[v]) for v in t) + b"\0\0")
with open("sphere.obj", "w") as f:
    f.write("".join("v %.9g %.9g %.9g\n" % p for p in P) + "".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in T))
EOF2
  measured "$vox" voxelize sphere.stl --res 16 --fill solid -o ss.vdb --report ss.json
  ratio "STL sphere solid 16" ss.json 1.0 1.6
  # The same sphere indexed: its winding tables were fitted on five meshes
  # (1.41x); refitted on 31 (docs/reliability.md, 2026-12-02 afternoon): 1.19.
  measured "$vox" voxelize sphere.obj --res 16 --fill solid -o so.vdb --report so.json
  ratio "OBJ sphere solid 16" so.json 1.0 1.3
  measured "$vox" voxelize cube.obj --res 256 --method sdf -o sdf.vdb --report sdf.json
  ratio "cube sdf 256" sdf.json 1.0 1.5
  # A surface bake clips the triangles reaching past 2^20 voxels and keeps
  # the clipped copy (16 bytes a triangle): a finely tiled square (few
  # voxels, many triangles) beside a ground plane 8e7 voxels wide, at two
  # sizes; the estimate's part follows the triangles, and the bake of
  # 500,000 triangles (0.82x before the copy and the tiles' lists counted)
  # lies at or over its peak.
  tiled() {  # N FILE [noplane]: an N x N vertex square of 2 (N-1)^2 triangles, and the far plane
    python3 - "$1" "$2" "${3:-}" <<'EOF2'
import sys
n, out, noplane = int(sys.argv[1]), sys.argv[2], sys.argv[3] == "noplane"
with open(out, "w") as f:
    w = f.write
    for j in range(n):
        for i in range(n):
            w(f"v {1 + 2 * i / (n - 1):.6f} {1 + 2 * j / (n - 1):.6f} 1\n")
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i + 1
            w(f"f {a} {a + 1} {a + n + 1}\nf {a} {a + n + 1} {a + n}\n")
    if noplane:
        sys.exit(0)
    v = n * n
    w("v -2000000 -2000000 0\nv 2000000 -2000000 0\nv 2000000 2000000 0\nv -2000000 2000000 0\n")
    w(f"f {v + 1} {v + 2} {v + 3}\nf {v + 1} {v + 3} {v + 4}\n")
EOF2
  }
  tiled 355 far1.obj
  tiled 501 far2.obj
  expect_exit 0 "$vox" voxelize far1.obj --bounds -8,-8,-1,8,8,12 --voxel-size 0.05 -o far1.vdb --report far1.json -q
  measured "$vox" voxelize far2.obj --bounds -8,-8,-1,8,8,12 --voxel-size 0.05 -o far2.vdb --report far2.json
  [ "$code" = 0 ] || fail "far plane bake: exit $code ($(head -c 300 err.txt))"
  ratio "500,000 triangles beside a far plane" far2.json 1.0 1.5
  python3 - far1.json far2.json <<'EOF2' || fail "the clipped triangles' part is missing or does not follow them"
import json, sys
for r, n in zip(sys.argv[1:], (355, 501)):
    c = max(json.load(open(r))["memory"]["checks"], key=lambda c: c["estimate_bytes"])
    p = c["parts"].get("clipped triangles", 0)
    t = 2 * (n - 1) ** 2 + 2  # the square's and the plane's (clipped to a fan each)
    print(f"clipped triangles: {p} bytes for {t} triangles")
    # 16 bytes each, and the plane's fans' weights and new vertices
    if not 16 * t <= p <= 16 * t + 4096:
        sys.exit(1)
EOF2
  rm -f far1.obj far2.obj far1.vdb far2.vdb
  # The square of 1,000,000 triangles alone peaks while its OBJ is read (the
  # file mapped, the arrays grown by doubling: 0.99 before), not in the bake:
  # that peak, read before the estimate, is counted where it is the larger.
  tiled 709 sq.obj noplane
  measured "$vox" voxelize sq.obj --bounds -8,-8,-1,8,8,12 --voxel-size 0.05 -o sq.vdb --report sq.json
  [ "$code" = 0 ] || fail "square bake: exit $code ($(head -c 300 err.txt))"
  ratio "1,000,000-triangle square" sq.json 1.0 1.5
  rm -f sq.obj sq.vdb
  measured "$vox" voxelize demo:hamlet --res 256 -o h1.vdb --report hb.json
  ratio "hamlet 256" hb.json 1.0 1.5
  expect_exit 0 "$vox" voxelize demo:hamlet --res 256 --threads 1 -o h2.vdb -q
  measured "$vox" diff h1.vdb h2.vdb --report d.json
  [ "$code" = 0 ] || fail "diff of two hamlets: exit $code ($(head -c 300 err.txt))"
  ratio "diff hamlet 256" d.json 1.0 1.5
  # Pyramids: many sparse grids, whose internal nodes outweigh their leaves (0.79 before).
  measured "$vox" mip h1.vdb -o p1.vdb --report mh.json
  ratio "mip hamlet 256" mh.json 1.0 1.5
  expect_exit 0 "$vox" mip h2.vdb -o p2.vdb -q
  measured "$vox" diff p1.vdb p2.vdb --report dp.json
  [ "$code" = 0 ] || fail "diff of two hamlet pyramids: exit $code ($(head -c 300 err.txt))"
  ratio "diff hamlet pyramids 256" dp.json 1.0 1.5
  # vox fuse: the first view is read before the estimate (its resident
  # memory) and was counted again as decoded ahead (one 2048^2 view: 2.2-2.3x).
  expect_exit 0 "$vox" render-canonical h1.vdb -o fv.png --orbit 2 --size 2048x2048 --mode depth,class --quiet
  for n in 1 2; do
    python3 -c "import json; json.dump({'views': [{'depth': 'fv_%03d.depth.exr' % i, 'label': 'fv_%03d.class.png' % i} for i in range($n)]}, open('fv$n.json', 'w'))"
  done
  measured "$vox" fuse fv1.json -o fv1.vdb --threads 2 --report fv1r.json
  [ "$code" = 0 ] || fail "fuse of one view: exit $code ($(head -c 300 err.txt))"
  ratio "fuse one 2048^2 view" fv1r.json 1.0 1.5
  measured "$vox" fuse fv2.json -o fv2.vdb --threads 2 --report fv2r.json
  [ "$code" = 0 ] || fail "fuse of two views: exit $code ($(head -c 300 err.txt))"
  ratio "fuse two 2048^2 views" fv2r.json 1.0 2.5
  rm -f fv_* fv1.vdb fv2.vdb
  # Under a limit each scene alone fits but both together do not: refused before reading.
  refused "diff under 90M" "$vox" diff h1.vdb h2.vdb --max-memory 90M
  expect_stderr "comparing h1.vdb with h2.vdb"
  ;;
oom)
  # An allocation failure the guard did not foresee (here: the address space
  # capped below what the bake needs, guard off) is exit 4 with a message,
  # never an abort, and leaves no output. (The hamlet at 1024 peaks at about
  # 700 MB of resident memory.)
  (ulimit -v 600000 && "$vox" voxelize demo:hamlet --res 1024 --max-memory 0 -o h.vdb) >out.txt 2>err.txt
  got=$?
  [ "$got" = 4 ] || fail "out of memory: exit $got, expected 4 ($(head -c 400 err.txt))"
  expect_stderr "out of memory"
  [ ! -e h.vdb ] || fail "an out-of-memory run left h.vdb"
  ls -a | grep -q '\.tmp-' && fail "an out-of-memory run left a temporary file"
  echo "oom: $(head -c 300 err.txt)"
  ;;
*)
  echo "unknown group $group" >&2
  exit 2
  ;;
esac
[ "$failures" = 0 ] || { echo "$failures failure(s)" >&2; exit 1; }
echo "memory_guard $group: ok"
