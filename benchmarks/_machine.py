"""What the benchmark scripts print about the machine they ran on (imported by them as
``from _machine import cpu_name``: a script's own folder is first on ``sys.path``), and the
busy neighbour they measure next to."""

from __future__ import annotations

import contextlib
import os
import platform
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path


def cpu_name() -> str:
    """The processor's model name (/proc/cpuinfo), else what ``platform`` knows."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


@contextlib.contextmanager
def busy_neighbour(on: bool = True) -> Iterator[None]:
    """One other process keeping a core busy (``python -c "while True: pass"``) while the block
    runs, as a second study worker, a browser or a CI job would; nothing when ``on`` is False."""
    if not on:
        yield
        return
    proc = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        time.sleep(0.5)  # running before the timing starts
        yield
    finally:
        proc.kill()
        proc.wait()


def environment() -> str:
    """The thread setting the benchmark runs with: gearrotor's and the BLAS variables (a user's
    default environment has none of them)."""
    names = ("GEARROTOR_THREADS", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
    set_ = [f"{k}={os.environ[k]}" for k in names if k in os.environ]
    return "environment: " + (", ".join(set_) if set_ else "default (no thread variables)")
