"""The GameController options of ``teamsim match`` (:mod:`teamsim.gc_bridge`): ``--gc-broadcast``
or ``--gc-listen`` with ``--gc-host``, ``--gc-port``, ``--gc-return-port``,
``--gc-team-port-base`` and ``--gc-timeout``."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from teamsim.cli_types import integer as _integer
from teamsim.cli_types import number as _number
from teamsim.gc_bridge import BridgeParams


def add_gc_arguments(p: Any) -> None:
    """The GameController options of ``match`` (:mod:`teamsim.gc_bridge`)."""
    g = p.add_argument_group("GameController (SPL wire protocols over UDP, paced to real time)")
    mode = g.add_mutually_exclusive_group()
    mode.add_argument(
        "--gc-broadcast",
        action="store_true",
        help="send the game state (port 3838, 2 Hz), each robot's status (3939, 1 Hz) and the team messages "
        "(10000 + team number) to --gc-host",
    )
    mode.add_argument(
        "--gc-listen",
        action="store_true",
        help="let an external GameController referee the match: follow its packets on --gc-host:--gc-port, "
        "send the robots' status and team messages back to it",
    )
    g.add_argument("--gc-host", default=None, help="IPv4 address to send to / listen on (default 127.0.0.1)")
    g.add_argument("--gc-port", type=_integer(0, 65535), default=None, help="control port (default 3838)")
    g.add_argument("--gc-return-port", type=_integer(1, 65535), default=None, help="status port (default 3939)")
    g.add_argument(
        "--gc-team-port-base", type=_integer(1, 65280), default=None, help="team messages go to this + team number"
    )
    g.add_argument(
        "--gc-timeout",
        type=_number(0.0, False, "a number of seconds"),
        default=None,
        help="seconds without GameController packets before a warning (default 2)",
    )


_GC_OPTIONS = {
    "gc_host": "host",
    "gc_port": "gc_port",
    "gc_return_port": "return_port",
    "gc_team_port_base": "team_port_base",
    "gc_timeout": "timeout",
}
"""``match`` option (argparse name) -> :class:`~teamsim.gc_bridge.BridgeParams` field."""


def bridge_params(args: argparse.Namespace) -> BridgeParams | None:
    """The bridge the GameController options ask for; ``None`` without ``--gc-broadcast`` / ``--gc-listen``."""
    given = {option: getattr(args, option) for option in _GC_OPTIONS if getattr(args, option) is not None}
    if not (args.gc_broadcast or args.gc_listen):
        if given:
            options = ", ".join("--" + option.replace("_", "-") for option in given)
            raise ValueError(f"{options}: only with --gc-broadcast or --gc-listen")
        return None
    fields = {_GC_OPTIONS[option]: value for option, value in given.items()}
    return BridgeParams(mode="listen" if args.gc_listen else "broadcast", **fields)


def warn(line: str) -> None:
    """A warning of ``match`` on stderr (the GameController fell silent)."""
    print(f"teamsim match: warning: {line}", file=sys.stderr, flush=True)
