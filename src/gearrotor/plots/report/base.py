"""What a report section is (:class:`Section`) and what it works on (:class:`Context`).

:func:`~.build.make_report` checks the request, then for the requested sections in page order
calls :meth:`Section.check` (input errors, before anything runs), then :meth:`Section.run`
(the analyses), then, inside the temporary report directory, :meth:`Section.write` of every
section (PNG files, numbers for ``report.json``, verdicts, and the section's part of the page).
A section reads what it needs from the :class:`Context` (the model, the operating speed, the
results of the analyses) and writes what it produces into it.
"""

from __future__ import annotations

import math
from collections.abc import Hashable
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ...errors import ModelError
from .blocks import RPM, _savefig
from .helper import Helper

if TYPE_CHECKING:
    from ...assembly import Assembly
    from ...model import Train

__all__ = ["Context", "Section"]

#: A part of the page: (html id, title, html body).
Part = tuple[str, str, str]


@dataclass
class Context:
    """The request, the analysis results and what the report has written so far.

    assembly : the model; speed : rad/s, magnitude of the reference-shaft operating speed (the
    direction of rotation follows the model, :attr:`sign`); max_frequency : rad/s; api : the
    unbalance section uses the API 617 unbalance of :attr:`api_edition` (``edition``: the one
    asked for, None: the model's); transient_file : a saved transient result;
    n_campbell, n_unbalance : speeds of the sweeps; operating_range : rad/s, the reference
    shaft's (minimum operating speed, maximum continuous speed) of the API checks: the model's
    (:func:`~gearrotor.analyses.model_operating_range`) unless a speed was asked for, else
    (speed, speed).

    results : analysis name -> its result (``"modal"``, ``"campbell"``, ``"unbalance"``,
    ``"transient"``: the dataset read from the file), filled by :meth:`Section.run`;
    notes : remarks shown under the summary (e.g. a sweep limited by bearing tables);
    directory : the temporary report directory the files go to (during ``write``);
    figures : the PNG files written, in page order; summary : the content of
    ``report.json``; verdicts : the checks of the summary table, one per check
    (:meth:`verdict`).
    """

    assembly: Assembly
    analyses: tuple[str, ...]
    speed: float
    max_frequency: float
    api: bool = False
    transient_file: Path | None = None
    n_campbell: int = 40
    n_unbalance: int = 400
    operating_range: tuple[float, float] | None = None
    results: dict[str, object] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    directory: Path | None = None
    figures: list[Path] = field(default_factory=list)
    summary: dict = field(default_factory=dict)
    verdicts: list[dict] = field(default_factory=list)
    # operating points (issue 11): the points of the operating-points section, and the model
    # before an --operating-point put its bearings at that point's loads
    operating_points: tuple[str, ...] = ()
    base_train: Train | None = None
    # the API 617 edition asked for (``--edition``); None: the model's [api_audit] edition
    edition: str | None = None
    # the second process for independent work (.helper; disabled: everything runs here)
    helper: Helper = field(default_factory=lambda: Helper(False))
    # the names of the PNG files submitted so far (one job per file)
    started: set[str] = field(default_factory=set)
    #: file name -> the helper job that writes it (:meth:`png_data` waits for it)
    jobs: dict[str, Hashable] = field(default_factory=dict)

    @property
    def train(self) -> Train:
        return self.assembly.train

    @property
    def api_range(self) -> tuple[float, float]:
        """rad/s: the operating range of the API checks (see the class docstring)."""
        return (
            self.operating_range
            if self.operating_range is not None
            else (
                self.speed,
                self.speed,
            )
        )

    @property
    def api_edition(self):
        """The API 617 edition of the ``--api`` unbalance and the audit
        (:class:`~gearrotor.analyses.audit.stability.Edition`): the one asked for, else the model's
        ``[api_audit] edition``, else the 8th."""
        from ...analyses.audit.stability import edition

        if self.edition is not None:
            return edition(self.edition, "--edition")
        table = self.train.api_audit
        return edition(None if table is None else table.edition, "api_audit.edition")

    @property
    def sign(self) -> float:
        """+1 or -1: the direction of rotation of the model's reference shaft."""
        return 1.0 if self.train.speed >= 0 else -1.0

    def sweep(self, lo: float, hi: float, n: int, what: str) -> np.ndarray:
        """``n`` reference speeds (rad/s) from ``lo`` to ``hi``, limited to the speed range of
        the tabulated bearings that do not hold their end values (a note says so)."""
        speeds, note = _sweep(lo, hi, n, _table_limits(self.assembly), what)
        if note:
            self.notes.append(note)
        return speeds

    def verdict(self, key: str, check: str, ok, detail: str, result: str | None = None) -> None:
        """Add a line to the summary (:func:`~.verdicts.verdict`): one line per check, so a
        check another section has already judged (same ``key``, e.g. the separation margins of
        the unbalance and audit sections, from the same response) is not added twice."""
        from .verdicts import verdict

        if any(v["key"] == key for v in self.verdicts):
            return
        self.verdicts.append(verdict(key, check, ok, detail, result))

    def png(self, fn, name: str, *args, **kw) -> None:
        """Write ``fn(*args, path=<directory>/name, **kw)``, a figure function of
        :mod:`gearrotor.plots` (pyplot), and close its figure: a job of :attr:`helper` (done
        by the time the page is written), once per name (:meth:`png_early` may have written
        it)."""
        path = self.directory / name
        if name not in self.started:
            self.started.add(name)
            self.jobs[name] = ("png", name)
            self.helper.submit(("png", name), partial(_draw, fn, args, kw, path))
        self.figures.append(path)

    def png_early(self, fn, name: str, *args, **kw) -> None:
        """:meth:`png`'s file, written here and now (the report's own process, while the
        helper runs an analysis) without adding it to :attr:`figures`: the section's
        :meth:`png` of the same name then only lists it."""
        if name not in self.started:
            self.started.add(name)
            _draw(fn, args, kw, self.directory / name)

    def pngs(self, fn, names: list[str], *args, **kw) -> None:
        """Several PNG files of one figure function ``fn(*args, pages, paths, **kw)`` that
        draws ``kw["pages"]`` into ``paths``: one job with a single process (pages of one size
        drawn on one figure), one job per page with the helper."""
        pages = kw.pop("pages")
        paths = [self.directory / n for n in names]
        step = 1 if self.helper.enabled else max(len(pages), 1)
        for lo in range(0, len(pages), step):
            job = partial(fn, *args, pages[lo : lo + step], paths[lo : lo + step], **kw)
            self.jobs.update(dict.fromkeys(names[lo : lo + step], ("png", names[lo])))
            self.helper.submit(("png", names[lo]), job)
        self.started.update(names)
        self.figures.extend(paths)

    def later(self, key: str, fn) -> None:
        """``results[key] = fn()``, computed by :attr:`helper` (a :class:`Later` until all
        sections have run; :func:`~.build.make_report` then puts the value in its place)."""
        self.results[key] = Later(key)
        self.helper.submit(key, fn)
        if not self.helper.enabled:
            self.results[key] = self.helper.result(key)

    def save(self, fig, name: str) -> None:
        """Write a matplotlib Figure as ``<directory>/name`` (PNG): a job of :attr:`helper`."""
        path = self.directory / name
        self.started.add(name)
        self.jobs[name] = ("png", name)
        self.helper.submit(("png", name), partial(_savefig, fig, path))
        self.figures.append(path)

    def png_data(self, name: str) -> str:
        """A PNG file of this report as base64, for a data URI in the page: its job finished
        first (with the helper process the file may still be being drawn)."""
        import base64

        if name in self.jobs:
            self.helper.result(self.jobs[name])
        return base64.b64encode((self.directory / name).read_bytes()).decode("ascii")


def _draw(fn, args, kw, path: Path) -> None:
    import matplotlib.pyplot as plt

    plt.close(fn(*args, path=path, **kw))


@dataclass(frozen=True)
class Later:
    """A result the helper computes (:meth:`Context.later`)."""

    key: str


class Section:
    """One section of the report. Subclasses set:

    analysis : the name in ``--analyses`` that requests the section's analysis, or None for
        a section that shows what the others computed (stability margins, bearing tables);
    default : whether the analysis runs when ``--analyses`` is not given;

    and override what they need of :meth:`check`, :meth:`run` and :meth:`write`.
    """

    analysis: str | None = None
    default: bool = False

    def check(self, ctx: Context) -> None:
        """Check the request before anything runs; raise :class:`~gearrotor.errors.ModelError`
        (called for requested sections only)."""

    def run(self, ctx: Context) -> None:
        """Run the analysis, into ``ctx.results[self.analysis]`` (requested sections only)."""

    def early(self, ctx: Context) -> None:
        """Write, before the results are all in, PNG files that need no analysis
        (:meth:`Context.png_early`; called with the helper only, while it runs an analysis)."""

    def write(self, ctx: Context) -> list[Part]:
        """Write the section's PNG files (:meth:`Context.png`, :meth:`Context.save`), add its
        numbers to ``ctx.summary`` and its checks to ``ctx.verdicts``; return its parts of the
        page. Called for every section: one without results returns ``[]``."""
        return []


def _table_limits(asm) -> tuple[float, float, list[str]]:
    """Reference-speed range (rad/s) allowed by tabulated bearings that do not hold end values."""
    lo, hi, names = 0.0, math.inf, []
    for b in asm.bearings:
        el = b.element
        if not el.speed_dependent or el.table.extrapolate == "hold":
            continue
        r = abs(asm.speed_ratio[b.shaft])
        if r == 0:
            continue
        lo = max(lo, float(el.table.speed[0]) / r)
        hi = min(hi, float(el.table.speed[-1]) / r)
        names.append(b.name)
    return lo, hi, names


def _sweep(lo: float, hi: float, n: int, limits, what: str) -> tuple[np.ndarray, str | None]:
    tlo, thi, names = limits
    note = None
    a, b = max(lo, tlo), min(hi, thi)
    if names and (a != lo or b != hi):
        note = (
            f"{what} limited to {a * RPM:.0f}..{b * RPM:.0f} rpm, the speed range of the "
            f"coefficient tables of {', '.join(names)}"
        )
    if not b > a:
        raise ModelError(
            f"no speed range for the {what}",
            field="bearings",
            value=f"{a * RPM:.6g}..{b * RPM:.6g} rpm",
            expected="bearing tables that cover the operating speed",
        )
    return np.linspace(a, b, n), note
