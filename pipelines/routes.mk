# Plan a route with every algorithm on every bundled chart: build/paths/CHART/ALGO.geojson (+ .json
# summary), then build/paths/summary.csv (usvtool metrics). Included by report.mk after charts.mk.
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
# Rudee Inlet: from the south-west lake past the piers and piles into Lake Rudee's channel (the
# fixed bridges cut the lakes off from the inlet on the chart)
ENDS_rudee_inlet := --start-lonlat -75.984285 36.825408 --goal-lonlat -75.973358 36.831274
# South San Diego Bay: the north channel down to the Chula Vista channel, among the lights
ENDS_south_san_diego := --start-lonlat -117.122549 32.649479 --goal-lonlat -117.118435 32.635674
# the grids with a route (US4MD81M, 25 M cells, is preprocessed only)
ROUTE_GRIDS := $(foreach c,$(GRIDS),$(if $(ENDS_$(c)),$(c)))

define route_rule
$(PATHS_DIR)/$(1)/$(2).geojson: $(OUT)/$(1).tif $(SRC)
	@mkdir -p $$(@D)
	$(USV) plan $$< $(ENDS_$(1)) --algo $(2) --seed $(SEED) --attempts $(ATTEMPTS) -o $$@ > $$(@:.geojson=.json)
endef
$(foreach c,$(ROUTE_GRIDS),$(foreach a,$(ALGOS),$(eval $(call route_rule,$(c),$(a)))))

ROUTES := $(foreach c,$(ROUTE_GRIDS),$(foreach a,$(ALGOS),$(PATHS_DIR)/$(c)/$(a).geojson))

# the table of the papers' metrics (docs/metrics.md): usvtool metrics writes it atomically; the
# any-angle route of each chart's directory is the reference of length_ratio
METRICS_SRC := $(wildcard usvtool/measure/*.py) usvtool/metrics.py usvtool/route.py usvtool/cli/metrics.py
$(PATHS_DIR)/summary.csv: $(ROUTES) $(METRICS_SRC)
	$(USV) metrics $(ROUTES) -o $@ > $(@:.csv=.json)
