# Preprocess every bundled chart into build/grids/ (grid GeoTIFF + preview PNG).
# Called from the top Makefile with BIN set to the virtualenv's bin directory.
BIN ?= .venv/bin
USV := $(BIN)/usvtool -q
OUT := build/grids
# every output depends on the code that makes it: a change re-runs the stages
SRC := $(shell find usvtool -name '*.py')

GRIDS := env1 env2 grid20 grid50 us5ma12m head_of_passes rudee_inlet south_san_diego us4md81m
all: $(GRIDS:%=$(OUT)/%.tif)

$(OUT):
	mkdir -p $@

# synthetic maps: 1 m cells; env maps keep a 3 m margin, the grid maps are used as drawn
$(OUT)/env%.tif: charts/env%.geojson $(SRC) | $(OUT)
	$(USV) preprocess $< -o $@ --preview $(@:.tif=.png) --cell-size 1 --margin 3 > $(@:.tif=.json)
$(OUT)/grid%.tif: charts/grid%.geojson $(SRC) | $(OUT)
	$(USV) preprocess $< -o $@ --preview $(@:.tif=.png) --cell-size 1 --no-swell \
		--occupancy 0.5 > $(@:.tif=.json)
# NOAA ENC cell (vector, Boston Harbor): 10 m cells
$(OUT)/us5ma12m.tif: charts/noaa/US5MA12M.000 $(SRC) | $(OUT)
	$(USV) preprocess $< -o $@ --preview $(@:.tif=.png) --cell-size 10 > $(@:.tif=.json)
# NOAA raster chart (BSB/KAP, Head of Passes): the paper's rule, 1.5 x ship length
$(OUT)/head_of_passes.tif: charts/noaa/11361_4.KAP $(SRC) | $(OUT)
	$(USV) preprocess $< -o $@ --preview $(@:.tif=.png) > $(@:.tif=.json)
# NOAA raster charts with ink hazards (piers, piles, docks, wrecks): the paper's rule
$(OUT)/rudee_inlet.tif: charts/noaa/12205_2.KAP $(SRC) | $(OUT)
	$(USV) preprocess $< -o $@ --preview $(@:.tif=.png) > $(@:.tif=.json)
$(OUT)/south_san_diego.tif: charts/noaa/SanDiego_2.KAP $(SRC) | $(OUT)
	$(USV) preprocess $< -o $@ --preview $(@:.tif=.png) > $(@:.tif=.json)
# NOAA ENC approach cell (55 x 78 km) with its three updates: the cell size its size error
# suggests for the 25-million-cell limit
$(OUT)/us4md81m.tif: charts/noaa/US4MD81M/US4MD81M.000 $(wildcard charts/noaa/US4MD81M/*) $(SRC) | $(OUT)
	$(USV) preprocess $< -o $@ --preview $(@:.tif=.png) --cell-size 12.1 > $(@:.tif=.json)
