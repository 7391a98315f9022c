# Every target sets itself up: a .venv with the CPU torch wheel and the package in dev mode.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: setup run test lint bench docs clean reproduce status extras

setup: $(STAMP)

$(STAMP): pyproject.toml
	test -d $(VENV) || $(PYTHON) -m venv $(VENV)
	$(BIN)/pip install -q --upgrade pip
	$(BIN)/pip install -q torch==2.13.0
	$(BIN)/pip install -q -e '.[dev]'
	touch $(STAMP)

# The main job: A2C on Zelda's human level 4, a curve that rises within minutes (docs/results.md).
run: $(STAMP)
	$(BIN)/gvgai-pcg train condition=zelda-lv4 env.obs=tiles model=compact device=cpu total_frames=1500000
	@echo "gvgai-pcg is installed in $(VENV)/bin: '. $(VENV)/bin/activate' puts it on this shell's PATH"

test: $(STAMP)
	$(BIN)/ruff check gvgai_pcg tests
	$(BIN)/ruff format --check gvgai_pcg tests
	$(BIN)/pytest -q -n 2

lint: $(STAMP)
	$(BIN)/ruff format gvgai_pcg tests
	$(BIN)/ruff check --fix gvgai_pcg tests

# The study from sweep to Table 1 (BUDGET=smoke|small|medium|paper; JOBS runs side by side), or the
# curricula comparison (BUDGET=curricula, issue 36); resumable, and what results/BUDGET holds
# finished is not trained again. A smoke test leaves the page alone; the others write their own.
# BORROW=reproduce/medium takes the runs that sweep trained exactly as this one would (curricula).
BUDGET ?= smoke
JOBS ?= 2
PAGE := $(if $(filter smoke curricula-smoke,$(BUDGET)),,--budget-page)
reproduce: $(STAMP)
	$(BIN)/gvgai-pcg reproduce --budget $(BUDGET) --jobs $(JOBS) --out reproduce/$(BUDGET) --publish results/$(BUDGET) $(PAGE) $(if $(BORROW),--borrow-from $(BORROW))

# Where `make reproduce` stands: each run's frames and state, and the run-hours left.
status: $(STAMP)
	$(BIN)/gvgai-pcg reproduce --budget $(BUDGET) --jobs $(JOBS) --out reproduce/$(BUDGET) --publish results/$(BUDGET) --status $(if $(BORROW),--borrow-from $(BORROW))

# DEVICE=cuda measures the GPU alone; left out, the CPU is measured, and CUDA too where there is one.
DEVICE ?=
bench: $(STAMP)
	$(BIN)/gvgai-pcg bench --output docs/benchmarks.md $(if $(DEVICE),--device $(DEVICE))

docs: $(STAMP)
	$(BIN)/mkdocs build --strict

clean:
	rm -rf $(VENV) build *.egg-info

# Every optional extra installs into a fresh venv (with the newest pip, as `make setup` has) and does
# its job there (CI runs it after `make test`): an extra that pip can only satisfy with an old,
# unbuildable release fails here, not for a user.
EXTRAS ?= slurm ray joblib tensorboard wandb
extras:
	@set -e; for extra in $(EXTRAS); do \
	  tmp=$$(mktemp -d); $(PYTHON) -m venv $$tmp/venv; \
	  echo "== pip install '.[$$extra]' in a fresh venv"; \
	  $$tmp/venv/bin/pip install -q --upgrade pip; \
	  $$tmp/venv/bin/pip install -q torch==2.13.0 ".[$$extra]"; \
	  (cd $$tmp && $$tmp/venv/bin/python $(CURDIR)/tests/extras_check.py $$extra); \
	  rm -rf $$tmp; \
	done
