"""Every file gearrotor writes goes through here: one atomic writer, and the checks of output
locations made before anything runs.

Atomic write: the content goes to a temporary file in the destination's directory
(``NAME.tmp-PID-TOKEN``), is flushed and ``fsync``-ed, then renamed over the destination with
``os.replace``. A reader sees the old file or the new one, never a part. On any failure (disk
full, read-only file system, permission, an exception while the content is produced) the
temporary is removed and one :class:`~gearrotor.errors.ModelError` names the file and the reason,
e.g. ``no space left on device writing results/x.nc``.

NetCDF is produced in memory first (xarray's ``to_netcdf()`` without a path) and written as
bytes: libhdf5 cannot recover from a full disk (it crashes the process), so it never writes to
a file here. Checkpoints (``.npz``) likewise.

Output locations (:func:`check_output`) are checked by actually creating and removing a probe
file or folder in the directory that will receive the output (``os.access`` says nothing
useful for root, on read-only mounts or in ``/proc``).

A command that writes several files writes them as one set (:func:`output_set`): every file of
the set is written to its temporary and synced first, and only when all are complete are they
renamed into place, one after the other within microseconds, with SIGINT and SIGTERM held back
meanwhile. A full disk, an error or Ctrl-C while the set is produced leaves none of its files
(the older ones, if any, stay as they were).

Temporaries of a process that was killed (SIGKILL, power cut) stay behind; their names carry
the pid, and :func:`remove_stale_temporaries` removes those whose process is gone. Every output
location checked by :func:`check_output` is cleaned of them: an output file of its own
(``NAME.tmp-PID-TOKEN``), an output folder of those of its files and of its own temporary
folder. An output folder built as a whole (the HTML report) is built in a temporary folder
named the same way (:func:`make_temporary_directory`, ``.NAME.tmp-PID-TOKEN`` next to it) and
then exchanged with the old folder in one step (:func:`replace_directory`).

Names of things (operating points, probes, shafts) become file-name components through
:func:`safe_name`; :func:`unique_names` keeps distinct names distinct after sanitising.
"""

from __future__ import annotations

import contextlib
import contextvars
import errno
import io
import json
import os
import re
import secrets
import shutil
import signal
import sys
import tempfile
import threading
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import IO, Any

from .errors import ModelError

__all__ = [
    "atomic_file",
    "check_output",
    "make_directory",
    "make_temporary_directory",
    "output_set",
    "remove_stale_temporaries",
    "replace_directory",
    "safe_name",
    "save_figure",
    "temporary_directory_prefix",
    "unique_names",
    "written",
    "write_bytes",
    "write_json",
    "write_netcdf",
    "write_npz",
    "write_text",
]

_TMP = re.compile(r"\.tmp-(\d+)(-[0-9a-f]{6})?$")

_REASONS = {
    errno.ENOSPC: "no space left on device",
    errno.EDQUOT: "disk quota exceeded",
    errno.EROFS: "read-only file system",
    errno.EACCES: "permission denied",
    errno.EPERM: "operation not permitted",
    errno.ENOENT: "the folder does not exist",
    errno.ENOTDIR: "a part of the path is not a folder",
    errno.EISDIR: "it is an existing folder",
    errno.ENAMETOOLONG: "the file name is too long",
}


def _reason(exc: OSError) -> str:
    if exc.errno in _REASONS:
        return _REASONS[exc.errno]
    return exc.strerror or str(exc) or type(exc).__name__


def _write_error(path: Path, exc: OSError) -> ModelError:
    return ModelError(f"{_reason(exc)} writing {path}")


def _temporary(path: Path) -> Path:
    return path.with_name(f"{path.name}.tmp-{os.getpid()}-{secrets.token_hex(3)}")


#: Every file this process has put in place, in order (:func:`written`).
_WRITTEN: list[Path] = []
#: Folders being built (:func:`make_temporary_directory`): what is written in them is not in
#: place until the folder is (:func:`replace_directory`).
_BUILDING: set[Path] = set()


def _record(path: Path) -> None:
    path = Path(os.path.abspath(path))
    if not any(p in _BUILDING for p in path.parents):
        _WRITTEN.append(path)


def written() -> tuple[Path, ...]:
    """The files this process has written so far, in order (a command's interruption message
    says which of them it wrote: :func:`gearrotor.cli.errors.cli_errors`)."""
    return tuple(_WRITTEN)


class _Set:
    """The files of an :func:`output_set`: destination → its complete, synced temporary."""

    def __init__(self) -> None:
        self.staged: dict[Path, Path] = {}
        self.folders: list[Path] = []  # created for the set (make_directory): removed with it

    def stage(self, tmp: Path, path: Path) -> None:
        key = Path(os.path.abspath(path))
        old = self.staged.pop(key, None)
        if old is not None:  # written twice in the set: the last content counts
            _discard(old)
        self.staged[key] = tmp

    def discard(self) -> None:
        for tmp in self.staged.values():
            _discard(tmp)
        self.staged.clear()
        for folder in reversed(self.folders):  # innermost first; only if still empty
            with contextlib.suppress(OSError):
                folder.rmdir()

    def commit(self) -> None:
        items = list(self.staged.items())
        self.staged.clear()
        with _signals_held():
            for k, (path, tmp) in enumerate(items):
                try:
                    os.replace(tmp, path)
                except OSError as exc:
                    for _, rest in items[k:]:
                        _discard(rest)
                    raise _write_error(path, exc) from None
                _record(path)


_SET: contextvars.ContextVar[_Set | None] = contextvars.ContextVar("output_set", default=None)


@contextlib.contextmanager
def _signals_held() -> Iterator[None]:
    """SIGINT and SIGTERM held back while the block runs and delivered when it ends.

    Python runs its signal handlers in the main thread whichever thread the kernel hands the
    signal to (BLAS, numba and executor threads do not block it), so the handlers themselves
    are swapped for ones that only note the signal: a per-thread signal mask would let a
    process-directed signal through another thread."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    pending: list[int] = []
    held = {}
    for sig in (signal.SIGINT, signal.SIGTERM):
        handler = signal.getsignal(sig)
        if handler is not None:  # None: installed outside Python, left alone
            held[sig] = signal.signal(sig, lambda signum, _frame: pending.append(signum))
    try:
        yield
    finally:
        for sig, handler in held.items():
            signal.signal(sig, handler)
        if pending:
            signal.raise_signal(pending[0])


@contextlib.contextmanager
def output_set() -> Iterator[None]:
    """The files written (through this module) within the block appear together or not at all:
    each is written to its temporary and synced as usual, but renamed into place only when the
    block ends normally, all of them at once (SIGINT and SIGTERM held back during the renames).
    An exception (a full disk, an error, Ctrl-C) removes every temporary of the set and leaves
    the destinations as they were. A set inside a set joins the outer one.

    Use it around the part of a command that writes its outputs (figures, JSON, NetCDF), not
    around files that must be stored as they come (a study's cases, checkpoints)."""
    if _SET.get() is not None:
        yield
        return
    current = _Set()
    token = _SET.set(current)
    try:
        yield
    except BaseException:
        current.discard()
        raise
    finally:
        _SET.reset(token)
    current.commit()


@contextlib.contextmanager
def atomic_file(path: str | os.PathLike, mode: str = "wb", **open_kw) -> Iterator[IO[Any]]:
    """Open a temporary file next to ``path`` for writing; on a normal exit it is flushed,
    ``fsync``-ed and renamed to ``path`` (within an :func:`output_set`, when the set ends). On
    any exception the temporary is removed; an ``OSError`` becomes a :class:`ModelError`
    naming ``path`` (others pass through)."""
    if mode not in ("w", "wb"):
        raise ValueError(f"atomic_file writes only: mode 'w' or 'wb', not {mode!r}")
    path = Path(path)
    tmp = _temporary(path)
    staging = _SET.get()
    try:
        with open(tmp, mode, **open_kw) as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        if staging is not None:
            staging.stage(tmp, path)
            return
        os.replace(tmp, path)
        _record(path)
    except OSError as exc:
        _discard(tmp)
        raise _write_error(path, exc) from None
    except BaseException:
        _discard(tmp)
        raise


def _discard(tmp: Path) -> None:
    with contextlib.suppress(OSError):
        tmp.unlink()


def write_bytes(path: str | os.PathLike, data: bytes | bytearray | memoryview) -> Path:
    """Write ``data`` to ``path`` atomically. Returns the path."""
    with atomic_file(path, "wb") as fh:
        fh.write(data)
    return Path(path)


def write_text(path: str | os.PathLike, text: str, *, newline: str | None = None) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically. Returns the path."""
    with atomic_file(path, "w", encoding="utf-8", newline=newline) as fh:
        fh.write(text)
    return Path(path)


def write_json(path: str | os.PathLike, obj: Any, *, indent: int | None = 1, **dumps_kw) -> Path:
    """``json.dumps(obj)`` to ``path`` atomically (serialised first: a value JSON cannot hold
    raises before the file is touched)."""
    return write_text(path, json.dumps(obj, indent=indent, **dumps_kw) + "\n")


def save_figure(fig, path: str | os.PathLike, **savefig_kw) -> Path:
    """``fig.savefig`` (a matplotlib Figure) to ``path`` atomically; the format follows the
    suffix of ``path`` (PNG by default)."""
    path = Path(path)
    savefig_kw.setdefault("format", path.suffix.lstrip(".").lower() or "png")
    return write_bytes(path, figure_bytes(fig, **savefig_kw))


def figure_bytes(fig, **savefig_kw) -> bytes:
    """The file :func:`save_figure` writes, in memory (``format`` PNG by default)."""
    savefig_kw.setdefault("format", "png")
    if savefig_kw["format"] == "png":
        # zlib level 3 instead of Pillow's 6: 13 % less time for an 8-mode page of the report
        # (0.45 -> 0.39 s), 9 % larger file (the same pixels)
        savefig_kw.setdefault("pil_kwargs", {"compress_level": 3})
    buf = io.BytesIO()
    with _laid_out(fig, savefig_kw) as kw:
        fig.savefig(buf, **kw)
    return buf.getvalue()


#: the savefig keywords :func:`_laid_out` handles (any other: matplotlib's own path)
_ONE_PASS_KW = frozenset({"format", "dpi", "bbox_inches", "pil_kwargs", "metadata"})


@contextlib.contextmanager
def _laid_out(fig, savefig_kw: dict):
    """``savefig_kw`` for a PNG save of ``fig`` that draws the figure once: matplotlib's
    ``savefig`` first draws a figure that has a layout engine (a constrained layout; also the
    placeholder ``tight_layout()`` leaves behind) or is cropped (``bbox_inches="tight"``) with
    drawing switched off, a full pass over every artist, to lay it out, then draws it again.
    Here the engine runs and the crop is measured at the save's dpi on the canvas the save
    draws with (what that pass did), and the figure is saved with no engine and the crop
    given: the same PNG, byte for byte (tests/plots/test_save_once.py), without that pass
    (0.1-0.2 s of a figure's 0.3-0.7 s)."""
    import matplotlib
    from matplotlib.backend_bases import get_registered_canvas_class
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.layout_engine import PlaceHolderLayoutEngine

    engine = fig.get_layout_engine()
    bbox = savefig_kw.get("bbox_inches")
    rc = matplotlib.rcParams
    canvas = fig.canvas
    if (
        savefig_kw.get("format") != "png"
        or not set(savefig_kw) <= _ONE_PASS_KW
        or not isinstance(savefig_kw.get("dpi"), int | float)
        or (engine is None and bbox != "tight")
        or bbox not in (None, "tight")
        or rc["figure.autolayout"]  # (then set_layout_engine(None) would set one)
        or rc["figure.constrained_layout.use"]
        or not (  # the save draws with Agg (a canvas without print_png switches to Agg); a
            # GUI canvas (an Agg subclass) would resize its window with the dpi: savefig's way
            type(canvas) is FigureCanvasAgg
            or (
                not hasattr(canvas, "print_png")
                and get_registered_canvas_class("png") is FigureCanvasAgg
            )
        )
        or getattr(canvas, "device_pixel_ratio", 1) != 1
    ):
        yield savefig_kw
        return
    agg = canvas if type(canvas) is FigureCanvasAgg else FigureCanvasAgg(fig)
    kw = dict(savefig_kw)
    try:
        dpi0 = fig.dpi
        fig.dpi = kw["dpi"]
        try:
            renderer = agg.get_renderer()
            run = fig.axes and not isinstance(engine, PlaceHolderLayoutEngine | None)
            if run:  # as Figure.draw runs it
                with contextlib.suppress(ValueError):
                    engine.execute(fig)
            if bbox == "tight":
                kw["bbox_inches"] = fig.get_tightbbox(renderer).padded(rc["savefig.pad_inches"])
        finally:
            fig.dpi = dpi0
        fig.set_layout_engine(None)
        yield kw
    finally:
        if engine is not None:
            fig.set_layout_engine(engine)
        fig.canvas = canvas


def write_netcdf(path: str | os.PathLike, dataset, *, engine: str = "h5netcdf") -> Path:
    """An xarray Dataset as NetCDF-4 to ``path`` atomically, produced in memory first (libhdf5
    does not survive a full disk)."""
    with contextlib.ExitStack() as stack:
        if "dask" in sys.modules:  # under a distributed Client, xarray would ask it for a lock
            import dask  # named after the BytesIO (it fails); the dataset is in memory here

            stack.enter_context(dask.config.set(scheduler="synchronous"))
        data = dataset.to_netcdf(engine=engine)
    with _released(data):
        return write_bytes(path, data)


@contextlib.contextmanager
def _released(data) -> Iterator[None]:
    """Release ``data`` when it is a memoryview (of a ``BytesIO``: what xarray's ``to_netcdf()``
    and :func:`_npz` return) once the block ends, also when it raises. A view left to the
    garbage collector in the reference cycle of an exception's traceback (a full disk) could be
    collected after its ``BytesIO``: Python 3.12 then printed "SystemError: deallocated BytesIO
    object has exported buffers" and crashed the process (SIGSEGV)."""
    try:
        yield
    finally:
        if isinstance(data, memoryview):
            data.release()


def _npz(arrays) -> memoryview:
    """``numpy.savez`` of ``arrays``, in memory."""
    import numpy as np

    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getbuffer()


def write_npz(path: str | os.PathLike, **arrays) -> Path:
    """``numpy.savez`` of ``arrays`` to ``path`` atomically (produced in memory first)."""
    data = _npz(arrays)
    with _released(data):
        return write_bytes(path, data)


def write_cache_entry(path: str | os.PathLike, **arrays) -> bool:
    """A cache entry (:mod:`gearrotor.cache`): ``numpy.savez`` of ``arrays`` put in place with
    one rename, at once (outside any :func:`output_set`: a cache entry is not one of a command's
    outputs, nor listed by :func:`written`), not synced (a damaged entry is solved again).
    Removes the temporaries killed writers left in its folder first. Returns False, having
    written nothing, when the folder cannot be written (an ``OSError``)."""
    path = Path(path)
    data = _npz(arrays)
    tmp = _temporary(path)
    try:
        remove_stale_temporaries(path.parent, token=True)
        with open(tmp, "wb") as fh:
            fh.write(data)
        os.replace(tmp, path)
    except OSError:
        _discard(tmp)
        return False
    except BaseException:
        _discard(tmp)
        raise
    finally:
        data.release()
    return True


@contextlib.contextmanager
def locked(path: str | os.PathLike) -> Iterator[None]:
    """An exclusive ``fcntl.flock`` on ``path`` (created empty if needed) while the block runs;
    no lock where ``fcntl`` does not exist. An ``OSError`` opening the file propagates."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - Windows
        yield
        return
    with open(path, "a") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


# ---- output locations ----------------------------------------------------------------------
def _probe(directory: Path, field: str | None, value: Path, expected: str) -> None:
    """Create and remove a file in ``directory``: the only reliable test that it can be written."""
    try:
        fd, name = tempfile.mkstemp(prefix=".gearrotor-probe-", dir=directory)
    except OSError as exc:
        raise ModelError(
            f"cannot write in {directory}: {_reason(exc)}",
            field=field,
            value=str(value),
            expected=expected,
        ) from None
    os.close(fd)
    _discard(Path(name))


def _writable_ancestor(folder: Path, field: str | None, value: Path, expected: str) -> None:
    """The nearest existing folder on the way to ``folder`` (which mkdir -p would create) is a
    folder and can be written."""
    anc = folder
    while not anc.exists() and anc != anc.parent:
        if anc.is_symlink():  # a dangling link: mkdir would fail on it
            break
        anc = anc.parent
    if not anc.is_dir():
        raise ModelError(f"{anc} is not a folder", field=field, value=str(value), expected=expected)
    _probe(anc, field, value, expected)


def check_output(
    path: str | os.PathLike, kind: str = "file", *, field: str | None = None, parents: bool = False
) -> Path:
    """Check, before anything runs, that ``path`` can receive an output; raise a
    :class:`ModelError` naming ``field`` and the path otherwise. Returns ``Path(path)``.

    kind ``"file"``: ``path`` is not an existing folder, its folder exists and can be written;
    with ``parents`` (a figure, whose folders the plotting function creates) its folder may
    also be missing, as long as it can be created.
    kind ``"directory"``: ``path`` is a folder or does not exist yet (it will be created with
    its missing parents), and the nearest existing folder on the way can be written.
    """
    path = Path(path)
    if kind == "file" and parents:
        expected = "a file path in a writable location"
        if path.is_dir():
            raise ModelError(
                "the output is an existing folder", field=field, value=str(path), expected=expected
            )
        _writable_ancestor(path.parent, field, path, expected)
    elif kind == "file":
        expected = "a file path in an existing, writable folder"
        if path.is_dir():
            raise ModelError(
                "the output is an existing folder", field=field, value=str(path), expected=expected
            )
        parent = path.parent
        if not parent.exists():
            raise ModelError(
                f"the folder {parent} does not exist",
                field=field,
                value=str(path),
                expected=expected,
            )
        if not parent.is_dir():
            raise ModelError(
                f"{parent} is not a folder", field=field, value=str(path), expected=expected
            )
        _probe(parent, field, path, expected)
    elif kind == "directory":
        expected = "a folder (new or existing) in a writable location"
        if path.is_symlink() and not path.exists():
            raise ModelError(
                f"the output is a symbolic link to a missing folder ({os.readlink(path)})",
                field=field,
                value=str(path),
                expected=expected,
            )
        if path.exists() and not path.is_dir():
            raise ModelError(
                "the output is an existing file, not a directory",
                field=field,
                value=str(path),
                expected=expected,
            )
        _writable_ancestor(path, field, path, expected)
    else:
        raise ValueError(f"kind must be 'file' or 'directory', not {kind!r}")
    _remove_stale_for(path, kind)
    return path


def _remove_stale_for(path: Path, kind: str) -> None:
    """The temporaries killed processes left for this output: a file's own
    (``NAME.tmp-PID-TOKEN``); a folder's files' and its own temporary folders."""
    if kind == "file":
        remove_stale_temporaries(path.parent, f"{path.name}.tmp-")
        return
    if path.is_dir():
        remove_stale_temporaries(path, token=True)
    target = path.resolve() if path.is_symlink() else path
    remove_stale_temporaries(target.parent, temporary_directory_prefix(target), directories=True)


def make_directory(path: str | os.PathLike, *, field: str | None = None) -> Path:
    """``mkdir -p`` with the errors of :func:`check_output`. Within an :func:`output_set`, the
    folders it creates go with the set when it fails (removed if still empty)."""
    path = Path(path)
    missing = []
    anc = path
    while not anc.exists() and anc != anc.parent:
        missing.append(anc)
        anc = anc.parent
    try:
        path.mkdir(parents=True, exist_ok=True)
        staging = _SET.get()
        if staging is not None:
            staging.folders.extend(reversed(missing))
    except OSError as exc:
        raise ModelError(
            f"cannot create the folder: {_reason(exc)}", field=field, value=str(path)
        ) from None
    return path


def temporary_directory_prefix(path: str | os.PathLike) -> str:
    """The name prefix of :func:`make_temporary_directory`'s folders for ``path``."""
    path = Path(path)
    return f".{path.name or path.resolve().name}.tmp-"  # "." is named after the folder it is


_RENAME_EXCHANGE = 2  # <linux/fs.h>
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Swap two paths in one step (Linux ``renameat2(RENAME_EXCHANGE)``); False where the
    system or the file system does not offer it."""
    if not sys.platform.startswith("linux"):
        return False
    import ctypes

    try:
        fn = ctypes.CDLL(None, use_errno=True).renameat2
    except (OSError, AttributeError):  # glibc < 2.28, musl without it
        return False
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    rc = fn(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE)
    if rc == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP):
        return False
    raise OSError(err, os.strerror(err), str(b))


def _remove_tree(path: Path) -> None:
    shutil.rmtree(path, ignore_errors=True)


def replace_directory(tmp: str | os.PathLike, path: str | os.PathLike) -> Path:
    """Put the complete folder ``tmp`` (from :func:`make_temporary_directory`) in place of the
    folder ``path`` as a whole: a new ``path`` is a rename; an existing one is exchanged with
    ``tmp`` in one step (Linux ``renameat2``; elsewhere two renames) and the old content, now
    under the temporary name, is removed. A reader, or a process killed at any moment, sees
    the old folder or the new one, never a mix; what a kill leaves under the temporary name
    is removed by the next run (:func:`check_output`). A symbolic link to a folder is followed:
    the folder it points to is replaced, the link stays. Returns ``path``."""
    tmp, path = Path(tmp), Path(path)
    built = Path(os.path.abspath(tmp))
    target = path.resolve() if path.is_symlink() else path
    try:
        with _signals_held():
            if not target.exists():
                os.rename(tmp, target)
            else:
                if not _exchange(tmp, target):
                    old = target.parent / (
                        f"{temporary_directory_prefix(target)}{os.getpid()}-{secrets.token_hex(3)}"
                    )
                    os.rename(target, old)
                    os.rename(tmp, target)
                    tmp = old
                _remove_tree(tmp)  # the old folder, now under the temporary name
    except OSError as exc:
        raise _write_error(path, exc) from None
    _BUILDING.discard(built)
    _record(path)
    return path


def make_temporary_directory(path: str | os.PathLike, *, field: str | None = None) -> Path:
    """Create an empty folder next to ``path`` in which the output folder ``path`` is built
    before it is moved into place: ``.NAME.tmp-PID-TOKEN`` (hidden; the pid lets the next run
    remove it when this process is killed: ``remove_stale_temporaries(path.parent,
    temporary_directory_prefix(path), directories=True)``), with the permissions of an ordinary
    folder (umask), not the private ones of ``tempfile.mkdtemp``."""
    path = Path(path)
    if path.is_symlink():  # built next to the folder it replaces (replace_directory)
        path = path.resolve()
    tmp = path.parent / f"{temporary_directory_prefix(path)}{os.getpid()}-{secrets.token_hex(3)}"
    try:
        tmp.mkdir()
        _BUILDING.add(Path(os.path.abspath(tmp)))
    except OSError as exc:
        raise ModelError(
            f"cannot create a folder next to the output: {_reason(exc)}",
            field=field,
            value=str(path),
        ) from None
    return tmp


_UNSAFE = re.compile(r"[^A-Za-z0-9._+-]+")


def safe_name(name: str) -> str:
    """A name usable as one file-name component: runs of characters other than letters, digits
    and ``._+-`` become ``_`` (no ``/``, no ``..``, no leading dot); never empty."""
    out = _UNSAFE.sub("_", str(name)).strip(".")
    out = out.replace("..", "_")
    return out or "_"


def unique_names(names: Sequence[str]) -> list[str]:
    """:func:`safe_name` of each name, distinct names kept distinct: a name whose sanitised
    form another, earlier name already has gets an index (``a/b``, ``a_b`` → ``a_b``,
    ``a_b-2``); equal names get the same file name. Case is ignored in the comparison (a
    case-insensitive file system would merge ``A`` and ``a``)."""
    taken: dict[str, str] = {}  # lower-case file name -> the name it stands for
    out: list[str] = []
    for name in names:
        base = safe_name(name)
        candidate, k = base, 1
        while taken.get(candidate.lower(), name) != name:
            k += 1
            candidate = f"{base}-{k}"
        taken[candidate.lower()] = name
        out.append(candidate)
    return out


def _pid_alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by someone else
        return True
    return True


def remove_stale_temporaries(
    directory: str | os.PathLike,
    prefix: str = "",
    *,
    directories: bool = False,
    token: bool = False,
) -> list[Path]:
    """Remove the temporaries (``PREFIX*.tmp-PID[-TOKEN]``) of processes that no longer run from
    ``directory`` (not recursive): files, and with ``directories`` also folders (with their
    content: :func:`make_temporary_directory`); with ``token`` only names that end in the
    writer's random token (``.tmp-PID-TOKEN``, as every temporary of this module's writers
    does: what a folder's cleaning takes for its own). Returns the paths removed."""
    directory = Path(directory)
    removed: list[Path] = []
    if not directory.is_dir():
        return removed
    for p in directory.iterdir():
        m = _TMP.search(p.name)
        if not (m and p.name.startswith(prefix)) or (token and m.group(2) is None):
            continue
        if _pid_alive(int(m.group(1))):
            continue
        if p.is_file():
            _discard(p)
        elif directories and p.is_dir() and not p.is_symlink():
            shutil.rmtree(p, ignore_errors=True)
        else:
            continue
        removed.append(p)
    return removed
