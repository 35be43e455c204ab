"""Benchmark: API 617 Level I's continuation, the targeted step against the full solve per step.

Run: ``python3 benchmarks/level1.py``. For the steam turbine (examples/steam_turbine_gearbox.toml)
at each operating point LC1..LC10 (its [api_audit] inputs, Q_A at the pinion), Level I with the
targeted continuation step (every eigenvalue by the QR algorithm without eigenvectors, the
eigenvectors of the modes the step reads by inverse iteration) and with a full eigen-solve at every
step (``stability._TARGETED = False``), in the same run: the CPU time of each (this process's, the
least of ``REPEAT`` runs: on a shared machine the wall time also counts the other processes'
turns), the solves and how many were targeted, and the largest relative difference of Q_0, the
log dec at Q_A and the followed mode's frequency at Q_A between the two.
"""

from __future__ import annotations

import platform
import time
from pathlib import Path

import numpy as np
from _machine import cpu_name, environment

from gearrotor.analyses.audit import stability
from gearrotor.analyses.audit.stability_audit import level1_inputs, level2_speeds
from gearrotor.analyses.static.operating_point import model_at_operating_point
from gearrotor.io import load_model
from gearrotor.model.speed_range import model_max_continuous_speed

MODEL = Path(__file__).resolve().parents[1] / "examples" / "steam_turbine_gearbox.toml"
REPEAT = 2


def _rel(a, b) -> float:
    if a is None or b is None:
        return 0.0 if a is b else float("inf")
    return abs(a - b) / max(abs(b), 1e-300)


def _timed(train, kw, targeted: bool):
    """(least CPU time, result, follower) of Level I with or without the targeted step."""
    stability._TARGETED = targeted
    made = []
    real_init = stability._Follower.__init__

    def init(self, *args, **kwargs):
        real_init(self, *args, **kwargs)
        made.append(self)

    stability._Follower.__init__ = init
    try:
        best, res = np.inf, None
        for _ in range(REPEAT):
            t0 = time.process_time()
            res = stability.level1(train, **kw)
            best = min(best, time.process_time() - t0)
    finally:
        stability._Follower.__init__ = real_init
        stability._TARGETED = True
    return best, res, made[-1]


def main() -> None:
    print(f"machine: {cpu_name()}, {platform.python_version()}; {environment()}")
    steam = load_model(MODEL)
    mcs = model_max_continuous_speed(steam, "Level I")
    speeds = sorted({float(abs(w)) for w in [mcs, *level2_speeds(steam)]})
    head = (
        f"{'point':>6} {'full s':>7} {'targeted s':>10} {'ratio':>6} {'solves':>6} "
        f"{'targeted':>8} {'Q_0 rel':>8} {'log dec rel':>11} {'freq rel':>8}"
    )
    print(head)
    print("-" * len(head))
    total = np.zeros(2)
    worst = 0.0
    for op in steam.operating_points:
        train = model_at_operating_point(steam, op.name, speeds)[0]
        kw = level1_inputs(train)
        t_full, full, _ = _timed(train, kw, False)
        t_fast, fast, f = _timed(train, kw, True)
        total += (t_full, t_fast)
        diffs = (
            _rel(fast.threshold_q, full.threshold_q),
            _rel(fast.log_dec_at_qa, full.log_dec_at_qa),
            _rel(fast.mode_at_qa["frequency_rpm"], full.mode_at_qa["frequency_rpm"]),
        )
        worst = max(worst, *diffs)
        assert fast.verdict == full.verdict
        print(
            f"{op.name:>6} {t_full:7.3f} {t_fast:10.3f} {t_full / t_fast:6.2f} "
            f"{f.n_solves:6d} {f.n_targeted:8d} {diffs[0]:8.1e} {diffs[1]:11.1e} {diffs[2]:8.1e}"
        )
    print("-" * len(head))
    print(
        f"{'all':>6} {total[0]:7.3f} {total[1]:10.3f} {total[0] / total[1]:6.2f}"
        f"{'':>16} largest relative difference {worst:.1e}; verdicts equal"
    )


if __name__ == "__main__":
    main()
