"""Faults of the machine and the user's hand, issue 17 "Faults" and issue 14 item 11: output
locations are checked before anything runs; a full disk or a read-only file system is one
error line naming the file (exit 2) and leaves no file behind; ``study run`` killed with SIGKILL
leaves no worker alive, Ctrl-C is one line and exit 130, SIGTERM exit 143, and the next run
removes the temporaries a killed run left.

"Before anything runs" is shown by replacing the first step of the computation (reading the
model, assembling it, planning the study) by a function that fails the test if called.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
import uuid
from pathlib import Path

import pytest

from fault_helpers import (
    Program,
    alive,
    cpu_seconds,
    dead_pid,
    descendants,
    full_disk_at_fsync,
    invoke,
    is_forkserver,
    leftovers,
    must_not_run,
    one_line_exit_2,
    parent_of,
    run_program,
    run_signalled,
    skip_without_proc,
    start_program,
    thread_cpu_seconds,
    tmpfs,
    workers_of,
)

SINGLE = "unity_gearbox_single_shaft.toml"
UNITY = "unity_gearbox.toml"
BEARING = "bearings/pinion_3lobe_dam.toml"
MOTOR = "motor_gearbox_compressor.toml"
LOAD, ASSEMBLE = "gearrotor.io.load_model", "gearrotor.assembly.assemble"


#: (command line with OUT for the output, option, kind, the first step of the computation)
COMMANDS = [
    (["modal", SINGLE, "--plot", "OUT"], "--plot", "directory", LOAD),
    (["campbell", SINGLE, "--plot", "OUT"], "--plot", "figure", LOAD),
    (["unbalance", SINGLE, "--plot", "OUT"], "--plot", "directory", LOAD),
    (["floquet", UNITY, "--plot", "OUT"], "--plot", "figure", LOAD),
    (
        ["bearing", BEARING, "--plot", "OUT"],
        "--plot",
        "directory",
        "gearrotor.bearings.io.load_bearing",
    ),
    (["transient", UNITY, "--output", "OUT"], "--output", "file", LOAD),
    (["transient", UNITY, "--plot", "OUT"], "--plot", "directory", LOAD),
    (
        ["transient", UNITY, "--checkpoint", "OUT"],
        "--checkpoint",
        "file",
        LOAD,
    ),
    (["transient-plot", "IN.nc", "--output", "OUT"], "--output", "directory", None),
    (["static", SINGLE, "--plot", "OUT"], "--plot", "directory", ASSEMBLE),
    (["ucs", SINGLE, "--plot", "OUT"], "--plot", "figure", LOAD),
    (["stability", SINGLE, "--plot", "OUT"], "--plot", "figure", LOAD),
    (
        ["torsional", "modes", SINGLE, "--plot", "OUT"],
        "--plot",
        "directory",
        LOAD,
    ),
    (
        ["torsional", "transient", MOTOR, "--output", "OUT"],
        "--output",
        "file",
        LOAD,
    ),
    (["report", SINGLE, "--output", "OUT"], "--output", "directory", ASSEMBLE),
]


def _args(cmd, examples, out, tmp_path):
    def one(a):
        if a == "OUT":
            return out
        if a == "IN.nc":
            return tmp_path / "never_read.nc"
        return examples / a if a.endswith(".toml") else a

    return [one(a) for a in cmd]


def _bad_outputs(kind, tmp_path):
    """Paths that cannot receive an output of this kind, with a part of the expected message."""
    sfx = ".png" if kind == "figure" else ".nc"  # the suffixes the commands accept
    (tmp_path / "adir").mkdir(exist_ok=True)
    (tmp_path / f"adir{sfx}").mkdir(exist_ok=True)
    (tmp_path / "afile").write_text("")
    if kind == "file":
        return [
            (tmp_path / f"adir{sfx}", "existing folder"),
            (tmp_path / "missing" / f"x{sfx}", "does not exist"),
            (tmp_path / "afile" / f"x{sfx}", "is not a folder"),
        ]
    if kind == "figure":  # a file whose missing folders the figure function creates
        out = [
            (tmp_path / f"adir{sfx}", "existing folder"),
            (tmp_path / "afile" / "x.png", "not a folder"),
        ]
    else:
        out = [(tmp_path / "afile", "existing file"), (tmp_path / "afile" / "sub", "not a folder")]
    if Path("/proc/self").exists():  # root may write almost anywhere, not into /proc
        out.append(
            (Path("/proc/nope.png" if kind == "figure" else "/proc/nope"), "cannot write in /proc")
        )
    return out


@pytest.mark.parametrize(("cmd", "option", "kind", "first_step"), COMMANDS)
def test_output_location_checked_before_anything_runs(
    cmd, option, kind, first_step, examples, tmp_path, monkeypatch
):
    if first_step is not None:
        monkeypatch.setattr(first_step, must_not_run)
    for out, needle in _bad_outputs(kind, tmp_path):
        r = invoke(*_args(cmd, examples, out, tmp_path))
        one_line_exit_2(r, option, needle, str(out))


def test_modal_plot_into_proc_prints_no_table(examples):
    """Issue 14 item 11, as reported: the modal table was printed, then the command failed."""
    r = invoke("modal", examples / SINGLE, "--plot", "/proc/nope")
    one_line_exit_2(r, "--plot", "/proc/nope")


def test_transient_removes_the_temporaries_of_a_killed_run(examples, tmp_path, monkeypatch):
    from gearrotor.errors import ModelError

    def stop(*a, **k):
        raise ModelError("stopped after the output checks")

    monkeypatch.setattr(LOAD, stop)
    dead = dead_pid()
    planted = tmp_path / f"x.nc.tmp-{dead}-a1b2c3"
    unrelated = tmp_path / f"y.nc.tmp-{dead}"
    planted.write_bytes(b"partial")
    unrelated.write_bytes(b"not ours to remove")
    r = invoke("transient", examples / SINGLE, "--output", tmp_path / "x.nc")
    assert r.exit_code == 2 and "stopped after the output checks" in r.stderr
    assert not planted.exists() and unrelated.exists()


STUDY = """
name = "faults"
model = "{model}"
output = "{folder}"

[set]
"meshes[0].variation.terms" = 5

[parameters]
unbalance = {{ paths = ["unbalances[0].amount", "unbalances[1].amount"], unit = "g*mm" }}

[cases]
columns = ["unbalance"]
rows = {rows}

[analysis]
type = "transient"
t_end = "{t_end} s"

[outputs]
window = "0.05 s"
"""


def _study(tmp_path, examples, *, folder="faults.study", rows=(360, 720), t_end=0.1) -> Path:
    path = tmp_path / f"study-{uuid.uuid4().hex[:6]}.toml"
    path.write_text(
        STUDY.format(
            model=(examples / UNITY).as_posix(),
            folder=folder,
            rows=str([[r] for r in rows]),
            t_end=t_end,
        )
    )
    return path


def test_study_outputs_checked_before_anything_runs(examples, tmp_path, monkeypatch):
    monkeypatch.setattr("gearrotor.studies.execute.plan", must_not_run)
    # both names of collect (studies.plots binds it when imported: importing it here, under the
    # patch, left the patched one in it for every later test of the process)
    monkeypatch.setattr("gearrotor.studies.plots.collect", must_not_run)  # imports it first
    monkeypatch.setattr("gearrotor.studies.collection.collect", must_not_run)
    (tmp_path / "afile").write_text("")
    bad = _study(tmp_path, examples, folder=(tmp_path / "afile").as_posix())
    one_line_exit_2(invoke("study", "run", bad), "output", "existing file")
    one_line_exit_2(invoke("study", "report", bad), "output", "existing file")
    good = _study(tmp_path, examples)
    r = invoke("study", "report", good, "--output", tmp_path / "afile" / "x")
    one_line_exit_2(r, "--output", "is not a folder")


# ---- full disk, read-only file system (a small tmpfs where mounting is allowed) ------------------
def test_transient_output_on_a_full_disk(examples, tmp_path):
    """The result (~0.5 MB) does not fit a 64 kB file system: before the atomic writer, libhdf5
    crashed the process (SIGSEGV, exit 139) and left ``x.nc.tmp``."""
    with tmpfs(tmp_path, "64k") as mnt:
        out = mnt / "x.nc"
        r = invoke(
            "transient", examples / SINGLE, "--t-end", "0.05", "--output", out, "--no-progress"
        )
        assert r.exit_code == 2, (r.output, r.exception)
        assert r.stderr.strip() == f"error: no space left on device writing {out}"
        assert not out.exists() and leftovers(mnt) == []


def test_transient_output_on_a_read_only_file_system(examples, tmp_path, monkeypatch):
    monkeypatch.setattr(LOAD, must_not_run)
    with tmpfs(tmp_path, "64k", "ro") as mnt:
        r = invoke("transient", examples / SINGLE, "--output", mnt / "x.nc")
        one_line_exit_2(r, "--output", "read-only file system", str(mnt / "x.nc"))


def test_report_on_a_full_disk_names_the_report_file(examples, tmp_path, monkeypatch):
    """The report is built in a temporary folder: the error names the file in the report folder
    the user asked for, and nothing is left (the full disk is injected at the writer's fsync)."""
    import errno

    from gearrotor import files

    def full(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(files.os, "fsync", full)
    out = tmp_path / "rep"
    r = invoke("report", examples / SINGLE, "--output", out, "--analyses", "modal")
    assert r.exit_code == 2, (r.output, r.exception)
    assert re.fullmatch(rf"error: no space left on device writing {out}/\S+\.png", r.stderr.strip())
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("method", ["spawn", "forkserver"])
def test_stop_pool_returns_when_a_worker_dies_while_sending_its_result(method):
    """Stopping the local pool (a full disk, Ctrl-C) kills the running workers; one killed
    while it sent its result (a transient case's dataset is megabytes) left half a message in
    the result pipe, and the pool's manager thread, which holds the pipe's write end too, waited
    for the rest for ever: the study run below hung in a full suite run. The worker here returns
    64 MB; the kill comes as its first bytes reach the pipe."""
    import threading
    from concurrent.futures import ProcessPoolExecutor

    from gearrotor.studies.workers import start_method, stop_pool, worker_processes

    if method == "forkserver" and start_method() != "forkserver":
        pytest.skip("workers are spawned here: no fork server")
    with worker_processes(method) as (context, _):  # as the study's pool (forked or spawned)
        pool = ProcessPoolExecutor(1, mp_context=context)
        pool.submit(os.urandom, 64 << 20)
        reader = pool._result_queue._reader
        deadline = time.monotonic() + 60
        while not reader.poll(0.001):
            assert time.monotonic() < deadline, "the worker never sent its result"
        stopper = threading.Thread(target=stop_pool, args=(pool,), daemon=True)
        stopper.start()
        stopper.join(30)
        assert not stopper.is_alive(), "stop_pool hung on a half-sent result"


def test_study_run_on_a_full_disk(examples, tmp_path):
    """The case files (~100 kB each) fill a 128 kB file system: one line naming the case file,
    exit 2, no temporary left; the manifest written before is intact."""
    with tmpfs(tmp_path, "128k") as mnt:
        study = _study(mnt, examples, rows=(360, 720, 1080))
        r = invoke("study", "run", study, "--workers", "1", "--no-progress")
        assert r.exit_code == 2, (r.output, r.exception)
        line = r.stderr.strip()
        assert re.fullmatch(r"error: no space left on device writing \S+/cases/\w+\.nc", line), line
        assert leftovers(mnt) == []
        assert (mnt / "faults.study" / "study.json").stat().st_size > 0


def test_study_run_on_a_read_only_file_system(examples, tmp_path, monkeypatch):
    monkeypatch.setattr("gearrotor.studies.execute.plan", must_not_run)
    with tmpfs(tmp_path, "64k", "ro") as mnt:
        study = _study(tmp_path, examples, folder=(mnt / "s.study").as_posix())
        one_line_exit_2(invoke("study", "run", study), "output", "read-only file system")


# ---- signals -------------------------------------------------------------------------------------
#: CPU seconds a worker has spent once it is surely inside its case's integration loop (30-s
#: cases run for ~10 s of CPU): a forked worker imports nothing (its fork server did), and
#: ``run_case`` spends at most ~0.7 s before the loop (numba's cache loaded, measured cold;
#: 0.04 s warm); a spawned worker first imports the stack (~2 s, workers.PRELOAD); a Dask worker
#: runs the case in a thread of its own (counted alone), which imports the analyses (~1.3 s)
#: first. CPU time, not a wait in seconds: the same moment on an idle and on a loaded machine.
_IN_CASE = {"forked": 1.0, "spawned": 3.0, "dask": 2.5}


def _in_case(worker: int, dask: bool) -> bool:
    """``worker`` (a local worker, or a Dask worker process) is computing its case."""
    if dask:
        return max(thread_cpu_seconds(worker), default=0.0) >= _IN_CASE["dask"]
    kind = "forked" if is_forkserver(parent_of(worker)) else "spawned"
    return cpu_seconds(worker) >= _IN_CASE[kind]


#: ``python -m gearrotor``, for :func:`fault_helpers.start_program`
_PYTHON_M_GEARROTOR = (
    "import runpy; runpy.run_module('gearrotor', run_name='__main__', alter_sys=True)"
)


def _start_study(study: Path, *extra: str, until: str = "computing") -> Program:
    """``python -m gearrotor study run`` (forked by ``start_program``) in its own session (a
    terminal's Ctrl-C goes to the whole group: ``os.killpg``) with two workers, returned once
    both are computing their cases (``until="computing"``: see ``_in_case``), as soon as both
    exist (``"starting"``: still importing, or just forked), or (``"preloading"``) once its
    fork server runs and has forked no worker yet: it is still importing what the cases need.
    Polled, never a fixed wait."""
    dask = "--scheduler" in extra
    args = ["study", "run", study, "--workers", "2", *extra]
    proc = start_program(_PYTHON_M_GEARROTOR, *args, new_session=True)
    deadline = time.time() + 120
    while time.time() < deadline:
        assert proc.poll() is None, proc.communicate()
        if until == "preloading":
            if any(is_forkserver(c) for c in descendants(proc.pid)):
                assert not workers_of(proc.pid), "forked before this test could look"
                return proc
        else:  # two workers (spawned, or forked by the fork server)
            workers = [c for c in workers_of(proc.pid) if alive(c)]
            if len(workers) >= 2 and (
                until == "starting" or sum(_in_case(w, dask) for w in workers) >= 2
            ):
                return proc
        time.sleep(0.02)
    proc.kill()
    raise AssertionError(f"the workers did not reach {until!r}")


def _all_end(processes: list[int], what: str) -> None:
    """Every one of ``processes`` ends within 10 s (PR_SET_PDEATHSIG and the fork server's end
    are delivered asynchronously: allow the kernel a moment)."""
    deadline = time.time() + 10
    while any(alive(w) for w in processes) and time.time() < deadline:
        time.sleep(0.05)
    assert not [w for w in processes if alive(w)], f"{what} outlived the study"


def _forkserver_expected() -> bool:
    from gearrotor.studies.workers import start_method

    return start_method() == "forkserver"


@pytest.mark.slow
@skip_without_proc
@pytest.mark.parametrize("moment", ["computing", "preloading"])
def test_sigkill_of_study_run_leaves_no_worker(examples, tmp_path, moment):
    """SIGKILL of ``study run`` (the parent only, as the OOM killer would) while its workers
    compute, or while its fork server is still importing what the cases need: no worker and no
    fork server is left (the workers' parent is the fork server: it ends with the study, and
    they with it)."""
    if moment == "preloading" and not _forkserver_expected():
        pytest.skip("workers are spawned here: no fork server")
    study = _study(tmp_path, examples, rows=(360, 720, 1080, 1440), t_end=30.0)
    proc = _start_study(study, "--no-progress", until=moment)
    processes = descendants(proc.pid)
    assert any(is_forkserver(c) for c in processes) == _forkserver_expected(), processes
    proc.kill()
    proc.communicate(timeout=30)
    _all_end(processes, "workers or the fork server")
    # the next run in that folder removes the temporaries a killed run leaves (one is planted:
    # the kill above may or may not have hit a write); a 0.1-s case of the same folder does it
    # as well as a 30-s one
    cases = tmp_path / "faults.study" / "cases"
    cases.mkdir(parents=True, exist_ok=True)
    planted = cases / f"0123456789abcdef0123.nc.tmp-{proc.pid}-abcdef"
    planted.write_bytes(b"partial")
    short = _study(tmp_path, examples, rows=(360,), t_end=0.1)
    r = invoke("study", "run", short, "--no-progress")
    assert r.exit_code == 0, (r.output, r.exception)
    assert not planted.exists() and leftovers(tmp_path / "faults.study") == []


@pytest.mark.slow
@skip_without_proc
@pytest.mark.parametrize("moment", ["computing", "preloading"])
@pytest.mark.parametrize(
    ("sig", "code", "how"), [(signal.SIGINT, 130, "Ctrl-C"), (signal.SIGTERM, 143, "SIGTERM")]
)
def test_interrupted_study_run_is_one_line(examples, tmp_path, sig, code, how, moment):
    """The signal while the workers compute, or while the fork server still imports what the
    cases need: the run was starting its first worker then (waiting for the server). Before,
    a SIGTERM there stopped the run with that worker not yet in the pool: forked afterwards,
    it found the pool's queues gone and printed a traceback after the one line."""
    if moment == "preloading" and not _forkserver_expected():
        pytest.skip("workers are spawned here: no fork server")
    # 30 s cases (~10 s of CPU): still computing when the signal comes, which _start_study
    # sends ~1 s of CPU into them (2 s cases ended within the fixed 4-s wait it had before)
    study = _study(tmp_path, examples, rows=(360, 720, 1080, 1440), t_end=30.0)
    proc = _start_study(study, "--no-progress", until=moment)
    processes = descendants(proc.pid)  # the workers, their fork server, the resource tracker
    if sig == signal.SIGINT:
        os.killpg(proc.pid, sig)  # what a terminal does: the whole foreground group
    else:
        proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == code, err
    assert "Traceback" not in err, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"interrupted ({how})"), err
    assert "run the same command again to resume" in lines[0]
    _all_end(processes, "processes")
    assert leftovers(tmp_path / "faults.study") == []
    assert not list(tmp_path.glob("faults.study/cases/*.nc")), "a case ended: not while computing"


@pytest.mark.slow
@skip_without_proc
@pytest.mark.parametrize(
    ("backend", "until"),
    [("dask", "computing"), ("dask", "starting"), ("local", "starting")],
    ids=["dask-computing", "dask-starting", "local-starting"],
)
def test_ctrl_c_of_study_run_with_its_workers_starting_or_computing(
    examples, tmp_path, backend, until
):
    """Ctrl-C to ``study run --scheduler local`` (a Dask LocalCluster), and to the local pool
    while its workers start: one line, exit 130, no process left, no temporary. Before: the
    Dask nanny logged "Worker process still alive after 4.0 seconds, killing" for each busy
    worker (and took those 4 s); workers still importing printed a KeyboardInterrupt traceback
    each, and an interrupted cluster start an "Exception ignored in atexit callback". (The
    local pool's fork server still importing: test_interrupted_study_run_is_one_line.)"""
    if backend == "dask":
        pytest.importorskip("distributed", reason="the Dask backend is the [dask] extra")
    study = _study(tmp_path, examples, rows=(360, 720, 1080, 1440), t_end=30.0)
    extra = ("--scheduler", "local") if backend == "dask" else ()
    proc = _start_study(study, "--no-progress", *extra, until=until)
    processes = descendants(proc.pid)
    os.killpg(proc.pid, signal.SIGINT)  # a terminal's Ctrl-C: the whole foreground group
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("interrupted (Ctrl-C)"), err
    _all_end(processes, "processes")
    assert leftovers(tmp_path / "faults.study") == []


# ---- a signal at any moment of `study run`, also after its cases have finished ----------------
#: Runs the ``gearrotor`` program after arranging for the process to send itself ``SIG`` at
#: ``POINT``: reading the study file (before the study is known), writing ``results.nc`` (inside
#: the atomic writer, the temporary half written), printing the summary, or exiting (an atexit
#: callback, after the command has returned). A real signal, delivered where a user's Ctrl-C or
#: a scheduler's SIGTERM can land; only the moment is chosen.
_SIGNAL_AT = """
import atexit, os, signal, sys
point, sig = sys.argv[1], signal.Signals[sys.argv[2]]
del sys.argv[1:3]

def deliver():
    os.kill(os.getpid(), sig)

if point == "reading":
    from gearrotor.studies import spec
    read = spec.load_study
    def load_study(*a, **k):
        deliver()
        return read(*a, **k)
    spec.load_study = load_study
elif point == "writing":
    from gearrotor import files
    fsync = files.os.fsync
    def in_results(fd):
        if os.readlink(f"/proc/self/fd/{fd}").split("/")[-1].startswith("results.nc.tmp-"):
            deliver()
        fsync(fd)
    files.os.fsync = in_results
elif point == "printing":
    import typer
    echo = typer.echo
    def summary(message=None, *a, **k):
        if str(message).startswith("results:"):
            deliver()
        echo(message, *a, **k)
    typer.echo = summary

from gearrotor.cli import main
if point == "exiting":
    atexit.register(deliver)
main()
"""

MODAL_STUDY = """
name = "signals"
model = "{model}"
output = "signals.study"
[parameters]
k = {{ paths = ["bearings[0].k", "bearings[1].k"], unit = "N/m" }}
[cases]
columns = ["k"]
rows = [[1e7], [2e7]]
[analysis]
type = "modal"
n_modes = 4
"""


@pytest.fixture(scope="module")
def finished_study(examples, tmp_path_factory) -> Path:
    """A small modal study whose cases have all finished (the signals come after them)."""
    folder = tmp_path_factory.mktemp("signals")
    study = folder / "study.toml"
    study.write_text(MODAL_STUDY.format(model=(examples / SINGLE).as_posix()))
    r = invoke("study", "run", study, "--workers", "1", "--no-progress")
    assert r.exit_code == 0, (r.output, r.exception)
    return folder


@pytest.mark.slow
@skip_without_proc
@pytest.mark.parametrize("point", ["reading", "writing", "printing", "exiting"])
@pytest.mark.parametrize(
    ("sig", "code", "how"), [("SIGINT", 130, "Ctrl-C"), ("SIGTERM", 143, "SIGTERM")]
)
def test_signal_at_any_moment_of_study_run_is_one_line(
    finished_study, tmp_path, point, sig, code, how
):
    """Before, a signal outside the cases' execution got Python's default: no message (exit 130
    through Typer, or a silent SIGTERM death) or, while the process exited, "Exception ignored in
    atexit callback" with a traceback and exit status 0."""
    import shutil

    import xarray as xr

    shutil.copytree(finished_study, tmp_path, dirs_exist_ok=True)
    folder = tmp_path / "signals.study"
    (folder / "results.nc").unlink()
    r = run_program(
        _SIGNAL_AT, point, sig, "study", "run", tmp_path / "study.toml", "--workers", "1",
        "--no-progress", timeout=120,
    )  # fmt: skip
    assert r.returncode == code, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"interrupted ({how})"), r.stderr
    if point == "reading":
        assert "nothing was run" in lines[0] and r.stdout == ""
    else:
        assert f"stored in {folder}; run the same command again to resume" in lines[0]
    assert leftovers(tmp_path) == []  # the half-written results.nc was removed
    results = folder / "results.nc"
    assert results.exists() == (point in ("printing", "exiting")), r.stdout
    if results.exists():  # complete
        with xr.open_dataset(results, engine="h5netcdf") as ds:
            assert ds.sizes["case"] == 2 and list(ds["status"].values) == ["done", "done"]


# ---- the report's temporary folder ------------------------------------------------------------
#: ``gearrotor report`` that prints the path of its temporary folder, complete, just before it
#: is published, and is killed there (SIGKILL): the moment that leaves the most behind
_KILLED_REPORT = """
import os, signal
from gearrotor.plots.report import build

def publish(tmp, output):
    print(tmp, flush=True)
    os.kill(os.getpid(), signal.SIGKILL)

build.replace_directory = publish
from gearrotor.cli import main
main()
"""


@pytest.mark.slow
def test_report_killed_leaves_nothing_after_the_next_run(examples, tmp_path):
    """The report is built in a temporary folder next to the output; SIGKILL (or a power cut)
    leaves it. Its name carries the pid (it was a random ``mkdtemp`` name, never removed), and
    the next report into the same output removes those of dead processes, not a live one's."""
    out = tmp_path / "rep"
    args = ["report", str(examples / SINGLE), "--output", str(out), "--analyses", "modal"]
    r = run_program(_KILLED_REPORT, *args)
    assert r.returncode == -signal.SIGKILL, r.stderr
    tmp, err = Path(r.stdout.splitlines()[-1]), r.stderr
    assert tmp.parent == tmp_path and tmp.name.startswith(".rep.tmp-"), err
    assert (tmp / "report.html").exists()  # killed with the whole report in it
    live = tmp_path / f".rep.tmp-{os.getpid()}-abcdef"  # a report being built right now
    live.mkdir()
    r = invoke("report", examples / SINGLE, "--output", out, "--analyses", "modal")
    assert r.exit_code == 0, (r.output, r.exception)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["rep", live.name])
    assert (out / "report.html").exists()


# ---- numba's cache ----------------------------------------------------------------------------
_WHERE = (
    "import numba\n"
    "from gearrotor.analyses.transient import kernels\n"
    "from gearrotor.analyses.torsional import drive_laws\n"
    "print(numba.config.CACHE_DIR)\n"
    "print(kernels.rk4_modal._cache._cache_path)\n"
    "print(drive_laws.law_torque._cache._cache_path)\n"
)


@pytest.mark.parametrize("user_choice", [False, True])
def test_numba_cache_outside_the_package(tmp_path, user_choice):
    """numba would write its cache next to the sources, into the installed package; it goes to
    the user cache directory (XDG_CACHE_HOME on Linux) unless NUMBA_CACHE_DIR says otherwise.
    numba decides where a kernel's cache is when the kernel is decorated: the paths of two
    kernels are read, nothing is compiled."""
    import gearrotor

    environ = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    environ["XDG_CACHE_HOME"] = str(tmp_path / "xdg")
    environ["PYTHONPATH"] = str(Path(gearrotor.__file__).parents[1])
    expected = tmp_path / "xdg" / "gearrotor" / "numba"
    if user_choice:
        environ["NUMBA_CACHE_DIR"] = str(tmp_path / "mine")
        expected = tmp_path / "mine"
    r = subprocess.run([sys.executable, "-c", _WHERE], env=environ, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.split()
    if user_choice:
        assert lines[0] == str(expected)
    else:  # one folder per version of the kernel sources (analyses/jit.py)
        assert Path(lines[0]).parent == expected and Path(lines[0]).name.startswith("src-")
    package = Path(gearrotor.__file__).parent
    for cache in map(Path, lines[1:]):
        assert cache.is_relative_to(expected) and not cache.is_relative_to(package), cache


_COMPILE = (
    "import numpy as np\n"
    "from gearrotor.analyses.transient import kernels\n"
    "kernels._interp(0.5, np.arange(3.0), np.arange(3.0), 0, 3)\n"
    "s = kernels._interp.stats\n"
    "print(sum(s.cache_hits.values()), sum(s.cache_misses.values()))\n"
)


@pytest.mark.parametrize("user_choice", [False, True])
def test_numba_cache_shared_by_copies_of_the_same_sources(tmp_path, user_choice):
    """A second checkout (another path, other time stamps) of the same sources loads the kernels
    the first compiled instead of compiling them again (numba files a module's cache under a
    hash of its absolute path; analyses/jit.py files gearrotor's by their place in the
    package); a change to another kernel module (one that a kernel may inline) makes it compile
    again, in the default folder and in one NUMBA_CACHE_DIR names. One small kernel compiled."""
    import shutil

    import gearrotor

    environ = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    environ["XDG_CACHE_HOME"] = str(tmp_path / "xdg")
    if user_choice:
        environ["NUMBA_CACHE_DIR"] = str(tmp_path / "mine")
    trees = []
    for name in ("a", "b", "c"):
        shutil.copytree(
            Path(gearrotor.__file__).parent,
            tmp_path / name / "gearrotor",
            ignore=shutil.ignore_patterns("__pycache__"),
        )
        trees.append(tmp_path / name)
    with (trees[2] / "gearrotor" / "analyses" / "torsional" / "drive_laws.py").open("a") as f:
        f.write("# changed\n")

    def hits_misses(tree: Path) -> list[int]:
        env = {**environ, "PYTHONPATH": str(tree)}
        r = subprocess.run(
            [sys.executable, "-c", _COMPILE], env=env, capture_output=True, text=True, cwd=tree
        )
        assert r.returncode == 0, r.stderr
        return [int(v) for v in r.stdout.split()]

    assert hits_misses(trees[0]) == [0, 1]  # compiled
    assert hits_misses(trees[1]) == [1, 0]  # the same sources elsewhere: loaded
    assert hits_misses(trees[2]) == [0, 1]  # another module changed: compiled again


# ---- names used as file names ------------------------------------------------------------------
@pytest.mark.slow
def test_study_report_sanitises_probe_names(examples, tmp_path):
    """A probe named ``../../x`` wrote outside the report folder, ``x/y`` failed after the
    computation; both become plain file names inside it."""
    study = _study(tmp_path, examples, rows=(360,), t_end=0.1)
    text = study.read_text().replace(
        "[set]\n", '[set]\n"probes[0].name" = "../../x"\n"probes[1].name" = "x/y"\n'
    )
    study.write_text(text)
    r = invoke("study", "run", study, "--workers", "1", "--no-progress")
    assert r.exit_code == 0, (r.output, r.exception)
    out = tmp_path / "deep" / "er" / "report"
    r = invoke("study", "report", study, "--output", out)
    assert r.exit_code == 0, (r.output, r.exception)
    written = [Path(p) for p in r.stdout.split()]
    assert written and all(p.resolve().parent == out.resolve() for p in written), written
    names = {p.name for p in written}
    assert "spectra____x_00-00.png" in names and "spectra_x_y_00-00.png" in names, names
    assert not list((tmp_path / "deep").glob("x*")) and not (tmp_path / "x_00-00.png").exists()


def test_ctrl_c_of_transient_is_one_line(examples, tmp_path, monkeypatch):
    """Ctrl-C during the run (KeyboardInterrupt from the integration loop): one line, exit 130,
    naming the checkpoint the same command resumes from."""
    ck = tmp_path / "run.ck"

    def interrupted(*args, checkpoint=None, **kwargs):
        ck.write_bytes(b"state")  # the checkpoint a real run leaves
        raise KeyboardInterrupt

    monkeypatch.setattr("gearrotor.analyses.transient.transient", interrupted)
    r = invoke("transient", examples / SINGLE, "--checkpoint", ck, "--no-progress")
    assert r.exit_code == 130, (r.output, r.exception)
    assert r.stderr.strip() == (
        f"interrupted (Ctrl-C): the state is saved in {ck}; run the same command again to resume"
    )


# ---- issue 23: a command's outputs together or not at all ---------------------------------------
#: Two operating points of the small model whose names sanitise alike (``a/b``, ``a_b``).
OPERATING_POINTS = """
[[operating_points]]
name = "a/b"
forces = [ { shaft = "s1", node = 2, force = ["0 N", "-500 N", "0 N"] } ]

[[operating_points]]
name = "a_b"
forces = [ { shaft = "s1", node = 2, force = ["0 N", "-900 N", "0 N"] } ]
"""


@pytest.fixture
def small_ops(tmp_path) -> Path:
    from reliability.conftest import SMALL

    path = tmp_path / "small.toml"
    path.write_text(SMALL + OPERATING_POINTS)
    return path


#: (command with MODEL, OUT (a new folder), what it writes into OUT when it succeeds)
SETS = [
    (
        ["static", "MODEL", "--all", "--plot", "OUT"],
        ["bearing_loads.png", "static.json", "static_a_b-2.png", "static_a_b.png"],
    ),
    (
        ["stability", "MODEL", "--mcs", "3000", "--qa", "1e5", "--at", "s1:2"]
        + ["--plot", "OUT/x.png"],
        ["x.png", "x_level2.png", "x_screening.png"],
    ),
    (["modal", "MODEL", "--plot", "OUT"], ["modal.json", "modes_1.png", "modes_2.png"]),
    (["unbalance", "MODEL", "--plot", "OUT"], ["bode.png", "orbits_operating.png"]),
    (
        ["transient", "MODEL", "--t-end", "0.01", "--no-progress", "--plot", "OUT"],
        [f"transient_{n}.png" for n in ("orbits", "spectra", "speeds", "time", "whirl_power")],
    ),
]


@pytest.mark.parametrize(("cmd", "outputs"), SETS, ids=[c[0][0] for c in SETS])
def test_full_disk_leaves_none_of_a_commands_files(small_ops, tmp_path, monkeypatch, cmd, outputs):
    """Issue 23: a full disk at the second file left the first (``static --plot`` kept LC1-LC8
    without static.json, ``stability --plot`` only its first chart). The disk fills at the
    second file's fsync: one error line, and neither the folder nor a file nor a temporary."""
    out = tmp_path / "out"
    args = [small_ops if a == "MODEL" else a.replace("OUT", str(out)) for a in cmd]
    r = invoke(*args)  # the complete set first: what the faulty run must not leave a part of
    assert r.exit_code == 0, (r.output, r.exception)
    assert sorted(p.name for p in out.iterdir()) == outputs
    shutil.rmtree(out)
    full_disk_at_fsync(monkeypatch, after=1)
    r = invoke(*args)
    assert r.exit_code == 2, (r.output, r.exception)
    assert re.fullmatch(rf"error: no space left on device writing {out}/\S+", r.stderr.strip())
    assert not out.exists() and leftovers(tmp_path) == []


def test_static_plot_on_a_real_full_disk(small_ops, tmp_path):
    """The issue's case on a real file system: 120 kB hold the first figure (77 kB) only."""
    with tmpfs(tmp_path, "120k") as mnt:
        r = invoke("static", small_ops, "--all", "--plot", mnt / "figs")
        assert r.exit_code == 2, (r.output, r.exception)
        assert "no space left on device writing" in r.stderr
        assert list(mnt.iterdir()) == []


def test_static_plot_names_stay_distinct(small_ops, tmp_path):
    """Issue 23: operating points ``a/b`` and ``a_b`` both wrote ``static_a_b.png`` (one figure
    lost); the second gets an index, and static.json says which figure is whose."""
    r = invoke("static", small_ops, "--all", "--plot", tmp_path / "figs")
    assert r.exit_code == 0, (r.output, r.exception)
    import json

    saved = json.loads((tmp_path / "figs" / "static.json").read_text())["operating_points"]
    assert [(p["operating_point"], p["figure"]) for p in saved] == [
        ("a/b", "static_a_b.png"),
        ("a_b", "static_a_b-2.png"),
    ]


# ---- issue 23: SIGKILL while writing, then the next run -----------------------------------------
COMMIT = "gearrotor.files:_Set.commit"  # all files complete, none in place yet


@pytest.mark.slow
@pytest.mark.parametrize(
    ("cmd", "target"),
    [
        (["static", "MODEL", "--all", "--plot", "OUT"], COMMIT),
        (
            ["transient", "MODEL", "--t-end", "0.01", "--output", "OUT.nc"],
            "gearrotor.files:_Set.commit",
        ),
        (["modal", "MODEL", "--plot", "OUT"], "gearrotor.files:write_json"),
    ],
    ids=["static-plot", "transient-output", "modal-plot"],
)
def test_temporaries_of_a_killed_run_are_removed_by_the_next(small_ops, tmp_path, cmd, target):
    """Issue 23: SIGKILL while the files are written (here: when they are all complete, just
    before they are renamed into place, the moment that leaves the most) left full-size
    ``static_LC1.png.tmp-PID-TOKEN`` files no later run removed. The next run into the same
    output removes them (their process is gone), and completes."""
    out = tmp_path / "out"
    args = [
        small_ops if a == "MODEL" else a.replace("OUT", str(out)) for a in cmd
    ]  # fmt: skip
    r = run_signalled(target, "SIGKILL", *args)
    assert r.returncode == -signal.SIGKILL, r.stderr
    assert leftovers(tmp_path), "the kill left no temporary: the test proves nothing"
    r = invoke(*args)
    assert r.exit_code == 0, (r.output, r.exception)
    assert leftovers(tmp_path) == []


# ---- issue 23: the report folder is replaced as a whole ----------------------------------------
@pytest.fixture(scope="module")
def campbell_report(examples, tmp_path_factory) -> Path:
    """A report with a Campbell diagram, which the next report (modes only) does not have
    (made once; each test gets a copy: :func:`earlier_report`)."""
    out = tmp_path_factory.mktemp("report") / "rep"
    r = invoke(
        "report", examples / SINGLE, "--output", out, "--analyses", "modal,campbell",
        "--max-frequency", "30000",
    )  # fmt: skip
    assert r.exit_code == 0, (r.output, r.exception)
    assert (out / "campbell.png").exists()
    return out


@pytest.fixture
def earlier_report(campbell_report, tmp_path) -> Path:
    """A copy of :func:`campbell_report`, at ``tmp_path / "rep"``."""
    out = tmp_path / "rep"
    shutil.copytree(campbell_report, out)
    return out


@pytest.mark.slow
@pytest.mark.parametrize(
    ("target", "new"),
    [("gearrotor.files:_exchange", False), ("gearrotor.files:_remove_tree", True)],
    ids=["before-the-exchange", "after-the-exchange"],
)
def test_report_killed_while_replacing_is_old_or_new_never_mixed(
    examples, earlier_report, target, new
):
    """Issue 23: SIGKILL while a report replaced an existing one left new JSON and figures with
    the old ``report.html`` and a stale ``campbell.png`` that survived the next run. The folder
    is exchanged as a whole: killed before, the old report is intact; after, the new one is
    complete (no campbell.png); the old one's remains go with the next run."""
    out = earlier_report
    old = {p.name: p.read_bytes() for p in out.iterdir()}
    args = ["report", examples / SINGLE, "--output", out, "--analyses", "modal"]
    r = run_signalled(target, "SIGKILL", *args)
    assert r.returncode == -signal.SIGKILL, r.stderr
    now = {p.name: p.read_bytes() for p in out.iterdir()}
    if new:
        assert "campbell.png" not in now and "modes_1.png" in now
        assert json.loads(now["report.json"])["inputs"]["analyses"] == ["modal"]
    else:
        assert now == old
    r = invoke(*args)
    assert r.exit_code == 0, (r.output, r.exception)
    assert sorted(p.name for p in out.parent.iterdir()) == ["rep"]  # no temporary left
    assert "campbell.png" not in {p.name for p in out.iterdir()}


def test_report_refuses_a_folder_that_is_not_a_report(examples, tmp_path, monkeypatch):
    """Replacing a folder as a whole would take the user's files with it: refused before
    anything runs."""
    monkeypatch.setattr(ASSEMBLE, must_not_run)
    (tmp_path / "mine.txt").write_text("keep me")
    r = invoke("report", examples / SINGLE, "--output", tmp_path)
    one_line_exit_2(r, "--output", "not a gearrotor report", "mine.txt", str(tmp_path))
    assert (tmp_path / "mine.txt").read_text() == "keep me"


@pytest.mark.slow
def test_report_through_a_symbolic_link(examples, earlier_report, tmp_path):
    """Issue 23: a report output that is a symbolic link to a folder: followed (documented in
    docs/report.md): the folder it points to is replaced, the link stays; a link to a missing
    folder is refused."""
    link = tmp_path / "latest"
    link.symlink_to(earlier_report)
    r = invoke("report", examples / SINGLE, "--output", link, "--analyses", "modal")
    assert r.exit_code == 0, (r.output, r.exception)
    assert link.is_symlink() and link.resolve() == earlier_report
    assert "campbell.png" not in {p.name for p in earlier_report.iterdir()}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["latest", "rep"]
    dangling = tmp_path / "dangling"
    dangling.symlink_to(tmp_path / "gone")
    r = invoke("report", examples / SINGLE, "--output", dangling, "--analyses", "modal")
    one_line_exit_2(r, "--output", "symbolic link to a missing folder")


# ---- issue 23: Ctrl-C is one line on every command ---------------------------------------------
REPORT = ["report", "MODEL", "--output", "OUT", "--analyses", "modal"]


@pytest.mark.slow
@pytest.mark.parametrize(
    ("cmd", "target", "nth"),
    [
        (["static", "MODEL", "--all"], "gearrotor.analyses.static:static", 1),
        (["static", "MODEL", "--all", "--plot", "OUT"], "gearrotor.plots.figures:save_figure", 2),
        (REPORT, "gearrotor.plots.figures:save_figure", 1),
        (REPORT, "gearrotor.analyses:modal", 1),
    ],
    ids=["static-computing", "static-plotting", "report-writing", "report-computing"],
)
def test_ctrl_c_is_one_line(small_ops, tmp_path, cmd, target, nth):
    """Issue 23: Ctrl-C on ``report`` and ``static`` exited 130 with no message. A real SIGINT
    while computing or while writing: one line, exit 130, and no file (outputs are written as a
    whole or not at all)."""
    out = tmp_path / "out"
    args = [small_ops if a == "MODEL" else a.replace("OUT", str(out)) for a in cmd]
    r = run_signalled(target, "SIGINT", *args, nth=nth)
    assert r.returncode == 130, (r.returncode, r.stderr)
    assert r.stderr.splitlines() == ["interrupted (Ctrl-C): no file was written"], r.stderr
    assert not out.exists() and leftovers(tmp_path) == []


def _commands(group, prefix=()) -> list[tuple[str, ...]]:
    subs = getattr(group, "commands", None)
    if not subs:
        return [prefix]
    return [c for name, sub in subs.items() for c in _commands(sub, (*prefix, name))]


#: every command, with arguments that pass its option checks (ARGS: the command's own)
EVERY = {
    ("show",): [SINGLE],
    ("modal",): [SINGLE],
    ("campbell",): [SINGLE],
    ("unbalance",): [SINGLE],
    ("static",): [SINGLE],
    ("bearing",): [BEARING],
    ("seal",): ["seals/pump_wear_ring.toml", "--speed", "3000"],
    ("mesh",): ["gears/spur_50_50.toml"],
    ("mesh-response",): [UNITY],
    ("transient",): [SINGLE],
    ("transient-plot",): ["RESULT"],
    ("report",): [SINGLE, "--output", "OUT"],
    ("floquet",): [UNITY],
    ("ucs",): [SINGLE],
    ("stability",): [SINGLE, "--mcs", "3000"],
    ("import-ross",): ["ROSS", "--output", "OUT.toml"],
    ("export",): [SINGLE, "--output", "OUT.py"],
    ("study", "run"): ["STUDY"],
    ("study", "status"): ["STUDY"],
    ("study", "report"): ["STUDY"],
    ("torsional", "modes"): [MOTOR],
    ("torsional", "campbell"): [MOTOR],
    ("torsional", "response"): [MOTOR, "--torque", "x"],
    ("torsional", "transient"): [MOTOR],
}
#: long-running by design: stops on Ctrl-C with its own line ("view stopped")
SERVERS = {("view",)}


def test_every_command_is_listed():
    from typer.main import get_command

    from gearrotor.cli import app

    assert set(_commands(get_command(app))) == set(EVERY) | SERVERS


@pytest.mark.parametrize("command", sorted(EVERY), ids=" ".join)
def test_ctrl_c_on_every_command(examples, tmp_path, monkeypatch, command):
    """Issue 23: a general mechanism (``cli.errors.cli_errors``): Ctrl-C on any command while it
    reads its input (the first thing every command does) is one line and exit 130; before, only
    ``study run`` and ``transient`` said anything."""

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr("gearrotor.inputs.read_text", interrupted)  # models, studies, tables
    monkeypatch.setattr("gearrotor.analyses.transient.load_result", interrupted)  # NetCDF
    monkeypatch.setattr("gearrotor.interop.ross.import_ross", interrupted, raising=False)
    (tmp_path / "x.nc").write_bytes(b"")
    (tmp_path / "study.toml").write_text("")
    (tmp_path / "rotor.toml").write_text("")
    subst = {
        "OUT": tmp_path / "out",
        "OUT.toml": tmp_path / "out.toml",
        "OUT.py": tmp_path / "out.py",
        "RESULT": tmp_path / "x.nc",
        "STUDY": tmp_path / "study.toml",
        "ROSS": tmp_path / "rotor.toml",
    }
    args = [subst.get(a, examples / a if a.endswith(".toml") else a) for a in EVERY[command]]
    r = invoke(*command, *args)
    assert r.exit_code == 130, (r.exit_code, r.output, r.exception)
    assert r.stderr.startswith("interrupted (Ctrl-C)") and len(r.stderr.splitlines()) == 1
    assert "Traceback" not in r.output
