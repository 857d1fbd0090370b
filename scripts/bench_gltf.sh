#!/bin/sh
# glTF read speed (docs/gltf.md#performance), one run on this machine:
#  * parse+decode throughput of a GLB (file bytes and triangles / the `parse`
#    phase of `vox voxelize --report`, plus the `voxelize` phase of the
#    --res 8 bake when the colour images decode during it (counts.texture_decode),
#    median of 3): a plain 240 k-triangle
#    model, the same Draco-compressed (Debian's draco_transcoder, its default
#    quantization), and the textured 15 k-triangle model (five 2048^2 JPEG
#    base-colour textures), on one thread and on all of them;
#  * `vox voxelize --res 256` of the textured 15 k-triangle model against the
#    same model with its textures removed, in one hyperfine run (the ratio),
#    and the textured run's phases with its decoding time (the images are
#    read by rows inside the voxelize phase, after the geometry: docs/gltf.md),
#    and both bakes' peak memory (/usr/bin/time).
# Needs oiiotool (openimageio-tools), draco_transcoder (draco), hyperfine.
# Usage: scripts/bench_gltf.sh [BUILD_DIR]   -> Markdown on stdout
set -eu
cd "$(dirname "$0")/.."
root=$(pwd)
VOX=$root/${1:-build}/bin/vox
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
all=$(nproc)

for i in 0 1 2 3 4; do  # photo-like JPEGs: blurred noise, about 1.6 MB each
  oiiotool --pattern noise:type=uniform:min=0:max=1:seed=$i 2048x2048 3 --blur 9x9 -d uint8 -o t$i.jpg
done
python3 "$root/bench/make_textured_glb.py" textured.glb plain.glb t0.jpg t1.jpg t2.jpg t3.jpg t4.jpg
python3 "$root/bench/make_textured_glb.py" --plain big.glb 400 300
draco_transcoder -i big.glb -o big-draco.glb >/dev/null

echo "### Parse + decode throughput (median of 3; MB/s of the file, M triangles/s)"
echo
echo "| file | size [MB] | triangles | 1 thread | $all threads |"
echo "|---|---:|---:|---:|---:|"
for f in big.glb big-draco.glb textured.glb; do
  line="| $f | $(python3 -c "import os; print(f'{os.path.getsize(\"$f\")/1e6:.2f}')")"
  for t in 1 "$all"; do
    for r in 1 2 3; do
      "$VOX" voxelize "$f" --res 8 -o p.vdb -q --threads "$t" --report "p$r.json"
    done
    [ "$t" = 1 ] && line="$line | $(python3 -c "import json; print(json.load(open('p1.json'))['counts']['triangles'])")"
    line="$line | $(python3 -c "
import json, os
d = [json.load(open(f'p{r}.json')) for r in (1, 2, 3)]
# Images decoded during the bake: at --res 8 its voxelize phase is that decoding.
s = sorted([sum(p['seconds'] for p in j['phases']
                if p['name'] == 'parse' or (p['name'] == 'voxelize' and 'texture_decode' in j['counts']))
            for j in d])[1]
print(f'{s * 1000:.0f} ms: {os.path.getsize(\"$f\") / 1e6 / s:.0f} MB/s, {d[0][\"counts\"][\"triangles\"] / 1e6 / s:.1f} M tri/s')")"
  done
  echo "$line |"
done
echo

echo "### Textured against untextured, --res 256, $all threads"
echo
hyperfine -N --warmup 1 --runs 7 --export-json v.json --export-markdown v.md \
  -n "textured (5 x 2048^2 JPEG)" "$VOX voxelize textured.glb --res 256 -o a.vdb -q --threads $all" \
  -n "textures removed" "$VOX voxelize plain.glb --res 256 -o b.vdb -q --threads $all" >/dev/null
cat v.md
python3 -c "
import json
r = json.load(open('v.json'))['results']
print(f'\nratio textured / untextured: wall {r[0][\"mean\"] / r[1][\"mean\"]:.2f} (target <= 1.5), '
      f'CPU (user + system) {(r[0][\"user\"] + r[0][\"system\"]) / (r[1][\"user\"] + r[1][\"system\"]):.2f}')"
"$VOX" voxelize textured.glb --res 256 -o a.vdb -q --threads "$all" --report t.json
python3 -c "
import json
j = json.load(open('t.json'))
ph = {p['name']: p['seconds'] for p in j['phases']}
d = j['counts'].get('texture_decode', {})
print(f'textured run: parse {ph[\"parse\"] * 1000:.0f} ms, voxelize {ph[\"voxelize\"] * 1000:.0f} ms (of which the '
      f'images read by rows after the geometry: {d.get(\"decode_seconds\", 0) * 1000:.0f} ms of decoding, summed over '
      f'the images), write {ph[\"write\"] * 1000:.0f} ms')"
if [ -x /usr/bin/time ]; then
  peak() { /usr/bin/time -f %M "$VOX" voxelize "$1" --res 256 -o m.vdb -q --threads "$all" 2>&1 >/dev/null | tail -1; }
  echo "peak memory (/usr/bin/time): textured $(( $(peak textured.glb) / 1024 )) MB, textures removed $(( $(peak plain.glb) / 1024 )) MB"
fi
echo "load average while measuring: $(cut -d' ' -f1-3 /proc/loadavg) on $all cores"
