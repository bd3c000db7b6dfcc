# The README's two commands: `make demo` and `make test`. Each sets itself up first
# (.ci/setup.sh: apt packages, .venv, pip install -e .); a second run skips what is there.
PY      := .venv/bin/python
MPIENV  := OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
OUT     ?= out
DEMO    ?= hopper_membrane

.PHONY: setup demo test test-slow bench clean

setup:
	@bash .ci/setup.sh

demo: setup
	$(MPIENV) $(PY) -m gsi.cli run demos/$(DEMO).toml --out $(OUT)/$(DEMO) --overwrite

test: setup
	$(MPIENV) NUMBA_NUM_THREADS=2 $(PY) -m pytest -q -ra --durations=15 tests

test-slow: setup
	$(MPIENV) $(PY) -m pytest -q -ra -m slow tests

bench: setup
	EXTRA_DEBS=liggghts bash .ci/setup.sh
	$(MPIENV) $(PY) benchmarks/settle.py --vs-liggghts
	$(MPIENV) $(PY) benchmarks/fe_step.py

clean:
	rm -rf out .pytest_cache
	find gsi benchmarks -name '*.nbi' -delete -o -name '*.nbc' -delete
	rm -rf "$${GSI_ENGINE_DIR:-$$HOME/.cache/gsi/engines}"
