# Every target sets up what it needs: a newcomer types `make run` or `make test` on a fresh machine.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
NATIVE_IDAS := $(VENV)/lib/dyadc/libdyadidas.so

.PHONY: install run test fuzz bench generate clean compat

install: $(STAMP) $(NATIVE_IDAS)

$(STAMP): pyproject.toml setup.py compiler/runtime/csv_rows.c
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[dev]'
	touch $(STAMP)

# The native IDAS driver (compiler/native/build.py: SUNDIALS from a pinned source package, gcc).
# Where it cannot be built (no compiler, no network) it says why and runs use CasADi's IDAS.
$(NATIVE_IDAS): $(STAMP) $(wildcard compiler/native/dyad_idas*) compiler/native/build.py
	$(BIN)/python -m compiler.native.build || true

run: install
	$(BIN)/python -c "from compiler.render.scene_outputs import write_scene_outputs; print(*write_scene_outputs('out'), sep='\n')"

test: install
	$(BIN)/python -m pytest -n 2 tests

# The fuzz tests of `make test` with far more examples each (docs/security.md, "Fuzzing"), and the
# metamorphic tests with METAMORPHIC_EXAMPLES rewritten formulations of every model (docs/testing.md).
FUZZ_EXAMPLES ?= 2000
METAMORPHIC_EXAMPLES ?= 20
fuzz: install
	DYADC_FUZZ_EXAMPLES=$(FUZZ_EXAMPLES) $(BIN)/python -m pytest -n 2 -p no:cacheprovider tests/fuzz
	DYADC_METAMORPHIC_EXAMPLES=$(METAMORPHIC_EXAMPLES) $(BIN)/python -m pytest -n 2 -p no:cacheprovider tests/metamorphic

# `make bench CORPUS=DIR` adds the detailed op-amp of the issue-32 targets (DIR holds
# ElectricalComponents/dyad and BlockComponents/dyad, as `make compat`'s corpus does)
bench: install
	$(BIN)/python benchmarks/run_all.py $(if $(CORPUS),--corpus $(CORPUS))

generate: install
	$(BIN)/dyadc generate

# Compatibility with published Dyad code (issue 17): `make compat CORPUS=DIR`, DIR a folder of Dyad
# repositories kept outside this project; rewrites docs/compatibility.md.
compat: install
	@test -n "$(CORPUS)" || { echo "usage: make compat CORPUS=DIR (a folder of Dyad repositories)"; exit 2; }
	$(BIN)/python benchmarks/compat.py $(CORPUS) --output docs/compatibility.md

clean:
	rm -rf $(VENV) out build dist *.egg-info .pytest_cache .hypothesis
