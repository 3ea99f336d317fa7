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
train          train a policy with Stable-Baselines3 (registered by :mod:`envs.cli`
               through the ``teamsim.commands`` entry points: teamsim never imports envs)
evaluate       play episodes with a trained model or random actions (the same way)
scenario       list or run scenarios: kidnapping, penalties, ... (registered by
               :mod:`scenarios.cli` the same way)
compare        compare localization variants over paired seeds (the same way)
=============  ==================================================================

``teamsim match --profile`` also prints where the time went, per robot-frame: physics, referee,
camera, each module of the brains and the glue (:mod:`teamsim.profile`).

``teamsim match`` draws a live progress line on stderr while it plays (game clock, score,
real-time factor; :mod:`teamsim.progress`) when stderr is a terminal, and nothing when it is
piped or with ``--quiet``; the line is removed before the summary is printed.

``teamsim match --gc-broadcast`` / ``--gc-listen`` put the match on the SPL GameController's UDP
protocols, paced to real time (:mod:`teamsim.gc_bridge`): it broadcasts its game state, the
robots' status and their team messages, or an external GameController referees it.

``teamsim match --out DIR`` writes ``config.json`` first, appends every event to
``events.jsonl`` as it happens (an interrupted run keeps what it computed), and writes
``summary.json`` at the end. Two runs never mix: ``match``, ``camera`` and ``train`` refuse an
``--out`` directory that holds the results of an earlier run unless ``--overwrite`` is given,
which deletes those results (only the files the command writes) before the new run starts;
``train --resume`` continues the run in the directory instead.

Options override the ``--config`` file only when they are given (``--seed`` included: without
it the file's seed, or 0, is used).

Bad input never ends in a traceback: the command exits with code 2 after one line on stderr,
``teamsim COMMAND: error: ...``, that names the option, or the file and the key path
(``config file c.json: MatchConfig.physics.robot: expected a mapping or RobotParams, got int 5``).
A traceback means a bug in teamsim.

``match --video`` opens the video file before the match, so a path that cannot be written is
such an error (code 2). A video that fails during the match (a full disk) stops only the video:
the match plays on, its summary is printed and written, and the command exits with code 1 after
one line on stderr naming the video and its error.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import json
import os
import re
import sys
from collections.abc import Mapping, Sequence
from importlib.metadata import entry_points
from pathlib import Path
from typing import Any, NoReturn, TextIO

from cognition.field import COLOUR_SCHEMES, FIELD_PRESETS
from cognition.pipeline import providers
from teamsim.brains import default_brains
from teamsim.cli_gc import add_gc_arguments, bridge_params, warn
from teamsim.cli_types import integer as _integer
from teamsim.cli_types import number as _number
from teamsim.events import EventLog, LogEvent
from teamsim.gc_bridge import GameControllerBridge
from teamsim.image_params import ImageParams
from teamsim.match import MAX_PLAYERS_PER_TEAM, OBSERVATIONS, PLAYERS, Match, MatchConfig
from teamsim.percept_params import PerceptParams
from teamsim.progress import MatchProgress

IMAGE_SIDE_PX = (16, 4096)
"""Smallest and largest image width or height (px) that ``--size`` accepts."""
MAX_JSON_DEPTH = 32
"""Deepest nesting of objects and arrays in ``--config``, ``--env-kwargs`` and ``--hyperparams``."""
MAX_CONFIG_BYTES = 16 * 2**20
"""Largest ``--config`` file (bytes)."""
MAX_MESSAGE_CHARS = 1000
"""Longest error line; the rest of a longer message is cut off."""
MAX_SEED = 2**63 - 1
"""Largest ``--seed`` of a match (a numpy seed); training uses :data:`envs.training.MAX_SEED`."""
MATCH_RESULTS = ("config.json", "events.jsonl", "summary.json")
"""The files ``teamsim match --out DIR`` writes into DIR (and ``--overwrite`` deletes)."""
COMMAND_GROUP = "teamsim.commands"
"""Entry-point group through which packages above ``teamsim`` add subcommands: each entry is a
function ``register(subparsers)`` that adds its parsers and sets ``handler(args, out) -> int``
as their default (``scenarios.cli`` adds ``scenario`` and ``compare`` this way)."""
_SNAPSHOT = re.compile(r"^t\d+\.\d\d_team\d+_player\d+(_annotated)?\.png$")


class _Parser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line: ``teamsim COMMAND: error: ...``."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _common_args(p: Any) -> None:
    """Options shared by the subcommands that run a match."""
    p.add_argument(
        "--seed",
        type=_integer(0, MAX_SEED),
        default=None,
        help="random seed (default: the --config file's seed, else 0)",
    )
    p.add_argument(
        "--players-per-team",
        type=_integer(1, MAX_PLAYERS_PER_TEAM),
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
        choices=[*providers("localization"), "none"],
        default=None,
        help="localization variant the players run and act on (default: maturing with percepts; 'none': "
        "the players read the truth)",
    )
    p.add_argument(
        "--players",
        choices=list(PLAYERS),
        default=None,
        help="brains of the home team (and of the away team without --opponents): scripted team play "
        "(default; on the truth with --localization none) or random walkers",
    )
    p.add_argument("--opponents", choices=list(PLAYERS), default=None, help="brains of the away team")
    p.add_argument(
        "--obstacles",
        choices=[p for p in providers("obstacles") if p != "none"],
        default=None,
        help="obstacle model of the players' world model (default: sectors)",
    )
    p.add_argument(
        "--half-seconds",
        type=_number(0.0, False, "a number of seconds"),
        default=None,
        help="length of a half in seconds (default 600)",
    )
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
    p.add_argument(
        "--video-fps",
        type=_number(0.0, False, "a number"),
        default=10.0,
        help="frames per simulated second in the video",
    )
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
    p.add_argument(
        "--out",
        type=Path,
        default=None,
        help="directory for config.json, events.jsonl, summary.json (refused if it holds them: see --overwrite)",
    )
    p.add_argument(
        "--overwrite",
        action="store_true",
        help="delete the results of an earlier run in --out (config.json, events.jsonl, summary.json) first",
    )
    p.add_argument("--events", action="store_true", help="also print the event log")
    p.add_argument(
        "--profile",
        action="store_true",
        help="also print where the time went: microseconds per robot-frame for physics, referee, camera, "
        "each cognition module and the glue (teamsim.profile)",
    )
    p.add_argument(
        "--quiet",
        action="store_true",
        help="no live progress line (it is drawn on stderr only when stderr is a terminal)",
    )
    add_gc_arguments(p)


def _camera_parser(sub: Any) -> None:
    p = sub.add_parser("camera", help="write robots' camera images of a match as PNG (with annotations)")
    _common_args(p)
    p.add_argument(
        "--time",
        type=_number(0.0, True, "a number of seconds"),
        nargs="+",
        default=[30.0],
        help="match times to take pictures at (s)",
    )
    p.add_argument("--robot", nargs="+", default=["all"], help="TEAM:NUMBER robots, or 'all' (default)")
    p.add_argument("--size", default="320x240", help=_SIZE_HELP)
    p.add_argument(
        "--out",
        type=Path,
        required=True,
        help="directory for the PNG files (refused if it holds pictures of a run: see --overwrite)",
    )
    p.add_argument("--overwrite", action="store_true", help="delete the pictures of an earlier run in --out first")


def _gallery_parser(sub: Any) -> None:
    p = sub.add_parser("gallery", help="render the README gallery of camera images")
    p.add_argument("--out", type=Path, default=Path("docs/gallery"), help="directory (default docs/gallery)")
    p.add_argument("--size", default="320x240", help=_SIZE_HELP)


_SIZE_HELP = f"image size WIDTHxHEIGHT, {IMAGE_SIDE_PX[0]}..{IMAGE_SIDE_PX[1]} px each (default 320x240)"


def _size(text: str) -> tuple[int, int]:
    """``--size WIDTHxHEIGHT`` in pixels, each side in :data:`IMAGE_SIDE_PX`."""
    low, high = IMAGE_SIDE_PX
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise ValueError(f"--size must be WIDTHxHEIGHT in pixels, e.g. 320x240; got {text!r}") from None
    if not (low <= w <= high and low <= h <= high):
        raise ValueError(f"--size: width and height must be {low}..{high} px each, got {text!r}")
    return w, h


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``teamsim`` command."""
    parser = _Parser(
        prog="teamsim",
        description="Simulator for teams of SPL-style soccer robots with a real cognition stack.",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    _match_parser(sub)
    _camera_parser(sub)
    _gallery_parser(sub)
    for entry in sorted(entry_points(group=COMMAND_GROUP), key=lambda e: e.name):
        entry.load()(sub)  # a package above teamsim adds its commands (each sets ``handler``)
    return parser


def config_from_args(args: argparse.Namespace) -> MatchConfig:
    """Merge a JSON config file and the command-line options into a :class:`MatchConfig`.

    An option overrides the file only when it is given. The file is checked on its own first,
    so that an error in it names the file and the key path.
    """
    data: dict[str, Any] = {}
    if args.config is not None:
        data = read_config_file(args.config)
        try:
            MatchConfig.from_mapping(data)
        except (ValueError, TypeError) as exc:
            raise ValueError(f"config file {args.config}: {exc}") from exc
    data = dict(data)
    if args.seed is not None:
        data["seed"] = args.seed
    if args.players_per_team is not None:
        data["players_per_team"] = args.players_per_team
    if args.field is not None:
        data["field"] = args.field
    if args.colours is not None:
        data["colours"] = args.colours
    if getattr(args, "percepts", None) is not None:
        data["percepts"] = _override(data.get("percepts"), preset=args.percepts)
    if getattr(args, "observation", None) is not None:
        data["observation"] = args.observation
    if getattr(args, "localization", None) is not None:
        if args.localization == "none":
            data["cognition"] = None
        else:
            data["cognition"] = _override(data.get("cognition") or {}, localization=args.localization)
    elif args.command == "match" and "cognition" not in data and data.get("observation", "percepts") == "percepts":
        data["cognition"] = {}  # the command's default: the full cognition stack (CognitionConfig's defaults)
    if getattr(args, "players", None) is not None:
        data["players"] = args.players
    if getattr(args, "obstacles", None) is not None:
        if data.get("cognition") is None:
            raise ValueError("--obstacles chooses the obstacle model of a cognition stack; the players read the truth")
        data["cognition"] = _override(data["cognition"], obstacles=args.obstacles)
    if args.images is not None:
        data["images"] = _override(data.get("images"), preset=args.images)
    referee: dict[str, Any] = {}
    if getattr(args, "half_seconds", None) is not None:
        referee["half_seconds"] = args.half_seconds
    if getattr(args, "rules", None) is not None:
        referee["rules"] = args.rules
    if referee:
        data["referee"] = _override(data.get("referee"), **referee)
    try:
        return MatchConfig.from_mapping(data)
    except (ValueError, TypeError) as exc:
        if args.config is None:
            raise
        raise ValueError(f"config file {args.config} with the command-line options: {exc}") from exc


def _override(section: Any, **values: Any) -> dict[str, Any]:
    """A config section (a mapping, a preset name or absent) with some of its keys replaced."""
    if isinstance(section, Mapping):
        return {**section, **values}
    if isinstance(section, str):
        return {"preset": section, **values}
    return dict(values)


def read_config_file(path: Path) -> dict[str, Any]:
    """The JSON object in the ``--config`` file ``path``; ``ValueError`` naming the file otherwise.

    The file must be UTF-8 JSON of at most :data:`MAX_CONFIG_BYTES` bytes, hold an object,
    nest at most :data:`MAX_JSON_DEPTH` levels and repeat no key within an object.
    """
    if not path.exists():
        raise ValueError(f"config file not found: {path}")
    if not path.is_file():
        raise ValueError(f"config file {path} is not a file")
    size = path.stat().st_size
    if size > MAX_CONFIG_BYTES:
        raise ValueError(f"config file {path} has {size} bytes; a config file has at most {MAX_CONFIG_BYTES}")
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"config file {path} is not UTF-8 text: {exc}") from None
    value = parse_json(text, f"config file {path}")
    if not isinstance(value, dict):
        raise ValueError(f"config file {path} must hold a JSON object, got {_json_type(value)}")
    return value


def parse_json(text: str, source: str) -> Any:
    """Parse JSON ``text`` strictly; every error is a ``ValueError`` that starts with ``source``.

    Errors: not JSON, a key twice in one object (JSON would keep the last silently), or
    objects and arrays nested deeper than :data:`MAX_JSON_DEPTH`.
    """

    def unique(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
        obj: dict[str, Any] = {}
        for key, value in pairs:
            if key in obj:
                raise ValueError(f"key {key!r} appears twice in one object")
            obj[key] = value
        return obj

    try:
        value = json.loads(text, object_pairs_hook=unique)
    except json.JSONDecodeError as exc:
        raise ValueError(f"{source} is not valid JSON: {exc}") from None
    except RecursionError:
        raise ValueError(f"{source} nests objects or arrays deeper than {MAX_JSON_DEPTH} levels") from None
    except ValueError as exc:  # a repeated key, or an integer with more digits than Python converts
        raise ValueError(f"{source}: {exc}") from None
    stack = [(value, 1)]
    while stack:
        item, depth = stack.pop()
        children = item.values() if isinstance(item, dict) else item if isinstance(item, list) else None
        if children is None:
            continue
        if depth > MAX_JSON_DEPTH:
            raise ValueError(f"{source} nests objects or arrays deeper than {MAX_JSON_DEPTH} levels")
        stack.extend((child, depth + 1) for child in children)
    return value


def _json_type(value: Any) -> str:
    """The JSON name of ``value``'s type, for messages."""
    names = {dict: "an object", list: "an array", str: "a string", bool: "a boolean", int: "a number"}
    names[float] = "a number"
    return "null" if value is None else names.get(type(value), type(value).__name__)


def _jsonable(obj: Any) -> Any:
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: _jsonable(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
    if isinstance(obj, list | tuple):
        return [_jsonable(v) for v in obj]
    return obj


def run_match(args: argparse.Namespace, out: TextIO) -> int:
    """Run ``teamsim match`` with parsed arguments."""
    config = config_from_args(args)
    gc = bridge_params(args)
    if args.video_robot not in ("auto", "none"):
        _robot(args.video_robot, config.players_per_team, "--video-robot")
    if args.out is not None:
        _refuse_results(args.out, _match_results(args.out), args.overwrite)
    if args.video_particles:
        if args.video is None or args.video_robot == "none":
            raise ValueError("--video-particles needs --video and a --video-robot (auto or TEAM:NUMBER)")
        if config.cognition is None or config.cognition.beliefs == "truth":
            raise ValueError("--video-particles needs a cognition stack: --localization (or 'cognition' in --config)")
    writer = None
    if args.video is not None:  # before anything runs: a path that cannot be written fails at once
        from teamsim.render import VideoWriter

        writer = VideoWriter(args.video, fps=args.video_fps)
    events_file: TextIO | None = None
    if args.out is not None:
        for stale in _match_results(args.out):  # only with --overwrite: refused above otherwise
            stale.unlink()
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
        home = default_brains(c.players, c.cognition, c.referee.rules)
        away = default_brains(args.opponents, c.cognition, c.referee.rules)
        brains = lambda team, number: home(team, number) if team == 0 else away(team, number)  # noqa: E731
    listen = gc is not None and gc.mode == "listen"
    match = Match(config, brains=brains, log=EventLog(sink=sink), external_referee=listen, profile=args.profile)
    panel = None
    shown: tuple[int, int] | None = None
    if args.video is not None and args.video_robot != "none":
        from teamsim.camera_views import CameraPanel, parse_robot

        n = config.players_per_team
        shown = (0, n) if args.video_robot == "auto" else parse_robot(args.video_robot, n)
        panel = CameraPanel(match, *shown, annotate=args.video_annotations)
    video_error: Exception | None = None  # the first failure of the video; it stops the video, not the match
    interrupted = False  # Ctrl-C during a GameController match: the summary is still printed
    try:
        on_step = None
        if writer is not None:
            from cognition.field import make_colour_scheme
            from teamsim.camera_views import belief_overlay, side_by_side
            from teamsim.render import TopDownRenderer

            renderer = TopDownRenderer(match.field, make_colour_scheme(config.colours))
            video = writer
            every = max(1, round(config.physics.physics_hz / args.video_fps))

            def on_step(m: Match) -> None:
                nonlocal video_error
                if video_error is not None or m.steps % every != 0:
                    return
                try:
                    beliefs = [belief_overlay(m, *shown)] if args.video_particles and shown is not None else []
                    top = renderer.render(m.snapshot(), m.game_state(), beliefs=[b for b in beliefs if b is not None])
                    video.write(top if panel is None else side_by_side(top, panel.render()))
                except Exception as exc:  # rendering or writing: reported after the summary
                    video_error = exc
                    with contextlib.suppress(Exception):
                        video.close()

        with MatchProgress(match, enabled=False if args.quiet else None) as progress:
            video_step = on_step

            def step(m: Match) -> None:
                progress.update(m)
                if video_step is not None:
                    video_step(m)

            if gc is None:
                summary = match.run(on_step=step)
            else:
                with GameControllerBridge(match, gc, warn=warn) as bridge:
                    print(f"GameController {gc.mode} on {gc.host}:{bridge.port}, real time (Ctrl-C stops)", file=out)
                    out.flush()
                    summary = bridge.run(on_step=step)
                interrupted = bridge.interrupted
    finally:
        if writer is not None:
            try:
                writer.close()
            except OSError as exc:
                video_error = video_error or exc
        if events_file is not None:
            events_file.close()
    print(summary.format(), file=out)
    if match.profile is not None:
        print(match.profile.format(match.wall_seconds, match.time), file=out)
    if args.events:
        print("events:", file=out)
        for ev in match.log.events:
            print(f"  {ev}", file=out)
    if args.out is not None:
        (args.out / "summary.json").write_text(json.dumps(summary.to_dict(), indent=2))
        print(f"results written to {args.out}", file=out)
    if writer is not None and video_error is not None:
        reason = " ".join(str(video_error).split()) or type(video_error).__name__
        if not isinstance(video_error, OSError):
            reason = f"{type(video_error).__name__}: {reason}"
        print(
            f"teamsim match: error: video {args.video} stopped after {writer.frame_count} frames "
            f"(the match and its results are complete): {reason}",
            file=sys.stderr,
        )
        return 1
    if args.video is not None:
        print(f"video written to {args.video}", file=out)
    return 130 if interrupted else 0


def _robot(text: str, players_per_team: int, option: str) -> tuple[int, int]:
    """``TEAM:NUMBER`` of ``option`` as (team, number); ``ValueError`` naming the option otherwise."""
    from teamsim.camera_views import parse_robot

    try:
        return parse_robot(text, players_per_team)
    except ValueError as exc:
        raise ValueError(f"{option}: {exc}") from None


def _match_results(folder: Path) -> list[Path]:
    """The files of an earlier ``teamsim match --out folder`` run in ``folder``."""
    return [folder / name for name in MATCH_RESULTS if (folder / name).exists()]


def _camera_results(folder: Path) -> list[Path]:
    """The pictures of an earlier ``teamsim camera --out folder`` run in ``folder``."""
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.iterdir() if _SNAPSHOT.match(p.name))


def _refuse_results(folder: Path, results: Sequence[Path], overwrite: bool) -> None:
    """Raise ``ValueError`` if ``folder`` is no directory, or holds ``results`` and ``overwrite`` is false."""
    if folder.exists() and not folder.is_dir():
        raise ValueError(f"--out {folder} exists and is not a directory")
    if results and not overwrite:
        names = ", ".join(p.name for p in results[:3]) + (f" and {len(results) - 3} more" if len(results) > 3 else "")
        raise ValueError(
            f"--out {folder} already holds the results of a run ({names}); use --overwrite to replace them "
            "or another directory"
        )


def run_camera(args: argparse.Namespace, out: TextIO) -> int:
    """Run ``teamsim camera`` with parsed arguments."""
    from teamsim.camera_views import write_snapshots

    config = config_from_args(args)
    size = _size(args.size)
    n = config.players_per_team
    if args.robot == ["all"]:
        robots = [(t, k) for t in (0, 1) for k in range(1, n + 1)]
    else:
        robots = [_robot(text, n, "--robot") for text in args.robot]
    _refuse_results(args.out, _camera_results(args.out), args.overwrite)
    match = Match(dataclasses.replace(config, observation="none"))
    for stale in _camera_results(args.out):  # only with --overwrite: refused above otherwise
        stale.unlink()
    paths = write_snapshots(match, args.time, robots, args.out, size)
    print(f"{len(paths)} images written to {args.out}", file=out)
    if match.finished and max(args.time) > match.time:
        print(f"note: the match ended at {match.time:.1f} s; pictures of later --time values show its end", file=out)
    return 0


def run_gallery(args: argparse.Namespace, out: TextIO) -> int:
    """Run ``teamsim gallery`` with parsed arguments."""
    from teamsim.camera_views import write_gallery

    paths = write_gallery(args.out, _size(args.size))
    print(f"{len(paths)} images written to {args.out}", file=out)
    return 0


def main(argv: Sequence[str] | None = None, out: TextIO | None = None) -> int:
    """Entry point of the ``teamsim`` console script; returns the exit code.

    0: done; 2: bad input (usage, options, config, an output directory in use, a request
    larger than memory), reported in one line on stderr; 130: ``train`` interrupted. Other
    exceptions are bugs and propagate with their traceback (Ctrl-C as ``KeyboardInterrupt``).
    """
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help (0) or a usage error, already printed in one line (2)
        return exc.code if isinstance(exc.code, int) else 2
    stream = out if out is not None else sys.stdout
    try:
        if args.command == "match":
            return run_match(args, stream)
        if args.command == "camera":
            return run_camera(args, stream)
        if args.command == "gallery":
            return run_gallery(args, stream)
        handler = getattr(args, "handler", None)
        if handler is not None:
            return int(handler(args, stream))
    except BrokenPipeError:  # the reader went away (``teamsim scenario list | head``): stop quietly
        with contextlib.suppress(OSError):
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except (ValueError, TypeError, OSError) as exc:
        return _report(args.command, str(exc) or type(exc).__name__)
    except MemoryError as exc:  # an allocation sized by the input (the sizes are bounded where they are known)
        detail = f" ({exc})" if str(exc) else ""
        return _report(args.command, f"out of memory{detail}: a size in the options or the config is too large")
    parser.error(f"unknown command {args.command!r}")
    return 2


def _report(command: str, message: str) -> int:
    """Print ``message`` as one error line of ``command`` on stderr; returns the exit code 2."""
    line = " ".join(message.split())
    if len(line) > MAX_MESSAGE_CHARS:
        line = line[:MAX_MESSAGE_CHARS] + f"... ({len(line) - MAX_MESSAGE_CHARS} more characters)"
    print(f"teamsim {command}: error: {line}", file=sys.stderr)
    return 2
