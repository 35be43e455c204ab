"""Shared pieces of the worked-example tests: run the ``gearrotor ...`` commands of a doc."""

from __future__ import annotations

import os
import re
import shlex
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# single-threaded BLAS: on a loaded 2-core machine a threaded dense eigensolve can be 50x slower
ENV = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")


def run(args: list[str], timeout: float = 600, status: int = 0) -> subprocess.CompletedProcess:
    """Run a command in the repository root; assert its exit status."""
    out = subprocess.run(args, cwd=ROOT, env=ENV, capture_output=True, text=True, timeout=timeout)
    assert out.returncode == status, f"{args}\n{out.stderr[-3000:]}"
    return out


def doc_commands(doc: Path) -> list[tuple[list[str], str]]:
    """(argv after ``gearrotor``, trailing comment) of the doc's bash blocks, continuation
    lines joined."""
    cmds = []
    for block in re.findall(r"```bash\n(.*?)```", doc.read_text(), flags=re.S):
        joined = re.sub(r"\\\n\s*", " ", block)
        for line in joined.splitlines():
            line = line.strip()
            if not line.startswith("gearrotor "):
                continue
            cmd, _, comment = line.partition("#")
            cmds.append((shlex.split(cmd)[1:], comment.strip()))
    return cmds


def find_run(runs, kind: str, *words: str, without: tuple[str, ...] = ()) -> dict:
    """The one result of a ``kind`` command whose arguments contain all ``words`` and none of
    ``without``."""
    hits = [
        r
        for c, r in runs
        if c[0] == kind
        and all(any(w in a for a in c) for w in words)
        and not any(any(w in a for a in c) for w in without)
    ]
    assert len(hits) == 1, (kind, words, [c for c, _ in runs])
    return hits[0]
