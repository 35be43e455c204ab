"""Study figures: overlay spectra of several cases and trend plots (metric vs parameter).

Every function returns the matplotlib ``Figure`` (the caller saves or closes it);
:func:`report` writes them all as PNG files. Spectra are amplitude spectra (zero-to-peak, µm or
rpm, in cpm) of each case's stored window (Hann window, linear trend removed).
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from ..errors import ModelError
from ..files import (
    check_output,
    figure_bytes,
    make_directory,
    output_set,
    unique_names,
    write_bytes,
    write_json,
)
from ..signals import padded_spectrum
from .cases import case_path, plan, study_status
from .collection import collect, file_sha256, read_case
from .spec import Study, TransientSettings

__all__ = [
    "overlay_spectra",
    "padded_spectrum",
    "report",
    "trend_figure",
    "trend_groups",
    "trend_png",
]

RPM = 30.0 / np.pi
_AMP_METRICS = (
    ("amp_1x", "1x amplitude, max over probes (µm)", "probe", 1e6),
    ("amp_2x", "2x amplitude, max over probes (µm)", "probe", 1e6),
    ("speed_fluctuation", "speed fluctuation, max over shafts (rpm)", "shaft", 1.0),
    ("peak_mesh_force", "peak mesh force, max over meshes (N)", "mesh", 1.0),
    ("contact_loss_fraction", "contact loss, max over meshes (%)", "mesh", 100.0),
    ("dominant_frequency", "dominant displacement frequency, max over probes (cpm)", "probe", 1.0),
)


def _pyplot():
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


#: Layout of the spectra figure (12 x 9.5 in), fixed: constrained layout measured every tick
#: label of the four log axes twice more per figure (0.5 of its 0.85 s). These are the
#: positions it found for the report's labels (figure fractions; column gap sized for the wider
#: speed tick labels; on the right, room for half a 6-digit frequency label at the panel's
#: edge), with the bottom margin set by the legend's rows.
_SPECTRA_FIGSIZE = (12.0, 9.5)
_SPECTRA_LEFT, _SPECTRA_RIGHT, _SPECTRA_TOP = 0.0551, 0.98, 0.947
_SPECTRA_WGAP, _SPECTRA_HGAP = 0.0869, 0.0775  # between the panels, figure fractions
_SPECTRA_BELOW_AXES = 35.6  # points from the legend's top to the lower panels (tick labels, label)


def overlay_spectra(
    cases: dict[str, xr.Dataset],
    *,
    channel: str,
    name: str,
    title: str = "",
    orders: Sequence[float] = (1.0, 2.0),
    figure=None,
):
    """One figure, four panels: the spectra of ``cases`` (label → case dataset) overlaid, in
    full (0 to 1.3× the mesh frequency) and zoomed at 1x, 2x and the mesh frequency (± 6x, to
    show the sidebands spaced at 1x). ``channel``: ``"probe"`` (probe ``name``, µm) or
    ``"speed"`` (shaft ``name``, rpm). ``figure``: a figure this function returned before,
    drawn again with these spectra (the same PNG as a new figure; its tick objects, about 240,
    are made once: 0.1 s a figure)."""
    plt = _pyplot()
    if figure is None:
        fig, axes = plt.subplots(2, 2, figsize=_SPECTRA_FIGSIZE)
        ax_full, ax1, ax2, axm = axes.ravel()
    else:
        fig = figure
        ax_full, ax1, ax2, axm = fig.axes[:4]
        for ax in (ax_full, ax1, ax2, axm):
            for line in list(ax.lines):
                line.remove()
            ax.set_prop_cycle(None)
        for legend in list(fig.legends):
            legend.remove()
    x1 = fmesh = None
    curves = []
    for k, (label, ds) in enumerate(cases.items()):
        t = ds["time"].values
        if len(t) < 16:
            continue
        dt = float(np.median(np.diff(t)))
        if channel == "probe":
            sig = ds["probe_signal"].sel(probe=name).values * 1e6
            shaft = int(ds["probe_shaft"].sel(probe=name))
        else:
            sig = ds["shaft_speed"].sel(shaft=name).values * RPM
            shaft = list(ds["shaft"].values).index(name)
        f, a = padded_spectrum(sig, dt)
        x1c = float(np.abs(ds["shaft_speed"].values[:, shaft]).mean() * RPM)
        x1 = x1c if x1 is None else x1
        if "mesh_frequency" in ds and ds.sizes.get("mesh", 0):
            fmesh = float(ds["mesh_frequency"].values[0]) if fmesh is None else fmesh
        curves.append((label, f"C{k % 10}", f, np.maximum(a, 1e-12)))
    if x1 is None:
        if figure is None:
            plt.close(fig)
        raise ValueError("no case has stored time histories (outputs.histories = 'none'?)")
    top = 1.3 * fmesh if fmesh else 12 * x1
    limits = {ax_full: (0, top), ax1: (0.5 * x1, 1.5 * x1), ax2: (1.5 * x1, 2.5 * x1)}
    limits[axm] = (fmesh - 6 * x1, fmesh + 6 * x1) if fmesh else (2.5 * x1, 10 * x1)
    for ax, (lo, hi) in limits.items():
        for label, color, f, a in curves:  # the samples in the panel and one beyond each edge
            i0, i1 = np.searchsorted(f, lo, "right") - 1, np.searchsorted(f, hi, "left") + 1
            sl = slice(max(i0, 0), i1)
            ax.semilogy(f[sl], a[sl], color=color, lw=1.0, label=label)
        ax.set_xlim(lo, hi)
    # the titles at y = 1, where matplotlib would put them (no tick labels above the panels):
    # placing them itself measures every y tick label of the panel at each draw (0.1 s a panel)
    ax_full.set_title("full spectrum", y=1.0)
    ax1.set_title(f"zoom at 1x ({x1:.0f} cpm)", y=1.0)
    ax2.set_title(f"zoom at 2x ({2 * x1:.0f} cpm)", y=1.0)
    if fmesh:
        axm.set_title(f"zoom at the mesh frequency ({fmesh:.0f} cpm) ± 6x", y=1.0)
        for j in range(-6, 7):
            axm.axvline(fmesh + j * x1, color="0.85", lw=0.6, zorder=0)
    else:
        axm.set_title("3x to 10x", y=1.0)
    unit = "µm" if channel == "probe" else "rpm"
    for ax, dec in ((ax_full, 6.0), (ax1, 4.0), (ax2, 4.0), (axm, 4.0)):
        ax.set_xlabel("frequency (cpm)")
        ax.set_ylabel(f"amplitude 0-pk ({unit})")
        ax.grid(True, which="both", alpha=0.3)
        _autoscale_y(ax, dec)
    for o in orders:
        for ax in (ax_full,):
            ax.axvline(o * x1, color="0.7", lw=0.6, ls="--", zorder=0)
    legend = fig.legend(
        *ax_full.get_legend_handles_labels(), loc="lower center", ncols=2, fontsize=8
    )
    what = f"probe {name}" if channel == "probe" else f"speed of {name}"
    fig.suptitle(f"{title}: {what}" if title else what, y=0.9956)
    renderer = _measuring_renderer(fig)  # text metrics only below: nothing is drawn
    box = legend.get_window_extent(renderer)
    bottom = (box.y1 + _SPECTRA_BELOW_AXES * fig.dpi / 72.0) / fig.bbox.height
    # y tick labels wider than those the margins were measured with ("10^-4"; "10^-10", or
    # "3x10^-5" on a panel spanning less than a decade) widen the margin left of their column
    ref = _text_width(renderer, _REF_TICK)
    left = _SPECTRA_LEFT + max(0.0, _ytick_width(ax_full, ax2, renderer) - ref) / fig.bbox.width
    gap = _SPECTRA_WGAP + max(0.0, _ytick_width(ax1, axm, renderer) - ref) / fig.bbox.width
    height = (_SPECTRA_TOP - bottom - _SPECTRA_HGAP) / 2
    width = (_SPECTRA_RIGHT - left - gap) / 2
    fig.subplots_adjust(
        left=left,
        right=_SPECTRA_RIGHT,
        top=_SPECTRA_TOP,
        bottom=bottom,
        wspace=gap / width,
        hspace=_SPECTRA_HGAP / height,
    )
    return fig


def _measuring_renderer(fig):
    """An Agg renderer at the figure's size and dpi for measuring text, kept with the figure:
    the canvas's own (``fig.canvas.get_renderer()``, the same metrics) is replaced by the save
    at 110 dpi, and with it the text-metric and mathtext caches matplotlib keys on the
    renderer, so that every figure the report draws again measured and drew its text with new
    renderers (24 figures: 0.1 s each, 20 % of ``study report``; issue 28)."""
    from matplotlib.backends.backend_agg import RendererAgg

    w, h = fig.canvas.get_width_height(physical=True)
    key = (w, h, fig.dpi)
    kept = getattr(fig, "_gearrotor_measure", None)
    if kept is None or kept[0] != key:
        kept = (key, RendererAgg(w, h, fig.dpi))
        fig._gearrotor_measure = kept
    return kept[1]


def _text_width(renderer, text: str) -> float:
    """Width (pixels) of a y tick label ``text`` (mathtext when between $)."""
    from matplotlib import rcParams
    from matplotlib.font_manager import FontProperties

    prop = FontProperties(size=rcParams["ytick.labelsize"])
    return renderer.get_text_width_height_descent(text, prop, ismath="$" in text)[0]


#: the widest y tick label of the panels the spectra layout was measured with
_REF_TICK = "$\\mathdefault{10^{-4}}$"


def _ytick_width(*axes_and_renderer) -> float:
    """Width (pixels) of the widest y tick label the axes will draw that is longer than
    :data:`_REF_TICK` (0 if none), from their locators and formatters (the tick objects are not
    made; a label is measured only when it is longer: mathtext takes milliseconds a label)."""
    *axes, renderer = axes_and_renderer
    widest = 0.0
    for ax in axes:
        lo, hi = sorted(ax.get_ylim())
        for which in (ax.yaxis.major, ax.yaxis.minor):
            locs = [v for v in which.locator() if lo <= v <= hi]
            for text in which.formatter.format_ticks(locs):
                if len(text) > len(_REF_TICK):
                    widest = max(widest, _text_width(renderer, text))
    return widest


def _autoscale_y(ax, decades: float = 4.0) -> None:
    """Fit the y range to the data inside the x limits (log axis, ``decades`` at most)."""
    lo_x, hi_x = ax.get_xlim()
    ys = []
    for line in ax.get_lines():
        x, y = line.get_xdata(), line.get_ydata()
        if len(np.shape(x)) and len(x) > 2:
            sel = (np.asarray(x) >= lo_x) & (np.asarray(x) <= hi_x)
            if sel.any():
                ys.append(np.asarray(y)[sel])
    if ys:
        y = np.concatenate(ys)
        top = float(y.max())
        ax.set_ylim(max(float(y.min()), top * 10.0**-decades) * 0.8, top * 2.0)


def _fmt(value, unit: str | None) -> str:
    text = f"{value:g}" if isinstance(value, float | np.floating) else str(value)
    return f"{text} {unit}" if unit else text


def trend_groups(
    ds: xr.Dataset, parameter: str, parameters: Sequence[str]
) -> list[tuple[str, np.ndarray]]:
    """Cases along which only ``parameter`` varies: groups of case indices with equal values of
    every other parameter and at least two distinct values of ``parameter`` (sorted by it);
    each with a label naming the fixed values."""
    others = [p for p in parameters if p != parameter]
    groups: dict[tuple, list[int]] = {}
    for i in range(ds.sizes["case"]):
        key = tuple(_fmt(ds[p].values[i], ds[p].attrs.get("units")) for p in others)
        groups.setdefault(key, []).append(i)
    out = []
    for key, idx in groups.items():
        vals = ds[parameter].values[idx]
        if len(set(np.asarray(vals).tolist())) < 2:
            continue
        order = np.argsort(vals, kind="stable")
        label = ", ".join(f"{p}={v}" for p, v in zip(others, key, strict=True)) or "all"
        out.append((label, np.asarray(idx)[order]))
    return out


def trend_figure(ds: xr.Dataset, parameter: str, parameters: Sequence[str]):
    """Metrics vs ``parameter`` (one line per group of :func:`trend_groups`); None when no two
    cases differ in ``parameter`` only."""
    groups = trend_groups(ds, parameter, parameters)
    if not groups or not np.issubdtype(ds[parameter].dtype, np.number):
        return None
    plt = _pyplot()
    modal = "damped_frequency" in ds
    if modal:
        panels = [
            ("damped_frequency", "damped natural frequency (rpm)", None, 1.0),
            ("log_dec", "log decrement", None, 1.0),
        ]
    else:
        # a model without meshes (or probes) has a metric of size 0: no panel for it
        panels = [p for p in _AMP_METRICS if p[0] in ds and ds.sizes.get(p[2], 0) > 0]
    if not panels:
        return None
    ncol = 3 if len(panels) > 2 else 2
    nrow = int(np.ceil(len(panels) / ncol))
    fig, axes = plt.subplots(
        nrow, ncol, figsize=(5 * ncol, 3.8 * nrow + 1.2), squeeze=False, constrained_layout=True
    )
    unit = ds[parameter].attrs.get("units", "")
    for ax, (var, ylabel, dim, scale) in zip(axes.ravel(), panels, strict=False):
        for k, (label, idx) in enumerate(groups):
            x = ds[parameter].values[idx]
            da = ds[var].isel(case=idx)
            if dim is None:  # modal: one line per mode
                for m in range(min(da.sizes["mode"], 6)):
                    ax.plot(
                        x,
                        da.isel(mode=m).values * scale,
                        marker="o",
                        color=f"C{m}",
                        ls=["-", "--", ":", "-."][k % 4],
                        ms=4,
                        label=f"mode {m}" if k == 0 else None,
                    )
            else:
                y = da.max(dim=dim).values * scale
                ax.plot(x, y, "o-", color=f"C{k % 10}", ms=4, label=label)
        ax.set_xlabel(f"{parameter} ({unit})" if unit else parameter)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
    for ax in axes.ravel()[len(panels) :]:
        ax.set_visible(False)
    fig.legend(
        *axes.ravel()[0].get_legend_handles_labels(),
        loc="outside lower center",
        ncols=2,
        fontsize=8,
    )
    fig.suptitle(f"{ds.attrs.get('title', 'study')}: trends in {parameter}")
    return fig


def trend_png(ds: xr.Dataset, parameter: str, parameters: Sequence[str]) -> bytes | None:
    """:func:`trend_figure` as the PNG ``study report`` writes (110 dpi), None when there is no
    trend. Kept in the results cache (:mod:`gearrotor.cache`, kind ``study-trend``), keyed by
    the content of ``ds`` (its variables, coordinates and title), the parameters, matplotlib's
    version and settings, and the sources of this module and of ``files.py``: a report of a
    group of cases (``--cases``) draws the same trend figures as the full report before it
    (0.4 s each for the seed study), and finds them there, byte for byte."""
    import matplotlib

    from .. import cache

    def render() -> dict:
        fig = trend_figure(ds, parameter, parameters)
        if fig is None:
            return {"png": np.zeros(0, np.uint8)}
        png = figure_bytes(fig, dpi=110)  # the file save_figure writes
        _pyplot().close(fig)
        return {"png": np.frombuffer(png, np.uint8)}

    rc = hashlib.sha256(repr(sorted(matplotlib.rcParams.items())).encode()).hexdigest()
    parts = ("trend", parameter, list(parameters), _content(ds), matplotlib.__version__, rc)
    png = cache.arrays(
        "study-trend",
        parts,
        render,
        sources=("studies/plots.py", "files.py"),
        max_bytes=TREND_CACHE_BYTES,
    )
    return bytes(png["png"]) if png["png"].size else None


def _content(ds: xr.Dataset) -> str:
    """SHA-256 of what a trend figure reads of ``ds``: every variable and coordinate (name,
    dimensions, dtype, values, attributes) and the title."""
    h = hashlib.sha256(repr(ds.attrs.get("title")).encode())
    for name in sorted(map(str, ds.variables)):
        var = ds.variables[name]
        values = np.ascontiguousarray(var.values)
        if values.dtype.kind == "O":  # text as objects: hash the text, not the pointers
            values = values.astype(str)
        h.update(repr((name, var.dims, values.dtype.str, values.shape)).encode())
        h.update(repr(sorted(var.attrs.items())).encode())
        h.update(values.tobytes())
    return h.hexdigest()


def report(
    study: Study,
    output: str | Path | None = None,
    *,
    cases: Sequence[int] | None = None,
    probes: Sequence[str] | None = None,
    per_figure: int = 7,
    progress=None,
    results=None,
    planned=None,
) -> list[Path]:
    """Write the study's figures as PNG into ``output`` (default ``<study folder>/report``):
    ``trend_<parameter>.png`` for every parameter, and for transient studies
    ``spectra_<probe>_<first>-<last>.png`` and ``spectra_speed_<shaft>_<first>-<last>.png``
    overlaying at most ``per_figure`` finished cases (``cases``: only these; ``probes``: only
    these probes). ``progress``: called with a line of text as each figure is written (the
    command line prints it on stderr). ``results``: the study's collected metrics
    (:func:`~gearrotor.studies.collection.collect`) when the caller has them already, else
    collected here (each case's file read once either way); ``planned``: the study's
    :func:`~gearrotor.studies.cases.plan` when the caller has it (27 models resolved: 0.3 s for
    the seed study). Returns the paths written."""
    plt = _pyplot()

    def note(text: str) -> None:
        if progress is not None:
            progress(text)

    out = Path(output) if output is not None else study.folder / "report"
    check_output(out, "directory", field="--output")  # also removes a killed run's temporaries
    with output_set():  # the figures and figures.json appear together or not at all
        make_directory(out, field="--output")
        written = _report_figures(
            study, out, cases, probes, per_figure, note, plt, results, planned
        )
        write_json(out / "figures.json", [p.name for p in written])
    return written


def _report_figures(
    study, out, cases, probes, per_figure, note, plt, results, planned
) -> list[Path]:
    planned = plan(study) if planned is None else planned
    ds = collect(study, planned=planned, write=False) if results is None else results
    params = list(study.parameters)
    written: list[Path] = []
    for p, stem in zip(params, unique_names(params), strict=True):
        png = trend_png(ds, p, params)
        if png is not None:
            path = out / f"trend_{stem}.png"
            write_bytes(path, png)
            written.append(path)
            note(f"{path.name} written")
    if not isinstance(study.analysis, TransientSettings):
        return written
    status = study_status(study, planned)
    done = [
        s.index for s in status if s.state == "done" and (cases is None or s.index in set(cases))
    ]
    seen_keys: set[str] = set()
    uniq = []
    for i in done:  # identical rows share one result: plot it once
        if planned[i].key not in seen_keys:
            seen_keys.add(planned[i].key)
            uniq.append(i)
    note(f"spectra of {len(uniq)} cases, {per_figure} per figure")
    fig = [None]  # one figure drawn again for each (overlay_spectra)
    try:
        for start in range(0, len(uniq), per_figure):
            chunk = uniq[start : start + per_figure]
            pngs = _spectra_pngs(study, planned, chunk, probes, fig)
            if pngs is None:  # no stored time histories
                break
            for file, png in pngs:
                path = out / file
                write_bytes(path, png)  # the file save_figure writes
                written.append(path)
                note(f"{path.name} written")
    finally:
        if fig[0] is not None:
            plt.close(fig[0])
    return written


#: The most the spectra figures kept in the results cache may take (the seed study's full
#: report: 24 figures, 11 MB); the least recently used are removed first.
SPECTRA_CACHE_BYTES = 256 * 2**20
TREND_CACHE_BYTES = 64 * 2**20


def _spectra_pngs(study, planned, chunk, probes, fig) -> list[tuple[str, bytes]] | None:
    """The spectra PNGs (file name, bytes) of one figure's cases ``chunk`` (indices into
    ``planned``): one per probe (or those of ``probes``) and one per shaft speed; None when the
    cases have no stored time histories. ``fig``: a one-element list holding the figure drawn
    again for each (made on first use).

    Kept in the results cache (kind ``study-spectra``), keyed by the SHA-256 of each case file,
    the cases' labels, ``probes``, the study's name, matplotlib's version and settings, and the
    sources that read and draw the cases: a report of the same results again (another output
    folder, a group of cases that fills a figure as the full report did) finds its figures,
    byte for byte, without reading the case files (0.5 s a figure for the seed study). A case
    file that cannot be hashed is read and drawn without the cache."""
    import matplotlib

    from .. import cache

    labels = [f"{i}: {planned[i].case.label}" for i in chunk]
    keys = [planned[i].key for i in chunk]

    def render() -> dict:
        data = {label: read_case(study, planned[i]) for label, i in zip(labels, chunk, strict=True)}
        first = next(iter(data.values()))
        if first.sizes.get("time", 0) < 16:
            return {"none": np.zeros(0, np.uint8)}
        tag = f"{chunk[0]:02d}-{chunk[-1]:02d}"
        names = [str(p) for p in first["probe"].values]
        if probes is not None:
            unknown = sorted(set(probes) - set(names))
            if unknown:
                raise ModelError(
                    "unknown probe", field="--probes", value=unknown, expected=f"some of {names}"
                )
            names = [p for p in names if p in set(probes)]
        shafts = [str(s) for s in first["shaft"].values]
        figures = [
            ("probe", probe, f"spectra_{stem}_{tag}.png")
            for probe, stem in zip(names, unique_names(names), strict=True)
        ] + [
            ("speed", shaft, f"spectra_speed_{stem}_{tag}.png")
            for shaft, stem in zip(shafts, unique_names(shafts), strict=True)
        ]
        out = {"files": np.frombuffer("\n".join(f for *_, f in figures).encode(), np.uint8)}
        for k, (channel, name, _) in enumerate(figures):
            fig[0] = overlay_spectra(
                data, channel=channel, name=name, title=study.name, figure=fig[0]
            )
            out[f"png{k}"] = np.frombuffer(figure_bytes(fig[0], dpi=110), np.uint8)
        return out

    digests = [file_sha256(case_path(study, key)) for key in keys]
    if None in digests:
        entry = render()
    else:
        rc = hashlib.sha256(repr(sorted(matplotlib.rcParams.items())).encode()).hexdigest()
        parts = (
            "spectra",
            digests,
            labels,
            None if probes is None else sorted(set(probes)),
            study.name,
            matplotlib.__version__,
            rc,
        )
        entry = cache.arrays(
            "study-spectra",
            parts,
            render,
            sources=("studies/plots.py", "studies/collection.py", "signals.py", "files.py"),
            max_bytes=SPECTRA_CACHE_BYTES,
        )
    if "files" not in entry:
        return None
    files = bytes(entry["files"]).decode().split("\n")
    return [(f, bytes(entry[f"png{k}"])) for k, f in enumerate(files)]
