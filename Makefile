# Two entry points (see README):
#   make run   - set up a virtualenv in .venv and run the main job
#   make test  - set up the same virtualenv and run the test suite's fast tier (all but `slow`)
# and for CI / before a release:
#   make test-slow - the slow tier alone (tests marked @pytest.mark.slow)
#   make test-all  - both tiers in one run
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: run test test-slow test-all setup bench docs clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e ".[test]"
	@# best effort: CHOLMOD (libsuitesparse-dev + scikit-sparse) speeds up every factorisation;
	@# SuperLU is the fallback, so this step never fails the set-up
	-@if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1 && [ ! -e /usr/include/suitesparse/cholmod.h ]; then \
		(apt-get update -qq && apt-get install -y -qq libsuitesparse-dev) >/dev/null 2>&1 || true; fi
	-@$(BIN)/pip install --quiet -e ".[cholmod]" >/dev/null 2>&1 || echo "CHOLMOD (scikit-sparse) not installed: SuperLU will be used"
	touch $(STAMP)

setup: $(STAMP)

run: $(STAMP)
	$(BIN)/hyperlattice reproduce --out reproduction

# pytest on WORKERS processes (pytest-xdist), each with two BLAS threads; --dist loadfile keeps a
# test file on one worker: a docs page's examples run in page order in one namespace, and a
# module-scoped fixture is built once (loadgroup would be finer, but its xdist_group marks are
# not applied under pytest 9: xdist 3.8 renames item._nodeid, which pytest 9 no longer reads)
WORKERS ?= 2
PYTEST  := $(BIN)/python -m pytest -n $(WORKERS) --dist loadfile --blas-threads 2

test: $(STAMP)
	$(PYTEST) -m "not slow"

test-slow: $(STAMP)
	$(PYTEST) -m slow

test-all: $(STAMP)
	$(PYTEST)

# the documentation site (docs/_build/html): the docs pages and the API reference from the
# docstrings, warnings as errors
docs: $(STAMP)
	$(BIN)/pip install --quiet -e ".[docs]"
	rm -rf docs/_build docs/generated
	$(BIN)/python -m sphinx -W --keep-going -q -b html docs docs/_build/html

bench: $(STAMP)
	for b in benchmarks/bench_*.py; do $(BIN)/python $$b || exit 1; done

clean:
	rm -rf $(VENV) reproduction .pytest_cache docs/_build docs/generated
