# The demo bake as a Makefile, the way users drive vox: each output depends on
# its inputs through the depfiles vox writes, so `make` reruns only what changed.
#   make -f scripts/demo.mk VOX=build/bin/vox OUT=out RES=256
VOX ?= build/bin/vox
OUT ?= out
RES ?= 256
MAP := scripts/demo/village_map.json

all: $(OUT)/hamlet.vdb $(OUT)/hamlet.info.txt $(OUT)/village.vdb $(OUT)/village.info.txt \
     $(OUT)/atlas/hamlet.atlas.json $(OUT)/atlas/hamlet.verify.txt $(OUT)/bijection.txt
	@echo
	@echo "demo outputs in $(OUT)/:"
	@ls -l $(OUT) | tail -n +2
	@echo
	@echo "  hamlet.vdb         the built-in hamlet, $(RES)^3 voxels, 7 classes (open it with vdb_print or Houdini)"
	@echo "  hamlet.info.txt    vox info of it; hamlet.report.json: phase timings and counts"
	@echo "  village.vdb        a seed 002 block map ($(MAP)) as a scene"
	@echo "  atlas/             hamlet atlases: summary RGBA8, identity, per-class votes, 1/2-bit bitmaps (PNG)"
	@echo "  atlas/hamlet.verify.txt  every atlas checked texel by texel against the scene"
	@echo "  bijection.txt      proof of the $(RES)^3 voxel<->texel mapping"

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

$(OUT)/%.info.txt: $(OUT)/%.vdb
	$(VOX) info $< > $@.tmp && mv $@.tmp $@

-include $(wildcard $(OUT)/*.d $(OUT)/atlas/*.d)

.PHONY: all
