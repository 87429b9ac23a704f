# Plan a route with every algorithm on every chart of the pipeline's route matrix:
# build/paths/CHART/ALGO.geojson (+ .json summary), then build/paths/summary.csv (usvtool metrics).
# Included by report.mk after charts.mk, whose build/pipeline.mk (from pipelines/report.yaml)
# gives ROUTE_GRIDS, ALGOS, SEED, ATTEMPTS, PLAN_OPTIONS, ENDS_<chart> and ROUTES: no list here.
# --allow-collision: a route that still collides after the attempts is a result (flagged
# collision_free false in the table), not a failed target (plan would exit 3 for it).
PATHS_DIR := build/paths
# the plan stage's code (CLI_SRC and contracts from charts.mk): a chart-only change re-plans nothing
PLAN_CONTRACTS := grid route collision collision_kernels measures geodesy atomic errors
PLAN_SRC := $(shell find usvtool/plan -name '*.py') usvtool/cli/plan.py $(CLI_SRC) \
	$(call contracts,$(PLAN_CONTRACTS))

define route_rule
$(PATHS_DIR)/$(1)/$(2).geojson: $(OUT)/$(1).tif $(PLAN_SRC)
	@mkdir -p $$(@D)
	$(USV) plan $$< $(ENDS_$(1)) --algo $(2) --seed $(SEED) --attempts $(ATTEMPTS) $(PLAN_OPTIONS) \
		--allow-collision -o $$@ --summary $$(@:.geojson=.json) > /dev/null
endef
$(foreach c,$(ROUTE_GRIDS),$(foreach a,$(ALGOS),$(eval $(call route_rule,$(c),$(a)))))

# the table of the papers' metrics (docs/metrics.md): usvtool metrics writes it atomically; the
# any-angle route of each chart's directory is the reference of length_ratio
METRICS_CONTRACTS := measures route trace angles grid geodesy atomic errors
METRICS_SRC := $(wildcard usvtool/metrics/*.py) usvtool/cli/metrics.py $(CLI_SRC) \
	$(call contracts,$(METRICS_CONTRACTS))
$(PATHS_DIR)/summary.csv: $(ROUTES) $(METRICS_SRC)
	$(USV) metrics $(ROUTES) -o $@ --summary $(@:.csv=.json) > /dev/null
