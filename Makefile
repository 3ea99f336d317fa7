# Convenience targets; the README Quickstart commands work without make.
.PHONY: install match test lint bench studies train-install

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
	python -m benchmarks.bench_vision --json out/bench_vision.json
	python -m benchmarks.bench_localization --json out/bench_localization.json
	python -m benchmarks.bench_worldmodel --json out/bench_worldmodel.json
	python -m benchmarks.bench_envs --json out/bench_envs.json
	python -m benchmarks.bench_training --json out/bench_training.json
	python -m benchmarks.bench_match --stages --json out/bench_match.json
	python -m benchmarks.bench_calls --json out/bench_calls.json
	python -m benchmarks.soak --json out/soak.json

# the reports in docs/studies (README tables come from them); resumable: run again after a stop
studies:
	pip install -e '.[studies]'
	teamsim compare --scenario kidnap-standing --seeds 20 --out docs/studies/kidnap-standing
	teamsim compare --scenario kidnap-with-pickup --seeds 20 --out docs/studies/kidnap-with-pickup
	teamsim compare --scenario lines-vs-no-lines --seeds 20 --out docs/studies/lines-vs-no-lines
	teamsim compare --scenario ball-noise ball-noise-rolling --seeds 20 --out docs/studies/ball-noise
	teamsim compare --scenario penalties-spl2010 penalties-spl2025 --seeds 10 --out docs/studies/penalties
	teamsim compare --scenario kidnap-during-play --seeds 10 --out docs/studies/kidnap-during-play
	teamsim compare --scenario percepts-vs-images --seeds 10 --out docs/studies/percepts-vs-images

# torch first, pinned: an unpinned torch pulls a multi-GB CUDA build
train-install:
	pip install torch==2.13.0 && pip install -e '.[all]'
