"""What building a frozen representation costs, with and without :func:`cognition.records.fast_init`.

A cognition frame hands its results from module to module as frozen dataclasses (sensor frame,
pose, ball, beliefs, motion request, ...), about twenty per robot and frame. This times the
construction of the hot ones, on values taken from a running match, with the class as shipped
(``fast_init``) and with the ``__init__`` that ``dataclass(frozen=True)`` writes (a twin class
with the same fields and ``__post_init__``), and a plain (not frozen) dataclass of ten floats
for scale. Each figure is the fastest of ``--repeats`` runs of ``--number`` constructions.

==========================  ===============================================================
figure                      meaning
==========================  ===============================================================
<Record>_fast_us            one construction with ``fast_init`` (us)
<Record>_dataclass_us       one construction with the dataclass's own ``__init__`` (us)
plain10_us                  a plain dataclass of ten floats (us)
frozen10_us                 a frozen dataclass of ten floats, the dataclass's ``__init__`` (us)
==========================  ===============================================================

Usage: ``python -m benchmarks.bench_records [--number 20000] [--repeats 5] [--json out.json]``
"""

from __future__ import annotations

import argparse
import dataclasses
import timeit
from collections.abc import Callable
from pathlib import Path
from typing import Any

from benchmarks.common import write_figures
from cognition.records import dataclass_twin
from cognition.representations import BallModel, HeadRequest, MotionRequest, RobotPose, SensorFrame, WalkRequest
from cognition.worldmodel.representations import Beliefs, Teammate
from teamsim.match import Match, MatchConfig


def _time(build: Callable[[], object], number: int, repeats: int) -> float:
    return min(timeit.repeat(build, number=number, repeat=repeats)) / number * 1e6


def main(argv: list[str] | None = None) -> dict[str, float]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--number", type=int, default=20000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    match = Match(MatchConfig(seed=0))
    match.run(until=5.0)
    beliefs = match.brains[3].beliefs
    assert beliefs is not None
    samples: list[Any] = [
        match.last_frames[3], beliefs.pose, beliefs.ball, beliefs, WalkRequest(0.1, 0.0, 0.2), HeadRequest(0.1, 0.3),
        MotionRequest(), Teammate(2, 1.0, 0.5, 0.1, 0.3),
    ]  # fmt: skip
    assert [type(s) for s in samples] == [
        SensorFrame, RobotPose, BallModel, Beliefs, WalkRequest, HeadRequest, MotionRequest, Teammate
    ]  # fmt: skip
    figures: dict[str, float] = {}
    print(f"{'record':16s} {'fast_init':>10s} {'dataclass':>10s}   (us per construction)")
    for sample in samples:
        cls = type(sample)
        values = [getattr(sample, f.name) for f in dataclasses.fields(sample)]
        twin = dataclass_twin(cls)
        fast = _time(lambda cls=cls, values=values: cls(*values), args.number, args.repeats)
        slow = _time(lambda twin=twin, values=values: twin(*values), args.number, args.repeats)
        figures[f"{cls.__name__}_fast_us"], figures[f"{cls.__name__}_dataclass_us"] = fast, slow
        print(f"{cls.__name__:16s} {fast:10.2f} {slow:10.2f}")
    names = [f"f{i}" for i in range(10)]
    plain = dataclasses.make_dataclass("Plain", [(n, float) for n in names])
    frozen = dataclasses.make_dataclass("Frozen", [(n, float) for n in names], frozen=True)
    ten = [float(i) for i in range(10)]
    figures["plain10_us"] = _time(lambda: plain(*ten), args.number, args.repeats)
    figures["frozen10_us"] = _time(lambda: frozen(*ten), args.number, args.repeats)
    print(f"ten floats: plain dataclass {figures['plain10_us']:.2f} us, frozen {figures['frozen10_us']:.2f} us")
    write_figures(args.json, figures)
    return figures


if __name__ == "__main__":
    main()
