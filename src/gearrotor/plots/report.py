"""The HTML report of a train (SPEC 3.6): one self-contained page plus the same figures as PNG.

:func:`make_report` runs the requested linear analyses (``modal``, ``campbell``,
``unbalance``), optionally reads a saved transient result, and writes into a directory:

* ``report.html`` – a single file with the plotly.js bundle embedded inline (no network access
  is needed to open it): summary and verdicts, the table of modes, stability margins, interactive
  3-D mode shapes, Campbell diagram with crossings, Bode plot, orbits, API 684 / API 617 checks,
  tabulated bearing coefficients, and for a transient result its spectra, waterfall and
  whirl-promoting power;
* PNG files of the same figures (matplotlib);
* ``report.json`` – the numbers of the report (modes, crossings, checks, inputs).

The directory is written atomically: everything goes to a temporary sibling directory first; a
new output directory is then renamed into place, an existing one receives each file by
``os.replace`` with ``report.html`` last. A failure leaves no partial report behind.

Speeds follow the ``campbell`` and ``unbalance`` commands: sweeps run over positive reference
speeds; the modal analysis runs at the given speed with the sign of the model's nominal speed.
When the model has tabulated (fluid-film) bearings, the sweeps are limited to the speed range of
their tables (unless the table holds its end values) and the report says so.
"""

from __future__ import annotations

import datetime as _dt
import html
import json
import math
import os
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import ModelError

__all__ = [
    "ANALYSES",
    "LOG_DEC_THRESHOLD",
    "Report",
    "make_report",
    "parse_analyses",
    "plot_bearing_coefficients",
    "plot_waterfall",
]

ANALYSES = ("modal", "campbell", "unbalance")
LOG_DEC_THRESHOLD = 0.1  # API 617 (Level II) acceptance: log dec of every mode above 0.1
RPM = 30 / np.pi  # rad/s -> rpm
_PLOTLY_CONFIG = {"displaylogo": False, "responsive": True}


@dataclass(frozen=True)
class Report:
    """What :func:`make_report` wrote and computed.

    ``directory`` holds ``html`` (the report), ``figures`` (PNG files) and ``json``;
    ``summary`` is the content of ``report.json``. The analysis results are kept for callers
    that want more than the report shows (``None`` when not requested).
    """

    directory: Path
    html: Path
    json: Path
    figures: tuple[Path, ...]
    summary: dict = field(repr=False)
    modal: object | None = field(default=None, repr=False)
    campbell: object | None = field(default=None, repr=False)
    unbalance: object | None = field(default=None, repr=False)
    transient: object | None = field(default=None, repr=False)


def parse_analyses(text: str | tuple[str, ...] | list[str]) -> tuple[str, ...]:
    """Analyses from ``"modal,campbell,unbalance"`` (any order, each at most once).

    ``"transient"`` is not run by the report: it is accepted only to state that a transient
    result file must be given (see :func:`make_report`).
    """
    items = text.split(",") if isinstance(text, str) else list(text)
    names = [s.strip().lower() for s in items if s.strip()]
    allowed = (*ANALYSES, "transient")
    bad = [n for n in names if n not in allowed]
    if bad or not names:
        raise ModelError(
            "unknown analysis" if bad else "no analysis requested",
            field="--analyses",
            value=",".join(bad) if bad else text,
            expected="a comma-separated subset of " + ", ".join(allowed),
        )
    out: list[str] = []
    for n in names:
        if n not in out:
            out.append(n)
    return tuple(out)


# ---- matplotlib figures the other modules do not provide ---------------------------------------
def _mpl_figure(size):
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, layout="constrained")
    return fig


def _savefig(fig, path: Path) -> Path:
    tmp = path.with_name(path.stem + ".tmp" + path.suffix)
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, path)
    return path


def plot_waterfall(ds, *, node: int = 0, component: str = "x", n_slices: int = 24, path=None):
    """Waterfall (matplotlib) of one node's displacement spectrum over a saved transient run:
    one spectrum (µm 0-pk, cpm) per time slice, offset by the slice time. Returns the Figure."""
    from .interactive import _run_and_mesh_cpm, waterfall_data

    f, amps, tc, sc = waterfall_data(ds, node=node, component=component, n_slices=n_slices)
    run, mesh = _run_and_mesh_cpm(ds)
    top = (mesh + 3 * run) if mesh is not None else 10 * run
    keep = f <= top
    fig = _mpl_figure((10, 6))
    ax = fig.add_subplot(projection="3d")
    for i in range(len(tc)):
        ax.plot(
            f[keep],
            np.full(int(keep.sum()), tc[i]),
            amps[i, keep] * 1e6,
            lw=0.7,
            color=f"C{i % 10}",
        )
    ax.set_xlabel("frequency (cpm)")
    ax.set_ylabel("time (s)")
    ax.set_zlabel("amplitude 0-pk (µm)")
    ax.set_title(f"Waterfall: {ds['node'].values[node]} {component}")
    if path is not None:
        _savefig(fig, Path(path))
    return fig


def plot_bearing_coefficients(assembly, path=None):
    """Tabulated bearing coefficients (matplotlib) against journal speed; ``None`` when no
    bearing of the assembly is tabulated."""
    tab = [b for b in assembly.bearings if b.element.speed_dependent]
    if not tab:
        return None
    fig = _mpl_figure((11, 4.5))
    ax = fig.subplots(1, 2)
    names = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")
    styles = ("-", "--", ":", "-.")
    for bi, b in enumerate(tab):
        t = b.element.table
        for j, nm in enumerate(names):
            ax[j // 4].plot(
                t.speed * RPM,
                t.values[:, j],
                styles[bi % 4],
                marker=".",
                color=f"C{j % 4}",
                label=f"{b.name}: {nm}",
            )
    for a, lab in zip(ax, ("stiffness (N/m)", "damping (N·s/m)"), strict=True):
        a.set_xlabel("journal speed (rpm)")
        a.set_ylabel(lab)
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.suptitle("Tabulated bearing coefficients")
    if path is not None:
        _savefig(fig, Path(path))
    return fig


# ---- checks --------------------------------------------------------------------------------------
def _mode_status(res, i: int) -> str:
    if res.overdamped[i]:
        return "over-damped"
    if res.unstable[i]:
        return "UNSTABLE"
    if res.log_dec[i] < LOG_DEC_THRESHOLD:
        return "low damping"
    return "stable"


def _stability(res, camp) -> dict:
    out: dict = {"threshold_log_dec": LOG_DEC_THRESHOLD}
    if res is not None:
        el = [i for i in range(len(res)) if not res.overdamped[i]]
        d = {
            "speed_rpm": float(res.speed * RPM),
            "stable": bool(res.stable),
            "unstable_modes": [int(i) for i in np.flatnonzero(res.unstable)],
            "low_damping_modes": [
                int(i)
                for i in el
                if 0 <= res.log_dec[i] < LOG_DEC_THRESHOLD and not res.unstable[i]
            ],
        }
        if el:
            k = min(el, key=lambda i: res.log_dec[i])
            d["lowest_log_dec"] = {
                "mode": int(k),
                "frequency_rpm": float(res.frequency_rpm[k]),
                "log_dec": float(res.log_dec[k]),
                "type": res.mode_type[k],
                "whirl": "/".join(res.whirl_per_shaft[k]),
            }
        d["ok"] = bool(res.stable) and not d["low_damping_modes"]
        out["modal"] = d
    if camp is not None:
        ld = np.where(camp.overdamped, np.inf, camp.log_dec)
        per_mode = []
        for j in range(ld.shape[1]):
            k = int(np.argmin(ld[:, j]))
            per_mode.append(
                {
                    "mode": j,
                    "min_log_dec": float(camp.log_dec[k, j]),
                    "at_speed_rpm": float(camp.speeds[k] * RPM),
                    "frequency_rpm": float(camp.damped_frequency[k, j] * RPM),
                }
            )
        lowest = min(per_mode, key=lambda d: d["min_log_dec"]) if per_mode else None
        out["campbell"] = {
            "speed_range_rpm": [float(camp.speeds[0] * RPM), float(camp.speeds[-1] * RPM)],
            "modes": per_mode,
            "lowest": lowest,
            "ok": lowest is None or lowest["min_log_dec"] >= LOG_DEC_THRESHOLD,
        }
    return out


def _api_checks(unb) -> dict:
    crit = []
    amp = []
    s = unb.speeds
    lo, hi = unb.operating_range
    in_op = (s >= lo * (1 - 1e-9)) & (s <= hi * (1 + 1e-9))
    if not np.any(in_op):
        in_op = np.zeros(len(s), bool)
        in_op[int(np.argmin(np.abs(s - hi)))] = True
    for p, lim in zip(unb.probes, unb.vibration_limit, strict=True):
        for c in p.criticals:
            crit.append(
                {
                    "probe": p.name,
                    "shaft": unb.shaft_names[p.shaft],
                    "speed_rpm": c.speed * RPM,
                    "probe_shaft_speed_rpm": c.probe_speed * RPM,
                    "amplitude_um": c.amplitude * 1e6,
                    "amplification_factor": c.amplification_factor,
                    "separation_margin_pct": c.separation_margin,
                    "required_margin_pct": c.required_margin,
                    "result": {True: "pass", False: "fail", None: "not determined"}[c.ok],
                }
            )
        pp = 2 * float(np.max(p.amplitude[in_op]))
        amp.append(
            {
                "probe": p.name,
                "max_pp_in_operating_range_um": pp * 1e6,
                "limit_pp_um": float(lim * 1e6),
                "result": "pass" if pp <= lim else "fail",
            }
        )
    return {
        "operating_range_rpm": [lo * RPM, hi * RPM],
        "criticals": crit,
        "amplitudes": amp,
        "ok": all(c["result"] != "fail" for c in crit) and all(a["result"] == "pass" for a in amp),
        "undetermined": sum(c["result"] == "not determined" for c in crit),
    }


# ---- speeds --------------------------------------------------------------------------------------
def _table_limits(asm) -> tuple[float, float, list[str]]:
    """Reference-speed range (rad/s) allowed by tabulated bearings that do not hold end values."""
    lo, hi, names = 0.0, math.inf, []
    for b in asm.bearings:
        el = b.element
        if not el.speed_dependent or el.table.extrapolate == "hold":
            continue
        r = abs(asm.speed_ratio[b.shaft])
        if r == 0:
            continue
        lo = max(lo, float(el.table.speed[0]) / r)
        hi = min(hi, float(el.table.speed[-1]) / r)
        names.append(b.name)
    return lo, hi, names


def _sweep(lo: float, hi: float, n: int, limits, what: str) -> tuple[np.ndarray, str | None]:
    tlo, thi, names = limits
    note = None
    a, b = max(lo, tlo), min(hi, thi)
    if names and (a != lo or b != hi):
        note = (
            f"{what} limited to {a * RPM:.0f}..{b * RPM:.0f} rpm, the speed range of the "
            f"coefficient tables of {', '.join(names)}"
        )
    if not b > a:
        raise ModelError(
            f"no speed range for the {what}",
            field="bearings",
            value=f"{a * RPM:.6g}..{b * RPM:.6g} rpm",
            expected="bearing tables that cover the operating speed",
        )
    return np.linspace(a, b, n), note


# ---- the report ----------------------------------------------------------------------------------
def make_report(
    model,
    output: str | Path,
    *,
    analyses: tuple[str, ...] | str = ANALYSES,
    speed: float | None = None,
    max_frequency: float | None = None,
    transient: str | Path | None = None,
    api: bool = False,
    n_campbell: int = 40,
    n_unbalance: int = 400,
    source: str | None = None,
    command: str | None = None,
) -> Report:
    """Run the analyses and write the report directory ``output``.

    Parameters
    ----------
    model : a :class:`~gearrotor.model.Train` (or its :class:`~gearrotor.assembly.Assembly`)
    output : directory to write (created; an existing directory is updated file by file)
    analyses : subset of ``("modal", "campbell", "unbalance")``; ``"transient"`` requires
        ``transient`` (the report reads a saved result, it does not run the solver)
    speed : rad/s, magnitude of the reference-shaft operating speed (default: the model's); the
        modal analysis runs at it, the API checks use it as the operating range, the Campbell
        sweep covers 0..1.25× and the unbalance sweep 0.02..1.5× of it
    max_frequency : rad/s, highest damped frequency of the modes and the Campbell diagram
        (default: 5 × speed)
    transient : path of a transient result (NetCDF written by ``TransientResult.save``)
    api : the unbalance section uses the API 617 unbalance, 4 × 6350 W/N g·mm per plane of the
        model's unbalances (W the plane's share of its shaft's mass, kg; N its shaft's speed at
        the operating speed, rpm; phases as in the model) instead of the model's amounts
        (:func:`gearrotor.analyses.api617.api617_unbalances`)
    n_campbell, n_unbalance : number of speeds of the Campbell and unbalance sweeps
    source, command : the model file and the command line, quoted in the report

    Raises
    ------
    ModelError : an invalid request (unknown analysis, non-positive speed, transient requested
        without a file, unreadable result file, unbalance report without unbalance or probes,
        output path that is a file) or an invalid model.
    """
    from ..analyses import campbell as run_campbell
    from ..analyses import modal as run_modal
    from ..analyses import unbalance_response
    from ..analyses.api617 import api617_unbalances
    from ..assembly import Assembly, assemble

    analyses = parse_analyses(analyses)
    if "transient" in analyses and transient is None:
        raise ModelError(
            "the transient section needs a saved transient result",
            field="--transient",
            value=None,
            expected="a NetCDF file written by the transient analysis (the report does not run "
            "the transient solver)",
        )
    if transient is not None and "transient" not in analyses:
        analyses = (*analyses, "transient")
    output = Path(output)
    if output.exists() and not output.is_dir():
        raise ModelError(
            "the report output is not a directory",
            field="--output",
            value=str(output),
            expected="a directory (new or existing)",
        )
    asm = model if isinstance(model, Assembly) else assemble(model)
    train = asm.train
    nominal = abs(float(train.speed))
    w = nominal if speed is None else float(speed)
    if not (np.isfinite(w) and w > 0):
        raise ModelError(
            "the report needs a positive operating speed",
            field="--speed",
            value=None if speed is None else f"{w * RPM:.6g} rpm",
            expected="a speed > 0 rpm (the direction of rotation follows the model)",
        )
    fmax = 5 * w if max_frequency is None else float(max_frequency)
    if not (np.isfinite(fmax) and fmax > 0):
        raise ModelError(
            "the maximum frequency must be positive",
            field="--max-frequency",
            value=f"{fmax * RPM:.6g} rpm",
            expected="a frequency > 0 rpm",
        )
    if n_campbell < 2 or n_unbalance < 3:
        raise ModelError(
            "too few sweep speeds",
            value=(n_campbell, n_unbalance),
            expected="n_campbell >= 2 and n_unbalance >= 3",
        )
    if "unbalance" in analyses:
        if not train.unbalances:
            raise ModelError(
                "the unbalance analysis needs an unbalance",
                field="unbalances",
                expected="at least one [[unbalances]] entry, or leave 'unbalance' "
                "out of --analyses",
            )
        if not train.probes:
            raise ModelError(
                "the unbalance analysis needs probes",
                field="probes",
                expected="at least one [[probes]] entry, or leave 'unbalance' out of --analyses",
            )
    ds = _read_transient(transient) if transient is not None else None

    sign = 1.0 if train.speed >= 0 else -1.0
    limits = _table_limits(asm)
    notes: list[str] = []
    res = camp = unb = unbalances = None
    if "modal" in analyses:
        res = run_modal(asm, speed=sign * w, max_frequency=fmax)
    if "campbell" in analyses:
        speeds, note = _sweep(0.0, 1.25 * w, n_campbell, limits, "Campbell sweep")
        notes += [note] if note else []
        try:
            camp = run_campbell(asm, speeds=speeds, max_frequency=fmax)
        except ModelError:
            raise
        except ValueError as exc:  # e.g. no mode below max_frequency: an input problem
            raise ModelError(
                f"the Campbell diagram cannot be made: {exc}",
                field="--max-frequency",
                value=f"{fmax * RPM:.6g} cpm",
                expected="a maximum frequency above the lowest modes of the train",
            ) from None
    if "unbalance" in analyses:
        speeds, note = _sweep(0.02 * w, 1.5 * w, n_unbalance, limits, "unbalance sweep")
        notes += [note] if note else []
        unbalances = api617_unbalances(asm, w) if api else list(train.unbalances)
        unb = unbalance_response(asm, speeds=speeds, unbalances=unbalances, operating_range=(w, w))

    output.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{output.name}.tmp-", dir=output.parent))
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o777 & ~umask)  # mkdtemp makes it private; the report is an ordinary folder
    try:
        figures, sections, summary = _write_contents(
            tmp,
            asm,
            res,
            camp,
            unb,
            ds,
            fmax=fmax,
            w=w,
            notes=notes,
            transient=transient,
            unbalances=unbalances,
            api=api,
        )
        summary["inputs"] = {
            "model": source,
            "command": command,
            "analyses": list(analyses),
            "speed_rpm": w * RPM,
            "max_frequency_rpm": fmax * RPM,
            "transient": None if transient is None else str(transient),
            "unbalance": "api617" if api else "model",
        }
        (tmp / "report.json").write_text(json.dumps(_clean(summary), indent=1), encoding="utf-8")
        page = _page(train, sections, summary, figures, notes, source=source, command=command)
        (tmp / "report.html").write_text(page, encoding="utf-8")
        _publish(tmp, output)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return Report(
        directory=output,
        html=output / "report.html",
        json=output / "report.json",
        figures=tuple(output / p.name for p in figures),
        summary=summary,
        modal=res,
        campbell=camp,
        unbalance=unb,
        transient=ds,
    )


def _read_transient(path):
    from ..analyses.transient import load_result

    path = Path(path)
    try:
        ds = load_result(path)
    except ModelError:
        raise
    except (OSError, ValueError, KeyError) as exc:
        raise ModelError(
            f"cannot read the transient result ({type(exc).__name__}: {exc})",
            file=str(path),
            expected="a NetCDF file written by the transient analysis",
        ) from None
    need = ("time", "x", "y", "node", "shaft_speed", "whirl_power", "component")
    missing = [v for v in need if v not in ds.variables]
    if missing:
        raise ModelError(
            "not a gearrotor transient result",
            file=str(path),
            value=f"missing {', '.join(missing)}",
            expected="a NetCDF file written by the transient analysis",
        )
    if ds.sizes.get("time", 0) < 64 or ds.sizes.get("node", 0) < 1:
        raise ModelError(
            "the transient result is too short for spectra",
            file=str(path),
            value=f"{ds.sizes.get('time', 0)} samples, {ds.sizes.get('node', 0)} nodes",
            expected="at least 64 time samples and one recorded node",
        )
    return ds


def _publish(tmp: Path, output: Path) -> None:
    if not output.exists():
        os.rename(tmp, output)
        return
    files = sorted(tmp.iterdir(), key=lambda p: (p.name == "report.html", p.name))
    for f in files:
        os.replace(f, output / f.name)
    tmp.rmdir()


def _clean(x):
    """JSON-safe copy: non-finite floats become None, numpy scalars Python numbers."""
    if isinstance(x, dict):
        return {str(k): _clean(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_clean(v) for v in x]
    if isinstance(x, np.generic):
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


def _write_contents(
    tmp: Path, asm, res, camp, unb, ds, *, fmax, w, notes, transient, unbalances, api
):
    """Write the PNG files; return (png paths, html sections, summary)."""
    from . import interactive as ix
    from .figures import plot_bode, plot_campbell, plot_mode_shapes, plot_orbits
    from .waterfall import plot_speed_waterfall, speed_varies, speed_waterfall

    figures: list[Path] = []
    sections: list[tuple[str, str, str]] = []  # (id, title, html)
    summary: dict = {"train": asm.train.name, "gearrotor_report": 1}

    def pyplot_png(fn, name, *args, **kw):
        import matplotlib.pyplot as plt

        fig = fn(*args, path=tmp / name, **kw)
        plt.close(fig)
        figures.append(tmp / name)

    stab = _stability(res, camp)
    summary["stability"] = stab
    if res is not None:
        summary["modal"] = res.to_dict()
        el = [i for i in range(len(res)) if not res.overdamped[i]]
        for k in range(0, min(len(el), 16), 8):
            pyplot_png(plot_mode_shapes, f"modes_{k // 8 + 1}.png", res, modes=el[k : k + 8])
        body = _modes_table(res)
        if el:
            body += _figure_html(ix.mode_shape_figure(res), "fig-modes")
        else:
            body += (
                "<p>Every mode below the maximum frequency is over-damped: no shape to draw.</p>"
            )
        sections.append(("modes", f"Modes at {res.speed * RPM:.0f} rpm", body))
    if res is not None or camp is not None:
        sections.append(("stability", "Stability margins", _stability_html(stab)))
    if camp is not None:
        summary["campbell"] = {
            "crossings": camp.to_dict()["crossings"],
            "orders": camp.to_dict()["orders"],
        }
        pyplot_png(plot_campbell, "campbell.png", camp, max_frequency=fmax)
        body = _figure_html(ix.campbell_figure(camp, max_frequency=fmax), "fig-campbell")
        body += _crossings_table(camp)
        sections.append(("campbell", "Campbell diagram", body))
    if unb is not None:
        used = _unbalances_used(asm, unbalances, api=api, w=w)
        checks = _api_checks(unb)
        checks["unbalance"] = used
        summary["api684"] = checks
        d = unb.to_dict()
        summary["unbalance"] = {
            "operating_range_rpm": d["operating_range_rpm"],
            "basis": used["basis"],
            "unbalances": used["planes"],
            "probes": [
                {k: v for k, v in p.items() if k not in ("amplitude_um", "phase_deg")}
                for p in d["probes"]
            ],
        }
        pyplot_png(plot_bode, "bode.png", unb)
        k_op = int(np.argmin(np.abs(unb.speeds - unb.operating_range[1])))
        pyplot_png(plot_orbits, "orbits_operating.png", unb, k_op)
        body = _unbalance_intro(unb, used)
        body += _figure_html(ix.bode_figure(unb), "fig-bode")
        body += _figure_html(ix.orbit_figure(unb), "fig-orbits")
        sections.append(("unbalance", "Unbalance response", body))
        sections.append(("api684", "API 684 / API 617 checks", _api_html(checks)))
    bfig = ix.bearing_coefficient_figure(asm)
    if bfig is not None:
        plot_bearing_coefficients(asm, path=tmp / "bearings.png")
        figures.append(tmp / "bearings.png")
        sections.append(("bearings", "Bearing coefficients", _figure_html(bfig, "fig-bearings")))
    if ds is not None:
        from ..analyses.transient import plots as tplots

        for name, fn in (
            ("transient_spectra.png", tplots.plot_spectra),
            ("transient_whirl_power.png", tplots.plot_whirl_power),
        ):
            _savefig(fn(ds), tmp / name)
            figures.append(tmp / name)
        plot_waterfall(ds, path=tmp / "transient_waterfall.png")
        figures.append(tmp / "transient_waterfall.png")
        wf = speed_waterfall(ds) if speed_varies(ds) else None
        if wf is not None:
            plot_speed_waterfall(wf, path=tmp / "transient_waterfall_speed.png")
            figures.append(tmp / "transient_waterfall_speed.png")
        tsum = _transient_summary(ds)
        if wf is not None:
            tsum["waterfall_vs_speed"] = wf.to_dict()
        summary["transient"] = tsum
        body = _transient_html(tsum, transient)
        body += _figure_html(ix.transient_spectrum_figure(ds), "fig-spectra")
        body += _figure_html(ix.waterfall_figure(ds), "fig-waterfall")
        if wf is not None:
            body += _speed_waterfall_html(wf)
            body += _figure_html(ix.speed_waterfall_figure(wf), "fig-waterfall-speed")
        body += _figure_html(ix.whirl_power_figure(ds), "fig-whirl-power")
        sections.append(("transient", "Transient", body))
    summary["verdicts"] = _verdicts(stab, summary.get("api684"))
    return figures, sections, summary


def _transient_summary(ds) -> dict:
    from ..signals import order_amplitudes

    t = ds["time"].values
    half = t >= t[0] + 0.5 * (t[-1] - t[0])
    out: dict = {
        "t_start_s": float(t[0]),
        "t_end_s": float(t[-1]),
        "samples": int(len(t)),
        "status": ds.attrs.get("status"),
        "nodes": {},
        "shafts": {},
        "meshes": {},
        "whirl_power_mean_W": {},
    }
    speed = ds["shaft_speed"].values
    for k, node in enumerate(ds["node"].values):
        si = int(ds["node_shaft"].values[k]) if "node_shaft" in ds else 0
        amps = {
            c: order_amplitudes(t[half], ds[c].values[half, k], speed[half, si]) for c in ("x", "y")
        }
        out["nodes"][str(node)] = {
            f"{c}_{n}x_um": float(amps[c][n - 1]) * 1e6 for c in ("x", "y") for n in (1, 2)
        }
    for k, name in enumerate(ds["shaft"].values):
        rpm = np.abs(speed[:, k]) * RPM
        out["shafts"][str(name)] = {
            "speed_min_rpm": float(rpm.min()),
            "speed_max_rpm": float(rpm.max()),
        }
    if "mesh" in ds.dims and "mesh_force" in ds:
        for k, name in enumerate(ds["mesh"].values):
            f = ds["mesh_force"].values[:, k]
            d = {"force_min_N": float(f.min()), "force_max_N": float(f.max())}
            if "contact" in ds:
                d["contact_loss_fraction"] = float(np.mean(ds["contact"].values[:, k] == 0))
            out["meshes"][str(name)] = d
    P = ds["whirl_power"].values
    for k, name in enumerate(ds["component"].values):
        out["whirl_power_mean_W"][str(name)] = float(np.mean(P[half, k]))
    return out


def _verdicts(stab: dict, api: dict | None) -> list[dict]:
    out = []
    m = stab.get("modal")
    if m is not None:
        low = m.get("lowest_log_dec")
        txt = (
            f"lowest log dec {low['log_dec']:.3g} (mode {low['mode']}, "
            f"{low['frequency_rpm']:.0f} cpm)"
            if low
            else "no lightly damped mode"
        )
        out.append(
            {
                "check": f"stability at {m['speed_rpm']:.0f} rpm",
                "ok": m["ok"],
                "detail": ("stable; " if m["stable"] else f"UNSTABLE modes {m['unstable_modes']}; ")
                + txt,
            }
        )
    c = stab.get("campbell")
    if c is not None and c["lowest"] is not None:
        lo = c["lowest"]
        out.append(
            {
                "check": "stability over the Campbell speed range",
                "ok": c["ok"],
                "detail": f"lowest log dec {lo['min_log_dec']:.3g} (mode {lo['mode']} at "
                f"{lo['at_speed_rpm']:.0f} rpm)",
            }
        )
    if api is not None:
        nf = sum(x["result"] == "fail" for x in api["criticals"])
        out.append(
            {
                "check": "API 684 separation margins",
                "ok": nf == 0,
                "detail": f"{len(api['criticals'])} critical peaks, {nf} fail, "
                f"{api['undetermined']} with AF not determined",
            }
        )
        na = sum(x["result"] == "fail" for x in api["amplitudes"])
        out.append(
            {
                "check": "API 617 vibration limit in the operating range",
                "ok": na == 0,
                "detail": f"{len(api['amplitudes'])} probes, {na} above the limit "
                + (
                    "(with the API 617 unbalance)"
                    if api["unbalance"]["basis"] == "api617"
                    else "(with the model's unbalance)"
                ),
            }
        )
    return out


# ---- HTML ----------------------------------------------------------------------------------------
_CSS = """
body { font-family: system-ui, -apple-system, 'Segoe UI', sans-serif; margin: 0; color: #222; }
header { background: #24364b; color: white; padding: 14px 28px; }
header h1 { margin: 0; font-size: 1.4em; }
header p { margin: 4px 0 0; opacity: 0.85; font-size: 0.9em; }
nav { position: sticky; top: 0; background: #eef2f6; padding: 6px 28px; z-index: 10;
      border-bottom: 1px solid #cdd6e0; font-size: 0.9em; }
nav a { margin-right: 14px; color: #24364b; text-decoration: none; }
main { padding: 0 28px 40px; max-width: 1300px; }
section { margin-top: 26px; }
h2 { border-bottom: 2px solid #24364b; padding-bottom: 3px; font-size: 1.2em; }
table { border-collapse: collapse; font-size: 0.85em; margin: 8px 0 14px; }
th, td { border: 1px solid #ccd; padding: 3px 8px; text-align: right; }
th { background: #eef2f6; }
td.l, th.l { text-align: left; }
tr.bad td { background: #fde2e2; }
tr.warn td { background: #fff4d6; }
tr.od td { color: #888; }
.ok { color: #1a7f37; font-weight: 600; }
.fail { color: #c62828; font-weight: 600; }
.na { color: #8a6d00; font-weight: 600; }
.note { background: #fff8e1; border-left: 4px solid #f0b400; padding: 6px 10px; }
.plot { margin: 10px 0 18px; border: 1px solid #e3e7ec; }
"""


def _e(x) -> str:
    return html.escape(str(x), quote=True)


def _fmt(x, spec=".3g", none="–") -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return none
    return format(x, spec)


def _badge(ok) -> str:
    if ok is None:
        return '<span class="na">n/a</span>'
    return '<span class="ok">pass</span>' if ok else '<span class="fail">FAIL</span>'


def _figure_html(fig, div_id: str) -> str:
    import plotly.io as pio

    fig.update_layout(template="plotly_white")
    h = fig.layout.height or 500
    inner = pio.to_html(
        fig,
        full_html=False,
        include_plotlyjs=False,
        include_mathjax=False,
        div_id=div_id,
        config=_PLOTLY_CONFIG,
        default_height=f"{h}px",
    )
    return f'<div class="plot">{inner}</div>'


def _modes_table(res) -> str:
    head = (
        "<table><tr><th>#</th><th>frequency (cpm)</th><th>frequency (Hz)</th>"
        "<th>log dec</th><th>damping ratio</th><th>whirl "
        + _e("/".join(res.shaft_names))
        + "</th><th>type</th><th>energy L / T / A (%)</th><th class='l'>status</th></tr>"
    )
    rows = [head]
    for i in range(len(res)):
        st = _mode_status(res, i)
        cls = {"UNSTABLE": "bad", "low damping": "warn", "over-damped": "od"}.get(st, "")
        fr = res.energy_fractions[i] * 100
        rows.append(
            f"<tr class='{cls}'><td>{i}</td><td>{res.frequency_rpm[i]:.1f}</td>"
            f"<td>{res.frequency_hz[i]:.3f}</td><td>{res.log_dec[i]:.4g}</td>"
            f"<td>{res.damping_ratio[i]:.4f}</td><td>{_e('/'.join(res.whirl_per_shaft[i]))}</td>"
            f"<td>{_e(res.mode_type[i])}</td><td>{fr[0]:.0f} / {fr[2]:.0f} / {fr[1]:.0f}</td>"
            f"<td class='l'>{_e(st)}</td></tr>"
        )
    rows.append("</table>")
    nr = int(np.sum(res.rigid_body))
    extra = (
        f"<p>{len(res)} damped modes up to the maximum frequency; "
        f"{len(res.real_eigenvalues)} real eigenvalues ({nr} rigid-body, "
        f"{len(res.real_eigenvalues) - nr} over-damped) are not listed. Whirl per shaft "
        "relative to that shaft's spin (F forward, B backward, – no lateral motion); type "
        "from kinetic-energy fractions (L lateral, T torsional, A axial).</p>"
    )
    return "\n".join(rows) + extra


def _stability_html(stab: dict) -> str:
    parts = [
        f"<p>Acceptance threshold: log dec ≥ {LOG_DEC_THRESHOLD} for every mode that is not "
        "over-damped (API 617 Level II criterion); a negative log dec is an unstable "
        "mode.</p>"
    ]
    m = stab.get("modal")
    if m is not None:
        low = m.get("lowest_log_dec")
        parts.append("<table><tr><th class='l'>at operating speed</th><th>value</th></tr>")
        parts.append(f"<tr><td class='l'>speed (rpm)</td><td>{m['speed_rpm']:.0f}</td></tr>")
        parts.append(f"<tr><td class='l'>all modes stable</td><td>{_badge(m['stable'])}</td></tr>")
        if low:
            parts.append(
                f"<tr><td class='l'>lowest log dec</td><td>{low['log_dec']:.4g} (mode "
                f"{low['mode']}, {low['frequency_rpm']:.0f} cpm, {_e(low['type'])}, "
                f"{_e(low['whirl'])})</td></tr>"
            )
            parts.append(
                f"<tr><td class='l'>margin to threshold</td>"
                f"<td>{low['log_dec'] - LOG_DEC_THRESHOLD:+.4g}</td></tr>"
            )
        parts.append(
            f"<tr><td class='l'>unstable modes</td><td>{m['unstable_modes'] or '–'}"
            f"</td></tr><tr><td class='l'>low-damping modes</td>"
            f"<td>{m['low_damping_modes'] or '–'}</td></tr></table>"
        )
    c = stab.get("campbell")
    if c is not None:
        lo, hi = c["speed_range_rpm"]
        parts.append(
            f"<p>Over the Campbell sweep {lo:.0f}..{hi:.0f} rpm, lowest log dec of each "
            "tracked mode:</p><table><tr><th>mode</th><th>min log dec</th>"
            "<th>at speed (rpm)</th><th>frequency there (cpm)</th><th>check</th></tr>"
        )
        for d in c["modes"]:
            cls = (
                "bad"
                if d["min_log_dec"] < 0
                else ("warn" if d["min_log_dec"] < LOG_DEC_THRESHOLD else "")
            )
            parts.append(
                f"<tr class='{cls}'><td>{d['mode']}</td><td>{d['min_log_dec']:.4g}</td>"
                f"<td>{d['at_speed_rpm']:.0f}</td><td>{d['frequency_rpm']:.0f}</td>"
                f"<td>{_badge(d['min_log_dec'] >= LOG_DEC_THRESHOLD)}</td></tr>"
            )
        parts.append("</table>")
    return "\n".join(parts)


def _crossings_table(camp) -> str:
    if not camp.crossings:
        return "<p>No mode crosses an excitation line in the speed range.</p>"
    rows = [
        "<h3>Crossing speeds</h3><table><tr><th>mode</th><th class='l'>excitation</th>"
        "<th>speed (rpm)</th><th>frequency (cpm)</th><th>log dec</th><th>whirl</th>"
        "<th>type</th></tr>"
    ]
    for c in camp.crossings:
        rows.append(
            f"<tr><td>{c.mode}</td><td class='l'>{_e(c.order)}</td><td>{c.speed * RPM:.0f}</td>"
            f"<td>{c.frequency * RPM:.0f}</td><td>{c.log_dec:.3g}</td><td>{_e(c.whirl)}</td>"
            f"<td>{_e(c.mode_type)}</td></tr>"
        )
    rows.append("</table>")
    return "\n".join(rows)


def _unbalances_used(asm, unbalances, *, api: bool, w: float) -> dict:
    """Which unbalance the response uses: ``{"basis", "label", "planes": [...]}``."""
    from ..analyses.api617 import api617_basis

    train = asm.train
    basis = api617_basis(asm, w) if api else [(None, None)] * len(unbalances)
    planes = []
    for k, (u, (mass, n)) in enumerate(zip(unbalances, basis, strict=True)):
        d = {
            "shaft": u.shaft,
            "node": train.node_index(u, f"unbalances[{k}]")[1],
            "amount_g_mm": u.amount * 1e6,
            "phase_deg": float(np.rad2deg(u.phase)),
        }
        if api:
            d["journal_mass_kg"] = mass
            d["max_continuous_speed_rpm"] = n * RPM
        planes.append(d)
    label = (
        "API 617 unbalance: 4 × 6350 W/N g·mm per plane (W its share of the shaft mass, kg; "
        "N its shaft's maximum continuous speed, rpm)"
        if api
        else "the model's unbalance"
    )
    return {"basis": "api617" if api else "model", "label": label, "planes": planes}


def _unbalance_list(used: dict) -> str:
    items = []
    for p in used["planes"]:
        txt = (
            f"{p['amount_g_mm']:.1f} g·mm on {_e(p['shaft'])} node {p['node']} at "
            f"{p['phase_deg']:.0f}°"
        )
        if "journal_mass_kg" in p:
            txt += (
                f" (W = {p['journal_mass_kg']:.2f} kg, N = {p['max_continuous_speed_rpm']:.0f} rpm)"
            )
        items.append(f"<li>{txt}</li>")
    return "<ul>" + "".join(items) + "</ul>"


def _unbalance_intro(unb, used: dict) -> str:
    return (
        f"<p>Sweep {unb.speeds[0] * RPM:.0f}..{unb.speeds[-1] * RPM:.0f} rpm "
        f"({len(unb.speeds)} speeds) with {_e(used['label'])}:</p>{_unbalance_list(used)}"
        "<p>Amplitudes are zero-to-peak, synchronous with each probe's own shaft.</p>"
    )


def _api_html(api: dict) -> str:
    lo, hi = api["operating_range_rpm"]
    parts = [
        f"<p>Operating range {lo:.0f}..{hi:.0f} rpm (reference shaft). Amplification factor by "
        "the half-power method (API 684); required separation margin per API 617: none for "
        "AF &lt; 2.5, else 17 (1 − 1/(AF − 1.5)) % below the minimum operating speed and "
        "10 + 17 (1 − 1/(AF − 1.5)) % (at most 26 %) above the maximum continuous speed.</p>",
        "<table><tr><th class='l'>probe</th><th class='l'>shaft</th><th>critical (rpm)</th>"
        "<th>probe shaft (rpm)</th><th>amplitude (µm 0-pk)</th><th>AF</th>"
        "<th>separation margin (%)</th><th>required (%)</th><th>result</th></tr>",
    ]
    if not api["criticals"]:
        parts.append("<tr><td class='l' colspan='9'>no response peak in the sweep</td></tr>")
    for c in api["criticals"]:
        ok = {"pass": True, "fail": False}.get(c["result"])
        cls = "bad" if ok is False else ("warn" if ok is None else "")
        parts.append(
            f"<tr class='{cls}'><td class='l'>{_e(c['probe'])}</td><td class='l'>"
            f"{_e(c['shaft'])}</td><td>{c['speed_rpm']:.0f}</td>"
            f"<td>{c['probe_shaft_speed_rpm']:.0f}</td><td>{c['amplitude_um']:.4g}</td>"
            f"<td>{_fmt(c['amplification_factor'], '.2f')}</td>"
            f"<td>{_fmt(c['separation_margin_pct'], '.1f')}</td>"
            f"<td>{_fmt(c['required_margin_pct'], '.1f')}</td><td>{_badge(ok)}</td></tr>"
        )
    parts.append("</table>")
    if api["undetermined"]:
        parts.append(
            "<p class='note'>n/a: a half-power point lies outside the sweep, so the "
            "amplification factor (and the required margin) is not determined.</p>"
        )
    parts.append(
        "<table><tr><th class='l'>probe</th><th>max pk-pk in operating range (µm)</th>"
        "<th>API 617 limit pk-pk (µm)</th><th>result</th></tr>"
    )
    for a in api["amplitudes"]:
        ok = a["result"] == "pass"
        parts.append(
            f"<tr class='{'' if ok else 'bad'}'><td class='l'>{_e(a['probe'])}</td>"
            f"<td>{a['max_pp_in_operating_range_um']:.4g}</td><td>{a['limit_pp_um']:.2f}</td>"
            f"<td>{_badge(ok)}</td></tr>"
        )
    used = api["unbalance"]
    if used["basis"] == "api617":
        parts.append(
            "</table><p id='api-unbalance'>Unbalance used for these checks: "
            f"{_e(used['label'])}, at the planes and phases of the model:</p>"
            + _unbalance_list(used)
        )
    else:
        parts.append(
            "</table><p id='api-unbalance'>Unbalance used for these checks: the model's "
            "unbalance (listed under Unbalance response), not the API 617 amount; the API 617 "
            "procedure applies 4× the allowable unbalance, 4 × 6350 W/N g·mm per plane "
            "(<code>gearrotor report --api</code>, <code>gearrotor unbalance --api</code>).</p>"
        )
    return "\n".join(parts)


def _transient_html(tsum: dict, path) -> str:
    parts = [
        f"<p>Result file <code>{_e(Path(path).name)}</code>: "
        f"{tsum['t_start_s']:.4g}..{tsum['t_end_s']:.4g} s, {tsum['samples']} samples, "
        f"status {_e(tsum['status'])}. Amplitudes by least squares over the second half "
        "of the run at each node's mean shaft speed.</p>",
        "<table><tr><th class='l'>node</th><th>x 1x (µm)</th><th>y 1x (µm)</th>"
        "<th>x 2x (µm)</th><th>y 2x (µm)</th></tr>",
    ]
    for n, a in tsum["nodes"].items():
        parts.append(
            f"<tr><td class='l'>{_e(n)}</td><td>{a['x_1x_um']:.4g}</td>"
            f"<td>{a['y_1x_um']:.4g}</td><td>{a['x_2x_um']:.4g}</td>"
            f"<td>{a['y_2x_um']:.4g}</td></tr>"
        )
    parts.append(
        "</table><table><tr><th class='l'>shaft</th><th>min speed (rpm)</th>"
        "<th>max speed (rpm)</th></tr>"
    )
    for n, a in tsum["shafts"].items():
        parts.append(
            f"<tr><td class='l'>{_e(n)}</td><td>{a['speed_min_rpm']:.2f}</td>"
            f"<td>{a['speed_max_rpm']:.2f}</td></tr>"
        )
    parts.append("</table>")
    if tsum["meshes"]:
        parts.append(
            "<table><tr><th class='l'>mesh</th><th>min force (N)</th>"
            "<th>max force (N)</th><th>contact loss (%)</th></tr>"
        )
        for n, a in tsum["meshes"].items():
            cl = a.get("contact_loss_fraction")
            parts.append(
                f"<tr><td class='l'>{_e(n)}</td><td>{a['force_min_N']:.1f}</td>"
                f"<td>{a['force_max_N']:.1f}</td>"
                f"<td>{_fmt(None if cl is None else 100 * cl, '.2f')}</td></tr>"
            )
        parts.append("</table>")
    return "\n".join(parts)


def _speed_waterfall_html(wf) -> str:
    lo, hi = wf.speed_rpm.min(), wf.speed_rpm.max()
    return (
        f"<h3 id='waterfall-speed'>Waterfall against speed</h3><p>The speed of {_e(wf.shaft)} "
        f"changes during the run ({lo:.0f}..{hi:.0f} rpm over the window centres): spectra of "
        f"{_e(wf.signal)} in {len(wf.time)} Hann windows of {wf.window_s * 1e3:.0f} ms (bin "
        f"{wf.bin_cpm:.0f} cpm), each drawn at its mean speed, with the shaft orders as dashed "
        "lines (" + ", ".join(f"{_e(k)} = {v:.4g}×" for k, v in wf.orders) + "). A ridge on a "
        "line is locked to the speed; a ridge at a constant frequency is a resonance the run "
        "sweeps through.</p>"
    )


def _page(train, sections, summary, figures, notes, *, source, command) -> str:
    import plotly
    from plotly.offline import get_plotlyjs

    from .. import __version__

    now = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    verdicts = summary.get("verdicts", [])
    vt = ["<table><tr><th class='l'>check</th><th>result</th><th class='l'>detail</th></tr>"]
    for v in verdicts:
        vt.append(
            f"<tr class='{'' if v['ok'] else 'bad'}'><td class='l'>{_e(v['check'])}</td>"
            f"<td>{_badge(v['ok'])}</td><td class='l'>{_e(v['detail'])}</td></tr>"
        )
    vt.append("</table>")
    if not verdicts:
        vt = ["<p>No stability or API check was requested.</p>"]
    shafts = train.layout().shafts
    model_rows = "".join(
        f"<tr><td class='l'>{_e(s.name)}</td><td>{len(s.z)}</td><td>{np.ptp(s.z):.4g}</td>"
        f"<td>({s.position[0]:.4g}, {s.position[1]:.4g})</td>"
        f"<td>{s.speed_ratio * train.speed * RPM:.1f}</td></tr>"
        for s in shafts
    )
    model_html = (
        "<table><tr><th class='l'>shaft</th><th>nodes</th><th>length (m)</th>"
        "<th>centre x, y (m)</th><th>nominal speed (rpm)</th></tr>" + model_rows + "</table>"
        f"<p>{len(train.bearings)} bearings, {len(train.meshes)} gear meshes, "
        f"{len(train.unbalances)} unbalances, {len(train.probes)} probes.</p>"
    )
    secs = [
        (
            "summary",
            "Summary",
            "".join(vt) + "".join(f"<p class='note'>{_e(n)}</p>" for n in notes),
        ),
        ("model", "Model", model_html),
        *sections,
    ]
    files = "".join(f"<li><a href='{_e(p.name)}'>{_e(p.name)}</a></li>" for p in figures)
    secs.append(
        (
            "files",
            "Static figures and data",
            "<p>Files written next to this report (PNG, and the numbers as "
            "<a href='report.json'>report.json</a>):</p><ul>" + files + "</ul>",
        )
    )
    nav = "".join(f"<a href='#{i}'>{_e(t)}</a>" for i, t, _ in secs)
    body = "\n".join(f"<section id='{i}'><h2>{_e(t)}</h2>\n{h}\n</section>" for i, t, h in secs)
    sub = " · ".join(
        x
        for x in (
            f"model {_e(source)}" if source else "",
            f"gearrotor {__version__}",
            f"plotly {plotly.__version__}",
            now,
        )
        if x
    )
    cmd = f"<p>Command: <code>{_e(command)}</code></p>" if command else ""
    return (
        "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>"
        f"<title>{_e(train.name)} – gearrotor report</title>"
        "<meta name='viewport' content='width=device-width, initial-scale=1'>"
        f"<style>{_CSS}</style>\n"
        f"<script type='text/javascript'>{get_plotlyjs()}</script>\n</head><body>"
        f"<header><h1>{_e(train.name)}</h1><p>{sub}</p>{cmd}</header>"
        f"<nav>{nav}</nav><main>{body}</main></body></html>\n"
    )
