"""Solved results kept on disk between runs: the fluid-film and seal coefficient tables.

A model with fluid-film bearings solves the Reynolds equation at every table speed each time it
is assembled (4 bearings × 20 speeds: seconds to tens of seconds), although the bearing file,
its load and its speeds rarely change between two runs of ``modal``, ``campbell``, ``report``
or a study. :func:`arrays` keeps such a result as an ``.npz`` file in
``<user cache dir>/gearrotor/results/<kind>/<fingerprint>/<key>.npz`` (``~/.cache/gearrotor``
on Linux, from ``platformdirs``):

* **key**: SHA-256 of the ``repr`` of everything the result depends on, as parsed (the
  bearing's geometry, lubricant, solver options, loads and speeds; not the file's name, path
  or time stamp): the same bearing in another folder or file is the same entry, a changed
  number a new one.
* **fingerprint**: a hash of the solver's sources (the modules that compute the result), the
  package version and NumPy's and SciPy's versions: a changed solver never reads an old
  result.
* A hit returns exactly the stored float64 arrays (bit for bit what the solver returned).
* Two processes that need the same entry at the same time (study workers, ``pytest -n``) take
  a lock on it (``fcntl.flock``): one solves, the other reads its result.
* The cache never stops an analysis: an unreadable or damaged entry is solved again and
  replaced, a cache folder that cannot be written is skipped. Entries are written to a
  temporary and renamed into place (``.tmp-PID-TOKEN``, removed if the write fails; those of a
  killed process are removed by the next writer in that folder).

``GEARROTOR_CACHE_DIR`` moves the cache; ``GEARROTOR_CACHE=off`` turns it off (every result
solved, nothing read or written). Entries are a few kilobytes; deleting the folder is always
safe. Figures kept for ``study report`` (``study-trend``, ``study-spectra``: hundreds of
kilobytes each) are bounded per kind (``max_bytes``), the least recently used removed first.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import io
import os
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path

__all__ = ["arrays", "cache_root", "enabled"]

_OFF = ("0", "off", "false", "no")


def enabled() -> bool:
    """False when ``GEARROTOR_CACHE`` is ``off`` (or 0/false/no)."""
    return os.environ.get("GEARROTOR_CACHE", "on").strip().lower() not in _OFF


def cache_root() -> Path:
    """``GEARROTOR_CACHE_DIR``, or ``<user cache dir>/gearrotor/results``."""
    if os.environ.get("GEARROTOR_CACHE_DIR"):
        return Path(os.environ["GEARROTOR_CACHE_DIR"])
    import platformdirs

    return Path(platformdirs.user_cache_dir("gearrotor", appauthor=False)) / "results"


@functools.cache
def _fingerprint(sources: tuple[str, ...]) -> str:
    """Hash of the source files under ``gearrotor/<source>`` (a module or a folder), the
    package version and NumPy's and SciPy's versions (once per process)."""
    import numpy
    import scipy

    from . import __version__

    root = Path(__file__).parent
    h = hashlib.sha256()
    h.update(f"{__version__} numpy {numpy.__version__} scipy {scipy.__version__}".encode())
    for source in sources:
        path = root / source
        for f in sorted(path.rglob("*.py")) if path.is_dir() else [path]:
            h.update(f.relative_to(root).as_posix().encode())
            h.update(f.read_bytes())
    return h.hexdigest()[:16]


def _key(parts: Iterable[object]) -> str:
    h = hashlib.sha256()
    for part in parts:
        h.update(repr(part).encode())
        h.update(b"\0")
    return h.hexdigest()[:32]


def _read(path: Path) -> dict | None:
    import numpy as np

    try:
        raw = path.read_bytes()  # whole (a few kB): no file left open by a failed parse
    except OSError:
        return None
    try:
        with np.load(io.BytesIO(raw), allow_pickle=False) as data:
            return {name: data[name] for name in data.files}
    except Exception:  # a damaged entry (a disk error, a foreign file): solved again
        return None


def arrays(
    kind: str,
    parts: Iterable[object],
    solve: Callable[[], Mapping],
    *,
    sources: tuple[str, ...],
    max_bytes: int | None = None,
) -> dict:
    """The arrays ``solve()`` returns (a mapping of names to NumPy arrays), from the cache when
    an entry of ``kind`` for ``parts`` exists, else solved and stored.

    ``parts`` is everything the result depends on (its ``repr`` is hashed: give parsed values,
    not file names); ``sources`` the modules or folders under ``gearrotor/`` whose code
    computes it (their content is part of the entry's folder name). ``max_bytes``: the most
    the entries of ``kind`` may take on disk (figures: hundreds of kilobytes each); when a new
    entry takes them over it, the least recently used are removed (:func:`_prune`)."""
    from . import files

    if not enabled():
        return dict(solve())
    folder = cache_root() / kind / _fingerprint(tuple(sources))
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return dict(solve())
    path = folder / f"{_key(parts)}.npz"
    hit = _read(path)
    if hit is not None:
        if max_bytes is not None:
            _touch(path)
        return hit
    with contextlib.ExitStack() as stack:
        try:
            stack.enter_context(files.locked(folder / f"{path.stem}.lock"))
        except OSError:  # the lock file cannot be made: solve without the cache
            return dict(solve())
        hit = _read(path)  # solved by another process while this one waited
        if hit is not None:
            return hit
        values = dict(solve())
        if files.write_cache_entry(path, **values) and max_bytes is not None:
            _prune(cache_root() / kind, max_bytes, keep=path)
        return values


def _touch(path: Path) -> None:
    """Mark an entry used now (its modification time: what :func:`_prune` orders by)."""
    with contextlib.suppress(OSError):
        os.utime(path)


def _prune(folder: Path, max_bytes: int, keep: Path) -> None:
    """Remove the least recently used entries under ``folder`` (every fingerprint of a kind,
    so entries of replaced sources go first) until they take at most ``max_bytes``; ``keep``
    (the entry just written) stays. Best effort: an entry another process removes meanwhile,
    or one that cannot be removed, is passed over."""
    entries = []
    for path in folder.glob("*/*.npz"):
        with contextlib.suppress(OSError):
            st = path.stat()
            entries.append((st.st_mtime, st.st_size, path))
    total = sum(size for _, size, _ in entries)
    for _, size, path in sorted(entries, key=lambda e: e[0]):
        if total <= max_bytes:
            break
        if path == keep:
            continue
        with contextlib.suppress(OSError):
            path.unlink()
            total -= size
        with contextlib.suppress(OSError):  # its lock file (empty) goes with it
            path.with_suffix(".lock").unlink()
