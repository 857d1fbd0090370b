#!/usr/bin/env bash
# Benchmarks `vox fuse` (docs/fuse.md): rays per second and voxel steps per
# ray when fusing VIEWS orbit renders (depth, class, normal) of the demo
# hamlet back into its grid (with carving, and votes only), against render-canonical casting the same views
# (the ratio comes from one hyperfine run), and the fused scene's peak memory.
# Writes markdown to docs/bench-fuse.md (or $OUT).
#
# Usage: scripts/bench_fuse.sh
# Env: BUILD_DIR (default build), RES (grid side, default 256), VIEWS (default 16),
#      SIZE (default 512x512), THREADS (default: all cores), RUNS (default 3).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
vox=$root/${BUILD_DIR:-build}/bin/vox
res=${RES:-256}
views=${VIEWS:-16}
size=${SIZE:-512x512}
threads=${THREADS:-$(nproc)}
runs=${RUNS:-3}
out=${OUT:-$root/docs/bench-fuse.md}
for tool in hyperfine python3; do
  command -v $tool >/dev/null || { echo "bench_fuse.sh: needs $tool (apt-get install hyperfine)" >&2; exit 4; }
done
[ -x "$vox" ] || { echo "bench_fuse.sh: build vox first ($vox)" >&2; exit 4; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

echo "== hamlet $res^3, $views views of $size" >&2
"$vox" voxelize demo:hamlet --res "$res" -o h.vdb --quiet
"$vox" render-canonical h.vdb -o o.png --orbit "$views" --size "$size" --mode depth,class,normal --quiet \
  --touched touched.json
python3 - "$views" <<'PY'
import json, sys
n = int(sys.argv[1])
json.dump({'views': [{'depth': 'o_%03d.depth.exr' % i, 'label': 'o_%03d.class.png' % i,
                      'normal': 'o_%03d.normal.png' % i} for i in range(n)]}, open('views.json', 'w'))
PY
hyperfine --warmup 1 --runs "$runs" --export-json times.json \
  -n "render-canonical (depth)" "$vox render-canonical h.vdb -o r.exr --orbit $views --size $size --mode depth --threads $threads --quiet" \
  -n "fuse" "$vox fuse views.json -o f.vdb --threads $threads --quiet" \
  -n "fuse --carve none" "$vox fuse views.json -o fn.vdb --carve none --threads $threads --quiet" \
  -n "fuse --threads 1" "$vox fuse views.json -o f1.vdb --threads 1 --quiet" >&2
"$vox" fuse views.json -o f.vdb --threads "$threads" --quiet --report report.json
rss=$( (command -v /usr/bin/time >/dev/null && /usr/bin/time -f %M "$vox" fuse views.json -o f.vdb --threads "$threads" --quiet 2>&1 >/dev/null | tail -1) || echo "")
load=$(cut -d' ' -f1-3 /proc/loadavg)
python3 - "$res" "$views" "$size" "$threads" "$rss" "$load" "$out" <<'PY'
import json, sys
res, views, size, threads, rss, load, out = sys.argv[1:8]
t = json.load(open('times.json'))['results']
mean = {r['command']: r['mean'] for r in t}
sd = {r['command']: r['stddev'] or 0 for r in t}
rep = json.load(open('report.json'))
tot = rep['counts']['totals']
phases = {p['name']: p['seconds'] for p in rep['phases']}
touched = json.load(open('touched.json'))['voxels_touched']
lines = []
lines.append('# `vox fuse` benchmark\n')
lines.append('Produced by `scripts/bench_fuse.sh` (RES=%s VIEWS=%s SIZE=%s THREADS=%s): the demo hamlet at %s^3, '
             '%s orbit views of %s rendered with `--mode depth,class,normal`, fused back into an empty grid. '
             'Load average while it ran: %s (the machine is shared: wall times include waiting for a core).\n'
             % (res, views, size, threads, res, views, size, load))
lines.append('| command | mean s | stddev s |')
lines.append('| --- | ---: | ---: |')
for k in mean:
    lines.append('| `%s` | %.3f | %.3f |' % (k, mean[k], sd[k]))
lines.append('')
lines.append('* fuse / render-canonical (same views, same hyperfine run): **%.2fx** the time; votes only '
             '(`--carve none`): %.2fx' % (mean['fuse'] / mean['render-canonical (depth)'],
                                         mean['fuse --carve none'] / mean['render-canonical (depth)']))
lines.append('* rays (pixels with a depth and a class): %d of %d pixels; voxel steps per ray: %.1f; '
             'free counts: %d on %d voxels' % (tot['rays'], tot['pixels'], tot['steps_per_ray'], tot['free_counts'], tot['free_voxels']))
lines.append('* rays per second in the fuse phase (wall clock of `Fuser::add`, %s threads): **%.2f M rays/s**, %.0f M voxel steps/s'
             % (threads, tot['rays_per_second'] / 1e6, tot['rays_per_second'] * tot['steps_per_ray'] / 1e6))
lines.append('* phases (s): ' + ', '.join('%s %.3f' % (k, v) for k, v in phases.items()))
lines.append('* the fused scene: %d voxels = the %d voxels the renders touched; ambiguous pixels: %d'
             % (tot['occupied_after'], touched, tot['ambiguous']))
if rss:
    lines.append('* peak memory (max RSS, `/usr/bin/time -f %%M`): %.0f MB' % (int(rss) / 1024))
open(out, 'w').write('\n'.join(lines) + '\n')
print('\n'.join(lines))
PY
