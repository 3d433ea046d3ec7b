"""FASTSIM: Kalker's algorithm for the simplified theory of rolling contact (Kalker 1982).

The patch ``x²/a² + y²/b² <= 1`` (``x`` along rolling, material entering at ``x = +a(y)``) is cut
into ``ny`` strips; each strip into ``nx`` cells with traction points at the cell centres. Along
a strip the traction grows from zero at the leading edge by the elastic increments

    Δpx = -(ξ/L1 - φ y/L3) Δx,   Δpy = -(η/L2 + φ x/L3) Δx,

and is cut back to the traction bound ``μ pz`` where it exceeds it (slip). Flexibilities from
Kalker's coefficients: ``L1 = 8a/(3 C11 G)``, ``L2 = 8a/(3 C22 G)``, ``L3 = π a sqrt(a/b)/(4 C23 G)``.
Traction bound: elliptic (Hertz) ``3Fz/(2πab) sqrt(1 - x²/a² - y²/b²)`` (default) or Kalker's
original parabolic ``2Fz/(πab) (1 - x²/a² - y²/b²)``.

Frictional power. The slip (per unit rolling distance) accumulated over an increment is
``s Δx = L (p - p_elastic)`` per component, where ``p_elastic`` is the traction the increment would
reach in adhesion and ``Lx = (|ξ| L1 + c|φ| L3) / (|ξ| + c|φ|)``, ``Ly = (|η| L2 + c|φ| L3) /
(|η| + c|φ|)``, ``c = sqrt(ab)``, are the flexibilities weighted by the creepages that load each
component. The dissipated power of the increment is ``-V p_mid · s Δx`` with ``p_mid`` the mean
traction over the increment; a last half-cell increment releases the traction to zero at the
trailing edge. ``power_density`` [W/m²] is this dissipation per cell area; ``power_local`` its
sum; ``power_global = -V (ξ Fx + η Fy + φ Mz)``. Without spin, or with spin alone, the two totals
agree up to the discretisation of the strip ends (the midpoint rule telescopes); with spin and
creepage together they differ (by up to about 6 % in the tested cases), because Kalker's three
flexibilities do not derive from one elastic energy. The wear laws of railwear consume ``power_density``.

Sign convention: Kalker's. Forces act on the body whose creepages are given; at small creepage
``Fx = -G c² C11 ξ``, ``Fy = -G c² C22 η - G c³ C23 φ``, ``Mz = G c³ C23 η - ...``.
"""

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from railwear.contact._checks import as_float_array, non_negative, poisson_ratio, positive
from railwear.contact.kalker import _kalker_scalar, kalker_coefficients
from railwear.errors import ScenarioError

__all__ = ["FastsimResult", "FastsimBatchResult", "fastsim", "fastsim_batch", "flexibilities"]

_BOUNDS = {"elliptic": 0, "parabolic": 1}


def flexibilities(a, b, shear_modulus, poisson):
    """Kalker's FASTSIM flexibilities (L1, L2, L3) [m/Pa] for semi-axes a, b [m] (vectorised).

    The compiled kernels take them from here: Kalker's coefficients are numpy, not compiled."""
    c11, c22, c23, _ = kalker_coefficients(np.asarray(a) / np.asarray(b), poisson)
    L1 = 8.0 * a / (3.0 * c11 * shear_modulus)
    L2 = 8.0 * a / (3.0 * c22 * shear_modulus)
    L3 = np.pi * a * np.sqrt(a / b) / (4.0 * c23 * shear_modulus)
    return L1, L2, L3


def _flexibilities_scalar(a, b, shear_modulus, poisson):
    """:func:`flexibilities` for one contact (floats), the same numbers without numpy's cost on
    one-element arrays."""
    c11, c22, c23, _ = _kalker_scalar(a / b, poisson)
    L1 = 8.0 * a / (3.0 * c11 * shear_modulus)
    L2 = 8.0 * a / (3.0 * c22 * shear_modulus)
    L3 = math.pi * a * math.sqrt(a / b) / (4.0 * c23 * shear_modulus)
    return L1, L2, L3


@njit(cache=True)
def _slip_flexibilities(a, b, xi, eta, phi, L1, L2, L3):
    """Per-component flexibilities that turn a traction cut-back into slip (module docstring)."""
    cphi = np.sqrt(a * b) * abs(phi)
    Lx = L1 if abs(xi) + cphi == 0.0 else (abs(xi) * L1 + cphi * L3) / (abs(xi) + cphi)
    Ly = L2 if abs(eta) + cphi == 0.0 else (abs(eta) * L2 + cphi * L3) / (abs(eta) + cphi)
    return Lx, Ly


_TAIL_STEPS = 8  # sub-steps of the last half cell, where the traction is released to zero


@njit(cache=True, inline="always")
def _march(px, py, step, xm, x, y, rx, eta, phi, L2, L3, a, b, pmax, parabolic, at_edge, Lx, Ly):
    """One FASTSIM increment of length ``step`` ending at x: new traction, slip flag, dissipation/V/dy."""
    if at_edge:
        bound = 0.0
    else:
        r2 = (x / a) ** 2 + (y / b) ** 2
        if parabolic:
            bound = pmax * max(0.0, 1.0 - r2)
        else:
            bound = pmax * np.sqrt(max(0.0, 1.0 - r2))
    return increment(px, py, step, xm, rx, eta, phi, L2, L3, bound, Lx, Ly)


@njit(cache=True, inline="always")
def increment(px, py, step, xm, rx, eta, phi, L2, L3, bound, Lx, Ly):
    """One FASTSIM increment of length ``step`` (midpoint ``xm``) under the traction bound
    ``bound`` [Pa] at its end: new traction, slip flag, dissipation/V/dy (``_march``; shared with
    :mod:`railwear.contact.strip_fastsim`)."""
    hx = px - rx * step
    hy = py - (eta / L2 + phi * xm / L3) * step
    h = np.sqrt(hx * hx + hy * hy)
    slipping = h > bound
    if slipping:
        scale = bound / h if h > 0.0 else 0.0
        nxv = hx * scale
        nyv = hy * scale
    else:
        nxv = hx
        nyv = hy
    # slip over the increment (zero in adhesion), times the mean traction over the increment
    diss = -(0.5 * (px + nxv) * Lx * (nxv - hx) + 0.5 * (py + nyv) * Ly * (nyv - hy))
    return nxv, nyv, slipping, diss


@njit(cache=True)
def _fastsim_kernel(a, b, fz, xi, eta, phi, mu, L1, L2, L3, speed, nx, ny, parabolic, fields,
                    px_out, py_out, pd_out, slip_out):
    """One contact. Returns (Fx, Fy, Mz, power_local, slip_area_fraction).

    When ``fields`` is True the traction (px, py) [Pa], power density [W/m²] and slip flags are
    written to the (nx, ny) arrays.
    """
    dy = 2.0 * b / ny
    if parabolic:
        pmax = mu * 2.0 * fz / (np.pi * a * b)
    else:
        pmax = mu * 1.5 * fz / (np.pi * a * b)
    Lx, Ly = _slip_flexibilities(a, b, xi, eta, phi, L1, L2, L3)
    Fx = 0.0
    Fy = 0.0
    Mz = 0.0
    power = 0.0
    slip_area = 0.0
    total_area = 0.0
    for j in range(ny):
        y = -b + (j + 0.5) * dy
        ay = a * np.sqrt(1.0 - (y / b) ** 2)
        dx = 2.0 * ay / nx
        cell = dx * dy
        total_area += nx * cell
        rx = xi / L1 - phi * y / L3  # elastic traction rate along the strip, x component
        px = 0.0
        py = 0.0
        x_prev = ay
        for i in range(nx):
            x = ay - (i + 0.5) * dx
            px_new, py_new, slipping, diss = _march(px, py, x_prev - x, 0.5 * (x + x_prev), x, y, rx,
                                                    eta, phi, L2, L3, a, b, pmax, parabolic, False, Lx, Ly)
            diss *= speed * dy
            power += diss
            Fx += px_new * cell
            Fy += py_new * cell
            Mz += (x * py_new - y * px_new) * cell
            if slipping:
                slip_area += cell
            if fields:
                px_out[i, j] = px_new
                py_out[i, j] = py_new
                slip_out[i, j] = slipping
                # increment 0 lies in cell 0, increment i in the downstream half of cell i-1 and
                # the upstream half of cell i
                if i == 0:
                    pd_out[0, j] += diss / cell
                else:
                    pd_out[i - 1, j] += 0.5 * diss / cell
                    pd_out[i, j] += 0.5 * diss / cell
            px = px_new
            py = py_new
            x_prev = x
        # downstream half of the last cell: the bound falls to zero at the trailing edge
        sub = 0.5 * dx / _TAIL_STEPS
        tail = 0.0
        for k in range(1, _TAIL_STEPS + 1):
            x = x_prev - sub
            px, py, slipping, diss = _march(px, py, sub, x + 0.5 * sub, x, y, rx, eta, phi, L2, L3,
                                            a, b, pmax, parabolic, k == _TAIL_STEPS, Lx, Ly)
            tail += diss
            x_prev = x
        tail *= speed * dy
        power += tail
        if fields:
            pd_out[nx - 1, j] += tail / cell
    return Fx, Fy, Mz, power, slip_area / total_area


@njit(cache=True)
def _fastsim_single(a, b, fz, xi, eta, phi, mu, L1, L2, L3, speed, nx, ny, parabolic):
    """One contact with fields: grid and kernel in one compiled call."""
    px = np.zeros((nx, ny))
    py = np.zeros((nx, ny))
    pd = np.zeros((nx, ny))
    slip = np.zeros((nx, ny), dtype=np.bool_)
    x = np.empty((nx, ny))
    y = np.empty((nx, ny))
    cell_area = np.empty(ny)
    dy = 2.0 * b / ny
    for j in range(ny):
        yc = -b + (j + 0.5) * dy
        ay = a * np.sqrt(1.0 - (yc / b) ** 2)
        dx = 2.0 * ay / nx
        cell_area[j] = dx * dy
        for i in range(nx):
            x[i, j] = ay - (i + 0.5) * dx
            y[i, j] = yc
    res = _fastsim_kernel(a, b, fz, xi, eta, phi, mu, L1, L2, L3, speed, nx, ny, parabolic, True,
                          px, py, pd, slip)
    return res, px, py, pd, slip, x, y, cell_area


@njit(cache=True)
def _fastsim_batch_kernel(a, b, fz, xi, eta, phi, mu, L1, L2, L3, speed, nx, ny, parabolic, out):
    dummy = np.zeros((1, 1))
    dummy_b = np.zeros((1, 1), dtype=np.bool_)
    for k in range(a.shape[0]):
        if fz[k] <= 0.0:
            out[k, :] = 0.0
            continue
        res = _fastsim_kernel(a[k], b[k], fz[k], xi[k], eta[k], phi[k], mu[k], L1[k], L2[k], L3[k],
                              speed[k], nx, ny, parabolic, False, dummy, dummy, dummy, dummy_b)
        for m in range(5):
            out[k, m] = res[m]


@dataclass(frozen=True)
class FastsimResult:
    """FASTSIM solution of one contact (SI units, Kalker's sign convention).

    Fx, Fy [N], Mz [N m]; px, py: traction field [Pa] (nx, ny), rows from the leading edge;
    x, y: cell-centre coordinates [m] (nx, ny); slip: True in the slip zone (nx, ny);
    power_density [W/m²] (nx, ny); power_local, power_global [W]; cell_area [m²] (ny,) per strip;
    slip_fraction: slip area over the discretised patch area; L1, L2, L3: flexibilities [m/Pa].
    """

    Fx: float
    Fy: float
    Mz: float
    px: np.ndarray
    py: np.ndarray
    x: np.ndarray
    y: np.ndarray
    slip: np.ndarray
    power_density: np.ndarray
    power_local: float
    power_global: float
    cell_area: np.ndarray
    slip_fraction: float
    L1: float
    L2: float
    L3: float

    @property
    def adhesion(self):
        """True in the adhesion zone (nx, ny)."""
        return ~self.slip

    @property
    def power(self):
        """(local, global) total frictional power [W]."""
        return self.power_local, self.power_global


def _check_common(a, b, normal_force, mu, shear_modulus, poisson, nx, ny, bound):
    a = positive(a, "a")
    b = positive(b, "b")
    fz = non_negative(normal_force, "normal_force")
    mu = non_negative(mu, "mu")
    G = positive(shear_modulus, "shear_modulus")
    poisson_ratio(poisson, "poisson")
    if int(nx) != nx or nx < 1:
        raise ScenarioError(f"nx must be a positive integer, got {nx}")
    if int(ny) != ny or ny < 1:
        raise ScenarioError(f"ny must be a positive integer, got {ny}")
    if bound not in _BOUNDS:
        raise ScenarioError(f"bound must be 'elliptic' or 'parabolic', got {bound!r}")
    return a, b, fz, mu, G


def _scalar(value, name, low=None, strict=False):
    """A finite float; ``low`` with ``strict`` gives a > or >= check. One-line ScenarioError."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ScenarioError(f"{name} must be a number") from None
    if not math.isfinite(v):
        raise ScenarioError(f"{name} must be finite")
    if low is not None and (v <= low if strict else v < low):
        raise ScenarioError(f"{name} must be {'>' if strict else '>='} {low:g}, got {v:g}")
    return v


def fastsim(a, b, normal_force, xi, eta, phi, mu, shear_modulus, poisson, nx=40, ny=40,
            bound="elliptic", speed=1.0):
    """FASTSIM for one contact.

    a, b [m] semi-axes (a along rolling); normal_force [N]; creepages xi, eta [-], phi [1/m];
    mu friction coefficient [-]; shear_modulus [Pa]; poisson [-]; nx, ny cells along and across
    rolling; bound "elliptic" (default) or "parabolic"; speed [m/s] scales the powers (with the
    default 1 m/s they are per unit rolling speed). Returns a :class:`FastsimResult`.
    """
    a = _scalar(a, "a", 0.0, strict=True)
    b = _scalar(b, "b", 0.0, strict=True)
    fz = _scalar(normal_force, "normal_force", 0.0)
    mu = _scalar(mu, "mu", 0.0)
    G = _scalar(shear_modulus, "shear_modulus", 0.0, strict=True)
    nu = _scalar(poisson, "poisson", 0.0)
    if nu >= 0.5:
        raise ScenarioError(f"poisson must lie in [0, 0.5), got {nu:g}")
    xi, eta, phi = _scalar(xi, "xi"), _scalar(eta, "eta"), _scalar(phi, "phi")
    speed = _scalar(speed, "speed", 0.0)
    if bound not in _BOUNDS:
        raise ScenarioError(f"bound must be 'elliptic' or 'parabolic', got {bound!r}")
    if int(nx) != nx or nx < 1 or int(ny) != ny or ny < 1:
        raise ScenarioError(f"nx and ny must be positive integers, got {nx}, {ny}")
    L1, L2, L3 = _flexibilities_scalar(a, b, G, nu)
    res, px, py, pd, slip, x, y, cell_area = _fastsim_single(
        a, b, fz, xi, eta, phi, mu, L1, L2, L3, speed, int(nx), int(ny), _BOUNDS[bound] == 1
    )
    Fx, Fy, Mz, p_loc, slip_frac = res
    return FastsimResult(
        Fx=Fx, Fy=Fy, Mz=Mz, px=px, py=py, x=x, y=y, slip=slip, power_density=pd,
        power_local=p_loc, power_global=-speed * (xi * Fx + eta * Fy + phi * Mz),
        cell_area=cell_area, slip_fraction=slip_frac, L1=L1, L2=L2, L3=L3,
    )


@dataclass(frozen=True)
class FastsimBatchResult:
    """FASTSIM totals for many contacts: arrays of Fx, Fy [N], Mz [N m], power_local,
    power_global [W], slip_fraction [-]."""

    Fx: np.ndarray
    Fy: np.ndarray
    Mz: np.ndarray
    power_local: np.ndarray
    power_global: np.ndarray
    slip_fraction: np.ndarray


def fastsim_batch(a, b, normal_force, xi, eta, phi, mu, shear_modulus, poisson, nx=40, ny=40,
                  bound="elliptic", speed=1.0):
    """FASTSIM for many contacts at once (arguments broadcast to one shape; no traction fields).

    Units and meaning as in :func:`fastsim`. A contact with zero normal force gives zeros.
    """
    a, b, fz, mu, G = _check_common(a, b, normal_force, mu, shear_modulus, poisson, nx, ny, bound)
    xi = as_float_array(xi, "xi")
    eta = as_float_array(eta, "eta")
    phi = as_float_array(phi, "phi")
    speed = non_negative(speed, "speed")
    nu = as_float_array(poisson, "poisson")
    arrays = np.broadcast_arrays(a, b, fz, xi, eta, phi, mu, G, nu, speed)
    shape = arrays[0].shape
    a, b, fz, xi, eta, phi, mu, G, nu, speed = (np.ascontiguousarray(v, dtype=float).ravel() for v in arrays)
    out = np.zeros((a.size, 5))
    L1, L2, L3 = (np.ascontiguousarray(L, dtype=float) for L in flexibilities(a, b, G, nu))
    _fastsim_batch_kernel(a, b, fz, xi, eta, phi, mu, L1, L2, L3, speed, int(nx), int(ny),
                          _BOUNDS[bound] == 1, out)
    p_glob = -speed * (xi * out[:, 0] + eta * out[:, 1] + phi * out[:, 2])
    r = lambda v: v.reshape(shape)  # noqa: E731
    return FastsimBatchResult(Fx=r(out[:, 0]), Fy=r(out[:, 1]), Mz=r(out[:, 2]),
                              power_local=r(out[:, 3]), power_global=r(p_glob),
                              slip_fraction=r(out[:, 4]))
