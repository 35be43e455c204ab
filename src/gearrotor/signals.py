"""Signal processing of sampled histories: amplitude spectra and their windows, spectral lines,
the dominant frequency, and shaft-order amplitudes.

Plain functions of arrays (NumPy/SciPy only): used by the transient result
(:class:`~gearrotor.analyses.transient.TransientResult`), the studies' metrics and figures, and the
report's transient figures. Frequencies in cpm, amplitudes zero-to-peak in the units of the
signal. (A module of the package root, beside :mod:`gearrotor.units`, rather than of
``analyses/``: it analyses signals, not trains, and its users need not import the transient
solver to compute a spectrum.)
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "DISPLAY_FLOOR",
    "amplitude_at",
    "dominant_frequency",
    "order_amplitudes",
    "padded_spectrum",
    "spectral_lines",
    "spectrum",
    "spectral_window",
]

#: Relative amplitude below which a figure treats a spectrum's content as window leakage and
#: round-off, not signal: a panel that zooms into part of a spectrum (near the mesh frequency)
#: spans at least this fraction of the spectrum's largest amplitude, and says so when nothing in
#: it reaches that level. Measured on the unity gearbox (SPEC 6.1, second half of 1 s, Hann, 4
#: averages), 180,000-230,000 cpm against the largest line: constant mesh stiffness 1.4e-9
#: (gear x) and 1.6e-9 (speed), nothing excites there; time-varying mesh (Ka/Kg = 0.2,
#: docs/examples/unity_gearbox.md) 4.4e-6 (gear x) and 1.7e-3 (speed).
DISPLAY_FLOOR = 1e-6


def spectral_window(name: str, n: int) -> NDArray:
    """Spectral window of n samples: ``"hann"``, ``"flattop"`` (5-term, side lobes below
    -90 dB, amplitude flat to 0.1 % across a bin) or ``"rect"``."""
    if name == "hann":
        return np.hanning(n)
    if name == "flattop":
        k = np.arange(n) / (n - 1) * 2 * np.pi
        return (
            0.21557895
            - 0.41663158 * np.cos(k)
            + 0.277263158 * np.cos(2 * k)
            - 0.083578947 * np.cos(3 * k)
            + 0.006947368 * np.cos(4 * k)
        )
    if name == "rect":
        return np.ones(n)
    raise ValueError(f"unknown window {name!r}; expected 'hann', 'flattop' or 'rect'")


def spectrum(
    x: NDArray,
    dt: float,
    *,
    window: str = "hann",
    segments: int = 1,
    overlap: float = 0.5,
    detrend: str = "linear",
) -> tuple[NDArray, NDArray]:
    """Averaged amplitude spectrum: (frequency in cpm, zero-to-peak amplitude).

    The signal (linear trend or mean removed: ``detrend = "linear"`` or ``"mean"``, so that a
    coasting speed does not swamp the low frequencies) is split into ``segments`` windows
    overlapping by ``overlap``;
    each is windowed (``"hann"``, ``"flattop"`` for amplitude accuracy, or ``"rect"``) and the
    magnitudes are averaged; scaling ``2|X|/Σw`` makes a sinusoid at a bin read its amplitude.
    """
    x = np.asarray(x, float)
    n = len(x)
    if detrend == "linear" and n > 1:
        tt = np.arange(n)
        x = x - np.polyval(np.polyfit(tt, x, 1), tt)
    elif detrend == "mean":
        x = x - x.mean()
    else:
        raise ValueError(f"unknown detrend {detrend!r}; expected 'linear' or 'mean'")
    if segments < 1 or n < 8:
        raise ValueError("spectrum needs at least 8 samples and segments >= 1")
    L = int(n / (1 + (segments - 1) * (1 - overlap)))
    step = max(1, int(L * (1 - overlap)))
    w = spectral_window(window, L)
    acc = np.zeros(L // 2 + 1)
    count = 0
    for s in range(0, n - L + 1, step):
        seg = x[s : s + L]
        acc += np.abs(np.fft.rfft((seg - seg.mean()) * w))
        count += 1
        if count == segments:
            break
    amp = 2 * acc / count / w.sum()
    f = np.fft.rfftfreq(L, dt) * 60.0
    return f, amp


def spectral_lines(
    x: NDArray, dt: float, *, count: int = 4, relative: float = 1e-3
) -> list[tuple[float, float, float, float]]:
    """The strongest lines of a signal: up to ``count`` tuples (frequency cpm, mean zero-to-peak
    amplitude, growth rate 1/s, amplitude at the end), strongest first, of lines at least
    ``relative`` times the strongest one.

    Lines are the peaks of the flat-top spectrum (:func:`spectrum`; peaks within the main-lobe
    half-width of 5 bins of a stronger one and the lowest 5 bins, the removed trend, are
    dropped; the window's side lobes lie below -90 dB, so keep ``relative`` above 1e-4). Each
    frequency is refined between bins by maximising the Hann-windowed Fourier transform (its
    narrow main lobe locates a line to a small fraction of a bin). The mean amplitude is the
    flat-top transform at that frequency over the whole signal. The growth rate σ compares
    the flat-top transforms of the two halves (exact for a line A·e^{σt}: both halves see the
    same window); the end amplitude extrapolates the second half's to the last sample with
    that σ, corrected for the window's weighting of e^{σt}. A line that neither grows nor
    decays has σ ≈ 0 and an end amplitude equal to its mean amplitude.
    """
    from scipy.optimize import minimize_scalar
    from scipy.signal import find_peaks

    x = np.asarray(x, float)
    f, a = spectrum(x, dt, window="flattop")
    lobe = 5
    if len(a) <= 2 * lobe or not np.any(a[lobe:] > 0):
        return []
    seg = a[lobe:]
    peaks, _ = find_peaks(seg, height=relative * seg.max(), distance=lobe)
    peaks = lobe + peaks[np.argsort(seg[peaks])[::-1][:count]]
    n = len(x)
    t = np.arange(n) * dt
    xd = x - np.polyval(np.polyfit(t, x, 1), t)
    hann = spectral_window("hann", n)
    half = n // 2
    th = t[:half] - t[:half].mean()  # time about the centre of a half
    flat, flat_h = spectral_window("flattop", n), spectral_window("flattop", half)
    df = f[1] - f[0]

    def amp(sig: NDArray, w: NDArray, tt: NDArray, fc: float) -> float:
        return float(2 * abs(np.exp(-2j * np.pi * fc / 60 * tt) @ (sig * w)) / w.sum())

    out = []
    for k in peaks:
        res = minimize_scalar(
            lambda fc: -amp(xd, hann, t, fc),
            bounds=(f[k] - df, f[k] + df),
            method="bounded",
            options={"xatol": 1e-4 * df},
        )
        fc = float(res.x)
        a1 = amp(xd[:half], flat_h, t[:half], fc)
        a2 = amp(xd[-half:], flat_h, t[-half:], fc)
        sigma = float(np.log(a2 / a1) / (half * dt)) if a1 > 0 and a2 > 0 else 0.0
        weight = float(flat_h @ np.exp(sigma * th) / flat_h.sum())  # window's mean of e^{σt}
        end = a2 * np.exp(sigma * (t[-1] - t[-half:].mean())) / weight
        out.append((fc, amp(xd, flat, t, fc), sigma, float(end)))
    return out


def amplitude_at(t: NDArray, x: NDArray, omega: float) -> float:
    """Zero-to-peak amplitude of the component at a constant ω (rad/s) by least squares (with
    offset). For shaft orders at a varying speed use :func:`order_amplitudes`."""
    A = np.column_stack([np.cos(omega * t), np.sin(omega * t), np.ones_like(t)])
    c, *_ = np.linalg.lstsq(A, x, rcond=None)
    return float(np.hypot(c[0], c[1]))


def order_amplitudes(
    t: NDArray, x: NDArray, speed: NDArray, orders: tuple[float, ...] = (1.0, 2.0)
) -> NDArray:
    """Zero-to-peak amplitudes (units of x) of shaft orders, tracked in the angle domain.

    The shaft angle θ(t) = ∫|Ω| dt follows the actual (fluctuating, coasting) speed, and all
    orders are fitted together with an offset and a linear drift, so a large 1x neither leaks
    into the 2x estimate (as a separate fit at 2·mean speed would) nor smears with the speed.
    """
    t = np.asarray(t, float)
    w = np.abs(np.asarray(speed, float))
    theta = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))])
    cols = [np.ones_like(t), t - t.mean()]
    for k in orders:
        cols += [np.cos(k * theta), np.sin(k * theta)]
    c, *_ = np.linalg.lstsq(np.column_stack(cols), np.asarray(x, float), rcond=None)
    return np.hypot(c[2::2], c[3::2])


def dominant_frequency(x: NDArray, dt: float) -> float:
    """Frequency (cpm) of the highest spectral peak above DC, refined between bins by a
    parabola through the log amplitudes of the peak bin and its neighbours."""
    if len(x) < 8:
        return float("nan")
    f, a = spectrum(x, dt)
    k = 1 + int(np.argmax(a[1:]))
    if 1 < k < len(a) - 1 and np.all(a[k - 1 : k + 2] > 0):
        al, be, ga = np.log(a[k - 1 : k + 2])
        den = al - 2 * be + ga
        shift = 0.5 * (al - ga) / den if den < 0 else 0.0
        return float(f[k] + shift * (f[1] - f[0]))
    return float(f[k])


def padded_spectrum(x: NDArray, dt: float, *, pad: int = 4) -> tuple[NDArray, NDArray]:
    """Amplitude spectrum (cpm, zero-to-peak) as :func:`spectrum`
    (Hann window, linear trend removed) with ``pad``× zero padding, for drawing: the peaks keep
    their height and the curve is interpolated between the bins."""
    x = np.asarray(x, float)
    n = len(x)
    tt = np.arange(n)
    x = x - np.polyval(np.polyfit(tt, x, 1), tt)
    w = np.hanning(n)
    amp = 2 * np.abs(np.fft.rfft((x - x.mean()) * w, n=pad * n)) / w.sum()
    return np.fft.rfftfreq(pad * n, dt) * 60.0, amp
