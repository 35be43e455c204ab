"""The HTML report of a train (SPEC 3.6): one self-contained page plus the same figures as PNG.

:func:`make_report` runs the requested linear analyses (``modal``, ``campbell``,
``unbalance``), optionally reads a saved transient result, and writes into a directory:

* ``report.html`` – a single file with the plotly.js bundle embedded inline (no network access
  is needed to open it): summary and verdicts, the table of modes, stability margins, interactive
  3-D mode shapes, Campbell diagram with crossings, Bode plot, orbits, API 684 / API 617 checks,
  tabulated bearing coefficients, and for a transient result its spectra, waterfall and
  whirl-promoting power;
* PNG files of the same figures (matplotlib);
* ``report.json`` – the numbers of the report (modes, crossings, checks, inputs).

The directory is written atomically: everything goes to a temporary sibling directory first; a
new output directory is then renamed into place, an existing one receives each file by
``os.replace`` with ``report.html`` last. A failure leaves no partial report behind.

Speeds follow the ``campbell`` and ``unbalance`` commands: sweeps run over positive reference
speeds; the modal analysis runs at the given speed with the sign of the model's nominal speed.
When the model has tabulated (fluid-film) bearings, the sweeps are limited to the speed range of
their tables (unless the table holds its end values) and the report says so.

Layout: :mod:`.build` (:func:`make_report`), :mod:`.base` (what a section is and what it works
on), :mod:`.sections` (one module per section, registered in page order in
:data:`.sections.SECTIONS`), :mod:`.page` (the HTML page), :mod:`.blocks` (shared helpers).
"""

from .blocks import LOG_DEC_THRESHOLD
from .build import ANALYSES, Report, make_report, parse_analyses
from .sections.bearings import plot_bearing_coefficients
from .sections.transient import plot_waterfall

__all__ = [
    "ANALYSES",
    "LOG_DEC_THRESHOLD",
    "Report",
    "make_report",
    "parse_analyses",
    "plot_bearing_coefficients",
    "plot_waterfall",
]
