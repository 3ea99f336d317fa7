"""``ball-rmse``: the structure of the Darmstadt paper's Table I, in simulation.

Ball RMSE in field coordinates for three observation models of the Kalman ball: fixed
angular sigmas of 5 degrees, fixed 15 degrees, and the adaptive sigmas the camera model
reports with each percept (Darmstadt Sec. IV-V). Two situations, as in the paper:

* **static**: one robot walks a fixed loop in its own half, its head on the ball, while the
  ball lies on the centre spot;
* **moving**: a goalkeeper stands in its goal area and watches balls rolled toward it every
  3 s from about 3 m away (they stop just before the keeper, so no goal interrupts).

For each seed one match is simulated and the robot's sensor frames recorded; each
observation model then runs offline on the same frames: a ``lowvar`` localization (the
same for all three) gives the pose, the Kalman ball the robot-frame ball, and the RMSE is
taken over every frame after the ball was first seen. The walking driver and the keeper's
head steer by ground truth (they are the experiment's script, not the estimators).

Results are appended to a JSON-lines file per (situation, seed) as they are computed, so an
interrupted run resumes where it stopped. The table gives mean RMSE with a 95% confidence
interval over seeds (t distribution).

Usage: ``python -m scenarios.ball_rmse [--seeds 20] [--out out/ball_rmse.jsonl]``
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from cognition.brain import BrainContext
from cognition.field import make_field
from cognition.gamestate import GameStateId
from cognition.localization import make_localizer
from cognition.oracle import OracleInput
from cognition.representations import BrainOutput, HeadRequest, MotionRequest, SensorFrame, WalkRequest
from cognition.worldmodel.ball import KalmanBallModel
from cognition.worldmodel.kalman_ball import KalmanBallParams
from teamsim.events import PlaceBall
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams

MODELS: dict[str, KalmanBallParams] = {
    "fixed 5 deg": KalmanBallParams(sigma_mode="fixed", fixed_sigma=math.radians(5.0)),
    "fixed 15 deg": KalmanBallParams(sigma_mode="fixed", fixed_sigma=math.radians(15.0)),
    "adaptive": KalmanBallParams(sigma_mode="adaptive"),
}
SITUATIONS = ("static", "moving")
SECONDS = 40.0
SETTLE = 0.5
"""Seconds after a ball placement that the RMSE leaves out."""
ROLLING_DECELERATION = 1.0
"""The simulator's ball deceleration on the carpet (m/s^2; ``teamsim.world``)."""
_T95 = {2: 12.706, 3: 4.303, 5: 2.776, 10: 2.262, 20: 2.093, 30: 2.045}
"""Two-sided 95% t quantiles by number of seeds (n - 1 degrees of freedom)."""


class Driver:
    """The experiment's robot: walks a loop (``static``) or keeps goal (``moving``), head on the ball."""

    uses_oracle = True
    LOOP = ((-3.0, -1.5), (-1.2, -1.5), (-1.2, 1.5), (-3.0, 1.5))

    def __init__(self, situation: str):
        self.situation = situation
        self.leg = 0

    def reset(self, context: BrainContext) -> None:
        self.context = context

    def think(self, frame: SensorFrame, oracle: OracleInput | None) -> BrainOutput:
        assert oracle is not None
        me = oracle.self_pose
        bearing = math.remainder(math.atan2(oracle.ball_y - me.y, oracle.ball_x - me.x) - me.theta, 2 * math.pi)
        head = HeadRequest(yaw=max(-1.5, min(1.5, bearing)), pitch=0.35)
        walk = WalkRequest()
        if self.situation == "static" and frame.game.state == GameStateId.PLAYING:
            tx, ty = self.LOOP[self.leg]
            if math.hypot(tx - me.x, ty - me.y) < 0.25:
                self.leg = (self.leg + 1) % len(self.LOOP)
                tx, ty = self.LOOP[self.leg]
            err = math.remainder(math.atan2(ty - me.y, tx - me.x) - me.theta, 2 * math.pi)
            walk = WalkRequest(forward=0.2 if abs(err) < 0.5 else 0.0, turn=max(-0.8, min(0.8, 1.5 * err)))
        return BrainOutput(MotionRequest(walk=walk, head=head))


KEEPER_POSE = (-4.2, 0.0, 0.0)
"""Where the goalkeeper stands in the ``moving`` situation (team frame = world frame)."""


def record(situation: str, seed: int) -> tuple[list[SensorFrame], np.ndarray, list[float]]:
    """The robot's frames, the true ball (team frame = world frame here) per frame and the
    times when a new ball was put down."""
    rng = np.random.default_rng(1000 + seed)
    events: list[PlaceBall] = []
    ref = RefereeParams(initial_seconds=0.5, ready_seconds=1.0, set_seconds=0.5, half_seconds=600.0)
    if situation == "moving":  # balls rolled at the keeper that stop 0.3 to 0.9 m before it
        t = 4.0
        while t < SECONDS:
            y0 = float(rng.uniform(-1.0, 1.0))
            tx, ty = KEEPER_POSE[0] + float(rng.uniform(0.3, 0.9)), float(rng.uniform(-0.5, 0.5))
            sx, sy = tx - (-1.5), ty - y0
            dist = math.hypot(sx, sy)
            speed = math.sqrt(2.0 * ROLLING_DECELERATION * dist)  # it stops at (tx, ty)
            events.append(PlaceBall(t, -1.5, y0, speed * sx / dist, speed * sy / dist))
            t += 3.0
    cfg = MatchConfig(seed=seed, players_per_team=1, referee=ref, events=tuple(events))
    m = Match(cfg, brains=lambda team, number: Driver(situation))
    if situation == "moving":  # the keeper stands in front of its goal
        m.kidnap(0, 1, KEEPER_POSE, False)
    frames, truth, last = [], [], None
    while m.time < SECONDS:
        m.step()
        f = m.last_frames[0]
        if f is not None and f is not last:
            last = f
            frames.append(f)
            truth.append(tuple(m.world.ball.position))
    return frames, np.array(truth), [ev.time for ev in events]


def rmse(
    frames: list[SensorFrame],
    truth: np.ndarray,
    params: KalmanBallParams,
    seed: int,
    situation: str = "static",
    placements: list[float] | None = None,
) -> float:
    """Field-coordinate ball RMSE (m) of one observation model on recorded frames, leaving
    out the first :data:`SETTLE` s after each ball placement (a real kick does not teleport
    the ball)."""
    field = make_field("spl2025")
    loc = make_localizer("lowvar", field, rng=np.random.default_rng(seed), player_number=1, players_per_team=1)
    if situation == "moving":  # the keeper knows where it was put
        loc.set_particles_around(np.array([KEEPER_POSE]))  # type: ignore[attr-defined]
    ball = KalmanBallModel(0.5 * field.dims.ball_diameter, params)
    sq = []
    seen = False
    for f, (bx, by) in zip(frames, truth, strict=True):
        pose = loc.update(f)
        b = ball.update(f, pose)
        seen = seen or b.source == "vision"
        settling = any(0.0 <= f.time - t < SETTLE for t in placements or ())
        if seen and not settling and math.isfinite(b.field_x):
            sq.append((b.field_x - bx) ** 2 + (b.field_y - by) ** 2)
    return float(math.sqrt(np.mean(sq))) if sq else math.nan


def run(seeds: int, out: Path) -> dict[str, dict[str, list[float]]]:
    """Compute (or resume) every (situation, seed); returns RMSEs per situation and model."""
    done: dict[tuple[str, int], dict[str, float]] = {}
    if out.exists():
        for line in out.read_text().splitlines():
            if line.strip():
                rec = json.loads(line)
                done[(rec["situation"], rec["seed"])] = rec["rmse"]
    out.parent.mkdir(parents=True, exist_ok=True)
    with out.open("a") as fh:
        for situation in SITUATIONS:
            for seed in range(seeds):
                if (situation, seed) in done:
                    continue
                frames, truth, placed = record(situation, seed)
                res = {name: rmse(frames, truth, prm, seed, situation, placed) for name, prm in MODELS.items()}
                fh.write(json.dumps({"situation": situation, "seed": seed, "rmse": res}) + "\n")
                fh.flush()
                done[(situation, seed)] = res
    table: dict[str, dict[str, list[float]]] = {s: {n: [] for n in MODELS} for s in SITUATIONS}
    for (situation, seed), res in done.items():
        if seed < seeds:
            for name, v in res.items():
                table[situation][name].append(v)
    return table


def format_table(table: dict[str, dict[str, list[float]]]) -> str:
    """Mean RMSE (cm) with 95% confidence intervals, as in the paper's Table I."""
    lines = [f"{'observation model':18s}" + "".join(f"{'RMSE ' + s + ' ball':>26s}" for s in SITUATIONS)]
    for name in MODELS:
        cells = []
        for s in SITUATIONS:
            v = np.array([x for x in table[s][name] if math.isfinite(x)]) * 100.0
            n = len(v)
            t = _T95.get(n, 1.96 if n > 30 else 2.3)
            half = t * v.std(ddof=1) / math.sqrt(n) if n > 1 else math.nan
            cells.append(f"{v.mean():8.1f} cm +- {half:4.1f} (n={n:2d})")
        lines.append(f"{name:18s}" + "".join(f"{c:>26s}" for c in cells))
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> dict[str, dict[str, list[float]]]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20, help="seeds per situation")
    ap.add_argument("--out", type=Path, default=Path("out/ball_rmse.jsonl"), help="results file (resumed)")
    args = ap.parse_args(argv)
    if args.seeds < 2:
        ap.error("--seeds must be at least 2 (confidence intervals)")
    table = run(args.seeds, args.out)
    print(format_table(table))
    return table


if __name__ == "__main__":
    main()
