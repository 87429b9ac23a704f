# usvtool: `make report` (main job on the bundled charts) and `make test`.
# Both create .venv and install the project on first use; the stamp makes later runs quick.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
USV := $(BIN)/usvtool
BUILD := build

.PHONY: test test-fast report regression baseline charts routes lint bench clean
# a recipe that fails removes the target it was making (no half-written file looks up to date)
.DELETE_ON_ERROR:

# installed with uv (from PyPI into the venv): the same packages and versions as pip resolves, in
# about 20 s from an empty cache rather than pip's 60 (it downloads and unpacks in parallel); by
# pip when uv cannot (uv reads no pip.conf: an index only pip is configured for). Compiled to
# bytecode as pip does by default (uv does not): without it, where PYTHONDONTWRITEBYTECODE is set,
# every process compiled the sources of what it imports, 2.5 s of CPU for a usvtool simulate of
# 1.1 s (13 s more at the installation, once; hundreds of processes in the tests)
EXTRAS := .[test,gym,trafficgen]
$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	{ $(BIN)/python -m pip install --quiet --disable-pip-version-check uv \
		&& $(BIN)/python -m uv pip install --quiet --compile-bytecode --python $(BIN)/python \
			-e '$(EXTRAS)'; } \
		|| $(BIN)/python -m pip install --quiet -e '$(EXTRAS)'
	touch $(STAMP)

# Debian packages the tests use: Chromium (the report's browser test), Pango (WeasyPrint's PDF) and
# ffmpeg (usvtool animate's MP4s). Installed with apt-get when missing and running as root;
# otherwise a note (the browser test and the MP4 test are then skipped and report.pdf not
# written, each saying why).
SYSTEM_STAMP := $(VENV)/.system-packages
$(SYSTEM_STAMP):
	@if command -v chromium >/dev/null && ldconfig -p | grep -q libpangoft2-1.0 \
		&& command -v ffmpeg >/dev/null; then :; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
		echo "installing Debian packages: chromium libpango-1.0-0 libpangoft2-1.0-0 ffmpeg"; \
		apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
			--no-install-recommends chromium libpango-1.0-0 libpangoft2-1.0-0 \
			fonts-dejavu-core ffmpeg >/dev/null; \
	else echo "note: install chromium, libpango-1.0-0, libpangoft2-1.0-0 and ffmpeg for the report's PDF, its browser test and usvtool animate's MP4s"; fi
	@mkdir -p $(VENV) && touch $@

# the suite in one worker process per core (pytest-xdist), a test module's tests in one worker
# (its module fixtures, some a whole batch or report, built once), the modules holding tests
# marked slow first (tests/conftest.py) so that the short ones fill the end: 2 min 7 s - 2 min 48 s on
# stop 29's machine; on stop 28's, 3 min 54 s against 6 min 41 s in one process
test: $(STAMP) $(SYSTEM_STAMP)
	$(BIN)/python -m pytest -q -n auto --dist loadscope

# the suite without the tests marked slow (whole pipelines, full-size charts, every scenario):
# under a minute, for the edit-test loop; `make test` (CI's) runs everything
test-fast: $(STAMP) $(SYSTEM_STAMP)
	$(BIN)/python -m pytest -q -n auto --dist loadscope -m "not slow"

lint: $(STAMP)
	$(BIN)/ruff check .

# the full comparison (docs/report.md): pipelines/full.yaml run by usvtool batch into build/batch
# (a job runs again only when its configuration or its stage's code changed: docs/batch.md),
# then the report from its table. A second `make report` with nothing changed does nothing; a
# change to a template or to the report stage renders the report again, and only that.
JOBS ?= 2
BATCH_DIR := $(BUILD)/batch
REPORT_DIR := $(BUILD)/report
REPORT_SRC := $(shell find usvtool/report -name '*.py') usvtool/cli/report.py $(wildcard templates/*)
BATCH_INPUTS := $(filter-out $(REPORT_SRC),$(shell find usvtool -name '*.py')) \
	$(shell find charts -type f -not -name '*.pyc') $(wildcard pipelines/*.yaml)

# ends with one line, also when the report was up to date: where it is, its pages, the verdicts
report: $(REPORT_DIR)/index.html
	@$(BIN)/python -c 'import json, sys; from usvtool.cli.report import summary_line; \
		print(summary_line(json.load(open(sys.argv[1], encoding="utf-8"))))' $(BUILD)/report.json

$(BATCH_DIR)/metrics.csv: $(STAMP) $(BATCH_INPUTS)
	@mkdir -p $(BUILD)
	$(USV) batch pipelines/full.yaml -j $(JOBS) -o $(BATCH_DIR) --summary $(BUILD)/batch.json > /dev/null

$(REPORT_DIR)/index.html: $(BATCH_DIR)/metrics.csv $(REPORT_SRC) $(SYSTEM_STAMP)
	$(USV) report $< -o $(REPORT_DIR) --summary $(BUILD)/report.json > /dev/null

# the CI regression report (docs/compare.md): pipelines/ci.yaml against baselines/ci.csv; exits
# 1 when a metric got worse or went missing. `make baseline` refreshes the baseline on purpose.
CI_DIR := $(BUILD)/ci
regression: $(STAMP)
	$(USV) batch pipelines/ci.yaml -j $(JOBS) -o $(CI_DIR) > /dev/null
	$(USV) compare baselines/ci.csv $(CI_DIR)/metrics.csv -o $(BUILD)/regression > /dev/null

baseline: $(STAMP)
	$(USV) batch pipelines/ci.yaml -j $(JOBS) -o $(CI_DIR) > /dev/null
	@mkdir -p baselines
	cp $(CI_DIR)/metrics.csv baselines/ci.csv
	cp $(CI_DIR)/timings.csv baselines/timings.csv

# the bundled charts' grids and one route on each with every algorithm (pipelines/report.yaml)
# through Make's own rules: build/grids/ and build/paths/summary.csv
charts: $(STAMP)
	$(MAKE) -f pipelines/charts.mk BIN=$(abspath $(BIN)) all

routes: charts
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
