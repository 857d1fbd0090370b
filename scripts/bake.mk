# A region bake as a Makefile: one target per region part, one merge, so
# `make -j` runs the regions side by side on one machine (docs/scale.md,
# "Running on Slurm and make"; scripts/bake-slurm.sh is the same bake on Slurm).
#
#   make -f scripts/bake.mk -j2 OUT=bake REGIONS=3 SOURCE='demo:city --extent 1024,128,1024'
#
# Variables:
#   SOURCE     the arguments of `vox voxelize` without --region and -o: the
#              source(s) and options, as shell words
#              (default: demo:hamlet --res 128)
#   REGIONS    the number of regions N (default 4); region I is baked by
#              `vox voxelize SOURCE --region I/N -o OUT/part-I.vdb`
#   OUT        the directory of the parts and the world (default bake)
#   PACK_ARGS  the arguments of every pack-chunks run, e.g. --chunk 16
#              (default none)
#   VOX        the vox binary (default: build/bin/vox beside scripts/)
#
# Targets:
#   all (default)  OUT/world.vdb (vox merge of the scene parts) and
#                  OUT/world.vpk (vox pack-chunks --merge of the part page files)
#   parts          every OUT/part-I.vdb and OUT/part-I.vpk, no merge
#   clean          removes the parts, the world and OUT/bake.args
#
# Resuming: vox writes every output atomically (a temporary file renamed when
# complete), so a part exists only when it is whole. After Ctrl-C, run the
# same command again: make rebakes only the parts that are missing, then merges.
# OUT/bake.args records SOURCE, REGIONS and PACK_ARGS; when they change, every
# part is rebaked (a part of another bake is never merged).
# SOURCE's inputs are tracked too: voxelize writes a depfile beside each part
# (OUT/part-I.vdb.d), so an edited mesh or block map rebakes its parts.

BAKE_MK_DIR := $(patsubst %/,%,$(dir $(lastword $(MAKEFILE_LIST))))
VOX ?= $(BAKE_MK_DIR)/../build/bin/vox
OUT ?= bake
REGIONS ?= 4
SOURCE ?= demo:hamlet --res 128
PACK_ARGS ?=

ifeq ($(shell [ "$(REGIONS)" -ge 1 ] 2>/dev/null && echo ok),)
  $(error REGIONS='$(REGIONS)' is not a whole number of regions >= 1)
endif

IDS := $(shell seq 0 $$(($(REGIONS) - 1)))
PARTS_VDB := $(foreach i,$(IDS),$(OUT)/part-$(i).vdb)
PARTS_VPK := $(foreach i,$(IDS),$(OUT)/part-$(i).vpk)

# The settings every part depends on, rewritten only when they change (so an
# unchanged bake keeps its parts).
BAKE_ARGS := REGIONS=$(REGIONS) SOURCE=$(SOURCE) PACK_ARGS=$(PACK_ARGS)
ifneq ($(BAKE_ARGS),$(file <$(OUT)/bake.args))
  $(shell mkdir -p $(OUT))
  $(file >$(OUT)/bake.args,$(BAKE_ARGS))
endif

.PHONY: all parts clean
.DELETE_ON_ERROR:

all: $(OUT)/world.vdb $(OUT)/world.vpk

parts: $(PARTS_VDB) $(PARTS_VPK)

$(PARTS_VDB): $(OUT)/part-%.vdb: $(OUT)/bake.args
	$(VOX) voxelize $(SOURCE) --region $*/$(REGIONS) -o $@ --depfile $@.d

$(PARTS_VPK): $(OUT)/part-%.vpk: $(OUT)/part-%.vdb
	$(VOX) pack-chunks $< -o $@ $(PACK_ARGS)

$(OUT)/world.vdb: $(PARTS_VDB)
	$(VOX) merge $^ -o $@

$(OUT)/world.vpk: $(PARTS_VPK)
	$(VOX) pack-chunks --merge $^ -o $@

clean:
	rm -f $(OUT)/part-*.vdb $(OUT)/part-*.vdb.d $(OUT)/part-*.vpk \
	      $(OUT)/world.vdb $(OUT)/world.vpk $(OUT)/bake.args

-include $(wildcard $(OUT)/part-*.vdb.d)
