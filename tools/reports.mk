# make reports: per-lens sweeps, the accuracy-against-time report and per-lens reports.
# Called by the top-level Makefile as `make -f tools/reports.mk`; lenses run in
# parallel with -j, and a lens is swept again only when its inputs changed (the lens
# file, the commands, or the sweep script).
#   make reports                    # every lens in lenses/, full sweep (~20 min, 2 cores)
#   make reports LENSES="simple dgauss.50mm" MODE=reduced OUT=/tmp/r   # a quick one
BIN    ?= bin
BUILD  ?= build
MODE   ?= full
OUT    ?= reports
CACHE  ?= $(OUT)/cache
LENSES ?= $(basename $(notdir $(wildcard lenses/*.lens)))
export BIN BUILD

TOOLS  := $(BIN)/lens-trace $(BIN)/lens-fit $(BIN)/lens-eval $(BUILD)/bench/bench_system tools/sweep.sh
SWEEPS := $(LENSES:%=$(CACHE)/%/sweep.tsv)

.PHONY: all
all: $(OUT)/accuracy-vs-time.md $(LENSES:%=$(OUT)/%.md)

$(CACHE)/%/sweep.tsv: lenses/%.lens $(TOOLS)
	@rm -rf $(CACHE)/$*
	@echo "reports: sweeping $*" >&2
	@tools/sweep.sh $< $(CACHE)/$* $(MODE)

$(OUT)/accuracy-vs-time.md: $(SWEEPS) tools/report_accuracy.py
	@python3 tools/report_accuracy.py $(CACHE) $@ $(OUT)/accuracy
	@echo "reports: wrote $@" >&2

$(OUT)/%.md: $(CACHE)/%/sweep.tsv tools/report_lens.sh tools/report_layout.sh $(BIN)/lens-spot $(BIN)/lens-distort $(BIN)/lens-layout
	@tools/report_lens.sh lenses/$*.lens $(CACHE)/$* $(OUT)
	@echo "reports: wrote $@" >&2
