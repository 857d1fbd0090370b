#!/usr/bin/env bash
# Benchmarks `vox fuse` (docs/fuse.md): rays per second and voxel steps per
# ray when fusing VIEWS orbit renders (depth, class, normal) of the demo
# hamlet back into its grid (carving with free counts at voted voxels, the default; at every
# crossed voxel, --free all; votes only, --carve none), against render-canonical casting the same views
# (the ratio comes from one hyperfine run), and the fused scene's peak memory.
# Writes markdown to docs/bench-fuse.md (or $OUT), keeping what an existing
# file holds from its "<!-- notes -->" line on.
#
# Usage: scripts/bench_fuse.sh
# Env: BUILD_DIR (default build), RES (grid side, default 256), VIEWS (default 16),
#      SIZE (default 512x512), THREADS (default: all cores), RUNS (default 3),
#      OLD_VOX (another vox binary, e.g. one built from an earlier commit: its
#      `fuse` and `fuse --threads 1` run in the same hyperfine run, and the
#      scenes must be byte-identical but the file UUID).
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
old=()
if [ -n "${OLD_VOX:-}" ]; then
  old=(-n "fuse (old binary)" "$OLD_VOX fuse views.json -o fo.vdb --threads $threads --quiet"
       -n "fuse --threads 1 (old binary)" "$OLD_VOX fuse views.json -o fo1.vdb --threads 1 --quiet")
fi
hyperfine --warmup 1 --runs "$runs" --export-json times.json "${old[@]}" \
  -n "render-canonical (depth)" "$vox render-canonical h.vdb -o r.exr --orbit $views --size $size --mode depth --threads $threads --quiet" \
  -n "fuse" "$vox fuse views.json -o f.vdb --threads $threads --quiet" \
  -n "fuse --free all" "$vox fuse views.json -o fa.vdb --free all --threads $threads --quiet" \
  -n "fuse --carve none" "$vox fuse views.json -o fn.vdb --carve none --threads $threads --quiet" \
  -n "fuse --threads 1" "$vox fuse views.json -o f1.vdb --threads 1 --quiet" >&2
"$vox" fuse views.json -o f.vdb --threads "$threads" --quiet --report report.json
"$vox" fuse views.json -o fa.vdb --free all --threads "$threads" --quiet --report report_all.json
"$vox" diff f.vdb fa.vdb >/dev/null || { echo "bench_fuse.sh: --free voted and --free all gave different scenes" >&2; exit 1; }
if [ -n "${OLD_VOX:-}" ]; then
  "$OLD_VOX" fuse views.json -o fo.vdb --threads "$threads" --quiet --report report_old.json
  # Byte for byte but the OpenVDB file's UUID (bytes 22-57).
  cmp -i 57 f.vdb fo.vdb || { echo "bench_fuse.sh: the old binary's scene differs" >&2; exit 1; }
fi
rss=$( (command -v /usr/bin/time >/dev/null && /usr/bin/time -f %M "$vox" fuse views.json -o f.vdb --threads "$threads" --quiet 2>&1 >/dev/null | tail -1) || echo "")
load=$(cut -d' ' -f1-3 /proc/loadavg)
oldrss=""
[ -n "${OLD_VOX:-}" ] && oldrss=$( (command -v /usr/bin/time >/dev/null && /usr/bin/time -f %M "$OLD_VOX" fuse views.json -o fo.vdb --threads "$threads" --quiet 2>&1 >/dev/null | tail -1) || echo "")
python3 - "$res" "$views" "$size" "$threads" "$rss" "$load" "$out" "$oldrss" <<'PY'
import json, os, sys
res, views, size, threads, rss, load, out, oldrss = sys.argv[1:9]
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
    lines.append('* peak memory (max RSS, `/usr/bin/time -f %%M`): %.0f MB' % (int(rss) / 1024)
                 + (' (old binary: %.0f MB)' % (int(oldrss) / 1024) if oldrss else ''))
if 'fuse (old binary)' in mean:
    o = json.load(open('report_old.json'))['counts']['totals']
    lines.append('* against the old binary (same hyperfine run; byte-identical scenes): `fuse` %.2fx faster in wall time '
                 '(%.3f s -> %.3f s), %.2fx in CPU time; `--threads 1` %.2fx wall, %.2fx CPU; rays per second in the fuse phase '
                 '%.2f M -> %.2f M (%.2fx; one run each, wall clock)'
                 % (mean['fuse (old binary)'] / mean['fuse'], mean['fuse (old binary)'], mean['fuse'],
                    cpu['fuse (old binary)'] / cpu['fuse'],
                    mean['fuse --threads 1 (old binary)'] / mean['fuse --threads 1'],
                    cpu['fuse --threads 1 (old binary)'] / cpu['fuse --threads 1'],
                    o['rays_per_second'] / 1e6, tot['rays_per_second'] / 1e6, tot['rays_per_second'] / o['rays_per_second']))
# Hand-written notes from the "<!-- notes -->" line of an existing output on are kept.
notes = ''
if os.path.exists(out):
    old = open(out).read().split('\n')
    if '<!-- notes -->' in old:
        notes = '\n' + '\n'.join(old[old.index('<!-- notes -->'):])
open(out, 'w').write('\n'.join(lines) + '\n' + notes)
print('\n'.join(lines))
PY
