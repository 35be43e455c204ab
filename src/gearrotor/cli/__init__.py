"""The ``gearrotor`` command line: a thin layer over the functions a Python user calls.

One module per command group, each a plain function registered here (the order below is the
order of ``gearrotor --help``):

==================  ==========================  ==============================================
command             module                      calls
==================  ==========================  ==============================================
``show``            :mod:`.show`                :func:`gearrotor.analyses.model_summary.summarize`
``modal``           :mod:`.modal`               :func:`gearrotor.analyses.modal`
``campbell``        :mod:`.campbell`            :func:`gearrotor.analyses.campbell`
``unbalance``       :mod:`.unbalance`           :func:`gearrotor.analyses.unbalance_response`
``static``          :mod:`.static`              :func:`gearrotor.analyses.static.static`
``bearing``         :mod:`.bearing`             :func:`gearrotor.bearings.coefficients`
``transient``,      :mod:`.transient`           :func:`gearrotor.analyses.transient.transient`
``transient-plot``
``report``          :mod:`.report`              :func:`gearrotor.plots.report.make_report`
``floquet``         :mod:`.floquet`             :func:`gearrotor.analyses.floquet.floquet`
``ucs``             :mod:`.ucs`                 :func:`gearrotor.analyses.ucs.ucs_map`
``stability``       :mod:`.stability`           :func:`gearrotor.analyses.audit.stability_audit`
``study ...``       :mod:`.study`               :mod:`gearrotor.studies`
``torsional ...``   :mod:`.torsional`           :mod:`gearrotor.analyses.torsional`
==================  ==========================  ==============================================

Shared options (``--set``, ``--format``, rpm) are in :mod:`.options`; every command maps errors
to exit statuses through :func:`.errors.cli_errors`: input errors print one clear message (file,
field, value, expectation) and exit with status 2, without a traceback; solver failures exit
with status 3 (see :mod:`.errors`). The analyses are imported inside the command functions, so
``gearrotor --help`` starts fast.
"""

from __future__ import annotations

import sys

import typer

from .bearing import bearing_cli
from .campbell import campbell_command
from .errors import EXIT_CODES_HELP, OneLineGroup
from .floquet import floquet_command
from .modal import modal_command
from .report import report_command
from .show import show_command
from .stability import stability_command
from .static import static_command
from .study import study_app
from .torsional import torsional_app
from .transient import plot_command, transient_command
from .ucs import ucs_command
from .unbalance import unbalance_command

__all__ = ["app", "main"]

app = typer.Typer(
    name="gearrotor",
    help=(
        "Dynamics of geared rotor-bearing trains: damped modes, Campbell diagrams, unbalance "
        "response, fluid-film bearings, nonlinear transients, HTML reports, Floquet stability "
        "and parametric studies."
    ),
    epilog=EXIT_CODES_HELP,
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # help text is printed as written: rich markup would take '[[operating_points]]' or
    # '[default]' for tags and drop them
    rich_markup_mode=None,
    cls=OneLineGroup,  # parser errors are one line, like every other error
)


def reflow(doc: str | None) -> str | None:
    """A docstring as help text: each paragraph's source line breaks joined into one line (the
    terminal wraps it), paragraphs kept apart."""
    if not doc:
        return doc
    import inspect

    paras = inspect.cleandoc(doc).split("\n\n")
    return "\n\n".join(" ".join(p.split()) for p in paras)


def _command(name: str, fn) -> None:
    app.command(name, help=reflow(fn.__doc__), epilog=EXIT_CODES_HELP)(fn)


_command("show", show_command)
_command("modal", modal_command)
_command("campbell", campbell_command)
_command("unbalance", unbalance_command)
_command("static", static_command)
_command("bearing", bearing_cli)
_command("transient", transient_command)
_command("transient-plot", plot_command)
_command("report", report_command)
_command("floquet", floquet_command)
_command("ucs", ucs_command)
_command("stability", stability_command)
app.add_typer(study_app, name="study")
app.add_typer(torsional_app, name="torsional")


def main() -> None:
    """Entry point of the ``gearrotor`` command (the program itself, not a call inside
    another program: ``study run`` then answers signals until the process exits)."""
    from . import study

    study.as_program = True
    app(prog_name="gearrotor")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
