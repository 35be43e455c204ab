"""The results cache (``gearrotor.cache``): fluid-film tables kept on disk between runs.

What must hold: a hit is bit for bit the solved result; the key follows the content (the same
bearing anywhere is one entry, a changed number a new one); a changed solver never reads an
old entry; two processes solve an entry once; a damaged entry or an unwritable folder never
stops an analysis; ``GEARROTOR_CACHE=off`` solves every time and writes nothing; a killed
writer's temporary is removed by the next writer.
"""

from __future__ import annotations

import multiprocessing
import os
import re
import time
from pathlib import Path

import numpy as np
import pytest

from fault_helpers import dead_pid, leftovers
from gearrotor import cache
from gearrotor.assembly import assemble
from gearrotor.io import load_model
from test_fluid_film_rotor import _model as rotor_model


@pytest.fixture
def folder(tmp_path, monkeypatch) -> Path:
    path = tmp_path / "cache"
    monkeypatch.setenv("GEARROTOR_CACHE_DIR", str(path))
    monkeypatch.delenv("GEARROTOR_CACHE", raising=False)
    return path


def _counting(calls: list, value: float = 1.0):
    def solve():
        calls.append(1)
        return {"values": np.array([[value, np.pi], [np.nextafter(1.0, 2.0), -0.0]])}

    return solve


def entries(folder: Path) -> list[Path]:
    return sorted(folder.rglob("*.npz"))


def test_a_hit_is_the_solved_result_bit_for_bit(folder):
    calls: list = []
    first = cache.arrays("t", ("a", (1.0, 2.0)), _counting(calls), sources=("cache.py",))
    second = cache.arrays("t", ("a", (1.0, 2.0)), _counting(calls), sources=("cache.py",))
    assert len(calls) == 1 and len(entries(folder)) == 1
    assert first["values"].tobytes() == second["values"].tobytes()  # -0.0 and 1 ulp kept
    cache.arrays("t", ("a", (1.0, 2.000000001)), _counting(calls), sources=("cache.py",))
    assert len(calls) == 2 and len(entries(folder)) == 2


def test_the_solver_sources_name_the_folder(folder):
    calls: list = []
    cache.arrays("t", ("a",), _counting(calls), sources=("cache.py",))
    cache.arrays("t", ("a",), _counting(calls), sources=("files.py",))
    assert len(calls) == 2
    assert len({p.parent for p in entries(folder)}) == 2
    assert cache._fingerprint(("bearings",)) != cache._fingerprint(("bearings", "elements"))


def test_off_solves_every_time_and_writes_nothing(folder, monkeypatch):
    monkeypatch.setenv("GEARROTOR_CACHE", "off")
    calls: list = []
    for _ in range(2):
        cache.arrays("t", ("a",), _counting(calls), sources=("cache.py",))
    assert len(calls) == 2 and not folder.exists()


def test_a_damaged_entry_is_solved_again_and_replaced(folder):
    calls: list = []
    cache.arrays("t", ("a",), _counting(calls), sources=("cache.py",))
    (path,) = entries(folder)
    path.write_bytes(b"PK\x03\x04 not a zip")
    again = cache.arrays("t", ("a",), _counting(calls, 2.0), sources=("cache.py",))
    assert len(calls) == 2 and again["values"][0, 0] == 2.0
    assert cache.arrays("t", ("a",), _counting(calls), sources=("cache.py",))["values"][0, 0] == 2
    assert len(calls) == 2


def test_an_unusable_folder_never_stops_the_analysis(tmp_path, monkeypatch):
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    monkeypatch.setenv("GEARROTOR_CACHE_DIR", str(blocker / "cache"))  # below a file
    calls: list = []
    out = cache.arrays("t", ("a",), _counting(calls), sources=("cache.py",))
    assert out["values"][0, 1] == np.pi and len(calls) == 1


def test_a_killed_writers_temporary_is_removed(folder):
    calls: list = []
    cache.arrays("t", ("a",), _counting(calls), sources=("cache.py",))
    (path,) = entries(folder)
    stale = path.with_name(f"x.npz.tmp-{dead_pid()}-abc123")
    stale.write_bytes(b"half")
    cache.arrays("t", ("b",), _counting(calls), sources=("cache.py",))
    assert not stale.exists()
    assert leftovers(folder) == []


def _slow_solver(marks: str):
    def solve():
        with open(marks, "a") as fh:
            fh.write("x")
        time.sleep(0.5)
        return {"values": np.arange(3.0)}

    return solve


def _worker(folder: str, marks: str) -> None:
    os.environ["GEARROTOR_CACHE_DIR"] = folder
    out = cache.arrays("t", ("shared",), _slow_solver(marks), sources=("cache.py",))
    assert out["values"].tolist() == [0.0, 1.0, 2.0]


def test_two_processes_solve_an_entry_once(folder, tmp_path):
    marks = tmp_path / "marks"
    ctx = multiprocessing.get_context("spawn")
    procs = [ctx.Process(target=_worker, args=(str(folder), str(marks))) for _ in range(2)]
    for p in procs:
        p.start()
    for p in procs:
        p.join(60)
    assert [p.exitcode for p in procs] == [0, 0]
    assert marks.read_text() == "x"


def _model(tmp_path: Path, bearing_text: str, sub: str) -> Path:
    where = tmp_path / sub
    where.mkdir()
    (where / "b.toml").write_text(bearing_text)
    ff = 'fluid_film = { file = "b.toml", load_case = 0, speeds = ["3000 rpm", "6000 rpm"] }'
    (where / "m.toml").write_text(rotor_model(4500, ff))
    return where / "m.toml"


def _film_K(path: Path) -> np.ndarray:
    from gearrotor import assembly

    assembly._solve_film_table.cache_clear()  # this process's memory: the disk cache is tested
    el = assemble(load_model(path)).bearings[0].element
    return np.stack([el.K(n * np.pi / 30) for n in (3000, 4500, 6000)])


def test_a_model_reads_its_bearing_table_by_content(folder, tmp_path, examples, monkeypatch):
    """The same bearing file in two folders is one entry (bit-identical stiffness); a changed
    clearance is a new one; with the cache off the model's matrices are the same."""
    text = (examples / "bearings" / "plain_ld1.toml").read_text()
    k1 = _film_K(_model(tmp_path, text, "one"))
    assert len(entries(folder)) == 1
    k2 = _film_K(_model(tmp_path, text, "two"))
    assert len(entries(folder)) == 1 and k1.tobytes() == k2.tobytes()
    clearance = re.search(r"^clearance\s*=.*$", text, flags=re.M)
    assert clearance, "plain_ld1.toml states its clearance"
    changed = text.replace(clearance.group(0), 'clearance = "0.11 mm"')
    assert changed != text
    k3 = _film_K(_model(tmp_path, changed, "three"))
    assert len(entries(folder)) == 2 and not np.allclose(k3, k1)
    monkeypatch.setenv("GEARROTOR_CACHE", "off")
    assert _film_K(_model(tmp_path, text, "four")).tobytes() == k1.tobytes()


def test_bounded_kinds_keep_the_most_recently_used(folder):
    """``max_bytes``: a new entry that takes the kind over it removes the least recently used
    (a hit counts as a use; the entry just written stays), across the kind's fingerprints."""
    size = 20_000  # bytes of each entry's array (its .npz a little more)

    def solve(k):
        return lambda: {"png": np.full(size, k, np.uint8)}

    def get(k, calls=None):
        def counted():
            if calls is not None:
                calls.append(k)
            return solve(k)()

        return cache.arrays("fig", ("f", k), counted, sources=("cache.py",), max_bytes=2.5 * size)

    get(0)
    time.sleep(0.01)
    get(1)
    time.sleep(0.01)
    get(0)  # a hit: 0 is now the most recently used
    time.sleep(0.01)
    get(2)  # over the bound: 1 goes
    calls: list = []
    for k in (0, 2, 1):
        assert int(get(k, calls)["png"][0]) == k
    assert calls == [1]  # 0 and 2 were kept, 1 solved again
    entries = list((folder / "fig").glob("*/*.npz"))
    assert sum(p.stat().st_size for p in entries) <= 2.5 * size + 2 * 1024
    locks = {p.stem for p in (folder / "fig").glob("*/*.lock")}
    assert locks <= {p.stem for p in entries}  # a removed entry's lock file went with it
    # unbounded kinds are never pruned
    for k in range(4):
        cache.arrays("table", ("t", k), solve(k), sources=("cache.py",))
    assert len(list((folder / "table").glob("*/*.npz"))) == 4
