"""One cognition frame of many brains (:func:`cognition.brain.think_all`): staged brains run
module by module over all robots, with the same outputs as brain by brain."""

from __future__ import annotations

import teamsim.match as match_module
from cognition.brain import StagedBrain, think_all
from cognition.pipeline import CognitionConfig
from cognition.profiling import ModuleProfile
from cognition.representations import BrainOutput, MotionRequest, SensorFrame, WalkRequest
from teamsim.match import Match, MatchConfig
from teamsim.referee import RefereeParams


class _Staged:
    """A staged brain that logs the order in which its stages run (into a shared log)."""

    uses_oracle = False
    stages = ("sense", "decide")

    def __init__(self, name: str, log: list[str]) -> None:
        self.name, self.log = name, log

    def reset(self, context: object) -> None:
        pass

    def think(self, frame: SensorFrame, oracle: object) -> BrainOutput:
        self.begin(frame, oracle)
        for s in self.stages:
            self.run_stage(s)
        return self.finish()

    def begin(self, frame: SensorFrame, oracle: object) -> None:
        self.frame = frame

    def run_stage(self, stage: str) -> None:
        self.log.append(f"{self.name}:{stage}")

    def finish(self) -> BrainOutput:
        return BrainOutput(MotionRequest(walk=WalkRequest(forward=0.01 * len(self.name))))


class _Plain:
    uses_oracle = False

    def __init__(self, log: list[str]) -> None:
        self.log = log

    def reset(self, context: object) -> None:
        pass

    def think(self, frame: SensorFrame, oracle: object) -> BrainOutput:
        self.log.append("plain")
        return BrainOutput(MotionRequest())


def test_staged_brains_run_stage_major_and_plain_brains_think() -> None:
    log: list[str] = []
    brains = [_Staged("a", log), _Plain(log), _Staged("bb", log)]
    assert isinstance(brains[0], StagedBrain) and not isinstance(brains[1], StagedBrain)
    profile = ModuleProfile()
    frames = [None, None, None]
    outs = think_all(brains, frames, [None] * 3, profile)  # type: ignore[arg-type]
    assert log == ["plain", "a:sense", "bb:sense", "a:decide", "bb:decide"]
    assert [o.motion.walk.forward for o in outs] == [0.01, 0.0, 0.02]  # each output at its brain's index
    assert list(profile.seconds) == ["other brains", "frame start", "sense", "decide"]


def test_the_default_match_is_the_same_stage_major_as_brain_by_brain() -> None:
    """The scripted team play on the full cognition stack (percepts, and the truth) gives the
    same match either way: the brains are independent within a frame."""
    for cognition in (CognitionConfig(), None):
        cfg = MatchConfig(
            seed=4, players_per_team=3, cognition=cognition,
            referee=RefereeParams(half_seconds=6.0, ready_seconds=3.0, halftime_seconds=1.0),
        )  # fmt: skip
        staged = Match(cfg)
        s1 = staged.run()
        one_by_one = Match(cfg)

        def brain_by_brain(brains, frames, oracles, profile=None):  # the loop think_all replaces
            return [b.think(f, o) for b, f, o in zip(brains, frames, oracles, strict=True)]

        original = match_module.think_all
        match_module.think_all = brain_by_brain
        try:
            s2 = one_by_one.run()
        finally:
            match_module.think_all = original
        assert repr(staged.snapshot()) == repr(one_by_one.snapshot())
        assert repr(staged.log.events) == repr(one_by_one.log.events)
        assert s1.localization == s2.localization and s1.score == s2.score
        assert isinstance(staged.brains[0], StagedBrain)
