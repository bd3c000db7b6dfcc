# The README's two commands: `make demo` and `make test`. Each sets itself up first
# (.ci/setup.sh: apt packages, .venv, pip install -e .); a second run skips what is there.
# `make test` runs pytest, then builds the docs and checks them in a headless browser.
PY      := .venv/bin/python
MPIENV  := OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
OUT     ?= out
DEMO    ?= hopper_membrane

SPHINX  := /usr/bin/python3 -m sphinx
DOCS_OUT := docs/_build

.PHONY: setup demo test test-slow bench clean docs docs-check gallery

setup:
	@bash .ci/setup.sh

demo: setup
	$(MPIENV) $(PY) -m gsi.cli run demos/$(DEMO).toml --out $(OUT)/$(DEMO) --overwrite

test: setup
	$(MPIENV) NUMBA_NUM_THREADS=2 $(PY) -m pytest -q -ra --durations=15 tests
	$(MAKE) --no-print-directory docs docs-check SETUP_DONE=1

# The documentation (Debian's python3-sphinx, python3-myst-parser, furo; see .ci/setup.sh):
# warnings are errors. The key reference, validation, performance and gallery pages are
# generated at build time (docs/_ext/gsi_docs.py). The system python runs Sphinx (the venv's pyvista
# pulls markdown-it-py 4 from PyPI, which Debian's myst-parser 0.18 refuses); conf.py
# puts this checkout first on sys.path, so autodoc imports this gsi.
docs: $(if $(SETUP_DONE),,setup)
	@start=$$(date +%s); \
	PYTHONPATH=$(CURDIR) $(SPHINX) -W --keep-going -b html -q docs $(DOCS_OUT)/html && \
	echo "docs: $(DOCS_OUT)/html/index.html ($$(( $$(date +%s) - start )) s)"

# Serve the built site on localhost, open it in headless chromium: screenshots of the
# landing page and a demo page in docs/_build/screenshots/; broken internal links or
# images that fail to load fail this step.
docs-check: $(if $(SETUP_DONE),,setup)
	/usr/bin/python3 docs/check_site.py

# Run every demo's --quick form into docs/_build/gallery/<name>/ (up to ~2 min each on
# 2 cores); the next `make docs` shows their monitor plots and summaries in the gallery.
GALLERY ?= pour hopper_membrane thermal_silo drum belt_hopper two_structures \
           thermal_silo_radiation plate_on_block drum_extrapolation kiln
gallery: setup
	@mkdir -p $(DOCS_OUT)/gallery
	@for d in $(GALLERY); do \
	  echo "gallery: $$d --quick"; \
	  $(MPIENV) $(PY) -m gsi.cli run demos/$$d.toml --quick --overwrite \
	    --out $(DOCS_OUT)/gallery/$$d > $(DOCS_OUT)/gallery-$$d.log 2>&1 || \
	    { echo "gallery: $$d failed (see $(DOCS_OUT)/gallery-$$d.log)"; exit 1; }; \
	done
	$(MAKE) --no-print-directory docs SETUP_DONE=1

test-slow: setup
	$(MPIENV) $(PY) -m pytest -q -ra -m slow tests

# Each benchmark's last key=value line is appended, with date, host CPU and command, to
# benchmarks/results/<name>.json (benchmarks/record.py); the docs' Performance page shows them.
bench: setup
	EXTRA_DEBS=liggghts bash .ci/setup.sh
	$(MPIENV) $(PY) benchmarks/record.py settle -- $(PY) benchmarks/settle.py --vs-liggghts
	$(MPIENV) $(PY) benchmarks/record.py fe_step -- $(PY) benchmarks/fe_step.py
	$(PY) benchmarks/record.py engine_compile -- $(PY) benchmarks/engine_compile.py

clean:
	rm -rf out .pytest_cache docs/_build docs/_generated
	find gsi benchmarks -name '*.nbi' -delete -o -name '*.nbc' -delete
	rm -rf "$$HOME/.cache/gsi"    # numba's cache of the kernels (gsi/jit.py)
