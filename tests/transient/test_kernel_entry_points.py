"""The transient kernels that only other kernels call are compiled without numba's Python entry
point (:func:`gearrotor.analyses.jit.kernel_only`, issue 28: compiling them into an empty cache
took ~23 % more CPU with it). Such a function must refuse a call from Python with an error
instead of jumping to an entry point that does not exist (a segmentation fault), and every
kernel the Python side calls must keep its entry point. That the results are the same to the
bit as with the former entry points is checked by
``test_transient_exponential.py::test_rerun_reproduces_a_backlash_run_bit_for_bit`` (slow: it
compiles twice) and ``benchmarks/kernel_results.py`` (every path of the kernels)."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest
from numba.core.registry import CPUDispatcher

from gearrotor.analyses import jit
from gearrotor.analyses.transient import kernels as kn

#: the kernels called from Python (the driver, prepare.py, the tests)
ENTRY_POINTS = {"rk4_physical", "rk4_modal", "etd_modal", "outputs_kernel", "etd_coefficients",
                "_interp"}  # fmt: skip


def _dispatchers():
    return {
        name: obj
        for name, obj in vars(kn).items()
        if isinstance(obj, CPUDispatcher) and obj.py_func.__module__ == kn.__name__
    }


def test_entry_points_keep_their_python_entry():
    """The kernels Python calls are plain dispatchers; the others called on their own (not
    inlined) from kernels have no Python entry point."""
    found = _dispatchers()
    assert ENTRY_POINTS <= set(found)
    for name in ENTRY_POINTS:
        assert not isinstance(found[name], jit.KernelOnly), name
    internal = {
        name
        for name, d in found.items()
        if name not in ENTRY_POINTS and d.targetoptions.get("inline", "never") == "never"
    }
    assert {"nonlinear_forces", "_accel_modal", "_accel_physical", "_etd_substep"} <= internal
    for name in internal:
        assert isinstance(found[name], jit.KernelOnly), name


def test_kernel_only_refuses_a_python_call():
    """A call from Python raises TypeError naming the function (nothing is compiled)."""
    with pytest.raises(TypeError, match="_lu_solve is compiled without a Python entry point"):
        kn._lu_solve(np.eye(2), np.ones(2), np.zeros(2, np.int64))


def test_kernel_only_after_compiling_does_not_crash(tmp_path):
    """Once compiled (here: called from a kernel), a call from Python with the very types it
    was compiled for still raises TypeError; numba alone would find the compiled version and
    jump to its missing entry point (the process dies: run in a child process)."""
    script = (
        "import numpy as np\n"
        "from numba import njit\n"
        "from gearrotor.analyses.jit import kernel_only\n"
        "@kernel_only(cache=True)\n"
        "def twice(x):\n"
        "    return 2.0 * x[0]\n"
        "@njit(cache=True)\n"
        "def caller(x):\n"
        "    return twice(x)\n"
        "x = np.array([1.5])\n"
        "print(caller(x))\n"
        "try:\n"
        "    twice(x)\n"
        "except TypeError as e:\n"
        "    print('TypeError', e)\n"
    )
    path = tmp_path / "twice.py"  # numba caches functions of files only
    path.write_text(script)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    for _ in range(2):  # compiled, then from the cache
        run = subprocess.run(
            [sys.executable, str(path)], env=env, capture_output=True, text=True, timeout=300
        )
        assert run.returncode == 0, run.stderr
        lines = run.stdout.splitlines()
        assert lines[0] == "3.0"
        assert lines[1].startswith("TypeError twice is compiled without a Python entry point")
