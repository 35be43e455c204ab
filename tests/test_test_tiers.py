"""The default test run leaves out the long cross-checks marked slow; ``-m slow`` runs them
alone, ``GEARROTOR_TESTS=all`` with the rest (CI, ``.ci/run``), a slow test named on the command
line runs (issue 28: the README's test command in ≤ 5 min on an idle 2-core machine, the whole
suite in CI)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

ROOT = Path(__file__).resolve().parents[1]


class _Item:
    def __init__(self, nodeid: str, slow: bool):
        self.nodeid, self._slow = nodeid, slow

    def get_closest_marker(self, name):
        return object() if name == "slow" and self._slow else None


def _config(markexpr="", args=()):
    deselected = []
    hook = SimpleNamespace(pytest_deselected=lambda items: deselected.extend(items))
    cfg = SimpleNamespace(
        option=SimpleNamespace(markexpr=markexpr), args=list(args), rootpath=ROOT, hook=hook
    )
    return cfg, deselected


def _items():
    return [
        _Item("tests/a.py::test_quick", False),
        _Item("tests/a.py::test_long", True),
        _Item("tests/a.py::test_long_p[1]", True),
        _Item("tests/b.py::TestX::test_long", True),
    ]


@pytest.fixture
def conftest(pytestconfig):
    """The suite's own conftest module (tests/conftest.py), as pytest loaded it."""
    path = ROOT / "tests" / "conftest.py"
    for plugin in pytestconfig.pluginmanager.get_plugins():
        if Path(getattr(plugin, "__file__", "") or "/").resolve() == path:
            return plugin
    raise AssertionError("tests/conftest.py is not loaded")


def _kept(conftest, monkeypatch, env=None, **kw):
    if env is None:
        monkeypatch.delenv("GEARROTOR_TESTS", raising=False)
    else:
        monkeypatch.setenv("GEARROTOR_TESTS", env)
    cfg, deselected = _config(**kw)
    items = _items()
    conftest._leave_out_slow(cfg, items)
    assert len(items) + len(deselected) == 4
    return [i.nodeid for i in items]


def test_default_run_leaves_out_the_slow_tests(conftest, monkeypatch):
    assert _kept(conftest, monkeypatch) == ["tests/a.py::test_quick"]


def test_all_or_a_mark_expression_keeps_them(conftest, monkeypatch):
    assert len(_kept(conftest, monkeypatch, env="all")) == 4
    # with -m, pytest's own mark expression selects among them
    assert len(_kept(conftest, monkeypatch, markexpr="slow")) == 4
    # only "all" means all
    assert _kept(conftest, monkeypatch, env="yes") == ["tests/a.py::test_quick"]


def test_a_slow_test_named_on_the_command_line_runs(conftest, monkeypatch):
    kept = _kept(conftest, monkeypatch, args=[str(ROOT / "tests/a.py") + "::test_long_p"])
    assert kept == ["tests/a.py::test_quick", "tests/a.py::test_long_p[1]"]
    kept = _kept(conftest, monkeypatch, args=["tests/b.py::TestX"])
    assert kept == ["tests/a.py::test_quick", "tests/b.py::TestX::test_long"]


def test_the_hook_is_called_by_pytest():
    """A collection of a file with one slow test, as a user runs it."""
    # as a user runs it: not under this run's tier setting nor as one of its xdist workers
    env = {
        k: v
        for k, v in os.environ.items()
        if k != "GEARROTOR_TESTS" and not k.startswith(("PYTEST_XDIST", "GEARROTOR_TEST_"))
    }
    target = "tests/transient/test_transient_seed.py"
    p = subprocess.run(
        [sys.executable, "-m", "pytest", "--co", "-q", "-p", "no:cacheprovider", target],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert p.returncode == 0, p.stdout + p.stderr
    assert re.search(r"\d+ deselected", p.stdout) and "test_nominal_case_rk4_3s" not in p.stdout
    assert "GEARROTOR_TESTS=all" in p.stdout
