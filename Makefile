# Two entry points: `make run` (the main job on the built-in default design)
# and `make test` (the whole suite). Both create .venv/ and install into it.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed-stamp
OUT    ?= out

.PHONY: run test install compile clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	@echo "compiling the fast path once, so that no later command stalls on it:"
	$(PY) -m analytic compile
	touch $(STAMP)

install: $(STAMP)

# The fast path's machine code is compiled once per checkout and cached on
# disk; `compile` loads it (0.3 s) or, after the model's sources changed,
# compiles it again with a progress count, so that no later command stalls
# silently and no test's time limit includes it.
compile: $(STAMP)
	@$(PY) -m analytic compile > /dev/null   # the progress count (stderr) shows; "ready" does not

# Quiet recipes (@): what is printed is the report itself, under 40 lines.
run: compile
	@$(PY) -m analytic simulate --plot $(OUT)/default-shot.png
	@echo "== cross-check: analytic against engine (every row: $(OUT)/crosscheck/table.txt)"
	@$(PY) -m crosscheck --report $(OUT)/crosscheck
	@$(PY) -m engine_model render --out $(OUT)/frames --gif --mp4

# On every core (pytest-xdist): each worker takes the next test as it finishes one, the
# slow ones first, and a Dask-cluster module whole on one worker (tests/conftest.py).
# `$(PY) -m pytest` alone still runs the whole suite in one process.
test: compile
	$(PY) -m pytest -n auto

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache .hypothesis build *.egg-info
