# The report at this stage: every bundled chart preprocessed (charts.mk), a route planned on each
# with every algorithm (routes.mk), and the table of the papers' metrics (build/paths/summary.csv).
BIN ?= .venv/bin
.DELETE_ON_ERROR:
include pipelines/charts.mk
include pipelines/routes.mk

report: all $(PATHS_DIR)/summary.csv
	@$(BIN)/python -c "import csv,sys; r=list(csv.reader(open('$(PATHS_DIR)/summary.csv'))); \
	w=[max(len(x[i]) for x in r) for i in range(len(r[0]))]; \
	[print('  '.join(c.ljust(n) for c,n in zip(x,w))) for x in r]"
