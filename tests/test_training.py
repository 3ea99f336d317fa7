"""Training and evaluation with Stable-Baselines3: SB3's env checks, parameter sharing, learning, files, CLI."""

from __future__ import annotations

import json
import tempfile
import warnings
from pathlib import Path

import gymnasium
import numpy as np
import pytest
import torch
from stable_baselines3 import PPO
from stable_baselines3.common.env_checker import check_env
from stable_baselines3.common.logger import Logger

import envs  # noqa: F401  (registers the Gymnasium ids)
from envs.evaluation import evaluate
from envs.training import latest_checkpoint, make_vec_env, train
from teamsim.cli import main

MODES = [(obs, act) for obs in ("truth", "percepts") for act in ("continuous", "discrete")]
SMALL_SOCCER = {"players_per_team": 2, "observation": "truth", "action_type": "discrete", "start": "playing"}
# a tiny PPO: updates every 64 steps of each env copy
TINY_PPO = {"n_steps": 64, "batch_size": 64, "n_epochs": 2}
SHORT_STRIKER = {"action_type": "discrete", "max_cycles": 40}
TEN_STEPS = ["--timesteps", "10", "--out", "X"]


@pytest.fixture(autouse=True)
def _one_torch_thread() -> None:
    """PPO built directly (not through train) uses one thread too: a second is far slower on 2 busy cores."""
    torch.set_num_threads(1)


@pytest.mark.parametrize("task", ["teamsim/Striker-v0", "teamsim/Keeper-v0"])
@pytest.mark.parametrize(("observation", "action_type"), MODES)
def test_sb3_check_env_passes_without_warnings(task: str, observation: str, action_type: str) -> None:
    env = gymnasium.make(task, observation=observation, action_type=action_type, max_cycles=20)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # SB3 reports problems (space bounds, dtypes, ...) as warnings
        check_env(env.unwrapped)


def test_soccer_parameter_sharing_one_policy_for_all_agents() -> None:
    venv = make_vec_env("soccer_v0", 2, 0, {**SMALL_SOCCER, "max_cycles": 32}, None)
    assert venv.num_envs == 4  # 2 agents x 2 matches -> 4 slots of one vector env
    model = PPO("MlpPolicy", venv, seed=0, device="cpu", **TINY_PPO)
    model.set_logger(Logger(folder=None, output_formats=[]))  # SB3's default makes a directory in /tmp
    model.learn(512)  # two rollouts of 64 steps x 4 slots
    assert model.num_timesteps == 512
    # 512 / 4 slots = 128 decisions per agent: every agent finished four 32-decision matches
    assert len(model.ep_info_buffer) == 16
    assert all(int(info["l"]) == 32 for info in model.ep_info_buffer)
    # one network: the same observation gives the same action whatever the slot
    obs = venv.reset()
    actions, _ = model.predict(np.repeat(obs[:1], 4, axis=0), deterministic=True)
    assert len(set(actions.tolist())) == 1
    venv.close()


def test_soccer_vec_env_is_seeded() -> None:
    def first_obs(seed: int) -> np.ndarray:
        venv = make_vec_env("soccer_v0", 2, seed, {**SMALL_SOCCER, "start": "kickoff"}, None)
        obs = venv.reset()
        venv.close()
        return obs

    a, b = first_obs(0), first_obs(0)
    np.testing.assert_array_equal(a, b)


@pytest.mark.slow(seconds=60)
def test_ppo_learns_to_score_better_than_random(tmp_path: Path) -> None:
    """PPO on Striker-v0 (truth, discrete macro-actions) beats uniform random macros on the same episodes.

    One decision a second (each macro runs 10 cognition frames) and 15 s episodes keep the
    credit assignment short, so ~2,000 decisions (~140 episodes, ~30 s) are enough; without the
    approach reward, walking to the ball and standing there pays nothing, and only kicks that
    move the ball toward the goal (and goals) do. Checked on seeds 0, 1, 2: trained mean returns
    2.0 / 2.3 / 2.7 with 3 / 5 / 4 goals in 20 episodes, random 0.05 / 0.3 / 1.1 with 0 / 0 / 1.
    """
    kw = {
        "action_type": "discrete",
        "decision_hz": 1.0,
        "cognition_hz": 10.0,
        "max_cycles": 15,
        "reward_weights": {"goal": 10.0, "ball_progress": 1.0, "ball_approach": 0.0, "penalty": 1.0},
    }
    hp = {"n_steps": 32, "batch_size": 64, "learning_rate": 1e-3}
    model = train("teamsim/Striker-v0", "ppo", 2048, tmp_path, env_kwargs=kw, hyperparams=hp, progress_bar=False)
    trained = evaluate(model, "teamsim/Striker-v0", episodes=20, seed=100)
    baseline = evaluate("random", "teamsim/Striker-v0", episodes=20, seed=100, env_kwargs=kw)
    assert [e["seed"] for e in trained.episodes] == [e["seed"] for e in baseline.episodes]
    assert trained.mean_return > baseline.mean_return + 1.0, (trained.format(), baseline.format())
    assert trained.goals_for > baseline.goals_for, (trained.format(), baseline.format())


def test_train_writes_config_checkpoints_model_and_resumes(tmp_path: Path) -> None:
    out = tmp_path / "run"
    kw = {"seed": 1, "env_kwargs": SHORT_STRIKER, "n_envs": 2, "hyperparams": TINY_PPO, "progress_bar": False}
    model_path = train("teamsim/Striker-v0", timesteps=256, out_dir=out, checkpoint_every=128, **kw)
    assert model_path == out / "model.zip" and model_path.is_file()
    config = json.loads((out / "config.json").read_text())
    assert config["env_id"] == "teamsim/Striker-v0" and config["timesteps"] == 256
    assert config["env_kwargs"] == SHORT_STRIKER and config["hyperparams"]["n_steps"] == 64
    assert sorted(p.name for p in (out / "checkpoints").iterdir()) == ["ppo_128_steps.zip", "ppo_256_steps.zip"]
    assert any((out / "tb").rglob("events.out.tfevents.*"))
    with pytest.raises(ValueError, match="already holds checkpoints"):
        train("teamsim/Striker-v0", timesteps=256, out_dir=out, **kw)
    train("teamsim/Striker-v0", timesteps=384, out_dir=out, checkpoint_every=128, resume=True, **kw)
    assert latest_checkpoint(out) == out / "checkpoints" / "ppo_384_steps.zip"
    assert PPO.load(out / "model.zip", device="cpu").num_timesteps == 384
    a2c = {**kw, "hyperparams": {"n_steps": 64}}  # valid for a2c: the resume check is what refuses
    with pytest.raises(ValueError, match="cannot resume: algo"):
        train("teamsim/Striker-v0", algo="a2c", timesteps=512, out_dir=out, resume=True, **a2c)


def test_train_without_tensorboard_writes_only_into_its_out_dir(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    system_tmp = tmp_path / "system-tmp"
    system_tmp.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(system_tmp))  # where SB3's own logger makes SB3-<time>
    monkeypatch.setattr("envs.training._tensorboard_available", lambda: False)
    kw = {"env_kwargs": SHORT_STRIKER, "n_envs": 2, "hyperparams": TINY_PPO, "progress_bar": False}
    train("teamsim/Striker-v0", timesteps=128, out_dir=tmp_path / "run", verbose=1, **kw)
    assert [p.name for p in system_tmp.iterdir() if p.name.startswith("SB3-")] == []  # torch may cache there
    written = sorted(p.name for p in (tmp_path / "run").iterdir())
    assert written == ["checkpoints", "config.json", "model.zip", "monitor"]
    assert "total_timesteps" in capsys.readouterr().out  # verbose=1 still prints SB3's training table


def test_train_is_deterministic_for_a_seed(tmp_path: Path) -> None:
    kw = {"env_kwargs": SHORT_STRIKER, "n_envs": 2, "hyperparams": TINY_PPO, "progress_bar": False}
    params = []
    for name in ("a", "b"):
        path = train("teamsim/Striker-v0", timesteps=128, out_dir=tmp_path / name, seed=3, **kw)
        params.append(PPO.load(path, device="cpu").policy.parameters_to_vector())
    np.testing.assert_array_equal(params[0], params[1])


def test_evaluate_reports_episodes_and_resumes_from_jsonl(tmp_path: Path) -> None:
    kw = {"env_kwargs": SHORT_STRIKER, "n_envs": 2, "hyperparams": TINY_PPO, "progress_bar": False}
    model = train("teamsim/Striker-v0", timesteps=128, out_dir=tmp_path / "run", **kw)
    log = tmp_path / "eval.jsonl"
    # the environment arguments come from the run's config.json (discrete actions, 40 decisions)
    first = evaluate(model, "teamsim/Striker-v0", episodes=3, seed=5, out=log)
    assert first.env_kwargs == SHORT_STRIKER
    assert [e["episode"] for e in first.episodes] == [0, 1, 2]
    for e in first.episodes:
        assert 1 <= e["length"] <= 40
        assert e["outcome"] in {"scored", "conceded", "out", "penalised", "time"}
        assert e["goals_for"] == int(e["outcome"] == "scored")
    assert len(log.read_text().splitlines()) == 3
    again = evaluate(model, "teamsim/Striker-v0", episodes=4, seed=5, out=log)
    assert again.episodes[:3] == first.episodes
    assert len(log.read_text().splitlines()) == 4
    fresh = evaluate(model, "teamsim/Striker-v0", episodes=4, seed=5)  # deterministic: same episodes
    assert [e["return"] for e in fresh.episodes] == [e["return"] for e in again.episodes]
    with pytest.raises(ValueError, match="another evaluation"):
        evaluate("random", "teamsim/Striker-v0", episodes=4, seed=5, out=log)
    text = again.format()
    assert "goals for" in text and "episodes         4" in text


@pytest.mark.slow(seconds=12)
@pytest.mark.parametrize(
    ("env_id", "env_kwargs"), [("teamsim/Striker-v0", SHORT_STRIKER), ("soccer_v0", {**SMALL_SOCCER, "max_cycles": 30})]
)
def test_worker_processes_train_the_same_model_as_one_process(env_id: str, env_kwargs: dict, tmp_path: Path) -> None:
    """``processes`` only moves the environments into worker processes: the rollouts, and so the
    trained weights, are the same bit for bit as in one process."""
    params = []
    for processes in (1, 2):
        path = train(
            env_id, timesteps=128, out_dir=tmp_path / str(processes), seed=5, env_kwargs=env_kwargs, n_envs=2,
            hyperparams=TINY_PPO, progress_bar=False, processes=processes,
        )  # fmt: skip
        params.append(PPO.load(path, device="cpu").policy.parameters_to_vector())
        assert json.loads((tmp_path / str(processes) / "config.json").read_text())["processes"] == processes
    np.testing.assert_array_equal(params[0], params[1])


def test_worker_process_counts_are_checked_before_anything_is_written(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"processes \(3\) must not exceed n_envs \(2\)"):
        train("soccer_v0", timesteps=10, out_dir=tmp_path, n_envs=2, processes=3)
    with pytest.raises(ValueError, match="one copy per worker process: processes must be 1 or n_envs"):
        train("teamsim/Striker-v0", timesteps=10, out_dir=tmp_path, n_envs=4, processes=2)
    with pytest.raises(ValueError, match=r"processes must be an integer in 1\.\.256"):
        train("teamsim/Striker-v0", timesteps=10, out_dir=tmp_path, processes=0)
    assert not any(tmp_path.iterdir())


def test_evaluate_soccer_plays_matches_with_the_shared_policy(tmp_path: Path) -> None:
    kw = {**SMALL_SOCCER, "max_cycles": 30}
    model = train(
        "soccer_v0", timesteps=128, out_dir=tmp_path / "run", env_kwargs=kw, hyperparams=TINY_PPO, progress_bar=False
    )
    report = evaluate(model, "soccer_v0", episodes=2)
    assert [e["length"] for e in report.episodes] == [30, 30]
    assert all(e["outcome"] in {"won", "lost", "draw"} for e in report.episodes)
    assert evaluate("random", "soccer_v0", episodes=1, env_kwargs=kw).episodes[0]["length"] == 30


@pytest.mark.parametrize(
    ("algo", "action_type", "hyperparams"),
    [
        ("a2c", "discrete", {"n_steps": 8}),
        ("sac", "continuous", {"learning_starts": 32, "batch_size": 32, "buffer_size": 1000}),
    ],
)
def test_a2c_and_sac_train_and_evaluate(algo: str, action_type: str, hyperparams: dict, tmp_path: Path) -> None:
    kw = {"action_type": action_type, "max_cycles": 20}
    opts = {"env_kwargs": kw, "n_envs": 1, "hyperparams": hyperparams, "progress_bar": False}
    model = train("teamsim/Striker-v0", algo, 64, tmp_path, **opts)
    report = evaluate(model, "teamsim/Striker-v0", episodes=1)  # the algorithm is read from config.json
    assert report.env_kwargs == kw and len(report.episodes) == 1


def test_errors_are_clear(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="unknown environment 'teamsim/Goalie-v0'"):
        train("teamsim/Goalie-v0", timesteps=10, out_dir=tmp_path)
    with pytest.raises(ValueError, match="unknown algorithm 'dqn'"):
        train("teamsim/Striker-v0", algo="dqn", timesteps=10, out_dir=tmp_path)
    with pytest.raises(ValueError, match="timesteps must be a positive integer"):
        train("teamsim/Striker-v0", timesteps=0, out_dir=tmp_path)
    with pytest.raises(ValueError, match="sac needs continuous actions"):
        train("teamsim/Striker-v0", algo="sac", timesteps=10, out_dir=tmp_path, env_kwargs={"action_type": "discrete"})
    with pytest.raises(FileNotFoundError, match="model file not found"):
        evaluate(tmp_path / "nothing.zip", "teamsim/Striker-v0")
    with pytest.raises(ValueError, match="unknown environment"):
        evaluate("random", "Striker")
    assert not any(tmp_path.iterdir())  # nothing was written by a refused call


def test_cli_train_and_evaluate(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "run"
    common = ["--env", "teamsim/Striker-v0", "--action-type", "discrete", "--env-kwargs", '{"max_cycles": 30}']
    budget = ["--timesteps", "256", "--n-envs", "2", "--hyperparams", json.dumps(TINY_PPO)]
    assert main(["train", *common, *budget, "--out", str(out), "--no-progress"]) == 0
    assert "model written to" in capsys.readouterr().out
    assert (out / "model.zip").is_file()
    log = tmp_path / "eval.jsonl"
    trained = ["--model", str(out / "model.zip"), "--env", "teamsim/Striker-v0"]
    assert main(["evaluate", *trained, "--episodes", "2", "--out", str(log)]) == 0
    text = capsys.readouterr().out
    assert "goals for" in text and "outcomes" in text and "episodes written to" in text
    assert len(log.read_text().splitlines()) == 2
    assert main(["evaluate", "--model", "random", *common, "--episodes", "1"]) == 0
    assert "evaluation of random" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["train", "--env", "Pong-v5", *TEN_STEPS], "unknown environment 'Pong-v5'"),
        (["train", "--env", "soccer_v0", "--algo", "ddpg", *TEN_STEPS], "unknown algorithm"),
        (["train", "--env", "soccer_v0", "--timesteps", "-5", "--out", "X"], "--timesteps: must be in 1..10"),
        (
            ["train", "--env", "teamsim/Keeper-v0", "--algo", "sac", "--action-type", "discrete", *TEN_STEPS],
            "sac needs continuous actions",
        ),
        (["train", "--env", "soccer_v0", *TEN_STEPS, "--env-kwargs", "[1]"], "JSON object"),
        (["train", "--env", "soccer_v0", *TEN_STEPS, "--envs", "0"], "--envs: must be in 1..256"),
        (["train", "--env", "teamsim/Striker-v0", *TEN_STEPS, "--envs", "3", "--n-envs", "4"], "processes must be 1"),
        (["evaluate", "--model", "missing/model.zip", "--env", "teamsim/Striker-v0"], "model file not found"),
    ],
)
def test_cli_errors(argv: list[str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    argv = [str(tmp_path / a) if a in ("X", "missing/model.zip") else a for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert f"teamsim {argv[0]}: error:" in err and message in err
