"""Evaluating policies on the teamsim environments: goals, outcomes and returns per episode.

```python
from envs.evaluation import evaluate

print(evaluate("out/ppo_striker/model.zip", "teamsim/Striker-v0", episodes=50).format())
print(evaluate("random", "teamsim/Striker-v0", episodes=50, env_kwargs={"action_type": "discrete"}).format())
```

The command line does the same: ``teamsim evaluate ...`` (:mod:`teamsim.cli`). A saved model
needs the ``train`` extra (``pip install -e '.[train]'``); policies are trained with
:func:`envs.training.train`, whose environments, algorithms and ``config.json`` this module
reuses (the dependency is one-way: :mod:`envs.training` does not import this module). No
paper describes this evaluation protocol.

:func:`evaluate` plays ``episodes`` episodes with the deterministic policy (or uniform random
actions for ``model="random"``) and returns an :class:`EvaluationReport`: goals for and
against, outcome counts and returns. Episode ``i`` is reset with a seed derived from
``(seed, i)`` (:func:`episode_seed`), so a trained policy and the random baseline meet the
same situations. With ``out`` it appends one JSON line per episode as it finishes and, run
again, skips the episodes the file already holds; a file with episodes of another evaluation
(another model file or content - each line carries the model's SHA-256 -, environment,
environment arguments or seed) is refused, never mixed. The environment keyword arguments default
to those the model was trained with (its ``config.json``); ``env_kwargs`` override them. For
``soccer_v0`` an episode is a match: the shared policy plays every agent of the controlled
team(s), goals are counted from the first agent's team's view and the outcome is ``won``,
``lost`` or ``draw`` (:func:`match_outcome`).
"""

from __future__ import annotations

import hashlib
import json
import math
import time
from collections import Counter
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np

from envs.training import (
    ALGOS,
    MAX_SEED,
    agent_spaces,
    algo_class,
    check_env_id,
    check_env_kwargs,
    jsonable,
    make_env,
    set_torch_threads,
)


@dataclass
class EvaluationReport:
    """The result of :func:`evaluate`: one dict per episode and totals over them.

    Each entry of ``episodes`` has ``episode`` (index), ``seed`` (its reset seed),
    ``goals_for``, ``goals_against``, ``outcome``, ``return`` (the agent's summed reward; for
    ``soccer_v0`` the mean over the agents) and ``length`` (decisions).
    """

    model: str
    env_id: str
    seed: int
    env_kwargs: dict[str, Any]
    episodes: list[dict[str, Any]] = field(default_factory=list)
    seconds: float = 0.0
    """Wall time of the episodes played by this call (resumed ones excluded), s."""

    @property
    def goals_for(self) -> int:
        """Goals scored over all episodes."""
        return sum(int(e["goals_for"]) for e in self.episodes)

    @property
    def goals_against(self) -> int:
        """Goals conceded over all episodes."""
        return sum(int(e["goals_against"]) for e in self.episodes)

    @property
    def outcomes(self) -> dict[str, int]:
        """Episodes per outcome."""
        return dict(Counter(str(e["outcome"]) for e in self.episodes).most_common())

    @property
    def mean_return(self) -> float:
        """Mean episode return (NaN without episodes)."""
        return float(np.mean([e["return"] for e in self.episodes])) if self.episodes else math.nan

    @property
    def std_return(self) -> float:
        """Standard deviation of the episode return (NaN without episodes)."""
        return float(np.std([e["return"] for e in self.episodes])) if self.episodes else math.nan

    @property
    def mean_length(self) -> float:
        """Mean episode length in decisions (NaN without episodes)."""
        return float(np.mean([e["length"] for e in self.episodes])) if self.episodes else math.nan

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-able summary and episodes."""
        return {
            "model": self.model,
            "env_id": self.env_id,
            "seed": self.seed,
            "env_kwargs": self.env_kwargs,
            "n_episodes": len(self.episodes),
            "goals_for": self.goals_for,
            "goals_against": self.goals_against,
            "outcomes": self.outcomes,
            "mean_return": self.mean_return,
            "std_return": self.std_return,
            "mean_length": self.mean_length,
            "episodes": self.episodes,
        }

    def format(self) -> str:
        """A readable report."""
        n = len(self.episodes)
        scored = sum(1 for e in self.episodes if e["goals_for"] > 0)
        kw = ", ".join(f"{k}={v}" for k, v in sorted(self.env_kwargs.items())) or "defaults"
        lines = [
            f"evaluation of {self.model} on {self.env_id} ({kw}; seed {self.seed})",
            f"  episodes         {n}",
            f"  goals for        {self.goals_for}  (episodes with a goal: {scored}/{n})",
            f"  goals against    {self.goals_against}",
            "  outcomes         " + ", ".join(f"{k} {v}" for k, v in self.outcomes.items()),
            f"  return           {self.mean_return:.2f} +- {self.std_return:.2f} (mean +- std)",
            f"  length           {self.mean_length:.1f} decisions (mean)",
        ]
        if self.seconds > 0:
            lines.append(f"  wall time        {self.seconds:.1f} s")
        return "\n".join(lines)


def episode_seed(seed: int, episode: int) -> int:
    """The reset seed of evaluation episode ``episode`` (the same for every model)."""
    return int(np.random.SeedSequence([int(seed), int(episode)]).generate_state(1)[0])


def match_outcome(goals_for: int, goals_against: int) -> str:
    """``won``, ``lost`` or ``draw`` of a ``soccer_v0`` match from the controlled team's view."""
    if goals_for > goals_against:
        return "won"
    return "lost" if goals_for < goals_against else "draw"


def _training_config(model_path: Path) -> dict[str, Any] | None:
    """The ``config.json`` of the run that wrote ``model_path`` (beside it, or above ``checkpoints/``)."""
    for folder in (model_path.parent, model_path.parent.parent):
        path = folder / "config.json"
        if path.is_file():
            try:
                data = json.loads(path.read_text())
            except json.JSONDecodeError:
                return None
            if isinstance(data, dict) and data.get("algo") in ALGOS:
                return data
    return None


def load_model(model_path: str | Path) -> Any:
    """Load a saved SB3 model; the algorithm is read from the run's ``config.json`` or tried in turn."""
    path = Path(model_path)
    if not path.is_file():
        raise FileNotFoundError(f"model file not found: {path} (train one with 'teamsim train ... --out DIR')")
    config = _training_config(path)
    algos = [config["algo"]] if config else list(ALGOS)
    errors = []
    for name in algos:
        try:
            return algo_class(name).load(path, device="cpu")
        except Exception as exc:  # SB3 raises many kinds for a file of another algorithm
            errors.append(f"{name}: {exc}")
    raise ValueError(f"cannot load {path} as a Stable-Baselines3 model: {'; '.join(errors)}")


def model_digest(model_path: str | Path) -> str:
    """SHA-256 (hex) of a saved model file: two evaluations of different models never share a log."""
    digest = hashlib.sha256()
    with Path(model_path).open("rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _read_jsonl(path: Path, key: dict[str, Any]) -> list[dict[str, Any]]:
    """Episodes already in ``path`` that belong to this evaluation (``key``); rewrites a torn last line.

    ``ValueError`` naming the file and line for a line of another evaluation or one that is
    no episode record.
    """
    if not path.is_file():
        return []
    good: list[dict[str, Any]] = []
    torn = False
    for number, line in enumerate(path.read_text().splitlines(), 1):
        if not line.strip():
            continue
        try:
            entry = json.loads(line)
        except json.JSONDecodeError:
            torn = True  # an interrupted write; the episode is played again
            continue
        episode = entry.get("episode") if isinstance(entry, dict) else None
        if not isinstance(episode, int) or isinstance(episode, bool) or episode < 0:
            raise ValueError(f"{path} line {number} is no episode record of 'teamsim evaluate'; use another --out file")
        for k, v in key.items():
            if entry.get(k) != v:
                raise ValueError(
                    f"{path} line {number} belongs to another evaluation ({k}={entry.get(k)!r}, now {v!r}); "
                    "use another --out file"
                )
        good.append(entry)
    if torn:
        path.write_text("".join(json.dumps(e) + "\n" for e in good))
    return good


def evaluate(
    model_path: str | Path,
    env_id: str,
    episodes: int = 50,
    seed: int = 0,
    env_kwargs: Mapping[str, Any] | None = None,
    out: str | Path | None = None,
    torch_threads: int | None = 1,
) -> EvaluationReport:
    """Play ``episodes`` episodes of ``env_id`` with a saved model or ``"random"`` actions (module docstring).

    ``torch_threads`` sets torch's CPU threads (None: leave them). Raises ``FileNotFoundError``
    for a missing model file and ``ValueError`` for an unknown environment, ``episodes < 1``, or
    a model whose spaces do not fit the environment.
    """
    check_env_id(env_id)
    if not isinstance(episodes, int) or isinstance(episodes, bool) or episodes < 1:
        raise ValueError(f"episodes must be a positive integer, got {episodes!r}")
    if not isinstance(seed, int) or isinstance(seed, bool) or not 0 <= seed <= MAX_SEED:
        raise ValueError(f"seed must be an integer in 0..{MAX_SEED}, got {seed!r}")
    if out is not None and Path(out).exists() and not Path(out).is_file():
        raise ValueError(f"out {out} exists and is not a file (a JSONL file of episodes)")
    model = None
    kwargs: dict[str, Any] = {}
    name = str(model_path)
    digest = None
    if name != "random":
        set_torch_threads(torch_threads)
        model = load_model(model_path)
        digest = model_digest(model_path)
        trained = _training_config(Path(model_path))
        if trained is not None:
            kwargs.update(trained.get("env_kwargs") or {})
    kwargs.update(check_env_kwargs(env_kwargs))
    env = make_env(env_id, kwargs)
    try:
        obs_space, act_space = agent_spaces(env_id, env)
        if model is not None and (model.observation_space != obs_space or model.action_space != act_space):
            raise ValueError(
                f"the model does not fit {env_id} with {kwargs or 'default arguments'}: it was trained on "
                f"observations {model.observation_space} and actions {model.action_space}, the environment has "
                f"{obs_space} and {act_space} (check --action-type and the environment arguments)"
            )
        report = EvaluationReport(model=name, env_id=env_id, seed=seed, env_kwargs=jsonable(kwargs))
        key = {
            "model": name,
            "model_sha256": digest,
            "env_id": env_id,
            "eval_seed": seed,
            "env_kwargs": report.env_kwargs,
        }
        path = Path(out) if out is not None else None
        done: dict[int, dict[str, Any]] = {}
        if path is not None:
            done = {int(e["episode"]): e for e in _read_jsonl(path, key)}
            path.parent.mkdir(parents=True, exist_ok=True)
        start = time.perf_counter()
        for i in range(episodes):
            if i in done:
                report.episodes.append(done[i])
                continue
            play = _play_match if env_id == "soccer_v0" else _play_episode
            entry = {**key, "episode": i, **play(env, model, act_space, episode_seed(seed, i))}
            report.episodes.append(entry)
            if path is not None:
                with path.open("a") as f:
                    f.write(json.dumps(entry) + "\n")
        report.seconds = time.perf_counter() - start
    finally:
        env.close()
    return report


def _action(model: Any, space: gymnasium.Space, obs: np.ndarray) -> Any:
    """The deterministic policy action for a batch of observations, or one random action each."""
    if model is None:
        return [space.sample() for _ in range(len(obs))]
    actions, _ = model.predict(obs, deterministic=True)
    return list(actions)


def _play_episode(env: Any, model: Any, space: gymnasium.Space, seed: int) -> dict[str, Any]:
    """One episode of a Gymnasium task."""
    space.seed(seed)
    obs, _ = env.reset(seed=seed)
    total, length, info = 0.0, 0, {}
    done = False
    while not done:
        action = _action(model, space, np.asarray(obs)[None])[0]
        obs, reward, terminated, truncated, info = env.step(action)
        total += float(reward)
        length += 1
        done = terminated or truncated
    goals_for, goals_against = (int(v) for v in info.get("score", (0, 0)))
    return {
        "seed": seed,
        "goals_for": goals_for,
        "goals_against": goals_against,
        "outcome": info.get("outcome") or ("time" if truncated else "over"),
        "return": total,
        "length": length,
    }


def _play_match(env: Any, model: Any, space: gymnasium.Space, seed: int) -> dict[str, Any]:
    """One ``soccer_v0`` match: the shared policy plays every agent."""
    space.seed(seed)
    obs, _ = env.reset(seed=seed)
    first = env.possible_agents[0]
    totals = dict.fromkeys(env.possible_agents, 0.0)
    score, length = (0, 0), 0
    while env.agents:
        agents = list(env.agents)
        actions = _action(model, space, np.stack([obs[a] for a in agents]))
        obs, rewards, _, _, infos = env.step(dict(zip(agents, actions, strict=True)))
        for a, r in rewards.items():
            totals[a] += float(r)
        score = tuple(int(v) for v in infos[first]["score"])
        length += 1
    return {
        "seed": seed,
        "goals_for": score[0],
        "goals_against": score[1],
        "outcome": match_outcome(*score),
        "return": float(np.mean(list(totals.values()))),
        "length": length,
    }
