# Two commands a newcomer needs: `make reproduce` and `make test`.
# Each creates .venv and installs the package (editable, with the dev extra) on first use.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
export OPENBLAS_NUM_THREADS := 1
export OMP_NUM_THREADS := 1
export MPLBACKEND := Agg

.PHONY: all venv test test-loaded test-narrow-simd test-fuzz test-min reproduce docs bench data lint clean

all: test

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev,tdms]'
	touch $(STAMP)

venv: $(STAMP)

test: $(STAMP)
	MPLCONFIGDIR=$$(mktemp -d) $(PY) -m pytest -q

# The whole suite again beside one CPU-burning process per core: a test that depends on the
# machine's speed (a wall-clock limit, a sleep, "some runs will have finished by now")
# fails here first.
test-loaded: $(STAMP)
	MPLCONFIGDIR=$$(mktemp -d) $(PY) scripts/loaded.py $(PY) -m pytest -q

# The numeric tests again with NumPy's SIMD dispatch narrowed to its baseline: every
# dispatched feature this CPU has is disabled, so sums are taken in another order (not the
# pages in the browser, nor the docs and kill tests: no numerics of their own).
test-narrow-simd: $(STAMP)
	@feats="$$($(PY) scripts/simd_features.py)"; echo "NPY_DISABLE_CPU_FEATURES=$$feats"; \
	NPY_DISABLE_CPU_FEATURES="$$feats" MPLCONFIGDIR=$$(mktemp -d) $(PY) -m pytest -q \
	  --ignore=tests/test_io_fuzz.py --ignore=tests/test_docs.py --ignore=tests/test_kill.py \
	  --ignore=tests/test_browser.py

# The property tests of every reader and the scene parser under the "fuzz" profile
# (tests/conftest.py): over 10,000 examples, about a minute.
test-fuzz: $(STAMP)
	HYPOTHESIS_PROFILE=fuzz MPLCONFIGDIR=$$(mktemp -d) $(PY) -m pytest -q tests/test_io_fuzz.py

# The whole suite on the oldest versions pyproject.toml allows (requirements-min.txt: the
# runtime dependencies and extras pinned at their floors, the test tools the newest that
# fit), in a venv of its own made anew (.venv-min/, about a minute to install). Not in CI
# (its time is counted): run it when a floor changes or a newer API is used.
test-min:
	rm -rf .venv-min
	$(PYTHON) -m venv .venv-min
	.venv-min/bin/python -m pip install --quiet --upgrade pip
	.venv-min/bin/python -m pip install --quiet -c requirements-min.txt -e '.[dev,tdms]'
	MPLCONFIGDIR=$$(mktemp -d) .venv-min/bin/python -m pytest -q

# The seed paper's figures and findings, then a campaign of the samples (its reports and
# overview); the campaign's pages are then opened in headless Chromium, checked as a reader
# sees them, and screenshotted into build/browser/ (skipped, saying so, without Chromium).
reproduce: $(STAMP)
	MPLCONFIGDIR=$$(mktemp -d) $(PY) -m pipeline.cli reproduce --samples data_samples --out build/reproduce
	MPLCONFIGDIR=$$(mktemp -d) $(PY) -m pipeline.cli campaign data_samples --out build/campaign
	$(PY) scripts/browser.py build/campaign --shots build/browser

# The documentation site: the user guide (docs/*.md), the examples' gallery (examples/, each
# script run), the API reference from the docstrings. Warnings are errors. Open
# build/docs/html/index.html. Nitpicky (-n): a cross-reference that reaches nothing fails it.
docs: $(STAMP)
	MPLCONFIGDIR=$$(mktemp -d) $(PY) -m sphinx -b html -n -W --keep-going -q -d build/docs/doctrees docs build/docs/html

bench: $(STAMP)
	MPLCONFIGDIR=$$(mktemp -d) $(PY) -m benchmarks --out build/bench

data: $(STAMP)
	$(PY) scripts/make_samples.py --out data_samples
	$(PY) scripts/make_format_samples.py --out data_samples

lint: $(STAMP)
	$(PY) -m ruff check pipeline tests benchmarks scripts examples docs

clean:
	rm -rf build .pytest_cache docs/auto_examples docs/reference .venv-min
