"""Checkpoints of long transient runs (:class:`~.options.Checkpoint`): the fingerprint that
ties a file to its run (model, method, step, settings) and the atomic write of the state."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np

from ...files import write_npz
from ...model import Train


def _fingerprint(train: Train, kind: str, dt: float, extra: str) -> str:
    h = hashlib.sha256()
    h.update(train.model_dump_json().encode())
    h.update(f"{kind}|{dt!r}|{extra}".encode())
    return h.hexdigest()


def _write_npz_atomic(path: Path, **arrays) -> None:
    write_npz(path, **arrays)


def _read_checkpoint(path: Path, fingerprint: str) -> dict | None:
    """The saved state of a run (``step``, ``q``, ``v`` and the records ``rec_*``) when the file
    ``path`` exists and its fingerprint is ``fingerprint``; otherwise None."""
    if not Path(path).exists():
        return None
    with np.load(path, allow_pickle=False) as ck:
        if str(ck["fingerprint"]) != fingerprint:
            return None
        return {k: ck[k] for k in ck.files if k != "fingerprint"}
