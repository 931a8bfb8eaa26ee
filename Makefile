# linkwork: the two set-up commands are `make demo` and `make test`.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed-$(shell cat pyproject.toml | cksum | cut -d' ' -f1)

.PHONY: demo test lint bench clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(STAMP): $(BIN)/python pyproject.toml
	$(BIN)/python -m pip install --quiet -e ".[test]"
	rm -f $(VENV)/.installed-*
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/linkwork analyze examples/sine_press.toml --out demo-output
	@echo "demo output written to demo-output/"

lint: $(STAMP)
	$(BIN)/ruff check linkwork tests benchmarks docs
	$(BIN)/mypy
	$(BIN)/lint-imports

test: $(STAMP) lint
	MPLBACKEND=Agg $(BIN)/python -m pytest -q

bench: $(STAMP)
	$(BIN)/python -m pip install --quiet -e ".[test,bench]"
	$(BIN)/python benchmarks/kinematics.py
	$(BIN)/python benchmarks/swashplate_synthesis.py
	$(BIN)/python benchmarks/tolerance_study.py
	$(BIN)/python benchmarks/machine.py
	$(BIN)/python benchmarks/cli.py
	$(BIN)/python benchmarks/long_cycle.py
	$(BIN)/python benchmarks/synthesis.py
	$(BIN)/python benchmarks/forces.py

clean:
	rm -rf $(VENV) demo-output linkwork-output dist .pytest_cache .mypy_cache .ruff_cache
