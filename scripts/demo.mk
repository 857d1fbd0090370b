# The demo bake as a Makefile, the way users drive vox: each output depends on
# its inputs through the depfiles vox writes, so `make` reruns only what changed.
#   make -f scripts/demo.mk VOX=build/bin/vox OUT=out RES=256
VOX ?= build/bin/vox
OUT ?= out
RES ?= 256
MAP := scripts/demo/village_map.json

all: $(OUT)/hamlet.vdb $(OUT)/hamlet.info.txt $(OUT)/village.vdb $(OUT)/village.info.txt
	@echo
	@echo "demo outputs in $(OUT)/:"
	@ls -l $(OUT) | tail -n +2
	@echo
	@echo "  hamlet.vdb         the built-in hamlet, $(RES)^3 voxels, 7 classes (open it with vdb_print or Houdini)"
	@echo "  hamlet.info.txt    vox info of it; hamlet.report.json: phase timings and counts"
	@echo "  village.vdb        a seed 002 block map ($(MAP)) as a scene"

$(OUT):
	mkdir -p $(OUT)

$(OUT)/hamlet.vdb: | $(OUT)
	$(VOX) voxelize demo:hamlet --res $(RES) -o $@ --depfile $@.d --report $(OUT)/hamlet.report.json

$(OUT)/village.vdb: $(MAP) | $(OUT)
	$(VOX) voxelize $(MAP) -o $@ --depfile $@.d --report $(OUT)/village.report.json

$(OUT)/%.info.txt: $(OUT)/%.vdb
	$(VOX) info $< > $@.tmp && mv $@.tmp $@

-include $(wildcard $(OUT)/*.d)

.PHONY: all
