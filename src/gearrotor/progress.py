"""Progress of long analyses: one small callback protocol the analyses accept.

An analysis that can take more than a couple of seconds takes a keyword-only ``progress``
argument: ``None`` (the default: nothing is reported) or a callable ``progress(fraction, text)``
called with the fraction done (0 to 1) and a short text of what it is doing ("speed 12/60",
"section Campbell"). The analyses report through :func:`report`; an analysis that calls another
hands it a part of its own range (:func:`part`), so nested analyses add up to one bar.

The command line shows it on stderr (``gearrotor.cli.progress``: a bar on a terminal, off with
``--no-progress`` and when stderr is not a terminal); a Python user passes any callable, e.g.
``campbell(train, ..., progress=lambda f, t: print(f"{f:.0%} {t}"))``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Sized
from typing import TypeVar

__all__ = ["Progress", "part", "report", "steps"]

#: ``progress(fraction, text)``: fraction done in [0, 1], what is being done.
Progress = Callable[[float, str], None]

T = TypeVar("T")


def report(progress: Progress | None, fraction: float, text: str = "") -> None:
    """Report ``fraction`` (clipped to [0, 1]) and ``text`` to ``progress`` (nothing if None)."""
    if progress is not None:
        progress(min(max(float(fraction), 0.0), 1.0), text)


def part(progress: Progress | None, start: float, stop: float, prefix: str = "") -> Progress | None:
    """The callback of a sub-task that covers ``start..stop`` of ``progress``'s range, its text
    prefixed with ``prefix`` (None when ``progress`` is None)."""
    if progress is None:
        return None

    def sub(fraction: float, text: str) -> None:
        label = f"{prefix}: {text}" if prefix and text else prefix or text
        report(progress, start + (stop - start) * fraction, label)

    return sub


def steps(
    progress: Progress | None, items: Iterable[T], label: Callable[[int, int, T], str] | str
) -> Iterator[T]:
    """Iterate over ``items`` reporting before each one (``label(i, n, item)``, or the string
    ``label`` with `` i/n`` added) and 1.0 at the end."""
    seq = list(items) if not isinstance(items, Sized) else items
    n = len(seq)
    for i, item in enumerate(seq):
        if progress is not None:
            text = label(i + 1, n, item) if callable(label) else f"{label} {i + 1}/{n}"
            report(progress, i / max(n, 1), text)
        yield item
    report(progress, 1.0, "")
