PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: generate check-generated check-generated-after-test build test test-interpreted lint bench demo clean

# The packages are installed without their bytecode (half the install's time: plotly's, sympy's and scipy's
# thousands of modules); a module is compiled when it is first imported, and the targets below write that
# bytecode (PYTHONDONTWRITEBYTECODE unset) so that the processes after the first read it.
$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet --no-compile -e ".[test]"
	touch $(STAMP)

generate: $(STAMP)
	PYTHONDONTWRITEBYTECODE= PYTHONHASHSEED=0 $(PY) -m symbolic.generate

check-generated: $(STAMP)
	PYTHONDONTWRITEBYTECODE= PYTHONHASHSEED=0 $(PY) -m symbolic.generate --check
	PYTHONDONTWRITEBYTECODE= PYTHONHASHSEED=1 $(PY) -m symbolic.generate --check

# CI's check after the suite, whose test_generated_is_current compared generated/ with a fresh derivation under its
# worker's own (random) hash seed: one more derivation, under PYTHONHASHSEED=1, so that two seeds are compared
check-generated-after-test: $(STAMP)
	PYTHONDONTWRITEBYTECODE= PYTHONHASHSEED=1 $(PY) -m symbolic.generate --check

build: $(STAMP)
	$(VENV)/bin/pkm build

lint: $(STAMP)
	$(VENV)/bin/ruff check .

# The suite's processes (its two workers, the command lines and derivations it starts) read the bytecode
# that the first of them writes, where PYTHONDONTWRITEBYTECODE would have each compile every module again.
# Each worker is one core (tests/conftest.py): OpenBLAS's threads, which spin while they wait for work, would
# take the other worker's core.
test: $(STAMP)
	$(VENV)/bin/ruff check .
	PYTHONDONTWRITEBYTECODE= OPENBLAS_NUM_THREADS=1 MPLBACKEND=Agg $(PY) -m pytest -n 2 --dist loadfile

# The interpreter's pass runs what only it can catch: every mechanism's contract at its first random design
# (every method over large batches, which the compiled pass evaluates compiled; the other designs are the
# compiled pass's), the compiled path's fallbacks with the compiler off, the global indices and the syntheses
# (IPOPT through the interpreted integrands); the compiled pass already runs every small evaluation on the
# interpreter and compares every catalogue kernel with it.
INTERPRETED_TESTS := tests/test_contract.py tests/test_compiled.py tests/test_global_indices.py tests/test_synthesis.py

test-interpreted: $(STAMP)
	PYTHONDONTWRITEBYTECODE= OPENBLAS_NUM_THREADS=1 PKM_COMPILED=0 MPLBACKEND=Agg $(PY) -m pytest -n 2 --dist load -W ignore::pkm.compiled.CompiledPathWarning \
		-k "not -1] and not -2]" $(INTERPRETED_TESTS)

bench: $(STAMP)
	MPLBACKEND=Agg $(PY) -m bench.run

demo: $(STAMP)
	PYTHONDONTWRITEBYTECODE= MPLBACKEND=Agg $(VENV)/bin/pkm reproduce gao1998 --out out

clean:
	rm -rf $(VENV) out
