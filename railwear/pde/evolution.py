"""The regularised evolution equation of the wheel radius (paper eq. 4).

    (1 - nu ∂xx) u_T = h(u_xx; u, u_x, v) - epsilon u_xxxx

for the radius deviation ``u(x, T)`` (m) on the periodic angle ``x`` (rad) over the normed life
time ``T``. Pseudo-spectral in ``x``; ETDRK4 in ``T`` with the stabilising split
``h = S u_xx + (h - S u_xx)``, the first part exact, the second explicit (``S`` at least the
largest slope ``∂h/∂u_xx`` met), so that the stiff smoothing of a non-monotone ``h`` does not
limit the step.
"""

import hashlib
import math
import warnings
from dataclasses import dataclass

import numpy as np
import xarray as xr

from railwear.errors import IllPosedError, NumericalInstabilityError, ResolutionWarning, ScenarioError
from railwear.pde import etdrk4
from railwear.pde.forms import BuiltinRate, as_wear_rate
from railwear.pde.linear import dispersion

TAIL_GROWTH = 1e3  # growth of the top of the spectrum, over its start, that counts as ill-posed


def wavenumbers(n_points):
    """Non-negative integer wavenumbers (polygon orders) of a real FFT over ``n_points``."""
    return np.arange(n_points // 2 + 1, dtype=float)


def _check_parameters(u0, t_end, speed, epsilon, nu, n_save):
    u0 = np.asarray(u0, dtype=float)
    if u0.ndim not in (1, 2) or u0.shape[-1] < 8 or u0.shape[-1] % 2:
        raise ScenarioError("u0 must be 1-D or 2-D (batch, angle) with an even number >= 8 of points")
    if not np.all(np.isfinite(u0)):
        raise ScenarioError("u0 has non-finite values")
    for name, value in (("t_end", t_end), ("epsilon", epsilon), ("nu", nu)):
        if not np.isfinite(value) or value < 0:
            raise ScenarioError(f"{name} must be finite and >= 0, got {value}")
    if t_end == 0:
        raise ScenarioError("t_end must be > 0")
    speed = np.asarray(speed, dtype=float)
    if speed.ndim > 1 or not np.all(np.isfinite(speed)) or np.any(speed < 0):
        raise ScenarioError("speed must be a finite value or 1-D array >= 0 (m/s)")
    if int(n_save) < 2:
        raise ScenarioError("n_save must be at least 2")
    return u0, speed


def _batch(u0, speed, rows=1):
    """Broadcast ``u0`` and ``speed`` to ``(batch, n)`` and ``(batch,)``; name the batch dimension."""
    batch_dim = None
    if speed.ndim == 1:
        batch_dim = "speed"
    elif u0.ndim == 2 or rows > 1:
        batch_dim = "member"
    n_rows = max(u0.shape[0] if u0.ndim == 2 else 1, speed.size if speed.ndim == 1 else 1, rows)
    if u0.ndim == 2 and u0.shape[0] != n_rows:
        raise ScenarioError(f"u0 has {u0.shape[0]} rows but the batch has {n_rows}")
    if speed.ndim == 1 and speed.size != n_rows:
        raise ScenarioError(f"speed has {speed.size} values but the batch has {n_rows} rows")
    u = np.broadcast_to(np.atleast_2d(u0), (n_rows, u0.shape[-1]))
    return np.array(u), np.broadcast_to(speed, (n_rows,)).astype(float), batch_dim


def _per_row(name, value, rows, unit):
    value = np.asarray(value, dtype=float)
    if value.ndim > 1 or not np.all(np.isfinite(value)) or value.size not in (1, rows):
        raise ScenarioError(f"{name} must be finite, one value or one per batch row ({rows}), {unit} per unit time")
    return np.broadcast_to(value.ravel(), (rows,)).copy()


def _curvatures(v, k):
    return np.fft.irfft(-(k**2) * v, axis=-1)


def _max_slope(forms, s, u, ux, speeds):
    """Largest ``∂h/∂u_xx`` per row over the present curvatures and a band four times as wide."""
    out = np.empty(len(speeds))
    for b, (form, speed) in enumerate(zip(forms, speeds)):
        reach = 4 * max(float(np.max(np.abs(s[b]))), 1e-12)
        grid = np.linspace(-reach, reach, 201)
        if isinstance(form, BuiltinRate):
            g = form.at_speed(speed)
            slopes = np.concatenate([g.slope(s[b]), g.slope(grid)])
        else:
            slopes = np.concatenate([form.slope(s[b], speed, u[b], ux[b]),
                                     form.slope(grid, speed)])
        out[b] = np.max(slopes)
    return out


def _growth_bound(forms, s, u, ux, speeds, k, epsilon, nu):
    """Largest linear growth rate per row, frozen at the present curvatures, over the kept orders."""
    low = np.empty(len(speeds))
    for b, (form, speed) in enumerate(zip(forms, speeds)):
        if isinstance(form, BuiltinRate):
            low[b] = np.min(form.at_speed(speed).slope(s[b]))
        else:
            low[b] = np.min(form.slope(s[b], speed, u[b], ux[b]))
    return np.max(dispersion(-np.minimum(low, 0.0)[:, None], k[None, :], epsilon, nu), axis=1)


@dataclass(frozen=True)
class EvolutionCheckpoint:
    """Everything needed to continue a solve bit for bit after output interval ``intervals``.

    ``fingerprint`` identifies the problem (initial state, speeds, ``h``, parameters); the rest is
    the loop's state: spectra saved so far with their times, the present spectra, the rows still
    running and the stop times of the others, the steps per interval of each row, the halvings
    spent and the stabilisation ``S`` in force.
    """

    fingerprint: str
    intervals: int
    steps: np.ndarray
    halvings: int
    stabilisation: np.ndarray
    spectra: np.ndarray
    active: np.ndarray
    stop_time: np.ndarray
    saved: np.ndarray
    times: np.ndarray
    tail_peak: np.ndarray


def _fingerprint(u_start, speeds, form, *parameters):
    digest = hashlib.sha256()
    digest.update(np.ascontiguousarray(u_start).tobytes())
    digest.update(np.ascontiguousarray(speeds).tobytes())
    name = getattr(getattr(form, "func", None), "__qualname__", None) or repr(form)
    digest.update(repr((name,) + parameters).encode())
    return digest.hexdigest()


def _richardson_error(v, v_half, n):
    """Per row: ``|u - u_half|_2 / 15`` over the out-of-round part ``|u - mean u|_2`` (floor 1 nm rms)."""
    diff = np.fft.irfft(v - v_half, n, axis=-1)
    dev = np.fft.irfft(np.concatenate([np.zeros_like(v[:, :1]), v[:, 1:]], axis=1), n, axis=-1)
    scale = np.maximum(np.sqrt(np.mean(dev**2, axis=-1)), 1e-9)
    return np.sqrt(np.mean(diff**2, axis=-1)) / 15 / scale


class _Problem:
    """The discretised equation for one set of rows, with the step-dependent weights."""

    def __init__(self, forms, n, speeds, epsilon, nu, dealias, stabilisation, drift, dispersion):
        self.forms, self.n, self.speeds = forms, n, speeds
        self.drift, self.dispersion = drift, dispersion
        self.epsilon, self.nu = epsilon, nu
        self.k = wavenumbers(n)
        kept = n // 3 if dealias else n // 2 - 1
        self.kept = kept
        mask = (self.k <= kept).astype(float)
        self.m_in = np.broadcast_to(-(self.k**2) + 0j, (len(speeds), self.k.size)).copy()
        self.m_out = np.broadcast_to(mask / (1 + nu * self.k**2) + 0j, self.m_in.shape).copy()
        self.fixed_stabilisation = stabilisation
        self.compiled = all(isinstance(f, BuiltinRate) for f in forms)
        if self.compiled:
            self.tables = [f.at_speed(float(v)) for f, v in zip(forms, speeds)]

    def set_stabilisation(self, v, S=None):
        """Choose ``S`` per row from the state ``v`` unless it was given; rebuild the weights' base."""
        if S is not None:
            S = np.asarray(S, float)
        elif self.fixed_stabilisation is not None:
            S = np.full(len(self.speeds), float(self.fixed_stabilisation))
        else:
            s, u, ux = self.fields(v)
            S = np.maximum(_max_slope(self.forms, s, u, ux, self.speeds), 0.0)
        self.S = S
        k2 = self.k**2
        self.L = -(self.epsilon * k2**2 + S[:, None] * k2) / (1 + self.nu * k2)
        if np.any(self.drift) or np.any(self.dispersion):
            odd = self.drift[:, None] * self.k - self.dispersion[:, None] * self.k**3
            self.L = self.L + 1j * odd / (1 + self.nu * k2)
        if self.compiled:
            width = max(max(t.poly.size for t in self.tables), 2)
            poly = np.zeros((len(self.speeds), width))
            for b, t in enumerate(self.tables):
                poly[b, : t.poly.size] = t.poly
            poly[:, 1] -= S
            self.poly = poly
            n_tab = max(t.table_value.size for t in self.tables)
            if n_tab and any(t.table_value.size != n_tab for t in self.tables):
                raise ScenarioError("h tables of one batch must have the same number of points")
            self.tab_lo = np.array([t.table_lo for t in self.tables])
            self.tab_ds = np.array([t.table_ds for t in self.tables])
            self.tab_val = np.array([t.table_value for t in self.tables]).reshape(len(self.tables), n_tab)
            self.tab_der = np.array([t.table_slope for t in self.tables]).reshape(len(self.tables), n_tab)

    def fields(self, v):
        """``u_xx``, ``u``, ``u_x`` on the grid (m/rad², m, m/rad)."""
        return (_curvatures(v, self.k), np.fft.irfft(v, self.n, axis=-1),
                np.fft.irfft(1j * self.k * v, self.n, axis=-1))

    def nonlinear_python(self, v):
        s, u, ux = self.fields(v)
        g = self.forms[0](s, u, ux, self.speeds[:, None]) - self.S[:, None] * s
        return np.fft.rfft(g, axis=-1) * self.m_out

    def growth_bound(self, v):
        s, u, ux = self.fields(v)
        return _growth_bound(self.forms, s, u, ux, self.speeds, self.k[: self.kept + 1],
                             self.epsilon, self.nu)

    def advance(self, v, co, n_steps, t0, active, stop_time, u_ref, depth_limit, blowup):
        """Advance one output interval; ``n_steps`` per row (the Python path takes equal steps)."""
        if self.compiled:
            return etdrk4.advance_compiled(
                v, self.n, co.E, co.E2, co.Q, co.f1, co.f2, co.f3, self.m_in, self.m_out,
                self.poly, self.tab_lo, self.tab_ds, self.tab_val, self.tab_der,
                n_steps, co.dt, t0, active, stop_time, u_ref, depth_limit, blowup)
        return etdrk4.advance_python(v, co, self.nonlinear_python, int(n_steps[0]), t0, active, stop_time,
                                     u_ref, depth_limit, blowup)

    def tail(self, v):
        """Largest amplitude per row in the top quarter of the kept orders, and overall."""
        amp = np.abs(v[:, 1 : self.kept + 1])
        top = amp[:, int(0.75 * self.kept) :]
        return top.max(axis=1), amp.max(axis=1)


def solve_evolution(
    u0, t_end, h, speed=0.0, epsilon=0.0, nu=0.0, *, dt=None, n_save=101, dealias=True,
    stabilisation=None, depth_limit=None, tail_tolerance=1e-3, max_halvings=6, progress=None,
    checkpoint=None, resume=None, resolution_tolerance=3e-5, rtol=1e-4, drift=0.0, dispersion=0.0,
):
    """Solve the evolution equation from ``u0`` (m) over normed time ``[0, t_end]``.

    Parameters
    ----------
    u0 : array (angle,) or (batch, angle)
        Radius deviation on an even number of equally spaced angles ``2π j / n`` (m).
    h : wear-rate form, name, or callable ``h(s, u, ux, speed)`` (see :mod:`railwear.pde.forms`),
        or a list of built-in forms, one per batch row.
    speed : float or 1-D array
        Vehicle speed (m/s); an array makes a batch over speeds, advanced together.
    epsilon, nu : float
        Regularisation ``-epsilon u_xxxx`` (rad⁴ per unit time) and ``+nu u_xxT`` (rad²).
    drift : float or 1-D array
        A term ``+drift u_x`` of ``h`` (rad per unit time; one per batch row or one for all): the
        pattern travels round the wheel at ``-drift`` without changing its growth. Taken exactly in
        the linear part.
    dispersion : float or 1-D array
        A term ``+dispersion u_xxx`` of ``h`` (rad³ per unit time; per row or one for all): order
        ``k`` travels at ``dispersion k²`` more. Taken exactly in the linear part.
    dt : float, optional
        A fixed time step, which turns the step-size control off. By default the first step
        comes from the largest linear growth rate met at the start and ``rtol`` controls it.
    n_save : int
        Number of equally spaced output times.
    dealias : bool
        2/3-rule dealiasing of the wear rate.
    stabilisation : float, optional
        The ``S`` of the split; by default the largest slope ``∂h/∂u_xx`` met.
    depth_limit : float, optional
        Stop a row when its most worn spot has lost this depth (m) since ``u0``.
    tail_tolerance : float
        The top quarter of the kept orders may grow to this fraction of the largest amplitude
        (and beyond 1000 times its start) before the run is declared ill-posed.
    rtol : float or None
        Step-size control (when ``dt`` is not given) for a relative error of about ``rtol`` in
        the out-of-round deviation at the end. Each output interval is also taken with half the steps, and the difference
        over 15 (Richardson, order 4) estimates its error; a row whose estimate passes its share
        ``rtol * interval / t_end`` takes the interval again with twice the steps, one far below
        it (1/32) halves them for the next. Costs half as much again per interval. ``None``
        keeps the first step throughout.
    resolution_tolerance : float
        Where the top quarter of the kept orders reaches this fraction of the largest amplitude
        (and ten times its start) the run warns (:class:`~railwear.errors.ResolutionWarning`)
        that the grid may not resolve it; the largest fraction met is ``spectral_tail``.
    progress : callable, optional
        Called with the fraction of ``t_end`` done after each output interval.
    checkpoint : callable, optional
        Called with an :class:`EvolutionCheckpoint` after each output interval.
    resume : EvolutionCheckpoint, optional
        Continue from a checkpoint of the same problem; the result is bit for bit that of an
        uninterrupted run.

    Returns an ``xarray.Dataset`` with ``u`` over (``time``, [``speed`` | ``member``], ``angle``)
    and the stop time per row. Raises :class:`~railwear.errors.IllPosedError` on growth at the grid
    scale and :class:`~railwear.errors.NumericalInstabilityError` on a blow-up that step halving
    does not cure; both carry the last good state.
    """
    u0, speed = _check_parameters(u0, t_end, speed, epsilon, nu, n_save)
    if depth_limit is not None and not depth_limit > 0:
        raise ScenarioError(f"depth_limit must be > 0 (m), got {depth_limit}")
    form = as_wear_rate(h)
    rows = len(form) if isinstance(form, list) else 1
    u_start, speeds, batch_dim = _batch(u0, speed, rows)
    forms = form if isinstance(form, list) else [form] * len(speeds)
    if len(forms) != len(speeds):
        raise ScenarioError(f"h lists {len(forms)} forms for a batch of {len(speeds)} rows")
    n = u_start.shape[-1]
    drift = _per_row("drift", drift, len(speeds), "rad")
    dispersion = _per_row("dispersion", dispersion, len(speeds), "rad³")
    problem = _Problem(forms, n, speeds, float(epsilon), float(nu), dealias, stabilisation, drift, dispersion)
    v = np.fft.rfft(u_start, axis=-1)
    if epsilon == 0 and nu == 0 and np.any(problem.growth_bound(v) > 0):
        raise IllPosedError(
            "h decreases with u_xx at the start and neither epsilon nor nu regularises it: "
            "the equation is ill-posed", last_good=u_start, last_time=0.0)
    problem.set_stabilisation(v)
    interval = t_end / (n_save - 1)
    if dt is None:
        # Each row its own step: the largest growth rate met sets σ Δt <= 0.25.
        steps = np.ceil(interval * problem.growth_bound(v) / 0.25)
        steps = np.maximum(steps, math.ceil(interval / (t_end / 200) * (1 - 1e-12)))
    elif np.isfinite(dt) and dt > 0:
        steps = np.full(len(speeds), math.ceil(interval / dt * (1 - 1e-12)))
    else:
        raise ScenarioError(f"dt must be > 0, got {dt}")
    steps = np.maximum(steps, 1).astype(np.int64)
    if not problem.compiled:
        steps[:] = steps.max()

    tail_start, amp_start = problem.tail(v)
    tail_ref = np.maximum(tail_start, tail_tolerance * amp_start)
    tail_peak = tail_start / np.maximum(amp_start, 1e-300)
    # A million times the largest out-of-round mode at the start, or than 1 nm of amplitude.
    blowup = 1e6 * max(float(np.max(np.abs(v[:, 1:]))), 0.5e-9 * n)
    depth = float(depth_limit) if depth_limit is not None else 0.0
    fingerprint = _fingerprint(u_start, speeds, form, t_end, epsilon, nu, dt, n_save, dealias,
                               stabilisation, depth_limit, tail_tolerance, max_halvings, rtol,
                               (tuple(drift), tuple(dispersion)) if np.any(drift) or np.any(dispersion) else None)
    if dt is not None:
        rtol = None
    if rtol is not None:
        if not rtol > 0:
            raise ScenarioError(f"rtol must be > 0, got {rtol}")
        steps = steps + steps % 2  # even, so that half the steps is exact
        local_tolerance = rtol * interval / t_end  # errors of the intervals add up to about rtol
    active = np.ones(len(speeds), dtype=bool)
    stop_time = np.full(len(speeds), np.nan)
    saved, times = [v.copy()], [0.0]
    halvings = j = 0
    if resume is not None:
        if resume.fingerprint != fingerprint:
            raise ScenarioError("resume: the checkpoint belongs to another problem")
        j, steps, halvings = resume.intervals, resume.steps.copy(), resume.halvings
        v, active, stop_time = resume.spectra.copy(), resume.active.copy(), resume.stop_time.copy()
        saved, times = list(resume.saved), list(resume.times)
        tail_peak = resume.tail_peak.copy()
        problem.set_stabilisation(v, resume.stabilisation)
    weights = {}

    def weights_for(row_steps):
        key = tuple(int(m) for m in row_steps)
        if key not in weights:
            weights[key] = etdrk4.etdrk4_coefficients(problem.L, interval / row_steps)
        return weights[key]

    while j < n_save - 1:
        t0 = j * interval
        v_start, active_start, stop_start = v.copy(), active.copy(), stop_time.copy()
        status, _ = problem.advance(v, weights_for(steps), steps, t0, active, stop_time, u_start,
                                    depth, blowup)
        if status == etdrk4.OK and rtol is not None:
            half = steps // 2
            v_half, active_half, stop_half = v_start.copy(), active_start.copy(), stop_start.copy()
            status_half, _ = problem.advance(v_half, weights_for(half), half, t0, active_half, stop_half,
                                             u_start, depth, blowup)
            error = _richardson_error(v, v_half, n)
            refine = active_start & ((error > local_tolerance) | (status_half != etdrk4.OK))
            if np.any(refine):
                v, active, stop_time = v_start, active_start, stop_start
                steps = np.where(refine, 2 * steps, steps)
                if not problem.compiled:  # the Python loop takes one step count for all rows
                    steps[:] = steps.max()
                if steps.max() > 2**24:
                    raise NumericalInstabilityError(
                        f"the step-size control cannot meet rtol = {rtol:g} near T = {t0:.4g}",
                        last_good=np.fft.irfft(v, n, axis=-1), last_time=t0)
                continue
            coarsen = (error < local_tolerance / 32) & (steps % 4 == 0)
            if problem.compiled or np.all(coarsen):
                steps = np.where(coarsen, steps // 2, steps)
        if status != etdrk4.OK:
            v, active = v_start, active_start
            stop_time[active] = np.nan
            halvings += 1
            if halvings > max_halvings:
                raise NumericalInstabilityError(
                    f"the solution blew up near T = {t0:.4g} even with the step cut to "
                    f"{interval / steps.max():.3g}", last_good=np.fft.irfft(v, n, axis=-1), last_time=t0)
            steps *= 2
            problem.set_stabilisation(v)
            weights.clear()
            continue
        tail, amp = problem.tail(v)
        bad = (tail > tail_tolerance * amp) & (tail > TAIL_GROWTH * np.maximum(tail_ref, 1e-300))
        tail_peak = np.maximum(tail_peak, tail / np.maximum(amp, 1e-300))
        if np.any(bad):
            raise IllPosedError(
                f"growth at the grid scale near T = {t0 + interval:.4g}: the equation is ill-posed "
                "or under-resolved (raise epsilon or nu, or the number of points)",
                last_good=np.fft.irfft(v_start, n, axis=-1), last_time=t0)
        j += 1
        if not np.any(active):
            saved.append(v.copy())
            times.append(float(np.nanmax(stop_time)))
            break
        saved.append(v.copy())
        times.append(j * interval)
        if checkpoint is not None:
            checkpoint(EvolutionCheckpoint(fingerprint, j, steps.copy(), halvings, problem.S.copy(),
                                           v.copy(), active.copy(), stop_time.copy(),
                                           np.array(saved), np.array(times), tail_peak.copy()))
        if progress is not None:
            progress(j / (n_save - 1))
    if progress is not None:
        progress(1.0)

    u = np.fft.irfft(np.array(saved), n, axis=-1)
    angle = 2 * np.pi * np.arange(n) / n
    stop = np.where(np.isnan(stop_time), times[-1], stop_time)
    start_ratio = tail_start / np.maximum(amp_start, 1e-300)
    coarse = (tail_peak > resolution_tolerance) & (tail_peak > 10 * start_ratio)
    if np.any(coarse):
        warnings.warn(
            f"the top quarter of the kept orders reached {tail_peak.max():.2g} of the largest "
            f"amplitude: {n} points may not resolve this run; compare with {2 * n}",
            ResolutionWarning, stacklevel=2)
    ds = _dataset(u, np.array(times), angle, speeds, batch_dim, stop, problem, forms[0],
                  interval / steps, dealias, depth_limit)
    ds["spectral_tail"] = ((batch_dim,) if batch_dim else (), tail_peak if batch_dim else tail_peak[0],
                           {"units": "1", "long_name": "largest amplitude in the top quarter of the kept orders over the largest amplitude"})
    ds.attrs["resolution_tolerance"] = resolution_tolerance
    return ds


def _dataset(u, times, angle, speeds, batch_dim, stop, problem, form, dt, dealias, depth_limit):
    coords = {
        "time": ("time", times, {"units": "1", "long_name": "normed life time"}),
        "angle": ("angle", angle, {"units": "rad", "long_name": "angle round the wheel"}),
    }
    u_attrs = {"units": "m", "long_name": "radius deviation from the nominal radius"}
    stop_attrs = {"units": "1", "long_name": "normed time at which the run stopped"}
    step_attrs = {"units": "1", "long_name": "time step of the run"}
    if batch_dim is None:
        data = {"u": (("time", "angle"), u[:, 0, :], u_attrs),
                "stop_time": ((), stop[0], stop_attrs), "time_step": ((), dt[0], step_attrs)}
        coords["speed"] = ((), speeds[0], {"units": "m s-1", "long_name": "vehicle speed"})
    else:
        data = {"u": (("time", batch_dim, "angle"), u, u_attrs),
                "stop_time": ((batch_dim,), stop, stop_attrs),
                "time_step": ((batch_dim,), dt, step_attrs)}
        if batch_dim == "speed":
            coords["speed"] = ("speed", speeds, {"units": "m s-1", "long_name": "vehicle speed"})
        else:
            coords["member"] = ("member", np.arange(len(speeds)), {"long_name": "batch member"})
            coords["speed"] = ((), speeds[0], {"units": "m s-1", "long_name": "vehicle speed"})
    attrs = {
        "h_form": form.name, "epsilon": problem.epsilon, "nu": problem.nu, "drift": problem.drift,
        "dispersion": problem.dispersion,
        "time_step": float(np.min(dt)),
        "dealias": int(dealias), "stabilisation": float(np.max(problem.S)),
        "depth_limit": float(depth_limit) if depth_limit is not None else 0.0,
        "method": "pseudo-spectral Fourier, ETDRK4 (Kassam & Trefethen 2005)",
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)
