"""The one atomic writer and the output-location checks (gearrotor.files), issue 17 "Faults".

A write either replaces the destination with the whole new content or leaves the old file as it
was, removes its temporary and raises one ModelError that names the file; the full-disk case is
provoked on a real, tiny tmpfs where the machine lets us mount one (root in a container), and by
an injected ENOSPC otherwise. The last test reads ``src/`` with ``ast``: no module but
``files.py`` writes a file directly.
"""

from __future__ import annotations

import ast
import json
import os
from pathlib import Path

import numpy as np
import pytest

from fault_helpers import dead_pid, full_disk_at_fsync, leftovers, tmpfs
from gearrotor import files
from gearrotor.errors import ModelError

SRC = Path(__file__).resolve().parents[1] / "src" / "gearrotor"


# ---- the atomic writer ---------------------------------------------------------------------
def test_round_trips_leave_no_temporary(tmp_path):
    xr = pytest.importorskip("xarray")
    ds = xr.Dataset({"a": ("t", np.linspace(0.0, 1.0, 7))}, attrs={"title": "x"})
    files.write_text(tmp_path / "a.txt", "héllo\n")
    files.write_bytes(tmp_path / "b.bin", b"\x00\x01")
    files.write_json(tmp_path / "c.json", {"k": [1, 2.5]})
    files.write_netcdf(tmp_path / "d.nc", ds)
    files.write_npz(tmp_path / "e.npz", q=np.arange(3.0))
    assert (tmp_path / "a.txt").read_text(encoding="utf-8") == "héllo\n"
    assert (tmp_path / "b.bin").read_bytes() == b"\x00\x01"
    assert json.loads((tmp_path / "c.json").read_text()) == {"k": [1, 2.5]}
    with xr.open_dataset(tmp_path / "d.nc", engine="h5netcdf") as back:
        np.testing.assert_array_equal(back["a"].values, ds["a"].values)
    with np.load(tmp_path / "e.npz") as z:
        np.testing.assert_array_equal(z["q"], np.arange(3.0))
    assert leftovers(tmp_path) == []


def test_figure_is_a_png(tmp_path):
    pytest.importorskip("matplotlib")
    from matplotlib.figure import Figure

    fig = Figure()
    fig.add_subplot().plot([0, 1], [1, 0])
    files.save_figure(fig, tmp_path / "f.png", dpi=50)
    assert (tmp_path / "f.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert leftovers(tmp_path) == []


def test_failure_keeps_the_old_file_and_removes_the_temporary(tmp_path):
    target = tmp_path / "t.json"
    files.write_json(target, {"old": True})
    with pytest.raises(RuntimeError), files.atomic_file(target, "w") as fh:
        fh.write('{"new": ')
        raise RuntimeError("the producer failed half-way")
    assert json.loads(target.read_text()) == {"old": True}
    with pytest.raises(TypeError):  # not JSON: nothing is written at all
        files.write_json(target, {"x": object()})
    assert json.loads(target.read_text()) == {"old": True}
    assert leftovers(tmp_path) == []


def test_injected_enospc_is_one_error_naming_the_file(tmp_path, monkeypatch):
    """The same path as a real full disk (below), for machines where mount is not allowed."""

    full_disk_at_fsync(monkeypatch)
    target = tmp_path / "x.nc"
    with pytest.raises(ModelError) as ei:
        files.write_bytes(target, b"0" * 1000)
    assert str(ei.value) == f"no space left on device writing {target}"
    assert not target.exists() and leftovers(tmp_path) == []


def test_full_disk_netcdf_and_json(tmp_path):
    """A 256 kB tmpfs and a ~1.6 MB dataset: libhdf5 is never asked to write to the full disk
    (it crashed the process with SIGSEGV, exit 139, before this writer), so the write ends in one
    error naming the file, and no temporary is left."""
    xr = pytest.importorskip("xarray")
    ds = xr.Dataset({"q": (("t", "d"), np.random.default_rng(0).normal(size=(20000, 10)))})
    with tmpfs(tmp_path, "256k") as mnt:
        for target, write in (
            (mnt / "big.nc", lambda p: files.write_netcdf(p, ds)),
            (mnt / "big.json", lambda p: files.write_json(p, ds["q"].values.tolist())),
        ):
            with pytest.raises(ModelError, match=f"^no space left on device writing {target}$"):
                write(target)
            assert not target.exists()
            assert leftovers(mnt) == []


def test_read_only_mount(tmp_path):
    with tmpfs(tmp_path, "64k", "ro") as mnt:
        with pytest.raises(ModelError, match="read-only file system"):
            files.check_output(mnt / "x.nc", "file", field="--output")
        with pytest.raises(ModelError, match="read-only file system"):
            files.check_output(mnt / "plots" / "deeper", "directory", field="--plot")
        with pytest.raises(ModelError, match=f"read-only file system writing {mnt / 'x.txt'}"):
            files.write_text(mnt / "x.txt", "x")


# ---- output locations ----------------------------------------------------------------------
def test_check_output_file(tmp_path):
    assert files.check_output(tmp_path / "new.nc") == tmp_path / "new.nc"
    (tmp_path / "adir").mkdir()
    with pytest.raises(ModelError, match="--output: the output is an existing folder"):
        files.check_output(tmp_path / "adir", field="--output")
    with pytest.raises(ModelError, match="the folder .*missing does not exist"):
        files.check_output(tmp_path / "missing" / "x.nc", field="--output")
    (tmp_path / "afile").write_text("")
    with pytest.raises(ModelError, match="is not a folder"):
        files.check_output(tmp_path / "afile" / "x.nc")
    assert leftovers(tmp_path) == [] and not list(tmp_path.glob(".gearrotor-probe-*"))


def test_check_output_directory(tmp_path):
    files.check_output(tmp_path / "a" / "b" / "c", "directory")  # created later, with parents
    assert not (tmp_path / "a").exists()  # the check creates nothing
    (tmp_path / "afile").write_text("")
    with pytest.raises(ModelError, match="existing file, not a directory"):
        files.check_output(tmp_path / "afile", "directory", field="--plot")
    with pytest.raises(ModelError, match="is not a folder"):
        files.check_output(tmp_path / "afile" / "sub", "directory", field="--plot")


@pytest.mark.skipif(not Path("/proc/self").exists(), reason="needs Linux /proc")
def test_check_output_proc():
    """``/proc`` accepts ``os.access(W_OK)`` for root but no new file: only a real probe tells."""
    with pytest.raises(ModelError, match="--plot: cannot write in /proc"):
        files.check_output("/proc/nope", "directory", field="--plot")
    with pytest.raises(ModelError, match="cannot write in /proc"):
        files.check_output("/proc/nope.png", "file", field="--plot")


@pytest.mark.parametrize(
    ("name", "expected"),
    [("gear1_x", "gear1_x"), ("../../x", "___x"), ("x/y", "x_y"), ("..", "_"), ("", "_")],
)
def test_safe_name(name, expected):
    out = files.safe_name(name)
    assert out == expected
    assert "/" not in out and ".." not in out and not out.startswith(".")


def test_stale_temporaries_of_dead_processes_are_removed(tmp_path):
    dead = dead_pid()
    stale = tmp_path / f"abc.nc.tmp-{dead}"
    stale_token = tmp_path / f"abc.nc.tmp-{dead}-a1b2c3"
    mine = tmp_path / f"def.nc.tmp-{os.getpid()}"
    keep = tmp_path / "abc.nc"
    for p in (stale, stale_token, mine, keep):
        p.write_text("")
    other = tmp_path / f"other.nc.tmp-{dead}"
    other.write_text("")
    removed = files.remove_stale_temporaries(tmp_path, prefix="abc.nc.tmp-")
    assert sorted(removed) == sorted([stale, stale_token])
    assert other.exists()
    assert files.remove_stale_temporaries(tmp_path) == [other]
    assert mine.exists() and keep.exists()


def test_temporary_folders_of_dead_processes_are_removed(tmp_path):
    """An output folder built as a whole (the report) is built in ``.NAME.tmp-PID-TOKEN``; the
    folders of dead processes go with their content, only when folders are asked for."""
    stale = tmp_path / f".rep.tmp-{dead_pid()}-a1b2c3"
    (stale / "sub").mkdir(parents=True)
    (stale / "sub" / "report.html").write_text("partial")
    made = files.make_temporary_directory(tmp_path / "rep")
    prefix = files.temporary_directory_prefix(tmp_path / "rep")
    assert prefix == ".rep.tmp-" and made.parent == tmp_path
    assert made.name.startswith(f"{prefix}{os.getpid()}-")
    umask = os.umask(0)
    os.umask(umask)
    assert made.stat().st_mode & 0o777 == 0o777 & ~umask  # an ordinary folder, not mkdtemp's
    assert files.remove_stale_temporaries(tmp_path, prefix) == []
    assert files.remove_stale_temporaries(tmp_path, prefix, directories=True) == [stale]
    assert sorted(tmp_path.iterdir()) == [made]


# ---- no direct write anywhere else ----------------------------------------------------------
_WRITE_METHODS = {"write_text", "write_bytes", "savefig", "to_netcdf", "to_csv", "write_html"}
_MODULE_WRITERS = {("np", "save"), ("np", "savez"), ("np", "savez_compressed")}
_MODULE_WRITERS |= {("numpy", n) for _, n in list(_MODULE_WRITERS)}
_MODULE_WRITERS |= {("json", "dump"), ("pickle", "dump")}


def _write_mode(call: ast.Call, position: int) -> bool:
    mode = call.args[position] if len(call.args) > position else None
    for kw in call.keywords:
        if kw.arg == "mode":
            mode = kw.value
    if mode is None:
        return False
    if not isinstance(mode, ast.Constant):
        return True  # a computed mode: count it, the writer must be files.py
    return any(c in str(mode.value) for c in "wax+")


def _direct_writes(tree: ast.AST) -> list[tuple[int, str]]:
    found = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        f = node.func
        if isinstance(f, ast.Name) and f.id == "open" and _write_mode(node, 1):
            found.append((node.lineno, "open(..., write mode)"))
        elif isinstance(f, ast.Attribute):
            if f.attr in _WRITE_METHODS:
                found.append((node.lineno, f".{f.attr}()"))
            elif f.attr == "open" and _write_mode(node, 0):
                found.append((node.lineno, ".open(write mode)"))
            elif isinstance(f.value, ast.Name) and (f.value.id, f.attr) in _MODULE_WRITERS:
                found.append((node.lineno, f"{f.value.id}.{f.attr}()"))
    return found


def test_the_scan_finds_direct_writes():
    """The scan itself: each kind of direct write is found (so the test below can fail)."""
    code = (
        "open(p, 'w')\nopen(p, mode='ab')\np.open('w')\np.write_text(s)\nfig.savefig(p)\n"
        "ds.to_netcdf(p)\nnp.savez(fh, a=a)\njson.dump(d, fh)\nopen(p)\np.open()\n"
    )
    assert [line for line, _ in _direct_writes(ast.parse(code))] == list(range(1, 9))


def test_every_write_goes_through_files_py():
    offenders = []
    for path in sorted(SRC.rglob("*.py")):
        if path == SRC / "files.py":
            continue
        for line, what in _direct_writes(ast.parse(path.read_text(encoding="utf-8"))):
            offenders.append(f"{path.relative_to(SRC.parent)}:{line}: {what}")
    assert not offenders, "direct writes outside gearrotor/files.py:\n" + "\n".join(offenders)


# ---- a set of files: all or nothing (issue 23) ---------------------------------------------
def test_output_set_appears_together(tmp_path):
    """Inside the set nothing is in place; at its end every file is; the old files stay until
    then."""
    files.write_text(tmp_path / "b.txt", "old b")
    with files.output_set():
        files.write_text(tmp_path / "a.txt", "a")
        files.write_json(tmp_path / "b.txt", {"b": 1})
        assert not (tmp_path / "a.txt").exists()
        assert (tmp_path / "b.txt").read_text() == "old b"
        with files.output_set():  # a set inside a set joins it
            files.write_bytes(tmp_path / "c.bin", b"c")
        assert not (tmp_path / "c.bin").exists()
    assert (tmp_path / "a.txt").read_text() == "a" and (tmp_path / "c.bin").read_bytes() == b"c"
    assert json.loads((tmp_path / "b.txt").read_text()) == {"b": 1}
    assert leftovers(tmp_path) == []
    assert files.written()[-3:] == tuple(
        Path(os.path.abspath(p))
        for p in (tmp_path / "a.txt", tmp_path / "b.txt", tmp_path / "c.bin")
    )


@pytest.mark.parametrize("fault", ["enospc", "error", "ctrl-c"])
def test_output_set_failure_leaves_none_of_its_files(tmp_path, monkeypatch, fault):
    """Issue 23: a full disk at the third file left the first two (``static --plot`` kept LC1-LC8
    without static.json). Now the old files stay as they were, the new ones and their
    temporaries are gone, and so is a folder the set created."""
    files.write_text(tmp_path / "a.txt", "old a")
    out = tmp_path / "new" / "deeper"
    if fault == "enospc":
        full_disk_at_fsync(monkeypatch, after=2)
    exc = {"enospc": ModelError, "error": RuntimeError, "ctrl-c": KeyboardInterrupt}[fault]
    with pytest.raises(exc), files.output_set():
        files.make_directory(out)
        files.write_text(tmp_path / "a.txt", "new a")
        files.write_text(out / "b.txt", "b")
        files.write_text(out / "c.txt", "c")  # the disk is full here
        if fault == "error":
            raise RuntimeError("the producer failed after three files")
        if fault == "ctrl-c":
            raise KeyboardInterrupt
    assert (tmp_path / "a.txt").read_text() == "old a"
    assert not (tmp_path / "new").exists()
    assert leftovers(tmp_path) == []


def _interrupt_at_first_rename(tmp_path, monkeypatch) -> None:
    """Write a set of 5 files with a real SIGINT sent at the first rename: the interrupt must
    come after the last rename (all files there), not between two."""
    import signal

    real = files.os.replace
    sent = []

    def replace(src, dst):
        if not sent:
            sent.append(dst)
            os.kill(os.getpid(), signal.SIGINT)
        real(src, dst)

    monkeypatch.setattr(files.os, "replace", replace)
    with pytest.raises(KeyboardInterrupt), files.output_set():
        for k in range(5):
            files.write_text(tmp_path / f"{k}.txt", str(k))
    assert sent and sorted(p.name for p in tmp_path.iterdir()) == [f"{k}.txt" for k in range(5)]


def test_signal_during_commit_comes_after_it(tmp_path, monkeypatch):
    """SIGINT and SIGTERM are held back while the set is renamed into place."""
    _interrupt_at_first_rename(tmp_path, monkeypatch)


def test_signal_during_commit_with_other_threads_alive(tmp_path, monkeypatch):
    """The same with another thread alive (BLAS, numba and executor threads are): the kernel
    hands a process-directed SIGINT to a thread that does not block it, and Python raises it in
    the main thread at once; a per-thread signal mask let it through between two renames (CI,
    stop 29)."""
    import threading

    done = threading.Event()
    other = threading.Thread(target=done.wait, daemon=True)
    other.start()
    try:
        _interrupt_at_first_rename(tmp_path, monkeypatch)
    finally:
        done.set()
        other.join()


# ---- stale temporaries of every output (issue 23) ------------------------------------------
def test_check_output_removes_the_temporaries_killed_runs_left(tmp_path):
    """A run killed while writing (SIGKILL) leaves ``NAME.tmp-PID-TOKEN`` full-size files; the
    next run's output check removes those of dead processes: of its own file, in its output
    folder, and its own temporary folders, not a live process's and not files of other names."""
    dead, live = dead_pid(), os.getpid()
    plots = tmp_path / "plots"
    plots.mkdir()
    stale = [
        tmp_path / f"x.nc.tmp-{dead}-a1b2c3",
        plots / f"static_LC1.png.tmp-{dead}-0f0f0f",
        plots / f"static.json.tmp-{dead}-abcdef",
    ]
    kept = [
        tmp_path / f"y.nc.tmp-{dead}-a1b2c3",  # another output's: its own run removes it
        plots / f"static_LC2.png.tmp-{live}-a1b2c3",  # being written right now
        plots / f"notes.tmp-{dead}",  # not a name this package writes
        plots / "static_LC1.png",
    ]
    for p in stale + kept:
        p.write_bytes(b"partial")
    stale_dir = tmp_path / f".plots.tmp-{dead}-123abc"
    stale_dir.mkdir()
    (stale_dir / "report.html").write_text("partial")
    files.check_output(tmp_path / "x.nc", "file", field="--output")
    files.check_output(plots, "directory", field="--plot")
    assert not any(p.exists() for p in [*stale, stale_dir])
    assert all(p.exists() for p in kept)


# ---- names as file names -------------------------------------------------------------------
def test_unique_names():
    """Issue 23: operating points ``a/b`` and ``a_b`` both wrote ``static_a_b.png``."""
    names = ["a/b", "a_b", "a b", "A_B", "a/b", "a_b-2", "..", ""]
    out = files.unique_names(names)
    assert out == ["a_b", "a_b-2", "a_b-3", "A_B-4", "a_b", "a_b-2-2", "_", "_-2"]
    distinct = {}
    for name, f in zip(names, out, strict=True):
        assert distinct.setdefault(f.lower(), name) == name  # one file name, one name
        assert f == files.safe_name(f)


# ---- a folder replaced as a whole (issue 23) -----------------------------------------------
def _report_like(folder: Path, marker: str) -> None:
    folder.mkdir()
    (folder / "report.html").write_text(marker)
    (folder / f"only_{marker}.png").write_text(marker)


def test_replace_directory(tmp_path):
    out = tmp_path / "rep"
    first = files.make_temporary_directory(out)
    (first / "report.html").write_text("one")
    files.replace_directory(first, out)  # new: a rename
    assert (out / "report.html").read_text() == "one"
    second = files.make_temporary_directory(out)
    (second / "report.html").write_text("two")
    files.replace_directory(second, out)  # existing: exchanged, the old content removed
    assert sorted(p.name for p in out.iterdir()) == ["report.html"]
    assert (out / "report.html").read_text() == "two"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rep"]


def test_replace_directory_through_a_symbolic_link(tmp_path):
    """A link to a folder is followed: the folder it points to is replaced, the link stays (the
    temporary is built next to the target, on its file system)."""
    target = tmp_path / "disk" / "reports"
    target.parent.mkdir()
    _report_like(target, "old")
    link = tmp_path / "rep"
    link.symlink_to(target)
    tmp = files.make_temporary_directory(link)
    assert tmp.parent == target.parent
    (tmp / "report.html").write_text("new")
    files.replace_directory(tmp, link)
    assert link.is_symlink() and link.resolve() == target
    assert sorted(p.name for p in target.iterdir()) == ["report.html"]
    assert (target / "report.html").read_text() == "new"
    assert sorted(p.name for p in target.parent.iterdir()) == ["reports"]


def test_replace_directory_without_exchange(tmp_path, monkeypatch):
    """Where the system has no atomic exchange (not Linux, or a file system without it), two
    renames; the old folder goes under the temporary name first, so a kill in between leaves
    it for the next run to remove."""
    monkeypatch.setattr(files, "_exchange", lambda a, b: False)
    out = tmp_path / "rep"
    _report_like(out, "old")
    tmp = files.make_temporary_directory(out)
    (tmp / "report.html").write_text("new")
    files.replace_directory(tmp, out)
    assert sorted(p.name for p in out.iterdir()) == ["report.html"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rep"]


def test_written_counts_files_in_place_only(tmp_path):
    """What a command says it wrote when Ctrl-C stops it (cli_errors): the files in place, not
    those of a set or of a folder being built, which go if it stops."""
    n = len(files.written())
    with pytest.raises(KeyboardInterrupt), files.output_set():
        files.write_text(tmp_path / "a.txt", "a")
        raise KeyboardInterrupt
    tmp = files.make_temporary_directory(tmp_path / "rep")
    files.write_text(tmp / "report.html", "r")
    assert files.written()[n:] == ()
    files.replace_directory(tmp, tmp_path / "rep")
    assert files.written()[n:] == (tmp_path / "rep",)


def test_a_failed_write_releases_its_in_memory_file(tmp_path, monkeypatch):
    """The NetCDF and npz bytes are memoryviews of a BytesIO (xarray's ``to_netcdf()``,
    ``files._npz``); a write that fails (a full disk) releases them at once. Left to the garbage
    collector in the exception's reference cycle, a view could be collected after its BytesIO:
    Python 3.12 printed "SystemError: deallocated BytesIO object has exported buffers" and the
    process crashed (SIGSEGV) — tests/test_faults.py's transient on a full tmpfs, then any later
    collection (found running the fault tests on 3.12.1)."""
    import xarray as xr

    views = []
    real_npz, real_netcdf = files._npz, xr.Dataset.to_netcdf

    def npz(arrays):
        views.append(real_npz(arrays))
        return views[-1]

    def to_netcdf(self, *a, **kw):
        views.append(real_netcdf(self, *a, **kw))
        return views[-1]

    monkeypatch.setattr(files, "_npz", npz)
    monkeypatch.setattr(xr.Dataset, "to_netcdf", to_netcdf)
    full_disk_at_fsync(monkeypatch)
    with pytest.raises(ModelError, match="no space left"):
        files.write_npz(tmp_path / "a.npz", x=np.zeros(3))
    with pytest.raises(ModelError, match="no space left"):
        files.write_netcdf(tmp_path / "a.nc", xr.Dataset({"x": ("n", np.zeros(3))}))
    (tmp_path / "ro").mkdir()
    (tmp_path / "ro").chmod(0o500)
    try:
        written = files.write_cache_entry(tmp_path / "ro" / "a.npz", x=np.zeros(3))
    finally:
        (tmp_path / "ro").chmod(0o700)
    assert len(views) == 3 and all(isinstance(v, memoryview) for v in views)
    for v in views:
        with pytest.raises(ValueError, match="released"):
            v.tobytes()
    assert written is False or os.geteuid() == 0  # root writes in a read-only folder
