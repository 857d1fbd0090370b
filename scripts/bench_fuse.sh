#!/usr/bin/env bash
# Benchmarks `vox fuse` (docs/fuse.md): rays per second and voxel steps per
# ray when fusing VIEWS orbit renders (depth, class, normal) of the demo
# hamlet back into its grid (carving with free counts at voted voxels, the default; at every
# crossed voxel, --free all; votes only, --carve none), against render-canonical casting the same views
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
  -n "fuse --free all" "$vox fuse views.json -o fa.vdb --free all --threads $threads --quiet" \
  -n "fuse --carve none" "$vox fuse views.json -o fn.vdb --carve none --threads $threads --quiet" \
  -n "fuse --threads 1" "$vox fuse views.json -o f1.vdb --threads 1 --quiet" >&2
"$vox" fuse views.json -o f.vdb --threads "$threads" --quiet --report report.json
"$vox" fuse views.json -o fa.vdb --free all --threads "$threads" --quiet --report report_all.json
"$vox" diff f.vdb fa.vdb >/dev/null || { echo "bench_fuse.sh: --free voted and --free all gave different scenes" >&2; exit 1; }
rss=$( (command -v /usr/bin/time >/dev/null && /usr/bin/time -f %M "$vox" fuse views.json -o f.vdb --threads "$threads" --quiet 2>&1 >/dev/null | tail -1) || echo "")
load=$(cut -d' ' -f1-3 /proc/loadavg)
python3 - "$res" "$views" "$size" "$threads" "$rss" "$load" "$out" <<'PY'
import json, sys
res, views, size, threads, rss, load, out = sys.argv[1:8]
t = json.load(open('times.json'))['results']
mean = {r['command']: r['mean'] for r in t}
sd = {r['command']: r['stddev'] or 0 for r in t}
cpu = {r['command']: r['user'] + r['system'] for r in t}
repAll = json.load(open('report_all.json'))['counts']['totals']
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
lines.append('| command | mean s (wall) | stddev s | CPU s (user + sys) |')
lines.append('| --- | ---: | ---: | ---: |')
for k in mean:
    lines.append('| `%s` | %.3f | %.3f | %.3f |' % (k, mean[k], sd[k], cpu[k]))
lines.append('')
rc = 'render-canonical (depth)'
lines.append('* fuse / render-canonical (same views, same hyperfine run): **%.2fx** the wall time, %.2fx the CPU time; '
             '`--free all` (every crossed voxel counted): %.2fx wall, %.2fx CPU; votes only (`--carve none`): %.2fx wall, %.2fx CPU'
             % (mean['fuse'] / mean[rc], cpu['fuse'] / cpu[rc], mean['fuse --free all'] / mean[rc],
                cpu['fuse --free all'] / cpu[rc], mean['fuse --carve none'] / mean[rc], cpu['fuse --carve none'] / cpu[rc]))
lines.append('* `--free voted` / `--free all`: %.2fx the wall time, %.2fx the CPU time; both give the same scene (`vox diff`)'
             % (mean['fuse'] / mean['fuse --free all'], cpu['fuse'] / cpu['fuse --free all']))
lines.append('* rays (pixels with a depth and a class): %d of %d pixels; free counts kept (`--free voted`): %d on %d voxels'
             % (tot['rays'], tot['pixels'], tot['free_counts'], tot['free_voxels']))
lines.append('* rays per second in the fuse phase (wall clock of both passes, %s threads): **%.2f M rays/s** '
             '(%.1f steps per ray, both passes); `--free all`: %.2f M rays/s (%.1f steps per ray), %d free counts on %d voxels'
             % (threads, tot['rays_per_second'] / 1e6, tot['steps_per_ray'], repAll['rays_per_second'] / 1e6,
                repAll['steps_per_ray'], repAll['free_counts'], repAll['free_voxels']))
lines.append('* phases (s): ' + ', '.join('%s %.3f' % (k, v) for k, v in phases.items()))
lines.append('* the fused scene: %d voxels = the %d voxels the renders touched; ambiguous pixels: %d'
             % (tot['occupied_after'], touched, tot['ambiguous']))
if rss:
    lines.append('* peak memory (max RSS, `/usr/bin/time -f %%M`): %.0f MB' % (int(rss) / 1024))
open(out, 'w').write('\n'.join(lines) + '\n')
print('\n'.join(lines))
PY
