"""Where the time of a match goes: ``teamsim match --profile``.

``Match(config, profile=True)`` times its own stages, and :func:`cognition.brain.think_all`,
which runs the brains' frame module by module over all robots, adds the time of each module
into a :class:`~cognition.profiling.ModuleProfile`. The table
divides every total by the robot-frames played (brain calls), so the rows add up to the wall
time of one robot's cognition frame including its share of the world's work:

=========================  ===================================================================
row                        what it times
=========================  ===================================================================
physics                    the world's physics steps (pymunk, robots, ball)
referee                    the referee after every physics step
camera                     percept synthesis, or rendering the camera images with their effects
cognition: MODULE          one module of the brains (frame start, input check, vision,
                           localization, team messages, ball model, ball hypotheses, team ball,
                           obstacles, goal model, beliefs, behaviour, team message out; ``other
                           brains``: brains without stages, e.g. the random walkers)
cognition: other           the rest of the brains' time (grouping them, collecting outputs)
match glue                 the match's side of a cognition frame: sensor frames, odometry, team
                           channel, error bookkeeping, commands
other                      the rest of the run (events, the step loop, callbacks such as video)
=========================  ===================================================================

Timing costs a few ``perf_counter`` calls per stage and module; the match's results are the
same with and without a profile.
"""

from __future__ import annotations

from cognition.profiling import ModuleProfile

__all__ = ["MatchProfile"]


class MatchProfile:
    """Seconds per stage of one match (module table), and the brains' modules."""

    WORLD = ("physics", "referee", "camera")

    def __init__(self) -> None:
        self.world = ModuleProfile()
        """Seconds of the match's own stages (:data:`WORLD`)."""
        self.brains = 0.0
        """Seconds inside the brains' frames (:func:`cognition.brain.think_all`)."""
        self.cognition_frames = 0.0
        """Seconds inside the match's cognition frames, brains included."""
        self.robot_frames = 0
        """Brain calls (robots times cognition frames)."""
        self.modules = ModuleProfile()
        """The brains' modules, as :func:`cognition.brain.think_all` timed them."""

    def rows(self, wall: float) -> list[tuple[str, float]]:
        """(row, seconds) of the module table, for a run of ``wall`` seconds."""
        out = [(name, self.world.seconds.get(name, 0.0)) for name in self.WORLD]
        modules = self.modules.seconds
        out += [(f"cognition: {name}", s) for name, s in modules.items()]
        out.append(("cognition: other", max(0.0, self.brains - self.modules.total())))
        out.append(("match glue", max(0.0, self.cognition_frames - self.brains)))
        counted = sum(s for _, s in out)
        out.append(("other", max(0.0, wall - counted)))
        return out

    def format(self, wall: float, simulated: float) -> str:
        """The table: microseconds per robot-frame and share of the wall time per row."""
        n = max(1, self.robot_frames)
        lines = [
            f"profile        {self.robot_frames} robot-frames in {wall:.1f} s wall "
            f"({simulated:.1f} s simulated, {simulated / wall if wall > 0 else 0.0:.1f}x real time)",
            f"  {'stage':32s} {'us per robot-frame':>18s} {'share':>7s}",
        ]
        for name, s in self.rows(wall):
            share = 100.0 * s / wall if wall > 0 else 0.0
            lines.append(f"  {name:32s} {1e6 * s / n:18.1f} {share:6.1f}%")
        lines.append(f"  {'total':32s} {1e6 * wall / n:18.1f} {100.0:6.1f}%")
        return "\n".join(lines)
