# The demo bake as a Makefile, the way users drive vox: each output depends on
# its inputs through the depfiles vox writes, so `make` reruns only what changed.
#   make -f scripts/demo.mk VOX=build/bin/vox OUT=out RES=256
VOX ?= build/bin/vox
OUT ?= out
RES ?= 256
MAP := scripts/demo/village_map.json

CAMERA := --eye 20,15,20 --target 0,2,0 --fov 40 --size 1280x720

all: $(OUT)/hamlet.vdb $(OUT)/hamlet.info.txt $(OUT)/village.vdb $(OUT)/village.info.txt \
     $(OUT)/atlas/hamlet.atlas.json $(OUT)/atlas/hamlet.verify.txt $(OUT)/bijection.txt \
     $(OUT)/hamlet_mips.vdb $(OUT)/hamlet.vpk.verify.txt \
     $(OUT)/render/hamlet.canonical.png $(OUT)/render/hamlet.verify.txt $(OUT)/render/pages.verify.txt \
     $(OUT)/render/village.png $(OUT)/house.vdb $(OUT)/render/house.png
	@echo
	@echo "demo outputs in $(OUT)/:"
	@ls -l $(OUT) | tail -n +2
	@echo
	@echo "  hamlet.vdb         the built-in hamlet, $(RES)^3 voxels, 7 classes (open it with vdb_print or Houdini)"
	@echo "  hamlet.info.txt    vox info of it; hamlet.report.json: phase timings and counts"
	@echo "  village.vdb        a block map ($(MAP)) as a scene"
	@echo "  atlas/             hamlet atlases: summary RGBA8, identity, per-class votes, 1/2-bit bitmaps (PNG)"
	@echo "  atlas/hamlet.verify.txt  every atlas checked texel by texel against the scene"
	@echo "  bijection.txt      proof of the $(RES)^3 voxel<->texel mapping"
	@echo "  hamlet_mips.vdb    LOD pyramid (levels 1..n, error per level vs the hamlet voxelized directly: hamlet_mips.report.json)"
	@echo "  hamlet.vpk         page file of the hamlet and its mips (16^3 chunks), verified: hamlet.vpk.verify.txt"
	@echo "  render/            hamlet.{canonical,shaded,class,normal}.png, hamlet.depth.exr from one exact pass,"
	@echo "                     $$(sed -n 's/^vox render-canonical: \(check: \)/\1/p' $(OUT)/render/hamlet.check.txt 2>/dev/null)"
	@echo "                     (hamlet.check.txt); the chunks it touched (hamlet.touched.json),"
	@echo "                     the same view from the page file, and village.png (the block map, shaded)"
	@echo "  house.vdb          a mesh with materials (scripts/demo/house.obj) through class rules"
	@echo "                     (scripts/demo/classes.json: wall, roof, trim), solid; render/house.png shaded"

$(OUT):
	mkdir -p $(OUT)

$(OUT)/hamlet.vdb: | $(OUT)
	$(VOX) voxelize demo:hamlet --res $(RES) -o $@ --depfile $@.d --report $(OUT)/hamlet.report.json

$(OUT)/village.vdb: $(MAP) | $(OUT)
	$(VOX) voxelize $(MAP) -o $@ --depfile $@.d --report $(OUT)/village.report.json

$(OUT)/atlas/hamlet.atlas.json: $(OUT)/hamlet.vdb
	$(VOX) build-atlas $< -o $(OUT)/atlas --all --depfile $@.d --report $(OUT)/atlas/report.json

$(OUT)/atlas/hamlet.verify.txt: $(OUT)/atlas/hamlet.atlas.json
	for f in $(OUT)/atlas/hamlet.*.png; do $(VOX) verify-bijection --atlas $$f --scene $(OUT)/hamlet.vdb || exit 1; done > $@.tmp && mv $@.tmp $@

$(OUT)/bijection.txt:
	$(VOX) verify-bijection --res $(RES) > $@.tmp && mv $@.tmp $@

$(OUT)/hamlet_mips.vdb: $(OUT)/hamlet.vdb
	$(VOX) mip $< -o $@ --source demo:hamlet --depfile $@.d --report $(OUT)/hamlet_mips.report.json

$(OUT)/hamlet.vpk: $(OUT)/hamlet_mips.vdb
	$(VOX) pack-chunks $< -o $@ --mips --depfile $@.d --report $(OUT)/hamlet.vpk.report.json

$(OUT)/hamlet.vpk.verify.txt: $(OUT)/hamlet.vpk
	$(VOX) pack-chunks --verify $< > $@.tmp 2>&1 && mv $@.tmp $@

$(OUT)/render/hamlet.canonical.png: $(OUT)/hamlet.vdb
	mkdir -p $(OUT)/render
	$(VOX) render-canonical $< -o $(OUT)/render/hamlet.png $(CAMERA) --mode canonical,shaded,class,depth,normal \
	  --touched $(OUT)/render/hamlet.touched.json --check --depfile $@.d --report $(OUT)/render/hamlet.report.json \
	  2>$(OUT)/render/hamlet.check.txt; s=$$?; cat $(OUT)/render/hamlet.check.txt >&2; exit $$s

$(OUT)/render/hamlet.verify.txt: $(OUT)/render/hamlet.canonical.png
	$(VOX) verify-bijection --canonical $< --scene $(OUT)/hamlet.vdb > $@.tmp && mv $@.tmp $@

$(OUT)/render/pages.verify.txt: $(OUT)/hamlet.vpk
	mkdir -p $(OUT)/render
	$(VOX) render-canonical $< -o $(OUT)/render/pages.png $(CAMERA)
	$(VOX) verify-bijection --canonical $(OUT)/render/pages.png --scene $(OUT)/hamlet.vdb > $@.tmp && mv $@.tmp $@

$(OUT)/render/village.png: $(OUT)/village.vdb scripts/demo/village_cameras.json
	mkdir -p $(OUT)/render
	$(VOX) render-canonical $< -o $@ --camera scripts/demo/village_cameras.json --view 0 --mode shaded --depfile $@.d

$(OUT)/house.vdb: scripts/demo/house.obj scripts/demo/classes.json | $(OUT)
	$(VOX) voxelize $< --res 64 --fill solid --classes scripts/demo/classes.json -o $@ --depfile $@.d \
	  --report $(OUT)/house.report.json

$(OUT)/render/house.png: $(OUT)/house.vdb
	mkdir -p $(OUT)/render
	$(VOX) render-canonical $< -o $@ --eye 9,7,12 --target 2,2,2.5 --fov 40 --size 640x480 --mode shaded --depfile $@.d

$(OUT)/%.info.txt: $(OUT)/%.vdb
	$(VOX) info $< > $@.tmp && mv $@.tmp $@

-include $(wildcard $(OUT)/*.d $(OUT)/atlas/*.d $(OUT)/render/*.d)

.PHONY: all
