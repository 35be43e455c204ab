"""Benchmark: what numba costs a transient before it steps (issue 28), and the steps after it.

    python benchmarks/numba_startup.py [--before SRC] [--busy] [--only exponential modal rk4]

For each kernel family of the lateral transient, one fresh process per figure, run with the
default environment (no thread pinning):

* cold compile: the process's CPU seconds for a short run in an empty numba cache
  (``NUMBA_CACHE_DIR`` a new temporary folder): the first run on a machine, or after the kernel
  sources changed; less the same run's CPU in a process with that cache filled, so that
  importing and the run itself are not counted;
* warm first call: in a new process with the cache filled, the first run's wall and CPU
  seconds less those of the same run repeated in the same process: loading the cached
  kernels (numba's one-off set-up of its compiler context, then reading the kernel), and
  whatever else the first run of a process does once (a module imported on first use);
* step: the repeated run's integration wall time (``stats.wall_time_s``) per step (µs).

The runs: ``exponential`` the SPEC 6.1 gearbox with 0.0254 mm backlash, the exponential
modal scheme (the kernels of ``etd_modal``; 0.05 s); ``modal`` classical modal RK4 (``rk4_modal``,
0.02 s); ``rk4`` RK4 on the full model (``rk4_physical``, dt 1e-6 s, 0.005 s). ``--before SRC``
runs every figure with an older ``src`` folder too, interleaved, and prints the ratio after /
before; ``--busy`` runs everything next to one busy process (``python -c "while True: pass"``).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

from _machine import busy_neighbour, cpu_name

ROOT = Path(__file__).resolve().parents[1]

_CHILD = r"""
import json, sys, time
from gearrotor import load_model
from gearrotor.analyses.transient import RK4, ModalRK4, transient
case = sys.argv[1]
ex = sys.argv[2]
if case == "exponential":
    train = load_model(ex, {"meshes[0].backlash.value": "0.0254 mm"})
    kw = dict(t_end=0.05)
elif case == "modal":
    train = load_model(ex)
    kw = dict(t_end=0.02, integrator=ModalRK4(exact_linear=False))
else:
    train = load_model(ex)
    kw = dict(t_end=0.005, integrator=RK4(dt=1e-6))
out = {}
for k in ("first", "again"):
    w, c = time.perf_counter(), time.process_time()
    r = transient(train, **kw)
    out[k] = (time.perf_counter() - w, time.process_time() - c)
out["steps"] = int(r.stats.steps)
out["integration"] = r.stats.wall_time_s  # the repeated run's stepping alone
print(json.dumps(out))
"""

CASES = ("exponential", "modal", "rk4")


def _run(case: str, src: Path, cache: Path) -> tuple[dict, float]:
    """One child process: its JSON report and its CPU seconds (the operating system's
    accounting of the finished child)."""
    env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=str(cache))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(
        [sys.executable, "-c", _CHILD, case, str(ROOT / "examples" / "unity_gearbox.toml")],
        env=env,
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    )
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return json.loads(proc.stdout.strip().splitlines()[-1]), cpu


def measure(case: str, src: Path) -> dict[str, float]:
    """Cold compile CPU, warm first-call wall and CPU, step time for one case and tree."""
    with tempfile.TemporaryDirectory() as tmp:
        cache = Path(tmp) / "numba"
        cold, cold_cpu = _run(case, src, cache)  # compiles into the empty cache
        warm, warm_cpu = _run(case, src, cache)  # loads from it
    steps = warm["steps"]
    return {
        "compile_cpu": cold_cpu - warm_cpu,
        "load_wall": warm["first"][0] - warm["again"][0],
        "load_cpu": warm["first"][1] - warm["again"][1],
        "step_us": 1e6 * warm["integration"] / steps,
        "steps": steps,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", type=Path, help="an older src/ folder to compare with")
    ap.add_argument("--busy", action="store_true", help="next to one busy process")
    ap.add_argument("--only", nargs="+", choices=CASES, default=list(CASES))
    args = ap.parse_args()
    trees = {"after": ROOT / "src"}
    if args.before:
        trees = {"before": args.before.resolve(), **trees}
    res: dict[tuple[str, str], dict[str, float]] = {}
    with busy_neighbour(args.busy):
        for case in args.only:
            for tree, src in trees.items():
                res[(case, tree)] = measure(case, src)
    print(
        f"machine: {cpu_name()}; {os.cpu_count()} cores; load average "
        f"{os.getloadavg()[0]:.1f}; default environment"
        + ("; next to one busy process" if args.busy else "")
    )
    cols = ("compile_cpu", "load_wall", "load_cpu", "step_us")
    heads = ("cold compile CPU s", "warm first call s", "its CPU s", "step µs")
    print("| run | tree | " + " | ".join(heads) + " |")
    print("|---|---|" + "---|" * len(cols))
    for case in args.only:
        for tree in trees:
            r = res[(case, tree)]
            cells = [f"{r['compile_cpu']:.1f}", f"{r['load_wall']:.3f}", f"{r['load_cpu']:.3f}"]
            cells.append(f"{r['step_us']:.1f}")
            print(f"| {case} ({r['steps']} steps) | {tree} | " + " | ".join(cells) + " |")
        if "before" in trees:
            b, a = res[(case, "before")], res[(case, "after")]
            ratios = [a[c] / b[c] if b[c] else float("nan") for c in cols]
            print(f"| {case} | after / before | " + " | ".join(f"{x:.2f}" for x in ratios) + " |")


if __name__ == "__main__":
    main()
