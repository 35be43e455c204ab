"""Benchmark: how fast the command line answers an input error and ``--help`` (issue 28).

    python3 benchmarks/startup.py [--before SRC] [--repeat 7]

Times whole processes (best of ``--repeat``, so that a loaded machine's noise does not decide):
``python -c "import numpy, scipy.sparse"`` (the reference), ``gearrotor --help``, ``gearrotor
modal`` on a missing model file, and on a model with a bad field; with ``--before SRC`` the
same commands with that ``src`` folder on PYTHONPATH, interleaved. Prints each time and its
ratio to the reference (goal: an input error within 2.5x).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _machine import cpu_name

ROOT = Path(__file__).resolve().parents[1]


def _time(args: list[str], src: Path) -> float:
    env = dict(os.environ, PYTHONPATH=str(src))
    t0 = time.perf_counter()
    subprocess.run(args, env=env, cwd=ROOT, capture_output=True)
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", type=Path, help="an older src/ folder to compare with")
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    trees = {"after": ROOT / "src"}
    if args.before:
        trees = {"before": args.before.resolve(), **trees}
    py = sys.executable
    with tempfile.TemporaryDirectory() as tmp:
        bad = Path(tmp) / "bad.toml"
        text = (ROOT / "examples" / "unity_gearbox.toml").read_text()
        bad.write_text(text.replace("elements = ", "elements = -", 1))
        cases = {
            "import numpy, scipy.sparse (reference)": [py, "-c", "import numpy, scipy.sparse"],
            "gearrotor --help": [py, "-m", "gearrotor", "--help"],
            "modal on a missing model file": [py, "-m", "gearrotor", "modal", f"{tmp}/no.toml"],
            "modal on a bad field": [py, "-m", "gearrotor", "modal", str(bad)],
        }
        best: dict[tuple[str, str], float] = {}
        for _ in range(args.repeat):
            for name, argv in cases.items():
                for tree, src in trees.items():
                    dt = _time(argv, src)
                    best[(name, tree)] = min(best.get((name, tree), float("inf")), dt)
    print(f"machine: {cpu_name()}; load average {os.getloadavg()[0]:.1f}; best of {args.repeat}")
    ref = {t: best[(next(iter(cases)), t)] for t in trees}
    print("| process | " + " | ".join(f"{t} s | {t} / reference" for t in trees) + " |")
    print("|---|" + "---|---|" * len(trees))
    for name in cases:
        cells = [f"{best[(name, t)]:.3f} | {best[(name, t)] / ref[t]:.2f}" for t in trees]
        print(f"| {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
