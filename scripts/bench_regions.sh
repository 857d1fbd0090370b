#!/usr/bin/env bash
# Region bakes against the single-process bake (docs/scale.md "Measured"):
# for each N, every region of `vox voxelize INPUT --region I/N` run one after
# the other (as a scheduler with one slot would), each under /usr/bin/time -v
# (wall, user + system CPU, peak RSS), then `vox merge` of the parts; the merged
# file is checked byte-identical (cmp) to the single-process bake's.
#
#   scripts/bench_regions.sh [VOX] [OUTDIR] -- INPUT-AND-OPTIONS...
#   e.g. scripts/bench_regions.sh build/bin/vox /tmp/rb -- demo:city --extent 2048,256,2048
#
# NS="1 2 4 8" picks the tile counts; THREADS (default 2) is passed to every run.
# Prints a Markdown table on stdout.
set -euo pipefail
vox=${1:-build/bin/vox}
out=${2:-/tmp/bench_regions}
shift 2 || true
[ "${1:-}" = "--" ] && shift
[ $# -gt 0 ] || { echo "usage: $0 VOX OUTDIR -- INPUT [OPTIONS...]" >&2; exit 2; }
vox=$(readlink -f "$vox")
threads=${THREADS:-2}
mkdir -p "$out"
cd "$out"

# timed NAME CMD...: runs CMD under /usr/bin/time -v; sets wall, cpu (user+sys, s) and rss (MiB).
timed() {
  local name=$1; shift
  /usr/bin/time -v "$@" 2> "$name.time" > /dev/null
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, t, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + t[i]; print s}' "$name.time")
  cpu=$(awk -F': ' '/User time/ {u = $2} /System time/ {s = $2} END {printf "%.2f", u + s}' "$name.time")
  rss=$(awk -F': ' '/Maximum resident/ {printf "%.0f", $2 / 1024}' "$name.time")
}

echo "| N | regions: wall sum [s] | CPU sum [s] | CPU / single | peak RSS max / min [MiB] | bound 1.5 x single / N + C [MiB] | merge wall [s] | merge CPU [s] | merge peak [MiB] | identical |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
timed single "$vox" voxelize "$@" -o single.vdb --threads "$threads" -q
singleWall=$wall singleCpu=$cpu singleRss=$rss
echo "| single | $singleWall | $singleCpu | 1.00 | $singleRss | - | - | - | - | - |"
baseline=$("$vox" --version > /dev/null; /usr/bin/time -v "$vox" voxelize demo:hamlet --res 8 -o tiny.vdb -q 2>&1 >/dev/null | awk -F': ' '/Maximum resident/ {printf "%.0f", $2 / 1024}')
for n in ${NS:-1 2 4 8}; do
  wallSum=0 cpuSum=0 rssMax=0 rssMin=999999999 parts=()
  for ((i = 0; i < n; i++)); do
    timed "r$n.$i" "$vox" voxelize "$@" --region "$i/$n" -o "p$n.$i.vdb" --threads "$threads" -q
    wallSum=$(echo "$wallSum + $wall" | bc -l) cpuSum=$(echo "$cpuSum + $cpu" | bc -l)
    [ "$rss" -gt "$rssMax" ] && rssMax=$rss
    [ "$rss" -lt "$rssMin" ] && rssMin=$rss
    parts+=("p$n.$i.vdb")
  done
  timed "m$n" "$vox" merge "${parts[@]}" -o "merged$n.vdb" --threads "$threads" -q
  same=no
  cmp -s single.vdb "merged$n.vdb" && same=yes
  bound=$(echo "1.5 * $singleRss / $n + $baseline" | bc -l)
  printf "| %d | %.2f | %.2f | %.2f | %d / %d | %.0f | %.2f | %.2f | %d | %s |\n" "$n" "$wallSum" "$cpuSum" \
    "$(echo "$cpuSum / $singleCpu" | bc -l)" "$rssMax" "$rssMin" "$bound" "$wall" "$cpu" "$rss" "$same"
  rm -f "${parts[@]}" "merged$n.vdb"
done
echo
echo "C = $baseline MiB: the peak RSS of a tiny bake (vox, its libraries, no scene). Single: $singleRss MiB peak, $(stat -c %s single.vdb) bytes."
