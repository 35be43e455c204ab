"""One mapping from errors to exit statuses, shared by every ``gearrotor`` command.

==========  ============================================================================
status      meaning
==========  ============================================================================
0           done
1           ``study run`` finished but some cases failed (listed on stderr); also any
            unexpected internal error (a bug: Python prints a traceback)
2           invalid input: model or study file (missing, unreadable, invalid field), bad
            option value, output path that cannot be written, or a missing optional
            package (the message names the extra to install). Inputs are checked before
            anything runs. Option-syntax errors of the command-line parser also exit with 2.
3           a solver failed: divergence, no convergence, non-finite response, a step above
            the integrator's stability limit (:class:`~gearrotor.errors.SolverError`)
130         stopped by Ctrl-C: one line, ``interrupted (Ctrl-C): ...`` saying what was kept
            (every command: :func:`cli_errors`; ``study run`` keeps its finished cases and
            ``transient --checkpoint`` its state, and the same command resumes; the others'
            outputs are written as a whole or not at all, so nothing is left half-written)
143         ``study run`` stopped by SIGTERM (likewise)
==========  ============================================================================

Every error is one message on stderr, no traceback: ``error: FILE: FIELD: what (got VALUE);
expected WHAT`` for input errors (:class:`~gearrotor.errors.ModelError` carries those parts) and
``solver error: ...`` for solver failures.

Use :func:`cli_errors` as a decorator of a command function (below ``@app.command()``) or as a
context manager around part of one. Errors of the command-line parser itself (an unknown option,
a value that does not parse, a missing argument) are one line too: ``error: --speed: ...``
(:class:`OneLineGroup`, the class of the ``gearrotor`` command group).
"""

from __future__ import annotations

import contextlib
import errno
import os
import re
import sys
from collections.abc import Callable

import typer
from typer.core import TyperGroup

from ..errors import ModelError, SolverError

__all__ = [
    "EXIT_CASES_FAILED",
    "EXIT_CODES_HELP",
    "EXIT_INPUT",
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "EXIT_SOLVER",
    "EXIT_TERMINATED",
    "OneLineGroup",
    "cli_errors",
    "input_error",
    "interrupted_line",
]

EXIT_OK = 0
EXIT_CASES_FAILED = 1
EXIT_INPUT = 2
EXIT_SOLVER = 3
#: Stopped by Ctrl-C (128 + SIGINT) or SIGTERM (128 + SIGTERM), the shell's convention.
EXIT_INTERRUPTED = 130
EXIT_TERMINATED = 143

#: Epilog of every command's ``--help``.
EXIT_CODES_HELP = (
    "Exit status: 0 done; 2 invalid input (model file, field, option value; nothing is run); "
    "3 solver failure (divergence, no convergence); 1 study cases failed, or an internal error; "
    "130 stopped by Ctrl-C (one line; no output file is left half-written)."
)

# optional packages and the extra that installs them
_EXTRAS = {
    "matplotlib": "plot",
    "plotly": "report",
    "xarray": "results",
    "h5netcdf": "results",
    "h5py": "results",
    "pandas": "results",
    "dask": "dask",
    "distributed": "dask",
}

_PATH_ERRORS = (
    FileNotFoundError,
    FileExistsError,
    IsADirectoryError,
    NotADirectoryError,
    PermissionError,
)
_ERRNOS = (errno.EROFS, errno.ENOSPC, errno.ENAMETOOLONG)


def input_error(exc: BaseException) -> ModelError | None:
    """The :class:`ModelError` an exception stands for at the command line, or ``None`` when it
    is not an input error (then it is a bug and keeps its traceback).

    ``ModelError`` itself; a missing optional package (names the extra to install); a file that
    cannot be read or written (names the file and the reason).
    """
    if isinstance(exc, ModelError):
        return exc
    if isinstance(exc, ImportError):
        name = (exc.name or "").split(".")[0]
        if name in _EXTRAS:
            return ModelError(
                f"this command needs the Python package {name!r}, which is not installed",
                expected=f"pip install 'gearrotor[{_EXTRAS[name]}]'",
            )
        return None
    if isinstance(exc, _PATH_ERRORS) or (isinstance(exc, OSError) and exc.errno in _ERRNOS):
        file = exc.filename
        return ModelError(
            exc.strerror or (os.strerror(exc.errno) if exc.errno else str(exc)),
            file=None if file is None else os.fsdecode(file),
            expected="a path that can be read (inputs) or written (outputs)",
        )
    return None


def interrupted_line(kept: str | None = None, *, since: int = 0, how: str = "Ctrl-C") -> str:
    """The one line of a command stopped by a signal: ``interrupted (Ctrl-C): KEPT``; without
    ``kept``, what the command wrote (:func:`gearrotor.files.written` from index ``since``):
    nothing (outputs are written as a whole or not at all), or the files it had finished."""
    from ..files import written

    if kept is None:
        done = written()[since:]
        if not done:
            kept = "no file was written"
        else:
            names = ", ".join(str(p) for p in done[:3]) + (" ..." if len(done) > 3 else "")
            kept = f"the {len(done)} file(s) written before it are complete: {names}"
    return f"interrupted ({how}): {kept}"


@contextlib.contextmanager
def cli_errors(interrupted: Callable[[], str | None] | None = None):
    """Map errors to the exit statuses of the module docstring, printing one line on stderr.

    A decorator (``@cli_errors()``, keeping the signature Typer reads) or a context manager
    (``with cli_errors(): ...``). Other exceptions pass through with their traceback.

    Ctrl-C (``KeyboardInterrupt``) is one line and exit status 130 (:func:`interrupted_line`);
    ``interrupted`` returns what was kept when the command has more to say (a checkpoint to
    resume from), or None for the default (which files were written).
    """
    from ..files import written

    since = len(written())
    try:
        yield
    except KeyboardInterrupt:
        kept = interrupted() if interrupted is not None else None
        end_line = "\n" if sys.stderr.isatty() else ""  # after a progress bar's line
        typer.echo(end_line + interrupted_line(kept, since=since), err=True)
        raise typer.Exit(EXIT_INTERRUPTED) from None
    except SolverError as exc:
        typer.echo(f"solver error: {exc}", err=True)
        raise typer.Exit(EXIT_SOLVER) from None
    except (ModelError, ImportError, OSError) as exc:
        err = input_error(exc)
        if err is None:
            raise
        typer.echo(f"error: {err}", err=True)
        raise typer.Exit(EXIT_INPUT) from None


def _click_exceptions():
    # typer carries its own copy of click (typer._click) in recent versions; older ones use click
    try:
        from typer._click import exceptions
    except ImportError:  # pragma: no cover
        from click import exceptions
    return exceptions


def usage_message(exc: BaseException) -> str:
    """One line for a command-line parser error: ``--speed: <what is wrong>; see '... --help'``."""
    text = " ".join(exc.format_message().split())
    text = re.sub(r"^Invalid value for '?([^':]+?)'?: ", r"\1: ", text)
    ctx = getattr(exc, "ctx", None)
    if ctx is not None and getattr(ctx, "command_path", None):
        text += f" (see '{ctx.command_path} --help')"
    return text


@contextlib.contextmanager
def one_line_usage_errors():
    """Print a parser error as one line on stderr and exit with status 2 (the README's promise:
    errors are one line); ``--help`` passes through and a bare command prints its help (stdout,
    status 0)."""
    exc_types = _click_exceptions()
    no_args = getattr(exc_types, "NoArgsIsHelpError", ())
    try:
        yield
    except no_args as exc:  # a bare command: its help on stdout, exit 0 (click >= 8.2 made it
        typer.echo(exc.format_message())  # an error on stderr with status 2)
        raise typer.Exit(EXIT_OK) from None
    except exc_types.ClickException as exc:
        typer.echo(f"error: {usage_message(exc)}", err=True)
        raise typer.Exit(EXIT_INPUT) from None


class OneLineGroup(TyperGroup):
    """The ``gearrotor`` group: parser errors of the group and of every command below it (the
    ``study`` group's too) are one line (:func:`one_line_usage_errors`)."""

    def __init__(self, *args, **kwargs):
        from .options import show_units_in_help

        super().__init__(*args, **kwargs)
        show_units_in_help(self)

    def make_context(self, *args, **kwargs):
        with one_line_usage_errors():
            return super().make_context(*args, **kwargs)

    def invoke(self, ctx):
        with one_line_usage_errors():
            return super().invoke(ctx)
