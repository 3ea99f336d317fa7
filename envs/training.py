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
teamsim/Striker-v0     Gymnasium task; ``n_envs`` copies in a ``DummyVecEnv`` (``processes`` 1) or a
                       ``SubprocVecEnv`` (one worker process per copy), each wrapped in ``Monitor``
teamsim/Keeper-v0      Gymnasium task; as above
soccer_v0              PettingZoo parallel env; parameter sharing: SuperSuit turns the N agents of one match
                       into N vector-env slots (``pettingzoo_env_to_vec_env_v1``), ``n_envs`` matches are
                       concatenated (``concat_vec_envs_v1``, spread over ``processes`` worker processes) and
                       wrapped in ``VecMonitor``; one policy plays every agent
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
                      tensorboard is installed) and ``model.zip`` at the end. A directory that holds a model
                      or checkpoints is refused unless ``resume`` or ``overwrite`` is given
``seed``              seeds the policy, the environments (copy ``i`` gets ``seed + i``) and SB3; 0..2**31 - 1
``env_kwargs``        keyword arguments of the environment (:class:`envs.core.EnvConfig` fields; another key
                      is an error naming it)
``n_envs``            environment copies, 1..256 (default 4 for the tasks, 1 match for ``soccer_v0``; with
                      ``processes`` > 1 and no ``n_envs``: one copy per process)
``processes``         worker processes that step the environments, 1..``n_envs`` (default 1: in the training
                      process). The tasks run one copy per process (``SubprocVecEnv``), so ``processes`` is 1
                      or ``n_envs``; ``soccer_v0`` spreads its matches over them. The observations, and so the
                      trained model, are the same bit for bit as with 1 process. The workers start a fresh
                      interpreter (forkserver), so a script that calls :func:`train` with ``processes`` > 1
                      needs an ``if __name__ == "__main__":`` guard
``checkpoint_every``  environment steps between checkpoints (default 10,000)
``progress_bar``      SB3's progress bar (needs tqdm and rich)
``hyperparams``       keyword arguments of the SB3 algorithm over :data:`DEFAULT_HYPERPARAMS`; checked
                      before anything is written (:func:`check_hyperparams`)
``resume``            continue from the latest checkpoint in ``out_dir/checkpoints`` (the environments
                      start new episodes, so a resumed run is not bit-identical to an uninterrupted one)
``overwrite``         delete the earlier run's files in ``out_dir`` (``model.zip``, ``config.json``,
                      checkpoints, monitor CSVs, TensorBoard runs; nothing else) before training
``torch_threads``     torch CPU threads (default 1: on 2 busy cores a second OpenMP thread made the PPO update
                      up to 100 times slower; None leaves torch's setting)
====================  ==========================================================================================

Interrupting :func:`train` (Ctrl-C) saves a checkpoint of the model so far before the
``KeyboardInterrupt`` propagates. On CPU a run is deterministic for a given seed (the same
``model.zip`` bit for bit).

Worker processes pay off when stepping the environments costs more than the policy update: on
the 2-core machine see the scaling figures of ``benchmarks/bench_training.py`` in the README.

Reference (2 shared cores): ``teamsim train --env teamsim/Striker-v0 --action-type discrete
--timesteps 120000`` runs at about 520 decisions/s (4 min) and the policy scores in 22 of 50
evaluation episodes, against 3 for random macro-actions and 0 for random continuous actions;
it learned to call ``kick_to_goal`` (or the identical ``pass``) every time, which is what the
best constant macro-action scores too.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import json
import math
import re
import shutil
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import gymnasium
import numpy as np

if TYPE_CHECKING:  # SB3 is an optional extra, imported where it is used
    from stable_baselines3.common.logger import Logger

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
MAX_SEED = 2**31 - 1
"""Largest seed of :func:`train` and :func:`envs.evaluation.evaluate` (numpy's legacy seeding takes 32 bits,
and a resumed run seeds with ``seed + steps``)."""
MAX_ENVS = 256
"""Most environment copies :func:`train` builds."""
_CHECKPOINT = re.compile(r"^(?P<algo>[a-z0-9]+)_(?P<steps>\d+)_steps\.zip$")
_TB_RUN = re.compile(r"^(" + "|".join(ALGOS) + r")_\d+$")
_MONITOR = re.compile(r"^\d+\.monitor\.csv$")
_SET_BY_TRAIN = ("policy", "env", "seed", "device", "tensorboard_log", "verbose", "_init_setup_model")
"""Constructor arguments of the SB3 algorithms that :func:`train` sets itself (not hyperparameters)."""
_NUMERIC_HYPERPARAMS: dict[str, tuple[type, float, float, bool]] = {
    # name: (int or float, low, high, low excluded); None is allowed for clip_range_vf and target_kl
    "learning_rate": (float, 0.0, math.inf, True),
    "n_steps": (int, 1, 1_000_000, False),
    "batch_size": (int, 1, 1_000_000, False),
    "n_epochs": (int, 1, 10_000, False),
    "gamma": (float, 0.0, 1.0, False),
    "gae_lambda": (float, 0.0, 1.0, False),
    "clip_range": (float, 0.0, math.inf, True),
    "clip_range_vf": (float, 0.0, math.inf, True),
    "ent_coef": (float, 0.0, math.inf, False),
    "vf_coef": (float, 0.0, math.inf, False),
    "max_grad_norm": (float, 0.0, math.inf, True),
    "target_kl": (float, 0.0, math.inf, True),
    "buffer_size": (int, 1, 10_000_000, False),
    "learning_starts": (int, 0, 10**12, False),
    "tau": (float, 0.0, 1.0, False),
    "gradient_steps": (int, -1, 1_000_000, False),
    "target_update_interval": (int, 1, 10**12, False),
    "sde_sample_freq": (int, -1, 10**12, False),
    "rms_prop_eps": (float, 0.0, math.inf, True),
    "stats_window_size": (int, 1, 1_000_000, False),
}
_FLAG_HYPERPARAMS = ("normalize_advantage", "use_sde", "use_rms_prop", "optimize_memory_usage", "use_sde_at_warmup")


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


def check_env_kwargs(env_kwargs: Mapping[str, Any] | None) -> dict[str, Any]:
    """``env_kwargs`` as a dict; ``ValueError`` naming a key that is no :class:`envs.core.EnvConfig` field.

    ``TypeError`` if it is no mapping. The values are checked by the environment when it is built.
    """
    from envs.core import EnvConfig

    if env_kwargs is None:
        return {}
    if not isinstance(env_kwargs, Mapping):
        raise TypeError(f"env_kwargs must be a mapping of EnvConfig fields, got {type(env_kwargs).__name__}")
    valid = sorted(f.name for f in dataclasses.fields(EnvConfig))
    unknown = sorted(str(k) for k in env_kwargs if k not in valid)
    if unknown:
        raise ValueError(f"unknown env_kwargs key(s) {unknown}; valid keys: {valid}")
    return dict(env_kwargs)


def check_hyperparams(algo: str, hyperparams: Mapping[str, Any] | None) -> dict[str, Any]:
    """The SB3 keyword arguments of ``algo`` in ``hyperparams``, checked; errors name the key.

    Unknown keys and the arguments :func:`train` sets itself are a ``ValueError`` listing the
    valid keys. Numbers (learning rate, rollout and batch sizes, discounts, coefficients, buffer
    size ...) must have the right type (``TypeError``) and lie in their range (``ValueError``;
    sizes are bounded so that a typo cannot ask for more memory than a machine has). SAC's
    ``ent_coef`` may also be ``"auto"`` or ``"auto_<initial value>"`` and its ``train_freq`` a
    pair ``[n, "step" | "episode"]``. Other values (``policy_kwargs`` contents, ...) are left to
    the algorithm, whose errors :func:`train` reports naming the keys given.
    """
    cls = algo_class(algo)
    if hyperparams is None:
        return {}
    if not isinstance(hyperparams, Mapping):
        raise TypeError(f"hyperparams must be a mapping of {algo} arguments, got {type(hyperparams).__name__}")
    accepted = set(inspect.signature(cls.__init__).parameters) - {"self", *_SET_BY_TRAIN}
    params = dict(hyperparams)
    reserved = sorted(str(k) for k in params if k in _SET_BY_TRAIN)
    if reserved:
        raise ValueError(f"hyperparams {reserved}: set by train() itself (seed, device, logging), not a hyperparameter")
    unknown = sorted(str(k) for k in params if k not in accepted)
    if unknown:
        raise ValueError(f"unknown hyperparams key(s) {unknown} for {algo}; valid keys: {sorted(accepted)}")
    for key, value in params.items():
        where = f"hyperparams.{key}"
        if key in _FLAG_HYPERPARAMS and not isinstance(value, bool):
            raise TypeError(f"{where}: expected true or false, got {type(value).__name__} {value!r}")
        if key == "policy_kwargs" and value is not None and not isinstance(value, Mapping):
            raise TypeError(f"{where}: expected a mapping, got {type(value).__name__}")
        if key == "ent_coef" and algo == "sac" and isinstance(value, str):
            if not re.fullmatch(r"auto(_\d+(\.\d*)?([eE][-+]?\d+)?)?", value):
                raise ValueError(f"{where}: expected a number >= 0, 'auto' or 'auto_<initial value>', got {value!r}")
            continue
        if key == "train_freq" and isinstance(value, list | tuple):
            if len(value) != 2 or value[1] not in ("step", "episode"):
                raise ValueError(f"{where}: expected an integer or [n, 'step' | 'episode'], got {value!r}")
            params[key] = (_number(where, value[0], (int, 1, 10**12, False)), value[1])
            continue
        if key == "train_freq":
            _number(where, value, (int, 1, 10**12, False))
        if key in _NUMERIC_HYPERPARAMS and not (value is None and key in ("clip_range_vf", "target_kl")):
            _number(where, value, _NUMERIC_HYPERPARAMS[key])
    return params


def _number(where: str, value: Any, rule: tuple[type, float, float, bool]) -> Any:
    """``value`` if it is a number of ``rule`` (type, low, high, low excluded); errors name ``where``."""
    kind, low, high, open_low = rule
    numeric = isinstance(value, int | float) and not isinstance(value, bool)
    if not numeric or (kind is int and not isinstance(value, int)):
        wanted = "an integer" if kind is int else "a number"
        raise TypeError(f"{where}: expected {wanted}, got {type(value).__name__} {value!r}")
    if not math.isfinite(value) or value < low or (open_low and value == low) or value > high:
        interval = f"{'(' if open_low else '['}{low:g}, {high:g}]"
        raise ValueError(f"{where} must be in {interval}, got {value!r}")
    return value


def make_env(env_id: str, env_kwargs: Mapping[str, Any] | None = None) -> Any:
    """One environment: a Gymnasium env for the tasks, a PettingZoo parallel env for ``soccer_v0``.

    Raises ``ValueError`` for an unknown environment or an ``env_kwargs`` key that is no
    :class:`envs.core.EnvConfig` field (:func:`check_env_kwargs`).
    """
    check_env_id(env_id)
    kwargs = check_env_kwargs(env_kwargs)
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


def _make_task(env_id: str, **kwargs: Any) -> gymnasium.Env:
    """``gymnasium.make(env_id, **kwargs)`` after registering the ids (runs in worker processes)."""
    import envs  # noqa: F401  (registers the Gymnasium ids)

    return gymnasium.make(env_id, **kwargs)


def check_processes(env_id: str, n_envs: int, processes: int) -> None:
    """``ValueError`` unless ``processes`` worker processes can run ``n_envs`` copies of ``env_id``."""
    if not isinstance(processes, int) or isinstance(processes, bool) or not 1 <= processes <= MAX_ENVS:
        raise ValueError(f"processes must be an integer in 1..{MAX_ENVS}, got {processes!r}")
    if processes > n_envs:
        raise ValueError(f"processes ({processes}) must not exceed n_envs ({n_envs}): each process steps whole copies")
    if env_id != "soccer_v0" and processes not in (1, n_envs):
        raise ValueError(
            f"{env_id} runs one copy per worker process: processes must be 1 or n_envs ({n_envs}), got {processes}"
        )


def make_vec_env(
    env_id: str,
    n_envs: int,
    seed: int,
    env_kwargs: Mapping[str, Any] | None,
    monitor_dir: Path | None,
    processes: int = 1,
):
    """The SB3 vector env of the module table, seeded with ``seed`` (copy ``i``: ``seed + i``),
    stepped in ``processes`` worker processes (1: in this process)."""
    check_env_id(env_id)
    check_processes(env_id, n_envs, processes)
    _sb3()
    from stable_baselines3.common.env_util import make_vec_env as sb3_make_vec_env
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv, VecMonitor

    if env_id != "soccer_v0":
        import envs  # noqa: F401  (registers the Gymnasium ids)

        return sb3_make_vec_env(
            # a worker process imports nothing of teamsim by itself: its factory registers the ids first
            env_id if processes == 1 else functools.partial(_make_task, env_id),
            n_envs=n_envs,
            seed=seed,
            env_kwargs=dict(env_kwargs or {}),
            vec_env_cls=DummyVecEnv if processes == 1 else SubprocVecEnv,
            # forkserver: the workers start from a clean interpreter, not a copy of torch's threads
            vec_env_kwargs=None if processes == 1 else {"start_method": "forkserver"},
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
    cpus = 0 if processes == 1 else processes  # SuperSuit: 0 steps the matches in this process
    venv = supersuit.concat_vec_envs_v1(venv, n_envs, num_cpus=cpus, base_class="gymnasium")
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
    overwrite: bool = False,
    processes: int = 1,
) -> Path:
    """Train a policy on ``env_id`` and save it; returns the path of ``out_dir/model.zip``.

    Options in the module table. Everything is checked before anything is written: raises
    ``ValueError`` for an unknown environment or algorithm, ``timesteps``, ``n_envs``,
    ``processes`` (:func:`check_processes`), ``checkpoint_every`` or ``seed`` out of range, bad
    ``env_kwargs`` or ``hyperparams`` (naming the key), SAC with discrete actions, ``resume``
    with ``overwrite``, a model or checkpoints in ``out_dir`` without ``resume`` or
    ``overwrite``, ``resume`` of a run with another environment or algorithm, or ``resume`` of
    a finished run without checkpoints.
    """
    check_env_id(env_id)
    cls = algo_class(algo)
    if not isinstance(timesteps, int) or isinstance(timesteps, bool) or timesteps <= 0:
        raise ValueError(f"timesteps must be a positive integer, got {timesteps!r}")
    if n_envs is None:
        many = isinstance(processes, int) and not isinstance(processes, bool) and processes > 1
        n_envs = processes if many else (1 if env_id == "soccer_v0" else 4)
    if not isinstance(n_envs, int) or isinstance(n_envs, bool) or not 1 <= n_envs <= MAX_ENVS:
        raise ValueError(f"n_envs must be an integer in 1..{MAX_ENVS}, got {n_envs!r}")
    check_processes(env_id, n_envs, processes)
    if not isinstance(checkpoint_every, int) or isinstance(checkpoint_every, bool) or checkpoint_every < 1:
        raise ValueError(f"checkpoint_every must be a positive integer, got {checkpoint_every!r}")
    if not isinstance(seed, int) or isinstance(seed, bool) or not 0 <= seed <= MAX_SEED:
        raise ValueError(f"seed must be an integer in 0..{MAX_SEED}, got {seed!r}")
    if resume and overwrite:
        raise ValueError("resume and overwrite exclude each other: continue the run in out_dir or replace it")
    env_kwargs = check_env_kwargs(env_kwargs)
    user_params = check_hyperparams(algo, hyperparams)
    _, action_space = _spaces(env_id, env_kwargs)  # also checks the env arguments before anything is written
    if algo == "sac" and not isinstance(action_space, gymnasium.spaces.Box):
        raise ValueError("sac needs continuous actions; use action_type='continuous' or algo 'ppo'/'a2c'")
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise ValueError(f"out_dir {out} exists and is not a directory")
    checkpoint = latest_checkpoint(out)
    has_model = (out / "model.zip").exists()
    if (checkpoint is not None or has_model) and not (resume or overwrite):
        found = (("checkpoints", checkpoint is not None), ("model.zip", has_model))
        held = " and ".join(name for name, present in found if present)
        raise ValueError(
            f"{out} already holds {held} of a run; pass resume=True (--resume) to continue it, "
            "overwrite=True (--overwrite) to replace it, or another out_dir"
        )
    if resume and checkpoint is None and has_model:
        raise ValueError(
            f"cannot resume: {out} holds model.zip but no checkpoint to continue from; "
            "pass overwrite=True (--overwrite) to replace it, or another out_dir"
        )
    params = {**DEFAULT_HYPERPARAMS[algo], **user_params}
    config = {
        "env_id": env_id,
        "algo": algo,
        "timesteps": timesteps,
        "out_dir": str(out),
        "seed": seed,
        "env_kwargs": jsonable(env_kwargs),
        "n_envs": n_envs,
        "processes": processes,
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
    if overwrite:
        checkpoint = None
        _delete_run(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "config.json").write_text(json.dumps(config, indent=2) + "\n")

    from stable_baselines3.common.callbacks import CheckpointCallback
    from stable_baselines3.common.utils import set_random_seed

    set_torch_threads(torch_threads)
    set_random_seed(seed)
    monitor = None if env_id == "soccer_v0" else out / "monitor"
    venv = make_vec_env(env_id, n_envs, seed, env_kwargs, monitor, processes)
    slots = venv.num_envs
    tb = str(out / "tb") if _tensorboard_available() else None
    if checkpoint is not None:
        model = cls.load(checkpoint, env=venv, device="cpu", tensorboard_log=tb)
        model.set_random_seed(seed + model.num_timesteps)
    else:
        try:
            model = cls("MlpPolicy", venv, seed=seed, device="cpu", tensorboard_log=tb, verbose=verbose, **params)
        except (AssertionError, ValueError, TypeError) as exc:  # SB3 checks its arguments with assert
            venv.close()
            if not user_params:
                raise
            raise ValueError(f"hyperparams {sorted(user_params)}: {algo} rejects them: {exc}") from exc
    if tb is None:  # SB3's own logger would make an empty SB3-<time> directory in the system's temp dir
        model.set_logger(_console_logger(verbose))
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


def _delete_run(out: Path) -> None:
    """Delete what :func:`train` wrote into ``out`` (and nothing else): model, config, checkpoints, logs."""
    for name in ("model.zip", "config.json"):
        (out / name).unlink(missing_ok=True)
    for folder, pattern in (("checkpoints", _CHECKPOINT), ("monitor", _MONITOR), ("tb", _TB_RUN)):
        path = out / folder
        if not path.is_dir():
            continue
        for item in path.iterdir():
            if pattern.match(item.name) and item.is_dir():
                shutil.rmtree(item)
            elif pattern.match(item.name):
                item.unlink()
        if not any(path.iterdir()):
            path.rmdir()


def set_torch_threads(threads: int | None) -> None:
    """Set torch's CPU threads (``None``: leave them).

    One thread is the default: on 2 cores shared with the simulator (and other processes), a
    second OpenMP thread made a PPO update of the 64 x 64 MLP up to 100 times slower.
    """
    if threads is not None:
        _sb3()
        import torch

        torch.set_num_threads(threads)


def _console_logger(verbose: int) -> Logger:
    """An SB3 logger that writes no files: the training table to stdout when ``verbose`` >= 1,
    else nothing (what SB3 logs without tensorboard, minus the directory it makes for that)."""
    import sys

    from stable_baselines3.common.logger import HumanOutputFormat, Logger

    return Logger(folder=None, output_formats=[HumanOutputFormat(sys.stdout)] if verbose >= 1 else [])


def _tensorboard_available() -> bool:
    try:
        import tensorboard  # noqa: F401
    except ImportError:
        return False
    return True
