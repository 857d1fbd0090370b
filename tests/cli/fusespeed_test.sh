#!/usr/bin/env bash
# vox fuse's speed work (docs/bench-fuse.md) end to end: the memory guard
# refuses a fusion over --max-memory (exit 4, nothing written), the second
# pass gives the same scene whether it reuses the decoded views or reads the
# images again, and views decoded ahead in parallel still fail in view order.
# Usage: fusespeed_test.sh GROUP VOX_BINARY
set -u
group=$1 vox=$2
# shellcheck source=test_lib.sh
. "$(dirname "$0")/test_lib.sh"

# N orbit views of SIZE of the demo hamlet at 64^3, and views.json for them.
render_views() {
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o h.vdb --quiet
  expect_exit 0 "$vox" render-canonical h.vdb -o o.png --orbit "$1" --size "$2" --mode depth,class,normal --quiet
  python3 - "$1" <<'PY'
import json, sys
n = int(sys.argv[1])
json.dump({'views': [{'depth': 'o_%03d.depth.exr' % i, 'label': 'o_%03d.class.png' % i,
                      'normal': 'o_%03d.normal.png' % i} for i in range(n)]}, open('views.json', 'w'))
PY
}

case $group in
memory)
  render_views 2 64x64
  expect_exit 4 "$vox" fuse views.json -o f.vdb --max-memory 20M --quiet
  expect_stderr "fusing 2 views of 64x64 into a 64 x 64 x 64 grid needs about"
  [ -e f.vdb ] && fail "a refused fusion wrote f.vdb"
  expect_exit 0 "$vox" fuse views.json -o f.vdb --quiet --report r.json
  jcheck r.json "c = [x for x in d['memory']['checks'] if x['what'].startswith('fusing 2 views')]; assert c and 'votes' in c[0]['parts'], d['memory']"
  # A setting the refusal suggests fits under the same limit (it once named
  # "--free voted --threads 1" at twice the limit): limits 1-20% under the
  # estimate, each suggestion run as given. A 128^3 grid, so that the settings
  # save more than the 1% the suggestions keep spare (8 MiB of free counts per
  # worker), also under the sanitizers' larger resident memory (540 MiB).
  expect_exit 0 "$vox" voxelize demo:hamlet --res 128 -o h128.vdb --quiet
  expect_exit 0 "$vox" render-canonical h128.vdb -o m.png --orbit 2 --size 64x64 --mode depth,class --quiet
  python3 -c "import json; json.dump({'views': [{'depth': 'm_%03d.depth.exr' % i, 'label': 'm_%03d.class.png' % i} for i in range(2)]}, open('m.json', 'w'))"
  expect_exit 4 "$vox" fuse m.json -o f.vdb --free all --threads 2 --max-memory 1M --quiet
  need=$(grep -o 'needs about [0-9.]* MiB' err.txt | grep -o '[0-9.]*' | head -1)
  [ -n "$need" ] || fail "no estimate in MiB: $(head -c 300 err.txt)"
  suggested=0
  for pct in 1 2 3 4 6 8 12 16 20; do
    limit=$(python3 -c "print('%dK' % int($need * 1024 * (100 - $pct) / 100))")
    "$vox" fuse m.json -o f.vdb --free all --threads 2 --max-memory "$limit" --quiet 2>err.txt && continue
    setting=$(grep -o ': [-a-z0-9 ]* would need about' err.txt | sed 's/^: //; s/ would need about$//')
    [ -n "$setting" ] || continue
    suggested=$((suggested + 1))
    threads=2 free=all words=()
    read -r -a words <<<"$setting"
    for ((k = 0; k + 1 < ${#words[@]}; k += 2)); do
      case ${words[k]} in --threads) threads=${words[k + 1]} ;; --free) free=${words[k + 1]} ;; *) fail "unexpected suggestion: $setting" ;; esac
    done
    expect_exit 0 "$vox" fuse m.json -o f.vdb --free "$free" --threads "$threads" --max-memory "$limit" --quiet
  done
  [ "$suggested" -gt 0 ] || fail "no refusal just under the estimate suggested a setting"
  rm -f f.vdb
  ;;
reuse)
  # 4 close-ups of 1024x1024 where every pixel walks keep 40.5 MiB (10 bytes a walked pixel and
  # 8 per 64 pixels); a 150M limit keeps at most 37.5 MiB (a quarter): the fourth view does not
  # fit and the second pass reads the images again.
  expect_exit 0 "$vox" voxelize demo:hamlet --res 64 -o h.vdb --quiet
  for t in 0 1 2 3; do
    expect_exit 0 "$vox" render-canonical h.vdb -o c$t.png --eye 0.1,12,0.3 --target "$((t % 2)),0,$((t / 2))" \
      --size 1024x1024 --mode depth,class,normal --quiet
  done
  python3 - <<'PY'
import json
json.dump({'views': [{'depth': 'c%d.depth.exr' % t, 'label': 'c%d.class.png' % t, 'normal': 'c%d.normal.png' % t}
                     for t in range(4)]}, open('views.json', 'w'))
PY
  expect_exit 0 "$vox" fuse views.json -o kept.vdb --threads 2 --quiet --report kept.json
  jcheck kept.json "assert all(v['used'] + v['skipped']['outside_grid'] == v['pixels'] for v in d['counts']['views']), 'a pixel does not walk'"
  jcheck kept.json "assert d['counts']['totals']['second_pass_views'] == 'kept'"
  expect_exit 0 "$vox" fuse views.json -o read.vdb --threads 1 --max-memory 150M --quiet --report read.json
  jcheck read.json "assert d['counts']['totals']['second_pass_views'] == 'read again'"
  expect_exit 0 "$vox" diff kept.vdb read.vdb
  # Byte for byte (the file's UUID is made from its content).
  cmp kept.vdb read.vdb >/dev/null || fail "kept and re-read views gave different bytes"
  render_views 4 512x512
  # Views of three sizes (a close-up where every pixel walks, an orbit view, the top view),
  # their distances read as z so that rays cross voted voxels before their hits: the kept
  # views carve as counting at every crossed voxel (--free all) does.
  expect_exit 0 "$vox" render-canonical h.vdb -o close.png --eye 0.1,12,0.3 --target 0,0,0 --size 200x150 \
    --mode depth,class,normal --quiet
  expect_exit 0 "$vox" render-canonical h.vdb -o top.png --view top --size 256x256 --mode depth,class,normal --quiet
  python3 - <<'PY'
import json
json.dump({'views': [{'depth': n + '.depth.exr', 'label': n + '.class.png', 'normal': n + '.normal.png'}
                     for n in ('close', 'o_001', 'top')]}, open('mixed.json', 'w'))
PY
  expect_exit 0 "$vox" fuse mixed.json -o mk.vdb --depth-kind z --threads 2 --quiet --report mk.json
  jcheck mk.json "t = d['counts']['totals']; assert t['second_pass_views'] == 'kept' and t['free_counts'] > 0, t"
  jcheck mk.json "v = d['counts']['views'][0]; assert v['used'] + v['skipped']['outside_grid'] == v['pixels'], v"
  expect_exit 0 "$vox" fuse mixed.json -o ma.vdb --depth-kind z --free all --threads 2 --quiet
  expect_exit 0 "$vox" diff mk.vdb ma.vdb
  ;;
loaderror)
  render_views 4 32x32
  python3 - <<'PY'
import json
v = json.load(open('views.json'))
v['views'][2]['label'] = 'missing2.png'
v['views'][3]['label'] = 'missing3.png'
json.dump(v, open('bad.json', 'w'))
PY
  for t in 1 2 4; do
    expect_exit 3 "$vox" fuse bad.json -o f.vdb --threads $t --quiet
    expect_stderr "views[2]"
    grep -qF "missing3" err.txt && fail "--threads $t: reported view 3 before view 2"
    [ -e f.vdb ] && fail "--threads $t: a failed fusion wrote f.vdb"
  done
  ;;
*)
  echo "unknown group $group" >&2
  exit 2
  ;;
esac
[ "$failures" = 0 ] || { echo "$failures failure(s) in fusespeed.$group" >&2; exit 1; }
echo "fusespeed.$group: ok"
