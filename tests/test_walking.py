"""The compiled walking engines (teamsim.walking) against a plain Python reference, bit for bit.

The reference is the per-robot walking engine as it ran in Python before the kernels (one robot,
one step, tuples and floats); both run on random states that cover every branch: resting and
moving heads, robots off the field, fallen (and getting up in this step), picked up, kicking,
standing still, and control bodies whose last velocity is zero, the same or new.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from cognition.geometry import wrap_angle
from teamsim import fouls
from teamsim import walking as wk


def _ref_head(row: list[float], dt: float) -> None:
    yaw, pitch, yaw_rate, pitch_rate, camera_now = (row[c] for c in (wk.HYAW, wk.HPITCH, wk.HYR, wk.HPR, wk.HCAM))
    ty, tp, speed, camera = row[wk.GYAW], row[wk.GPITCH], row[wk.GSPEED], row[wk.GCAM]
    if ty == yaw and tp == pitch and yaw_rate == 0.0 and pitch_rate == 0.0 and camera_now == camera:
        row[wk.RESTING] = 1.0
        return
    reach = speed * dt
    dy = min(max(ty - yaw, -reach), reach)
    dp = min(max(tp - pitch, -reach), reach)
    if dy == 0.0 and dp == 0.0 and yaw_rate == 0.0 and pitch_rate == 0.0 and camera_now == camera:
        return
    row[wk.HYAW], row[wk.HPITCH], row[wk.HYR], row[wk.HPR] = yaw + dy, pitch + dp, dy / dt, dp / dt
    row[wk.HCAM], row[wk.HEAD_MOVED] = camera, 1.0


def _ref_pre(row: list[float], now: float, dt: float) -> int:
    """One robot's step before the physics; returns the send bits."""
    if row[wk.RESTING] == 0.0:
        _ref_head(row, dt)
    if row[wk.IN_SPACE] == 0.0:
        return 0
    if 0 <= row[wk.FALLEN_UNTIL] <= now:
        row[wk.FALLEN_UNTIL] = row[wk.FALLEN_SINCE] = -1.0
    if row[wk.PICKED] or row[wk.FALLEN_UNTIL] >= 0:
        vx = vy = w = 0.0
    else:
        tx, ty, tw = (0.0, 0.0, 0.0) if now < row[wk.BUSY_UNTIL] else (row[wk.TX], row[wk.TY], row[wk.TW])
        lin, ang = row[wk.LIN_ACC] * dt, row[wk.ANG_ACC] * dt
        vx = row[wk.VX] + min(lin, max(-lin, tx - row[wk.VX]))
        vy = row[wk.VY] + min(lin, max(-lin, ty - row[wk.VY]))
        w = row[wk.VW] + min(ang, max(-ang, tw - row[wk.VW]))
    row[wk.VX], row[wk.VY], row[wk.VW] = vx, vy, w
    last = (row[wk.CX], row[wk.CY], row[wk.CW])
    if (vx, vy, w) == (0.0, 0.0, 0.0) and last == (0.0, 0.0, 0.0):
        row[wk.HAS_ROT] = 0.0
        return 0
    c, s = math.cos(row[wk.BTH]), math.sin(row[wk.BTH])
    row[wk.ROT_C], row[wk.ROT_S], row[wk.HAS_ROT] = c, s, 1.0
    cvx, cvy = c * vx - s * vy, s * vx + c * vy
    bits = 0
    if (cvx, cvy, w) != last:
        if cvx != last[0] or cvy != last[1] or cvx == 0.0 or cvy == 0.0:
            bits |= wk.SEND_VELOCITY
        if w != last[2] or w == 0.0:
            bits |= wk.SEND_ANGULAR
        row[wk.CX], row[wk.CY], row[wk.CW] = cvx, cvy, w
    px, py, pth = row[wk.PX], row[wk.PY], row[wk.PTH]
    pc, ps = math.cos(pth), math.sin(pth)
    dx, dy = vx * dt, vy * dt
    row[wk.PX], row[wk.PY], row[wk.PTH] = px + pc * dx - ps * dy, py + ps * dx + pc * dy, pth + w * dt
    return bits


def _ref_post(row: list[float]) -> None:
    if row[wk.IN_SPACE] == 0.0:
        return
    x0, y0, th0 = row[wk.BX], row[wk.BY], row[wk.BTH]
    x1, y1, th1 = row[wk.NX], row[wk.NY], row[wk.NTH]
    row[wk.BX], row[wk.BY], row[wk.BTH] = x1, y1, th1
    if (x1, y1, th1) == (x0, y0, th0):
        return
    row[wk.WTH] = wrap_angle(th1)
    c, s = (row[wk.ROT_C], row[wk.ROT_S]) if row[wk.HAS_ROT] else (math.cos(th0), math.sin(th0))
    lx, ly = c * (x1 - x0) + s * (y1 - y0), -s * (x1 - x0) + c * (y1 - y0)
    ax, ay, ath = row[wk.MX], row[wk.MY], row[wk.MTH]
    ac, as_ = math.cos(ath), math.sin(ath)
    row[wk.MX], row[wk.MY], row[wk.MTH] = ax + ac * lx - as_ * ly, ay + as_ * lx + ac * ly, ath + (th1 - th0)


def _random_states(g: np.random.Generator, n: int, now: float) -> np.ndarray:
    s = np.zeros((n, wk.WIDTH))
    s[:, : wk.NTH + 1] = g.normal(0.0, 0.5, (n, wk.NTH + 1))
    s[:, wk.HYAW : wk.HPR + 1] = g.normal(0.0, 0.5, (n, 4))
    s[:, wk.GYAW : wk.GPITCH + 1] = g.normal(0.0, 0.5, (n, 2))
    s[:, wk.GSPEED] = g.uniform(0.5, 8.0, n)
    s[:, wk.HCAM], s[:, wk.GCAM] = g.integers(0, 2, n), g.integers(0, 2, n)
    s[:, wk.IN_SPACE] = g.random(n) < 0.9
    s[:, wk.PICKED] = g.random(n) < 0.1
    s[:, wk.RESTING] = g.random(n) < 0.2
    s[:, wk.FALLEN_UNTIL] = np.where(g.random(n) < 0.2, now + g.uniform(-0.02, 1.0, n), -1.0)
    s[:, wk.FALLEN_SINCE] = np.where(s[:, wk.FALLEN_UNTIL] >= 0, now - 1.0, -1.0)
    s[:, wk.BUSY_UNTIL] = np.where(g.random(n) < 0.2, now + 0.3, 0.0)
    s[:, wk.HAS_ROT] = g.random(n) < 0.5
    s[:, wk.LIN_ACC], s[:, wk.ANG_ACC] = 0.5, 3.0
    # some heads already at their target, some robots standing with a still control body, some
    # control bodies already at the speed the step will ask for, some bodies that did not move
    at = g.random(n) < 0.3
    s[at, wk.HYAW], s[at, wk.HPITCH], s[at, wk.HYR], s[at, wk.HPR] = s[at, wk.GYAW], s[at, wk.GPITCH], 0.0, 0.0
    s[at, wk.HCAM] = s[at, wk.GCAM]
    still = g.random(n) < 0.3
    s[still, wk.VX] = s[still, wk.VY] = s[still, wk.VW] = 0.0
    s[still, wk.TX] = s[still, wk.TY] = s[still, wk.TW] = 0.0
    s[still, wk.CX] = s[still, wk.CY] = s[still, wk.CW] = 0.0
    turning = ~still & (g.random(n) < 0.3)  # on the spot: the world velocity is exactly zero (sent again)
    s[turning, wk.VX] = s[turning, wk.VY] = s[turning, wk.TX] = s[turning, wk.TY] = 0.0
    s[turning, wk.CX] = s[turning, wk.CY] = 0.0
    unmoved = g.random(n) < 0.2
    s[unmoved, wk.NX], s[unmoved, wk.NY], s[unmoved, wk.NTH] = s[unmoved, wk.BX], s[unmoved, wk.BY], s[unmoved, wk.BTH]
    return s


@pytest.mark.parametrize("seed", range(6))
def test_kernels_equal_the_python_reference_bit_for_bit(seed: int) -> None:
    g = np.random.default_rng(seed)
    now, dt = 12.34, 0.01
    n = 64
    s = _random_states(g, n, now)
    ref = [list(map(float, row)) for row in s]
    sends = np.zeros((n, 2), dtype=np.int64)
    body_ids = (1000 + g.permutation(n)).astype(np.uint64)
    for step in range(3):  # three steps: the second and third start from what the first left
        t = now + step * dt
        n_send = wk.pre_step_nb(s, t, dt, sends)
        bits = [_ref_pre(row, t, dt) for row in ref]
        assert [tuple(r) for r in sends[:n_send].tolist()] == [(i, b) for i, b in enumerate(bits) if b]
        # what pymunk lists: the bodies in the space, in its order, with bodies no robot owns
        moved = g.normal(0.0, 0.01, (n, 3)) * (g.random((n, 1)) < 0.8)
        moved[:, 2] += g.choice([0.0, 7.0, -7.0], n)  # angles past pi, to be wrapped
        new = s[:, wk.BX : wk.BTH + 1] + moved
        listed = [r for r in range(n) if s[r, wk.IN_SPACE] != 0.0]
        ids = np.concatenate([body_ids[listed], [11, 12, 13]]).astype(np.uint64)
        poses = np.concatenate([new[listed], g.normal(0.0, 3.0, (3, 3))])
        order = g.permutation(len(ids))
        flat = np.concatenate([poses[order].reshape(-1), np.full(6, np.nan)])  # room past the count
        wk.post_step_nb(s, flat, np.concatenate([ids[order], [0, 0]]).astype(np.uint64), len(ids), body_ids)
        for r in listed:
            ref[r][wk.NX], ref[r][wk.NY], ref[r][wk.NTH] = new[r].tolist()
        for row in ref:
            _ref_post(row)
        assert s.tobytes() == np.array(ref).tobytes(), f"step {step}: rows differ"
    # the branches were all taken
    assert sends[:n_send, 1].max() == wk.SEND_VELOCITY | wk.SEND_ANGULAR


def test_take_motions_copies_and_restarts() -> None:
    g = np.random.default_rng(3)
    s = g.normal(size=(4, wk.WIDTH))
    before = s.copy()
    out = np.empty((4, 6))
    wk.take_motions_nb(s, out)
    assert np.array_equal(out, before[:, wk.PX : wk.MTH + 1])
    assert not s[:, wk.PX : wk.MTH + 1].any()
    rest = np.ones(wk.WIDTH, dtype=bool)
    rest[wk.PX : wk.MTH + 1] = False
    assert np.array_equal(s[:, rest], before[:, rest])


def test_scene_rows_read_the_state() -> None:
    s = np.zeros((3, wk.WIDTH))
    s[:, wk.BX : wk.BTH + 1] = [[1.0, 2.0, 0.5], [-1.0, 0.5, 3.0], [0.0, 0.0, 0.0]]
    s[:, wk.IN_SPACE] = [1.0, 1.0, 0.0]
    s[0, wk.VY] = 0.1
    s[0, wk.HCAM] = 1.0
    s[:, wk.FALLEN_UNTIL] = [-1.0, 5.0, -1.0]
    obs, occ = np.zeros((3, 12)), np.zeros((3, 5))
    wk.scene_rows_nb(s, np.array([0.0, 1.0, 1.0]), 1.0, -1.0, 0.14, 0.58, 0.2, obs, occ)
    assert obs[:, 0:3].tolist() == s[:, wk.BX : wk.BTH + 1].tolist()
    assert obs[:, 7].tolist() == [1.0, 0.0, 0.0]  # camera
    assert obs[:, 8].tolist() == [1.0, 0.0, 0.0]  # walking
    assert obs[:, 9].tolist() == [1.0, 0.0, 0.0]  # sees: on the field, standing, not picked up
    assert obs[:, 10].tolist() == [1.0, -1.0, -1.0] and obs[:, 11].tolist() == [0.0, 1.0, 1.0]
    assert occ[:, 3].tolist() == [0.58, 0.2, 0.58] and occ[:, 4].tolist() == [1.0, 1.0, 0.0]


def _ref_field_fouls(s: np.ndarray, entered: list[float], lx: float, ly: float, margin: float, gx: float, gy: float,
                     now: float, inactive: float) -> list[tuple[int, int]]:  # fmt: skip
    """The foul detector's former Python loop over the robots (teamsim.fouls)."""
    out = []
    for r, row in enumerate(s.tolist()):
        if not row[wk.IN_SPACE] or row[wk.PENALIZED]:
            continue
        ax, ay = abs(row[wk.BX]), abs(row[wk.BY])
        if ax <= lx and ay <= ly:
            entered[r] = 1.0
        elif entered[r] and not (ax <= lx + margin and ay <= ly + margin) and not (ay < gy and ax < gx):
            out.append((r, fouls.LEFT_FIELD))
            continue
        if row[wk.FALLEN_UNTIL] >= 0 and now - row[wk.FALLEN_SINCE] >= inactive:
            out.append((r, fouls.INACTIVE))
    return out


@pytest.mark.parametrize("seed", range(4))
def test_field_fouls_kernel_equals_the_python_reference(seed: int) -> None:
    g = np.random.default_rng(seed)
    n, now = 200, 50.0
    s = np.zeros((n, wk.WIDTH))
    s[:, wk.BX], s[:, wk.BY] = g.uniform(-5.8, 5.8, n), g.uniform(-3.8, 3.8, n)  # in, near and beyond the lines
    s[:, wk.IN_SPACE] = g.random(n) < 0.9
    s[:, wk.PENALIZED] = g.random(n) < 0.1
    fallen = g.random(n) < 0.3
    s[:, wk.FALLEN_UNTIL] = np.where(fallen, now + 1.0, -1.0)
    s[:, wk.FALLEN_SINCE] = np.where(fallen, now - g.uniform(0.0, 40.0, n), -1.0)
    entered = (g.random(n) < 0.7).astype(float)
    ref_entered = entered.tolist()
    out = np.zeros((n, 2), dtype=np.int64)
    args = (4.55, 3.05, 0.14, 5.1, 0.8, now, 20.0)
    k = fouls.field_fouls_nb(s, entered, *args[:5], args[5], args[6], out)
    ref = _ref_field_fouls(s, ref_entered, *args)
    assert [tuple(r) for r in out[:k].tolist()] == ref
    assert entered.tolist() == ref_entered
    assert {code for _, code in ref} == {fouls.LEFT_FIELD, fouls.INACTIVE}  # both fouls occur


def test_post_step_refuses_a_body_count_its_arrays_do_not_hold() -> None:
    """post_step_nb reads n bodies' poses and ids: a count beyond the arrays, or fewer body ids than
    robots, is a ValueError before anything is read or written (not a read past the end)."""
    s = np.zeros((2, wk.WIDTH))
    before = s.copy()
    ids, body_ids = np.array([7, 8], dtype=np.uint64), np.array([7, 8], dtype=np.uint64)
    for poses, n, bids in ((np.zeros(3), 2, body_ids), (np.zeros(6), 3, body_ids), (np.zeros(6), 2, body_ids[:1])):
        with pytest.raises(ValueError, match="n bodies need"):
            wk.post_step_nb(s, poses, ids, n, bids)
    assert np.array_equal(s, before)
    wk.post_step_nb(s, np.arange(6.0), ids, 2, body_ids)  # in range: taken
    assert s[1, wk.NX] == 3.0 and s[1, wk.NTH] == 5.0
