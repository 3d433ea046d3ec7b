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

import math
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
    """ETDRK4 weights for a linear part ``L`` (shape ``(batch, nk)``; complex with a drift) and the step of each row."""

    dt: np.ndarray
    E: np.ndarray
    E2: np.ndarray
    Q: np.ndarray
    f1: np.ndarray
    f2: np.ndarray
    f3: np.ndarray


def etdrk4_coefficients(L, dt, n_contour=32):
    """ETDRK4 weights by the mean over a circle of radius 1 round each ``dt L``.

    ``L`` has shape ``(batch, nk)``; ``dt`` is one step or one per row. A real ``L`` takes
    ``n_contour`` points on the upper half circle (the real part of their mean is the mean over
    the circle), a complex one (a drift term) ``2 n_contour`` on the whole circle. The contour
    mean avoids the cancellation of the closed forms near ``dt L = 0`` (Kassam & Trefethen 2005,
    eq. 2.5 and section 3; they take 16 points).
    """
    L = np.asarray(L)
    real = not np.iscomplexobj(L) or not np.any(L.imag)
    L = L.real.astype(float) if real else L.astype(complex)
    dt = np.broadcast_to(np.asarray(dt, dtype=float).reshape(-1, 1), (L.shape[0], 1))
    points = n_contour if real else 2 * n_contour
    r = np.exp(1j * np.pi * (np.arange(1, points + 1) - 0.5) / n_contour)
    LR = (dt * L)[..., None] + r
    eLR2 = np.exp(LR / 2)
    eLR = eLR2 * eLR2
    LR2 = LR * LR
    inv3 = 1 / (LR2 * LR)

    def mean(z):  # C-ordered (not a view on the real part): the compiled loop's one layout
        m = dt * np.mean(z, axis=-1)
        return np.ascontiguousarray(m.real) if real else m

    return ETDCoefficients(
        dt=dt[:, 0].copy(),
        E=np.exp(dt * L),
        E2=np.exp(dt * L / 2),
        Q=mean((eLR2 - 1) / LR),
        f1=mean((-4 - LR + eLR * (4 - 3 * LR + LR2)) * inv3),
        f2=mean((2 + LR + eLR * (LR - 2)) * inv3),
        f3=mean((-4 - 3 * LR - LR2 + eLR * (4 - LR)) * inv3),
    )


@njit(cache=True)
def hermite_pieces(tab_ds, tab_val, tab_der):
    """The cubic of each table interval in the local coordinate ``p`` in [0, 1), per batch row.

    Row ``b`` holds ``(y0, d0, c2, c3)`` of interval ``j`` at ``[b, j]``, so that the
    table is ``y0 + p (d0 + p (c2 + p c3))`` there, with ``d = ds g'`` and ``c2 = 3 (y1 - y0) -
    2 d0 - d1``, ``c3 = 2 (y0 - y1) + d0 + d1`` (the cubic Hermite basis in Horner form). The
    sums are those :func:`pointwise` formed per point before, so the values are the same to the
    bit. A table of one point gets one zero piece (never used).
    """
    nb, ntab = tab_val.shape
    out = np.zeros((nb, max(ntab - 1, 1), 4))
    for b in range(nb):
        ds = tab_ds[b]
        for j in range(ntab - 1):
            y0, y1 = tab_val[b, j], tab_val[b, j + 1]
            d0, d1 = ds * tab_der[b, j], ds * tab_der[b, j + 1]
            out[b, j, 0] = y0
            out[b, j, 1] = d0
            out[b, j, 2] = 3.0 * (y1 - y0) - 2.0 * d0 - d1
            out[b, j, 3] = 2.0 * (y0 - y1) + d0 + d1
    return out


@njit(cache=True)
def pointwise(w, poly, tab_lo, tab_ds, tab_val, tab_der):
    """``g(w)`` per batch row: ``sum_j poly[b, j] w^j`` plus a cubic Hermite table.

    The table of row ``b`` holds values and derivatives at ``tab_lo[b] + i * tab_ds[b]``; outside
    it the table continues linearly with its end slope. A table with no points is left out.
    """
    return pointwise_pieces(w, poly, tab_lo, tab_ds, tab_val, tab_der,
                            hermite_pieces(tab_ds, tab_val, tab_der))


@njit(cache=True)
def pointwise_pieces(w, poly, tab_lo, tab_ds, tab_val, tab_der, pieces):
    """:func:`pointwise` with the table's cubics ``pieces`` from :func:`hermite_pieces`.

    Each row goes in passes over its points: the polynomial, then the interval index ``j`` and
    ``p`` (``t = (w - lo) / ds``, ``j = floor(t)``, ``p = t - j``), then the cubics, then the
    linear continuation outside the table. Only the cubics' loads are scalar: the other passes
    have no branch and no indirect load, and the compiler vectorises them.
    """
    nb, n = w.shape
    out = np.empty_like(w)
    npoly = poly.shape[1]
    ntab = tab_val.shape[1]
    top = ntab - 1
    last = float(max(top - 1, 0))  # the last interval's index
    at = np.empty(n, np.uint64)  # unsigned: indexing without the check for a negative index
    cubic = np.empty(n)
    for b in range(nb):
        row, res = w[b], out[b]
        for i in range(n):
            res[i] = 0.0
        for j in range(npoly - 1, -1, -1):
            c = poly[b, j]
            for i in range(n):
                res[i] = res[i] * row[i] + c
        if ntab == 0:
            continue
        lo, ds = tab_lo[b], tab_ds[b]
        inv_ds = 1.0 / ds
        piece = pieces[b]
        for i in range(n):
            t = (row[i] - lo) * inv_ds
            tc = t if t > 0.0 else 0.0  # clamped to a valid interval (a NaN to the first)
            j0 = int(tc if tc < last else last)
            at[i] = j0
            cubic[i] = t - j0  # p, used only inside the table
        for i in range(n):
            k, p = at[i], cubic[i]
            cubic[i] = piece[k, 0] + p * (piece[k, 1] + p * (piece[k, 2] + p * piece[k, 3]))
        y_lo, g_lo = tab_val[b, 0], tab_der[b, 0]
        y_hi, g_hi = tab_val[b, top], tab_der[b, top]
        x_hi = lo + top * ds
        for i in range(n):
            x = row[i]
            t = (x - lo) * inv_ds
            below = y_lo + g_lo * (x - lo)
            above = y_hi + g_hi * (x - x_hi)  # also where x is not a number (then neither is this)
            res[i] += cubic[i] if (t > 0.0) & (t < top) else (below if t <= 0.0 else above)
    return out


@njit(cache=True)
def _transform(w_in, n, poly, tab_lo, tab_ds, tab_val, tab_der, pieces):
    """``rfft(g(irfft(w_in)))``: the nonlinear term before its output multiplier ``m_out``."""
    w = np.fft.irfft(w_in, n, axis=-1)
    return np.fft.rfft(pointwise_pieces(w, poly, tab_lo, tab_ds, tab_val, tab_der, pieces), axis=-1)


@njit(cache=True)
def _times(v, m):
    """``v m`` element by element."""
    out = np.empty_like(v)
    nb, nk = v.shape
    for b in range(nb):
        for i in range(nk):
            out[b, i] = v[b, i] * m[b, i]
    return out


@njit(cache=True)
def _max_depth(u_ref, v, n, b):
    """Largest ``u_ref - u`` over the angle for batch row ``b`` (removed depth, m)."""
    u = np.fft.irfft(v[b], n)
    return _row_depth(u_ref, u, b)


@njit(cache=True)
def _row_depth(u_ref, u, b):
    """Largest ``u_ref[b] - u`` over the angle, ``u`` the row on the grid."""
    d = u_ref[b, 0] - u[0]
    for i in range(1, u.size):
        d = max(d, u_ref[b, i] - u[i])
    return d


@njit(cache=True)
def _row_status(row, blowup):
    """``NONFINITE`` if ``row`` holds a value that is not finite, else ``BLOWUP`` if the largest
    modulus of its non-constant modes exceeds ``blowup``, else ``OK``. (The mean, mode 0, moves
    with the uniform wear and is no sign of instability.)

    A first pass, which the compiler vectorises, finds a part that is not finite (``x - x`` is
    not 0) or could exceed ``blowup``; the modulus (a ``hypot``) is computed only for the latter.
    """
    near = blowup / math.sqrt(2.0)
    nonfinite, candidate = False, False
    for i in range(row.size):
        re, im = row[i].real, row[i].imag
        nonfinite |= (re - re != 0.0) | (im - im != 0.0)
        candidate |= (i > 0) & ((abs(re) > near) | (abs(im) > near))
    if nonfinite:
        return NONFINITE
    if not candidate:
        return OK
    large = False
    for i in range(1, row.size):
        re, im = row[i].real, row[i].imag
        if max(abs(re), abs(im)) > near and math.hypot(re, im) > blowup:
            large = True
    return BLOWUP if large else OK


@njit(cache=True, fastmath=True)  # a bound: the sum may be taken in any order
def _change_bound(v, v_new, b, n):
    """An upper bound of ``max |irfft(v_new[b]) - irfft(v[b])|`` over the grid (m):
    ``(|dv_0| + 2 sum |dv_k| + |dv_(n/2)|) / n`` with ``|z| <= |Re z| + |Im z|``."""
    nk = v.shape[1]
    total = 0.0
    for i in range(nk):
        d = v_new[b, i] - v[b, i]
        total += abs(d.real) + abs(d.imag)
    total = 2.0 * total
    d0 = v_new[b, 0] - v[b, 0]
    total -= abs(d0.real) + abs(d0.imag)
    if n % 2 == 0:
        d1 = v_new[b, nk - 1] - v[b, nk - 1]
        total -= abs(d1.real) + abs(d1.imag)
    return total / n


# A depth bound below this fraction of the limit skips the exact depth: the rounding of the
# exact depth (an inverse FFT of m-sized values) is many orders below the margin.
_DEPTH_MARGIN = 1.0 - 1e-6


@njit(cache=True)
def _accept(v, v_new, n, active, stop_time, t_step, dt, u_ref, depth_limit, blowup, depth_bound):
    # ``t_step`` and ``dt`` hold the time at the start of the step and the step of each row.
    """Copy ``v_new`` into the active rows of ``v``; returns ``(status, all_rows_stopped)``.

    A non-finite value or an amplitude above ``blowup`` leaves ``v`` untouched. With
    ``depth_limit > 0`` a row whose removed depth ``max(u_ref - u)`` reaches the limit is
    interpolated linearly to the crossing within the step, frozen, and its time written to
    ``stop_time``. ``depth_bound`` holds per row an upper bound of the depth of ``v`` (``inf``
    where none is known) and is updated: the exact depth (an inverse FFT) is taken only for rows
    whose bound plus :func:`_change_bound` could reach the limit, so the rows that stop, and
    where, are those of the exact depth at every step.
    """
    nb = v.shape[0]
    for b in range(nb):
        if active[b]:
            status = _row_status(v_new[b], blowup)
            if status != OK:
                return status, False
    exact = np.zeros(nb, dtype=np.bool_)
    if depth_limit > 0.0:
        for b in range(nb):
            if active[b]:
                depth_bound[b] += _change_bound(v, v_new, b, n)
                exact[b] = not depth_bound[b] < _DEPTH_MARGIN * depth_limit
    # The grid values of the rows that need them at once: one batched transform.
    u_new = np.fft.irfft(v_new, n, axis=-1) if np.any(exact) else np.empty((0, n))
    for b in range(nb):
        if not active[b]:
            continue
        if exact[b]:
            d_new = _row_depth(u_ref, u_new[b], b)
            depth_bound[b] = d_new / _DEPTH_MARGIN if d_new > 0.0 else d_new * _DEPTH_MARGIN
            if d_new >= depth_limit:
                d_old = _max_depth(u_ref, v, n, b)
                theta = (depth_limit - d_old) / (d_new - d_old) if d_new > d_old else 1.0
                for i in range(v.shape[1]):  # element by element: a row assignment costs seconds of compile
                    v[b, i] = v[b, i] + theta * (v_new[b, i] - v[b, i])
                stop_time[b] = t_step[b] + theta * dt[b]
                active[b] = False
                continue
        for i in range(v.shape[1]):
            v[b, i] = v_new[b, i]
    return OK, not np.any(active)


@njit(cache=True)
def _stage(E2, v, Q, R, m_out, m_in):
    """``N = R m_out`` and the stage ``s = E2 v + Q N`` in one pass: ``(N, s, s m_in)``."""
    N, out, out_in = np.empty_like(v), np.empty_like(v), np.empty_like(v)
    nb, nk = v.shape
    for b in range(nb):
        for i in range(nk):
            N[b, i] = R[b, i] * m_out[b, i]
            out[b, i] = E2[b, i] * v[b, i] + Q[b, i] * N[b, i]
            out_in[b, i] = out[b, i] * m_in[b, i]
    return N, out, out_in


@njit(cache=True)
def _stage_c(E2, a, Q, R, m_out, Nv, m_in):
    """``Nb = R m_out`` and the stage ``c = E2 a + Q (2 Nb - Nv)`` in one pass: ``(Nb, c, c m_in)``."""
    Nb, out, out_in = np.empty_like(a), np.empty_like(a), np.empty_like(a)
    nb, nk = a.shape
    for b in range(nb):
        for i in range(nk):
            Nb[b, i] = R[b, i] * m_out[b, i]
            out[b, i] = E2[b, i] * a[b, i] + Q[b, i] * (2 * Nb[b, i] - Nv[b, i])
            out_in[b, i] = out[b, i] * m_in[b, i]
    return Nb, out, out_in


@njit(cache=True)
def _combine(v, E, f1, f2, f3, Nv, Na, Nb, Rc, m_out, out):
    """The ETDRK4 update ``E v + f1 Nv + 2 f2 (Na + Nb) + f3 Nc`` with ``Nc = Rc m_out`` into
    ``out``, in one pass."""
    nb, nk = v.shape
    for b in range(nb):
        for i in range(nk):
            Nc = Rc[b, i] * m_out[b, i]
            out[b, i] = (E[b, i] * v[b, i] + Nv[b, i] * f1[b, i]
                         + 2 * (Na[b, i] + Nb[b, i]) * f2[b, i] + Nc * f3[b, i])


@njit(cache=True)
def _step(v, E, E2, Q, f1, f2, f3, m_in, m_out, n, poly, tab_lo, tab_ds, tab_val, tab_der, pieces, out):
    """One ETDRK4 step of the rows ``v`` into ``out``. Each stage's pass also forms its ``N``
    (the transform times ``m_out``) and the next input (times ``m_in``), so the transforms are
    the only other passes over the rows."""
    terms = (n, poly, tab_lo, tab_ds, tab_val, tab_der, pieces)
    Nv, a, a_in = _stage(E2, v, Q, _transform(_times(v, m_in), *terms), m_out, m_in)
    Na, b, b_in = _stage(E2, v, Q, _transform(a_in, *terms), m_out, m_in)
    Nb, c, c_in = _stage_c(E2, a, Q, _transform(b_in, *terms), m_out, Nv, m_in)
    _combine(v, E, f1, f2, f3, Nv, Na, Nb, _transform(c_in, *terms), m_out, out)


# Rows stepped together: the step's arrays of a block and its h tables' cubics stay in the
# core's cache through the four stages, where those of a whole batch of 64 do not.
_BLOCK_ROWS = 8


@njit(cache=True)
def _rows(a, idx):
    """The rows ``idx`` of ``a``, a new C-ordered array (numba's gather compiles in a fraction of a
    row-by-row copy's time)."""
    return a[idx]


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
    if not (E.shape == v.shape and E2.shape == v.shape and Q.shape == v.shape
            and f1.shape == v.shape and f2.shape == v.shape and f3.shape == v.shape):
        raise ValueError("the ETDRK4 weights must have the shape of v")
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
            cpieces = hermite_pieces(cds, cval, cder)
            cdt = _rows(dt, idx)
            bound = np.full(idx.size, np.inf)
        cv = _rows(v, idx) if idx.size != nb else v
        v_new = np.empty_like(cv)
        for r0 in range(0, idx.size, _BLOCK_ROWS):
            r = slice(r0, min(r0 + _BLOCK_ROWS, idx.size))
            _step(cv[r], cE[r], cE2[r], cQ[r], cf1[r], cf2[r], cf3[r], cin[r], cout[r], n, cpoly[r],
                  clo[r], cds[r], cval[r], cder[r], cpieces[r], v_new[r])
        cactive = np.ones(idx.size, dtype=np.bool_)
        cstop = _rows(stop_time, idx)
        status, _ = _accept(cv, v_new, n, cactive, cstop, t0 + step * cdt, cdt, cref,
                            depth_limit, blowup, bound)
        if status != OK:
            return status, step
        for i in range(idx.size):
            if idx.size != nb:
                for j in range(v.shape[1]):
                    v[idx[i], j] = cv[i, j]
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
    bound = np.full(v.shape[0], np.inf)
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
                               u_ref, depth_limit, blowup, bound)
        if status != OK:
            return status, step
        if done:
            return OK, step + 1
    return OK, n_steps
