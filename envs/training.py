"""Training policies on the teamsim environments with Stable-Baselines3.

```python
from envs.evaluation import evaluate
from envs.training import train

model = train("teamsim/Striker-v0", timesteps=50_000, out_dir="out/ppo_striker",
              env_kwargs={"action_type": "discrete"})
print(evaluate(model, "teamsim/Striker-v0", episodes=50).format())
```

The command line does the same: ``teamsim train ...`` (:mod:`teamsim.cli`). No paper
describes this training setup. Evaluating a trained policy (``teamsim evaluate``: goals and
outcomes per episode) is :mod:`envs.evaluation`, which imports the environment and algorithm
helpers of this module (never the other way round). Training needs the ``train`` extra
(``pip install -e '.[train]'``: torch pinned to the CPU build, stable-baselines3, supersuit,
tensorboard, tqdm, rich).

Environments (``env_id``):

=====================  =====================================================================================
id                     how it is trained
=====================  =====================================================================================
teamsim/Striker-v0     Gymnasium task; ``n_envs`` copies in a ``DummyVecEnv``, each wrapped in ``Monitor``
teamsim/Keeper-v0      Gymnasium task; as above
soccer_v0              PettingZoo parallel env; parameter sharing: SuperSuit turns the N agents of one match
                       into N vector-env slots (``pettingzoo_env_to_vec_env_v1``), ``n_envs`` matches are
                       concatenated (``concat_vec_envs_v1``) and wrapped in ``VecMonitor``; one policy plays
                       every agent
=====================  =====================================================================================

Options of :func:`train`:

====================  ==========================================================================================
option                meaning
====================  ==========================================================================================
``algo``              ``ppo`` (default), ``a2c`` or ``sac`` (continuous actions only)
``timesteps``         environment steps (decisions) in total, over all vector-env slots; > 0 (SB3 rounds it up
                      to whole rollouts of ``n_steps`` x slots)
``out_dir``           ``config.json`` (written first), ``checkpoints/`` (``ALGO_<steps>_steps.zip``),
                      ``monitor/`` (per-episode CSV of the Gymnasium tasks), ``tb/`` (TensorBoard, when
                      tensorboard is installed) and ``model.zip`` at the end
``seed``              seeds the policy, the environments (copy ``i`` gets ``seed + i``) and SB3
``env_kwargs``        keyword arguments of the environment (:class:`envs.core.EnvConfig` fields)
``n_envs``            environment copies (default 4 for the tasks, 1 match for ``soccer_v0``)
``checkpoint_every``  environment steps between checkpoints (default 10,000)
``progress_bar``      SB3's progress bar (needs tqdm and rich)
``hyperparams``       keyword arguments of the SB3 algorithm over :data:`DEFAULT_HYPERPARAMS`
``resume``            continue from the latest checkpoint in ``out_dir/checkpoints`` (the environments
                      start new episodes, so a resumed run is not bit-identical to an uninterrupted one)
``torch_threads``     torch CPU threads (default 1: on 2 busy cores a second OpenMP thread made the PPO update
                      up to 100 times slower; None leaves torch's setting)
====================  ==========================================================================================

Interrupting :func:`train` (Ctrl-C) saves a checkpoint of the model so far before the
``KeyboardInterrupt`` propagates. On CPU a run is deterministic for a given seed (the same
``model.zip`` bit for bit).

Reference (2 shared cores): ``teamsim train --env teamsim/Striker-v0 --action-type discrete
--timesteps 120000`` runs at about 520 decisions/s (4 min) and the policy scores in 22 of 50
evaluation episodes, against 3 for random macro-actions and 0 for random continuous actions;
it learned to call ``kick_to_goal`` (or the identical ``pass``) every time, which is what the
best constant macro-action scores too.
"""

from __future__ import annotations

import json
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np

ENV_IDS: tuple[str, ...] = ("teamsim/Striker-v0", "teamsim/Keeper-v0", "soccer_v0")
"""Environments :func:`train` and :func:`envs.evaluation.evaluate` know."""
ALGOS: tuple[str, ...] = ("ppo", "a2c", "sac")
"""Stable-Baselines3 algorithms by name."""
DEFAULT_HYPERPARAMS: dict[str, dict[str, Any]] = {
    # batches of n_steps x slots decisions; a drill episode is 30-300 decisions
    "ppo": {"n_steps": 256, "batch_size": 256, "n_epochs": 10, "gamma": 0.99, "learning_rate": 3e-4, "ent_coef": 0.01},
    "a2c": {"n_steps": 16, "gamma": 0.99, "ent_coef": 0.01},
    "sac": {"learning_starts": 1000, "buffer_size": 100_000, "batch_size": 256, "gamma": 0.99},
}
"""Hyperparameters of each algorithm unless ``hyperparams`` overrides them."""
CHECKPOINT_EVERY = 10_000
"""Default environment steps between checkpoints."""
_CHECKPOINT = re.compile(r"^(?P<algo>[a-z0-9]+)_(?P<steps>\d+)_steps\.zip$")


class TrainingDependencyError(ImportError):
    """Stable-Baselines3 / torch / SuperSuit are missing (install the ``train`` extra)."""


def _sb3() -> Any:
    """Import Stable-Baselines3 or explain how to install it."""
    try:
        import stable_baselines3
    except ImportError as exc:  # pragma: no cover - depends on the installation
        raise TrainingDependencyError(
            "training needs stable-baselines3 and torch: pip install -e '.[train]' "
            "(torch is pinned to the CPU build there)"
        ) from exc
    return stable_baselines3


def algo_class(algo: str) -> Any:
    """The Stable-Baselines3 class of ``algo`` (``ppo``, ``a2c``, ``sac``)."""
    if algo not in ALGOS:
        raise ValueError(f"unknown algorithm {algo!r}; valid: {list(ALGOS)}")
    sb3 = _sb3()
    return {"ppo": sb3.PPO, "a2c": sb3.A2C, "sac": sb3.SAC}[algo]


def check_env_id(env_id: str) -> None:
    """Raise ``ValueError`` unless ``env_id`` is one of :data:`ENV_IDS`."""
    if env_id not in ENV_IDS:
        raise ValueError(f"unknown environment {env_id!r}; valid: {list(ENV_IDS)}")


def make_env(env_id: str, env_kwargs: Mapping[str, Any] | None = None) -> Any:
    """One environment: a Gymnasium env for the tasks, a PettingZoo parallel env for ``soccer_v0``."""
    check_env_id(env_id)
    kwargs = dict(env_kwargs or {})
    if env_id == "soccer_v0":
        from envs import soccer_v0

        return soccer_v0.parallel_env(**kwargs)
    import envs  # noqa: F401  (registers the Gymnasium ids)

    return gymnasium.make(env_id, **kwargs)


def agent_spaces(env_id: str, env: Any) -> tuple[gymnasium.Space, gymnasium.Space]:
    """Observation and action space of one agent of ``env`` (a :func:`make_env` env of ``env_id``)."""
    if env_id == "soccer_v0":
        agent = env.possible_agents[0]
        return env.observation_space(agent), env.action_space(agent)
    return env.observation_space, env.action_space


def _spaces(env_id: str, env_kwargs: Mapping[str, Any] | None) -> tuple[gymnasium.Space, gymnasium.Space]:
    """Observation and action space of one agent (builds the env, which checks the arguments)."""
    env = make_env(env_id, env_kwargs)
    try:
        return agent_spaces(env_id, env)
    finally:
        env.close()


def make_vec_env(env_id: str, n_envs: int, seed: int, env_kwargs: Mapping[str, Any] | None, monitor_dir: Path | None):
    """The SB3 vector env of the module table, seeded with ``seed`` (copy ``i``: ``seed + i``)."""
    check_env_id(env_id)
    _sb3()
    from stable_baselines3.common.env_util import make_vec_env as sb3_make_vec_env
    from stable_baselines3.common.vec_env import DummyVecEnv, VecMonitor

    if env_id != "soccer_v0":
        import envs  # noqa: F401  (registers the Gymnasium ids)

        return sb3_make_vec_env(
            env_id,
            n_envs=n_envs,
            seed=seed,
            env_kwargs=dict(env_kwargs or {}),
            vec_env_cls=DummyVecEnv,
            monitor_dir=None if monitor_dir is None else str(monitor_dir),
        )
    try:
        import supersuit
        from supersuit.vector.sb3_vector_wrapper import SB3VecEnvWrapper
    except ImportError as exc:  # pragma: no cover - depends on the installation
        raise TrainingDependencyError("soccer_v0 training needs supersuit: pip install -e '.[train]'") from exc

    class SeededSB3VecEnv(SB3VecEnvWrapper):
        """SuperSuit's SB3 wrapper, with SB3's ``seed()`` passed to the next ``reset``.

        SuperSuit's wrapper forwards ``seed`` to a Gymnasium vector env that has no ``seed``
        method and resets without a seed; here match copy ``i`` is reset with ``seed + i``.
        """

        _pending_seed: int | None = None

        def seed(self, seed: int | None = None) -> list[int | None]:
            self._pending_seed = seed
            return [seed] * self.num_envs

        def reset(self, seed: int | None = None, options: dict[str, Any] | None = None) -> Any:
            seed = self._pending_seed if seed is None else seed
            self._pending_seed = None
            observations, self.reset_infos = self.venv.reset(seed=seed, options=options)
            return observations

        def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
            if attr_name == "render_mode":  # the Gymnasium vector env below has no get_attr for it
                return [self.render_mode] * self.num_envs
            return super().get_attr(attr_name, indices)

    venv = supersuit.pettingzoo_env_to_vec_env_v1(make_env(env_id, env_kwargs))
    venv = supersuit.concat_vec_envs_v1(venv, n_envs, num_cpus=0, base_class="gymnasium")
    sb3_venv = SeededSB3VecEnv(venv)
    sb3_venv.seed(seed)
    return VecMonitor(sb3_venv)


def latest_checkpoint(out_dir: str | Path) -> Path | None:
    """The checkpoint with the most steps in ``out_dir/checkpoints`` (``None`` if there is none)."""
    found = [
        (int(m["steps"]), p) for p in Path(out_dir, "checkpoints").glob("*.zip") if (m := _CHECKPOINT.match(p.name))
    ]
    return max(found)[1] if found else None


def jsonable(value: Any) -> Any:
    """``value`` as plain JSON types (dataclasses and mappings as dicts, tuples as lists)."""
    if hasattr(value, "__dataclass_fields__"):
        return {k: jsonable(getattr(value, k)) for k in value.__dataclass_fields__}
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [jsonable(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def _progress_bar_available() -> bool:
    try:
        import rich  # noqa: F401
        import tqdm  # noqa: F401
    except ImportError:
        return False
    return True


def train(
    env_id: str,
    algo: str = "ppo",
    timesteps: int = 100_000,
    out_dir: str | Path = "out/train",
    seed: int = 0,
    env_kwargs: Mapping[str, Any] | None = None,
    n_envs: int | None = None,
    checkpoint_every: int = CHECKPOINT_EVERY,
    progress_bar: bool = True,
    hyperparams: Mapping[str, Any] | None = None,
    resume: bool = False,
    torch_threads: int | None = 1,
    verbose: int = 0,
) -> Path:
    """Train a policy on ``env_id`` and save it; returns the path of ``out_dir/model.zip``.

    Options in the module table. Raises ``ValueError`` for an unknown environment or
    algorithm, non-positive ``timesteps``/``n_envs``/``checkpoint_every``, SAC with
    discrete actions, or checkpoints in ``out_dir`` without ``resume``.
    """
    check_env_id(env_id)
    cls = algo_class(algo)
    if not isinstance(timesteps, int) or isinstance(timesteps, bool) or timesteps <= 0:
        raise ValueError(f"timesteps must be a positive integer, got {timesteps!r}")
    if n_envs is None:
        n_envs = 1 if env_id == "soccer_v0" else 4
    if not isinstance(n_envs, int) or n_envs < 1:
        raise ValueError(f"n_envs must be a positive integer, got {n_envs!r}")
    if not isinstance(checkpoint_every, int) or checkpoint_every < 1:
        raise ValueError(f"checkpoint_every must be a positive integer, got {checkpoint_every!r}")
    env_kwargs = dict(env_kwargs or {})
    _, action_space = _spaces(env_id, env_kwargs)  # also checks the env arguments before anything is written
    if algo == "sac" and not isinstance(action_space, gymnasium.spaces.Box):
        raise ValueError("sac needs continuous actions; use action_type='continuous' or algo 'ppo'/'a2c'")
    out = Path(out_dir)
    checkpoint = latest_checkpoint(out)
    if checkpoint is not None and not resume:
        raise ValueError(f"{out} already holds checkpoints of a run; pass resume=True (--resume) or another out_dir")
    params = {**DEFAULT_HYPERPARAMS[algo], **dict(hyperparams or {})}
    config = {
        "env_id": env_id,
        "algo": algo,
        "timesteps": timesteps,
        "out_dir": str(out),
        "seed": seed,
        "env_kwargs": jsonable(env_kwargs),
        "n_envs": n_envs,
        "checkpoint_every": checkpoint_every,
        "progress_bar": progress_bar,
        "hyperparams": jsonable(params),
        "resume": resume,
        "torch_threads": torch_threads,
    }
    if resume and (out / "config.json").is_file():
        before = json.loads((out / "config.json").read_text())
        for key in ("env_id", "algo", "env_kwargs"):
            if before.get(key) != config[key]:
                raise ValueError(f"cannot resume: {key} was {before.get(key)!r} in {out}, now {config[key]!r}")
    out.mkdir(parents=True, exist_ok=True)
    (out / "config.json").write_text(json.dumps(config, indent=2) + "\n")

    from stable_baselines3.common.callbacks import CheckpointCallback
    from stable_baselines3.common.utils import set_random_seed

    set_torch_threads(torch_threads)
    set_random_seed(seed)
    venv = make_vec_env(env_id, n_envs, seed, env_kwargs, None if env_id == "soccer_v0" else out / "monitor")
    slots = venv.num_envs
    tb = str(out / "tb") if _tensorboard_available() else None
    if checkpoint is not None:
        model = cls.load(checkpoint, env=venv, device="cpu", tensorboard_log=tb)
        model.set_random_seed(seed + model.num_timesteps)
    else:
        model = cls("MlpPolicy", venv, seed=seed, device="cpu", tensorboard_log=tb, verbose=verbose, **params)
    remaining = timesteps - model.num_timesteps
    callback = CheckpointCallback(
        save_freq=max(1, checkpoint_every // slots), save_path=str(out / "checkpoints"), name_prefix=algo
    )
    try:
        if remaining > 0:
            model.learn(
                total_timesteps=remaining,
                callback=callback,
                progress_bar=progress_bar and _progress_bar_available(),
                reset_num_timesteps=checkpoint is None,
                tb_log_name=algo,
            )
    except KeyboardInterrupt:
        model.save(out / "checkpoints" / f"{algo}_{model.num_timesteps}_steps.zip")
        raise
    finally:
        venv.close()
    model.save(out / "model.zip")
    return out / "model.zip"


def set_torch_threads(threads: int | None) -> None:
    """Set torch's CPU threads (``None``: leave them).

    One thread is the default: on 2 cores shared with the simulator (and other processes), a
    second OpenMP thread made a PPO update of the 64 x 64 MLP up to 100 times slower.
    """
    if threads is not None:
        _sb3()
        import torch

        torch.set_num_threads(threads)


def _tensorboard_available() -> bool:
    try:
        import tensorboard  # noqa: F401
    except ImportError:
        return False
    return True
