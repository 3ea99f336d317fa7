# Convenience targets; the README Quickstart commands work without make.
.PHONY: install match test lint bench train-install

install:
	pip install -e .

match: install
	teamsim match

test:
	pip install -e '.[dev]' && python -m pytest

lint:
	ruff check . && ruff format --check .

bench:
	python -m benchmarks.bench_physics --json out/bench_physics.json
	python -m benchmarks.bench_percepts --json out/bench_percepts.json
	python -m benchmarks.bench_images --json out/bench_images.json
	python -m benchmarks.bench_localization --json out/bench_localization.json
	python -m benchmarks.bench_worldmodel --json out/bench_worldmodel.json
	python -m benchmarks.bench_envs --json out/bench_envs.json
	python -m benchmarks.soak --json out/soak.json

# torch first, pinned: an unpinned torch pulls a multi-GB CUDA build
train-install:
	pip install torch==2.13.0 && pip install -e '.[all]'
