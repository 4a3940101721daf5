# tether_sim: every target first brings .venv/ up to date (tools/setup_env.sh: quick when nothing changed).
#   make run    the main job (ROPOS validation run end to end)
#   make test   the test suite
#   make bench  the quick benchmark figures (full ladders: commands in BENCHMARKS.md)
#   make setup  only the environment (incl. the numba compile of the solver kernels when the sources
#               changed); make clean removes it and the build outputs
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
# then the kernel twin tests once more with the JIT off (the kernels as plain Python; ~1 min)
test: setup
	TETHER_SIM_REQUIRE_ROS=1 $(PY) -m pytest -q -n $(PYTEST_WORKERS) --dist loadfile $(PYTEST_ARGS)
	NUMBA_DISABLE_JIT=1 $(PY) -m pytest -q -p no:cacheprovider -m jit_off test/solvers/dg test/numerics/test_colour_map.py test/physics/test_waves.py test/physics/test_snap.py test/network/test_network_dynamics.py

bench: setup
	# the quick figures (a few minutes); the full ladders of BENCHMARKS.md are run by hand (commands there)
	$(PY) benchmarks/bench_dg.py
	$(PY) benchmarks/bench_solvers.py --duration 2 --scenario-duration 0.05
	$(PY) benchmarks/bench_moordyn.py --lengths 1730 --segments 20 40 80

docs: setup
	$(PY) tools/gen_param_docs.py

clean:
	rm -rf .venv build install log .pytest_cache out *.egg-info
	find . -name __pycache__ -type d -prune -exec rm -rf {} +
