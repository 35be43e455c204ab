"""TOML model files.

A model file maps one-to-one onto :class:`gearrotor.model.Train`: top-level keys are the train's
fields (``name``, ``reference_shaft``, ``speed``, ``[materials.NAME]``, ``[[shafts]]``,
``[[bearings]]``, ``[[meshes]]``, ...). Values are plain numbers (SI) or strings with units.
Unknown keys are errors. Every error names the file, the field, the value and what was expected.
"""

from __future__ import annotations

import copy
import difflib
import re
import tomllib
import typing
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ValidationError

from ..errors import ModelError
from ..inputs import (
    MAX_LISTED,
    WHIRL_TABLE_COLUMNS,
    read_table,
    read_toml,
    read_whirl_table,
    table_columns,
)
from ..model import Train

__all__ = [
    "load_model",
    "model_from_file_data",
    "model_from_dict",
    "apply_overrides",
    "format_validation_error",
    "model_field_paths",
    "parse_overrides",
]

_PATH_TOKEN = re.compile(r"([^.\[\]]+)|\[(\d+)\]")


def _loc_to_path(loc: tuple) -> str:
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        elif isinstance(part, str) and re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", part):
            out += f".{part}" if out else part
        # union/validator tags such as 'function-before[...]' are dropped
    return out or "(top level)"


def _lookup(data: Any, loc: tuple) -> Any:
    cur = data
    for part in loc:
        try:
            cur = cur[part]
        except (KeyError, IndexError, TypeError):
            return None
    return cur


_UNION_TYPES = frozenset({"model_type", "dict_type", "model_attributes_type"})


def format_validation_error(
    exc: ValidationError, data: dict, file: str | None, what: str = "the model"
) -> ModelError:
    """Turn a pydantic error into one :class:`ModelError` listing the problems (at most
    :data:`~gearrotor.inputs.MAX_LISTED` of them, then how many more; unknown keys of one table
    are listed together)."""
    lines = []
    seen = set()
    unknown: dict[str, list[str]] = {}
    errors = exc.errors(include_url=False)
    # a union field (a number or a table): when the number branch explains the error, drop the
    # table branch's "should be a valid dictionary"
    explained = {_loc_to_path(e["loc"]) for e in errors if e["type"] not in _UNION_TYPES}
    errors = [
        e
        for e in errors
        if e["type"] not in _UNION_TYPES or _loc_to_path(e["loc"]) not in explained
    ]
    for err in errors:
        if err["type"] == "extra_forbidden" and err["loc"]:
            parent = _loc_to_path(err["loc"][:-1]) if len(err["loc"]) > 1 else "(top level)"
            if parent not in unknown:
                unknown[parent] = []
                lines.append(("unknown", parent))
            unknown[parent].append(str(err["loc"][-1]))
            continue
        path = _loc_to_path(err["loc"])
        msg = err["msg"].removeprefix("Value error, ")
        if err["type"] == "extra_forbidden":
            msg = "unknown key (not a field of this table; check the spelling)"
        if err["type"] == "missing":
            msg = "required field is missing"
        key = (path, msg)
        if key in seen:
            continue
        seen.add(key)
        value = err.get("input") if err["type"] != "missing" else None
        if isinstance(value, dict):
            value = None
        text = f"{path}: {msg}"
        if value is not None and err["type"] != "extra_forbidden":
            shown = repr(value)
            text += f" (got {shown if len(shown) <= 80 else shown[:77] + '...'})"
        lines.append(text)
    for k, line in enumerate(lines):
        if isinstance(line, tuple):
            keys = unknown[line[1]]
            if len(keys) == 1:
                path = keys[0] if line[1] == "(top level)" else f"{line[1]}.{keys[0]}"
                lines[k] = f"{path}: unknown key (not a field of this table; check the spelling)"
            else:
                lines[k] = (
                    f"{line[1]}: {len(keys)} unknown keys {_list_some(keys)} (not fields of "
                    "this table; check the spelling)"
                )
    n = len(lines)
    if n > MAX_LISTED:
        lines = [*lines[:MAX_LISTED], f"... and {n - MAX_LISTED} more"]
    if n == 1:
        return ModelError(lines[0], file=file)
    # one line, like every error message (the README's promise): the problems joined by "; "
    return ModelError(f"{n} errors in {what}: " + "; ".join(lines), file=file or None)


def _list_some(keys: list[str]) -> str:
    from ..inputs import list_some

    return list_some([repr(k) for k in keys])


def _parse_path(path: str) -> list[str | int]:
    parts: list[str | int] = []
    pos = 0
    for m in _PATH_TOKEN.finditer(path):
        if m.group(1) is not None:
            parts.append(int(m.group(1)) if m.group(1).isdigit() else m.group(1))
        else:
            parts.append(int(m.group(2)))
        pos = m.end()
    if not parts or pos != len(path):
        raise ModelError(
            "cannot read the override path",
            field=path,
            expected="a dotted path such as 'meshes[0].variation.ka_ratio'",
        )
    return parts


def _coerce(value: str) -> Any:
    """A --set value: TOML scalar syntax if it parses (numbers, booleans, arrays), else a string."""
    from ..inputs import MAX_DEPTH, depth_ok

    try:
        out = tomllib.loads(f"v = {value}")["v"]
    except tomllib.TOMLDecodeError:
        return value
    except RecursionError:
        out = None
    if out is None or not depth_ok(out):
        shown = value if len(value) <= 40 else value[:37] + "..."
        raise ModelError(
            "the value nests arrays or tables too deeply",
            field="--set",
            value=shown,
            expected=f"at most {MAX_DEPTH} levels",
        )
    return out


def parse_overrides(items: list[str] | None) -> dict[str, str]:
    """``--set`` options ``["meshes[0].variation.ka_ratio=0.2", ...]`` → {path: value}."""
    out = {}
    for item in items or []:
        if "=" not in item:
            raise ModelError(
                "a --set option needs PATH=VALUE",
                field="--set",
                value=item,
                expected="e.g. meshes[0].variation.ka_ratio=0.2",
            )
        key, value = item.split("=", 1)
        out[key.strip()] = value.strip()
    return out


def apply_overrides(data: dict, overrides: dict[str, Any] | None) -> dict:
    """Return a copy of ``data`` with values replaced by dotted path.

    Paths use the model's field names: ``speed``, ``meshes[0].variation.ka_ratio`` (``meshes.0``
    works too), ``unbalances[1].amount``. String values are read as TOML scalars when they parse
    (``"0.2"`` → 0.2) and kept as strings otherwise (``"720 g*mm"``).
    """
    if not overrides:
        return data
    data = copy.deepcopy(data)
    for path, value in overrides.items():
        parts = _parse_path(path)
        cur: Any = data
        for k, part in enumerate(parts[:-1]):
            nxt = parts[k + 1]
            try:
                cur = cur[part]
            except (KeyError, IndexError, TypeError):
                if isinstance(cur, dict) and isinstance(part, str) and not isinstance(nxt, int):
                    cur[part] = {}
                    cur = cur[part]
                else:
                    raise ModelError(
                        "override path does not exist in the model",
                        field=path,
                        value=value,
                        expected="an existing table or list index",
                    ) from None
        last = parts[-1]
        if isinstance(last, int):
            if not isinstance(cur, list) or last >= len(cur):
                raise ModelError("override index out of range", field=path, value=value)
        elif not isinstance(cur, dict):
            raise ModelError("override path does not name a table field", field=path, value=value)
        cur[last] = _coerce(value) if isinstance(value, str) else value
    return data


def model_from_dict(data: dict, *, file: str | None = None) -> Train:
    """Validate a model given as nested dicts (as read from TOML) and resolve its layout."""
    try:
        train = Train.model_validate(data)
    except ValidationError as exc:
        raise format_validation_error(exc, data, file) from None
    try:
        train.layout()
    except ModelError as exc:
        raise exc.with_file(file) if file else exc from None
    return train


def load_model(path: str | Path, overrides: dict[str, Any] | None = None) -> Train:
    """Read, override and validate a TOML model file."""
    path = Path(path)
    return model_from_file_data(read_toml(path, "model"), path, overrides)


def model_from_file_data(data: dict, path: str | Path, overrides: dict | None = None) -> Train:
    """The model of a model file's parsed content ``data`` (as :func:`load_model` reads it):
    overrides applied, relative paths resolved against the file's folder, validated, and the
    table and bearing files it points to read. ``data`` is not modified."""
    path = Path(path)
    name = str(path)
    if not data:
        raise ModelError(
            "the model file is empty",
            file=name,
            expected="a model (see docs/model_format.md)",
        )
    if "shafts" not in data:
        other = (
            "a bearing file" if "bearing" in data else "a study file" if "cases" in data else None
        )
        if other:
            raise ModelError(
                f"this is {other}, not a rotor model file",
                file=name,
                expected="a model file with [[shafts]] (see docs/model_format.md)",
            )
    original = data
    try:
        data = apply_overrides(data, overrides)
        if not overrides:  # apply_overrides copies only when it changes something
            data = copy.deepcopy(data)
        _resolve_paths(data, path.parent)
        train = model_from_dict(data, file=name)
    except ModelError as exc:
        hint = override_path_error(original, overrides)
        raise (hint or exc).with_file(name) from None
    _check_files(train, name)
    _check_gear_files(train, name)
    return train


def _canonical(parts: list[str | int]) -> str:
    out = ""
    for part in parts:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else part)
    return out


def _field_models(annotation: Any) -> list[tuple[str, type[BaseModel]]]:
    """The model classes a field annotation holds, each with how it is reached: ``""``
    (directly or in a union), ``"[]"`` (items of a list) or ``"{}"`` (values of a table)."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [("", annotation)]
    origin, out = typing.get_origin(annotation), []
    for arg in typing.get_args(annotation):
        kind = "[]" if origin in (list, tuple) else "{}" if origin is dict else ""
        out += [(kind or k, m) for k, m in _field_models(arg)]
    return out


def model_field_paths(data: dict, cls: type[BaseModel] = Train) -> set[str]:
    """Every dotted path ``--set`` can name in a model given as nested dicts: the fields of
    ``cls`` (recursively, also those of optional tables the data leaves out), with the list
    indices and table keys the data has (``meshes[0].variation.ka_ratio``,
    ``materials.steel.E``). A field that is a table or a number (``meshes[0].stiffness``) is a
    path itself."""
    paths: set[str] = set()

    def walk(model: type[BaseModel], value: Any, prefix: str, depth: int) -> None:
        if depth > 12:
            return
        for name, field in model.model_fields.items():
            path = f"{prefix}.{name}" if prefix else name
            paths.add(path)
            sub = value.get(name) if isinstance(value, dict) else None
            for kind, inner in _field_models(field.annotation):
                if kind == "[]":
                    items = sub if isinstance(sub, list) else []
                    for k, item in enumerate(items):
                        paths.add(f"{path}[{k}]")
                        walk(inner, item, f"{path}[{k}]", depth + 1)
                elif kind == "{}":
                    for key, item in (sub if isinstance(sub, dict) else {}).items():
                        paths.add(f"{path}.{key}")
                        walk(inner, item, f"{path}.{key}", depth + 1)
                else:
                    walk(inner, sub, path, depth + 1)

    walk(cls, data, "", 0)
    return paths


def override_path_error(data: dict, overrides: dict[str, Any] | None) -> ModelError | None:
    """The error of the first ``--set`` path that names no field of the model ``data``, with
    the closest field paths (``did you mean``), or ``None`` when every path names one. An index
    past the end of a list names the list's length instead."""
    if not overrides:
        return None
    valid = model_field_paths(data)
    for path, value in overrides.items():
        try:
            parts = _parse_path(path)
        except ModelError:
            return None  # apply_overrides already says so
        canonical = _canonical(parts)
        if canonical in valid:
            continue
        # a list index past the end of a list the model has
        for k, part in enumerate(parts):
            if isinstance(part, int) and _canonical(parts[:k]) in valid:
                if _canonical(parts[: k + 1]) in valid:
                    continue
                entry = re.compile(re.escape(_canonical(parts[:k])) + r"\[\d+\]")
                n = sum(1 for p in valid if entry.fullmatch(p))
                return ModelError(
                    "override index out of range",
                    field=path,
                    value=value,
                    expected=f"an index 0..{n - 1} (the model has {n})"
                    if n
                    else "a list the model has (this one is empty)",
                )
        depth = len(parts)
        same = sorted(p for p in valid if len(_parse_path(p)) == depth)
        close = difflib.get_close_matches(canonical, same, n=1, cutoff=0.7)
        close = close or difflib.get_close_matches(canonical, sorted(valid), n=1, cutoff=0.7)
        if not close:
            continue
        return ModelError(
            "no such field in the model",
            field=path,
            value=value,
            expected=f"a field of the model: did you mean {close[0]!r}?",
        )
    return None


def _check_files(train: Train, file: str) -> None:
    """Read the table and bearing files the model points to, before anything runs: an error
    names the model file, the field and the file it points to."""
    for group in ("bearings", "seals"):
        for k, b in enumerate(getattr(train, group, None) or []):
            table, ff = getattr(b, "table_file", None), getattr(b, "fluid_film", None)
            field = f"{group}[{k}].table_file" if table is not None else f"{group}[{k}].fluid_film"
            try:
                if table is not None:
                    if table_columns(table) == WHIRL_TABLE_COLUMNS:
                        _check_whirl(read_whirl_table(table), b, f"{group}[{k}]", table)
                    else:
                        read_table(table)
                if ff is not None:
                    read_toml(ff.file, "bearing")
            except ModelError as exc:
                raise ModelError(str(exc), field=field, file=file) from None
            inline = getattr(b, "table", None)
            if inline is not None and inline.whirl is not None and inline.whirl_dependent:
                try:
                    _check_whirl(inline.whirl_rows(), b, f"{group}[{k}].table", None)
                except ModelError as exc:
                    raise exc.with_file(file) from None
            seal_file = getattr(b, "file", None)
            if seal_file is not None:  # a seal file: read here, its fields checked at assembly
                try:
                    read_toml(seal_file, "seal")
                except ModelError as exc:
                    raise ModelError(str(exc), field=f"{group}[{k}].file", file=file) from None


def _check_whirl(rows, entry, field: str, file: str | None) -> None:
    """A speed × whirl table's rows fitted within the entry's ``fit_tolerance`` (the fits are
    kept for the assembly, :func:`gearrotor.elements.fit_row`)."""
    import numpy as np

    from ..elements.whirl_bearing import fit_rows

    if all(np.all(v == v[0]) for _, _, v in rows):
        return  # constant in whirl: a speed table
    fit_rows(rows, entry.fit_tolerance, field=field, file=file)


def _check_gear_files(train: Train, file: str) -> None:
    """Read the gear-pair files the meshes point to (their keys are checked at assembly)."""
    for k, m in enumerate(train.meshes):
        if m.geometry is not None and m.geometry.file is not None:
            try:
                read_toml(m.geometry.file, "gear-pair")
            except ModelError as exc:
                raise ModelError(str(exc), field=f"meshes[{k}].geometry.file", file=file) from None


def _resolve_paths(data: dict, base: Path) -> None:
    """Make the bearing files of a model absolute, relative to the model file's folder."""
    items = [
        b
        for group in ("bearings", "seals")
        for b in (data.get(group) if isinstance(data.get(group), list) else [])
    ]
    for b in items:
        if not isinstance(b, dict):
            continue
        if isinstance(b.get("table_file"), str):
            b["table_file"] = str((base / b["table_file"]).resolve())
        if isinstance(b.get("file"), str):  # a [[seals]] seal file
            b["file"] = str((base / b["file"]).resolve())
        ff = b.get("fluid_film")
        if isinstance(ff, dict) and isinstance(ff.get("file"), str):
            ff["file"] = str((base / ff["file"]).resolve())
    for m in data.get("meshes") if isinstance(data.get("meshes"), list) else []:
        geo = m.get("geometry") if isinstance(m, dict) else None
        if isinstance(geo, dict) and isinstance(geo.get("file"), str):  # a gear-pair file
            geo["file"] = str((base / geo["file"]).resolve())
