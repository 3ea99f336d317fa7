"""The PettingZoo and Gymnasium environments: the libraries' own checks, actions, rewards, observations."""

from __future__ import annotations

import functools
import math

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from pettingzoo.test import (
    api_test,
    max_cycles_test,
    parallel_api_test,
    parallel_seed_test,
    render_test,
    state_test,
)

import envs  # noqa: F401  (registers the Gymnasium ids)
from cognition.behaviors.actions import MACROS, ActionError
from envs import soccer_v0
from teamsim.placement import world_to_team

MODES = [(obs, act) for obs in ("truth", "percepts") for act in ("continuous", "discrete")]
SMALL = {"players_per_team": 2, "start": "playing", "half_seconds": 60.0}


@pytest.mark.parametrize(("observation", "action_type"), MODES)
def test_pettingzoo_parallel_and_aec_api(observation: str, action_type: str) -> None:
    kw = {**SMALL, "observation": observation, "action_type": action_type, "control": "both"}
    parallel_api_test(soccer_v0.parallel_env(**kw), num_cycles=25)
    api_test(soccer_v0.env(**kw), num_cycles=15)


@pytest.mark.parametrize(("observation", "action_type"), MODES)
def test_pettingzoo_seed_determinism(observation: str, action_type: str) -> None:
    kw = {**SMALL, "observation": observation, "action_type": action_type}
    parallel_seed_test(functools.partial(soccer_v0.parallel_env, **kw), num_cycles=20)


def test_pettingzoo_max_cycles_and_render(tmp_path) -> None:
    max_cycles_test(soccer_v0)
    render_test(functools.partial(soccer_v0.env, **SMALL, render_path=str(tmp_path / "human.mp4")))
    assert (tmp_path / "human.mp4").stat().st_size > 0  # human mode wrote frames without a display


@pytest.mark.parametrize("task", ["teamsim/Striker-v0", "teamsim/Keeper-v0"])
@pytest.mark.parametrize(("observation", "action_type"), MODES)
def test_gymnasium_check_env(task: str, observation: str, action_type: str) -> None:
    env = gymnasium.make(task, observation=observation, action_type=action_type, max_cycles=20)
    check_env(env.unwrapped, skip_render_check=True)
    obs, _ = env.reset(seed=3)
    assert env.observation_space.contains(obs)


def _two_envs(**kw):
    a = soccer_v0.parallel_env(**{**SMALL, "observation": "truth", **kw})
    b = soccer_v0.parallel_env(**{**SMALL, "observation": "truth", **kw})
    return a, b


@pytest.mark.parametrize(
    "bad",
    [
        np.array([np.nan, 0, 0, 0, 0, 0, 0]),
        np.array([0.0, np.inf, 0, 0, 0, 0, 0]),
        np.zeros(6),
        np.zeros((7, 1)),
        "forward",
    ],
)
def test_bad_continuous_actions_are_rejected_without_changing_the_env(bad: object) -> None:
    env, twin = _two_envs()
    env.reset(seed=5)
    twin.reset(seed=5)
    good = {a: np.full(7, 0.3, dtype=np.float32) for a in env.agents}
    before = env.core.match.snapshot()
    with pytest.raises(ActionError, match=r"home_2") as raised:
        env.step({**good, "home_2": bad})
    assert "home_1" not in str(raised.value)  # only the sender is named
    after = env.core.match.snapshot()
    assert after.time == before.time and env.core.cycles == 0
    # nothing was applied: the env continues exactly like a twin that never saw the bad action
    for _ in range(5):
        o1, r1, *_ = env.step(good)
        o2, r2, *_ = twin.step(good)
        assert all(np.array_equal(o1[a], o2[a]) for a in o1) and r1 == r2


def test_parallel_step_names_every_agent_with_a_bad_action() -> None:
    env = soccer_v0.parallel_env(**SMALL, observation="truth", control="both")
    env.reset(seed=5)
    actions = {a: np.zeros(7) for a in env.agents}
    with pytest.raises(ActionError) as raised:
        env.step({**actions, "home_1": np.full(7, np.nan), "away_2": np.zeros(3)})
    message = str(raised.value)
    assert "home_1" in message and "finite" in message
    assert "away_2" in message and "shape" in message
    assert "home_2" not in message and "away_1" not in message
    assert env.core.cycles == 0


def _aec_pair(**kw):
    kw = {**SMALL, "observation": "truth", "control": "both", **kw}
    env, twin = soccer_v0.env(**kw), soccer_v0.env(**kw)
    env.reset(seed=7)
    twin.reset(seed=7)
    return env, twin


@pytest.mark.parametrize("bad_agent", ["home_1", "away_2"])  # the first agent to act, and the last
def test_aec_bad_action_is_refused_at_the_senders_step_and_the_env_stays_usable(bad_agent: str) -> None:
    env, twin = _aec_pair()
    order = list(env.agents)
    assert order[0] == "home_1" and order[-1] == "away_2"
    good = np.full(7, 0.2, dtype=np.float32)
    for agent in order:
        assert env.agent_selection == agent
        if agent == bad_agent:
            with pytest.raises(ActionError, match=rf"{bad_agent}.*finite"):
                env.step(np.array([0.0, np.nan, 0, 0, 0, 0, 0]))
            assert env.agent_selection == agent  # still this agent's turn, nothing stored
            assert env.unwrapped.core.cycles == 0
        env.step(good)
    assert env.unwrapped.core.cycles == 1  # the cycle completed with the valid action
    for _ in order:
        twin.step(good)
    assert twin.unwrapped.core.cycles == 1
    for agent in order:
        assert np.array_equal(env.observe(agent), twin.observe(agent))
    # and it keeps going like the twin that never saw the bad action
    for _ in range(2 * len(order)):
        env.step(good)
        twin.step(good)
    assert env.unwrapped.core.cycles == twin.unwrapped.core.cycles == 3
    assert all(np.array_equal(env.observe(a), twin.observe(a)) for a in order)


def test_aec_bad_discrete_action_names_the_agent() -> None:
    env, _ = _aec_pair(action_type="discrete")
    env.step(1)  # home_1
    assert env.agent_selection == "home_2"
    with pytest.raises(ActionError, match=r"home_2.*out of range"):
        env.step(len(MACROS))
    env.step(2)
    assert env.agent_selection == "away_1"


def test_aec_action_for_a_finished_agent_must_be_none() -> None:
    env = soccer_v0.env(**SMALL, observation="truth", max_cycles=1)
    env.reset(seed=0)
    for _ in env.possible_agents:
        env.step(np.zeros(7))
    agent = env.agent_selection
    assert env.truncations[agent]
    with pytest.raises(ValueError, match=rf"{agent} is done.*None"):
        env.step(np.zeros(7))
    env.step(None)  # the agent is removed as PettingZoo expects
    assert agent not in env.agents


@pytest.mark.parametrize("observation", ["truth", "percepts"])
def test_pettingzoo_state_test_and_state_space(observation: str) -> None:
    kw = {**SMALL, "observation": observation, "control": "both"}
    state_test(soccer_v0.env(**kw), soccer_v0.parallel_env(**kw), num_cycles=5)
    env = soccer_v0.parallel_env(**kw)
    with pytest.raises(RuntimeError, match="before reset"):
        env.state()
    env.reset(seed=1)
    state = env.state()
    assert env.state_space.shape == state.shape == (4 * env.observation_space("home_1").shape[0],)
    assert env.state_space.dtype == state.dtype and env.state_space.contains(state)


def test_out_of_range_continuous_actions_are_clipped() -> None:
    env, twin = _two_envs()
    env.reset(seed=2)
    twin.reset(seed=2)
    big = np.array([5.0, -3.0, 9.0, -2.0, 4.0, 7.0, -8.0])
    clipped = np.clip(big, -1.0, 1.0)
    for _ in range(4):
        o1, *_ = env.step(dict.fromkeys(env.agents, big))
        o2, *_ = twin.step(dict.fromkeys(twin.agents, clipped))
        assert all(np.array_equal(o1[a], o2[a]) for a in o1)


@pytest.mark.parametrize("bad", [7, -1, 2.5, 2.0, True, "1", np.nan, [1, 2], np.array([1])])
def test_bad_discrete_actions_are_rejected(bad: object) -> None:
    env = soccer_v0.parallel_env(**SMALL, observation="truth", action_type="discrete")
    env.reset(seed=1)
    with pytest.raises(ActionError):
        env.step({"home_1": 0, "home_2": bad})
    env.step({"home_1": np.int64(1), "home_2": np.array(2)})  # numpy ints and 0-d int arrays, as Discrete takes
    assert env.core.cycles == 1


def test_step_rejects_unknown_or_missing_agents_and_bad_arguments() -> None:
    env = soccer_v0.parallel_env(**SMALL, observation="truth")
    env.reset(seed=1)
    zero = np.zeros(7)
    with pytest.raises(ValueError, match="unknown agents"):
        env.step({"home_1": zero, "home_2": zero, "away_9": zero})
    with pytest.raises(ValueError, match="no action for live agents"):
        env.step({"home_1": zero})
    with pytest.raises(ValueError, match="unknown reward term 'goals'"):
        soccer_v0.parallel_env(reward_weights={"goals": 1.0})
    with pytest.raises(ValueError, match="whole multiple"):
        soccer_v0.parallel_env(decision_hz=7.0)
    with pytest.raises(TypeError, match="colour"):
        soccer_v0.parallel_env(colour="red")


def test_truth_observation_matches_the_world() -> None:
    env = soccer_v0.parallel_env(players_per_team=3, observation="truth", start="playing")
    obs, _ = env.reset(seed=4)
    for _ in range(10):
        obs, *_ = env.step({a: env.action_space(a).sample() for a in env.agents})
    m = env.core.match
    f = m.field
    for k, robot in enumerate(m.world.robots[:3]):
        o = obs[f"home_{k + 1}"]
        x, y, th = world_to_team(m.referee.sign(0), *robot.pose)
        assert o[0] == pytest.approx(x / f.half_length, abs=1e-5)
        assert o[1] == pytest.approx(y / f.half_width, abs=1e-5)
        assert math.atan2(o[3], o[2]) == pytest.approx(th, abs=1e-4)
        bx, by, _ = world_to_team(m.referee.sign(0), m.world.ball.position.x, m.world.ball.position.y, 0.0)
        c, s = math.cos(th), math.sin(th)
        rel = (c * (bx - x) + s * (by - y), -s * (bx - x) + c * (by - y))
        assert o[7] * f.dims.length == pytest.approx(rel[0], abs=1e-4)
        assert o[8] * f.dims.length == pytest.approx(rel[1], abs=1e-4)
        assert o[11] == 1.0 and o[30] == 1.0  # ball valid, game PLAYING


def test_percepts_observation_comes_from_beliefs_not_truth() -> None:
    env = soccer_v0.parallel_env(players_per_team=2, observation="percepts", start="playing", action_type="discrete")
    env.reset(seed=2)
    for _ in range(40):
        obs, *_ = env.step(dict.fromkeys(env.agents, 6))  # scan: stand and look for landmarks
    m = env.core.match
    f = m.field
    errors, exact = [], 0
    for k in range(2):
        o = obs[f"home_{k + 1}"]
        x, y, _ = world_to_team(m.referee.sign(0), *m.world.robots[k].pose)
        err = math.hypot(o[0] * f.half_length - x, o[1] * f.half_width - y)
        errors.append(err)
        exact += err < 1e-6
        assert o[4] > 0.0  # the estimate carries its uncertainty
    assert max(errors) < 0.6 and exact == 0


def test_goal_and_ball_progress_rewards() -> None:
    env = soccer_v0.parallel_env(**SMALL, observation="truth", reward_weights={"goal": 1.0, "ball_progress": 0.5})
    env.reset(seed=0)
    m = env.core.match
    sign = m.referee.sign(0)
    m.world.place_ball(sign * 2.0, 0.0, sign * 1.0, 0.0)  # rolling toward the away goal
    _, rewards, *_ = env.step(dict.fromkeys(env.agents, np.zeros(7)))
    assert rewards["home_1"] > 0.0 and rewards["home_1"] == rewards["home_2"]
    m.world.place_ball(sign * 4.3, 0.0, sign * 2.0, 0.0)  # into the goal
    total = {a: 0.0 for a in env.agents}
    scored = False
    for _ in range(10):
        _, rewards, _, _, infos = env.step(dict.fromkeys(env.agents, np.zeros(7)))
        for a in rewards:
            total[a] += rewards[a]
        scored = scored or infos["home_1"]["reward_terms"]["goal"] == 1.0
    assert scored and m.referee.score[0] == 1
    assert total["home_1"] > 0.9  # the goal counts, the ball's return to the centre does not


def test_both_teams_controlled_get_opposite_goal_rewards() -> None:
    env = soccer_v0.parallel_env(**SMALL, observation="truth", control="both", reward_weights={"ball_progress": 1.0})
    env.reset(seed=0)
    m = env.core.match
    m.world.place_ball(0.0, 0.0, 1.0, 0.0)
    _, rewards, *_ = env.step(dict.fromkeys(env.agents, np.zeros(7)))
    assert rewards["home_1"] == pytest.approx(-rewards["away_1"]) and rewards["home_1"] != 0.0


def test_truncation_after_max_cycles_and_termination_at_the_end_of_the_match() -> None:
    env = soccer_v0.parallel_env(**SMALL, observation="truth", max_cycles=7)
    env.reset(seed=0)
    for i in range(7):
        _, _, terms, truncs, _ = env.step(dict.fromkeys(env.agents, np.zeros(7)))
        assert not any(terms.values()) and all(truncs.values()) == (i == 6)
    assert env.agents == []
    env = soccer_v0.parallel_env(players_per_team=1, observation="truth", start="playing", half_seconds=1.0)
    env.reset(seed=0)
    steps = 0
    while env.agents:
        _, _, terms, _, _ = env.step(dict.fromkeys(env.agents, np.zeros(7)))
        steps += 1
    assert all(terms.values()) and env.core.match.finished and steps < 600  # two 1-s halves, half time, READY and SET


def test_drills_end_with_an_outcome() -> None:
    env = gymnasium.make("teamsim/Keeper-v0", action_type="discrete", max_cycles=300)
    outcomes = []
    for seed in range(3):
        env.reset(seed=seed)
        done = False
        while not done:
            _, _, term, trunc, info = env.step(0)  # the keeper stands still
            done = term or trunc
        outcomes.append(info["outcome"])
    assert set(outcomes) <= {"scored", "conceded", "out", "cleared", "penalised", "time"}
    assert "conceded" in outcomes  # a scripted striker beats a keeper that does nothing


def test_striker_that_never_kicks_is_penalised_for_a_stuck_game() -> None:
    # go_to_ball lines up behind the ball and never kicks: after 20 s the referee removes the
    # robot nearest the still ball (LOCAL_GAME_STUCK) and the episode ends "penalised"
    env = gymnasium.make("teamsim/Striker-v0", action_type="discrete", max_cycles=400)
    env.reset(seed=1)
    steps, done = 0, False
    while not done:
        _, _, term, trunc, info = env.step(MACROS.index("go_to_ball"))
        steps += 1
        done = term or trunc
    assert info["outcome"] == "penalised" and term and not trunc
    assert 195 <= steps <= 215  # 20 s at 10 decisions per second


def test_images_observation_runs_vision_on_rendered_pixels() -> None:
    """``observation="images"``: every cognition frame brings a camera image, the agents' own
    vision turns it into percepts, and localization on them keeps the robot near the truth."""
    env = soccer_v0.parallel_env(players_per_team=2, observation="images", start="playing", opponents="random")
    obs, _ = env.reset(seed=3)
    for _ in range(20):
        obs, *_ = env.step({a: env.action_space(a).sample() for a in env.agents})
        assert all(env.observation_space(a).contains(o) for a, o in obs.items())
    m = env.core.match
    assert m.image_count > 0 and m.percept_count == 0
    brain = env.core.policies["home_1"]
    vision = brain.provider.vision
    assert vision is not None and vision.debug is not None
    assert m.localization_errors.summary().position_error_mean < 0.5


def test_the_cognition_frame_of_an_env_is_chosen_by_name() -> None:
    """``cognition`` names the other modules of every robot's frame; the env's own keys stay its own."""
    from envs.core import EnvConfig

    env = soccer_v0.parallel_env(players_per_team=2, cognition={"goal": "none", "hypotheses": "none"})
    env.reset(seed=1)
    for _ in range(3):
        env.step({a: env.action_space(a).sample() for a in env.agents})
    stages = {b.provider.stages for b in env.core.match.brains}  # type: ignore[attr-defined]
    assert all("goal model" not in s and "ball hypotheses" not in s and "localization" in s for s in stages)
    assert all(b.beliefs is None or b.beliefs.goal is None for b in env.core.policies.values())
    with pytest.raises(ValueError, match=r"set 'localization' with the environment's localization"):
        EnvConfig(cognition={"localization": "amcl"})
    with pytest.raises(ValueError, match=r"EnvConfig.cognition.goal must be one of \['posts', 'none'\], got 'x'"):
        EnvConfig(cognition={"goal": "x"})
    with pytest.raises(ValueError, match=r"unknown EnvConfig.cognition.goal_params key\(s\) \['y'\]"):
        EnvConfig(cognition={"goal_params": {"y": 1}})
