"""Shared pieces of the fuzz tests: seeded batches under hypothesis, packet mutations, and the
GameController v18 oracle written from RoboCupGameControlData.h (used by ``test_fuzz_decoders``
and ``test_gc_bridge``)."""

from __future__ import annotations

import math
import struct
from collections.abc import Callable

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cognition.gamestate import PACKET_SIZE, GameControlData, GameStateId, RobotInfo, TeamInfo

PER_DECODER = 10_000
"""Inputs each decoder must decode in this file (asserted)."""
EXAMPLES = 25
"""Hypothesis examples per decoder: one seed each."""
BATCH = 420
"""Inputs decoded per example (``EXAMPLES * BATCH`` >= :data:`PER_DECODER`)."""
FUZZ = settings(
    max_examples=EXAMPLES,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=list(HealthCheck),
)
SEED = st.integers(0, 2**64 - 1)
CARPET = (4.5 + 0.7 + 1.0, 3.0 + 0.7 + 1.0)  # field + border strip + the 1 m margin (m)


def run_seeded(fuzz: Callable[[np.random.Generator], None]) -> None:
    """Run ``fuzz`` on a generator seeded by each of the :data:`EXAMPLES` hypothesis seeds."""

    @FUZZ
    @given(seed=SEED)
    def run(seed: int) -> None:
        fuzz(np.random.default_rng(seed))

    run()


# -- mutations ------------------------------------------------------------------------------

_EXTREME_BYTES = (0, 1, 2, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 19, 20, 21, 99, 127, 128, 254, 255)
_EXTREME_INT16 = (-32768, -1, 0, 1, 32767)
_EXTREME_FLOATS = (
    math.nan, math.inf, -math.inf, 0.0, -0.0, 1e-45, -1e-45, 3.4e38, -3.4e38, -1.0, -1e-30,
    100.0, 100.001, -100.001, 50.0, 50.01, 4.0, 4.001, math.pi, 1e9, 1.1e9, 99.0, 99.99, 100.01,
    CARPET[0], CARPET[0] + 0.01, -CARPET[0] - 0.01, CARPET[1], CARPET[1] + 0.01, -CARPET[1] - 0.01,
)  # fmt: skip
_F32 = struct.Struct("<f")
_I16 = struct.Struct("<h")
_OPS = ("flip", "flip", "flip", "byte", "byte", "byte", "float", "float", "float", "int16", "int16", "cut", "extend")
_N_OPS = (1, 1, 1, 1, 2, 2, 3, 4)
"""How many mutations a packet gets: mostly one, so that a fair share stays valid."""


def mutate(rng: np.random.Generator, raw: bytes, float_offsets: tuple[int, ...] = ()) -> bytes:
    """``raw`` after 1 to 4 random mutations (``float`` ops write at ``float_offsets``; without
    them they flip a bit instead)."""
    out = bytearray(raw)
    for _ in range(_N_OPS[int(rng.integers(len(_N_OPS)))]):
        kind = _OPS[int(rng.integers(len(_OPS)))]
        if not out and kind != "extend":
            continue
        i = int(rng.integers(len(out))) if out else 0
        extreme = rng.random() < 0.5
        if kind == "flip" or (kind == "float" and not float_offsets):
            out[i] ^= 1 << int(rng.integers(8))
        elif kind == "byte":
            out[i] = _EXTREME_BYTES[int(rng.integers(len(_EXTREME_BYTES)))] if extreme else int(rng.integers(256))
        elif kind == "float":
            o = float_offsets[int(rng.integers(len(float_offsets)))]
            if o + 4 <= len(out):
                if extreme:
                    _F32.pack_into(out, o, _EXTREME_FLOATS[int(rng.integers(len(_EXTREME_FLOATS)))])
                else:
                    out[o : o + 4] = rng.bytes(4)  # any float32: subnormals, NaN payloads, ...
        elif kind == "int16" and i + 2 <= len(out):
            v = _EXTREME_INT16[int(rng.integers(len(_EXTREME_INT16)))] if extreme else int(rng.integers(-32768, 32768))
            _I16.pack_into(out, i, v)
        elif kind == "cut":
            del out[i:]
        elif kind == "extend":
            out += rng.bytes(int(rng.integers(1, 17)))
    return bytes(out)


# -- GameController packets -----------------------------------------------------------------

_PLAYERS = tuple(RobotInfo(p, 45 if p else 0) for p in (0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 14, 15, 0, 0, 0, 0, 0, 0))
GC_BASES = [
    GameControlData(kicking_team=255).pack(),
    GameControlData(
        packet_number=200, players_per_team=7, competition_phase=1, competition_type=1, game_phase=1, state=3,
        set_play=5, first_half=0, kicking_team=12, secs_remaining=-5, secondary_time=32767,
        teams=(TeamInfo(team_number=12, field_player_colour=9, goalkeeper_colour=3, goalkeeper=0, score=255,
                        penalty_shot=7, single_shots=0xFFFF, message_budget=0, players=_PLAYERS),
               TeamInfo(team_number=255, field_player_colour=0, goalkeeper=20)),
    ).pack(),
    GameControlData(state=GameStateId.PLAYING, kicking_team=2, secs_remaining=412, teams=(
        TeamInfo(team_number=1), TeamInfo(team_number=2, players=tuple(reversed(_PLAYERS))))).pack(),
]  # fmt: skip
_GC_HEAD = struct.Struct("<4sBBBBBBBBBBhh")
_GC_TEAM = struct.Struct("<BBBBBBHH")


def gc_problems(raw: bytes) -> list[str]:
    """What RoboCupGameControlData.h v18 says is wrong with ``raw`` (empty: a valid packet)."""
    if len(raw) != PACKET_SIZE:
        return ["size"]
    (header, version, _packet, per_team, comp_phase, comp_type, game_phase, state, set_play, first_half, kicking,
     _secs, _secondary) = _GC_HEAD.unpack_from(raw, 0)  # fmt: skip
    problems = []
    if header != b"RGme" or version != 18:
        return ["header"]
    for name, value, ok in [
        ("players_per_team", per_team, range(1, 21)), ("competition_phase", comp_phase, (0, 1)),
        ("competition_type", comp_type, (0, 1)), ("game_phase", game_phase, (0, 1, 2, 3)),
        ("state", state, range(6)), ("set_play", set_play, range(6)), ("first_half", first_half, (0, 1)),
    ]:  # fmt: skip
        if value not in ok:
            problems.append(name)
    numbers = []
    for t in range(2):
        base = 18 + t * 50
        number, colour, keeper_colour, keeper, *_ = _GC_TEAM.unpack_from(raw, base)
        numbers.append(number)
        if colour > 9 or keeper_colour > 9:
            problems.append("colour")
        if keeper > 20:
            problems.append("goalkeeper")
        for p in range(20):
            if raw[base + 10 + 2 * p] not in (0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 14, 15):
                problems.append("penalty")
    if numbers[0] == numbers[1]:
        problems.append("team numbers")
    if kicking not in (*numbers, 255):
        problems.append("kicking_team")
    return problems
