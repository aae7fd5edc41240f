# Two entry points: `make run` (the main job on the built-in default design)
# and `make test` (the whole suite). Both create .venv/ and install into it.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed-stamp
OUT    ?= out

.PHONY: run test install compile clean crosscheck run-shot run-crosscheck run-frames docs serve browser notebook

# uv (from PyPI, into the environment) installs the dependencies in parallel:
# 26 s from an empty cache where pip took 52-115 s on the same machine. It
# writes the bytecode at install as pip does (--compile-bytecode), so that no
# process compiles the libraries' sources again (3.4 s of each command where
# PYTHONDONTWRITEBYTECODE is set).
# One line says what is under way; a failing step still prints its command and error.
$(STAMP): pyproject.toml
	@echo "installing into $(VENV)/ (about 30-50 s on a fresh machine)"
	@$(PYTHON) -m venv $(VENV)
	@$(PY) -m pip install -qq uv
	@$(PY) -m uv pip install --quiet --compile-bytecode --python $(PY) -e '.[test,docs]'
	@touch $(STAMP)

install: $(STAMP)

# The fast path's machine code is compiled once per checkout and cached on
# disk (tens of seconds, with a progress count), so that no later command
# stalls on it and no test's time limit includes it; again only when a source
# of the analytic model changed (numba's cache is stamped with them, and
# ``analytic compile`` then compiles; otherwise it only loads, in 4-5 s).
# It is compiled in scopes (analytic/scope.py): the full cross-check needs the one
# that handles every design; the suite runs all three (the ideal machine's two
# smaller ones beside the largest, on the two cores: about as long as it alone).
# Every source of the analytic package, the two paths' rooms (analytic/fast/, analytic/reference/)
# and the tools' subpackages included: a stamp older than any of them compiles again.
ANALYTIC_SOURCES := $(shell find analytic -name '*.py' -not -path '*/__pycache__/*')
COMPILED := $(VENV)/.compiled-stamp
$(COMPILED): $(STAMP) $(ANALYTIC_SOURCES)
	@$(PY) -m analytic compile --scope everything
	@touch $(COMPILED)

COMPILED_ALL := $(VENV)/.compiled-all-stamp
$(COMPILED_ALL): $(STAMP) $(ANALYTIC_SOURCES)
	@$(PY) -m analytic compile
	@touch $(COMPILED) $(COMPILED_ALL)

compile: $(COMPILED_ALL)

# `make run`: the default shot, the quick cross-check and the frames, two at a
# time (the machine's cores; the shot first, the longest beside it). Quiet recipes (@); each
# job's report is printed whole as it ends (--output-sync), under 40 lines in all.
# None of them needs the fast path: the shot draws the scipy path's history, and the
# quick cross-check's four designs take its summaries (--path reference: the same
# numbers to round-off, in seconds, where compiling the fast path takes tens of them).
run: $(STAMP)
	@$(MAKE) --no-print-directory -j2 --output-sync=target run-shot run-frames run-crosscheck

run-shot:
	@$(PY) -m analytic simulate --plot $(OUT)/default-shot.png

run-crosscheck:
	@$(PY) -m crosscheck --quick --workers 1 --no-progress --path reference --report $(OUT)/crosscheck

run-frames:
	@$(PY) -m engine_model render --quiet --out $(OUT)/frames --gif --mp4

# The full cross-check: every design of the default suite (about a minute).
crosscheck: $(COMPILED)
	@$(PY) -m crosscheck --report $(OUT)/crosscheck

# On every core (pytest-xdist): each worker takes the next test as it finishes one, the
# slow ones first (tests/conftest.py), and each module marked xdist_group (a Dask cluster's,
# the rolling shots', the recorded motion's) whole on one worker (--dist loadgroup).
# `$(PY) -m pytest` alone still runs the whole suite in one process. Then the
# documentation site, so that a broken link or reference fails the tests too.
# The suite also compiles the fast path's other (public) numba mechanism, its smallest scope only,
# into the same disk cache under its own names (tests/test_analytic_numba_mechanisms.py): in the
# suite, on one worker beside the others' tests, rather than here before them, and again only
# when a source of the model changed.
test: compile browser
	$(PY) -m pytest -n auto --dist loadgroup
	@$(MAKE) --no-print-directory docs

# The workbench: the whole project in a local web page (python -m workbench), opened in the browser.
serve: compile
	@$(PY) -m workbench

# The workbench's browser tests drive Debian's chromium (never a browser build of
# Playwright's own, which cannot be downloaded here); CI runs as root.
browser:
	@test -x /usr/bin/chromium || (apt-get update -qq && apt-get install -y -qq chromium)

# The documentation site into docs/_build/html, every warning an error
# (--keep-going lists them all first). It imports the package for the API
# reference and renders the notebook as stored, without running it. -E reads
# every page afresh: an incremental build would not repeat an unchanged page's
# warnings, and would pass the second time.
docs: $(STAMP)
	@$(PY) -m sphinx -b html -E -W --keep-going -q docs docs/_build/html
	@echo "docs: docs/_build/html/index.html"

# The example notebook run from top to bottom and stored with its outputs (the suite's
# notebook test does the same, rewriting the file only where its text changed).
notebook: compile
	@$(PY) docs/execute_notebook.py

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache .hypothesis build *.egg-info docs/_build
