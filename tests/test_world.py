"""The physical world: walking limits, kicks, ball rolling, collisions, falls and the head."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cognition.field import make_field
from cognition.representations import HeadRequest, KickRequest, WalkRequest
from teamsim.robot import RobotParams
from teamsim.world import PhysicsParams, World


def make_world(players: int = 1, seed: int = 0, params: PhysicsParams | None = None) -> World:
    gens = [np.random.default_rng([seed, i]) for i in range(2 * players + 1)]
    world = World(make_field("spl2025"), players, params or PhysicsParams(), gens[1:], gens[0])
    for r in world.robots:
        r.add_to(world.space)
    for i, r in enumerate(world.robots):
        r.teleport(-3.0 + 2.0 * i, -2.0, 0.0)
    world.place_ball(0.0, 2.5)
    return world


def run(world: World, seconds: float, t0: float = 0.0) -> float:
    steps = round(seconds / world.dt)
    for k in range(steps):
        world.step(t0 + k * world.dt)
    return t0 + steps * world.dt


def test_walk_speed_and_acceleration_limits() -> None:
    world = make_world()
    robot = world.robot(0, 1)
    p = robot.params
    robot.command(WalkRequest(forward=10.0), None, HeadRequest())
    run(world, 0.2)
    assert robot.velocity[0] == pytest.approx(p.max_linear_accel * 0.2, abs=0.011)
    run(world, 2.0, 0.2)
    speed = math.hypot(*robot.body.velocity)
    assert speed == pytest.approx(p.max_forward, rel=0.02)
    robot.command(WalkRequest(forward=0.25, left=0.15, turn=1.0), None, HeadRequest())
    run(world, 2.0, 2.2)
    vx, vy, w = robot.velocity
    norm = math.sqrt((vx / p.max_forward) ** 2 + (vy / p.max_sideways) ** 2 + (w / p.max_turn) ** 2)
    assert norm == pytest.approx(1.0, abs=1e-6)  # combined command scaled onto the limit


def test_ball_rolls_to_a_stop_with_constant_deceleration() -> None:
    world = make_world()
    world.place_ball(0.0, 0.0, 2.0, 0.0)
    run(world, 3.0)
    decel = world.params.ball_rolling_decel
    expected = 2.0**2 / (2 * decel)
    assert world.ball.position.x == pytest.approx(expected, rel=0.03)
    assert abs(world.ball.velocity) < 1e-9


def test_kick_sends_ball_in_the_requested_direction_with_noise() -> None:
    directions, speeds = [], []
    for seed in range(40):
        world = make_world(seed=seed)
        robot = world.robot(0, 1)
        robot.teleport(0.0, 0.0, 0.0)
        world.place_ball(0.22, 0.0)
        robot.command(WalkRequest(), KickRequest(direction=0.3, strength=0.8), HeadRequest())
        events = world.step(0.0)
        assert [e.kind for e in events if e.kind == "robot_kick"] == ["robot_kick"]
        vx, vy = world.ball.velocity
        directions.append(math.atan2(vy, vx))
        speeds.append(math.hypot(vx, vy))
        # the kick blocks walking for its duration
        robot.command(WalkRequest(forward=0.25), None, HeadRequest())
        run(world, 0.5, 0.01)
        assert abs(robot.velocity[0]) < 1e-9
    p = RobotParams()
    assert np.mean(directions) == pytest.approx(0.3, abs=0.05)
    assert np.std(directions) == pytest.approx(p.kick_direction_sigma, rel=0.35)
    assert np.mean(speeds) == pytest.approx(0.8 * p.kick_max_speed, rel=0.06)
    assert np.std(speeds) > 0.0


def test_kick_out_of_reach_misses() -> None:
    world = make_world()
    robot = world.robot(0, 1)
    robot.teleport(0.0, 0.0, 0.0)
    world.place_ball(0.6, 0.0)
    robot.command(WalkRequest(), KickRequest(), HeadRequest())
    events = world.step(0.0)
    assert not [e for e in events if e.kind == "robot_kick"]
    assert abs(world.ball.velocity) == 0.0


def test_robots_collide_and_hard_impacts_topple_them() -> None:
    falls = 0
    for seed in range(30):
        world = make_world(players=1, seed=seed)
        a, b = world.robot(0, 1), world.robot(1, 1)
        a.teleport(-0.15, 0.0, 0.0)
        b.teleport(0.15, 0.0, math.pi)
        a.body.velocity = (1.0, 0.0)  # a hard charge (1 m/s each), as after a stumble
        b.body.velocity = (-1.0, 0.0)
        saw_contact = False
        for k in range(100):
            events = world.step(k * world.dt)
            saw_contact |= any(e.kind == "robot_robot" for e in events)
        assert saw_contact
        # bodies never overlap by more than a little
        gap = math.dist(a.body.position, b.body.position) - 2 * a.params.radius
        assert gap > -0.02
        falls += a.is_fallen() + b.is_fallen()
    assert falls > 10  # 2 m/s closing speed topples robots often


def test_gentle_contact_does_not_topple_and_getting_up_takes_seconds() -> None:
    world = make_world(players=1)
    a, b = world.robot(0, 1), world.robot(1, 1)
    a.teleport(-0.35, 0.0, 0.0)
    b.teleport(0.0, 0.0, math.pi)
    a.command(WalkRequest(forward=0.1), None, HeadRequest())
    run(world, 3.0)
    assert not a.is_fallen() and not b.is_fallen()
    until = b.fall(3.0)
    assert 2.5 <= until - 3.0 <= 8.0
    b.command(WalkRequest(forward=0.2), None, HeadRequest())
    run(world, 1.0, 3.0)
    assert abs(b.body.velocity) < 1e-6 or b.velocity[0] == 0.0
    run(world, until - 4.0 + 1.0, 4.0)
    assert not b.is_fallen() and b.velocity[0] > 0.0


# pymunk clears forces after each sub-step and a physics step has 2 of them, so a force
# applied once per step acts for half the time: factor 4 is an average of 2x floor friction.
@pytest.mark.parametrize(("factor", "slides"), [(1.4, False), (4.0, True)])
def test_pushed_robot_slides_only_beyond_floor_friction(factor: float, slides: bool) -> None:
    world = make_world(players=1)
    robot = world.robot(1, 1)
    robot.teleport(0.0, 0.0, 0.0)
    for k in range(100):
        robot.body.apply_force_at_local_point((factor * robot.params.floor_force, 0.0))
        world.step(k * world.dt)
    moved = robot.body.position.x
    assert (moved > 0.1) == slides
    assert moved < 0.01 or slides


def test_head_respects_joint_and_rate_limits() -> None:
    world = make_world()
    robot = world.robot(0, 1)
    p = robot.params
    robot.command(WalkRequest(), None, HeadRequest(yaw=3.0, pitch=-2.0, speed=2.0))
    world.step(0.0)
    assert robot.head.yaw == pytest.approx(2.0 * world.dt)
    assert robot.head.yaw_rate == pytest.approx(2.0)
    run(world, 3.0, world.dt)
    assert robot.head.yaw == pytest.approx(p.head_yaw_limit)
    assert robot.head.pitch == pytest.approx(p.head_pitch_min)
    assert robot.head.yaw_rate == 0.0


def test_bad_physics_params() -> None:
    with pytest.raises(ValueError, match="substeps"):
        PhysicsParams(substeps=0)
    with pytest.raises(ValueError, match="max_forward"):
        RobotParams(max_forward=-0.1)
    with pytest.raises(ValueError, match="physics_hz"):
        PhysicsParams(physics_hz=math.nan)
    world = make_world()
    with pytest.raises(ValueError, match="finite"):
        world.place_ball(math.nan, 0.0)
    with pytest.raises(ValueError, match="no robot 3"):
        world.robot(0, 3)


def test_the_c_getters_read_what_the_body_properties_read() -> None:
    """The physics loop reads bodies with pymunk's C getters (teamsim.robot.get_position, ...):
    over a walk with pushes and a kick, robots' and the ball's positions, angles and velocities
    are those of the public properties, bit for bit, and each robot's pose after a step is its
    body's (what post_step stores)."""
    from teamsim.robot import get_angle, get_angular_velocity, get_position, get_velocity

    world = make_world(players=3, seed=5)
    world.place_ball(0.3, 0.05, 0.4, -0.2)
    rng = np.random.default_rng(2)
    moving = 0
    for k in range(300):
        if k % 25 == 0:
            for r in world.robots:
                r.command(
                    WalkRequest(rng.uniform(-0.1, 0.3), rng.uniform(-0.1, 0.1), rng.uniform(-0.5, 0.5)),
                    KickRequest() if k == 100 else None, HeadRequest(),
                )  # fmt: skip
        world.step(k * world.dt)
        for body in [r.body for r in world.robots] + [world.ball]:
            p, v = get_position(body._body), get_velocity(body._body)
            assert (p.x, p.y) == tuple(body.position) and (v.x, v.y) == tuple(body.velocity)
            assert get_angle(body._body) == body.angle
            assert get_angular_velocity(body._body) == body.angular_velocity
            moving += v.x != 0.0 or v.y != 0.0
        for r in world.robots:
            assert r.body_pose == (r.body.position.x, r.body.position.y, r.body.angle)
    assert moving > 300  # the readers were compared on moving bodies, not only on resting ones


def test_the_c_setters_set_what_the_body_properties_set() -> None:
    """teamsim.robot.set_velocity and set_angular_velocity (pymunk's C setters, as the physics
    loop calls them) leave a body as the property setters do, bit for bit."""
    import pymunk

    from teamsim.robot import set_angular_velocity, set_velocity

    rng = np.random.default_rng(4)
    for _ in range(200):
        vx, vy, w = (float(v) for v in rng.normal(0.0, 2.0, 3))
        a, b = pymunk.Body(1.0, 1.0), pymunk.Body(1.0, 1.0)
        a.velocity, a.angular_velocity = (vx, vy), w
        set_velocity(b._body, (vx, vy))
        set_angular_velocity(b._body, w)
        assert tuple(b.velocity) == tuple(a.velocity) == (vx, vy) and b.angular_velocity == a.angular_velocity == w


def _colliding_space(seed: int) -> tuple[object, list[object], list[int]]:
    """A space of balls flying into each other and into walls, with a collision counter."""
    import pymunk

    g = np.random.default_rng(seed)
    space = pymunk.Space()
    walls = [pymunk.Segment(space.static_body, a, b, 0.05) for a, b in (((-2, -2), (2, -2)), ((2, -2), (2, 2)))]
    space.add(*walls)
    bodies = []
    for _ in range(12):
        b = pymunk.Body(1.0, 1.0)
        b.position = tuple(g.uniform(-1.5, 1.5, 2))
        b.velocity = tuple(g.normal(0.0, 3.0, 2))
        c = pymunk.Circle(b, 0.15)
        c.elasticity = 0.8
        space.add(b, c)
        bodies.append(b)
    hits = [0]

    def begin(arbiter: object, space: object, data: object) -> None:
        hits[0] += 1

    space.on_collision(begin=begin)
    return space, bodies, hits


def test_step_space_steps_as_pymunk_does() -> None:
    """World's direct Chipmunk step (teamsim.world.step_space) moves bodies and calls collision
    handlers exactly as pymunk's Space.step, also on the first step (new bodies to check)."""
    from teamsim.world import step_space

    a, bodies_a, hits_a = _colliding_space(1)
    b, bodies_b, hits_b = _colliding_space(1)
    for _ in range(400):
        a.step(0.005)
        step_space(b, 0.005)
    assert hits_a[0] == hits_b[0] > 5
    for x, y in zip(bodies_a, bodies_b, strict=True):
        assert tuple(x.position) == tuple(y.position) and tuple(x.velocity) == tuple(y.velocity)


def test_step_space_carries_out_what_a_handler_asks_for_during_the_step() -> None:
    """A collision handler that removes a body and asks for a post-step callback: after
    step_space the body is gone and the callback ran, as after Space.step."""
    import pymunk

    from teamsim.world import step_space

    for stepper in (pymunk.Space.step, step_space):
        space, bodies, _ = _colliding_space(2)
        done: list[int] = []

        def begin(arbiter: pymunk.Arbiter, space: pymunk.Space, data: object, done: list[int] = done) -> None:
            body = arbiter.shapes[0].body
            if body in space.bodies and body.body_type == pymunk.Body.DYNAMIC and not done:
                space.remove(body, *body.shapes)
                space.add_post_step_callback(lambda s, key: done.append(key), 7)

        space.on_collision(begin=begin)
        for _ in range(200):
            stepper(space, 0.005)
        assert done == [7] and len(space.bodies) == len(bodies) - 1, stepper


def test_body_poses_reads_every_body_by_id_as_it_leaves_rejoins_and_the_space_grows() -> None:
    """BodyPoses lists each body of the space once with the pose the body properties give, bit
    for bit: after robots left and rejoined the space (Chipmunk reorders its bodies) and after
    the space came to hold far more bodies than the arrays were made for (they are reallocated
    and the numpy views follow)."""
    import pymunk

    from teamsim.world import BodyPoses

    world = make_world(players=2, seed=3)
    reader = BodyPoses(world.space, 3)

    def check() -> None:
        n = reader.read()
        listed = {int(i): tuple(reader.poses[3 * k : 3 * k + 3].tolist()) for k, i in enumerate(reader.ids[:n])}
        assert len(listed) == n == len(world.space.bodies) + 1  # Chipmunk lists the static body too
        for body in [*world.space.bodies, world.space.static_body]:
            assert listed[body.id] == (body.position.x, body.position.y, body.angle)

    for k in range(20):
        world.step(k * world.dt)
    check()
    first = world.robots[0]
    first.remove_from(world.space)
    check()
    first.add_to(world.space)
    first.teleport(1.0, -0.5, 3.0)
    check()
    rng = np.random.default_rng(1)
    for _ in range(200):  # far past the arrays' first capacity
        body = pymunk.Body(1.0, 1.0)
        body.position = (rng.uniform(-4, 4), rng.uniform(-3, 3))
        body.angle = rng.uniform(-10, 10)
        world.space.add(body)
    check()


def test_a_robots_pose_is_its_body_pose_with_the_angle_wrapped_bit_for_bit() -> None:
    """Robot.pose is body_pose with wrap_angle's angle, as the walking engine stores it after a
    step (teamsim.walking.wrap_angle_nb, compiled) and as teleport stores it; angles beyond pi
    (robots turning on the spot for a while) and placements at +-pi included."""
    from cognition.geometry import wrap_angle
    from teamsim.walking import wrap_angle_nb

    rng = np.random.default_rng(8)
    angles = np.concatenate([rng.uniform(-40.0, 40.0, 20000), [math.pi, -math.pi, 0.0, -0.0, 3 * math.pi, 1e-300]])
    for a in angles.tolist():
        assert math.copysign(1.0, wrap_angle_nb(a)) == math.copysign(1.0, wrap_angle(a))
        assert wrap_angle_nb(a) == wrap_angle(a)
    world = make_world(players=2, seed=6)
    world.robots[1].teleport(0.5, 0.5, math.pi)
    world.robots[2].teleport(-0.5, 0.5, -math.pi)
    turned = 0
    for k in range(600):
        if k % 50 == 0:
            for r in world.robots:
                r.command(WalkRequest(0.1, 0.0, 1.5 if r.number == 1 else -1.5), None, HeadRequest())
        world.step(k * world.dt)
        for r in world.robots:
            x, y, th = r.body_pose
            assert r.pose == (x, y, wrap_angle(th)) == (r.body.position.x, r.body.position.y, wrap_angle(r.body.angle))
            turned += abs(th) > math.pi
    assert turned > 100  # unwrapped body angles beyond pi were part of the comparison


def test_a_resting_untouched_ball_is_not_looked_at_again_within_a_step_and_nothing_changes() -> None:
    """World.step reads the resting ball's velocity before a later sub-step only when a shape
    touched it in the one before. The count of touching shapes follows Chipmunk's own list of
    the ball's contacts after every sub-step, and a world that reads before every sub-step (as
    before the count) moves the same to the bit while robots walk into the resting ball, push it
    and it rolls into the net and the border."""
    from teamsim import world as world_module

    def play(world: World, checks: list[int], check_always: bool) -> list[tuple[float, ...]]:
        choose = world._choose_ball_integrator

        def counted() -> None:
            checks.append(1)
            choose()

        world._choose_ball_integrator = counted  # type: ignore[method-assign]
        rng = np.random.default_rng(5)
        trace: list[tuple[float, ...]] = []
        step_space = world_module.step_space

        def watched(space: object, dt: float) -> None:
            step_space(space, dt)  # type: ignore[arg-type]
            touching: list[object] = []
            world.ball.each_arbiter(lambda arb: touching.append(arb) if arb.contact_point_set.points else None)
            assert world._ball_contacts - offset == len(touching)

        offset = 1000 if check_always else 0  # never 0: as if always touched, read before every sub-step
        world._ball_contacts += offset
        world_module.step_space = watched
        try:
            for k in range(1500):
                if k % 150 == 0:
                    world.place_ball(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0))
                    for i, r in enumerate(world.robots):
                        bx, by = world.ball.position
                        r.teleport(bx - 0.5 + 0.1 * i, by + rng.uniform(-0.2, 0.2), rng.uniform(-0.3, 0.3))
                if k % 150 == 100:
                    world.place_ball(4.4, rng.uniform(-1.5, 1.5), 2.0, rng.uniform(-1.0, 1.0))  # into net or border
                for r in world.robots:
                    r.command(WalkRequest(0.25, 0.0, 0.0), None, HeadRequest())
                world.step(k * world.dt)
                b = world.ball
                trace.append((b.position.x, b.position.y, b.velocity.x, b.velocity.y, *world.robots[0].body_pose))
        finally:
            world_module.step_space = step_space
        return trace

    lean: list[int] = []
    full: list[int] = []
    assert play(make_world(players=2, seed=9), lean, False) == play(make_world(players=2, seed=9), full, True)
    assert len(lean) < 0.8 * len(full)  # reads were saved


def test_team_poses_are_world_to_team_of_every_robots_pose_bit_for_bit() -> None:
    """teamsim.walking.team_poses_nb (the match's oracle inputs and localization errors) gives
    world_to_team(sign, *robot.pose) for both attack directions to the bit, with each robot's
    penalised and fallen flags, while robots turn past +-pi; an output too small is a clear
    error, not a write past its end."""
    from teamsim.placement import world_to_team
    from teamsim.walking import WIDTH, team_poses_nb

    world = make_world(players=3, seed=2)
    world.robots[4].penalized = True
    world.robots[1].fall(0.0, 2.0)
    rows = np.empty((len(world.robots), 5))
    negated = 0
    for k in range(400):
        if k % 40 == 0:
            for r in world.robots:
                r.command(WalkRequest(0.1, 0.05, 1.2 if r.number % 2 else -1.2), None, HeadRequest())
        world.step(k * world.dt)
        for sign in (1.0, -1.0):
            team_poses_nb(world.motion.array, sign, rows)
            for r, row in zip(world.robots, rows.tolist(), strict=True):
                assert tuple(row[:3]) == world_to_team(sign, *r.pose)
                assert (row[3], row[4]) == (float(not r.penalized), float(r.is_fallen()))
                negated += sign < 0 and abs(r.pose[2]) > 3.0
    assert negated > 20  # headings near +-pi, where the half turn wraps, were compared
    with pytest.raises(ValueError, match="a row of 5 for every robot"):
        team_poses_nb(np.zeros((6, WIDTH)), 1.0, np.zeros((5, 5)))
