"""Scenario files: the built-in ones load, and every kind of bad file is refused before anything
runs, naming the file, the key and what is allowed (exit 2 from the command line)."""

from __future__ import annotations

import math

import pytest

from scenarios.spec import ScenarioError, builtin_names, load, parse
from teamsim.cli import main
from teamsim.events import ForcePenalty, Kidnap, PlaceBall

GOOD = """
description = "a test"
duration = 20.0
variants = ["mcl", "reset"]
[match]
players_per_team = 2
[home]
brain = "observer"
trace = [1]
[[timeline]]
kind = "kidnap"
time = 5.0
team = "home"
number = 2
region = "own-half"
[[timeline]]
kind = "penalty"
time = 6.0
team = "away"
number = 1
code = "illegal_position"
[[timeline]]
kind = "ball"
time = 2.0
every = 4.0
until = 10.0
at = [1.0, 0.5]
roll_to = { x = [-1.0, -0.5], y = [0.0, 0.2] }
"""


def test_every_builtin_scenario_loads_with_its_variants():
    names = builtin_names()
    required = {"kidnap-standing", "kidnap-during-play", "kidnap-with-pickup", "penalties-spl2010",
                "penalties-spl2025", "lines-vs-no-lines", "ball-noise"}  # fmt: skip
    assert required <= set(names)
    for name in names:
        s = load(name)
        assert s.name == name and s.source == f"builtin:{name}" and s.duration > 0 and s.variants
        for v in s.variants:
            assert s.variant(v.name) is v
    assert load("penalties-spl2010").match.referee.rules == "spl2010"
    assert load("penalties-spl2025").variant("no-prior").localization_params.penalty_prior is False
    assert load("lines-vs-no-lines").variant("no-lines").localization_params.field_lines is False
    assert load("ball-noise").variant("fixed-15deg").ball.fixed_sigma == pytest.approx(math.radians(15.0))


def test_a_good_file_expands_its_timeline_the_same_for_every_variant(tmp_path):
    s = parse(GOOD.encode(), "good.toml", "good")
    ev = s.events(3)
    assert ev == s.events(3)  # the draws depend on the seed only
    assert ev != s.events(4)
    kinds = [type(e) for e in ev]
    assert kinds.count(PlaceBall) == 3 and kinds.count(Kidnap) == 1 and kinds.count(ForcePenalty) == 1
    assert [e.time for e in ev if isinstance(e, PlaceBall)] == [2.0, 6.0, 10.0]
    kid = next(e for e in ev if isinstance(e, Kidnap))
    assert kid.team == 0 and kid.number == 2 and -4.2 <= kid.pose[0] <= -0.3 and abs(kid.pose[1]) <= 2.7
    pen = next(e for e in ev if isinstance(e, ForcePenalty))
    assert pen.team == 1 and pen.code == 5
    for b in (e for e in ev if isinstance(e, PlaceBall)):  # rolled to stop inside the target box
        speed = math.hypot(b.vx, b.vy)
        stop = (b.x + b.vx / speed * speed**2 / 2.0, b.y + b.vy / speed * speed**2 / 2.0)
        assert -1.0 - 1e-9 <= stop[0] <= -0.5 + 1e-9 and -1e-9 <= stop[1] <= 0.2 + 1e-9
    cfg = s.config(3)
    assert cfg.seed == 3 and cfg.events == ev and cfg.players_per_team == 2
    assert s.traced() == (1,)
    with pytest.raises(ScenarioError, match=r"unknown variant 'nope'.*'maturing'"):
        s.variant("nope")


def _bad(fragment: str, replace: str = "", append: str = "", prepend: str = "") -> str:
    text = GOOD.replace(fragment, replace) if fragment else GOOD
    return prepend + text + append


BAD = [
    # (file text, fragments the error must hold)
    (_bad("", prepend="speed = 3\n"), ["bad.toml", "top level", "unknown key(s) ['speed']", "valid keys"]),
    (_bad('description = "a test"\n', 'description = "a test"\nduration = 5\n'), ["bad.toml", "not valid TOML"]),
    (_bad("duration = 20.0\n"), ["bad.toml", "missing key(s) ['duration']"]),
    (_bad("duration = 20.0", "duration = -1"), ["bad.toml", "duration", "(0, 3600]"]),
    (_bad('variants = ["mcl", "reset"]', 'variants = ["mcl", "fastslam"]'), ["variants[1]", "'fastslam'", "maturing"]),
    (_bad("players_per_team = 2", "players_per_team = 2\nseed = 4"), ["match", "unknown key(s) ['seed']"]),
    (_bad("players_per_team = 2", "players_per_team = 2\nwind = 4"), ["match", "unknown key(s) ['wind']"]),
    (_bad("players_per_team = 2", "players_per_team = 9"), ["MatchConfig.players_per_team", "9"]),
    (_bad('brain = "observer"', 'brain = "genius"'), ["home.brain", "'genius'", "observer"]),
    (_bad('brain = "observer"', 'brain = "random"'), ["home.brain", "does not localize"]),
    (_bad("trace = [1]", "trace = [3]"), ["home.trace[0]", "player 3 does not exist", "1..2"]),
    (_bad("number = 2\n", "number = 6\n"), ["timeline[0].number", "player 6 does not exist"]),
    (_bad('region = "own-half"', "pose = [12.0, 0.0, 0.0]"), ["timeline[0].pose", "off the carpet"]),
    (_bad('region = "own-half"', 'region = "moon"'), ["timeline[0].region", "'moon'", "own-half"]),
    (_bad('code = "illegal_position"', "code = 13"), ["timeline[1].code", "unknown penalty 13", "illegal_position"]),
    (_bad('code = "illegal_position"', 'code = "offside"'), ["timeline[1].code", "'offside'"]),
    (_bad('kind = "kidnap"', 'kind = "teleport"'), ["timeline[0].kind", "'teleport'", "kidnap"]),
    (_bad('team = "home"', 'team = "red"'), ["timeline[0].team", "'red'", "home"]),
    (_bad("time = 5.0", "time = 50.0"), ["timeline[0].time", "[0, 20]"]),
    (_bad("time = 5.0", "time = 5.0\nspeed = 1"), ["timeline[0]", "unknown key(s) ['speed']"]),
    (_bad('region = "own-half"\n', ""), ["timeline[0]", "either 'pose' or 'region'"]),
    (_bad("", append='[variants.x]\nlocalization = "mcl"\n'), ["bad.toml", "not valid TOML"]),
    (_bad("", append="[recovery]\nerror_m = 0\n"), ["recovery.error_m", "(0, 100]"]),
    (_bad("", prepend='metrics = ["speed"]\n'), ["metrics[0]", "'speed'", "localization"]),
]


@pytest.mark.parametrize(("text", "fragments"), BAD, ids=[f"bad{i}" for i in range(len(BAD))])
def test_a_bad_file_is_refused_naming_the_file_and_the_key(text, fragments, tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ScenarioError) as info:
        load(path)
    for f in fragments:
        assert f in str(info.value), (f, str(info.value))
    code = main(["scenario", "run", str(path), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("teamsim scenario: error: ") and "Traceback" not in err
    assert fragments[0] in err and not (tmp_path / "out").exists()  # refused before anything ran


def test_custom_variants_are_checked_and_named(tmp_path):
    text = GOOD.replace('variants = ["mcl", "reset"]\n', "") + (
        '[variants.slow]\nlocalization = "mcl"\nlocalization_params = { particles = 50 }\n'
        '[variants.bad]\nlocalization = "reset"\nlocalization_params = { particles = -5 }\n'
    )
    path = tmp_path / "v.toml"
    path.write_text(text)
    with pytest.raises(ScenarioError, match=r"v.toml.*particles.*-5"):
        load(path)
    path.write_text(text.replace("particles = -5", "partikels = 5"))
    with pytest.raises(ScenarioError, match=r"unknown LocalizationParams key\(s\) \['partikels'\]"):
        load(path)
    path.write_text(text.replace("particles = -5", "particles = 80"))
    s = load(path)
    assert [v.name for v in s.variants] == ["slow", "bad"] and s.variant("slow").localization_params.particles == 50
    with pytest.raises(ScenarioError, match=r"unknown variant 'mcl'.*\['slow', 'bad'\]"):
        s.variant("mcl")  # with tables, only the file's variants exist


def test_unknown_names_on_the_command_line_exit_2(tmp_path, capsys):
    assert main(["scenario", "run", "no-such-scenario"]) == 2
    assert "no scenario 'no-such-scenario'" in capsys.readouterr().err
    argv = ["compare", "--scenario", "kidnap-standing", "--variant", "mcl", "magic", "--out", str(tmp_path / "o")]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "unknown variant 'magic'" in err and "lowvar" in err and not (tmp_path / "o").exists()
    assert main(["compare", "--report-only", str(tmp_path)]) == 2
    assert "no runs.csv" in capsys.readouterr().err
    assert main(["scenario", "list"]) == 0
    listed = capsys.readouterr().out
    assert all(name in listed for name in builtin_names())


def test_a_variant_chooses_the_providers_of_other_modules(tmp_path):
    """``modules`` sets slots of the cognition frame by name; the home brains run them."""
    from scenarios.runner import simulate

    text = GOOD.replace('variants = ["mcl", "reset"]\n', "") + (
        '[variants.grid]\nlocalization = "odometry"\nmodules = { obstacles = "grid", goal = "none" }\n'
        '[variants.plain]\nlocalization = "odometry"\n'
    )
    path = tmp_path / "m.toml"
    path.write_text(text)
    s = load(path)
    config = s.variant("grid").cognition()
    assert (config.obstacles, config.goal, config.localization) == ("grid", "none", "odometry")
    assert s.variant("plain").cognition().obstacles == "sectors"
    _, match = simulate(s, "grid", 0)
    provider = match.brains[0].provider  # type: ignore[attr-defined]
    assert type(provider.obstacles).__name__ == "ObstacleGrid" and "goal model" not in provider.stages
    away = match.brains[-1].provider  # type: ignore[attr-defined]
    assert type(away.obstacles).__name__ == "ObstacleSectors" and "goal model" in away.stages  # its own defaults
    path.write_text(text.replace('goal = "none"', 'goal = "hough"'))
    with pytest.raises(ScenarioError, match=r"variants\.grid\.modules\.goal must be one of \['posts', 'none'\]"):
        load(path)
    path.write_text(text.replace('goal = "none"', 'localization = "amcl"'))
    with pytest.raises(ScenarioError, match=r"variants\.grid\.modules: unknown key\(s\) \['localization'\]"):
        load(path)
