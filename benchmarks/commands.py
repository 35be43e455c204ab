"""Benchmark: the long commands as a user runs them (issue 28's table), idle and next to a busy
process, optionally against another source tree in the same run.

    python3 benchmarks/commands.py [--before SRC] [--pinned] [--repeat N] [--only NAME ...]
                                   [--suite]

Each command is run as ``python -m gearrotor ...`` in the default environment (the thread
variables OMP/OPENBLAS/MKL_NUM_THREADS and GEARROTOR_THREADS removed, as on a fresh
machine), first on the machine as it is ("idle"), then next to one busy process (``python -c
"while True: pass"``, started and stopped by this script). ``--before SRC`` runs every command
with that ``src`` folder on PYTHONPATH too (e.g. a ``git archive`` of an older commit), each
pair one after the other, so that the ratio holds when the machine's load drifts; ``--pinned``
adds a column with BLAS pinned to one thread (OPENBLAS_NUM_THREADS=1). ``--suite`` adds the
test suite (``python -m pytest -n 2 -q -x``; minutes). Prints a table with the load average
before each row (other sessions on a shared machine load it: compare within a row).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _machine import busy_neighbour, cpu_name

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"
THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "GEARROTOR_THREADS")


def commands(out: Path) -> dict[str, list[str]]:
    """The issue's table: name -> arguments of ``python -m gearrotor``."""
    st = str(EX / "steam_turbine_gearbox.toml")
    fl = str(EX / "unity_gearbox.toml")
    return {
        "stability steam turbine": ["stability", st],
        "campbell flagship (60 speeds)": [
            "campbell",
            fl,
            "--max-speed",
            "12000",
            "--max-frequency",
            "80000",
        ],
        "ucs steam turbine": ["ucs", st],
        "static --all steam turbine": ["static", st, "--all"],
        "report flagship": ["report", fl, "-o", str(out / "report")],
        # docs/audit.md's audit report (API 617 audit, torsional, every operating point)
        "report steam turbine audit": [
            "report",
            st,
            "-o",
            str(out / "audit"),
            "--operating-point",
            "LC10",
            "--analyses",
            "modal,campbell,unbalance,audit,torsional",
            "--all-operating-points",
        ],
    }


def _env(src: Path, pinned: bool) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in THREAD_VARS}
    env["PYTHONPATH"] = str(src)
    if pinned:
        env.update(OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
    return env


def _run(args: list[str], src: Path, pinned: bool, cwd: Path) -> float:
    t0 = time.perf_counter()
    p = subprocess.run(
        args, env=_env(src, pinned), cwd=cwd, capture_output=True, text=True, timeout=3600
    )
    dt = time.perf_counter() - t0
    if p.returncode != 0:
        tail = (p.stderr or p.stdout).strip().splitlines()[-3:]
        raise SystemExit(f"{' '.join(args)} failed ({p.returncode}): " + " | ".join(tail))
    return dt


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", type=Path, help="an older src/ folder to compare with")
    ap.add_argument("--after", type=Path, help="the src/ folder to measure (default: this tree's)")
    ap.add_argument("--pinned", action="store_true", help="add a column with 1 BLAS thread")
    ap.add_argument("--repeat", type=int, default=1, help="runs per cell (the median is shown)")
    ap.add_argument("--only", nargs="*", help="run only the commands whose name has these words")
    ap.add_argument("--suite", action="store_true", help="also the test suite (pytest -n 2)")
    args = ap.parse_args()
    trees = {"after": (args.after or ROOT / "src").resolve()}
    if args.before:
        trees = {"before": args.before.resolve(), **trees}
    variants = [(t, False) for t in trees]
    if args.pinned:
        variants += [(t, True) for t in trees]
    cores = len(os.sched_getaffinity(0))
    print(f"machine: {cpu_name()}, {cores} cores; python {sys.version.split()[0]}")
    print("trees: " + ", ".join(f"{k} = {v}" for k, v in trees.items()))
    with tempfile.TemporaryDirectory() as tmp:
        cmds = {
            name: [sys.executable, "-m", "gearrotor", *a] for name, a in commands(Path(tmp)).items()
        }
        if args.suite:
            cmds["test suite (pytest -n 2)"] = [
                sys.executable,
                "-m",
                "pytest",
                "-n",
                "2",
                "-q",
                "-x",
            ]
        if args.only:
            cmds = {k: v for k, v in cmds.items() if any(w in k for w in args.only)}
        rows = []
        for name, argv in cmds.items():
            for busy in (False, True):
                load = os.getloadavg()[0]
                cells = {}
                with busy_neighbour(busy):
                    for _ in range(args.repeat):
                        for tree, pinned in variants:
                            dt = _run(argv, trees[tree], pinned, ROOT)
                            cells.setdefault((tree, pinned), []).append(dt)
                med = {k: sorted(v)[len(v) // 2] for k, v in cells.items()}
                rows.append((name, busy, load, med))
                print(
                    f"  {name} {'busy' if busy else 'idle'}: "
                    + ", ".join(
                        f"{t}{' pinned' if p else ''} {s:.2f} s" for (t, p), s in med.items()
                    ),
                    flush=True,
                )
    print()
    head = [f"{t}{' (1 BLAS thread)' if p else ''}" for t, p in variants]
    ratio = "before/after" if args.before else None
    print("| command | next to | load | " + " | ".join(head) + (f" | {ratio} |" if ratio else " |"))
    print("|---|---|---|" + "---|" * (len(head) + bool(ratio)))
    for name, busy, load, med in rows:
        cells = [f"{med[v]:.2f}" for v in variants]
        extra = f" | {med[('before', False)] / med[('after', False)]:.1f}×" if ratio else ""
        print(
            f"| {name} | {'one busy process' if busy else '(idle)'} | {load:.1f} | "
            + " | ".join(cells)
            + extra
            + " |"
        )


if __name__ == "__main__":
    main()
