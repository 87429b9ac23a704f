# usvtool: `make report` (main job on the bundled charts) and `make test`.
# Both create .venv and install the project on first use; the stamp makes later runs quick.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
USV := $(BIN)/usvtool
BUILD := build

.PHONY: test report charts lint bench clean
# a recipe that fails removes the target it was making (no half-written file looks up to date)
.DELETE_ON_ERROR:

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $(STAMP)

test: $(STAMP)
	$(BIN)/python -m pytest -q

lint: $(STAMP)
	$(BIN)/ruff check .

charts: $(STAMP)
	$(MAKE) -f pipelines/charts.mk BIN=$(abspath $(BIN)) all

report: charts
	$(MAKE) -j2 -f pipelines/report.mk BIN=$(abspath $(BIN)) report

# speed and quality figures (several minutes): preprocessing, planning, ISSA 20 x 20, the
# bundled charts' routes over 10 seeds, Table 1
bench: charts
	$(BIN)/python benchmarks/bench_preprocess.py
	$(BIN)/python benchmarks/bench_plan.py
	$(BIN)/python benchmarks/bench_issa20.py
	$(BIN)/python benchmarks/bench_charts.py
	$(BIN)/python benchmarks/bench_functions.py --runs 5 -j 2

clean:
	rm -rf $(BUILD)
