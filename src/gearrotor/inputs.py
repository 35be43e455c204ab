"""One reader for every input file (model, study, bearing and table files).

Whatever a file holds, reading it either returns its content or raises one
:class:`~gearrotor.errors.ModelError` whose message is one line naming the file: a missing file,
a directory, a file larger than :data:`MAX_BYTES`, text that is not UTF-8 (the byte offset of
the first bad byte is named; a UTF-8 byte-order mark is accepted), TOML that does not parse or
nests deeper than :data:`MAX_DEPTH`. No input can make the reader run out of memory, recurse
without bound or print a traceback.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path
from typing import Any, NamedTuple

from .errors import ModelError

__all__ = [
    "MAX_BYTES",
    "MAX_DEPTH",
    "MAX_LISTED",
    "TABLE_COLUMNS",
    "WHIRL_TABLE_COLUMNS",
    "TableFile",
    "depth_ok",
    "list_some",
    "parse_toml",
    "read_table",
    "read_text",
    "read_toml",
    "table_columns",
    "read_whirl_table",
    "check_whirl_rows",
]

#: Largest input file read (bytes). The largest real models are a few tens of kB.
MAX_BYTES = 4 * 1024 * 1024
#: Deepest nesting of TOML tables and arrays (a model needs about 5).
MAX_DEPTH = 32
#: At most this many items (unknown keys, errors) are listed in one message.
MAX_LISTED = 10


def list_some(items: list, limit: int = MAX_LISTED) -> str:
    """``a, b, c`` or ``a, b, ... (and 12 more)``: a list bounded for an error message."""
    shown = ", ".join(str(x) for x in items[:limit])
    return shown + (f", ... (and {len(items) - limit} more)" if len(items) > limit else "")


def read_text(path: str | Path, kind: str = "input") -> str:
    """The text of an input file (UTF-8, optional byte-order mark), checked.

    ``kind`` names the file in messages ("model", "study", "bearing", "table"). Raises
    :class:`ModelError` naming the file when it is missing, a directory, unreadable, larger than
    :data:`MAX_BYTES` or not UTF-8 text.
    """
    path = Path(path)
    name = str(path)
    try:
        if path.is_dir():
            raise ModelError(f"the {kind} file is a directory", file=name, expected="a file")
        with path.open("rb") as fh:
            data = fh.read(MAX_BYTES + 1)
    except FileNotFoundError:
        raise ModelError(f"{kind} file not found", file=name) from None
    except ModelError:
        raise
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise ModelError(f"cannot read the {kind} file: {reason}", file=name) from None
    if len(data) > MAX_BYTES:
        raise ModelError(
            f"the {kind} file is larger than {MAX_BYTES // (1024 * 1024)} MiB",
            file=name,
            expected=f"a {kind} file of at most {MAX_BYTES} bytes",
        )
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        bad = data[exc.start : exc.start + 1]
        hint = ""
        if data[:2] in (b"\xff\xfe", b"\xfe\xff"):
            hint = " (it looks like UTF-16: save it as UTF-8)"
        raise ModelError(
            f"the {kind} file is not UTF-8 text: byte 0x{bad.hex()} at offset {exc.start}{hint}",
            file=name,
            expected="a text file in UTF-8",
        ) from None


def depth_ok(doc: Any) -> bool:
    """Whether nested dicts/lists ``doc`` are at most :data:`MAX_DEPTH` levels deep (iterative)."""
    stack = [(doc, 1)]
    while stack:
        node, depth = stack.pop()
        if depth > MAX_DEPTH:
            return False
        if isinstance(node, dict):
            stack.extend((v, depth + 1) for v in node.values())
        elif isinstance(node, list):
            stack.extend((v, depth + 1) for v in node)
    return True


def parse_toml(text: str, name: str, kind: str = "input") -> dict:
    """Parse TOML text of the file ``name``; errors as in :func:`read_toml`."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ModelError(f"invalid TOML: {str(exc).splitlines()[0]}", file=name) from None
    except RecursionError:
        doc = None
    if doc is None or not depth_ok(doc):
        raise ModelError(
            f"the {kind} file nests tables or arrays too deeply",
            file=name,
            expected=f"at most {MAX_DEPTH} levels",
        )
    return doc


def read_toml(path: str | Path, kind: str = "input") -> dict:
    """The parsed content of a TOML input file, checked as in :func:`read_text`, with TOML
    syntax errors and nesting deeper than :data:`MAX_DEPTH` reported in one line."""
    return parse_toml(read_text(path, kind), str(path), kind)


#: The columns of a bearing coefficient table file (rpm, N/m, N*s/m), as
#: :func:`gearrotor.bearings.save_table` writes them.
TABLE_COLUMNS = ("speed_rpm", "kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")


#: The columns of a speed × whirl table file (rpm, rpm, N/m, N*s/m), as
#: :func:`gearrotor.bearings.pads.save_whirl_table` writes them.
WHIRL_TABLE_COLUMNS = ("speed_rpm", "whirl_rpm", *TABLE_COLUMNS[1:])


def table_columns(path: str | Path) -> tuple[str, ...]:
    """:data:`WHIRL_TABLE_COLUMNS` when a table file has a ``whirl_rpm`` column (CSV header or
    TOML array), else :data:`TABLE_COLUMNS` (a file that cannot be read: the regular reader
    reports it)."""
    path = Path(path)
    try:
        text = read_text(path, "table")
        if path.suffix.lower() == ".toml":
            whirl = "whirl_rpm" in parse_toml(text, str(path), "table")
        else:
            first = next(
                (ln for ln in text.splitlines() if ln.strip() and not ln.startswith("#")), ""
            )
            whirl = "whirl_rpm" in [h.strip() for h in first.split(",")]
    except ModelError:
        whirl = False
    return WHIRL_TABLE_COLUMNS if whirl else TABLE_COLUMNS


def read_table(path: str | Path, columns: tuple[str, ...] = TABLE_COLUMNS) -> TableFile:
    """The columns of a table file (``.csv``: a header row of the column names, ``#`` comments;
    ``.toml``: one array per column, optional ``name`` and ``load = [Fx, Fy]``).

    Whatever the file holds (nothing, random bytes, a directory, other columns, text where a
    number belongs, a value that is not finite, no rows) the result is a :class:`TableFile` or
    one :class:`ModelError` naming the file (and the line or column).
    """
    import csv
    import math

    path = Path(path)
    name = str(path)
    want = ",".join(columns)
    suffix = path.suffix.lower()
    if suffix not in (".csv", ".toml"):
        raise ModelError(
            "unknown table format",
            file=name,
            value=path.suffix or "(no suffix)",
            expected="a .csv or .toml table file (columns " + want + ")",
        )
    text = read_text(path, "table")
    if not text.strip():
        raise ModelError("the table file is empty", file=name, expected=f"columns {want}")
    title, load = "", (0.0, 0.0)
    data: dict[str, list[float]] = {c: [] for c in columns}
    if suffix == ".toml":
        doc = parse_toml(text, name, "table")
        unknown = sorted(set(doc) - set(columns) - {"name", "load"})
        missing = [c for c in columns if c not in doc]
        if unknown or missing:
            raise ModelError(
                "wrong columns in the table"
                + (f"; unknown: {list_some(unknown)}" if unknown else "")
                + (f"; missing: {list_some(missing)}" if missing else ""),
                file=name,
                expected=f"arrays {want}",
            )
        for c in columns:
            vals = doc[c]
            if not isinstance(vals, list) or not all(
                isinstance(v, int | float) and not isinstance(v, bool) for v in vals
            ):
                raise ModelError(
                    "a column is not an array of numbers", field=c, file=name, expected="numbers"
                )
            data[c] = [float(v) for v in vals]
        title = doc.get("name", "")
        ld = doc.get("load", [0.0, 0.0])
        if (
            not isinstance(title, str)
            or not isinstance(ld, list)
            or len(ld) != 2
            or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in ld)
        ):
            raise ModelError(
                "bad 'name' or 'load'", file=name, expected="name a string, load = [Fx, Fy] in N"
            )
        load = (float(ld[0]), float(ld[1]))
    else:
        header = None
        for line_no, line in enumerate(text.splitlines(), start=1):
            if line.startswith("# bearing:"):
                head, _, rest = line[len("# bearing:") :].partition("; load Fx,Fy = ")
                title = head.strip()
                try:
                    fx, fy = (float(v) for v in rest.replace("N", "").split(","))
                    load = (fx, fy)
                except ValueError:
                    pass
                continue
            if line.startswith("#") or not line.strip():
                continue
            try:
                row = next(csv.reader([line]))
            except csv.Error:
                row = None
            if header is None:
                header = [h.strip() for h in row or []]
                if header != list(columns):
                    shown = ",".join(header)
                    raise ModelError(
                        "wrong columns in the table header",
                        field=f"line {line_no}",
                        value=shown if len(shown) <= 80 else shown[:77] + "...",
                        expected=want,
                        file=name,
                    )
                continue
            try:
                if row is None or len(row) != len(columns):
                    raise ValueError
                for c, v in zip(columns, row, strict=True):
                    data[c].append(float(v))
            except ValueError:
                shown = line.strip()
                raise ModelError(
                    "bad row in the table",
                    field=f"line {line_no}",
                    value=shown if len(shown) <= 80 else shown[:77] + "...",
                    expected=f"{len(columns)} numbers ({want})",
                    file=name,
                ) from None
    n = {len(v) for v in data.values()}
    if n != {len(data[columns[0]])} or not data[columns[0]]:
        raise ModelError(
            "the table has no rows or columns of different lengths",
            file=name,
            value={c: len(v) for c, v in data.items()},
            expected=f"at least one row of {want}",
        )
    for c, vals in data.items():
        if not all(math.isfinite(v) for v in vals):
            raise ModelError(
                "the table holds a value that is not finite",
                field=c,
                file=name,
                expected="finite numbers",
            )
    # coefficients at a speed are one row (issue 23); a speed × whirl table has one row per
    # (speed, whirl), checked by read_whirl_table
    if "speed_rpm" in data and "whirl_rpm" not in data:
        seen: dict[float, int] = {}
        for k, v in enumerate(data["speed_rpm"]):
            if abs(v) in seen:
                raise ModelError(
                    f"rows {seen[abs(v)] + 1} and {k + 1} are at the same speed (the speed's "
                    "sign is the sense of rotation; a table row holds for either)",
                    field="speed_rpm",
                    file=name,
                    value=v,
                    expected="one row per speed",
                )
            seen[abs(v)] = k
    return TableFile(data, title, load)


class TableFile(NamedTuple):
    """A table file's content: ``columns`` {name: values}, the ``name`` and ``load`` it states."""

    columns: dict[str, list[float]]
    name: str
    load: tuple[float, float]


#: a row of a speed × whirl table: (|shaft speed| rad/s, whirl frequencies (n_w,) rad/s,
#: coefficients (n_w, 8) kxx … cyy in N/m and N*s/m), numpy arrays
WhirlRow = tuple


def read_whirl_table(path: str | Path) -> tuple[WhirlRow, ...]:
    """The rows of a speed × whirl table file, grouped by speed (a row per distinct speed, in
    the file's order of whirl frequencies), checked (:func:`check_whirl_rows`)."""
    import numpy as np

    t = read_table(path, WHIRL_TABLE_COLUMNS)
    cols = {k: np.asarray(v, float) for k, v in t.columns.items()}
    speed = np.abs(cols["speed_rpm"]) * (math.pi / 30)  # the rows of one |speed| together
    whirl = cols["whirl_rpm"] * (math.pi / 30)
    vals = np.column_stack([cols[c] for c in TABLE_COLUMNS[1:]])
    rows = []
    for s in dict.fromkeys(speed.tolist()):  # distinct speeds, in file order
        sel = speed == s
        rows.append((float(s), whirl[sel], vals[sel]))
    return check_whirl_rows(rows, file=str(path))


def check_whirl_rows(rows, *, file: str | None = None) -> tuple[WhirlRow, ...]:
    """Sort the rows by speed (distinct) and check them: whirl frequencies ≥ 0 and strictly
    increasing, each row covering its speed (the synchronous coefficients, whirl =
    speed, are read from it). One-line errors naming ``file``."""
    import numpy as np

    rpm = math.pi / 30
    rows = sorted(rows, key=lambda r: r[0])
    for s, w, _ in rows:
        if w[0] < 0 or np.any(np.diff(w) <= 0):
            raise ModelError(
                "the whirl frequencies of a speed must be >= 0 and strictly increasing",
                field="whirl_rpm",
                value=f"{(w / rpm).round(6).tolist()} at {s / rpm:.6g} rpm",
                expected="increasing whirl frequencies >= 0, each once per speed",
                file=file,
            )
        if w[0] > s * (1 + 1e-12) or w[-1] < s * (1 - 1e-12):
            raise ModelError(
                "the whirl frequencies of a speed must cover that speed (the synchronous "
                "coefficients, whirl = speed, are read from them)",
                field="whirl_rpm",
                value=f"{w[0] / rpm:.6g}..{w[-1] / rpm:.6g} rpm at {s / rpm:.6g} rpm",
                expected=f"whirl frequencies from <= {s / rpm:.6g} to >= {s / rpm:.6g} rpm",
                file=file,
            )
    return tuple(rows)
