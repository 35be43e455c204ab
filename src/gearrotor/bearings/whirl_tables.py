"""Speed × whirl coefficient tables as a model reads them (issue 24): the rows of a model's
``table`` with ``whirl``, of a table file with a ``whirl_rpm`` column (what
:func:`gearrotor.bearings.pads.save_whirl_table` writes), checked with one-line errors.

A row is ``(speed, whirl, values)``: |shaft speed| (rad/s), whirl frequencies (n_w,) (rad/s,
≥ 0, increasing) and the eight coefficients (n_w, 8) kxx … cyy (N/m, N·s/m). The rows of a
file may have different whirl frequencies (ragged); each must cover its own speed, because the
synchronous coefficients (whirl = speed) are read from it.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import ModelError
from ..inputs import TABLE_COLUMNS, WHIRL_TABLE_COLUMNS, read_table, table_columns

__all__ = ["WHIRL_TABLE_COLUMNS", "Row", "is_whirl_table", "read_whirl_table", "rows_of_table"]

Row = tuple[float, NDArray, NDArray]
_RPM = math.pi / 30


def is_whirl_table(path: str | Path) -> bool:
    """True when a table file has a ``whirl_rpm`` column (CSV header or TOML array)."""
    return table_columns(path) == WHIRL_TABLE_COLUMNS


def read_whirl_table(path: str | Path) -> tuple[Row, ...]:
    """The rows of a speed × whirl table file, grouped by speed (a row per distinct speed, in
    the file's order of whirl frequencies), checked (:func:`check_rows`)."""
    t = read_table(path, WHIRL_TABLE_COLUMNS)
    cols = {k: np.asarray(v, float) for k, v in t.columns.items()}
    speed = np.abs(cols["speed_rpm"]) * _RPM
    whirl = cols["whirl_rpm"] * _RPM
    vals = np.column_stack([cols[c] for c in TABLE_COLUMNS[1:]])
    rows = []
    for s in dict.fromkeys(speed.tolist()):  # distinct speeds, in file order
        sel = speed == s
        rows.append((float(s), whirl[sel], vals[sel]))
    return check_rows(rows, file=str(path))


def rows_of_table(table) -> tuple[Row, ...]:
    """The rows of a model's :class:`~gearrotor.model.BearingTable` with ``whirl``."""
    w = np.asarray(table.whirl, float)
    names = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")
    rows = []
    for i, s in enumerate(table.speed):
        vals = np.column_stack([np.asarray(getattr(table, n)[i], float) for n in names])
        rows.append((abs(float(s)), w.copy(), vals))
    return check_rows(rows)


def check_rows(rows, *, file: str | None = None) -> tuple[Row, ...]:
    """Sort the rows by speed and check them: distinct speeds, whirl frequencies ≥ 0 and
    strictly increasing, each row covering its speed."""
    rows = sorted(rows, key=lambda r: r[0])
    for (a, *_), (b, *_) in zip(rows, rows[1:], strict=False):
        if b <= a:
            raise ModelError(
                "two rows of the speed × whirl table have the same |speed|",
                field="speed_rpm",
                value=f"{a / _RPM:.6g} rpm",
                expected="one speed per row group (|speed| distinct)",
                file=file,
            )
    for s, w, _ in rows:
        if w[0] < 0 or np.any(np.diff(w) <= 0):
            raise ModelError(
                "the whirl frequencies of a speed must be >= 0 and strictly increasing",
                field="whirl_rpm",
                value=f"{(w / _RPM).round(6).tolist()} at {s / _RPM:.6g} rpm",
                expected="increasing whirl frequencies >= 0, each once per speed",
                file=file,
            )
        if w[0] > s * (1 + 1e-12) or w[-1] < s * (1 - 1e-12):
            raise ModelError(
                "the whirl frequencies of a speed must cover that speed (the synchronous "
                "coefficients, whirl = speed, are read from them)",
                field="whirl_rpm",
                value=f"{w[0] / _RPM:.6g}..{w[-1] / _RPM:.6g} rpm at {s / _RPM:.6g} rpm",
                expected=f"whirl frequencies from <= {s / _RPM:.6g} to >= {s / _RPM:.6g} rpm",
                file=file,
            )
    return tuple(rows)
