#!/usr/bin/env bash
# Refactoring guard: bakes every kind of artefact `vox` writes (scenes from the
# demo, a block map, meshes of every reader, an OpenVDB grid; atlases, bitmaps,
# pyramids, page files of every layout, renders of every mode, touched sets,
# `info --json`) into one directory, so that two builds can be compared byte
# for byte.
#
#   scripts/snapshot_outputs.sh VOX DIR          # bake into DIR (made empty first)
#   scripts/snapshot_outputs.sh --compare VOX A B # compare two snapshots; exit 1 if they differ
#
# Files are compared with cmp. `.vdb` files written through OpenVDB carry a
# random UUID, so where their bytes differ they are compared with `VOX diff`
# (every voxel, vote, colour, flag and the header, sources included) instead.
# Reports and depfiles hold timings and paths and are left out. Meshes come from
# ../shared/data when it is present (skipped with a message otherwise).
set -u

if [ "${1:-}" = --compare ]; then
  vox=$2 a=$3 b=$4 bad=0 n=0
  while IFS= read -r f; do
    n=$((n + 1))
    if [ ! -e "$b/$f" ]; then echo "only in $a: $f"; bad=1; continue; fi
    cmp -s "$a/$f" "$b/$f" && continue
    case $f in
      *.vdb) "$vox" diff "$a/$f" "$b/$f" >/dev/null 2>&1 && continue ;;
    esac
    echo "differs: $f"; bad=1
  done < <(cd "$a" && find . -type f ! -name '*.report.json' ! -name '*.d' ! -name '*.log' ! -path './in/*' | sort)
  extra=$(cd "$b" && find . -type f ! -name '*.report.json' ! -name '*.d' ! -name '*.log' ! -path './in/*' | sort | while read -r f; do [ -e "$a/$f" ] || echo "$f"; done)
  [ -n "$extra" ] && { echo "only in $b: $extra"; bad=1; }
  echo "compared $n files: $([ $bad = 0 ] && echo identical || echo DIFFERENT)"
  exit $bad
fi

vox=$(realpath "$1") out=$2
here=$(cd "$(dirname "$0")/.." && pwd)
data=$(realpath -m "${VOX_DATA:-$here/../shared/data}")  # one spelling, whichever checkout runs
rm -rf "$out"; mkdir -p "$out"; cd "$out" || exit 4
# Inputs by relative path: scenes record their sources' paths.
mkdir -p in && cp "$here/scripts/demo/village_map.json" "$here/scripts/demo/village_cameras.json" in/
log=run.log
run() { echo "+ $*" >>"$log"; "$vox" "$@" >>"$log" 2>&1 || echo "exit $? from: vox $*" | tee -a "$log" >&2; }
cam="--eye 20,15,20 --target 0,2,0 --fov 40 --size 160x90"

# Scenes
run voxelize demo:hamlet --res 64 -o hamlet64.vdb
run voxelize demo:hamlet --res 256 -o hamlet256.vdb
run voxelize in/village_map.json -o village.vdb
meshes=()
if [ -d "$data" ]; then
  run voxelize "$data/cuda_voxelizer/bunny.OBJ" --res 128 -o bunny.vdb
  run voxelize "$data/cuda_voxelizer/bunny.OBJ" --res 128 --fill solid -o bunny_solid.vdb
  run voxelize "$data/common-3d-test-models/fandisk.obj" --res 96 --fill solid -o fandisk.vdb
  run voxelize "$data/common-3d-test-models/beetle.obj" --res 96 --fill solid --ignore-missing-materials -o beetle.vdb
  run voxelize "$data/common-3d-test-models/spot.obj" --res 64 -o spot.vdb
  run voxelize "$data/cgal-data/pig.stl" --res 64 --fill solid -o pig.vdb
  run voxelize "$data/mesh-misc/assimp/Wuson.ply" --res 64 -o wuson.vdb
  run voxelize "$data/mesh-misc/assimp/float-color.ply" --res 16 -o floatcolor.vdb
  run voxelize "$data/mesh-misc/assimp/cube_with_vertexcolors.obj" --res 16 -o vcolor.vdb
  run voxelize "$data/mesh-misc/assimp/spider.obj" --res 64 -o spider.vdb
  run voxelize "$data/gltf/assimp/BoxTextured-glTF-Binary/BoxTextured.glb" --res 32 -o boxtex.vdb
  run voxelize "$data/gltf/assimp/2CylinderEngine-glTF-Binary/2CylinderEngine.glb" --res 96 -o engine.vdb
  run voxelize "$data/gltf/tinygltf/Cube-texture-ext/Cube-textransform.gltf" --res 16 -o cubetex.vdb
  run voxelize "$data/common-3d-test-models/teapot.obj" --res 48 --method sdf -o teapot_sdf.vdb
  run voxelize "$data/derived/armadillo_ls128.vdb" --res 64 -o armadillo.vdb
  run voxelize "$data/derived/armadillo_fog128.vdb" --res 48 --threshold 0.5 -o armadillo_fog.vdb
  meshes=(bunny bunny_solid fandisk spider boxtex engine)
else
  echo "snapshot_outputs: $data absent: mesh and grid inputs skipped" >&2
fi

# Atlases, pyramids, page files, renders
for s in hamlet64 village "${meshes[@]}"; do
  run build-atlas $s.vdb -o atlas_$s --all
  "$vox" info $s.vdb --json > info_$s.json 2>>"$log"
  run mip $s.vdb -o ${s}_mips.vdb
  run mip $s.vdb -o ${s}_maj.vdb --occupancy majority --levels 2
  for layout in bricks svo columns; do
    run pack-chunks ${s}_mips.vdb -o ${s}_$layout.vpk --mips --layout $layout
    "$vox" info ${s}_$layout.vpk --json > info_${s}_$layout.json 2>>"$log"
  done
  run pack-chunks $s.vdb -o ${s}_c8.vpk --chunk 8 --align 64
  run pack-chunks $s.vdb -o ${s}_c32.vpk --chunk 32
done
run mip hamlet64.vdb -o split.vdb --split --levels 2
run build-atlas hamlet256.vdb -o atlas_hamlet256 --summary --occupancy --occupancy2
run build-atlas hamlet64.vdb -o atlas_f16 --identity --format rgba16f
run build-atlas hamlet64.vdb -o atlas_exr --identity --format rgba32ui

modes=canonical,class,shaded,depth,normal
run render-canonical hamlet256.vdb -o r_hamlet.png $cam --mode $modes --touched r_hamlet.touched.json --touched-bitmap r_hamlet.tb.png
run render-canonical hamlet64.vdb -o r_far.png --eye 100000,70000,80000 --target 0,1,0 --fov 0.004 --size 40x30
run render-canonical hamlet64.vdb -o r_in.png --eye 0.05,1.0,0.05 --target 5,1,3 --fov 100 --size 40x30 --mode $modes
run render-canonical village.vdb -o r_village.png --camera in/village_cameras.json --mode $modes
for layout in bricks svo columns; do
  run render-canonical hamlet64_$layout.vpk -o r_pages_$layout.png $cam --mode $modes
  run render-canonical hamlet64_$layout.vpk --level 1 -o r_pages_l1_$layout.png $cam
done
for s in "${meshes[@]}"; do
  run render-canonical $s.vdb -o r_$s.png --eye 3,2,3 --target 0,0,0 --size 96x64 --mode $modes
done
for f in r_hamlet.canonical.png atlas_hamlet64/*.png; do
  [ -e "$f" ] && "$vox" info "$f" --json > "info_$(echo "$f" | tr / _).json" 2>>"$log"
done
echo "snapshot: $(find . -type f | wc -l) files in $out"
