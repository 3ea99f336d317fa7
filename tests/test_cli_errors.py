"""Bad input to the ``teamsim`` command line and to ``from_mapping``: clear one-line errors, never tracebacks.

Every bad input exits with code 2 and prints exactly one line on stderr, ``teamsim <command>: error: ...``,
naming the option or the key path (and the file, for ``--config``). The tests run ``teamsim.cli.main``
in-process; a few go through a subprocess to see what a user sees. Nothing here plays a full match.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from cognition.params import from_mapping
from teamsim.match import MatchConfig
from teamsim.robot import RobotParams


# -- from_mapping: key paths and types -------------------------------------------------------
@pytest.mark.parametrize(
    ("data", "error", "path"),
    [
        ({"physics": 5}, TypeError, "MatchConfig.physics: expected a mapping or PhysicsParams, got int"),
        ({"referee": []}, TypeError, "MatchConfig.referee: expected a mapping or RefereeParams, got list"),
        ({"physics": {"robot": 5}}, TypeError, "MatchConfig.physics.robot: expected a mapping or RobotParams"),
        ({"odometry": None}, TypeError, "MatchConfig.odometry: expected a mapping or OdometryParams, got NoneType"),
        ({"referee": {"fouls": 5}}, TypeError, "MatchConfig.referee.fouls: expected a mapping or FoulParams"),
        ({"percepts": 5}, TypeError, "MatchConfig.percepts: expected a mapping, a preset name or PerceptParams"),
        ({"seed": True}, TypeError, "MatchConfig.seed: expected an integer, got bool True"),
        ({"seed": 1.5}, TypeError, "MatchConfig.seed: expected an integer, got float 1.5"),
        ({"field": {}}, TypeError, "MatchConfig.field: expected a string, got dict"),
        ({"physics": {"robot": {"radius": "x"}}}, TypeError, "MatchConfig.physics.robot.radius: expected a number"),
        ({"images": {"white_balance": [1, 2]}}, TypeError, "MatchConfig.images.white_balance: expected a list of 3"),
        ({"images": {"white_balance": [1, 2, "x"]}}, TypeError, "MatchConfig.images.white_balance[2]: expected a"),
        ({"referee": {"rules": "spl1999"}}, ValueError, "MatchConfig.referee.rules: expected one of 'spl2025'"),
        ({"physics": {"robot": {"radius": -1}}}, ValueError, "MatchConfig.physics.robot.radius must be"),
        ({"referee": {"fouls": {"nope": 1}}}, ValueError, "unknown MatchConfig.referee.fouls key(s) ['nope']"),
    ],
)
def test_from_mapping_names_the_key_path(data: dict, error: type[Exception], path: str) -> None:
    with pytest.raises(error) as info:
        MatchConfig.from_mapping(data)
    assert path in str(info.value)


def test_from_mapping_keeps_listing_the_valid_keys_and_accepts_instances_and_lists() -> None:
    with pytest.raises(ValueError, match=r"unknown MatchConfig\.physics\.robot key\(s\) \['radiu'\]; valid keys: \["):
        MatchConfig.from_mapping({"physics": {"robot": {"radiu": 0.2}}})
    robot = RobotParams(radius=0.2)
    cfg = MatchConfig.from_mapping({"physics": {"robot": robot}, "images": {"white_balance": [1, 1, 0.9]}})
    assert cfg.physics.robot is robot
    assert cfg.images.white_balance == (1, 1, 0.9)  # a JSON list becomes the annotated tuple
    assert from_mapping(RobotParams, {"radius": 0.2}, "physics.robot").radius == 0.2
    with pytest.raises(ValueError, match=r"^physics\.robot\.radius must be"):  # ``where`` is the path
        from_mapping(RobotParams, {"radius": 0.0}, "physics.robot")


# -- the command line: one line on stderr, exit 2 --------------------------------------------
QUICK = ["--half-seconds", "1", "--players-per-team", "1", "--observation", "none", "--localization", "none"]
DEEP = '{"a": ' * 100_000 + "1" + "}" * 100_000  # json.loads raises RecursionError on this
TRAIN = ["train", "--env", "teamsim/Striker-v0", "--timesteps", "64", "--no-progress"]
EVALUATE = ["evaluate", "--model", "random", "--env", "teamsim/Striker-v0", "--episodes", "1"]

# (argv, content of the --config file CFG or None, fragments the error line must hold)
BAD_INPUTS: list[tuple[list[str], str | bytes | None, list[str]]] = [
    # --config: the file itself
    (["match", "--config", "CFG"], '{"seed": ', ["config file", "c.json", "is not valid JSON"]),
    (["match", "--config", "MISSING"], None, ["config file not found", "missing.json"]),
    (["match", "--config", "DIR"], None, ["config file", "is not a file"]),
    (["match", "--config", "CFG"], "[1, 2]", ["config file", "c.json", "must hold a JSON object, got an array"]),
    (["match", "--config", "CFG"], b'{"seed": "\xff"}', ["config file", "c.json", "not UTF-8"]),
    (["match", "--config", "CFG"], '{"seed": 1, "seed": 2}', ["c.json", "'seed' appears twice"]),
    (["match", "--config", "CFG"], DEEP, ["c.json", "nests objects or arrays deeper than 32"]),
    (["match", "--config", "CFG"], '{"a": ' * 40 + "1" + "}" * 40, ["c.json", "deeper than 32"]),
    # --config: unknown keys at every level
    (["match", "--config", "CFG"], '{"speed": 3}', ["c.json", "unknown MatchConfig key(s) ['speed']", "valid keys"]),
    (["match", "--config", "CFG"], '{"physics": {"hz": 3}}', ["c.json", "unknown MatchConfig.physics key(s) ['hz']"]),
    (["match", "--config", "CFG"], '{"physics": {"robot": {"r": 1}}}', ["c.json", "MatchConfig.physics.robot key"]),
    (["match", "--config", "CFG"], '{"referee": {"fouls": {"x": 1}}}', ["c.json", "MatchConfig.referee.fouls key"]),
    (["match", "--config", "CFG"], '{"percepts": "noisy"}', ["c.json", "unknown MatchConfig.percepts preset"]),
    (["match", "--config", "CFG"], '{"events": {}}', ["c.json", "MatchConfig.events: expected a list"]),
    (["match", "--config", "CFG"], '{"events": [{"kind": "teleport"}]}', ["c.json", "events[0].kind", "'teleport'"]),
    (
        ["match", "--config", "CFG"],
        '{"events": [{"kind": "kidnap", "time": 1, "team": 0, "number": 9}]}',
        ["c.json", "MatchConfig.events[0]", "player 9"],
    ),
    (
        ["match", "--config", "CFG"],
        '{"events": [{"kind": "penalty", "time": 1, "team": 0, "number": 1, "code": 13}]}',
        ["c.json", "MatchConfig.events[0].code", "13"],
    ),
    # --config: the removed oracle players, with what replaced them
    (
        ["match", "--config", "CFG"],
        '{"players": "oracle"}',
        ["c.json", "MatchConfig.players='oracle'", "removed", "players='scripted' with no cognition"],
    ),
    (
        ["match", "--config", "CFG"],
        '{"players": "oracle", "cognition": {"localization": "lowvar"}}',
        ["c.json", "MatchConfig.players='oracle'", "players='scripted' with this cognition", "localization=lowvar"],
    ),
    # --config: sections and values of the wrong type
    (["match", "--config", "CFG"], '{"physics": 5}', ["c.json: MatchConfig.physics: expected a mapping"]),
    (["match", "--config", "CFG"], '{"referee": []}', ["c.json: MatchConfig.referee: expected a mapping"]),
    (["match", "--config", "CFG"], '{"physics": {"robot": 5}}', ["c.json: MatchConfig.physics.robot: expected a"]),
    (["match", "--config", "CFG"], '{"odometry": 5}', ["c.json: MatchConfig.odometry: expected a mapping"]),
    (["match", "--config", "CFG"], '{"referee": {"fouls": 5}}', ["c.json: MatchConfig.referee.fouls: expected a"]),
    (["match", "--config", "CFG"], '{"seed": "7"}', ["c.json: MatchConfig.seed: expected an integer, got str"]),
    (["match", "--config", "CFG"], '{"field": 5}', ["c.json: MatchConfig.field: expected a string"]),
    # --config: values out of range
    (["match", "--config", "CFG"], '{"seed": -1}', ["c.json", "MatchConfig.seed", "-1"]),
    (["match", "--config", "CFG"], '{"referee": {"half_seconds": -5}}', ["c.json", "MatchConfig.referee.half_seconds"]),
    (["match", "--config", "CFG"], '{"physics": {"robot": {"radius": 0}}}', ["c.json", "physics.robot.radius"]),
    # match options
    (["match", "--seed", "-1"], None, ["argument --seed", "-1"]),
    (["match", "--seed", "x"], None, ["argument --seed", "'x'"]),
    (["match", "--players-per-team", "9"], None, ["argument --players-per-team", "1..7", "9"]),
    (["match", "--half-seconds", "nan"], None, ["argument --half-seconds", "nan"]),
    (["match", "--video-fps", "0"], None, ["argument --video-fps", "> 0"]),
    (["match", "--field", "wembley"], None, ["argument --field", "invalid choice: 'wembley'"]),
    (["match", "--players", "oracle"], None, ["argument --players", "invalid choice: 'oracle'"]),
    (["match", "--opponents", "oracle"], None, ["argument --opponents", "invalid choice: 'oracle'"]),
    (["match", *QUICK, "--video-robot", "3:1"], None, ["--video-robot", "'3:1'"]),
    (["match", *QUICK, "--video-robot", "0:4"], None, ["--video-robot", "does not exist", "1..1"]),
    (["match", *QUICK, "--video", "FILE/m.mp4"], None, ["m.mp4"]),
    # camera
    (["camera", "--size", "100000x100000", "--out", "OUT"], None, ["--size", "16..4096", "100000x100000"]),
    (["camera", "--size", "wide", "--out", "OUT"], None, ["--size", "WIDTHxHEIGHT", "'wide'"]),
    (["camera", "--time", "-1", "--out", "OUT"], None, ["argument --time", "-1"]),
    (["camera", "--time", "inf", "--out", "OUT"], None, ["argument --time", "inf"]),
    (["camera", "--robot", "2:1", "--out", "OUT"], None, ["--robot", "'2:1'", "does not exist"]),
    (["camera", "--out", "FILE"], None, ["--out", "exists and is not a directory"]),
    # train and evaluate
    ([*TRAIN, "--out", "OUT", "--hyperparams", '{"learning_rate": "x"}'], None, ["hyperparams.learning_rate", "'x'"]),
    ([*TRAIN, "--out", "OUT", "--hyperparams", '{"n_steps": 0}'], None, ["hyperparams.n_steps", "[1, 1e+06]", "0"]),
    ([*TRAIN, "--out", "OUT", "--hyperparams", '{"gama": 0.9}'], None, ["unknown hyperparams key(s) ['gama']"]),
    ([*TRAIN, "--out", "OUT", "--hyperparams", '{"seed": 3}'], None, ["hyperparams ['seed']", "set by train()"]),
    ([*TRAIN, "--out", "OUT", "--hyperparams", "[1]"], None, ["--hyperparams must be a JSON object, got an array"]),
    ([*TRAIN, "--out", "OUT", "--hyperparams", "{"], None, ["--hyperparams is not valid JSON"]),
    ([*TRAIN, "--out", "OUT", "--env-kwargs", '{"max_cycle": 3}'], None, ["unknown env_kwargs key(s) ['max_cycle']"]),
    ([*TRAIN, "--out", "OUT", "--env-kwargs", DEEP], None, ["--env-kwargs nests objects or arrays deeper"]),
    ([*TRAIN, "--out", "OUT", "--n-envs", "100000"], None, ["argument --n-envs", "1..256"]),
    ([*TRAIN, "--out", "OUT", "--seed", "5000000000"], None, ["argument --seed", "0..2147483647"]),
    ([*TRAIN, "--out", "OUT", "--resume", "--overwrite"], None, ["resume and overwrite exclude each other"]),
    (["train", "--env", "teamsim/Striker-v0"], None, ["the following arguments are required: --timesteps, --out"]),
    ([*EVALUATE, "--env-kwargs", '{"reward_weights": 5}'], None, ["reward_weights"]),
    ([*EVALUATE, "--episodes", "0"], None, ["argument --episodes", "0"]),
    ([*EVALUATE, "--out", "DIR"], None, ["out", "exists and is not a file"]),
]


def _argv(argv: list[str], content: str | bytes | None, tmp_path: Path) -> list[str]:
    """``argv`` with its placeholders replaced by paths under ``tmp_path`` (the config file written)."""
    (tmp_path / "folder").mkdir()
    (tmp_path / "file").write_text("not a directory")
    config = tmp_path / "c.json"
    if isinstance(content, bytes):
        config.write_bytes(content)
    elif content is not None:
        config.write_text(content)
    places = {"CFG": config, "MISSING": tmp_path / "missing.json", "DIR": tmp_path / "folder", "OUT": tmp_path / "out"}
    out = [str(places[a]) if a in places else a for a in argv]
    return [a.replace("FILE", str(tmp_path / "file")) for a in out]


def _one_error_line(command: str, capsys: pytest.CaptureFixture[str]) -> str:
    """The single stderr line of a refused command (asserted: one line, the command's prefix, no traceback)."""
    err = capsys.readouterr().err
    lines = err.splitlines()
    assert len(lines) == 1, err[:2000]
    assert lines[0].startswith(f"teamsim {command}: error: "), lines[0]
    assert "Traceback" not in err
    return lines[0]


@pytest.mark.parametrize(
    ("argv", "content", "fragments"), BAD_INPUTS, ids=[f"{i:02d}-{a[0]}" for i, (a, _, _) in enumerate(BAD_INPUTS)]
)
def test_bad_input_exits_2_with_one_line_naming_it(
    argv: list[str],
    content: str | bytes | None,
    fragments: list[str],
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    from teamsim.cli import main

    assert main(_argv(argv, content, tmp_path)) == 2
    line = _one_error_line(argv[0], capsys)
    for fragment in fragments:
        assert fragment in line, (fragment, line)
    assert not (tmp_path / "out").exists()  # refused before anything was written


def test_a_request_larger_than_memory_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The localization's candidate buffer sized by the config: bounded by its range, or at worst a MemoryError."""
    from teamsim.cli import main

    config = tmp_path / "c.json"
    config.write_text(json.dumps({"cognition": {"localization_params": {"maturing_candidates": 10**12}}}))
    argv = ["match", "--config", str(config), *QUICK[:4], "--localization", "maturing"]
    assert main(argv) == 2
    line = _one_error_line("match", capsys)
    assert "maturing_candidates" in line or "out of memory" in line, line


def test_memory_error_is_reported_but_a_bug_keeps_its_traceback(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    import teamsim.cli as cli

    def exhausted(*args: object, **kwargs: object) -> None:
        raise MemoryError("Unable to allocate 7.3 TiB")

    monkeypatch.setattr(cli, "Match", exhausted)
    assert cli.main(["match", *QUICK]) == 2
    assert "out of memory (Unable to allocate 7.3 TiB)" in _one_error_line("match", capsys)

    def buggy(*args: object, **kwargs: object) -> None:
        raise KeyError("a bug")

    monkeypatch.setattr(cli, "Match", buggy)
    with pytest.raises(KeyError):
        cli.main(["match", *QUICK])


@pytest.mark.parametrize(
    ("argv", "config", "fragment"),
    [
        (["match"], DEEP, "nests objects or arrays deeper than 32"),
        (["match"], '{"referee": {"fouls": 5}}', "MatchConfig.referee.fouls: expected a mapping"),
        (["train", "--env", "teamsim/Striker-v0", "--timesteps", "64", "--hyperparams", '{"learning_rate": "x"}'], None,
         "hyperparams.learning_rate"),
        (["camera", "--size", "100000x100000"], None, "--size"),
    ],
    ids=["deep-config", "fouls-not-a-mapping", "learning-rate-a-string", "huge-image"],
)  # fmt: skip
def test_what_a_user_sees_in_a_terminal(argv: list[str], config: str | None, fragment: str, tmp_path: Path) -> None:
    import subprocess
    import sys

    if config is not None:
        (tmp_path / "c.json").write_text(config)
        argv = [*argv, "--config", str(tmp_path / "c.json")]
    argv = [*argv, "--out", str(tmp_path / "out")]
    done = subprocess.run([sys.executable, "-m", "teamsim", *argv], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1 and "Traceback" not in done.stderr, done.stderr[-3000:]
    assert done.stderr.startswith(f"teamsim {argv[0]}: error: ") and fragment in done.stderr


# -- options override the config file only when given --------------------------------------
def _config(tmp_path: Path, data: dict, *argv: str) -> MatchConfig:
    from teamsim.cli import build_parser, config_from_args

    path = tmp_path / "c.json"
    path.write_text(json.dumps(data))
    return config_from_args(build_parser().parse_args(["match", "--config", str(path), *argv]))


def test_the_config_seed_is_used_unless_seed_is_given(tmp_path: Path) -> None:
    from teamsim.cli import build_parser, config_from_args

    assert _config(tmp_path, {"seed": 7}).seed == 7
    assert _config(tmp_path, {"seed": 7}, "--seed", "3").seed == 3
    assert _config(tmp_path, {"seed": 7}, "--seed", "0").seed == 0  # an explicit 0 wins too
    assert config_from_args(build_parser().parse_args(["match"])).seed == 0


def test_options_replace_only_the_keys_they_name(tmp_path: Path) -> None:
    data = {
        "players_per_team": 2,
        "referee": {"half_seconds": 30, "penalty_seconds": 20},
        "percepts": {"preset": "harsh", "latency": 0.0},
        "images": "ideal",
        "cognition": {"localization": "amcl"},
    }
    kept = _config(tmp_path, data)
    assert kept.players_per_team == 2 and kept.referee.half_seconds == 30 and kept.cognition.localization == "amcl"
    assert kept.percepts.latency == 0.0 and kept.images == MatchConfig.from_mapping({"images": "ideal"}).images
    changed = _config(tmp_path, data, "--half-seconds", "5", "--percepts", "ideal", "--players-per-team", "3")
    assert changed.referee.half_seconds == 5 and changed.referee.penalty_seconds == 20
    assert changed.percepts.latency == 0.0  # the file's key stays on top of the option's preset
    ideal = MatchConfig.from_mapping({"percepts": "ideal"}).percepts
    assert changed.percepts.sigma_alpha_base == ideal.sigma_alpha_base and changed.players_per_team == 3


def test_the_seed_of_the_config_reaches_the_match_results(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from teamsim.cli import main

    (tmp_path / "c.json").write_text('{"seed": 5}')
    assert main(["match", *QUICK, "--config", str(tmp_path / "c.json"), "--out", str(tmp_path / "out")]) == 0
    assert json.loads((tmp_path / "out" / "config.json").read_text())["seed"] == 5
    assert json.loads((tmp_path / "out" / "summary.json").read_text())["seed"] == 5
    assert "seed=5" in capsys.readouterr().out


# -- --out never mixes two runs -----------------------------------------------------------
def _without_timing(summary: dict) -> dict:
    return {k: v for k, v in summary.items() if "wall" not in k and "real_time" not in k}


def test_match_out_refuses_earlier_results_and_overwrite_replaces_them(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from teamsim.cli import main

    out = tmp_path / "out"
    assert main(["match", *QUICK, "--seed", "1", "--out", str(out)]) == 0
    before = {name: (out / name).read_bytes() for name in ("config.json", "events.jsonl", "summary.json")}
    capsys.readouterr()
    assert main(["match", *QUICK, "--seed", "2", "--out", str(out)]) == 2
    line = _one_error_line("match", capsys)
    assert str(out) in line and "--overwrite" in line and "another directory" in line
    assert {name: (out / name).read_bytes() for name in before} == before  # untouched

    (out / "notes.txt").write_text("mine")
    assert main(["match", *QUICK, "--seed", "2", "--out", str(out), "--overwrite"]) == 0
    assert main(["match", *QUICK, "--seed", "2", "--out", str(tmp_path / "fresh")]) == 0
    for name in ("config.json", "events.jsonl"):  # exactly what a run into an empty directory writes
        assert (out / name).read_bytes() == (tmp_path / "fresh" / name).read_bytes()
    summary = json.loads((out / "summary.json").read_text())
    assert _without_timing(summary) == _without_timing(json.loads((tmp_path / "fresh" / "summary.json").read_text()))
    assert summary["seed"] == 2 and (out / "notes.txt").read_text() == "mine"  # other files are not ours to delete


def test_overwrite_deletes_the_old_results_before_the_run_starts(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A run that fails after --overwrite leaves no summary of the old run beside its own config."""
    import teamsim.cli as cli

    out = tmp_path / "out"
    assert cli.main(["match", *QUICK, "--seed", "1", "--out", str(out)]) == 0

    def crash(*args: object, **kwargs: object) -> None:
        raise RuntimeError("the simulator failed")

    monkeypatch.setattr(cli, "Match", crash)
    with pytest.raises(RuntimeError):
        cli.main(["match", *QUICK, "--seed", "2", "--out", str(out), "--overwrite"])
    assert not (out / "summary.json").exists()
    assert json.loads((out / "config.json").read_text())["seed"] == 2
    assert (out / "events.jsonl").read_text() == ""


def test_camera_out_refuses_earlier_pictures_and_overwrite_replaces_them(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from teamsim.cli import main

    out = tmp_path / "shots"
    argv = ["camera", "--players-per-team", "1", "--robot", "0:1", "--size", "64x48", "--out", str(out)]
    assert main([*argv, "--time", "0"]) == 0
    (out / "notes.txt").write_text("mine")
    capsys.readouterr()
    assert main([*argv, "--time", "0.5"]) == 2
    line = _one_error_line("camera", capsys)
    assert str(out) in line and "t0000.00_team0_player1.png" in line and "--overwrite" in line
    assert main([*argv, "--time", "0.5", "--overwrite"]) == 0
    names = sorted(p.name for p in out.iterdir())
    assert names == ["notes.txt", "t0000.50_team0_player1.png", "t0000.50_team0_player1_annotated.png"]


def test_camera_notes_times_after_the_end_of_the_match(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from teamsim.cli import main

    (tmp_path / "c.json").write_text('{"referee": {"half_seconds": 1}}')
    argv = [
        "camera",
        "--config",
        str(tmp_path / "c.json"),
        "--players-per-team",
        "1",
        "--robot",
        "0:1",
        "--size",
        "64x48",
    ]
    assert main([*argv, "--time", "100000", "--out", str(tmp_path / "shots")]) == 0
    assert "note: the match ended at" in capsys.readouterr().out


TINY_TRAIN = [
    *["train", "--env", "teamsim/Striker-v0", "--action-type", "discrete", "--env-kwargs", '{"max_cycles": 10}'],
    *["--timesteps", "32", "--n-envs", "1", "--hyperparams", '{"n_steps": 32, "batch_size": 32, "n_epochs": 1}'],
    "--no-progress",
]


def test_train_out_refuses_an_earlier_run_and_overwrite_replaces_only_its_files(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from teamsim.cli import main

    out = tmp_path / "run"
    (out / "checkpoints").mkdir(parents=True)
    (out / "checkpoints" / "ppo_128_steps.zip").write_bytes(b"an old checkpoint")
    (out / "model.zip").write_bytes(b"an old model")
    (out / "notes.txt").write_text("mine")
    assert main([*TINY_TRAIN, "--out", str(out)]) == 2
    line = _one_error_line("train", capsys)
    assert str(out) in line and "checkpoints and model.zip" in line and "--resume" in line and "--overwrite" in line
    (out / "checkpoints" / "ppo_128_steps.zip").unlink()
    assert main([*TINY_TRAIN, "--out", str(out), "--resume"]) == 2  # a finished run without checkpoints
    assert "cannot resume" in _one_error_line("train", capsys)
    (out / "checkpoints" / "ppo_128_steps.zip").write_bytes(b"an old checkpoint")

    assert main([*TINY_TRAIN, "--out", str(out), "--overwrite"]) == 0
    assert not (out / "checkpoints" / "ppo_128_steps.zip").exists() and (out / "notes.txt").read_text() == "mine"
    assert (out / "model.zip").read_bytes() != b"an old model"
    assert json.loads((out / "config.json").read_text())["timesteps"] == 32


def test_evaluate_out_never_mixes_episodes_of_two_models_at_one_path(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from teamsim.cli import main

    out, log = tmp_path / "run", tmp_path / "eval.jsonl"
    evaluate = ["evaluate", "--model", str(out / "model.zip"), "--env", "teamsim/Striker-v0", "--episodes", "1"]
    assert main([*TINY_TRAIN, "--out", str(out), "--seed", "1"]) == 0
    assert main([*evaluate, "--out", str(log)]) == 0
    assert main([*TINY_TRAIN, "--out", str(out), "--seed", "2", "--overwrite"]) == 0  # another model, same path
    capsys.readouterr()
    assert main([*evaluate, "--episodes", "2", "--out", str(log)]) == 2
    line = _one_error_line("evaluate", capsys)
    assert f"{log} line 1 belongs to another evaluation (model_sha256=" in line and "another --out file" in line
    assert len(log.read_text().splitlines()) == 1

    broken = tmp_path / "broken.jsonl"
    broken.write_text("5\n")
    assert main([*evaluate, "--out", str(broken)]) == 2
    assert f"{broken} line 1 is no episode record" in _one_error_line("evaluate", capsys)
