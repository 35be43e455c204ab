"""The command line's click command, built once per test process.

typer builds a click command from the app's functions (their signatures and type hints: the
options of about 30 commands) on every ``app(...)`` call and every ``CliRunner().invoke(app,
...)``: ~30-40 ms a call, ~40 s of CPU over the suite's ~1,000 invocations (py-spy over the
whole suite). A program calls the command line once; the suite calls it a thousand times in the
same processes (pytest workers, the fork server of :mod:`doc_examples`), so it keeps each app's
command (by app object; a new ``typer.Typer()`` is built anew). Imported for its effect by
``conftest.py`` and by the fork server (``doc_examples._PRELOAD``).
"""

from __future__ import annotations

import sys
import weakref

import typer.main
import typer.testing


def install() -> None:
    """Make ``typer.main.get_command`` (used by ``Typer.__call__`` and typer's ``CliRunner``)
    return the command it built before for the same app."""
    if getattr(typer.main.get_command, "cached_per_app", False):
        return
    build = typer.main.get_command
    built: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()

    def get_command(typer_instance):
        try:
            return built[typer_instance]
        except KeyError:
            command = built[typer_instance] = build(typer_instance)
            return command

    get_command.cached_per_app = True
    typer.main.get_command = get_command
    typer.testing._get_command = get_command


install()
if "gearrotor.cli" in sys.modules:  # the fork server, after the package: build it before forking
    typer.main.get_command(sys.modules["gearrotor.cli"].app)
