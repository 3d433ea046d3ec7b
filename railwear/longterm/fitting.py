"""Strategy 4's fit: ``h(u_xx, u_x, u_xxx; v)`` from frozen-geometry statistics (paper Fig. 8, eq. 4).

For each speed, the disk wheel runs over a set of frozen geometries (strategy 3's Monte Carlo,
:class:`~railwear.longterm.disk_wheel.DiskWheel`). Every cell gives a pair: the local
curvature ``u_xx`` (m/rad², spectral, as the evolution equation sees it) and the mean rate
``u_T = -r`` (m per unit normed time) with its standard error, and the odd derivatives ``u_x``
(m/rad) and ``u_xxx`` (m/rad³). ``h = p(u_xx) + c u_x + d u_xxx``, ``p`` a polynomial of low
degree, is fitted to all cells by least squares (fitting bin means instead would bias it where
``h`` is curved and the bins are wide). The drift ``c`` (rad per unit normed time) and the
dispersion ``d`` (rad³) carry the phase of the dynamic response: order ``n`` travels round the
wheel at ``-(c - d n²)``, the local form of the Fourier technique's ``Im λ_n / n``. On a periodic
grid the odd derivatives are uncorrelated with ``u_xx``'s harmonics, so they barely disturb ``p``. To check it, the pairs are binned by curvature (bins of
equal count) and the mean of the fit over each bin's cells is compared with the bin's mean rate,
in units of its standard error (the scatter about the fit over the square root of the count):
the reduced χ² (of the rates less the odd terms). The fitted polynomials, sampled on a curvature grid, are emitted as
:class:`railwear.pde.Table` ``(curvature, rate, speed)``.

This is the paper's "randomisation": the wear of the dynamic wheel is not a pointwise function of
``u_xx`` (the dynamics carry memory round the wheel), and the fit keeps only the mean relation.
"""

from dataclasses import dataclass

import numpy as np
import xarray as xr

from railwear.errors import ScenarioError
from railwear.pde import Table


def derivative(u, order):
    """``d^order u / dx^order`` (m/rad^order) of ``u`` (m) on equally spaced angles, spectrally
    (the Nyquist harmonic dropped for odd orders)."""
    u = np.asarray(u, float)
    n = u.shape[-1]
    k = np.fft.rfftfreq(n, 1.0 / n)
    factor = (1j * k) ** order
    if order % 2:
        factor[-1] = 0.0
    return np.fft.irfft(factor * np.fft.rfft(u, axis=-1), n, axis=-1)


def curvature(u):
    """``u_xx`` (m/rad²) of ``u`` (m) on equally spaced angles, spectrally."""
    return derivative(u, 2)


def gather(frozen, speeds, geometries, rng):
    """Frozen-geometry statistics: ``frozen(speed)`` gives the
    :class:`~railwear.longterm.disk_wheel.DiskWheel` at a speed (m/s); ``geometries`` is
    ``(n_geometries, n_angles)`` of ``u`` (m). Returns a Dataset over (speed, geometry, angle) with
    ``curvature``, ``slope`` (``u_x``), ``third_derivative`` (``u_xxx``), ``rate`` (``u_T``, m per unit normed time) and ``standard_error``, and the cost."""
    geometries = np.atleast_2d(np.asarray(geometries, float))
    speeds = np.atleast_1d(np.asarray(speeds, float))
    shape = (speeds.size,) + geometries.shape
    rate, error = np.empty(shape), np.empty(shape)
    revolutions = nfev = 0
    for i, v in enumerate(speeds):
        f = frozen(float(v))
        for g, u in enumerate(geometries):
            mean, se, cost = f.statistics(u, rng)
            rate[i, g], error[i, g] = -mean, se
            revolutions += cost["revolutions"]
            nfev += cost["rhs_evaluations"]
    s = np.broadcast_to(curvature(geometries), shape)
    slope = np.broadcast_to(derivative(geometries, 1), shape)
    third = np.broadcast_to(derivative(geometries, 3), shape)
    dims = ("speed", "geometry", "angle")
    return xr.Dataset(
        {"curvature": (dims, np.array(s), {"units": "m rad-2", "long_name": "curvature u_xx of the frozen geometry"}),
         "slope": (dims, np.array(slope), {"units": "m rad-1", "long_name": "slope u_x of the frozen geometry"}),
         "third_derivative": (dims, np.array(third), {"units": "m rad-3", "long_name": "u_xxx of the frozen geometry"}),
         "rate": (dims, rate, {"units": "m", "long_name": "mean u_T per unit normed time (negative: wear)"}),
         "standard_error": (dims, error, {"units": "m", "long_name": "Monte Carlo standard error of the rate"}),
         "cost_revolutions": ((), revolutions, {"units": "1", "long_name": "wheel revolutions simulated"}),
         "cost_rhs_evaluations": ((), nfev, {"units": "1", "long_name": "right-hand sides evaluated"})},
        coords={"speed": ("speed", speeds, {"units": "m s-1", "long_name": "vehicle speed"})})


@dataclass(frozen=True)
class Fit:
    """The fitted ``h``: the table, the polynomial coefficients per speed (lowest first), the drift
    and the dispersion per speed (coefficients of ``u_x`` and ``u_xxx``, rad and rad³ per unit
    normed time), per bin the mean curvature, mean
    rate (less the odd terms) and its standard error and the mean of the fit over the bin's
    cells, and the reduced χ² per speed."""

    table: Table
    coefficients: np.ndarray
    drift: np.ndarray
    dispersion: np.ndarray
    bin_curvature: np.ndarray
    bin_rate: np.ndarray
    bin_error: np.ndarray
    bin_fit: np.ndarray
    chi2: np.ndarray

    def __call__(self, s, speed_index=0):
        """The fitted polynomial at curvature ``s`` (m/rad²) for the speed of ``speed_index``."""
        return np.polynomial.polynomial.polyval(np.asarray(s, float), self.coefficients[speed_index])


def fit_h(stats, degree=3, bins=24, points=33):
    """Fit ``h(u_xx)`` per speed to :func:`gather`'s statistics (see the module docstring).

    ``degree`` of the polynomial, ``bins`` of equal count, ``points`` in the emitted table over
    the curvature range all speeds share."""
    if int(degree) != degree or degree < 1:
        raise ScenarioError("degree must be a whole number >= 1")
    if int(bins) != bins or bins < degree + 2:
        raise ScenarioError("bins must exceed the degree by at least 2")
    if int(points) != points or points < 4:
        raise ScenarioError("points must be >= 4")
    speeds = stats.speed.values
    drift, dispersion = [], []
    coefficients, centres, means, errors, chi2, bin_fit = [], [], [], [], [], []
    lo, hi = -np.inf, np.inf
    for i in range(speeds.size):
        s = stats.curvature.values[i].ravel()
        r = stats.rate.values[i].ravel()
        odd = np.column_stack([stats.slope.values[i].ravel(), stats.third_derivative.values[i].ravel()])
        design = np.column_stack([np.polynomial.polynomial.polyvander(s, int(degree)), odd])
        scale = np.maximum(np.linalg.norm(design, axis=0), 1e-300)  # columns span many decades
        solution = np.linalg.lstsq(design / scale, r, rcond=None)[0] / scale
        coef = solution[:-2]
        drift.append(solution[-2])
        dispersion.append(solution[-1])
        r = r - odd @ solution[-2:]
        fitted = np.polynomial.polynomial.polyval(s, coef)
        groups = np.array_split(np.argsort(s, kind="stable"), bins)
        c = np.array([s[g].mean() for g in groups])
        m = np.array([r[g].mean() for g in groups])
        # the bin mean's error: the scatter of its cells about the fit (the Monte Carlo error of
        # each cell and the part of the wear the local curvature does not explain)
        e = np.array([(r[g] - fitted[g]).std(ddof=1) / np.sqrt(g.size) for g in groups])
        e = np.maximum(e, 1e-12 * np.max(np.abs(m)))
        f = np.array([fitted[g].mean() for g in groups])
        resid = (f - m) / e
        bin_fit.append(f)
        coefficients.append(coef)
        centres.append(c)
        means.append(m)
        errors.append(e)
        chi2.append(float(np.sum(resid**2) / (bins - degree - 1)))
        lo, hi = max(lo, s.min()), min(hi, s.max())
    grid = np.linspace(lo, hi, int(points))
    rate = np.array([np.polynomial.polynomial.polyval(grid, coef) for coef in coefficients]).T
    if speeds.size == 1:
        table = Table(grid, rate[:, 0])
    else:
        table = Table(grid, rate, speeds)
    return Fit(table, np.array(coefficients), np.array(drift), np.array(dispersion), np.array(centres), np.array(means), np.array(errors),
               np.array(bin_fit), np.array(chi2))
