"""Ball candidates: seeds from scanned columns, refinement and verification (steps 1-3 of the ball detector).

The compiled search of :func:`~cognition.vision.ball.detect_ball`, the ball detector after
NimbRo section 6.1 (its module docstring describes the method and holds the parameter table):

- **seeds**: every few columns are read row by row for runs of ball pixels, and each run
  seeds centres at its middle or one radius from its ends (:func:`_candidates`,
  :func:`_run_end_seeds`, :func:`_dip`, :func:`_coarse_row`);
- **refinement**: a seed is moved toward the centre by a horizontal and a vertical chord,
  lines are rejected, and the outline is fitted with :mod:`.ball_fit` (:func:`_try_seed`,
  :func:`_refine`);
- **verification**: size, fill, black patches (modern) and the carpet around the ball give
  the candidate's score (:func:`_verify`, :func:`_plausible`, :func:`_content`).

:class:`_State` holds one image's work (the centres tried, the candidates found, best first).
Also the layout of the parameter vector the compiled code reads (built by
``ball._vector``) and of the candidate rows. Pixels ``u`` right, ``v`` down, radii in pixels;
ground points in metres in the robot frame (+x forward, +y left).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numpy.typing import NDArray

from cognition.vision.ball_fit import (
    _N_RAYS,
    BLACK,
    GREEN,
    ORANGE,
    WHITE,
    YELLOW,
    _chord,
    _expected,
    _fit,
    _in_string,
    _is_ball,
    _radius,
    _run_end,
    _stretch,
    _thin,
)

_STEP, _ROWS, _MIN_RUN, _MIN_R, _MAX_D, _TOL, _RESID, _FILL = 0, 1, 2, 3, 4, 5, 6, 7
_MIN_BLACK, _MAX_BLACK, _MIN_WHITE, _RING_GREEN, _RING_OTHER, _RING_ORANGE, _MAX_TESTS, _MAX_CAND = range(8, 16)
_DARK = 16


def _disc_pattern() -> NDArray[np.float64]:
    """Sample offsets inside a unit disc: the centre and rings at 0.3, 0.55 and 0.8."""
    pts = [(0.0, 0.0)]
    for ring, (rad, n) in enumerate(((0.3, 6), (0.55, 10), (0.8, 14))):
        for k in range(n):
            a = 2.0 * math.pi * (k + 0.5 * (ring + 1)) / n
            pts.append((rad * math.cos(a), rad * math.sin(a)))
    return np.array(pts)


_DISC = _disc_pattern()
_RING = np.array([(math.cos(a), math.sin(a)) for a in 2.0 * math.pi * (np.arange(24) + 0.5) / 24.0])
"""Unit directions of the ring samples outside the ball (v grows downward: sin > 0 is below)."""

# candidate columns: u, v, radius reported, x, y, score, expected radius
_CU, _CV, _CR, _CX, _CY, _CS, _CE = 0, 1, 2, 3, 4, 5, 6
_N_CAND = 7


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _refine(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    u: float,
    v: float,
    r: float,
    ball_r: float,
    modern: bool,
    pts: NDArray[np.float64],
    used: NDArray[np.bool_],
    keep: NDArray[np.bool_],
    prm: NDArray[np.float64],
) -> tuple[bool, float, float, float, float, float]:  # pragma: no cover - compiled
    """From a seed centre: (plausible, centre u, v, expected radius there, fitted radius (NaN:
    fixed), rms residual)."""
    reach = int(2.6 * r) + 2
    a, b, ra, rb = _chord(rgb, classes, u, v, True, reach, modern)
    if ra and rb and b - a < r:
        return False, u, v, r, math.nan, math.inf  # a chord through the centre is a diameter: too thin
    # an edge farther than a diameter from the seed (inside the ball) is not the ball's
    near_a, near_b = ra and u - a <= 2.2 * r, rb and b - u <= 2.2 * r
    if ra and rb and b - a <= 3.2 * r:
        u = 0.5 * (a + b)
    elif near_a and not rb:
        u = a + r
    elif near_b and not ra:
        u = b - r
    a, b, ra, rb = _chord(rgb, classes, u, v, False, reach, modern)
    if ra and rb and b - a < r:
        return False, u, v, r, math.nan, math.inf
    if ra and rb and b - a <= 3.2 * r:
        v = 0.5 * (a + b)
    elif rb and b - v <= 2.2 * r:  # the lower edge meets the carpet: the ball sits on it
        v = b - r
    elif ra and v - a <= 2.2 * r:
        v = a + r
    if _thin(classes, u, v, r, modern) or not _plausible(rgb, classes, u, v, r, modern, prm):
        return False, u, v, r, math.nan, math.inf
    rad, rms = math.nan, math.inf
    for _ in range(2):
        e = _radius(cam, u, v, ball_r)
        if not math.isfinite(e):
            return False, u, v, r, math.nan, math.inf
        r = e
        ok, u, v, rad, rms = _fit(rgb, classes, u, v, r, modern, pts, used, keep)
        if not ok:
            return False, u, v, r, math.nan, math.inf
    e = _radius(cam, u, v, ball_r)
    if not math.isfinite(e):
        return False, u, v, r, math.nan, math.inf
    return True, u, v, e, rad, rms


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _candidates(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    ball_r: float,
    modern: bool,
    prm: NDArray[np.float64],
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Verified ball candidates (K x 7: u, v, radius px, x, y, score, expected radius), best first.

    The scanned columns are read row by row (the class image is row-major), each keeping the
    start of its current run of ball pixels. Where a ball is big enough (R at least 1.5 x three
    column steps, from the row where that holds at every column down) only every third column
    is read.
    """
    h, w = classes.shape
    step = int(prm[_STEP])
    rs = int(prm[_ROWS])
    max_tests = int(prm[_MAX_TESTS])
    st = _State(max_tests)
    n_cols = (w - step // 2 + step - 1) // step
    i0 = step // 2
    tops = np.empty(n_cols, dtype=np.int64)
    starts = np.full(n_cols, -1, dtype=np.int64)
    darks = np.full(n_cols, -1, dtype=np.int64)  # last BLACK row of the current run (modern)
    first = h
    for c in range(n_cols):
        i = i0 + c * step
        b0 = min(int(boundary[i]), h - 1)  # no carpet in the column: a ball may hide it at the bottom
        rb = _radius(cam, i + 0.5, float(b0), ball_r)
        pad = int(2.2 * rb) + 1 if math.isfinite(rb) else 0
        tops[c] = max(0, b0 - pad)
        first = min(first, tops[c])
    split = _coarse_row(cam, w, h, ball_r, 4.5 * step)
    lut = np.zeros(256, dtype=np.bool_)  # ball pixel by class
    for c in range(256):
        lut[c] = _is_ball(c, modern)
    half = 0.5 * (rs - 1)  # a run's ends lie up to rs - 1 rows before the samples that show them
    j = first
    while j <= h and st.more():
        fine = 1 if j < split else 3  # big balls below the split: every third column
        if j >= split and j - rs < split:
            for c in range(n_cols):  # the other columns stop
                if c % 3 != 0:
                    starts[c] = -1
        for c in range(0, n_cols, fine):
            i = i0 + c * step
            cl = classes[j, i] if j < h else GREEN  # below the image: every run ends
            if not lut[cl]:
                if starts[c] < 0:
                    continue  # the common case: carpet, no run open
                if not modern and cl != GREEN and j + rs < h and classes[j + rs, i] == ORANGE:
                    continue  # classic: a net's string or noise across the ball
            elif j < tops[c]:
                continue
            else:
                if starts[c] < 0:
                    starts[c] = j
                if cl == BLACK:
                    darks[c] = j
                continue
            # a run [start, j) of ball pixels ends in column i
            start = starts[c]
            starts[c] = -1
            if j - start < 2 * rs:
                continue  # a single sample: balls this small are beyond the range
            lo = start - half
            bounded = start - rs >= tops[c]
            top = False  # the run goes on to the image's top
            if not bounded and not modern:  # it began where the column's scan begins: look above for its start
                q, stop = start - 1, start - 2.2 * _radius(cam, i + 0.5, float(j), ball_r)
                while q >= 0 and q >= stop and lut[classes[q, i]]:
                    q -= 1
                if q >= 0 and q >= stop:
                    lo, bounded = q + 1.0, True
                top = q < 0
            _run_end_seeds(
                rgb, classes, boundary, cam, ball_r, modern, prm, st, i, lo, j - half, bounded, j < h,
                darks[c], top,
            )  # fmt: skip
        if j == h:
            break
        j = min(j + rs, h)
    return st.best(int(prm[_MAX_CAND]))


@nb.experimental.jitclass(
    [
        ("tested", nb.float64[:, :]),
        ("n_tested", nb.int64),
        ("n_tests", nb.int64),
        ("n_seeds", nb.int64),
        ("max_tests", nb.int64),
        ("cand", nb.float64[:, :]),
        ("n_cand", nb.int64),
        ("pts", nb.float64[:, :]),
        ("used", nb.bool_[:]),
        ("keep", nb.bool_[:]),
    ]
)
class _State:  # pragma: no cover - compiled
    """Work of one image: the seeds and fitted centres tried (u, v, R, 1 if fitted), the counts,
    the candidates found and the silhouette buffers."""

    def __init__(self, max_tests: int) -> None:
        self.max_tests = max_tests
        self.tested = np.empty((5 * max_tests, 4))
        self.n_tested = 0
        self.n_tests = 0
        self.n_seeds = 0
        self.cand = np.empty((max_tests, _N_CAND))
        self.n_cand = 0
        self.pts = np.empty((_N_RAYS, 2))
        self.used = np.empty(_N_RAYS, dtype=np.bool_)
        self.keep = np.empty(_N_RAYS, dtype=np.bool_)

    def more(self) -> bool:
        return self.n_seeds < 4 * self.max_tests and self.n_tests < self.max_tests

    def near(self, u: float, v: float, r: float, fitted: bool) -> bool:
        """A seed (``fitted`` False) near an earlier seed, or a fitted centre near an earlier one."""
        for t in range(self.n_tested):
            if (self.tested[t, 3] > 0.5) != fitted:
                continue
            q = r if fitted else self.tested[t, 2]
            if abs(self.tested[t, 0] - u) < 0.6 * q and abs(self.tested[t, 1] - v) < 0.6 * q:
                return True
        return False

    def add(self, u: float, v: float, r: float, fitted: bool) -> None:
        if self.n_tested < self.tested.shape[0]:
            k = self.n_tested
            self.tested[k, 0], self.tested[k, 1], self.tested[k, 2] = u, v, r
            self.tested[k, 3] = 1.0 if fitted else 0.0
            self.n_tested += 1

    def best(self, n_max: int) -> NDArray[np.float64]:
        """The candidates by score, best first, without those overlapping a better one."""
        order = np.argsort(-self.cand[: self.n_cand, _CS])
        out = np.empty((min(self.n_cand, n_max), _N_CAND))
        n = 0
        for k in order:
            if n >= out.shape[0]:
                break
            ok = True
            for m in range(n):
                d = math.hypot(out[m, _CU] - self.cand[k, _CU], out[m, _CV] - self.cand[k, _CV])
                if d < out[m, _CE] + self.cand[k, _CE]:
                    ok = False
                    break
            if ok:
                out[n] = self.cand[k]
                n += 1
        return out[:n]


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _coarse_row(cam: NDArray[np.float64], w: int, h: int, ball_r: float, r_min: float) -> int:  # pragma: no cover
    """The first row from which a ball's radius is at least ``r_min`` px in every column (at the
    image's left, middle and right; R grows downward), or ``h``."""
    lo, hi = 0, h
    if not _big(cam, w, float(h - 1), ball_r, r_min):
        return h
    while hi - lo > 1:
        m = (lo + hi) // 2
        if _big(cam, w, float(m), ball_r, r_min):
            hi = m
        else:
            lo = m
    return hi


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _big(cam: NDArray[np.float64], w: int, v: float, ball_r: float, r_min: float) -> bool:  # pragma: no cover
    for u in (0.0, 0.5 * w, float(w)):
        r = _radius(cam, u, v, ball_r)
        if not (r >= r_min):
            return False
    return True


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _run_end_seeds(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    boundary: NDArray[np.int32],
    cam: NDArray[np.float64],
    ball_r: float,
    modern: bool,
    prm: NDArray[np.float64],
    st: _State,
    i: int,
    lo: float,
    hi: float,
    bounded: bool,
    closed: bool,
    dark: int,
    top: bool,
) -> None:  # pragma: no cover - compiled
    """Seeds from a run of ball pixels [lo, hi) (rows) in column ``i`` and the candidates they
    lead to. ``bounded``: the run began below a non-ball pixel; ``closed``: it ended above one
    (not at the image's bottom); ``dark``: its last BLACK row; ``top``: it goes on to the image's
    top row.

    A run up to about a diameter long seeds its middle. A longer one, or one open at the top,
    seeds a centre one radius above its lower end and (if bounded) one below its upper end; the
    end of a run open at the top (the hall above a straight field boundary) seeds only where
    the boundary dips, classic where the image's top cuts the run (no hall above it) or, modern,
    where black lies near its lower end (a ball's patches in front of a robot or the hall);
    modern, a run open at both ends seeds one radius above the image's bottom when black lies
    there.
    """
    u = i + 0.5
    mid = 0.5 * (lo + hi)
    r = _radius(cam, u, mid, ball_r)
    if bounded and hi - lo <= 2.6 * r:
        if r >= prm[_MIN_R] and hi - lo >= prm[_MIN_RUN] * r:
            _try_seed(rgb, classes, cam, ball_r, modern, prm, st, u, mid)
        return
    # a ball resting on the lower end of the run (R there, not in the run's middle: an open run
    # may reach above the horizon)
    rr = _radius(cam, u, hi - _radius(cam, u, hi, ball_r), ball_r)
    if closed and rr >= prm[_MIN_R] and hi - lo >= prm[_MIN_RUN] * rr:
        if (
            bounded or (top and not modern) or _dip(boundary, i, int(hi + 0.5), rr)
            or (modern and (dark >= hi - 2.2 * rr or _black_near(classes, i, hi - rr, rr)))
        ):  # fmt: skip
            _try_seed(rgb, classes, cam, ball_r, modern, prm, st, u, hi - rr)
    elif not closed and not bounded and modern and rr >= prm[_MIN_R] and _black_near(classes, i, hi - rr, rr):
        _try_seed(rgb, classes, cam, ball_r, modern, prm, st, u, hi - rr)  # cut by the image's bottom
    if bounded:
        rr = _radius(cam, u, lo + _radius(cam, u, lo, ball_r), ball_r)
        if rr >= prm[_MIN_R] and hi - lo >= prm[_MIN_RUN] * rr:
            _try_seed(rgb, classes, cam, ball_r, modern, prm, st, u, lo + rr)


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _black_disc(classes: NDArray[np.uint8], u: float, v: float, r: float) -> bool:  # pragma: no cover - compiled
    """Modern: a BLACK pixel among the disc samples of radius r around (u, v) (a seed inside the
    ball, not necessarily at its centre, sees a patch; the class is darker than the patches'
    test in :func:`_content` asks for, relative to the carpet)."""
    h, w = classes.shape
    for k in range(_DISC.shape[0]):
        i = math.floor(u + r * _DISC[k, 0])
        j = math.floor(v + r * _DISC[k, 1])
        if 0 <= i < w and 0 <= j < h and classes[j, i] == BLACK:
            return True
    return False


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _black_near(classes: NDArray[np.uint8], i: int, v: float, r: float) -> bool:  # pragma: no cover - compiled
    """Modern: BLACK pixels (a ball's patches) on three rows across a disc of radius r centred
    at column ``i``, row ``v`` (every quarter radius)."""
    h, w = classes.shape
    d = max(1, int(0.25 * r))
    for dv in (-0.4, 0.0, 0.4):
        j = math.floor(v + dv * r)
        if not 0 <= j < h:
            continue
        for q in range(max(0, i - int(0.7 * r)), min(w, i + int(0.7 * r) + 1), d):
            if classes[j, q] == BLACK:
                return True
    return False


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _dip(boundary: NDArray[np.int32], i: int, j: int, r: float) -> bool:  # pragma: no cover - compiled
    """The field boundary at column ``i`` (at row ``j``) lies at least r / 2 below the boundary
    2.5 r to both sides (or the image edge): something small stands in front of the hall there."""
    w = boundary.shape[0]
    k = int(2.5 * r) + 1
    lo = boundary[i - k] if i - k >= 0 else -1
    hi = boundary[i + k] if i + k < w else -1
    return max(lo, hi) < j - 0.5 * r


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _try_seed(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    cam: NDArray[np.float64],
    ball_r: float,
    modern: bool,
    prm: NDArray[np.float64],
    st: _State,
    su: float,
    sv: float,
) -> None:  # pragma: no cover - compiled
    """Refine, fit and verify the seed centre (su, sv) unless it (or its fitted centre) was
    tried before; a verified ball becomes a candidate."""
    if not st.more() or st.near(su, sv, 0.0, False):
        return
    r0 = _radius(cam, su, sv, ball_r)
    if not math.isfinite(r0):
        return
    st.n_seeds += 1
    st.add(su, sv, r0, False)
    if modern and not _black_disc(classes, su, sv, r0):
        return  # no black patch near: a robot, a post, a line or the hall (cheaper than the chords)
    ok, cu, cv, re, rad, rms = _refine(rgb, classes, cam, su, sv, r0, ball_r, modern, st.pts, st.used, st.keep, prm)
    if not ok or st.near(cu, cv, re, True):
        return
    st.n_tests += 1
    st.add(cu, cv, re, True)
    score = _verify(rgb, classes, cu, cv, re, rad, rms, modern, prm)
    if score <= 0.0:
        return
    re, x, y = _expected(cam, cu, cv, ball_r)
    if not math.isfinite(re) or math.hypot(x, y) > prm[_MAX_D] or st.n_cand >= st.cand.shape[0]:
        return
    k = st.n_cand
    st.cand[k, _CU], st.cand[k, _CV] = cu, cv
    # reported as the on-axis radius (what the pinhole relation of the percepts expects)
    st.cand[k, _CR] = (rad if math.isfinite(rad) else re) / _stretch(cam, cu, cv)
    st.cand[k, _CX], st.cand[k, _CY], st.cand[k, _CS], st.cand[k, _CE] = x, y, score, re
    st.n_cand += 1


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _content(
    rgb: NDArray[np.uint8], classes: NDArray[np.uint8], u: float, v: float, r: float, modern: bool, dark_value: float
) -> tuple[int, float, float, float, int, float, float, float, float]:  # pragma: no cover - compiled
    """What lies inside and around a ball of radius r centred at (u, v): (samples inside, share
    of ball pixels (classic: ORANGE or blended YELLOW, NaN if less than half ORANGE), share of
    black (darker than ``dark_value`` x the carpet on the ring), share of WHITE or grey, ring
    samples below the ball, their GREEN share, their share neither GREEN nor WHITE, ORANGE share
    of the whole ring, 1 if those other samples all lie at one end of the ring below (an
    obstacle beside the ball) else 0). Where the ring below is cut by the image edge the samples
    beside the ball count too, or else the whole ring (and the last value is NaN). Classic: a
    net's strings across the ball count as ball."""
    h, w = classes.shape
    rr = 1.3 * r + 1.5
    n_all = n_all_green = n_orange = 0
    n = np.zeros((3, 3), dtype=np.int64)  # below, beside and below, all: samples, GREEN, other
    lead = trail = 0  # other samples below before the first / after the last GREEN or WHITE one
    carpet = 0.0
    for k in range(_RING.shape[0]):  # counter-clockwise from the right; v grows downward: sin > 0 is below
        i = math.floor(u + rr * _RING[k, 0])
        j = math.floor(v + rr * _RING[k, 1])
        if not (0 <= i < w and 0 <= j < h):
            continue
        c = classes[j, i]
        n_all += 1
        n_orange += c == ORANGE
        if c == GREEN:
            n_all_green += 1
            carpet += max(rgb[j, i, 0], rgb[j, i, 1], rgb[j, i, 2])
        other = c != GREEN and c != WHITE
        for t in range(3):
            if _RING[k, 1] > (0.25, -0.5, -2.0)[t]:
                n[t, 0] += 1
                n[t, 1] += c == GREEN
                n[t, 2] += other
        if _RING[k, 1] > 0.25:
            if not other:
                trail = 0
            elif n[0, 0] - n[0, 2] == 0:
                lead += 1
            else:
                trail += 1
    t = 0
    while t < 2 and n[t, 0] < 6:  # the image's edge cuts the ring below: look beside the ball too
        t += 1
    n_low, n_green, n_other = n[t, 0], n[t, 1], n[t, 2]
    # obstacles beside the ball cover the ring below from its ends: the carpet (or a line) shows
    # on at least four samples between them
    side = math.nan
    if t == 0:
        side = 1.0 if n_other == lead + trail and n_low - n_other >= 4 else 0.0
    dark = dark_value * carpet / max(n_all_green, 1)
    n_in = n_ball = n_blend = n_black = n_white = 0
    for k in range(_DISC.shape[0]):
        i = math.floor(u + r * _DISC[k, 0])
        j = math.floor(v + r * _DISC[k, 1])
        if not (0 <= i < w and 0 <= j < h):
            continue
        c = classes[j, i]
        n_in += 1
        if _is_ball(c, modern):
            n_ball += 1
        elif not modern and (c == YELLOW or _in_string(classes, i, j)):
            n_blend += 1  # orange blurred or blended with the carpet looks yellow; a net's string
        if max(rgb[j, i, 0], rgb[j, i, 1], rgb[j, i, 2]) < dark:
            n_black += 1
        elif c == WHITE or c == 0:
            n_white += 1
    m = max(n_in, 1)
    fill = (n_ball + n_blend) / m if n_ball >= 0.5 * n_in else math.nan
    ml = max(n_low, 1)
    return (
        n_in, fill, n_black / m, n_white / m, n_low, n_green / ml, n_other / ml, n_orange / max(n_all, 1), side
    )  # fmt: skip


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _capped(
    rgb: NDArray[np.uint8], classes: NDArray[np.uint8], u: float, v: float, r: float
) -> bool:  # pragma: no cover - compiled
    """Classic: the ball pixels above the centre (u, v) end within 1.5 r + 2 px, or at the image's
    top: a ball, not the foot of a goal post or an orange board going on upward."""
    reach = int(1.5 * r) + 2
    end, real = _run_end(rgb, classes, math.floor(u), math.floor(v), 0, -1, reach, False)
    return real or end <= 0.0


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _plausible(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    u: float,
    v: float,
    r: float,
    modern: bool,
    prm: NDArray[np.float64],
) -> bool:  # pragma: no cover - compiled
    """A loose form of :func:`_verify`'s colour tests for a rough centre (before the fit)."""
    n_in, fill, black, _, _, _, _, _, _ = _content(rgb, classes, u, v, r, modern, prm[_DARK])
    if n_in < 8 or not fill >= prm[_FILL] - 0.25:
        return False
    return not modern or black >= 0.5 * prm[_MIN_BLACK]


@nb.njit(cache=True, error_model="numpy", fastmath=False)
def _verify(
    rgb: NDArray[np.uint8],
    classes: NDArray[np.uint8],
    u: float,
    v: float,
    r: float,
    rad: float,
    rms: float,
    modern: bool,
    prm: NDArray[np.float64],
) -> float:  # pragma: no cover - compiled
    """Score in (0, 1] of a ball centred at (u, v) with expected radius r, fitted radius ``rad``
    (NaN: fixed to r) and fit residual ``rms`` (px); 0: no ball."""
    if r < prm[_MIN_R]:
        return 0.0
    tol = prm[_TOL]
    fit = 1.0
    if math.isfinite(rad):
        err = abs(rad / r - 1.0)
        if err > tol:
            return 0.0
        fit = 1.0 - 0.5 * err / tol
    if rms > prm[_RESID] * r + 0.5:
        return 0.0
    n_in, fill, black, white, n_low, green, other, orange, side = _content(rgb, classes, u, v, r, modern, prm[_DARK])
    if n_in < 9 or n_low < 6 or not fill >= prm[_FILL]:
        return 0.0
    if math.isnan(side):  # the image's edge cuts the ring below the ball
        if modern and (green < prm[_RING_GREEN] or other > 0.6):
            return 0.0
    elif green < prm[_RING_GREEN] or (other > prm[_RING_OTHER] and not (side > 0.5 and other <= 0.6)):
        return 0.0
    if modern and (black < prm[_MIN_BLACK] or black > prm[_MAX_BLACK] or white < prm[_MIN_WHITE]):
        return 0.0
    if not modern and (orange > prm[_RING_ORANGE] or not _capped(rgb, classes, u, v, r)):
        return 0.0
    return fill * (0.5 + 0.5 * green) * fit
