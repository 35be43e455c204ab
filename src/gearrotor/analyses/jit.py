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

Inside that folder numba would file each module's kernels under a hash of the module's absolute
path, so every checkout, worktree or copy of the same sources compiled every kernel again
(~45 s of CPU for the transient kernels; the test suite of a fresh clone paid it in each
worker). :func:`configure_cache` also registers :class:`PackageCacheLocator`, which files
gearrotor's kernels by their place in the package instead (``gearrotor/analyses/transient``);
numba's own check still applies (a cached kernel is used only while its source file's content
hash is the one it was compiled from), and the stamp also carries the hash of every kernel
module, so a kernel that inlines another module's compiled function is compiled again when that
module changes, whichever folder ``NUMBA_CACHE_DIR`` names.
"""

from __future__ import annotations

import functools
import os
import sys
from pathlib import Path

from numba import njit
from numba.core import caching, config
from numba.core.registry import CPUDispatcher

__all__ = ["KernelOnly", "PackageCacheLocator", "cache_dir", "configure_cache", "kernel_only"]


def cache_dir() -> Path:
    """``<user cache dir>/gearrotor/numba/src-DIGEST`` (``NUMBA_CACHE_DIR`` when it is set).

    DIGEST is a hash of the sources of every module that compiles kernels: numba keys a
    cached kernel on its own file's content only, so a kernel that calls a compiled
    function of another module (the transients call the drive laws of
    ``torsional/drive_laws.py``) would keep running the old callee after that module
    changed. One folder per version of the kernel sources avoids it."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return Path(os.environ["NUMBA_CACHE_DIR"])
    import platformdirs

    base = Path(platformdirs.user_cache_dir("gearrotor", appauthor=False)) / "numba"
    return base / f"src-{_kernel_sources_digest()}"


@functools.cache
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
    _register_locator()
    return path


_PACKAGE = Path(__file__).resolve().parents[1]  # src/gearrotor (or site-packages/gearrotor)


def _register_locator() -> None:
    """Put :class:`PackageCacheLocator` first in numba's list of cache locators (once; a numba
    without that list keeps its own locators: the kernels are then cached per checkout)."""
    classes = getattr(caching.CacheImpl, "_locator_classes", None)
    if isinstance(classes, list) and PackageCacheLocator not in classes:
        classes.insert(0, PackageCacheLocator)


class PackageCacheLocator(caching.UserProvidedCacheLocator):
    """numba's locator for a user-provided cache folder, for gearrotor's own kernels only: the
    kernels of ``<package>/analyses/transient/kernels.py`` go to
    ``NUMBA_CACHE_DIR/gearrotor/analyses/transient`` whichever folder the package was loaded
    from; the source stamp is numba's (the file's content hash) together with the hash of all
    kernel modules (:func:`_kernel_sources_digest`)."""

    def __init__(self, py_func, py_file):
        super().__init__(py_func, py_file)
        where = Path(py_file).resolve().parent.relative_to(_PACKAGE)
        self._cache_path = os.path.join(config.CACHE_DIR, "gearrotor", *where.parts)

    def get_source_stamp(self):
        return super().get_source_stamp(), _kernel_sources_digest()

    @classmethod
    def from_function(cls, py_func, py_file):
        try:
            Path(py_file).resolve().relative_to(_PACKAGE)
        except (OSError, ValueError):
            return None  # not a gearrotor module: numba's other locators decide
        return super().from_function(py_func, py_file)


class KernelOnly(CPUDispatcher):
    """A numba dispatcher compiled without a Python entry point (:func:`kernel_only`): calling
    it from Python raises TypeError (numba would jump to a null entry point and crash)."""

    def __call__(self, *args, **kwargs):
        raise TypeError(
            f"{self.py_func.__qualname__} is compiled without a Python entry point: "
            "it is called from other compiled kernels only"
        )


def kernel_only(**options):
    """``numba.njit(**options)`` for a function called only from other compiled kernels: without
    the wrappers numba adds so that Python (``no_cpython_wrapper``) or C (``no_cfunc_wrapper``)
    can call it, as numba compiles its own ``@overload`` implementations.

    Why: numba compiles a called kernel on its own before its caller, and links it into the
    caller's module, which LLVM then optimises and compiles again, so each kernel is compiled
    once by itself and once in every kernel that reaches it. The Python wrapper (it unboxes
    every array of every pack, ~60 for the modal model) is compiled with it, and was as large
    as the function itself: without it, compiling the transient kernels into an empty cache
    takes ~23 % less CPU (docs/performance.md, "numba start-up"). The function itself, and so
    every result, is the same to the bit: the wrappers only convert arguments.

    The dispatcher becomes a :class:`KernelOnly`, whose call from Python raises TypeError."""

    def decorate(fn):
        dispatcher = njit(no_cpython_wrapper=True, no_cfunc_wrapper=True, **options)(fn)
        dispatcher.__class__ = KernelOnly  # same layout (adds no slots): only __call__ differs
        return dispatcher

    return decorate
