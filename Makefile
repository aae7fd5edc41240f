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
	touch $(STAMP)

install: $(STAMP)

# The fast path's machine code is compiled once per checkout (and cached on
# disk): do it here, with a message, so that no later command stalls silently
# and no test's time limit includes it.
compile: $(STAMP)
	$(PY) -c "from analytic import fast; fast.compile(progress=True)"

run: compile
	$(PY) -m analytic simulate --plot $(OUT)/default-shot.png
	$(PY) -m crosscheck --report $(OUT)/crosscheck
	$(PY) -m engine_model render --out $(OUT)/frames --fps 15

test: compile
	$(PY) -m pytest

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache .hypothesis build *.egg-info
