"""The ``teamsim train`` and ``teamsim evaluate`` commands, registered from above through the
``teamsim.commands`` entry point (``teamsim`` never imports ``envs``).

=========  =======================================================================================
command    what it does
=========  =======================================================================================
train      train a policy on teamsim/Striker-v0, teamsim/Keeper-v0 or soccer_v0 with
           Stable-Baselines3 (:mod:`envs.training`; needs the train extra)
evaluate   play episodes with a trained model or random actions; report goals, outcomes and returns
           (:mod:`envs.evaluation`)
=========  =======================================================================================

The training and evaluation modules are imported when the command runs, so that ``teamsim
match`` does not load torch. Bad input ends with exit code 2 and one line naming the option.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any, TextIO

from teamsim.cli import _json_type, parse_json
from teamsim.cli_types import integer as _integer


def register(sub: Any) -> None:
    """Add ``train`` and ``evaluate`` to the ``teamsim`` subcommands (the entry point)."""
    _train_parser(sub)
    _evaluate_parser(sub)


_RL_ENV_HELP = "teamsim/Striker-v0, teamsim/Keeper-v0 or soccer_v0"
_RL_MAX_SEED = 2**31 - 1  # the same bound as envs.training.MAX_SEED (importing it would load torch)
_RL_MAX_ENVS = 256  # the same bound as envs.training.MAX_ENVS
_MAX_STEPS = 10**12


def _rl_env_args(p: Any) -> None:
    """Options of the environment shared by ``train`` and ``evaluate``."""
    p.add_argument("--env", required=True, help=f"environment: {_RL_ENV_HELP}")
    p.add_argument(
        "--seed", type=_integer(0, _RL_MAX_SEED), default=0, help=f"random seed, 0..{_RL_MAX_SEED} (default 0)"
    )
    p.add_argument("--observation", choices=["truth", "percepts"], default=None, help="observation mode")
    p.add_argument("--action-type", choices=["continuous", "discrete"], default=None, help="action type")
    p.add_argument(
        "--env-kwargs",
        default=None,
        metavar="JSON",
        help='more environment arguments as a JSON object, e.g. \'{"reward_weights": {"goal": 20}}\'',
    )


def _train_parser(sub: Any) -> None:
    p = sub.add_parser(
        "train",
        help="train a policy with Stable-Baselines3 (needs the train extra)",
        description="Train a policy on a teamsim environment. Writes OUT/config.json first, checkpoints to "
        "OUT/checkpoints, TensorBoard logs to OUT/tb and the model to OUT/model.zip. An interrupted run keeps its "
        "checkpoints; --resume continues from the latest.",
    )
    _rl_env_args(p)
    p.add_argument("--algo", default="ppo", help="ppo (default), a2c or sac (continuous actions only)")
    p.add_argument(
        "--timesteps", type=_integer(1, _MAX_STEPS), required=True, help="environment steps (decisions) in total"
    )
    p.add_argument(
        "--out",
        type=Path,
        required=True,
        help="output directory (refused if it holds a model or checkpoints: see --resume and --overwrite)",
    )
    p.add_argument(
        "--n-envs",
        type=_integer(1, _RL_MAX_ENVS),
        default=None,
        help=f"environment copies, 1..{_RL_MAX_ENVS} (default 4; soccer_v0: 1 match)",
    )
    p.add_argument(
        "--envs",
        type=_integer(1, _RL_MAX_ENVS),
        default=1,
        metavar="N",
        help="worker processes that step the environments (default 1: in the training process); the tasks run "
        "one copy per process (--n-envs defaults to N), soccer_v0 spreads its --n-envs matches over them",
    )
    p.add_argument(
        "--checkpoint-every",
        type=_integer(1, _MAX_STEPS),
        default=10_000,
        help="steps between checkpoints (default 10000)",
    )
    p.add_argument("--hyperparams", default=None, metavar="JSON", help="algorithm keyword arguments as JSON")
    p.add_argument("--resume", action="store_true", help="continue from the latest checkpoint in --out")
    p.add_argument(
        "--overwrite",
        action="store_true",
        help="delete the model, checkpoints, logs and config.json of an earlier run in --out first",
    )
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(handler=run_train)


def _evaluate_parser(sub: Any) -> None:
    p = sub.add_parser(
        "evaluate",
        help="play episodes with a trained model (or random actions) and report goals and outcomes",
        description="Evaluate a model saved by 'teamsim train' (deterministic actions) or 'random' actions. The "
        "environment arguments default to those the model was trained with. --out appends one JSON line per "
        "episode and, run again, skips the episodes the file holds.",
    )
    p.add_argument("--model", required=True, help="DIR/model.zip of 'teamsim train', or 'random'")
    _rl_env_args(p)
    p.add_argument(
        "--episodes",
        type=_integer(1, _MAX_STEPS),
        default=50,
        help="episodes (matches for soccer_v0; default 50)",
    )
    p.add_argument(
        "--out",
        type=Path,
        default=None,
        help="JSONL file of the episodes (resumable; refused if it holds episodes of another model or environment)",
    )
    p.set_defaults(handler=run_evaluate)


def _json_object(text: str | None, option: str) -> dict[str, Any]:
    """The JSON object given to ``option`` (``{}`` if it was not given)."""
    if text is None:
        return {}
    value = parse_json(text, option)
    if not isinstance(value, dict):
        raise ValueError(f"{option} must be a JSON object, got {_json_type(value)}")
    return value


def _rl_env_kwargs(args: argparse.Namespace) -> dict[str, Any]:
    kwargs = _json_object(args.env_kwargs, "--env-kwargs")
    if args.observation is not None:
        kwargs["observation"] = args.observation
    if args.action_type is not None:
        kwargs["action_type"] = args.action_type
    return kwargs


def run_train(args: argparse.Namespace, out: TextIO) -> int:
    """Run ``teamsim train`` with parsed arguments."""
    import time

    start = time.perf_counter()
    try:
        from envs.training import train

        path = train(
            args.env,
            algo=args.algo,
            timesteps=args.timesteps,
            out_dir=args.out,
            seed=args.seed,
            env_kwargs=_rl_env_kwargs(args),
            n_envs=args.n_envs,
            processes=args.envs,
            checkpoint_every=args.checkpoint_every,
            progress_bar=not args.no_progress,
            hyperparams=_json_object(args.hyperparams, "--hyperparams"),
            resume=args.resume,
            overwrite=args.overwrite,
        )
    except ImportError as exc:
        raise ValueError(f"training needs the train extra (pip install -e '.[train]'): {exc}") from exc
    except KeyboardInterrupt:
        print(f"interrupted: checkpoints kept in {args.out / 'checkpoints'}; continue with --resume", file=out)
        return 130
    seconds = time.perf_counter() - start
    rate = "" if args.resume else f" ({args.timesteps / seconds:.0f} steps/s)"
    print(f"trained {args.algo} on {args.env} to {args.timesteps} steps in {seconds:.1f} s{rate}", file=out)
    print(f"model written to {path}", file=out)
    return 0


def run_evaluate(args: argparse.Namespace, out: TextIO) -> int:
    """Run ``teamsim evaluate`` with parsed arguments."""
    try:
        from envs.evaluation import evaluate

        report = evaluate(
            args.model, args.env, episodes=args.episodes, seed=args.seed, env_kwargs=_rl_env_kwargs(args), out=args.out
        )
    except ImportError as exc:
        raise ValueError(f"evaluation needs the train extra (pip install -e '.[train]'): {exc}") from exc
    print(report.format(), file=out)
    if args.out is not None:
        print(f"episodes written to {args.out}", file=out)
    return 0
