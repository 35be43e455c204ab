"""One error-to-exit-status mapping for every command (gearrotor.cli.errors): 2 for invalid input
(file, field, option value, unwritable output, missing optional package), 3 for a solver
failure, 1 for a study whose cases failed; one message on stderr, no traceback.

Real failures where they are cheap to provoke (a bearing load beyond its capacity, an unbalance
so large that the response overflows, an RK4 step outside its stability region); the modal and
Campbell solvers, which do not fail on a valid model, are replaced by one that raises, which
checks the mapping only.
"""

from __future__ import annotations

import sys

import pytest
from typer.testing import CliRunner

from gearrotor.cli import app
from gearrotor.cli.errors import EXIT_CASES_FAILED, EXIT_INPUT, EXIT_SOLVER, input_error
from gearrotor.errors import ModelError, SolverError

SINGLE = "unity_gearbox_single_shaft.toml"
UNITY = "unity_gearbox.toml"
HUGE_UNBALANCE = "unbalances[0].amount=1e305 kg*m"  # m e ω² overflows: non-finite response


def invoke(*args: str):
    return CliRunner().invoke(app, [str(a) for a in args])


def check(r, code: int, *needles: str) -> None:
    assert r.exit_code == code, (r.exit_code, r.output, r.exception)
    assert "Traceback" not in r.output
    prefix = "solver error: " if code == EXIT_SOLVER else "error: "
    assert r.stderr.startswith(prefix), r.stderr
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr
    for n in needles:
        assert n in r.stderr, (n, r.stderr)


def test_documented_codes():
    assert (EXIT_CASES_FAILED, EXIT_INPUT, EXIT_SOLVER) == (1, 2, 3)


@pytest.mark.parametrize(
    "cmd",
    [
        ["modal"],
        ["campbell"],
        ["unbalance"],
        ["bearing"],
        ["transient"],
        ["transient-plot"],
        ["report"],
        ["floquet"],
        ["ucs"],
        ["stability"],
        ["study", "run"],
        ["study", "status"],
        ["study", "report"],
    ],
)
def test_help_states_the_exit_codes(cmd):
    r = invoke(*cmd, "--help")
    assert r.exit_code == 0, r.output
    text = " ".join(r.output.split())
    assert "Exit status: 0 done; 2 invalid input" in text and "3 solver failure" in text


# ---- input errors: 2 --------------------------------------------------------------------------
@pytest.mark.parametrize(
    "cmd", [["modal"], ["campbell"], ["unbalance"], ["transient"], ["report", "-o", "OUT"]]
)
def test_missing_model_file_exits_2(cmd, tmp_path):
    missing = tmp_path / "nope.toml"
    args = [a if a != "OUT" else str(tmp_path / "out") for a in cmd]
    r = invoke(args[0], missing, *args[1:])
    check(r, EXIT_INPUT, "nope.toml")
    assert not (tmp_path / "out").exists()


def test_bad_field_names_file_field_value_expected(examples, tmp_path):
    text = (examples / UNITY).read_text().replace("node = 10, teeth = 30", "node = 99, teeth = 30")
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    for cmd in (["modal"], ["campbell"], ["unbalance"], ["transient"], ["report", "-o", "o"]):
        r = invoke(cmd[0], bad, *cmd[1:])
        check(r, EXIT_INPUT, str(bad), "meshes[0].gear.node", "99", "expected")


@pytest.mark.parametrize(
    ("args", "needles"),
    [
        (["modal", UNITY, "--format", "xml"], ["--format", "'xml'", "expected 'table' or 'json'"]),
        (["campbell", UNITY, "--orders", "ten"], ["--orders", "'ten'"]),
        (["campbell", UNITY, "--n-speeds", "1"], ["--n-speeds", "'1'", "2.."]),
        (["unbalance", UNITY, "--operating-range", "6000"], ["--operating-range", "MIN,MAX"]),
        (["unbalance", UNITY, "--set", "meshes[0].stiffness"], ["PATH=VALUE"]),
        (["bearing", "bearings/plain_ld1.toml", "--load", "1"], ["--load", "FX,FY"]),
        (["transient", UNITY, "--method", "euler"], ["--method", "'euler'", "'modal' or 'rk4'"]),
        (["transient", UNITY, "--format", "xml"], ["--format", "'xml'"]),
        (["report", UNITY, "-o", "OUT", "--analyses", "bogus"], ["--analyses", "bogus"]),
        (["report", UNITY, "-o", "OUT", "--speed", "0"], ["--speed", "positive"]),
    ],
)
def test_bad_option_values_exit_2(examples, tmp_path, args, needles):
    args = [
        str(examples / a) if a.endswith(".toml") else (str(tmp_path / "o") if a == "OUT" else a)
        for a in args
    ]
    check(invoke(*args), EXIT_INPUT, *needles)


def test_option_syntax_errors_are_2_too(examples):
    """The parser's own errors (a number that is not a number) use the same status."""
    r = invoke("modal", examples / SINGLE, "--speed", "fast")
    assert r.exit_code == EXIT_INPUT


def test_unwritable_output_exits_2(examples, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    r = invoke("modal", examples / SINGLE, "--max-frequency", "10000", "--plot", blocker / "d")
    check(r, EXIT_INPUT, str(blocker))


def test_missing_optional_package_names_the_extra(examples, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "plotly", None)  # import plotly -> ImportError
    r = invoke("report", examples / SINGLE, "-o", tmp_path / "o", "--analyses", "modal")
    check(r, EXIT_INPUT, "'plotly'", "pip install 'gearrotor[report]'")
    assert not (tmp_path / "o").exists()


def test_transient_plot_unreadable_file_exits_2(tmp_path):
    check(invoke("transient-plot", tmp_path / "none.nc"), EXIT_INPUT, "none.nc")
    junk = tmp_path / "junk.nc"
    junk.write_text("not netcdf")
    check(invoke("transient-plot", junk), EXIT_INPUT, "junk.nc", "cannot read the result file")


STUDY = """
name = "t"
model = "{model}"

[parameters]
ka = {{ path = "meshes[0].variation.ka_ratio" }}

[cases]
columns = ["ka"]
rows = [[{ka}]]

[analysis]
type = "transient"
t_end = "0.05 s"
"""


def test_study_input_error_exits_2(examples, tmp_path):
    p = tmp_path / "s.toml"
    p.write_text(STUDY.format(model=(examples / UNITY).as_posix(), ka=0.1) + "colour = 1\n")
    for cmd in ("run", "status", "report"):
        check(invoke("study", cmd, p), EXIT_INPUT, "colour")
    check(invoke("study", "status", tmp_path / "none.toml"), EXIT_INPUT, "none.toml")


def test_study_with_invalid_row_exits_2(examples, tmp_path):
    """A row whose model is invalid is an input error of the study file, found before anything
    runs (issue 17): exit 2 naming the study file and the row."""
    p = tmp_path / "s.toml"
    p.write_text(STUDY.format(model=(examples / UNITY).as_posix(), ka=-0.5))
    r = invoke("study", "run", p, "--workers", "1", "--no-progress")
    check(r, EXIT_INPUT, "s.toml", "cases.rows[0]", "ka_ratio", "-0.5")
    assert not (tmp_path / "s.study").exists()


def test_study_with_failed_cases_exits_1(examples, tmp_path):
    """A case that fails is listed and recorded; the run exits 1 (not 2 or 3: the study ran)."""
    p = tmp_path / "s.toml"
    text = STUDY.format(model=(examples / UNITY).as_posix(), ka=0.1)
    # 1000 kg*m of unbalance: the run diverges (a solver failure of that case)
    p.write_text(
        text.replace("[parameters]", '[set]\n"unbalances[0].amount" = "1000 kg*m"\n\n[parameters]')
    )
    r = invoke("study", "run", p, "--workers", "1", "--no-progress")
    assert r.exit_code == EXIT_CASES_FAILED, r.output
    assert "case 0 failed" in r.stderr and "diverged" in r.stderr


# ---- solver failures: 3 -----------------------------------------------------------------------
def test_unbalance_solver_failure_exits_3(examples):
    r = invoke("unbalance", examples / SINGLE, "--n-speeds", "5", "--set", HUGE_UNBALANCE)
    check(r, EXIT_SOLVER, "non-finite unbalance response")


def test_report_solver_failure_exits_3_and_writes_nothing(examples, tmp_path):
    r = invoke(
        "report",
        examples / SINGLE,
        "-o",
        tmp_path / "o",
        "--analyses",
        "unbalance",
        "--set",
        HUGE_UNBALANCE,
    )
    check(r, EXIT_SOLVER, "non-finite unbalance response")
    assert not (tmp_path / "o").exists()


def test_bearing_without_equilibrium_exits_3(examples):
    r = invoke("bearing", examples / "bearings" / "plain_ld1.toml", "--load", "0,-1e9")
    check(r, EXIT_SOLVER, "no equilibrium found")


def test_transient_step_outside_stability_exits_3(examples):
    """The transient command used to exit 1 here; a solver failure is 3 for every command."""
    r = invoke(
        "transient",
        examples / UNITY,
        "--t-end",
        "0.001",
        "--method",
        "rk4",
        "--dt",
        "1e-3",
        "--no-progress",
    )
    check(r, EXIT_SOLVER, "dt")


@pytest.mark.parametrize(("cmd", "target"), [("modal", "modal"), ("campbell", "campbell")])
def test_eigensolver_failure_exits_3(examples, monkeypatch, cmd, target):
    def fail(*args, **kwargs):
        raise SolverError("sparse eigensolver did not converge for 12 modes")

    monkeypatch.setattr(f"gearrotor.analyses.{target}", fail)
    r = invoke(cmd, examples / SINGLE, "--max-frequency", "10000")
    check(r, EXIT_SOLVER, "did not converge")


def test_modal_overflow_exits_3(examples):
    """An absurd stiffness (1e308 N/m) overflows the state matrix: a solver error naming the
    cause, not a LAPACK traceback."""
    r = invoke("modal", examples / SINGLE, "--set", "bearings[0].k=1e308 N/m")
    check(r, EXIT_SOLVER, "overflows")


def test_floquet_input_errors_exit_2(examples):
    check(invoke("floquet", examples / UNITY, "--ka", "0.5,x"), EXIT_INPUT, "--ka")
    check(invoke("floquet", examples / UNITY, "--ka", "1.5"), EXIT_INPUT, "ka_ratio")
    check(invoke("floquet", examples / SINGLE), EXIT_INPUT, "meshes")


# ---- the mapping itself -----------------------------------------------------------------------
def test_input_error_mapping():
    e = ModelError("bad", field="f", value=1, expected="2", file="m.toml")
    assert input_error(e) is e
    nf = input_error(FileNotFoundError(2, "No such file or directory", "out/x.nc"))
    assert str(nf).startswith("out/x.nc: No such file or directory")
    miss = ImportError("No module named 'xarray'", name="xarray")
    assert "gearrotor[results]" in str(input_error(miss))
    # not input errors: left to show their traceback
    assert input_error(ImportError("x", name="numpy")) is None
    assert input_error(OSError(5, "Input/output error")) is None
    assert input_error(ValueError("bug")) is None
