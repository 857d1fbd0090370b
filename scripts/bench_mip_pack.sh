#!/usr/bin/env bash
# Benchmarks `vox mip` against OpenVDB's vdb_lod and `vdb_tool -multires` (Debian
# libopenvdb-tools) on the same voxels (vdb_tool reduces float grids only, so it
# gets the scene's `vox export --fog` volume: the same active voxels), and `vox pack-chunks` against just loading the scene
# (`vox info`), with hyperfine; every ratio comes from one hyperfine run.
# Writes the markdown results to docs/bench-mip-pack.md (or $OUT).
#
# Usage: scripts/bench_mip_pack.sh [MESH]   (default: the Stanford bunny of ../shared/data)
# Env: BUILD_DIR (default build), THREADS (default: all cores), RUNS (default 5).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
vox=$root/${BUILD_DIR:-build}/bin/vox
mesh=${1:-$root/../shared/data/common-3d-test-models/stanford-bunny.obj}
threads=${THREADS:-$(nproc)}
runs=${RUNS:-5}
out=${OUT:-$root/docs/bench-mip-pack.md}
for tool in hyperfine vdb_lod vdb_tool python3; do
  command -v $tool >/dev/null || { echo "bench_mip_pack.sh: needs $tool (apt-get install hyperfine libopenvdb-tools)" >&2; exit 4; }
done
[ -x "$vox" ] || { echo "bench_mip_pack.sh: build vox first ($vox)" >&2; exit 4; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

echo "== scenes" >&2
"$vox" voxelize demo:hamlet --res 256 -o hamlet256.vdb --quiet
scenes="hamlet256"
if [ -f "$mesh" ]; then
  "$vox" voxelize "$mesh" --res 1024 -o mesh1024.vdb --quiet
  scenes="$scenes mesh1024"
fi

# Every layout `vox pack-chunks --layout` knows (its help lists the layout table).
layouts=$("$vox" pack-chunks --help | sed -n 's/.*--layout \([a-z|]*\)=.*/\1/p' | tr '|' ' ')
export LAYOUTS="$layouts"
results=$work/results.jsonl
: > "$results"
for s in $scenes; do
  levels=$("$vox" info --json $s.vdb | python3 -c "import json,sys,math; d=json.load(sys.stdin); print(math.ceil(math.log2(max(d['dims']))))")
  echo "== mip $s (levels 1..$levels)" >&2
  "$vox" export $s.vdb --fog -o fog_$s.vdb --quiet
  hyperfine --warmup 1 --runs "$runs" --export-json mip_$s.json \
    -n "vox mip" "$vox mip $s.vdb -o m.vdb --levels $levels --threads $threads --quiet" \
    -n "vdb_lod" "vdb_lod $s.vdb l.vdb -range 0-$levels" \
    -n "vdb_tool -multires" "vdb_tool -read fog_$s.vdb -multires levels=$levels -write t.vdb" >&2
  echo "== pack $s" >&2
  hyperfine --warmup 1 --runs "$runs" --export-json pack_$s.json \
    -n "vox info (load)" "$vox info $s.vdb" \
    -n "vox pack-chunks" "$vox pack-chunks $s.vdb -o p.vpk --threads $threads --quiet" \
    -n "vox pack-chunks --mips" "$vox pack-chunks $s.vdb -o pm.vpk --mips --threads $threads --quiet" >&2
  "$vox" pack-chunks $s.vdb -o p.vpk --threads "$threads" --quiet --report pack_report_$s.json
  "$vox" pack-chunks $s.vdb -o p8.vpk --chunk 8 --align 64 --threads "$threads" --quiet --report pack8_report_$s.json
  for layout in $layouts; do
    "$vox" pack-chunks $s.vdb -o l.vpk --layout $layout --threads "$threads" --quiet --report layout_${layout}16_$s.json
    "$vox" pack-chunks $s.vdb -o l.vpk --layout $layout --chunk 8 --align 64 --threads "$threads" --quiet --report layout_${layout}8_$s.json
    "$vox" pack-chunks --verify l.vpk --quiet
  done
  "$vox" info --json $s.vdb > info_$s.json
  "$vox" mip $s.vdb -o m.vdb --threads "$threads" --quiet --report mip_report_$s.json
  python3 - "$s" >> "$results" <<'PY'
import json, os, sys
s = sys.argv[1]
mip = {r["command"]: r for r in json.load(open(f"mip_{s}.json"))["results"]}
pack = {r["command"]: r for r in json.load(open(f"pack_{s}.json"))["results"]}
rep = json.load(open(f"pack_report_{s}.json"))["counts"]
rep8 = json.load(open(f"pack8_report_{s}.json"))["counts"]
info = json.load(open(f"info_{s}.json"))
mr = json.load(open(f"mip_report_{s}.json"))
print(json.dumps({
  "scene": s, "dims": info["dims"], "occupied": info["occupied"], "vdb_bytes": info["file_bytes"],
  "mip_vox": mip["vox mip"]["mean"], "mip_vox_sd": mip["vox mip"]["stddev"],
  "mip_lod": mip["vdb_lod"]["mean"], "mip_lod_sd": mip["vdb_lod"]["stddev"],
  "mip_tool": mip["vdb_tool -multires"]["mean"], "mip_tool_sd": mip["vdb_tool -multires"]["stddev"],
  "mip_phases": mr["phases"], "pyramid_bytes": os.path.getsize("m.vdb"), "lod_bytes": os.path.getsize("l.vdb"),
  "info": pack["vox info (load)"]["mean"], "pack": pack["vox pack-chunks"]["mean"],
  "pack_mips": pack["vox pack-chunks --mips"]["mean"],
  "vpk_bytes": rep["file_bytes"], "bpv": rep["bytes_per_voxel"], "chunks": rep["chunks"], "align": rep["align"],
  "pack_core_s": rep["pack_seconds"], "pack_phases": json.load(open(f"pack_report_{s}.json"))["phases"],
  "vpk8_bytes": rep8["file_bytes"], "bpv8": rep8["bytes_per_voxel"],
  "layouts": [dict(layout=l, chunk=c, **{k: r[k] for k in ("file_bytes", "voxels", "chunks", "bytes_per_voxel", "pack_seconds", "align")},
                   payload_bytes=sum(x["payload_bytes"] for x in r["levels"]))
              for l in os.environ["LAYOUTS"].split() for c in (16, 8)
              for r in [json.load(open(f"layout_{l}{c}_{s}.json"))["counts"]]],
}))
PY
done

# Hand-written notes below the "<!-- notes -->" line of an existing $out are kept.
notes=$work/notes.md
if [ -f "$out" ] && grep -q '^<!-- notes -->' "$out"; then sed -n '/^<!-- notes -->/,$p' "$out" > "$notes"; else : > "$notes"; fi
python3 - "$results" "$threads" "$runs" "$mesh" "$notes" > "$out" <<'PY'
import json, sys, subprocess, platform
rows = [json.loads(l) for l in open(sys.argv[1])]
threads, runs, mesh = sys.argv[2], sys.argv[3], sys.argv[4]
cpu = subprocess.run("lscpu | grep 'Model name' | sed 's/.*: *//'", shell=True, capture_output=True, text=True).stdout.strip()
p = print
p("# `vox mip` and `vox pack-chunks`: measurements\n")
p(f"Produced by `scripts/bench_mip_pack.sh` (hyperfine, {runs} runs after a warm-up, `--threads {threads}`;")
p(f"vdb_lod uses TBB on every core, which is the same {threads} here). Machine: {cpu}, {platform.system()}.")
p(f"Scenes: `vox voxelize demo:hamlet --res 256` and `vox voxelize {mesh.split('/')[-1]} --res 1024` (surface).")
p("Every ratio compares commands timed in the same hyperfine run. Times are whole processes")
p("(start, read the .vdb, work, write).\n")
p("## `vox mip` against `vdb_lod` and `vdb_tool -multires`\n")
p("vox mip and vdb_lod read the same scene file and write every level from 0 to one voxel")
p("into one .vdb. vdb_lod processes the int32 `votes.<id>` grids (it skips the bool")
p("`occupancy` grid, an unsupported type) with OpenVDB's MultiResGrid restriction; vox mip")
p("reduces occupancy, votes (exact sums) and colour, so it does strictly more work per level.")
p("`vdb_tool -multires` (the same MultiResGrid) takes float grids only, so it reads the")
p("scene's `vox export --fog` volume (one float grid, the same active voxels) and writes")
p("levels 1 to one voxel.\n")
p("| scene | dims | occupied | vox mip (s) | vdb_lod (s) | vdb_lod / vox mip | vdb_tool -multires (s) | vdb_tool / vox mip | pyramid .vdb | vdb_lod .vdb |")
p("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
for r in rows:
    p(f"| {r['scene']} | {'x'.join(map(str, r['dims']))} | {r['occupied']:,} | {r['mip_vox']:.3f} ± {r['mip_vox_sd']:.3f} | "
      f"{r['mip_lod']:.3f} ± {r['mip_lod_sd']:.3f} | **{r['mip_lod'] / r['mip_vox']:.2f}x** | "
      f"{r['mip_tool']:.3f} ± {r['mip_tool_sd']:.3f} | **{r['mip_tool'] / r['mip_vox']:.2f}x** | {r['pyramid_bytes'] / 1e6:.1f} MB | {r['lod_bytes'] / 1e6:.1f} MB |")
p("\nPhases of one `vox mip --report` run (seconds):\n")
for r in rows:
    p(f"* {r['scene']}: " + ", ".join(f"{ph['name']} {ph['seconds']:.3f}" for ph in r["mip_phases"]))
p("\n## `vox pack-chunks` against loading the scene\n")
p("Target: packing (bricks, C = 16, the default `--align auto`, level 0) costs at most 2x the time of")
p("just loading the scene (`vox info`, which reads and checks the .vdb and counts its voxels).\n")
p("| scene | .vdb | vox info (s) | pack-chunks (s) | pack / info | pack --mips (s) | .vpk (C=16, auto) | bytes/voxel | .vpk (C=8, 64 B) | bytes/voxel | pack core MB/s |")
p("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
for r in rows:
    p(f"| {r['scene']} | {r['vdb_bytes'] / 1e6:.2f} MB | {r['info']:.3f} | {r['pack']:.3f} | **{r['pack'] / r['info']:.2f}x** | {r['pack_mips']:.3f} | "
      f"{r['vpk_bytes'] / 1e6:.2f} MB ({r['align']} B) | {r['bpv']:.2f} | {r['vpk8_bytes'] / 1e6:.2f} MB | {r['bpv8']:.2f} | {r['vpk_bytes'] / 1e6 / r['pack_core_s']:.0f} |")
p("\n\"pack core MB/s\" is the page file's size over the time of the chunking itself (the")
p("`pack_seconds` of `--report`, without reading the .vdb). Phases of one run (seconds):\n")
for r in rows:
    p(f"* {r['scene']}: " + ", ".join(f"{ph['name']} {ph['seconds']:.3f}" for ph in r["pack_phases"]))
p("\n## Layouts: bytes per occupied voxel\n")
p("`vox pack-chunks --layout L` of each scene (level 0 only), C = 16 with the default `--align auto`")
p("(the alignment it chose in brackets) and C = 8 with 64-byte alignment (formats/pagefile/PAGEFILE.md). \"file\" counts the whole")
p(".vpk (header, index, metadata, alignment padding); \"payload\" only the chunk payloads. svo")
p("payloads include the mip bricks of the inner nodes (C = 16 and 32); columns payloads the mip")
p("ladder. Pack time is the chunking alone (`pack_seconds` of `--report`), one run.\n")
p("| scene | layout | C, alignment | chunks | .vpk | file bytes/voxel | payload bytes/voxel | pack (s) |")
p("| --- | --- | --- | ---: | ---: | ---: | ---: | ---: |")
for r in rows:
    for l in r["layouts"]:
        al = f"auto ({l['align']} B)" if l["chunk"] == 16 else "64 B"
        p(f"| {r['scene']} | {l['layout']} | {l['chunk']}, {al} | {l['chunks']:,} | {l['file_bytes'] / 1e6:.2f} MB | "
          f"**{l['bytes_per_voxel']:.2f}** | {l['payload_bytes'] / l['voxels']:.2f} | {l['pack_seconds']:.3f} |")
notes = open(sys.argv[5]).read()
if notes:
    p("")
    p(notes.rstrip("\n"))
PY
echo "wrote $out" >&2
