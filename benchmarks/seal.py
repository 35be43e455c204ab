"""Benchmark: the cost of a seal per speed (issue 24: at most 0.1 s per speed).

Every example seal file (examples/seals/) at 8 speeds, synchronous whirl: the first speed
(which, for a labyrinth, also solves the speed-independent leakage and, for a real gas,
tabulates CoolProp's properties) and the median of the others, best of ``--repeat`` runs.

    python benchmarks/seal.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from _machine import cpu_name  # noqa: E402

from gearrotor.seals import coefficients as _coefficients  # noqa: E402
from gearrotor.seals import coolprop_available, load_seal, seal_coefficients  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "seals"
SPEEDS_RPM = (2000, 4000, 6000, 8000, 10000, 12000, 14000, 16000)


def _clear_caches() -> None:
    from gearrotor.seals import annular

    _coefficients._labyrinth_flow_cached.cache_clear()
    annular._annular_flow.cache_clear()


def time_file(path: Path, repeat: int) -> tuple[float, float, float]:
    """(load s, first speed s, median of the other speeds s), best of ``repeat``."""
    best = (math.inf, math.inf, math.inf)
    for _ in range(repeat):
        _clear_caches()
        t0 = time.perf_counter()
        seal = load_seal(path)
        t1 = time.perf_counter()
        times = []
        for rpm in SPEEDS_RPM:
            s0 = time.perf_counter()
            seal_coefficients(seal, rpm * math.pi / 30)
            times.append(time.perf_counter() - s0)
        run = (t1 - t0, times[0], statistics.median(times[1:]))
        best = tuple(min(a, b) for a, b in zip(best, run, strict=True))
    return best


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="timing repeats (best is reported)")
    args = ap.parse_args(argv)
    print(
        f"machine : {platform.node()} | {cpu_name()} | {os.cpu_count()} cpus | "
        f"Python {platform.python_version()}"
    )
    print(f"speeds  : {', '.join(str(s) for s in SPEEDS_RPM)} rpm, synchronous whirl\n")
    print(f"{'seal file':<34} {'type':<15} {'load s':>8} {'1st speed s':>12} {'per speed s':>12}")
    worst = 0.0
    for path in sorted(EXAMPLES.glob("*.toml")):
        text = path.read_text()
        if "shafts" in text:  # the rotor model
            continue
        if "composition" in text and not coolprop_available():
            print(f"{path.name:<34} (CoolProp not installed: skipped)")
            continue
        load, first, per = time_file(path, args.repeat)
        kind = load_seal(path).kind
        worst = max(worst, first, per)
        print(f"{path.name:<34} {kind:<15} {load:>8.3f} {first:>12.4f} {per:>12.4f}")
    print(f"\nslowest speed: {worst:.4f} s (target <= 0.1 s per speed)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
