PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: generate check-generated build test test-interpreted lint bench demo clean

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[test]"
	touch $(STAMP)

generate: $(STAMP)
	PYTHONHASHSEED=0 $(PY) -m symbolic.generate

check-generated: $(STAMP)
	PYTHONHASHSEED=0 $(PY) -m symbolic.generate --check
	PYTHONHASHSEED=1 $(PY) -m symbolic.generate --check

build: $(STAMP)
	$(VENV)/bin/pkm build

lint: $(STAMP)
	$(VENV)/bin/ruff check .

test: $(STAMP)
	$(VENV)/bin/ruff check .
	MPLBACKEND=Agg $(PY) -m pytest -n 2 --dist loadfile

test-interpreted: $(STAMP)
	PKM_COMPILED=0 MPLBACKEND=Agg $(PY) -m pytest -n 2 --dist loadfile -W ignore::pkm.compiled.CompiledPathWarning

bench: $(STAMP)
	MPLBACKEND=Agg $(PY) -m bench.run

demo: $(STAMP)
	MPLBACKEND=Agg $(VENV)/bin/pkm reproduce gao1998 --out out

clean:
	rm -rf $(VENV) out
