"""The GameController bridge under load: decoding costs, and a match that keeps real time
while a flood of packets hits its control port.

Decoding is timed on one core (median of repeats) for a valid v18 packet, a packet of the wrong
length, a packet with one field out of range (decoded up to the range check) and a valid status
packet. The flood figures run the default 5 v 5 match (full cognition, ``maturing``) in
``listen`` mode on the loopback interface for ``--seconds`` of real time while a separate
process sends packets at a fixed rate: valid GameController packets with a new packet number
each (each one must be decoded: the worst case), or garbage. A match that keeps real time
simulates ``--seconds`` in ``--seconds`` of wall time; what the bridge does not read in time is
dropped by the kernel (``read_share``).

=================================  ===========================================================
figure                             meaning
=================================  ===========================================================
decode_valid_us                    :func:`teamsim.gc_bridge.decode_game_control`, valid packet
decode_size_us                     the same, a packet of the wrong length
decode_field_us                    the same, a packet with ``state`` = 9
decode_status_us                   :func:`teamsim.gc_bridge.decode_return`, valid packet
flood_<kind>_<rate>_sim_per_wall   simulated / wall seconds during the flood (1.0: real time)
flood_<kind>_<rate>_read_share     packets read (received + rejected) / packets sent
=================================  ===========================================================

Usage: ``python -m benchmarks.bench_gc [--seconds 5] [--rates 0 2000 10000] [--json out.json]``
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
import timeit
from pathlib import Path

from benchmarks.common import write_figures
from cognition.gamestate import GameControlData
from cognition.pipeline import CognitionConfig
from cognition.returndata import ReturnData
from teamsim.gc_bridge import BridgeParams, BridgeStats, GameControllerBridge, decode_game_control, decode_return
from teamsim.match import Match, MatchConfig

_SENDER = r"""
import socket, sys, time
from cognition.gamestate import GameControlData
port, rate, seconds, kind = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
packets = [GameControlData(packet_number=k, state=1).pack() for k in range(256)]
garbage = b"x" * 118
sent, start = 0, time.monotonic()
while (now := time.monotonic()) - start < seconds:
    due = int((now - start) * rate)
    while sent < due:
        sock.sendto(packets[sent % 256] if kind == "valid" else garbage, ("127.0.0.1", port))
        sent += 1
    time.sleep(0.001)
print(sent)
"""


def decode_costs() -> dict[str, float]:
    """Microseconds per decode, median of 7 repeats."""
    valid = GameControlData(state=3, kicking_team=1).pack()
    bad_field = valid[:10] + bytes([9]) + valid[11:]
    status = ReturnData(3, 1, False, 100.0, 200.0, 0.5, 1.0, 300.0, -40.0).pack()
    stats = BridgeStats()
    cases = {
        "decode_valid_us": lambda: decode_game_control(valid, stats),
        "decode_size_us": lambda: decode_game_control(valid[:-1], stats),
        "decode_field_us": lambda: decode_game_control(bad_field, stats),
        "decode_status_us": lambda: decode_return(status, stats),
    }
    out = {}
    for name, call in cases.items():
        n = 2000
        out[name] = statistics.median(timeit.repeat(call, number=n, repeat=7)) / n * 1e6
    return out


def flood(kind: str, rate: float, seconds: float) -> dict[str, float]:
    """Run the default match in listen mode for ``seconds`` while ``rate`` packets/s arrive."""
    match = Match(MatchConfig(cognition=CognitionConfig()), external_referee=True)
    match.run(until=0.5)  # compile and warm up before the clock starts
    with GameControllerBridge(match, BridgeParams("listen", gc_port=0, timeout=3600.0)) as bridge:
        sender = subprocess.Popen(
            [sys.executable, "-c", _SENDER, str(bridge.port), str(rate), str(seconds), kind],
            stdout=subprocess.PIPE,
            text=True,
        )
        t0, start = match.time, time.monotonic()
        summary = bridge.run(until=match.time + seconds)
        wall = time.monotonic() - start
        out, _ = sender.communicate(timeout=60)
    sent = int(out.strip() or 0)
    net = summary.network or {}
    read = net.get("received", 0) + net.get("rejected", 0)
    return {
        f"flood_{kind}_{int(rate)}_sim_per_wall": (match.time - t0) / wall,
        f"flood_{kind}_{int(rate)}_read_share": read / sent if sent else 1.0,
    }


def main(argv: list[str] | None = None) -> int:
    """Print the figures (and write them with ``--json``)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=5.0, help="real seconds per flood run")
    ap.add_argument("--rates", type=float, nargs="+", default=[0.0, 2000.0, 10000.0], help="packets per second")
    ap.add_argument("--json", type=Path, default=None, help="write the figures here")
    args = ap.parse_args(argv)
    figures = decode_costs()
    for name, value in figures.items():
        print(f"{name:36s} {value:10.2f}")
    for kind in ("valid", "garbage"):
        for rate in args.rates:
            if rate == 0.0 and kind == "garbage":
                continue
            for name, value in flood(kind, rate, args.seconds).items():
                figures[name] = value
                print(f"{name:36s} {value:10.3f}")
    write_figures(args.json, figures)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
