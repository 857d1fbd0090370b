#!/usr/bin/env bash
# Region bakes against the region count (docs/scale.md "Measured"): bakes
# demo:city at EXTENT as N regions, one after the other on this machine (a
# cluster would run them at once), packs each part, and merges the parts into
# the world's scene and page file. Per N it prints one Markdown row:
#   N | regions: largest CPU s, largest peak MiB | total CPU s | pack CPU s |
#   merge .vdb s, merge .vpk s (wall) | occupied voxels | part bytes per voxel |
#   world .vpk bytes | merge MB/s of .vpk output
# N = 1 is the single-process bake (no --region); when the memory guard
# refuses it, the row says so with the estimate.
# Usage: scripts/bench_scale.sh EXTENT "N..." [VOX]
#   e.g. scripts/bench_scale.sh 4096,512,4096 "1 2 4 8"
# Env: THREADS (default 2), KEEP=1 keeps the work directory (printed),
#      WORK=DIR puts it there (default: a temp dir on the disk of /tmp),
#      ONLY="I..." bakes and packs only those regions of each N (a world too
#      big for this machine's disk or afternoon: each part is deleted once
#      measured, nothing is merged) and prints one row per region instead.
#      SCENE_MERGE=0 skips `vox merge` (a world whose scene does not fit one
#      process: its page file is merged, its scene stays in parts), and then
#      each part's .vdb is deleted once packed and counted (disk).
set -u
extent=${1:?usage: bench_scale.sh EXTENT \"N...\" [VOX]}
counts=${2:?usage: bench_scale.sh EXTENT \"N...\" [VOX]}
vox=$(realpath "${3:-build/bin/vox}")
threads=${THREADS:-2}
[ -x "$vox" ] || { echo "bench_scale.sh: build vox first ($vox)" >&2; exit 4; }
work=${WORK:-$(mktemp -d)}
mkdir -p "$work"
[ "${KEEP:-0}" = 1 ] && echo "bench_scale.sh: work in $work" >&2 || trap 'rm -rf "$work"' EXIT
cd "$work" || exit 4

# timed OUT ARGS...: runs vox ARGS, writes "user+sys wall maxrss_kib" to OUT; returns vox's status.
timed() {
  local out=$1
  shift
  /usr/bin/time -f '%U %S %e %M' -o t.txt "$vox" "$@" --threads "$threads" -q 2>err.txt >/dev/null
  local rc=$?
  local u=0 s=0 e=0 m=0
  read -r u s e m <t.txt 2>/dev/null || true
  python3 -c "print($u + $s, $e, $m)" >"$out" 2>/dev/null || echo "0 0 0" >"$out"
  return $rc
}

if [ -n "${ONLY:-}" ]; then
  echo "| N | region | box | CPU s | wall s | peak MiB | occupied voxels | .vdb B/voxel | pack CPU s | pack peak MiB | .vpk B/voxel |"
  echo "|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|"
  for n in $counts; do
    for i in $ONLY; do
      [ "$i" -lt "$n" ] || continue
      if ! timed r.txt voxelize demo:city --extent "$extent" --region "$i/$n" -o part.vdb; then
        echo "| $n | $i | failed: $(head -c 200 err.txt) |"
        continue
      fi
      read -r c w m <r.txt
      timed p.txt pack-chunks part.vdb -o part.vpk || { echo "| $n | $i | pack failed: $(head -c 200 err.txt) |"; continue; }
      read -r pc pw pm <p.txt
      info=$("$vox" info part.vdb --json)
      occ=$(echo "$info" | python3 -c 'import json,sys; print(json.load(sys.stdin)["occupied"])')
      box=$(echo "$info" | python3 -c 'import json,sys; b=json.load(sys.stdin)["region"]["box"]; print("empty" if b is None else "%d..%d x %d..%d" % (b[0], b[3], b[2], b[5]))')
      printf '| %s | %s | %s | %.1f | %.1f | %s | %s | %.2f | %.1f | %s | %.2f |\n' "$n" "$i" "$box" "$c" "$w" \
        "$(python3 -c "print(f'{$m / 1024:,.0f}')")" "$(python3 -c "print(f'{$occ:,}')")" \
        "$(python3 -c "print($(stat -c %s part.vdb) / max($occ, 1))")" "$pc" "$(python3 -c "print(f'{$pm / 1024:,.0f}')")" \
        "$(python3 -c "print($(stat -c %s part.vpk) / max($occ, 1))")"
      rm -f part.vdb part.vpk
    done
  done
  echo
  echo "demo:city --extent $extent, --threads $threads, regions $ONLY only, load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
  exit 0
fi

echo "| N | largest region: CPU s / peak MiB | all regions: CPU s | pack parts: CPU s | merge .vdb: s | merge .vpk: s | occupied voxels | part .vdb B/voxel | world .vpk | merge .vpk MB/s |"
echo "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for n in $counts; do
  rm -f part-*.vdb part-*.vpk part-*.count world.vdb world.vpk
  maxcpu=0 maxrss=0 totcpu=0 packcpu=0 failed=""
  for ((i = 0; i < n; i++)); do
    region=(--region "$i/$n")
    [ "$n" = 1 ] && region=()
    if ! timed r.txt voxelize demo:city --extent "$extent" "${region[@]}" -o part-$i.vdb; then
      failed=$(head -c 300 err.txt)
      break
    fi
    read -r c w m <r.txt
    totcpu=$(python3 -c "print($totcpu + $c)")
    maxcpu=$(python3 -c "print(max($maxcpu, $c))")
    maxrss=$(python3 -c "print(max($maxrss, $m))")
    timed p.txt pack-chunks part-$i.vdb -o part-$i.vpk || { failed=$(head -c 300 err.txt); break; }
    read -r c w m <p.txt
    packcpu=$(python3 -c "print($packcpu + $c)")
    if [ "${SCENE_MERGE:-1}" = 0 ]; then
      echo "$("$vox" info part-$i.vdb --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["occupied"])') $(stat -c %s part-$i.vdb)" >part-$i.count
      rm -f part-$i.vdb
    fi
  done
  if [ -n "$failed" ]; then
    echo "| $n | refused or failed: $(echo "$failed" | tr '|' '/') | | | | | | | | |"
    continue
  fi
  occ=0 partbytes=0
  for ((i = 0; i < n; i++)); do
    if [ -f part-$i.count ]; then
      read -r o b <part-$i.count
    else
      o=$("$vox" info part-$i.vdb --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["occupied"])')
      b=$(stat -c %s part-$i.vdb)
    fi
    occ=$((occ + o))
    partbytes=$((partbytes + b))
  done
  if [ "$n" = 1 ]; then
    mv part-0.vpk world.vpk
    mergevdb=- mergevpk=- mbs=-
  else
    if [ "${SCENE_MERGE:-1}" = 0 ]; then
      echo "- skipped" >mv.txt
    else
      timed mv.txt merge part-*.vdb -o world.vdb || { echo "| $n | merge failed: $(head -c 200 err.txt) |"; continue; }
    fi
    timed mp.txt pack-chunks --merge part-*.vpk -o world.vpk || { echo "| $n | page merge failed: $(head -c 200 err.txt) |"; continue; }
    mergevdb=$(cut -d' ' -f2 mv.txt)
    mergevpk=$(cut -d' ' -f2 mp.txt)
    mbs=$(python3 -c "print(f'{$(stat -c %s world.vpk) / 1e6 / max($mergevpk, 1e-9):.0f}')")
  fi
  # Every N gives the same world: the page file's digest says so.
  sum=$(sha256sum world.vpk | cut -c1-12)
  printf '| %s | %.1f / %s | %.1f | %.1f | %s | %s | %s | %.2f | %s MB (%s) | %s |\n' "$n" "$maxcpu" \
    "$(python3 -c "print(f'{$maxrss / 1024:,.0f}')")" "$totcpu" "$packcpu" "$mergevdb" "$mergevpk" \
    "$(python3 -c "print(f'{$occ:,}')")" "$(python3 -c "print($partbytes / max($occ, 1))")" \
    "$(python3 -c "print(f'{$(stat -c %s world.vpk) / 1e6:,.0f}')")" "sha256 $sum" "$mbs"
done
echo
echo "demo:city --extent $extent, --threads $threads, load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
