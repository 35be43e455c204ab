"""Where numba keeps the compiled kernels: a user cache directory, not the installed package.

numba's ``cache=True`` writes its ``*.nbi``/``*.nbc`` files next to the source by default,
i.e. into the installed package tree (site-packages, or the checkout of an editable install),
which may be read-only, shared between users or versions, and is not the package's to change
at run time. :func:`configure_cache` points numba at
``<user cache dir>/gearrotor/numba/src-…`` (``~/.cache/gearrotor/numba`` on Linux, from
``platformdirs``; one folder per version of the kernel sources, :func:`cache_dir`) unless
``NUMBA_CACHE_DIR`` is already set, which then wins. The modules that compile kernels call it
before their first ``@njit(cache=True)``: numba decides where a function's cache lives when it
is decorated.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

__all__ = ["cache_dir", "configure_cache"]


def cache_dir() -> Path:
    """``<user cache dir>/gearrotor/numba/src-DIGEST`` (``NUMBA_CACHE_DIR`` when it is set).

    DIGEST is a hash of the sources of every module that compiles kernels: numba keys a
    cached kernel on its own file's time stamp only, so a kernel that calls a compiled
    function of another module (the transients call the drive laws of
    ``torsional/drive_laws.py``) would keep running the old callee after that module
    changed. One folder per version of the kernel sources avoids it."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return Path(os.environ["NUMBA_CACHE_DIR"])
    import platformdirs

    base = Path(platformdirs.user_cache_dir("gearrotor", appauthor=False)) / "numba"
    return base / f"src-{_kernel_sources_digest()}"


def _kernel_sources_digest() -> str:
    """Hash of the modules under ``analyses/`` that define numba kernels (name and content)."""
    import hashlib

    root = Path(__file__).parent
    h = hashlib.sha1()
    for path in sorted(root.rglob("*.py")):
        data = path.read_bytes()
        if b"njit" in data:
            h.update(path.relative_to(root).as_posix().encode())
            h.update(data)
    return h.hexdigest()[:16]


def configure_cache() -> Path:
    """Point numba's cache at :func:`cache_dir` (the environment variable, which processes
    started later inherit, and numba's configuration, if numba is already imported)."""
    path = cache_dir()
    os.environ["NUMBA_CACHE_DIR"] = str(path)
    numba = sys.modules.get("numba")
    if numba is not None:
        numba.config.CACHE_DIR = str(path)
    return path
