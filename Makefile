# tether_sim: every target first brings .venv/ up to date (tools/setup_env.sh: quick when nothing changed).
#   make run    the main job (ROPOS validation run end to end)
#   make test   the test suite
#   make bench  the benchmark scripts (benchmarks/*.py), figures for BENCHMARKS.md
#   make setup  only the environment; make clean removes it and the build outputs
SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c
PY := .venv/bin/python
# pytest options: PYTEST_ARGS="-k foo" make test
PYTEST_ARGS ?=
PYTEST_WORKERS ?= 2

.PHONY: setup run test bench docs clean
.DEFAULT_GOAL := test

setup:
	@tools/setup_env.sh

run: setup
	$(PY) -m tether_sim.ros.main_job

# TETHER_SIM_REQUIRE_ROS=1: a missing rclpy fails the ROS tests instead of skipping them
test: setup
	TETHER_SIM_REQUIRE_ROS=1 $(PY) -m pytest -q -n $(PYTEST_WORKERS) --dist loadfile $(PYTEST_ARGS)

bench: setup
	@shopt -s nullglob; scripts=(benchmarks/*.py); \
	if (( $${#scripts[@]} == 0 )); then echo "no benchmarks/*.py yet"; fi; \
	for script in "$${scripts[@]}"; do echo "== $$script"; $(PY) "$$script"; done

docs: setup
	$(PY) tools/gen_param_docs.py

clean:
	rm -rf .venv build install log .pytest_cache out *.egg-info
	find . -name __pycache__ -type d -prune -exec rm -rf {} +
