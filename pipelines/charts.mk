# Preprocess every chart of the pipeline into build/grids/ (grid GeoTIFF + preview PNG).
# Called from the top Makefile with BIN set to the virtualenv's bin directory. The charts, their
# sources and options live in pipelines/report.yaml (docs/pipelines.md): this file holds no list.
BIN ?= .venv/bin
USV := $(BIN)/usvtool -q
OUT := build/grids
# every output depends on the code that makes it: a change re-runs the stages
SRC := $(shell find usvtool -name '*.py')

# the pipeline's lists as Make variables (GRIDS, CHART_SOURCE_*, PREPROCESS_*, ROUTE_GRIDS, ALGOS,
# ENDS_*, ROUTES, ...), regenerated when the YAML or its reader changes (Make then restarts)
PIPELINE ?= pipelines/report.yaml
PIPELINE_MK := build/pipeline.mk
include $(PIPELINE_MK)
$(PIPELINE_MK): $(PIPELINE) usvtool/pipeline.py
	@mkdir -p $(@D)
	$(BIN)/python -m usvtool.pipeline make $< -o $@

all: $(GRIDS:%=$(OUT)/%.tif)

$(OUT):
	mkdir -p $@

define grid_rule
$(OUT)/$(1).tif: $(CHART_SOURCE_$(1)) $(CHART_INPUTS_$(1)) $(SRC) | $(OUT)
	$(USV) preprocess $$< -o $$@ --preview $$(@:.tif=.png) $(PREPROCESS_$(1)) > $$(@:.tif=.json)
endef
$(foreach c,$(GRIDS),$(eval $(call grid_rule,$(c))))
