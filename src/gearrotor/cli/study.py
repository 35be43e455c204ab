"""``gearrotor study``: parametric studies (:mod:`gearrotor.studies`), a sub-application with
the commands ``gearrotor study run STUDY.toml [--scheduler ADDR|local] [--workers N]``,
``gearrotor study status STUDY.toml`` and ``gearrotor study report STUDY.toml [--output DIR]``.
Exit statuses are those of :mod:`.errors`: input errors print one message (file,
field, value, expectation) and exit with status 2; a run in which some cases failed exits with
status 1 after listing them (the failures are recorded per case, a solver failure of one case
does not stop the study).
"""

from __future__ import annotations

import signal
import sys
import time
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ModelError
from ..files import check_output
from .errors import (
    EXIT_CASES_FAILED,
    EXIT_CODES_HELP,
    EXIT_INTERRUPTED,
    EXIT_TERMINATED,
    cli_errors,
)

__all__ = ["EXIT_INTERRUPTED", "EXIT_TERMINATED", "study_app"]

#: Set by :func:`gearrotor.cli.main` (the ``gearrotor`` program): ``study run`` then answers
#: SIGINT and SIGTERM until the process exits (:class:`~gearrotor.studies.workers.StopSignals`);
#: called inside another program (a test runner's ``CliRunner``) it puts the handlers back.
as_program = False

study_app = typer.Typer(
    help="Parametric studies: a matrix of cases run in parallel (local processes or Dask).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    epilog=EXIT_CODES_HELP,
)

StudyArg = Annotated[Path, typer.Argument(help="study file (TOML)")]


def _parse_cases(text: str | None) -> list[int] | None:
    """``"0,3,5-7"`` → [0, 3, 5, 6, 7]."""
    if text is None:
        return None
    out: list[int] = []
    try:
        for part in text.split(","):
            part = part.strip()
            if "-" in part:
                a, b = part.split("-", 1)
                out.extend(range(int(a), int(b) + 1))
            elif part:
                out.append(int(part))
    except ValueError:
        raise ModelError(
            "cannot read the case list",
            field="--cases",
            value=text,
            expected="indices and ranges such as 0,3,5-7",
        ) from None
    return out


@study_app.command("run", epilog=EXIT_CODES_HELP)
@cli_errors()
def run_command(
    study: StudyArg,
    scheduler: Annotated[
        str | None,
        typer.Option(
            "--scheduler",
            help="Dask scheduler address (tcp://host:8786), or 'local' for a Dask "
            "LocalCluster; default: local processes",
        ),
    ] = None,
    workers: Annotated[
        int | None,
        typer.Option(
            "--workers",
            "-j",
            help="worker processes, local or Dask LocalCluster (default: the cores not busy with "
            "other processes, or --threads N); "
            "ignored with a remote scheduler",
        ),
    ] = None,
    cases: Annotated[
        str | None,
        typer.Option("--cases", help="run only these case indices, e.g. 0,3,5-7"),
    ] = None,
    retry_failed: Annotated[bool, typer.Option(help="run previously failed cases again")] = True,
    progress: Annotated[bool, typer.Option(help="progress bar on stderr")] = True,
) -> None:
    """Run the cases of a study that have not finished (resumes an interrupted study).
    Ctrl-C or SIGTERM stops it with one line (exit status 130 or 143), whenever it comes; its
    workers stop with it, also when it is killed; the finished cases are kept."""
    from ..studies.workers import StopSignals, Terminated

    folder: list[Path] = []  # the study's folder, once the study file is read

    def line(signum: int) -> str:
        how = "SIGTERM" if signum == signal.SIGTERM else "Ctrl-C"
        if not folder:
            return f"interrupted ({how}) while reading the study: nothing was run"
        return (
            f"interrupted ({how}): the finished cases are stored in {folder[0]}; run the same "
            "command again to resume"
        )

    stop = StopSignals(line).install()  # before anything else: the command's whole life
    try:
        _run(study, folder, scheduler, workers, cases, retry_failed, progress)
    except (KeyboardInterrupt, Terminated):
        signum = stop.received or signal.SIGINT  # KeyboardInterrupt raised by someone else
        typer.echo(
            ("\n" if sys.stderr.isatty() else "") + line(signum),  # end the progress bar's line
            err=True,
        )
        raise typer.Exit(
            EXIT_TERMINATED if signum == signal.SIGTERM else EXIT_INTERRUPTED
        ) from None
    finally:
        if as_program:  # keep answering until the process has exited
            stop.finish()
        else:
            stop.restore()


def _run(study, folder, scheduler, workers, cases, retry_failed, progress) -> None:
    from ..studies.execute import run_study
    from ..studies.spec import check_cases, load_study

    st = load_study(study)
    folder.append(st.folder)
    check_cases(st)  # every row's model is valid before anything runs (exit 2)
    summary = run_study(
        st,
        scheduler=scheduler,
        workers=workers,
        cases=_parse_cases(cases),
        retry_failed=retry_failed,
        progress=progress,
    )
    typer.echo(
        f"study {st.name}: {summary.n_cases} cases, {summary.n_runs} distinct runs, "
        f"{summary.executed} executed, {summary.skipped} already finished, "
        f"{len(summary.failed)} failed; {summary.wall_time_s:.1f} s on {summary.workers} "
        f"workers ({summary.backend})"
    )
    typer.echo(f"results: {st.folder / 'results.nc'}")
    if summary.failed:
        for i, err in summary.failed.items():
            typer.echo(f"case {i} failed: {err}", err=True)
    sys.stdout.flush()  # here, where a signal is still answered by unwinding
    if summary.failed:
        raise typer.Exit(EXIT_CASES_FAILED)


@study_app.command("status", epilog=EXIT_CODES_HELP)
@cli_errors()
def status_command(study: StudyArg) -> None:
    """List the cases of a study with their state (done, failed, pending)."""
    from ..studies.execute import study_status
    from ..studies.spec import load_study

    st = load_study(study)
    rows = study_status(st)
    counts = {s: sum(r.state == s for r in rows) for s in ("done", "failed", "pending")}
    typer.echo(
        f"study {st.name} ({st.folder}): {len(rows)} cases, {counts['done']} done, "
        f"{counts['failed']} failed, {counts['pending']} pending"
    )
    typer.echo(f"{'case':>4}  {'state':<8}{'key':<22}parameters")
    for r in rows:
        typer.echo(f"{r.index:>4}  {r.state:<8}{r.key:<22}{r.label}")
        if r.error:
            typer.echo(f"{'':>14}error: {r.error.splitlines()[0][:300]}")


@study_app.command("report", epilog=EXIT_CODES_HELP)
@cli_errors()
def report_command(
    study: StudyArg,
    output: Annotated[
        Path | None,
        typer.Option(
            "--output", "-o", help="directory for the PNGs (default: <study folder>/report)"
        ),
    ] = None,
    cases: Annotated[
        str | None, typer.Option("--cases", help="overlay only these cases, e.g. 0-3,7")
    ] = None,
    probes: Annotated[
        str | None,
        typer.Option("--probes", help="spectra of these probes only, e.g. gear1_x,gear2_x"),
    ] = None,
    per_figure: Annotated[int, typer.Option("--per-figure", help="cases per overlay figure")] = 7,
) -> None:
    """Overlay spectra (1x, 2x, mesh-frequency zooms) and trend plots of a study, as PNG."""
    from ..studies.cases import plan
    from ..studies.collection import collect
    from ..studies.plots import report
    from ..studies.spec import load_study

    st = load_study(study)
    check_output(st.folder, "directory", field="output")
    if output is not None:
        check_output(output, "directory", field="--output")
    if per_figure < 1:
        raise ModelError(
            "cases per figure must be positive",
            field="--per-figure",
            value=per_figure,
            expected="an integer >= 1",
        )
    t0 = time.perf_counter()

    def progress(text: str) -> None:  # the report takes a minute: say what it does (stderr)
        typer.echo(f"[{time.perf_counter() - t0:5.1f} s] {text}", err=True)

    progress(f"collecting the results of {st.name!r}")
    planned = plan(st)
    collected = collect(st, planned=planned)  # also writes results.nc when it is not up to date
    paths = report(
        st,
        output,
        cases=_parse_cases(cases),
        probes=None if probes is None else [p.strip() for p in probes.split(",")],
        per_figure=per_figure,
        progress=progress,
        results=collected,
        planned=planned,
    )
    for p in paths:
        typer.echo(str(p))
