"""Argument types of the ``teamsim`` command line (shared by :mod:`teamsim.cli`,
:mod:`teamsim.cli_gc` and the commands registered from above): each turns an option's text
into a checked value or raises ``argparse.ArgumentTypeError``, which argparse reports as a
one-line usage error naming the option."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable


def integer(low: int, high: int) -> Callable[[str], int]:
    """An argparse type: an integer in ``low..high``."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer in {low}..{high}, got {text!r}") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"must be in {low}..{high}, got {value}")
        return value

    return parse


def number(low: float, inclusive: bool, what: str) -> Callable[[str], float]:
    """An argparse type: a finite number above ``low`` (or equal to it, if ``inclusive``)."""
    bound = f">= {low:g}" if inclusive else f"> {low:g}"

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what} {bound}, got {text!r}") from None
        if not math.isfinite(value) or value < low or (value == low and not inclusive):
            raise argparse.ArgumentTypeError(f"must be {what} {bound}, got {text!r}")
        return value

    return parse
