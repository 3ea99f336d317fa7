"""Animated GIF written frame by frame, in memory bounded by one frame.

Pillow's multi-frame GIF save needs every frame at once, which for a 20-minute match video
means gigabytes. :class:`GifStream` instead encodes each frame on its own and appends it to an
open file straight away (GIF89a, https://www.w3.org/Graphics/GIF/spec-gif89a.txt):

=======================================  ==================================================
written                                  when
=======================================  ==================================================
header ``GIF89a`` + logical screen       first frame (its size is the canvas size; no global
descriptor + ``NETSCAPE2.0`` loop block  colour table; loop forever)
graphic control extension + image block  per frame whose pixels differ from the previous
                                         frame: delay (cs), disposal "do not dispose"; the
                                         image block covers only the changed rectangle and
                                         carries its own local colour table
trailer ``;``                            :meth:`GifStream.finish`
=======================================  ==================================================

Each image block is cut out of a single-frame GIF that Pillow encodes in memory (adaptive
palette of at most 256 colours, LZW data), so the pixels are Pillow's; only the container is
written here. A frame identical to the one before is not written again: the previous frame's
delay grows instead. One frame is held back until its delay is known, so the memory held is
the previous frame's pixels plus one encoded frame, whatever the length of the video.

Timing: frame ``i`` (0-based) starts at ``round(i * 100 / fps)`` centiseconds (GIF delays are
whole centiseconds), so the video's clock stays within 5 ms of ``i / fps`` instead of drifting
by the rounding of one delay per frame. A delay is at least 1 cs (above 100 fps the video runs
slower than real time) and a delay beyond the format's 65,535 cs is split over repeats of the
same image block.
"""

from __future__ import annotations

import io
import math
import struct
from typing import BinaryIO

import numpy as np
from numpy.typing import NDArray
from PIL import Image


class VideoError(OSError):
    """A video file could not be created, written or finished (the message names the file)."""


_MAX_SIDE = 0xFFFF  # GIF sizes, offsets and delays are unsigned 16-bit
_EXTENSION = 0x21
_IMAGE = 0x2C
_TRAILER = b"\x3b"
_DISPOSAL_KEEP = 1 << 2  # graphic control packed field: disposal method 1, "do not dispose"
_LOOP_FOREVER = b"\x21\xff\x0bNETSCAPE2.0\x03\x01" + struct.pack("<H", 0) + b"\x00"


def _skip_sub_blocks(data: bytes, pos: int) -> int:
    """Index just past the data sub-blocks starting at ``pos`` (through the zero terminator)."""
    while True:
        if pos >= len(data):
            raise VideoError("Pillow wrote a truncated GIF: data sub-blocks run past the end")
        size = data[pos]
        pos += 1 + size
        if size == 0:
            return pos


def image_block(rgb: NDArray[np.uint8], left: int, top: int) -> bytes:
    """One GIF image block of an RGB ``uint8`` image placed at (``left``, ``top``) px on the canvas.

    The block is the image descriptor with a local colour table, the LZW minimum code size and
    the LZW data sub-blocks, taken from a single-frame GIF that Pillow encodes in memory.
    """
    height, width = rgb.shape[:2]
    buf = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(rgb)).save(buf, format="GIF", interlace=False, optimize=True)
    data = buf.getvalue()
    if data[:6] not in (b"GIF87a", b"GIF89a") or len(data) < 13:
        raise VideoError(f"Pillow did not write a GIF header (got {data[:6]!r})")
    screen_flags = data[10]
    pos = 13
    table, table_bits = b"", -1
    if screen_flags & 0x80:  # global colour table: 3 * 2**(n+1) bytes
        table_bits = screen_flags & 0x07
        table = data[pos : pos + (3 << (table_bits + 1))]
        pos += len(table)
    while pos < len(data) and data[pos] == _EXTENSION:  # introducer, label, sub-blocks
        pos = _skip_sub_blocks(data, pos + 2)
    if pos + 10 > len(data) or data[pos] != _IMAGE:
        raise VideoError("Pillow wrote a GIF without an image descriptor where one was expected")
    w, h, flags = struct.unpack_from("<HHB", data, pos + 5)
    if (w, h) != (width, height):
        raise VideoError(f"Pillow wrote a {w} x {h} GIF image for a {width} x {height} frame")
    pos += 10
    if flags & 0x80:  # a local colour table wins over the global one
        table_bits = flags & 0x07
        table = data[pos : pos + (3 << (table_bits + 1))]
        pos += len(table)
    if table_bits < 0 or len(table) != 3 << (table_bits + 1):
        raise VideoError("Pillow wrote a GIF image without a complete colour table")
    end = _skip_sub_blocks(data, pos + 1)  # pos: LZW minimum code size
    descriptor = struct.pack("<BHHHHB", _IMAGE, left, top, w, h, 0x80 | (flags & 0x40) | table_bits)
    return descriptor + table + data[pos:end]


class GifStream:
    """Appends frames to an animated GIF in an open binary file, looping forever.

    ``fps`` (frames per second, finite, > 0) sets the delays. Call :meth:`add` per frame and
    :meth:`finish` once at the end; the file object is not closed here.
    """

    def __init__(self, file: BinaryIO, fps: float) -> None:
        if not (math.isfinite(fps) and fps > 0):
            raise ValueError(f"fps must be a finite number > 0, got {fps!r}")
        self.file = file
        self.fps = float(fps)
        self.frames_added = 0
        """Frames passed to :meth:`add` (identical consecutive frames count each)."""
        self.blocks_written = 0
        """Image blocks in the file so far (the pending frame not counted)."""
        self._previous: NDArray[np.uint8] | None = None
        self._pending: bytes | None = None
        self._pending_start = 0  # cs
        self._finished = False

    def _start_cs(self, index: int) -> int:
        """Scheduled start of frame ``index`` (centiseconds from the first frame)."""
        return round(index * 100.0 / self.fps)

    def add(self, frame: NDArray[np.uint8]) -> None:
        """Append an RGB ``uint8`` frame (H x W x 3, H and W in 1..65535, same size as the first)."""
        if self._finished:
            raise ValueError("GifStream.add after finish()")
        if frame.dtype != np.uint8 or frame.ndim != 3 or frame.shape[2] != 3:
            raise ValueError(f"frame must be uint8 H x W x 3, got {frame.dtype} {frame.shape}")
        h, w = frame.shape[:2]
        if not (1 <= h <= _MAX_SIDE and 1 <= w <= _MAX_SIDE):
            raise ValueError(f"GIF frame height and width must be in 1..{_MAX_SIDE} px, got {h} x {w}")
        previous = self._previous
        if previous is None:
            self.file.write(b"GIF89a" + struct.pack("<HHBBB", w, h, 0x70, 0, 0) + _LOOP_FOREVER)
            block = image_block(frame, 0, 0)
        elif frame.shape != previous.shape:
            raise ValueError(f"frame shape {frame.shape} differs from the first {previous.shape}")
        else:
            changed = np.any(frame != previous, axis=2)
            rows = np.flatnonzero(changed.any(axis=1))
            if rows.size == 0:  # identical: the pending frame lasts longer
                self.frames_added += 1
                return
            cols = np.flatnonzero(changed.any(axis=0))
            r0, r1, c0, c1 = int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1
            block = image_block(frame[r0:r1, c0:c1], c0, r0)
            self._flush_pending(self._start_cs(self.frames_added))
        self._previous = frame.copy()
        self._pending = block
        self.frames_added += 1

    def _flush_pending(self, end_cs: int) -> None:
        """Write the pending frame shown until ``end_cs`` (at least 1 cs)."""
        if self._pending is None:
            return
        delay = max(1, end_cs - self._pending_start)
        self._pending_start += delay
        while delay > 0:
            part = min(delay, _MAX_SIDE)
            self.file.write(b"\x21\xf9\x04" + struct.pack("<BHBB", _DISPOSAL_KEEP, part, 0, 0) + self._pending)
            self.blocks_written += 1
            delay -= part
        self._pending = None

    def finish(self) -> None:
        """Write the last frame and the trailer (nothing if no frame was added). Safe to call twice."""
        if self._finished:
            return
        self._finished = True
        if self._pending is None:
            return
        self._flush_pending(self._start_cs(self.frames_added))
        self.file.write(_TRAILER)
        self._previous = None
