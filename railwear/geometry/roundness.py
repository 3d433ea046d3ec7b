"""Out-of-round wheels: initial radius deviations and the polygon spectrum of a deviation ``u(x)``.

Angles are equally spaced on ``[0, 2π)``; deviations are in metres. The amplitude of order ``n``
is that of ``A_n cos(n x + φ_n)``; the roughness level is ``20 log10(A_n / sqrt(2) / 1 µm)`` dB,
the rms of the harmonic re 1 µm.
"""

import numpy as np

from railwear.errors import ScenarioError

ROUGHNESS_REFERENCE = 1e-6  # m, reference of the roughness level in dB


def grid_angles(n_points):
    """``2π j / n`` for ``j = 0 .. n-1`` (rad)."""
    return 2 * np.pi * np.arange(n_points) / n_points


def harmonics(n_points, orders, amplitudes, phases=None):
    """``sum_n A_n cos(n x + φ_n)`` on the grid (amplitudes in m, phases in rad)."""
    orders = np.atleast_1d(np.asarray(orders))
    amplitudes = np.atleast_1d(np.asarray(amplitudes, float))
    phases = np.zeros(orders.size) if phases is None else np.atleast_1d(np.asarray(phases, float))
    if not orders.size == amplitudes.size == phases.size:
        raise ScenarioError("initial.orders, amplitudes and phases must have the same length")
    if np.any(orders < 1) or np.any(orders >= n_points // 2):
        raise ScenarioError(f"initial.orders must lie in [1, {n_points // 2 - 1}] for {n_points} points")
    x = grid_angles(n_points)
    return np.sum(amplitudes[:, None] * np.cos(orders[:, None] * x + phases[:, None]), axis=0)


def random_perturbation(n_points, rms, lowest_order, highest_order, rng, slope=0.0):
    """Harmonics of the given orders with random phases and amplitudes ``∝ n^-slope`` (``slope``
    0: equal amplitudes; 1: a level falling 6 dB per doubling of the order, as a re-profiled wheel's
    spectrum rises with the wavelength), scaled to ``rms`` (m)."""
    if not 1 <= lowest_order <= highest_order < n_points // 2:
        raise ScenarioError(
            f"initial orders must satisfy 1 <= lowest <= highest < {n_points // 2}")
    orders = np.arange(lowest_order, highest_order + 1)
    phases = rng.uniform(0, 2 * np.pi, orders.size)
    shape = orders.astype(float) ** -slope
    # Amplitudes A_n: the rms of the sum is sqrt(sum A_n² / 2).
    return harmonics(n_points, orders, rms * shape * np.sqrt(2 / np.sum(shape**2)), phases)


def resample_measured(angle, deviation, n_points):
    """Periodic cubic spline of a measured deviation (angles in rad on ``[0, 2π)``) onto the grid."""
    angle = np.asarray(angle, float)
    deviation = np.asarray(deviation, float)
    if angle.size < 4:
        raise ScenarioError("a measured wheel needs at least 4 points")
    order = np.argsort(angle)
    a, d = angle[order], deviation[order]
    closed_a = np.append(a, a[0] + 2 * np.pi)
    closed_d = np.append(d, d[0])
    from scipy.interpolate import CubicSpline  # here: scipy.interpolate costs 0.2-0.5 s to import

    return CubicSpline(closed_a, closed_d, bc_type="periodic")(
        np.mod(grid_angles(n_points) - a[0], 2 * np.pi) + a[0])


def harmonic_amplitudes(u):
    """Amplitude ``A_n`` (m) of each order ``n = 0 .. N/2`` along the last axis (``A_0`` the mean)."""
    u = np.asarray(u, float)
    n = u.shape[-1]
    amp = 2 * np.abs(np.fft.rfft(u, axis=-1)) / n
    amp[..., 0] /= 2
    if n % 2 == 0:
        amp[..., -1] /= 2
    return amp


def count_maxima(u, prominence=0.1):
    """Local maxima round the wheel that stand out by ``prominence`` of the peak-to-peak range."""
    u = np.asarray(u, float)
    span = np.ptp(u)
    if span == 0:
        return 0
    n = u.size
    x = np.concatenate([u, u, u]).tolist()
    floor = prominence * span
    return sum(1 for peak in _local_maxima(x) if n <= peak < 2 * n and _prominence(x, peak) >= floor)


def _local_maxima(x):
    """Indices of the local maxima of the list ``x``, a flat top counted once at its middle
    (rounded down); the ends are never maxima. The rule of ``scipy.signal.find_peaks``, which
    costs 0.5 s to import (scipy.signal) for this alone."""
    peaks, i, last = [], 1, len(x) - 1
    while i < last:
        if x[i - 1] < x[i]:
            ahead = i + 1
            while ahead < last and x[ahead] == x[i]:
                ahead += 1
            if x[ahead] < x[i]:
                peaks.append((i + ahead - 1) // 2)
                i = ahead
        i += 1
    return peaks


def _prominence(x, peak):
    """How far ``x[peak]`` stands above the higher of the lowest points on either side before a
    higher point (or the end) is met: ``scipy.signal.peak_prominences`` with no window."""
    top = x[peak]
    left = right = top
    i = peak
    while i >= 0 and x[i] <= top:
        left = min(left, x[i])
        i -= 1
    i = peak
    while i < len(x) and x[i] <= top:
        right = min(right, x[i])
        i += 1
    return top - max(left, right)


def polygon_spectrum(u, u_initial=None, max_order=None):
    """What a user reads off a wheel: spectrum, dominant order, maxima and removed depth.

    Returns a dict with ``order``, ``amplitude`` (m), ``roughness_level`` (dB re 1 µm),
    ``dominant_order`` (largest amplitude among orders >= 1), ``maxima``, ``peak_to_peak`` (m) and,
    given ``u_initial``, ``max_removed_depth`` and ``mean_removed_depth`` (m).
    """
    u = np.asarray(u, float)
    amp = harmonic_amplitudes(u)
    top = amp.size - 1 if max_order is None else min(max_order, amp.size - 1)
    orders = np.arange(1, top + 1)
    a = amp[1 : top + 1]
    with np.errstate(divide="ignore"):
        level = 20 * np.log10(a / np.sqrt(2) / ROUGHNESS_REFERENCE)
    out = {
        "order": orders,
        "amplitude": a,
        "roughness_level": level,
        "dominant_order": int(orders[np.argmax(a)]),
        "maxima": count_maxima(u),
        "peak_to_peak": float(np.ptp(u)),
    }
    if u_initial is not None:
        removed = np.asarray(u_initial, float) - u
        out["max_removed_depth"] = float(np.max(removed))
        out["mean_removed_depth"] = float(np.mean(removed))
    return out


def log_growth(times, values):
    """Least-squares slope of ``ln values`` against ``times`` along the first axis and its standard
    error (``inf`` with fewer than 3 times; ``nan`` where a value is not positive)."""
    t = np.asarray(times, float)
    v = np.asarray(values, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        y = np.where(v > 0, np.log(np.where(v > 0, v, 1.0)), np.nan)
    tc = t - t.mean()
    sxx = float(np.sum(tc**2))
    if t.size < 2 or sxx == 0:
        nan = np.full(v.shape[1:], np.nan)
        return nan, nan
    slope = np.tensordot(tc, y - y.mean(0), axes=(0, 0)) / sxx
    if t.size < 3:
        return slope, np.full(slope.shape, np.inf)
    residual = y - y.mean(0) - np.multiply.outer(tc, slope)
    return slope, np.sqrt(np.sum(residual**2, axis=0) / (t.size - 2) / sxx)


# What growth() calls present and seeded at the start (the regime itself: railwear.longterm.regime)
PRESENT = 0.1  # an order is present at the start with at least this share of the largest amplitude
SEEDED = 0.01  # ... and seeded with at least this share (not made from nothing by the nonlinearity)


def growth(times, deviation):
    """The growth behind the regime of a run: ``deviation`` (m) over (time, angle) at normed
    ``times``. Returns a dict: ``rms_rate`` and ``rms_rate_error`` (fitted ln-rate of the
    out-of-round rms per unit time and its standard error), ``rms_factor`` (``exp(rate T)`` over
    the run), ``order_rate`` and ``order_rate_error`` per order ``1..N/2-1`` (``nan`` where an
    amplitude vanishes), ``present`` (orders present at the start), ``leading_order`` (the
    present order that grows fastest) with its ``leading_factor``, and the largest harmonic at the
    end's ``dominant_factor`` (``exp(rate T)``) and ``dominant_significant`` (its growth beyond 2
    standard errors, from a start of at least ``SEEDED`` of the largest amplitude)."""
    d = np.asarray(deviation, float)
    t = np.asarray(times, float)
    span = t[-1] - t[0]
    rms = np.sqrt(np.mean((d - d.mean(-1, keepdims=True)) ** 2, axis=-1))
    rate, rate_error = log_growth(t, rms[:, None])
    amp = harmonic_amplitudes(d)[:, 1 : d.shape[-1] // 2]
    order_rate, order_error = log_growth(t, amp)
    start = amp[0] if amp[0].max() > 0 else amp[-1]
    present = start >= PRESENT * start.max() if start.max() > 0 else np.zeros(start.size, bool)
    candidates = np.where(present & np.isfinite(order_rate), order_rate, -np.inf)
    k = int(np.argmax(candidates))
    j = int(np.argmax(amp[-1]))
    return {"rms_rate": float(rate[0]), "rms_rate_error": float(rate_error[0]),
            "rms_factor": float(np.exp(rate[0] * span)), "order_rate": order_rate, "order_rate_error": order_error,
            "present": present, "leading_order": k + 1 if np.isfinite(candidates[k]) else 0,
            "leading_factor": float(np.exp(candidates[k] * span)) if np.isfinite(candidates[k]) else 0.0,
            "leading_significant": bool(np.isfinite(candidates[k]) and candidates[k] > 2 * order_error[k]),
            "dominant_factor": float(np.exp(order_rate[j] * span)) if np.isfinite(order_rate[j]) else 0.0,
            "dominant_significant": bool(np.isfinite(order_rate[j]) and order_rate[j] > 2 * order_error[j]
                                         and start[j] >= SEEDED * start.max())}
