"""Checkpoints of long transient runs (:class:`~.options.Checkpoint`): the fingerprint that
ties a file to its run (model, method, step, settings) and the atomic write of the state."""

from __future__ import annotations

import hashlib
import zipfile
import zlib
from pathlib import Path

import numpy as np

from ...errors import ModelError
from ...files import write_npz
from ...model import Train


def _fingerprint(train: Train, kind: str, dt: float, extra: str) -> str:
    h = hashlib.sha256()
    h.update(train.model_dump_json().encode())
    h.update(f"{kind}|{dt!r}|{extra}".encode())
    return h.hexdigest()


def _write_npz_atomic(path: Path, **arrays) -> None:
    write_npz(path, **arrays)


_KEYS = ("step", "q", "v", "rec_q", "rec_v", "rec_a", "rec_om", "rec_t", "rec_env")
_EXPECTED = "a checkpoint written by gearrotor's transient (delete the file to start from t = 0)"


def _read_checkpoint(path: Path, fingerprint: str) -> dict | None:
    """The saved state of a run (``step``, ``q``, ``v`` and the records ``rec_*``) when the file
    ``path`` exists and its fingerprint is ``fingerprint``; otherwise None. A file that is not a
    readable checkpoint raises :class:`ModelError` naming it."""
    path = Path(path)
    if not path.exists():
        return None
    try:
        with open(path, "rb") as fh:  # closed whatever np.load meets
            ck = np.load(fh, allow_pickle=False)
            if not hasattr(ck, "files") or "fingerprint" not in ck.files:
                raise ValueError("it has no fingerprint")
            if str(ck["fingerprint"]) != fingerprint:
                return None
            data = {k: ck[k] for k in ck.files if k != "fingerprint"}
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile, zlib.error) as exc:
        raise ModelError(
            f"the checkpoint cannot be read ({type(exc).__name__}: {exc})",
            file=str(path),
            expected=_EXPECTED,
        ) from None
    missing = [k for k in _KEYS if k not in data]
    if missing:
        raise ModelError(
            f"the checkpoint lacks {', '.join(missing)}", file=str(path), expected=_EXPECTED
        )
    return data


def _check_state(
    path: Path, ck: dict, *, n_steps: int, save_every: int, q, rec_q, rec_om, rec_env
) -> int:
    """The step a checkpoint resumes at, after checking that its arrays fit the run."""
    step = int(ck["step"]) if np.ndim(ck["step"]) == 0 else -1
    nr = step // save_every if step > 0 else 0
    ok = (
        0 < step < n_steps
        and ck["q"].shape == q.shape
        and ck["v"].shape == q.shape
        and all(ck[k].shape == (nr, *rec_q.shape[1:]) for k in ("rec_q", "rec_v", "rec_a"))
        and ck["rec_om"].shape == (nr, *rec_om.shape[1:])
        and ck["rec_t"].shape == (nr,)
        and ck["rec_env"].shape == (nr, *rec_env.shape[1:])
        and all(np.all(np.isfinite(ck[k])) for k in ("q", "v"))
    )
    if not ok:
        raise ModelError(
            "the checkpoint does not fit this run (step or array shapes; damaged?)",
            file=str(path),
            value=f"step {ck['step']!r}",
            expected=_EXPECTED,
        )
    return step
