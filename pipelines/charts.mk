# Preprocess every chart of the pipeline into build/grids/ (grid GeoTIFF + preview PNG).
# Called from the top Makefile with BIN set to the virtualenv's bin directory. The charts, their
# sources and options live in pipelines/report.yaml (docs/pipelines.md): this file holds no list.
BIN ?= .venv/bin
USV := $(BIN)/usvtool -q
OUT := build/grids
# a recipe that fails removes its target: a half-written file never looks up to date
.DELETE_ON_ERROR:

# each stage's outputs depend on the code of that stage, the CLI basics and the contract modules
# (usvtool/NAME.py) it imports: a change re-runs that stage (and what depends on its outputs) only
CLI_SRC := usvtool/__init__.py usvtool/cli/__init__.py usvtool/cli/options.py
contracts = $(patsubst %,usvtool/%.py,$(1))
CHART_CONTRACTS := grid geodesy atomic errors
CHART_SRC := $(shell find usvtool/chart -name '*.py') usvtool/cli/preprocess.py $(CLI_SRC) \
	$(call contracts,$(CHART_CONTRACTS))

# the pipeline's lists as Make variables (GRIDS, CHART_SOURCE_*, CHART_INPUTS_*, PREPROCESS_*,
# ROUTE_GRIDS, ALGOS, ENDS_*, ROUTES, ...) from the batch's own command lines and file lists,
# regenerated when the YAML, the code writing it or a folder of the charts' files changes (a file
# added or removed there: a new sidecar, an update, a glob's match); Make then restarts
PIPELINE ?= pipelines/report.yaml
PIPELINE_MK := build/pipeline.mk
PIPELINE_MK_SRC := usvtool/pipeline.py usvtool/companions.py usvtool/batch/commands.py \
	usvtool/batch/make.py usvtool/cli/batch.py
include $(PIPELINE_MK)
$(PIPELINE_MK): $(PIPELINE) $(PIPELINE_MK_SRC) $(CHART_FOLDERS)
	@mkdir -p $(@D)
	$(USV) batch $< --make-fragment $@

all: $(GRIDS:%=$(OUT)/%.tif)

$(OUT):
	mkdir -p $@

define grid_rule
$(OUT)/$(1).tif: $(CHART_SOURCE_$(1)) $(CHART_INPUTS_$(1)) $(CHART_SRC) | $(OUT)
	$(USV) preprocess $$< -o $$@ --preview $$(@:.tif=.png) --summary $$(@:.tif=.json) \
		$(PREPROCESS_$(1)) > /dev/null
endef
$(foreach c,$(GRIDS),$(eval $(call grid_rule,$(c))))
