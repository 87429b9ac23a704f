# Plan a route with every algorithm on every bundled chart: build/paths/CHART/ALGO.geojson (+ .json
# summary), then build/paths/summary.csv. Included by report.mk after charts.mk.
ALGOS := wso iwso ssa issa pso pso-issa gwo woa mrfo boa iwso+s anyangle astar
SEED ?= 1
# optimizer runs at most per route (usvtool plan --attempts): a new run while the best route
# collides; every route's summary says which run gave it (docs/planning.md, "Attempts")
ATTEMPTS ?= 5
PATHS_DIR := build/paths

# start and goal of each chart's route (map metres, or lon/lat for the NOAA charts)
ENDS_env1 := --start 10 10 --goal 490 490
ENDS_env2 := --start 10 10 --goal 490 490
ENDS_grid20 := --start 0.5 0.5 --goal 19.5 19.5
ENDS_grid50 := --start 1.5 1.5 --goal 49.5 49.5
# Boston: Nantasket Roads to Massachusetts Bay, between the outer harbour islands
ENDS_us5ma12m := --start-lonlat -70.93391 42.32119 --goal-lonlat -70.79426 42.31806
# Mississippi: the main channel from Pilottown down to Head of Passes
ENDS_head_of_passes := --start-lonlat -89.2677 29.1840 --goal-lonlat -89.2619 29.1240

define route_rule
$(PATHS_DIR)/$(1)/$(2).geojson: $(OUT)/$(1).tif $(SRC)
	@mkdir -p $$(@D)
	$(USV) plan $$< $(ENDS_$(1)) --algo $(2) --seed $(SEED) --attempts $(ATTEMPTS) -o $$@ > $$(@:.geojson=.json)
endef
$(foreach c,$(GRIDS),$(foreach a,$(ALGOS),$(eval $(call route_rule,$(c),$(a)))))

ROUTES := $(foreach c,$(GRIDS),$(foreach a,$(ALGOS),$(PATHS_DIR)/$(c)/$(a).geojson))

$(PATHS_DIR)/summary.csv: $(ROUTES) pipelines/summarise.py
	$(BIN)/python pipelines/summarise.py $(PATHS_DIR) > $@.tmp && mv $@.tmp $@
