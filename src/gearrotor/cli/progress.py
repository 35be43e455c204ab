"""The progress every long command shows on stderr (:mod:`gearrotor.progress` callbacks).

Each command runs with a :class:`Reporter` (:func:`reporting`, set up by
:func:`gearrotor.cli.common_options`); the command hands :func:`current` to its analysis as
``progress=``. On a terminal the reporter draws one line, redrawn in place at most ten times a
second and only once the command has run for :data:`DELAY` s (quick commands stay silent)::

    campbell [############............]  48 %  speed 29/60  3 s

and erases it when the work is done or anything else is written to stderr (an error message
then starts on a clean line). ``--no-progress`` turns it off, and it is off when stderr is not
a terminal (a log file, a pipe, a test runner); ``--progress`` forces it on, then as plain lines
(at most one a second, and the last one) where stderr is not a terminal.
"""

from __future__ import annotations

import contextlib
import sys
import time
from collections.abc import Iterator
from typing import TextIO

__all__ = ["DELAY", "Reporter", "current", "reporting"]

#: Seconds a command runs before its bar appears on a terminal.
DELAY = 1.0
_WIDTH = 24

_current: Reporter | None = None


class Reporter:
    """A :data:`gearrotor.progress.Progress` callback that draws on ``stream``.

    ``tty``: redraw one line in place (default: whether ``stream`` is a terminal); otherwise a
    line per report, at most one per ``interval`` s besides the first and the last.
    """

    def __init__(
        self,
        title: str,
        stream: TextIO | None = None,
        *,
        tty: bool | None = None,
        delay: float = DELAY,
        interval: float | None = None,
    ) -> None:
        self.title = title
        self.stream = stream if stream is not None else sys.stderr
        self.tty = _isatty(self.stream) if tty is None else tty
        self.delay = delay if self.tty else 0.0
        self.interval = interval if interval is not None else (0.1 if self.tty else 1.0)
        self.t0 = time.perf_counter()
        self._last = -1e9
        self._drawn = False  # a line is on the terminal (tty)
        self._done = False

    def __call__(self, fraction: float, text: str = "") -> None:
        now = time.perf_counter()
        end = fraction >= 1.0
        if end:
            if self.tty:
                self.clear()
            elif not self._done and self._last > -1e9:
                self._line(fraction, text, now)
            self._done = True
            return
        self._done = False
        if now - self.t0 < self.delay or now - self._last < self.interval:
            return
        self._line(fraction, text, now)

    def _line(self, fraction: float, text: str, now: float) -> None:
        fill = int(_WIDTH * fraction)
        bar = "#" * fill + "." * (_WIDTH - fill)
        body = f"{self.title} [{bar}] {100 * fraction:3.0f} %  {text}  {now - self.t0:.0f} s"
        if self.tty:
            self.stream.write("\r\x1b[K" + body)
            self._drawn = True
        else:
            self.stream.write(body.rstrip() + "\n")
        self.stream.flush()
        self._last = now

    def clear(self) -> None:
        """Erase the drawn line (a terminal), so that other output starts on a clean line."""
        if self._drawn:
            self.stream.write("\r\x1b[K")
            self.stream.flush()
            self._drawn = False


def _isatty(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


class _ClearingStream:
    """stderr while a bar may be drawn: anything written first erases the bar's line."""

    def __init__(self, stream, reporter: Reporter) -> None:
        self._stream = stream
        self._reporter = reporter

    def write(self, text: str) -> int:
        self._reporter.clear()
        return self._stream.write(text)

    def __getattr__(self, name: str):
        return getattr(self._stream, name)


def current() -> Reporter | None:
    """The running command's reporter, or None when progress is off."""
    return _current


@contextlib.contextmanager
def reporting(title: str, enabled: bool | None) -> Iterator[Reporter | None]:
    """Run a command with progress on stderr: ``enabled`` True (forced), False (off) or None
    (on when stderr is a terminal)."""
    global _current
    stream = sys.stderr
    on = _isatty(stream) if enabled is None else enabled
    if not on:
        yield None
        return
    reporter = Reporter(title, stream)
    old, old_stderr = _current, sys.stderr
    _current = reporter
    if reporter.tty:
        sys.stderr = _ClearingStream(stream, reporter)
    try:
        yield reporter
    finally:
        reporter.clear()
        _current = old
        sys.stderr = old_stderr
