"""Out-of-round wheels: initial radius deviations and the polygon spectrum of a deviation ``u(x)``.

Angles are equally spaced on ``[0, 2π)``; deviations are in metres. The amplitude of order ``n``
is that of ``A_n cos(n x + φ_n)``; the roughness level is ``20 log10(A_n / sqrt(2) / 1 µm)`` dB,
the rms of the harmonic re 1 µm.
"""

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.signal import find_peaks

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


def random_perturbation(n_points, rms, lowest_order, highest_order, rng):
    """Equal-amplitude harmonics of the given orders with random phases, scaled to ``rms`` (m)."""
    if not 1 <= lowest_order <= highest_order < n_points // 2:
        raise ScenarioError(
            f"initial orders must satisfy 1 <= lowest <= highest < {n_points // 2}")
    orders = np.arange(lowest_order, highest_order + 1)
    phases = rng.uniform(0, 2 * np.pi, orders.size)
    # Equal amplitudes A: the rms of the sum is A sqrt(count / 2).
    return harmonics(n_points, orders, np.full(orders.size, rms * np.sqrt(2 / orders.size)), phases)


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
    peaks, _ = find_peaks(np.concatenate([u, u, u]), prominence=prominence * span)
    return int(np.count_nonzero((peaks >= n) & (peaks < 2 * n)))


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


# Ratio of the final to the initial peak-to-peak deviation that separates the regimes.
REGIME_BOUNDS = ((2.5, "polygonalising"), (1.0, "onset"), (0.5, "stable"), (0.0, "smoothing"))


def regime(peak_to_peak_initial, peak_to_peak_final):
    """The regime of the paper's Figs 9-11 from the growth of the out-of-round deviation.

    ``r = final / initial`` peak-to-peak: ``r >= 2.5`` polygonalising, ``1 <= r < 2.5`` onset
    of instability, ``0.5 <= r < 1`` stable (the mean radius falls, the shape stays),
    ``r < 0.5`` smoothing.
    """
    if peak_to_peak_initial == 0:
        return "stable" if peak_to_peak_final == 0 else "polygonalising"
    r = peak_to_peak_final / peak_to_peak_initial
    return next(name for bound, name in REGIME_BOUNDS if r >= bound)
