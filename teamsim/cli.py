"""The ``teamsim`` command line.

=============  ==================================================================
subcommand     what it does
=============  ==================================================================
match          run a full headless match and print its summary; optionally write
               a video (MP4 or GIF: the top-down view beside one robot's camera)
               and the results to a directory
camera         run a match to given times and write robots' camera images as PNG,
               raw and with their ground-truth annotations
gallery        render the README's gallery of camera images (docs/gallery)
train          train a policy on teamsim/Striker-v0, teamsim/Keeper-v0 or soccer_v0
               with Stable-Baselines3 (:mod:`envs.training`; needs the train extra)
evaluate       play episodes with a trained model or random actions; report goals,
               outcomes and returns (:mod:`envs.evaluation`)
=============  ==================================================================

``teamsim match --out DIR`` writes ``config.json`` first, appends every event to
``events.jsonl`` as it happens (an interrupted run keeps what it computed), and writes
``summary.json`` at the end.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any, TextIO

from cognition.field import COLOUR_SCHEMES, FIELD_PRESETS
from cognition.localization import VARIANTS
from cognition.worldmodel import OBSTACLE_MODELS
from teamsim.brains import default_brains
from teamsim.events import EventLog, LogEvent
from teamsim.image_params import ImageParams
from teamsim.match import MAX_PLAYERS_PER_TEAM, OBSERVATIONS, PLAYERS, Match, MatchConfig
from teamsim.percept_params import PerceptParams


def _common_args(p: Any) -> None:
    """Options shared by the subcommands that run a match."""
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument(
        "--players-per-team",
        type=int,
        default=None,
        help=f"robots per team, 1..{MAX_PLAYERS_PER_TEAM} (default 5)",
    )
    p.add_argument("--field", choices=sorted(FIELD_PRESETS), default=None, help="field preset (default spl2025)")
    p.add_argument("--colours", choices=sorted(COLOUR_SCHEMES), default=None, help="colour scheme (default classic)")
    p.add_argument(
        "--images",
        choices=sorted(ImageParams.PRESETS),
        default=None,
        help="camera image effects preset (default: default)",
    )
    p.add_argument("--config", type=Path, default=None, help="JSON file with MatchConfig overrides")


def _match_parser(sub: Any) -> None:
    p = sub.add_parser(
        "match",
        help="run a full headless match and print its summary",
        description="Run a full match (two halves) and print a summary. By default both teams play the "
        "scripted team play on their own cognition stack (maturing localization, world model, team messages); "
        "the summary reports the localization error.",
    )
    _common_args(p)
    p.add_argument(
        "--localization",
        choices=[*VARIANTS, "none"],
        default=None,
        help="localization variant the players run and act on (default: maturing with percepts; 'none': "
        "the players read the truth)",
    )
    p.add_argument(
        "--players",
        choices=list(PLAYERS),
        default=None,
        help="brains of the home team (and of the away team without --opponents): scripted team play "
        "(default), the foundation's oracle players, or random walkers",
    )
    p.add_argument("--opponents", choices=list(PLAYERS), default=None, help="brains of the away team")
    p.add_argument(
        "--obstacles",
        choices=list(OBSTACLE_MODELS),
        default=None,
        help="obstacle model of the localizing players (default: sectors)",
    )
    p.add_argument("--half-seconds", type=float, default=None, help="length of a half in seconds (default 600)")
    p.add_argument(
        "--rules",
        choices=["spl2025", "spl2010"],
        default=None,
        help="penalty return rule set (default spl2025)",
    )
    p.add_argument(
        "--percepts",
        choices=sorted(PerceptParams.PRESETS),
        default=None,
        help="percept noise preset of the camera model (default: default)",
    )
    p.add_argument(
        "--observation",
        choices=list(OBSERVATIONS),
        default=None,
        help="what sensor frames carry: synthesized percepts, rendered images or nothing (default percepts)",
    )
    p.add_argument("--video", type=Path, default=None, help="write a video (.mp4 or .gif) of the match")
    p.add_argument("--video-fps", type=float, default=10.0, help="frames per simulated second in the video")
    p.add_argument(
        "--video-robot",
        default="auto",
        help="whose camera is shown beside the top-down view: TEAM:NUMBER (e.g. 0:3), 'auto' "
        "(team 0's highest number) or 'none' (top-down only)",
    )
    p.add_argument("--video-annotations", action="store_true", help="draw ground-truth annotations on the camera")
    p.add_argument(
        "--video-particles",
        action="store_true",
        help="draw the particles and the estimated pose of the --video-robot robot (needs --localization)",
    )
    p.add_argument("--out", type=Path, default=None, help="directory for config.json, events.jsonl, summary.json")
    p.add_argument("--events", action="store_true", help="also print the event log")


def _camera_parser(sub: Any) -> None:
    p = sub.add_parser("camera", help="write robots' camera images of a match as PNG (with annotations)")
    _common_args(p)
    p.add_argument("--time", type=float, nargs="+", default=[30.0], help="match times to take pictures at (s)")
    p.add_argument("--robot", nargs="+", default=["all"], help="TEAM:NUMBER robots, or 'all' (default)")
    p.add_argument("--size", default="320x240", help="image size WIDTHxHEIGHT (default 320x240)")
    p.add_argument("--out", type=Path, required=True, help="directory for the PNG files")


def _gallery_parser(sub: Any) -> None:
    p = sub.add_parser("gallery", help="render the README gallery of camera images")
    p.add_argument("--out", type=Path, default=Path("docs/gallery"), help="directory (default docs/gallery)")
    p.add_argument("--size", default="320x240", help="image size WIDTHxHEIGHT (default 320x240)")


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise ValueError(f"--size must be WIDTHxHEIGHT in pixels, e.g. 320x240; got {text!r}") from None
    return w, h


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``teamsim`` command."""
    parser = argparse.ArgumentParser(
        prog="teamsim",
        description="Simulator for teams of SPL-style soccer robots with a real cognition stack.",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    _match_parser(sub)
    _camera_parser(sub)
    _gallery_parser(sub)
    _train_parser(sub)
    _evaluate_parser(sub)
    return parser


def config_from_args(args: argparse.Namespace) -> MatchConfig:
    """Merge a JSON config file and the command-line options into a :class:`MatchConfig`."""
    data: dict[str, Any] = {}
    if args.config is not None:
        if not args.config.is_file():
            raise ValueError(f"config file not found: {args.config}")
        try:
            data = json.loads(args.config.read_text())
        except json.JSONDecodeError as exc:
            raise ValueError(f"config file {args.config} is not valid JSON: {exc}") from exc
        if not isinstance(data, dict):
            raise ValueError(f"config file {args.config} must hold a JSON object")
    data["seed"] = args.seed
    if args.players_per_team is not None:
        data["players_per_team"] = args.players_per_team
    if args.field is not None:
        data["field"] = args.field
    if args.colours is not None:
        data["colours"] = args.colours
    if getattr(args, "percepts", None) is not None:
        current = data.get("percepts")
        data["percepts"] = dict(current, preset=args.percepts) if isinstance(current, dict) else args.percepts
    if getattr(args, "observation", None) is not None:
        data["observation"] = args.observation
    if getattr(args, "localization", None) is not None:
        data["localization"] = None if args.localization == "none" else args.localization
    elif args.command == "match" and "localization" not in data and data.get("observation", "percepts") == "percepts":
        data["localization"] = "maturing"  # the command's default: the full cognition stack
    if getattr(args, "players", None) is not None:
        data["players"] = args.players
    if getattr(args, "obstacles", None) is not None:
        data["obstacle_model"] = args.obstacles
    if args.images is not None:
        current = data.get("images")
        data["images"] = dict(current, preset=args.images) if isinstance(current, dict) else args.images
    referee = dict(data.get("referee", {}))
    if getattr(args, "half_seconds", None) is not None:
        referee["half_seconds"] = args.half_seconds
    if getattr(args, "rules", None) is not None:
        referee["rules"] = args.rules
    if referee:
        data["referee"] = referee
    return MatchConfig.from_mapping(data)


def _jsonable(obj: Any) -> Any:
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: _jsonable(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
    if isinstance(obj, list | tuple):
        return [_jsonable(v) for v in obj]
    return obj


def run_match(args: argparse.Namespace, out: TextIO) -> int:
    """Run ``teamsim match`` with parsed arguments."""
    config = config_from_args(args)
    if args.video_fps <= 0:
        raise ValueError(f"--video-fps must be > 0, got {args.video_fps}")
    if args.video_particles:
        if args.video is None or args.video_robot == "none":
            raise ValueError("--video-particles needs --video and a --video-robot (auto or TEAM:NUMBER)")
        if config.localization is None:
            raise ValueError("--video-particles needs --localization (or 'localization' in --config)")
    events_file: TextIO | None = None
    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "config.json").write_text(json.dumps(_jsonable(config), indent=2))
        events_file = (args.out / "events.jsonl").open("w")

    def sink(ev: LogEvent) -> None:
        if events_file is not None:
            events_file.write(json.dumps(ev.to_json()) + "\n")
            events_file.flush()

    brains = None
    if args.opponents is not None:
        c = config
        home = default_brains(c.players, c.localization, c.localization_params, c.referee.rules, c.obstacle_model)
        away = default_brains(args.opponents, c.localization, c.localization_params, c.referee.rules, c.obstacle_model)
        brains = lambda team, number: home(team, number) if team == 0 else away(team, number)  # noqa: E731
    match = Match(config, brains=brains, log=EventLog(sink=sink))
    panel = None
    shown: tuple[int, int] | None = None
    if args.video is not None and args.video_robot != "none":
        from teamsim.camera_views import CameraPanel, parse_robot

        n = config.players_per_team
        shown = (0, n) if args.video_robot == "auto" else parse_robot(args.video_robot, n)
        panel = CameraPanel(match, *shown, annotate=args.video_annotations)
    writer = None
    try:
        on_step = None
        if args.video is not None:
            from cognition.field import make_colour_scheme
            from teamsim.camera_views import belief_overlay, side_by_side
            from teamsim.render import TopDownRenderer, VideoWriter

            renderer = TopDownRenderer(match.field, make_colour_scheme(config.colours))
            writer = VideoWriter(args.video, fps=args.video_fps)
            every = max(1, round(config.physics.physics_hz / args.video_fps))

            def on_step(m: Match) -> None:
                if m.steps % every == 0:
                    beliefs = [belief_overlay(m, *shown)] if args.video_particles and shown is not None else []
                    top = renderer.render(m.snapshot(), m.game_state(), beliefs=[b for b in beliefs if b is not None])
                    writer.write(top if panel is None else side_by_side(top, panel.render()))

        summary = match.run(on_step=on_step)
    finally:
        if writer is not None:
            writer.close()
        if events_file is not None:
            events_file.close()
    print(summary.format(), file=out)
    if args.events:
        print("events:", file=out)
        for ev in match.log.events:
            print(f"  {ev}", file=out)
    if args.out is not None:
        (args.out / "summary.json").write_text(json.dumps(summary.to_dict(), indent=2))
        print(f"results written to {args.out}", file=out)
    if args.video is not None:
        print(f"video written to {args.video}", file=out)
    return 0


def run_camera(args: argparse.Namespace, out: TextIO) -> int:
    """Run ``teamsim camera`` with parsed arguments."""
    from teamsim.camera_views import parse_robot, write_snapshots

    config = config_from_args(args)
    n = config.players_per_team
    if args.robot == ["all"]:
        robots = [(t, k) for t in (0, 1) for k in range(1, n + 1)]
    else:
        robots = [parse_robot(text, n) for text in args.robot]
    match = Match(dataclasses.replace(config, observation="none"))
    paths = write_snapshots(match, args.time, robots, args.out, _size(args.size))
    print(f"{len(paths)} images written to {args.out}", file=out)
    return 0


def run_gallery(args: argparse.Namespace, out: TextIO) -> int:
    """Run ``teamsim gallery`` with parsed arguments."""
    from teamsim.camera_views import write_gallery

    paths = write_gallery(args.out, _size(args.size))
    print(f"{len(paths)} images written to {args.out}", file=out)
    return 0


# -- train / evaluate: reinforcement learning with Stable-Baselines3 ----------------------------
# The CLI is the application shell: these handlers import envs lazily; teamsim's modules never import envs.

_RL_ENV_HELP = "teamsim/Striker-v0, teamsim/Keeper-v0 or soccer_v0"


def _rl_env_args(p: Any) -> None:
    """Options of the environment shared by ``train`` and ``evaluate``."""
    p.add_argument("--env", required=True, help=f"environment: {_RL_ENV_HELP}")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
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
    p.add_argument("--timesteps", type=int, required=True, help="environment steps (decisions) in total")
    p.add_argument("--out", type=Path, required=True, help="output directory")
    p.add_argument("--n-envs", type=int, default=None, help="environment copies (default 4; soccer_v0: 1 match)")
    p.add_argument("--checkpoint-every", type=int, default=10_000, help="steps between checkpoints (default 10000)")
    p.add_argument("--hyperparams", default=None, metavar="JSON", help="algorithm keyword arguments as JSON")
    p.add_argument("--resume", action="store_true", help="continue from the latest checkpoint in --out")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")


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
    p.add_argument("--episodes", type=int, default=50, help="episodes (matches for soccer_v0; default 50)")
    p.add_argument("--out", type=Path, default=None, help="JSONL file of the episodes (resumable)")


def _json_object(text: str | None, option: str) -> dict[str, Any]:
    if text is None:
        return {}
    try:
        value = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ValueError(f"{option} is not valid JSON: {exc}") from exc
    if not isinstance(value, dict):
        raise ValueError(f"{option} must be a JSON object, got {text!r}")
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
            checkpoint_every=args.checkpoint_every,
            progress_bar=not args.no_progress,
            hyperparams=_json_object(args.hyperparams, "--hyperparams"),
            resume=args.resume,
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


def main(argv: Sequence[str] | None = None, out: TextIO | None = None) -> int:
    """Entry point of the ``teamsim`` console script; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    stream = out if out is not None else sys.stdout
    try:
        if args.command == "match":
            return run_match(args, stream)
        if args.command == "camera":
            return run_camera(args, stream)
        if args.command == "gallery":
            return run_gallery(args, stream)
        if args.command == "train":
            return run_train(args, stream)
        if args.command == "evaluate":
            return run_evaluate(args, stream)
    except (ValueError, TypeError, OSError) as exc:
        print(f"teamsim {args.command}: error: {exc}", file=sys.stderr)
        return 2
    parser.error(f"unknown command {args.command!r}")
    return 2
