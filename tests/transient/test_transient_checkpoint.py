"""Checkpoints of the transient (issue 17 "Faults"): written every 5 % of the simulated time by
default (a run killed at 57 % loses at most 5 %, not everything as with the former
once-a-minute wall-clock rule), at a settable simulated interval (``--checkpoint-every``) or
wall-clock interval; a resumed run is bit-identical to an uninterrupted one; a damaged
checkpoint is an input error naming the file (exit 2), not a traceback.

The model is the SPEC 6.1 gearbox with 4 elements per shaft, RK4 at dt = 20 µs saved every
0.2 ms (10 steps), 0.2 s: 10 000 steps, a second per run.
"""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

from gearrotor.analyses.transient import RK4, Checkpoint, Save, driver, transient
from gearrotor.cli import app
from gearrotor.errors import ModelError

T_END, DT, SAVE_DT = 0.2, 2e-5, 2e-4
KW = dict(t_end=T_END, integrator=RK4(dt=DT), save=Save(dt=SAVE_DT))


@pytest.fixture(scope="module")
def train(make_gearbox):
    return make_gearbox(elements=4)


@pytest.fixture(scope="module")
def reference(train):
    return transient(train, **KW)


@pytest.fixture
def writes(monkeypatch):
    """The simulated times at which checkpoints are written (the files are written too)."""
    times: list[float] = []
    real = driver._write_npz_atomic

    def spy(path, **arrays):
        times.append(int(arrays["step"]) * DT)
        real(path, **arrays)
        assert path.exists()

    monkeypatch.setattr(driver, "_write_npz_atomic", spy)
    return times


@pytest.mark.parametrize(
    ("simulated", "expected"),
    [
        (None, [0.01 * k for k in range(1, 20)]),  # default: 5 % of t_end, 19 before the end
        (0.03, [0.03 * k for k in range(1, 7)]),
        (0.03009, [0.03 * k for k in range(1, 7)]),  # rounded to whole save intervals (0.2 ms)
        (0.1, [0.1]),  # longer than a chunk (0.05 s): whole chunks
        (0.07, [0.05, 0.10, 0.15]),
    ],
)
def test_cadence_in_simulated_time(train, writes, tmp_path, simulated, expected):
    ck = Checkpoint(tmp_path / "run.npz", every=1e9, simulated=simulated)
    transient(train, checkpoint=ck, **KW)
    np.testing.assert_allclose(writes, expected, rtol=0, atol=DT / 2)
    assert not ck.path.exists()  # removed at the end


def test_whole_chunk_interval_is_bit_identical_to_no_checkpoint(train, reference, tmp_path):
    res = transient(train, checkpoint=Checkpoint(tmp_path / "run.npz", simulated=0.05), **KW)
    for name in ("time", "final_q", "node_x", "shaft_speed"):
        np.testing.assert_array_equal(getattr(res, name), getattr(reference, name), name)


def test_cadence_in_wall_time(train, writes, tmp_path):
    """``every = 0`` (wall seconds) writes at the end of every chunk (0.05 s of simulated time)."""
    transient(train, checkpoint=Checkpoint(tmp_path / "run.npz", every=0.0, simulated=1.0), **KW)
    np.testing.assert_allclose(writes, [0.05, 0.10, 0.15], atol=DT / 2)


def test_killed_at_57_percent_loses_less_than_5_percent(train, tmp_path, monkeypatch):
    """The issue's case: a run stopped at 57 % of t_end resumes from the last checkpoint
    (55 %) and ends bit-identical to an uninterrupted run with the same checkpoints."""
    reference = transient(train, checkpoint=Checkpoint(tmp_path / "ref.npz"), **KW)
    ck = Checkpoint(tmp_path / "run.npz", every=1e9)
    real = driver.kn.rk4_physical

    def dies_at_57_percent(t0, dt, nst, *args):  # in the chunk that would pass 57 %
        if t0 + nst * dt > 0.57 * T_END:
            raise KeyboardInterrupt
        return real(t0, dt, nst, *args)

    monkeypatch.setattr(driver.kn, "rk4_physical", dies_at_57_percent)
    with pytest.raises(KeyboardInterrupt):
        transient(train, checkpoint=ck, **KW)
    monkeypatch.setattr(driver.kn, "rk4_physical", real)
    res = transient(train, checkpoint=ck, **KW)
    n_steps = round(T_END / DT)
    resumed_at = n_steps - res.stats.rhs_evaluations // 4
    assert resumed_at * DT == pytest.approx(0.55 * T_END, abs=DT / 2)
    np.testing.assert_array_equal(res.final_q, reference.final_q)
    np.testing.assert_array_equal(res.node_x, reference.node_x)
    np.testing.assert_array_equal(res.time, reference.time)


@pytest.mark.parametrize(
    ("content", "needle"),
    [
        (b"not a checkpoint at all", "cannot be read"),
        (b"", "cannot be read"),
        ("TRUNCATED", "cannot be read"),
        ("NO_FINGERPRINT", "no fingerprint"),
        ("WRONG_SHAPES", "does not fit this run"),
    ],
)
def test_damaged_checkpoint_is_an_input_error(train, tmp_path, monkeypatch, content, needle):
    path = tmp_path / "run.npz"
    if content == "TRUNCATED":  # a real checkpoint cut in half (a crash of an old writer)
        _real_checkpoint(train, path, monkeypatch)
        data = path.read_bytes()
        path.write_bytes(data[: len(data) // 2])
    elif content == "NO_FINGERPRINT":
        np.savez(path, step=3)
    elif content == "WRONG_SHAPES":  # this run's fingerprint, arrays of another size
        _real_checkpoint(train, path, monkeypatch)
        with np.load(path) as z:
            arrays = {k: z[k] for k in z.files}
        arrays["q"] = arrays["q"][:-1]
        np.savez(path, **arrays)
    else:
        path.write_bytes(content)
    with pytest.raises(ModelError, match=needle) as ei:
        transient(train, checkpoint=Checkpoint(path), **KW)
    assert str(ei.value).startswith(f"{path}: ")
    assert "delete the file to start from t = 0" in str(ei.value)


def _real_checkpoint(train, path, monkeypatch):
    """Leave the checkpoint a run writes at 10 % of t_end."""
    real = driver.kn.rk4_physical

    def stop(t0, *args):
        if t0 >= 0.1 * T_END - DT / 2:
            raise KeyboardInterrupt
        return real(t0, *args)

    monkeypatch.setattr(driver.kn, "rk4_physical", stop)
    with pytest.raises(KeyboardInterrupt):
        transient(train, checkpoint=Checkpoint(path, every=1e9), **KW)
    monkeypatch.setattr(driver.kn, "rk4_physical", real)
    assert path.exists()


def test_cli_damaged_checkpoint_and_bad_options(examples, tmp_path, monkeypatch):
    model = str(examples / "unity_gearbox_single_shaft.toml")
    ck = tmp_path / "run.npz"
    ck.write_bytes(b"\x00" * 100)
    r = CliRunner().invoke(
        app, ["transient", model, "--t-end", "0.01", "--checkpoint", str(ck), "--no-progress"]
    )
    assert r.exit_code == 2, (r.output, r.exception)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {ck}: the checkpoint cannot be read")

    def must_not_run(*a, **k):
        raise AssertionError("the options were not checked before the run")

    monkeypatch.setattr("gearrotor.io.load_model", must_not_run)
    for args, field in (
        (["--checkpoint", str(ck), "--checkpoint-every", "0"], "--checkpoint-every"),
        (["--checkpoint", str(ck), "--checkpoint-every", "nan"], "--checkpoint-every"),
        (["--checkpoint", str(ck), "--checkpoint-wall", "-1"], "--checkpoint-wall"),
        (["--checkpoint-every", "0.1"], "--checkpoint-every"),  # without a checkpoint file
    ):
        r = CliRunner().invoke(app, ["transient", model, *args])
        assert r.exit_code == 2, (args, r.output, r.exception)
        assert r.stderr.startswith(f"error: {field}: "), r.stderr
        assert len(r.stderr.strip().splitlines()) == 1
