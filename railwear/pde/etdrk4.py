"""Fourth-order exponential time differencing (ETDRK4) for ``v' = L v + N(v)`` with diagonal ``L``.

Cox & Matthews, J. Comput. Phys. 176 (2002) 430; coefficients by contour integrals after
Kassam & Trefethen, SIAM J. Sci. Comput. 26 (2005) 1214. ``v`` is a batch of real-FFT spectra of
shape ``(batch, n // 2 + 1)``.

The compiled path covers nonlinear terms of the form

    N(v) = m_out * rfft(g(irfft(m_in * v)))

with ``g`` applied point by point: a cubic polynomial plus a tabulated function (cubic Hermite on
a uniform grid), both per batch row. The evolution equation (``g = h(u_xx) - S u_xx``,
``m_in = -k^2``) and the Kuramoto-Sivashinsky equation (``g = u^2 / 2``, ``m_in = 1``,
``m_out = -i k``) are both of this form, so one compiled loop serves them. A nonlinear term given
as a Python callable takes :func:`advance_python` instead.
"""

from dataclasses import dataclass

import numpy as np
import rocket_fft  # noqa: F401  (registers numpy.fft inside numba-compiled code)
from numba import njit

# Segment status codes returned by the compiled loop.
OK = 0
NONFINITE = 1
BLOWUP = 2


@dataclass(frozen=True)
class ETDCoefficients:
    """ETDRK4 weights for a linear part ``L`` (real, shape ``(batch, nk)``) and the step of each row."""

    dt: np.ndarray
    E: np.ndarray
    E2: np.ndarray
    Q: np.ndarray
    f1: np.ndarray
    f2: np.ndarray
    f3: np.ndarray


def etdrk4_coefficients(L, dt, n_contour=64):
    """ETDRK4 weights by the mean over ``n_contour`` points of a unit circle round each ``dt L``.

    ``L`` has shape ``(batch, nk)``; ``dt`` is one step or one per row. The contour mean avoids
    the cancellation of the closed forms near ``dt L = 0`` (Kassam & Trefethen 2005, eq. 2.5 and
    section 3).
    """
    L = np.asarray(L, dtype=float)
    dt = np.broadcast_to(np.asarray(dt, dtype=float).reshape(-1, 1), (L.shape[0], 1))
    r = np.exp(1j * np.pi * (np.arange(1, n_contour + 1) - 0.5) / n_contour)
    LR = (dt * L)[..., None] + r
    eLR = np.exp(LR)

    def mean(z):
        return dt * np.mean(z, axis=-1).real

    return ETDCoefficients(
        dt=dt[:, 0].copy(),
        E=np.exp(dt * L),
        E2=np.exp(dt * L / 2),
        Q=mean((np.exp(LR / 2) - 1) / LR),
        f1=mean((-4 - LR + eLR * (4 - 3 * LR + LR**2)) / LR**3),
        f2=mean((2 + LR + eLR * (LR - 2)) / LR**3),
        f3=mean((-4 - 3 * LR - LR**2 + eLR * (4 - LR)) / LR**3),
    )


@njit(cache=True)
def pointwise(w, poly, tab_lo, tab_ds, tab_val, tab_der):
    """``g(w)`` per batch row: ``sum_j poly[b, j] w^j`` plus a cubic Hermite table.

    The table of row ``b`` holds values and derivatives at ``tab_lo[b] + i * tab_ds[b]``; outside
    it the table continues linearly with its end slope. A table with no points is left out.
    """
    nb, n = w.shape
    out = np.empty_like(w)
    npoly = poly.shape[1]
    ntab = tab_val.shape[1]
    for b in range(nb):
        for i in range(n):
            x = w[b, i]
            acc = 0.0
            for j in range(npoly - 1, -1, -1):
                acc = acc * x + poly[b, j]
            if ntab > 0:
                t = (x - tab_lo[b]) / tab_ds[b]
                if t <= 0.0:
                    acc += tab_val[b, 0] + tab_der[b, 0] * (x - tab_lo[b])
                elif t >= ntab - 1:
                    x_hi = tab_lo[b] + (ntab - 1) * tab_ds[b]
                    acc += tab_val[b, ntab - 1] + tab_der[b, ntab - 1] * (x - x_hi)
                else:
                    j0 = int(t)
                    p = t - j0
                    p2 = p * p
                    p3 = p2 * p
                    acc += (
                        (2 * p3 - 3 * p2 + 1) * tab_val[b, j0]
                        + (p3 - 2 * p2 + p) * tab_ds[b] * tab_der[b, j0]
                        + (-2 * p3 + 3 * p2) * tab_val[b, j0 + 1]
                        + (p3 - p2) * tab_ds[b] * tab_der[b, j0 + 1]
                    )
            out[b, i] = acc
    return out


@njit(cache=True)
def _nonlinear(v, n, m_in, m_out, poly, tab_lo, tab_ds, tab_val, tab_der):
    w = np.fft.irfft(v * m_in, n, axis=-1)
    return np.fft.rfft(pointwise(w, poly, tab_lo, tab_ds, tab_val, tab_der), axis=-1) * m_out


@njit(cache=True)
def _max_depth(u_ref, v, n, b):
    """Largest ``u_ref - u`` over the angle for batch row ``b`` (removed depth, m)."""
    u = np.fft.irfft(v[b], n)
    return np.max(u_ref[b] - u)


@njit(cache=True)
def _accept(v, v_new, n, active, stop_time, t_step, dt, u_ref, depth_limit, blowup):
    # ``t_step`` and ``dt`` hold the time at the start of the step and the step of each row.
    """Copy ``v_new`` into the active rows of ``v``; returns ``(status, all_rows_stopped)``.

    A non-finite value or an amplitude above ``blowup`` leaves ``v`` untouched. With
    ``depth_limit > 0`` a row whose removed depth ``max(u_ref - u)`` reaches the limit is
    interpolated linearly to the crossing within the step, frozen, and its time written to
    ``stop_time``.
    """
    nb = v.shape[0]
    for b in range(nb):
        if active[b]:
            peak = np.max(np.abs(v_new[b]))
            if not np.isfinite(peak):
                return NONFINITE, False
            if peak > blowup:
                return BLOWUP, False
    for b in range(nb):
        if not active[b]:
            continue
        if depth_limit > 0.0:
            d_new = _max_depth(u_ref, v_new, n, b)
            if d_new >= depth_limit:
                d_old = _max_depth(u_ref, v, n, b)
                theta = (depth_limit - d_old) / (d_new - d_old) if d_new > d_old else 1.0
                v[b] = v[b] + theta * (v_new[b] - v[b])
                stop_time[b] = t_step[b] + theta * dt[b]
                active[b] = False
                continue
        v[b] = v_new[b]
    return OK, not np.any(active)


@njit(cache=True)
def _rows(a, idx):
    out = np.empty((idx.size,) + a.shape[1:], dtype=a.dtype)
    for i in range(idx.size):
        out[i] = a[idx[i]]
    return out


@njit(cache=True)
def advance_compiled(
    v, n, E, E2, Q, f1, f2, f3, m_in, m_out, poly, tab_lo, tab_ds, tab_val, tab_der,
    row_steps, dt, t0, active, stop_time, u_ref, depth_limit, blowup,
):
    """Advance the spectra ``v`` in place: row ``b`` by up to ``row_steps[b]`` steps of ``dt[b]``.

    Rows with ``active[b]`` False stay frozen; see :func:`_accept` for the depth stop and the
    guard. Only the rows that still have steps to take are transformed, gathered into one batch
    that is rebuilt when a row finishes, so a batch costs what its rows cost apart. Returns
    ``(status, steps_done)``; on a failed guard ``v`` holds the last good step of each row.
    """
    nb = v.shape[0]
    idx = np.arange(0)
    for step in range(np.max(row_steps)):
        running = np.nonzero(active & (row_steps > step))[0]
        if running.size == 0:
            return OK, step
        if running.size != idx.size or np.any(running != idx):
            idx = running
            cE, cE2, cQ = _rows(E, idx), _rows(E2, idx), _rows(Q, idx)
            cf1, cf2, cf3 = _rows(f1, idx), _rows(f2, idx), _rows(f3, idx)
            cin, cout, cpoly = _rows(m_in, idx), _rows(m_out, idx), _rows(poly, idx)
            clo, cds = _rows(tab_lo, idx), _rows(tab_ds, idx)
            cval, cder, cref = _rows(tab_val, idx), _rows(tab_der, idx), _rows(u_ref, idx)
            cdt = _rows(dt, idx)
        cv = _rows(v, idx) if idx.size != nb else v
        Nv = _nonlinear(cv, n, cin, cout, cpoly, clo, cds, cval, cder)
        a = cE2 * cv + cQ * Nv
        Na = _nonlinear(a, n, cin, cout, cpoly, clo, cds, cval, cder)
        b = cE2 * cv + cQ * Na
        Nb = _nonlinear(b, n, cin, cout, cpoly, clo, cds, cval, cder)
        c = cE2 * a + cQ * (2 * Nb - Nv)
        Nc = _nonlinear(c, n, cin, cout, cpoly, clo, cds, cval, cder)
        v_new = cE * cv + Nv * cf1 + 2 * (Na + Nb) * cf2 + Nc * cf3
        cactive = np.ones(idx.size, dtype=np.bool_)
        cstop = _rows(stop_time, idx)
        status, _ = _accept(cv, v_new, n, cactive, cstop, t0 + step * cdt, cdt, cref,
                            depth_limit, blowup)
        if status != OK:
            return status, step
        for i in range(idx.size):
            if idx.size != nb:
                v[idx[i]] = cv[i]
            if not cactive[i]:
                active[idx[i]] = False
                stop_time[idx[i]] = cstop[i]
    return OK, np.max(row_steps)


def advance_python(v, co, nonlinear, n_steps, t0, active, stop_time, u_ref, depth_limit, blowup):
    """:func:`advance_compiled` for a Python ``nonlinear(v) -> N(v)`` and weights ``co``.

    Used for user-supplied wear-rate callables, which numba cannot compile into the loop. The
    stages repeat those of :func:`advance_compiled`: numba does not cache a loop that takes its
    nonlinear term as a function argument, so the two loops cannot share one source.
    """
    n = u_ref.shape[-1]
    for step in range(n_steps):
        Nv = nonlinear(v)
        a = co.E2 * v + co.Q * Nv
        Na = nonlinear(a)
        b = co.E2 * v + co.Q * Na
        Nb = nonlinear(b)
        c = co.E2 * a + co.Q * (2 * Nb - Nv)
        Nc = nonlinear(c)
        v_new = co.E * v + Nv * co.f1 + 2 * (Na + Nb) * co.f2 + Nc * co.f3
        status, done = _accept(v, v_new, n, active, stop_time, t0 + step * co.dt, co.dt,
                               u_ref, depth_limit, blowup)
        if status != OK:
            return status, step
        if done:
            return OK, step + 1
    return OK, n_steps
