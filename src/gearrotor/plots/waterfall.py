"""Waterfall against speed of a run-up or coast-down.

Short-time amplitude spectra of one signal (a probe, or a node's x or y) along a transient run,
each placed at the mean speed of its window, with the shaft orders (1x, 2x, each gear-mesh
frequency) drawn as lines ``f = order × speed`` through the windows. A component locked to the
shaft speed lies on its order line; a resonance stays at a fixed frequency while the speed
sweeps through it.

* :func:`speed_waterfall` computes the spectra (:class:`SpeedWaterfall`) from a
  :class:`~gearrotor.analyses.transient.TransientResult` or the ``xarray.Dataset`` of a saved
  result; :func:`short_time_spectra` is the same on plain arrays;
* :func:`speed_varies` says whether a run changes speed enough for such a plot (the report draws
  it only then);
* :func:`plot_speed_waterfall` draws it with matplotlib (the plotly version is
  :func:`gearrotor.plots.report.sections.transient.speed_waterfall_figure`).

Window length: the 1x of a shaft sweeping at α rev/s² moves by one frequency bin (1/T) during a
window of length T when T = 1/√α, which balances smearing by the sweep against the resolution;
that is the default, bounded by a quarter of the run and 32 samples. Hann window, zero-to-peak
amplitude (a steady sinusoid at a bin reads its amplitude), linear trend removed per window.
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import ModelError
from ..files import save_figure
from ..signals import DISPLAY_FLOOR

__all__ = [
    "SpeedWaterfall",
    "plot_speed_waterfall",
    "short_time_spectra",
    "speed_varies",
    "speed_waterfall",
]

RPM = 30.0 / np.pi  # rad/s -> rpm
MIN_SAMPLES = 32  # shortest window (samples)


@dataclass(frozen=True)
class SpeedWaterfall:
    """Short-time spectra of one signal along a run, placed at the speed of each window.

    Shapes: nw windows, nf frequencies. Amplitudes zero-to-peak in the signal's unit (m).
    ``orders`` are ``(label, order)`` pairs relative to ``shaft`` (whose speed is
    ``speed_rpm``): 1x, 2x and one per gear mesh (teeth × that gear's shaft speed / this
    shaft's speed).
    """

    signal: str  # e.g. "probe gear1_x" or "shaft1[10] x"
    shaft: str  # the shaft whose speed places the windows
    frequency_cpm: NDArray  # (nf,)
    amplitude: NDArray  # (nw, nf) m 0-pk
    time: NDArray  # (nw,) s, window centres
    speed_rpm: NDArray  # (nw,) mean |speed| of `shaft` over each window
    window_s: float  # window length, s
    orders: tuple[tuple[str, float], ...]

    @property
    def bin_cpm(self) -> float:
        """Frequency resolution (bin width), cpm."""
        return float(self.frequency_cpm[1] - self.frequency_cpm[0])

    @property
    def nyquist_cpm(self) -> float:
        return float(self.frequency_cpm[-1])

    def order_line(self, order: float) -> NDArray:
        """(nw,) frequency (cpm) of a shaft order at each window."""
        return order * self.speed_rpm

    def ridge(self, order: float, half_width: float = 1.5) -> tuple[NDArray, NDArray]:
        """Per window, the frequency (cpm) and amplitude of the largest spectral line within
        ``half_width`` bins of the order line (NaN where the line is beyond the Nyquist
        frequency)."""
        fl = self.order_line(order)
        fpk = np.full(len(fl), np.nan)
        apk = np.full(len(fl), np.nan)
        for i, f0 in enumerate(fl):
            m = np.abs(self.frequency_cpm - f0) <= half_width * self.bin_cpm
            if f0 > self.nyquist_cpm or not m.any():
                continue
            k = np.flatnonzero(m)[np.argmax(self.amplitude[i, m])]
            fpk[i], apk[i] = self.frequency_cpm[k], self.amplitude[i, k]
        return fpk, apk

    def to_dict(self) -> dict:
        """JSON-ready description (no spectra)."""
        return {
            "signal": self.signal,
            "shaft": self.shaft,
            "windows": int(len(self.time)),
            "window_s": self.window_s,
            "bin_cpm": self.bin_cpm,
            "speed_range_rpm": [float(self.speed_rpm.min()), float(self.speed_rpm.max())],
            "orders": {k: float(v) for k, v in self.orders},
        }


# ---- computation ---------------------------------------------------------------------------
def short_time_spectra(
    t: NDArray,
    x: NDArray,
    speed: NDArray,
    *,
    window: float | None = None,
    n_windows: int = 40,
) -> tuple[NDArray, NDArray, NDArray, NDArray, float]:
    """Hann-windowed amplitude spectra of ``x`` over ``n_windows`` windows evenly spread along
    the run (overlapping when needed).

    Parameters
    ----------
    t : (n,) s, uniformly sampled
    x : (n,) the signal
    speed : (n,) rad/s, the speed that places each window (its sign is ignored)
    window : s, window length (default: 1/√α with α the mean sweep rate in rev/s², at most a
        quarter of the run and at least 32 samples)
    n_windows : number of windows

    Returns
    -------
    frequency_cpm (nf,), amplitude (n_windows, nf) 0-pk, window-centre time (n_windows,) s,
    mean |speed| per window (n_windows,) rpm, window length s.
    """
    from ..signals import spectrum

    t = np.asarray(t, float)
    x = np.asarray(x, float)
    w = np.abs(np.asarray(speed, float))
    n = len(t)
    if n < 2 * MIN_SAMPLES or len(x) != n or len(w) != n:
        raise ModelError(
            "too few samples for a waterfall",
            value=f"{n} samples",
            expected=f"at least {2 * MIN_SAMPLES} samples of time, signal and speed",
        )
    dt = float(np.median(np.diff(t)))
    duration = float(t[-1] - t[0])
    if window is None:
        slope = abs(np.polyfit(t - t[0], w, 1)[0]) / (2 * np.pi)  # rev/s²
        window = 1.0 / np.sqrt(slope) if slope > 0 else duration
        window = min(window, duration / 4)
    L = max(MIN_SAMPLES, int(round(window / dt)))
    if L > n:
        raise ModelError(
            "the waterfall window is longer than the run",
            field="window",
            value=f"{window:.4g} s",
            expected=f"at most {duration:.4g} s",
        )
    if n_windows < 2:
        raise ModelError("a waterfall needs at least 2 windows", field="n_windows", value=n_windows)
    starts = np.unique(np.round(np.linspace(0, n - L, n_windows)).astype(int))
    amps, tc, sc = [], [], []
    f = None
    for a in starts:
        f, amp = spectrum(x[a : a + L], dt, window="hann")
        amps.append(amp)
        tc.append(float(np.mean(t[a : a + L])))
        sc.append(float(np.mean(w[a : a + L]) * RPM))
    return f, np.array(amps), np.array(tc), np.array(sc), L * dt


def _channels(result):
    """The arrays of a TransientResult or of the Dataset of a saved one."""
    if hasattr(result, "data_vars"):
        ds = result
        return {
            "time": ds["time"].values,
            "shaft_speed": ds["shaft_speed"].values,
            "shafts": [str(s) for s in ds["shaft"].values],
            "nodes": [str(s) for s in ds["node"].values],
            "node_shaft": ds["node_shaft"].values.astype(int),
            "x": ds["x"].values,
            "y": ds["y"].values,
            "probes": [str(s) for s in ds["probe"].values] if "probe" in ds.dims else [],
            "probe_signal": ds["probe_signal"].values if "probe_signal" in ds else None,
            "model_json": ds.attrs.get("model_json"),
        }
    r = result
    return {
        "time": r.time,
        "shaft_speed": r.shaft_speed,
        "shafts": list(r.shaft_names),
        "nodes": list(r.node_labels),
        "node_shaft": np.asarray(r.node_shaft, int),
        "x": r.node_x,
        "y": r.node_y,
        "probes": list(r.probe_names),
        "probe_signal": r.probes,
        "model_json": r.model_json,
    }


def speed_varies(result, *, threshold: float = 0.01, shaft: int = 0) -> bool:
    """Whether the run is a run-up or coast-down: the mean |speed| of ``shaft`` over tenths of
    the run spans at least ``threshold`` (fraction) of its largest value. Averaging over tenths
    keeps torsional speed oscillations out."""
    c = _channels(result)
    w = np.abs(c["shaft_speed"][:, shaft])
    if len(w) < 10:
        return False
    means = np.array([b.mean() for b in np.array_split(w, 10)])
    top = means.max()
    return bool(top > 0 and (means.max() - means.min()) >= threshold * top)


def speed_waterfall(
    result,
    *,
    probe: str | None = None,
    node: str | None = None,
    component: str = "x",
    window: float | None = None,
    n_windows: int = 40,
) -> SpeedWaterfall:
    """Waterfall against speed of one signal of a transient run.

    Parameters
    ----------
    result : a :class:`~gearrotor.analyses.transient.TransientResult` or the
        ``xarray.Dataset`` of a saved one (:func:`~gearrotor.analyses.transient.load_result`)
    probe : probe name (default: the first probe; without probes, the first node's ``x``)
    node, component : a recorded node label (e.g. ``"shaft1[10]"``) and ``"x"`` or ``"y"``,
        instead of a probe
    window : window length, s (default in the module docstring)
    n_windows : number of windows along the run

    The windows are placed at the speed of the signal's shaft; the mesh orders are relative to
    it through the mean speed ratio of the run.
    """
    c = _channels(result)
    model = _model(c["model_json"])
    if probe is not None and node is not None:
        raise ModelError(
            "give a probe or a node, not both", field="probe/node", value=(probe, node)
        )
    if component not in ("x", "y"):
        raise ModelError(
            "unknown component", field="component", value=component, expected="'x' or 'y'"
        )
    if node is None and (probe is not None or c["probes"]):
        name = probe if probe is not None else c["probes"][0]
        if name not in c["probes"] or c["probe_signal"] is None:
            raise ModelError(
                "unknown probe",
                field="probe",
                value=name,
                expected="one of " + (", ".join(c["probes"]) or "(no probe recorded)"),
            )
        x = c["probe_signal"][:, c["probes"].index(name)]
        pr = [p for p in (model or {}).get("probes", []) if p.get("name") == name]
        shaft_name = pr[0]["shaft"] if pr else c["shafts"][0]
        signal = f"probe {name}"
    else:
        label = node if node is not None else c["nodes"][0]
        if label not in c["nodes"]:
            raise ModelError(
                "unknown node",
                field="node",
                value=label,
                expected="one of " + ", ".join(c["nodes"]),
            )
        k = c["nodes"].index(label)
        x = c[component][:, k]
        shaft_name = c["shafts"][int(c["node_shaft"][k])]
        signal = f"{label} {component}"
    si = c["shafts"].index(shaft_name) if shaft_name in c["shafts"] else 0
    speed = c["shaft_speed"]
    f, amp, tc, sc, T = short_time_spectra(
        c["time"], x, speed[:, si], window=window, n_windows=n_windows
    )
    orders: list[tuple[str, float]] = [("1x", 1.0), ("2x", 2.0)]
    mean = np.mean(np.abs(speed), axis=0)
    meshes = (model or {}).get("meshes", [])
    for k, m in enumerate(meshes):
        try:
            gs = c["shafts"].index(m["gear"]["shaft"])
            order = float(m["gear"]["teeth"]) * mean[gs] / mean[si]
        except (KeyError, ValueError, TypeError, ZeroDivisionError):
            continue
        name = m.get("name") or f"meshes[{k}]"
        orders.append(("mesh" if len(meshes) == 1 else f"mesh {name}", order))
    return SpeedWaterfall(
        signal=signal,
        shaft=c["shafts"][si],
        frequency_cpm=f,
        amplitude=amp,
        time=tc,
        speed_rpm=sc,
        window_s=T,
        orders=tuple(orders),
    )


def _model(text) -> dict | None:
    try:
        return json.loads(text) if text else None
    except (TypeError, ValueError):
        return None


# ---- figure ------------------------------------------------------------------------------------
def _bands(
    wf: SpeedWaterfall, max_frequency: float | None = None
) -> list[tuple[str, float, float]]:
    """Frequency ranges (title, lo, hi in cpm) of the figure: 0 to 3.5× the highest speed (1x,
    2x), and, when a mesh order is within the Nyquist frequency, the band the mesh lines sweep
    ± 3× the highest speed. ``max_frequency`` (cpm) instead gives one panel 0..max."""
    top = float(wf.speed_rpm.max())
    nyq = wf.nyquist_cpm
    if max_frequency is not None:
        return [("spectra", 0.0, min(float(max_frequency), nyq))]
    out = [("orders 1x, 2x", 0.0, min(3.5 * top, nyq))]
    mesh = [o for lab, o in wf.orders if lab.startswith("mesh")]
    if mesh:
        lo = min(mesh) * float(wf.speed_rpm.min()) - 3 * top
        hi = min(max(mesh) * top + 3 * top, nyq)
        if lo < hi and lo > out[0][2]:
            out.append(("near the mesh frequency", lo, hi))
    return out


def _order_lines(wf: SpeedWaterfall, lo: float, hi: float) -> list[tuple[int, str, float, bool]]:
    """(colour index, label or "", order, is a sideband) of the order lines that cross the band
    lo..hi (cpm): the orders of ``wf`` and the ±1x sidebands of each mesh order (one label)."""
    out = []
    s = wf.speed_rpm
    for k, (lab, o) in enumerate(wf.orders):
        lines = [(lab, o, False)]
        if lab.startswith("mesh"):
            lines += [(f"{lab} ± 1x", o - 1, True), ("", o + 1, True)]
        for name, order, side in lines:
            if order * s.min() <= hi and order * s.max() >= lo:
                out.append((k, name, order, side))
    return out


def _gain(wf: SpeedWaterfall, m: NDArray) -> tuple[float, float, str]:
    """(offset per metre of amplitude, amplitude of the scale bar (m), a note): the largest
    spectrum in the band is drawn 4 window spacings tall, unless it is below
    :data:`~gearrotor.signals.DISPLAY_FLOOR` of the largest amplitude of the whole waterfall
    (window leakage and round-off, e.g. near the mesh frequency of a constant mesh): then that
    floor is 4 spacings, the band's content draws flat, and the note says how small it is."""
    span = float(np.ptp(wf.speed_rpm)) or float(wf.speed_rpm.max()) * 0.1 or 1.0
    spacing = span / max(len(wf.speed_rpm) - 1, 1)
    peak = float(np.max(wf.amplitude[:, m])) if m.any() else 0.0
    floor = DISPLAY_FLOOR * float(np.max(wf.amplitude, initial=0.0))
    note = ""
    if peak < floor:
        note = (
            f"largest {peak * 1e6:.2g} µm: below {DISPLAY_FLOOR:g} of the largest line "
            "(leakage, round-off)"
        )
        peak = floor
    return (4 * spacing / peak if peak > 0 else 0.0), peak, note


def plot_speed_waterfall(wf: SpeedWaterfall, *, max_frequency: float | None = None, path=None):
    """Waterfall against speed (matplotlib): each window's spectrum drawn on a baseline at its
    speed (rpm), amplitude upwards (scale bar in µm), front spectra hiding those behind; shaft
    orders as dashed lines. One panel for 1x/2x and one near the mesh frequency. Returns the
    Figure (written to ``path`` when given)."""
    from matplotlib.figure import Figure

    bands = _bands(wf, max_frequency)
    fig = Figure(figsize=(6.5 * len(bands), 6.5), layout="constrained")
    axes = fig.subplots(1, len(bands), squeeze=False, sharey=True)[0]
    order = np.argsort(wf.speed_rpm)[::-1]  # back (highest speed) first
    f = wf.frequency_cpm
    for ax, (title, lo, hi) in zip(axes, bands, strict=True):
        m = (f >= lo) & (f <= hi)
        gain, peak, note = _gain(wf, m)
        if note:
            ax.text(
                0.5,
                0.985,
                note,
                transform=ax.transAxes,
                ha="center",
                va="top",
                fontsize=8,
                zorder=10**5,
                bbox=dict(facecolor="white", edgecolor="0.7", alpha=0.9),
            )
        for z, i in enumerate(order):
            base = wf.speed_rpm[i]
            y = base + gain * wf.amplitude[i, m]
            ax.fill_between(f[m], base, y, color="white", zorder=2 * z + 1, lw=0)
            ax.plot(f[m], y, color="C0", lw=0.7, zorder=2 * z + 2)
        s = np.sort(wf.speed_rpm)
        for k, lab, o, side in _order_lines(wf, lo, hi):
            ax.plot(
                o * s,
                s,
                ls=":" if side else "--",
                lw=0.8 if side else 1.0,
                color=f"C{(k + 1) % 10}",
                zorder=10**4,
                label=lab,
            )
        ax.set_xlim(lo, hi)
        ax.set_xlabel("frequency (cpm)")
        ax.set_title(title)
        ax.grid(alpha=0.25, zorder=0)
        ax.legend(loc="lower right", fontsize=8, framealpha=0.9).set_zorder(10**5)
        if gain > 0:  # scale bar: the largest amplitude of the band
            xb = hi - 0.04 * (hi - lo)
            yb = float(s[-1])
            ax.plot([xb, xb], [yb, yb + gain * peak], color="k", lw=2.5, zorder=10**4)
            ax.text(
                xb,
                yb + gain * peak,
                f"{peak * 1e6:.3g} µm",
                ha="right",
                va="bottom",
                fontsize=8,
                zorder=10**4,
            )
    axes[0].set_ylabel(f"speed of {wf.shaft} (rpm)")
    fig.suptitle(
        f"Waterfall against speed: {wf.signal} (0-pk; {len(wf.time)} windows of "
        f"{wf.window_s * 1e3:.0f} ms, bin {wf.bin_cpm:.0f} cpm)"
    )
    if path is not None:
        save_figure(fig, path, dpi=120)
    return fig
