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

Temporaries of a process that was killed (SIGKILL, power cut) stay behind; their names carry
the pid, and :func:`remove_stale_temporaries` removes those whose process is gone. An output
folder built as a whole (the HTML report) is built in a temporary folder named the same way
(:func:`make_temporary_directory`, ``.NAME.tmp-PID-TOKEN`` next to it), and its writer removes
the temporary folders of dead processes at its next run.
"""

from __future__ import annotations

import contextlib
import errno
import io
import json
import os
import re
import secrets
import shutil
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any

from .errors import ModelError

__all__ = [
    "atomic_file",
    "check_output",
    "make_directory",
    "make_temporary_directory",
    "remove_stale_temporaries",
    "safe_name",
    "save_figure",
    "temporary_directory_prefix",
    "write_bytes",
    "write_json",
    "write_netcdf",
    "write_npz",
    "write_text",
]

_TMP = re.compile(r"\.tmp-(\d+)(?:-[0-9a-f]+)?$")

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


@contextlib.contextmanager
def atomic_file(path: str | os.PathLike, mode: str = "wb", **open_kw) -> Iterator[IO[Any]]:
    """Open a temporary file next to ``path`` for writing; on a normal exit it is flushed,
    ``fsync``-ed and renamed to ``path``. On any exception the temporary is removed; an
    ``OSError`` becomes a :class:`ModelError` naming ``path`` (others pass through)."""
    if mode not in ("w", "wb"):
        raise ValueError(f"atomic_file writes only: mode 'w' or 'wb', not {mode!r}")
    path = Path(path)
    tmp = _temporary(path)
    try:
        with open(tmp, mode, **open_kw) as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
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
    buf = io.BytesIO()
    fig.savefig(buf, **savefig_kw)
    return write_bytes(path, buf.getbuffer())


def write_netcdf(path: str | os.PathLike, dataset, *, engine: str = "h5netcdf") -> Path:
    """An xarray Dataset as NetCDF-4 to ``path`` atomically, produced in memory first (libhdf5
    does not survive a full disk)."""
    with contextlib.ExitStack() as stack:
        if "dask" in sys.modules:  # under a distributed Client, xarray would ask it for a lock
            import dask  # named after the BytesIO (it fails); the dataset is in memory here

            stack.enter_context(dask.config.set(scheduler="synchronous"))
        data = dataset.to_netcdf(engine=engine)
    return write_bytes(path, data)


def write_npz(path: str | os.PathLike, **arrays) -> Path:
    """``numpy.savez`` of ``arrays`` to ``path`` atomically (produced in memory first)."""
    import numpy as np

    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return write_bytes(path, buf.getbuffer())


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
    return path


def make_directory(path: str | os.PathLike, *, field: str | None = None) -> Path:
    """``mkdir -p`` with the errors of :func:`check_output`."""
    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ModelError(
            f"cannot create the folder: {_reason(exc)}", field=field, value=str(path)
        ) from None
    return path


def temporary_directory_prefix(path: str | os.PathLike) -> str:
    """The name prefix of :func:`make_temporary_directory`'s folders for ``path``."""
    path = Path(path)
    return f".{path.name or path.resolve().name}.tmp-"  # "." is named after the folder it is


def make_temporary_directory(path: str | os.PathLike, *, field: str | None = None) -> Path:
    """Create an empty folder next to ``path`` in which the output folder ``path`` is built
    before it is moved into place: ``.NAME.tmp-PID-TOKEN`` (hidden; the pid lets the next run
    remove it when this process is killed: ``remove_stale_temporaries(path.parent,
    temporary_directory_prefix(path), directories=True)``), with the permissions of an ordinary
    folder (umask), not the private ones of ``tempfile.mkdtemp``."""
    path = Path(path)
    tmp = path.parent / f"{temporary_directory_prefix(path)}{os.getpid()}-{secrets.token_hex(3)}"
    try:
        tmp.mkdir()
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
    directory: str | os.PathLike, prefix: str = "", *, directories: bool = False
) -> list[Path]:
    """Remove the temporaries (``PREFIX*.tmp-PID[-TOKEN]``) of processes that no longer run from
    ``directory`` (not recursive): files, and with ``directories`` also folders (with their
    content: :func:`make_temporary_directory`). Returns the paths removed."""
    directory = Path(directory)
    removed: list[Path] = []
    if not directory.is_dir():
        return removed
    for p in directory.iterdir():
        m = _TMP.search(p.name)
        if not (m and p.name.startswith(prefix)) or _pid_alive(int(m.group(1))):
            continue
        if p.is_file():
            _discard(p)
        elif directories and p.is_dir() and not p.is_symlink():
            shutil.rmtree(p, ignore_errors=True)
        else:
            continue
        removed.append(p)
    return removed
