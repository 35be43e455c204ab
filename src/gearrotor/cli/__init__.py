"""The ``gearrotor`` command line: a thin layer over the functions a Python user calls.

One module per command group, each a plain function registered here (the order below is the
order of ``gearrotor --help``):

==================  ==========================  ==============================================
command             module                      calls
==================  ==========================  ==============================================
``show``            :mod:`.show`                :func:`gearrotor.analyses.model_summary.summarize`
``view``            :mod:`.view`                a live model view on 127.0.0.1
``modal``           :mod:`.modal`               :func:`gearrotor.analyses.modal`
``campbell``        :mod:`.campbell`            :func:`gearrotor.analyses.campbell`
``unbalance``       :mod:`.unbalance`           :func:`gearrotor.analyses.unbalance_response`
``static``          :mod:`.static`              :func:`gearrotor.analyses.static.static`
``bearing``         :mod:`.bearing`             :func:`gearrotor.bearings.coefficients`
``seal``            :mod:`.seal`                :func:`gearrotor.seals.seal_coefficients`
``mesh``            :mod:`.mesh`                :func:`gearrotor.gears.mesh_curves`
``transient``,      :mod:`.transient`           :func:`gearrotor.analyses.transient.transient`
``transient-plot``
``report``          :mod:`.report`              :func:`gearrotor.plots.report.make_report`
``floquet``         :mod:`.floquet`             :func:`gearrotor.analyses.lateral.floquet.floquet`
``mesh-response``   :mod:`.mesh_response`       :mod:`gearrotor.analyses.lateral.mesh_response`
``ucs``             :mod:`.ucs`                 :func:`gearrotor.analyses.ucs_map`
``stability``       :mod:`.stability`           :func:`gearrotor.analyses.stability_audit`
``import-ross``     :mod:`.ross`                :func:`gearrotor.interop.import_ross`
``export``          :mod:`.ross`                :func:`gearrotor.interop.ross_script`
``study ...``       :mod:`.study`               :mod:`gearrotor.studies`
``torsional ...``   :mod:`.torsional`           :mod:`gearrotor.analyses.torsional`
==================  ==========================  ==============================================

Shared options (``--set``, ``--format``, rpm) are in :mod:`.options`; every command also gets
``--threads`` there (:func:`common_options`: it runs in a
:func:`gearrotor.threads.scope`); every command maps errors
to exit statuses through :func:`.errors.cli_errors`: input errors print one clear message (file,
field, value, expectation) and exit with status 2, without a traceback; solver failures exit
with status 3 (see :mod:`.errors`). The analyses are imported inside the command functions, so
``gearrotor --help`` starts fast.
"""

from __future__ import annotations

import functools
import inspect
import sys
import typing
from collections.abc import Callable
from pathlib import Path

import typer

from .bearing import bearing_cli
from .campbell import campbell_command
from .errors import EXIT_CODES_HELP, OneLineGroup, cli_errors
from .floquet import floquet_command
from .mesh import mesh_command
from .mesh_response import mesh_response_command
from .modal import modal_command
from .options import ProgressOpt, ThreadsOpt
from .report import report_command
from .ross import export_command, import_ross_command
from .seal import seal_command
from .show import show_command
from .stability import stability_command
from .static import static_command
from .study import study_app
from .torsional import torsional_app
from .transient import plot_command, transient_command
from .ucs import ucs_command
from .unbalance import unbalance_command
from .view import view_command

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


def _check_model_file(path: Path | None) -> None:
    """A missing, unreadable or unparsable model file is reported at once, before the command
    imports anything heavy (the model classes, the analyses): the same one-line error the
    model reader gives (:func:`gearrotor.inputs.read_toml`)."""
    if path is not None:
        from ..inputs import read_toml

        read_toml(path, "model")


def common_options(fn: Callable, name: str | None = None) -> Callable:
    """Give a command function the options every command has, keeping the parameters Typer
    reads: ``--threads`` (the command runs in a :func:`gearrotor.threads.scope` with that
    setting; a bad ``GEARROTOR_THREADS`` is an input error, before anything runs) and
    ``--progress/--no-progress`` (a :func:`.progress.reporting` titled ``name``; commands with
    their own ``progress`` option keep it). A command with a ``model`` file argument has the
    file read first (:func:`_check_model_file`)."""
    sig = inspect.signature(fn, eval_str=True)
    if "threads" in sig.parameters:
        return fn
    title = name or fn.__name__.removesuffix("_command")
    own_progress = "progress" in sig.parameters
    model_arg = sig.parameters.get("model")
    reads_model = model_arg is not None and typing.get_args(model_arg.annotation)[:1] == (Path,)

    @functools.wraps(fn)
    def command(*args, threads: str | None = None, **kwargs):
        from .. import threads as threads_
        from .progress import reporting

        show = None if own_progress else kwargs.pop("show_progress", None)
        with threads_.using(threads):
            with cli_errors():
                threads_.setting()  # GEARROTOR_THREADS is read (and checked) before anything runs
                if reads_model:
                    _check_model_file(sig.bind_partial(*args, **kwargs).arguments.get("model"))
            with threads_.scope(), reporting(title, False if own_progress else show):
                return fn(*args, **kwargs)

    extra = [
        inspect.Parameter(
            "threads", inspect.Parameter.KEYWORD_ONLY, default=None, annotation=ThreadsOpt
        )
    ]
    annotations = {"threads": ThreadsOpt}
    if not own_progress:
        extra.append(
            inspect.Parameter(
                "show_progress",
                inspect.Parameter.KEYWORD_ONLY,
                default=None,
                annotation=ProgressOpt,
            )
        )
        annotations["show_progress"] = ProgressOpt
    command.__signature__ = sig.replace(parameters=[*sig.parameters.values(), *extra])
    command.__annotations__ = {**fn.__annotations__, **annotations}
    return command


def _command(name: str, fn) -> None:
    app.command(name, help=reflow(fn.__doc__), epilog=EXIT_CODES_HELP)(common_options(fn, name))


_command("show", show_command)
_command("view", view_command)
_command("modal", modal_command)
_command("campbell", campbell_command)
_command("unbalance", unbalance_command)
_command("static", static_command)
_command("bearing", bearing_cli)
_command("seal", seal_command)
_command("mesh", mesh_command)
_command("transient", transient_command)
_command("transient-plot", plot_command)
_command("report", report_command)
_command("floquet", floquet_command)
_command("mesh-response", mesh_response_command)
_command("ucs", ucs_command)
_command("stability", stability_command)
_command("import-ross", import_ross_command)
_command("export", export_command)
for _group in (study_app, torsional_app):  # the options every command has, also in the groups
    for _info in _group.registered_commands:
        _info.callback = common_options(_info.callback, _info.name)
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
