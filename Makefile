# bodyplay: `make test` and `make demo` create .venv when missing, install, and run.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: test demo lint typecheck bench clean

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev]'
	touch $(STAMP)

test: $(STAMP)
	$(PY) -m pytest -q

demo: $(STAMP)
	$(PY) -m apps.goalkeeper --headless --out out/goalkeeper

lint: $(STAMP)
	$(VENV)/bin/ruff check sdk apps tests benchmarks tools
	$(VENV)/bin/mypy

bench: $(STAMP)
	$(PY) -m pytest -q -m benchmark benchmarks tests

clean:
	rm -rf $(VENV) build *.egg-info
