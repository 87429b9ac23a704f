# The report: for now the preprocessed grids of every bundled chart and their summaries.
BIN ?= .venv/bin
include pipelines/charts.mk

report: all
	$(BIN)/python -c "import json,glob; [print(f, json.load(open(f))['obstacle_fraction']) for f in sorted(glob.glob('$(OUT)/*.json'))]"
