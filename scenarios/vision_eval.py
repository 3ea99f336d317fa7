"""``teamsim vision-eval``: precision, recall and position errors of the vision pipeline per feature kind.

The evaluation renders camera images of random scenes with :class:`teamsim.images.ImageRenderer`,
runs :class:`cognition.vision.Vision` on them and matches its percepts to the renderer's
ground-truth annotations (:meth:`ImageRenderer.annotate`), kind by kind. It measures whatever
the pipeline reports: a kind the pipeline does not produce yet shows 0 detections (and its
recall 0). It is the tool behind the vision issue's bars (DNT section 4 and NimbRo section 5
report detection rates and errors the same way: per feature type, against hand labels).

**Frames.** A seeded generator (``--seed``) draws every frame's scene; the image effects draw
from a second generator split from the same seed, so ``--images`` (and ``--motion``) never
change the scenes, and frame ``k`` is the same for every ``--frames`` above ``k``. The
observer (team 0, player 1, team frame = world frame) stands anywhere between the goal lines
and up to ``border`` beyond the touchlines (where robots play, and where penalised robots
wait), facing anywhere, head yaw uniform in ``±head_yaw``, pitch
uniform in [``pitch_low``, ``pitch_high``], the lower camera in a ``lower_camera`` share of the
frames. The ball lies ``ball_near``..``ball_far`` ahead within the view in a ``ball_ahead``
share of the frames, anywhere on the carpet otherwise; 0..``max_robots`` other robots of both
teams (a ``robot_in_view`` share of them in the view, ``fallen`` of them lying) stand around,
at least 0.45 m apart, the ball at least 0.25 m from each.
With ``--motion`` the head turns (yaw rate ±2 rad/s, pitch rate ±1 rad/s) and the robot walks
in half the frames (blur, rolling shutter and the percepts' sigmas follow).

======================  =========  ============  ===================================================
FrameParams             default    range         meaning
======================  =========  ============  ===================================================
border                  0.3 m      [0, 0.7]      how far beyond the touchlines the observer stands
head_yaw                1.2 rad    [0, 2.1]      head yaw is uniform in ±head_yaw
pitch_low               -0.1 rad   [-0.7, 0.5]   smallest head pitch (rad, + looks down)
pitch_high              0.45 rad   [-0.7, 0.5]   largest head pitch
lower_camera            0.2        [0, 1]        share of frames from the lower camera
ball_ahead              0.8        [0, 1]        share of frames with the ball ahead, in the view
ball_near               0.2 m      [0, 10]       nearest ball ahead
ball_far                5.0 m      (0, 10]       farthest ball ahead
max_robots              6          [0, 9]        other robots: uniform 0..max_robots
robot_in_view           0.5        [0, 1]        share of them placed 0.5..5 m ahead, in the view
fallen                  0.1        [0, 1]        share of them lying on the ground
======================  =========  ============  ===================================================

**Matching, counting and errors** are those of :mod:`scenarios.vision_match` (tolerances in
:class:`~scenarios.vision_match.EvalParams`): greedy one-to-one matching by pixel distance per
kind, annotations that count for recall within the image margin and the evaluation distance,
detections that count for precision within that distance, and distance / bearing errors of
the matched pairs against the true positions.

**Output.** A table per method (stdout). With ``--out DIR``: ``metrics.json`` (all figures, the
arguments, the seed, the parameters and the bars), ``frames.csv`` (one row per frame and method:
pose, camera, and ``ann / det / tp / fp / fn`` per kind) and ``worst_frames.png`` (one method)
or ``worst_frames_<method>.png`` (``--method both``): the 9 frames with the most errors (false
positives plus misses), annotations thin (:func:`teamsim.images.draw_annotations`) and
detections thick (:func:`cognition.vision.draw.draw_percepts`). ``--gallery DIR`` instead draws
the detections on the README gallery scenes (:func:`teamsim.camera_views.gallery_scenes`).

**Bars** (the vision issue, stated for ``default`` images and >= 500 frames per colour
scheme): crossings precision >= 0.95, recall >= 0.80; posts precision, recall and side accuracy
>= 0.97; ball precision and recall >= 0.95 (within 4 m); circle recall >= 0.7 (half in view);
median relative distance error < 5 % (posts, crossings, circle, marks, ball). Each is printed
as ``ok`` or ``FAIL``; the exit code does not depend on them.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar, TextIO

import cv2
import numpy as np
from numpy.typing import NDArray

from cognition.camera import CameraRig
from cognition.field import FIELD_PRESETS, Field
from cognition.params import PROBABILITY, Range, Ranges, check_ranges, non_negative, positive
from cognition.percepts import Percepts
from cognition.vision import METHODS, Vision, VisionParams
from scenarios.vision_match import KINDS, EvalParams, Tally, evaluate_frame
from scenarios.vision_pictures import montage, overlay, write_gallery
from scenarios.vision_report import check_bars, format_recall_by_distance, format_table, summarize
from teamsim.cli_types import integer
from teamsim.image_params import ImageParams
from teamsim.images import ImageAnnotations, ImageRenderer, save_png
from teamsim.percepts import Scene, SceneRobot

_SCORED = ("post", "crossing", "line", "circle", "mark", "ball", "robot")
"""Kinds whose errors rank the worst frames (``crossing_any`` would count crossings twice)."""
RESULT_FILES = ("metrics.json", "frames.csv")
"""Files ``--out`` writes besides the worst-frame images (``worst_frames*.png``)."""
PLAYERS_PER_TEAM = 5
"""Players per team of the evaluation scenes (the observer is team 0 player 1)."""
_WORST = 9


@dataclass(frozen=True)
class FrameParams:
    """How random evaluation frames are drawn (module table)."""

    border: float = 0.3
    head_yaw: float = 1.2
    pitch_low: float = -0.1
    pitch_high: float = 0.45
    lower_camera: float = 0.2
    ball_ahead: float = 0.8
    ball_near: float = 0.2
    ball_far: float = 5.0
    max_robots: int = 6
    robot_in_view: float = 0.5
    fallen: float = 0.1

    RANGES: ClassVar[Ranges] = {
        "border": non_negative(0.7),
        "head_yaw": non_negative(2.1),
        "pitch_low": Range(-0.7, 0.5),
        "pitch_high": Range(-0.7, 0.5),
        "lower_camera": PROBABILITY,
        "ball_ahead": PROBABILITY,
        "ball_near": non_negative(10.0),
        "ball_far": positive(10.0),
        "max_robots": Range(0, 2 * PLAYERS_PER_TEAM - 1),
        "robot_in_view": PROBABILITY,
        "fallen": PROBABILITY,
    }

    def __post_init__(self) -> None:
        check_ranges(self)
        if self.pitch_low > self.pitch_high or self.ball_near > self.ball_far:
            raise ValueError("FrameParams: pitch_low <= pitch_high and ball_near <= ball_far are required")


# -- frames --------------------------------------------------------------------------------


@dataclass(frozen=True)
class EvalFrame:
    """One evaluation scene: robot 0 of ``robots`` is the observer (world frame, SI units)."""

    index: int
    robots: tuple[SceneRobot, ...]
    ball: tuple[float, float]

    @property
    def observer(self) -> SceneRobot:
        return self.robots[0]

    def scene(self) -> Scene:
        """The :class:`Scene` (the observer is team 0 player 1, robot index 0)."""
        return Scene.build(list(self.robots), self.ball, PLAYERS_PER_TEAM)


def frame_generators(seed: int) -> tuple[np.random.Generator, np.random.Generator]:
    """(scene generator, image-effect generator), both split from ``seed``."""
    scenes, effects = np.random.SeedSequence(seed).spawn(2)
    return np.random.default_rng(scenes), np.random.default_rng(effects)


def make_frames(
    n: int, rng: np.random.Generator, field: Field, params: FrameParams | None = None, motion: bool = False
) -> list[EvalFrame]:
    """``n`` random frames (module docstring) drawn from ``rng``; ``motion`` only switches the
    drawn head rates and walking on (the poses are the same either way)."""
    p = params or FrameParams()
    hfov = CameraRig().upper.hfov
    return [_frame(k, rng, field, p, motion, hfov) for k in range(n)]


def _frame(k: int, rng: np.random.Generator, fld: Field, p: FrameParams, motion: bool, hfov: float) -> EvalFrame:
    lx, ly = fld.half_length, fld.half_width + p.border
    cx, cy = fld.half_length + fld.dims.border_strip - 0.15, fld.half_width + fld.dims.border_strip - 0.15
    goal_y = fld.dims.goal_inner_width / 2 + fld.dims.goal_post_diameter + 0.15

    def in_goal(px: float, py: float) -> bool:  # behind a goal line, between the posts: no robot stands there
        return abs(px) > fld.half_length and abs(py) < goal_y

    x, y = rng.uniform(-lx, lx), rng.uniform(-ly, ly)
    while in_goal(x, y):
        x, y = rng.uniform(-lx, lx), rng.uniform(-ly, ly)
    th = rng.uniform(-math.pi, math.pi)
    yaw = rng.uniform(-p.head_yaw, p.head_yaw)
    pitch = rng.uniform(p.pitch_low, p.pitch_high)
    camera = "lower" if rng.random() < p.lower_camera else "upper"
    yaw_rate, pitch_rate, turn_rate = rng.uniform(-1.0, 1.0, 3) * (2.0, 1.0, 1.0) * motion  # drawn always
    walking = bool(rng.random() < 0.5) and motion
    look = th + yaw
    observer = SceneRobot(
        0, 1, x, y, th, head_yaw=yaw, head_pitch=pitch, camera=camera, yaw_rate=float(yaw_rate),
        pitch_rate=float(pitch_rate), walking=walking, turn_rate=float(turn_rate),
    )  # fmt: skip
    placed = [(x, y)]

    def ahead(near: float, far: float) -> tuple[float, float]:
        d, b = rng.uniform(near, far), look + rng.uniform(-0.5, 0.5) * hfov
        return float(np.clip(x + d * math.cos(b), -cx, cx)), float(np.clip(y + d * math.sin(b), -cy, cy))

    def anywhere() -> tuple[float, float]:
        return float(rng.uniform(-cx, cx)), float(rng.uniform(-cy, cy))

    slots = [(0, n) for n in range(2, PLAYERS_PER_TEAM + 1)] + [(1, n) for n in range(1, PLAYERS_PER_TEAM + 1)]
    count = int(rng.integers(0, p.max_robots + 1))
    chosen = rng.choice(len(slots), size=count, replace=False)
    others = []
    for s in chosen:
        team, number = slots[int(s)]
        in_view, fallen, heading = rng.random() < p.robot_in_view, rng.random() < p.fallen, rng.uniform(-3.2, 3.2)
        for _ in range(20):
            rx, ry = ahead(0.5, 5.0) if in_view else anywhere()
            if min(math.hypot(rx - a, ry - b) for a, b in placed) > 0.45 and not in_goal(rx, ry):
                placed.append((rx, ry))
                others.append(SceneRobot(team, number, rx, ry, heading, sees=False, fallen=fallen))
                break
    ball = ahead(p.ball_near, p.ball_far) if rng.random() < p.ball_ahead else anywhere()
    for _ in range(20):
        if min(math.hypot(ball[0] - a, ball[1] - b) for a, b in placed) > 0.25:
            break
        ball = anywhere()
    return EvalFrame(k, (observer, *others), ball)


# -- the run -------------------------------------------------------------------------------


@dataclass
class MethodRun:
    """The results of one line method over all frames."""

    method: str
    vision: Vision | None
    error: str | None = None
    totals: dict[str, Tally] = field(default_factory=lambda: {k: Tally() for k in KINDS})
    rows: list[dict[str, Any]] = field(default_factory=list)
    seconds: float = 0.0
    differs: bool = False
    """Whether its percepts differed from the first available method's on some frame."""
    worst: list[tuple[int, int, NDArray[np.uint8], ImageAnnotations, Percepts, str]] = field(default_factory=list)
    """(score, -frame index, image, annotations, percepts, caption) of the worst frames."""


def make_vision(method: str, field_map: Field, colours: str) -> tuple[Vision | None, str | None]:
    """The pipeline for ``method``, or (None, why) when the pipeline does not offer it."""
    try:
        return Vision(VisionParams(method=method), field=field_map, scheme=colours, team=0), None  # type: ignore[arg-type]
    except (ValueError, TypeError, NotImplementedError) as exc:
        return None, f"{type(exc).__name__}: {exc}"


def evaluate(
    frames: Sequence[EvalFrame],
    methods: Sequence[str],
    colours: str = "classic",
    images: str = "default",
    size: tuple[int, int] = (320, 240),
    effects_rng: np.random.Generator | None = None,
    params: EvalParams | None = None,
    field_map: Field | None = None,
) -> tuple[list[MethodRun], float]:
    """Render, detect and match every frame for each method; returns the runs and the time spent
    rendering and annotating (s)."""
    p = params or EvalParams()
    fld = field_map or Field(FIELD_PRESETS["spl2025"], "spl2025")
    rig = CameraRig().with_resolution(*size)
    ren = ImageRenderer(fld, colours, rig, ImageParams.preset(images), effects_rng or np.random.default_rng(0))
    runs = []
    for m in methods:
        vision, error = make_vision(m, fld, colours)
        runs.append(MethodRun(m, vision, error))
    if frames:  # compile or load the compiled kernels outside the timing, on a renderer of its own
        warm = ImageRenderer(fld, colours, rig, ImageParams.preset(images), np.random.default_rng(0))
        scene = frames[0].scene()
        image = warm.render(scene, 0)
        warm.annotate(scene)
        for run in runs:
            if run.vision is not None:
                try:
                    run.vision.detect(image, warm.camera_matrix(scene, 0))
                except NotImplementedError as exc:
                    run.vision, run.error = None, f"NotImplementedError: {exc}"
    render_s = 0.0
    for frame in frames:
        start = time.perf_counter()
        scene = frame.scene()
        image = ren.render(scene, 0)
        ann = ren.annotate(scene)[0]
        if ann is None:
            raise RuntimeError(
                f"frame {frame.index}: the observer's camera sees nothing"
            )  # make_frames never does this
        render_s += time.perf_counter() - start
        o = frame.observer
        first: NDArray[np.float64] | None = None
        for run in runs:
            if run.vision is None:
                continue
            start = time.perf_counter()
            percepts = run.vision.detect(image, ann.camera, 0.0, o.yaw_rate, o.pitch_rate, o.walking)
            run.seconds += time.perf_counter() - start
            if first is None:
                first = percepts.rows
            elif not np.array_equal(first, percepts.rows, equal_nan=True):
                run.differs = True
            tallies = evaluate_frame(percepts, ann, scene, fld, p)
            _record(run, frame, tallies, image, ann, percepts)
    return runs, render_s


def _record(
    run: MethodRun, frame: EvalFrame, tallies: dict[str, Tally], image: NDArray[np.uint8], ann: ImageAnnotations,
    percepts: Percepts,
) -> None:  # fmt: skip
    o = frame.observer
    ball = math.hypot(frame.ball[0] - o.x, frame.ball[1] - o.y)
    row: dict[str, Any] = {
        "method": run.method, "frame": frame.index, "camera": o.camera, "x": round(o.x, 4), "y": round(o.y, 4),
        "theta": round(o.theta, 4), "head_yaw": round(o.head_yaw, 4), "head_pitch": round(o.head_pitch, 4),
        "robots": len(frame.robots) - 1, "ball_distance": round(ball, 3),
    }  # fmt: skip
    score = 0
    parts = []
    for name in KINDS:
        t = tallies[name]
        run.totals[name].add(t)
        row.update({f"{name}_ann": t.annotations, f"{name}_det": t.detections, f"{name}_tp": t.tp})
        row.update({f"{name}_fp": t.fp, f"{name}_fn": t.fn})
        if name in _SCORED and t.fp + t.fn:
            score += t.fp + t.fn
            parts.append(f"{name[:5]} {t.fp}/{t.fn}")
    row["errors"] = score
    run.rows.append(row)
    if score == 0:
        return
    caption = f"frame {frame.index}: {score} errors (FP/FN)\n" + ", ".join(parts)
    entry = (score, -frame.index, image, ann, percepts, caption)
    run.worst.append(entry)
    run.worst.sort(key=lambda e: (e[0], e[1]), reverse=True)
    del run.worst[_WORST:]


HELP = """Render --frames random camera frames (random robot pose, head angles, camera, ball and robots;
seeded by --seed; --images and --motion do not change them), run the vision, match its
detections to the renderer's ground truth kind by kind and print precision, recall and
distance / bearing errors per feature type.

Matching (tolerances for 320 px wide images, scaled with the width; greedy by pixel distance,
one-to-one): posts base within 8 px or inside the true box, side must agree when both give one;
crossings within 8 px and the same type (crossing_any: any type), counted for recall when
every arm shows its first 0.2 m, unhidden, at least 6 px long and 2 px wide (crossing_seen: every
crossing in view); lines: both ends within 4 px of the visible pieces of one true line
(precision), true pieces over 20 px at least half covered (recall); circle centre within
0.3 m on the ground, recall over frames with at least half of it visible;
marks within 8 px; ball within max(4 px, its image radius); robots: feet inside the true box
widened by 4 px. Annotations count when at least 4 px inside the image and within 6 m (ball:
4 m) of the robot; detections when measured within the same distance. Errors: |measured -
true distance| (m and relative), bearing (deg), median and 90th percentile."""


# -- the command ---------------------------------------------------------------------------


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT in pixels, e.g. 320x240; got {text!r}") from None
    if not (16 <= w <= 2048 and 16 <= h <= 2048):
        raise argparse.ArgumentTypeError(f"width and height must be 16..2048 px each, got {text!r}")
    return w, h


def add_parser(sub: Any) -> None:
    """Add ``vision-eval`` to the ``teamsim`` subcommands (called by :func:`scenarios.cli.register`)."""
    p = sub.add_parser(
        "vision-eval",
        help="precision, recall and errors of the vision per feature type on rendered frames",
        description=HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--frames", type=integer(1, 100_000), default=500, help="frames to render (default 500)")
    p.add_argument(
        "--colours", choices=["classic", "modern"], default="classic", help="colour scheme (default classic)"
    )
    p.add_argument(
        "--images",
        choices=sorted(ImageParams.PRESETS),
        default="default",
        help="image effects preset (default default)",
    )
    p.add_argument(
        "--method", choices=[*METHODS, "both"], default="dnt", help="line method, or both side by side (default dnt)"
    )
    p.add_argument("--seed", type=integer(0, 2**63 - 1), default=0, help="seed of the frames (default 0)")
    p.add_argument("--size", type=_size, default=(320, 240), help="image size WIDTHxHEIGHT (default 320x240)")
    p.add_argument("--motion", action="store_true", help="random head rates and walking (blur; larger sigmas)")
    p.add_argument(
        "--out", type=Path, default=None, metavar="DIR",
        help="directory for metrics.json, frames.csv and worst_frames*.png (refused if it holds metrics.json)",
    )  # fmt: skip
    p.add_argument("--overwrite", action="store_true", help="replace the results of an earlier run in --out")
    p.add_argument(
        "--gallery", type=Path, default=None, metavar="DIR",
        help="instead of evaluating: draw the detections on the README gallery scenes into DIR",
    )  # fmt: skip
    p.set_defaults(handler=run_command)


def _results(folder: Path) -> list[Path]:
    if not folder.is_dir():
        return []
    names = [folder / n for n in RESULT_FILES if (folder / n).exists()]
    return names + sorted(folder.glob("worst_frames*.png"))


def run_command(args: argparse.Namespace, out: TextIO) -> int:
    """``teamsim vision-eval``."""
    methods = list(METHODS) if args.method == "both" else [args.method]
    if args.gallery is not None:
        if args.gallery.exists() and not args.gallery.is_dir():
            raise ValueError(f"--gallery {args.gallery} exists and is not a directory")
        paths = write_gallery(args.gallery, methods, out)
        print(f"{len(paths)} images written to {args.gallery}", file=out)
        return 0
    if args.out is not None:
        if args.out.exists() and not args.out.is_dir():
            raise ValueError(f"--out {args.out} exists and is not a directory")
        if (args.out / "metrics.json").exists() and not args.overwrite:
            raise ValueError(
                f"--out {args.out} already holds the results of a run (metrics.json); use --overwrite to replace "
                "them or another directory"
            )
    fld = Field(FIELD_PRESETS["spl2025"], "spl2025")
    scene_rng, effects_rng = frame_generators(args.seed)
    frames = make_frames(args.frames, scene_rng, fld, motion=args.motion)
    start = time.perf_counter()
    runs, render_s = evaluate(frames, methods, args.colours, args.images, args.size, effects_rng)
    wall = time.perf_counter() - start
    report: dict[str, Any] = {
        "command": "vision-eval",
        "args": {k: (str(v) if isinstance(v, Path) else v) for k, v in vars(args).items() if k != "handler"},
        "seed": args.seed, "frames": args.frames, "field": "spl2025", "colours": args.colours,
        "images": args.images, "size": list(args.size), "motion": args.motion,
        "frame_params": dataclasses.asdict(FrameParams()), "eval_params": dataclasses.asdict(EvalParams()),
        "render_ms_per_frame": 1e3 * render_s / len(frames), "wall_s": wall, "methods": {},
    }  # fmt: skip
    for run in runs:
        title = (
            f"method {run.method}: {args.frames} frames, {args.colours} colours, {args.images} images, seed {args.seed}"
        )
        if run.vision is None:
            print(f"{title}: unavailable ({run.error})\n", file=out)
            report["methods"][run.method] = {"available": False, "error": run.error}
            continue
        kinds = {name: summarize(run.totals[name]) for name in KINDS}
        bars = check_bars(kinds)
        ms = 1e3 * run.seconds / len(frames)
        print(f"{title}; vision {ms:.2f} ms/frame", file=out)
        print(format_table(kinds), file=out)
        print(format_recall_by_distance(kinds), file=out)
        print("bars of the issue (stated for default images, >= 500 frames):", file=out)
        for b in bars:
            print(f"  {_bar_text(b)}", file=out)
        print(file=out)
        report["methods"][run.method] = {"available": True, "vision_ms_per_frame": ms, "kinds": kinds, "bars": bars}
    done = [r for r in runs if r.vision is not None]
    for run in done[1:]:
        report["methods"][run.method]["identical_to"] = None if run.differs else done[0].method
        if not run.differs:
            print(
                f"note: method {run.method} reported exactly the percepts of method {done[0].method} on every frame "
                "(does the pipeline implement it yet?)",
                file=out,
            )
    print(f"{len(frames)} frames: rendering {1e3 * render_s / len(frames):.2f} ms/frame, {wall:.1f} s in all", file=out)
    if args.out is not None:
        _write(args.out, runs, report)
        print(f"results written to {args.out}", file=out)
    return 0


def _bar_text(b: dict[str, Any]) -> str:
    v = "-" if b["value"] is None else f"{b['value']:.3f}"
    return f"{b['kind']} {b['figure'].replace('_', ' ')} {v} {b['op']} {b['bound']:g} {'ok' if b['ok'] else 'FAIL'}"


def _write(folder: Path, runs: list[MethodRun], report: dict[str, Any]) -> None:
    for stale in _results(folder):  # earlier results (refused above without --overwrite)
        stale.unlink()
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "metrics.json").write_text(json.dumps(report, indent=2, allow_nan=False, default=_json_default))
    rows = [row for run in runs for row in run.rows]
    with (folder / "frames.csv").open("w", newline="") as f:
        if rows:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    available = [r for r in runs if r.vision is not None]
    for run in available:
        name = "worst_frames.png" if len(runs) == 1 else f"worst_frames_{run.method}.png"
        panels = [overlay(img, ann, per, 2, cap) for _, _, img, ann, per, cap in run.worst]
        if not panels:  # not a single error: an empty picture says so
            panels = [np.zeros((480, 640, 3), dtype=np.uint8)]
            cv2.putText(panels[0], "no errors", (20, 240), cv2.FONT_HERSHEY_SIMPLEX, 1.0, (255, 255, 255), 2)
        save_png(folder / name, montage(panels))


def _json_default(obj: Any) -> Any:
    if isinstance(obj, np.integer | np.bool_):
        return obj.item()
    if isinstance(obj, np.floating):
        return None if not math.isfinite(obj) else float(obj)
    if isinstance(obj, tuple):
        return list(obj)
    raise TypeError(f"not JSON serializable: {type(obj).__name__}")
