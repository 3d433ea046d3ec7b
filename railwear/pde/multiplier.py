"""A Fourier multiplier plus a local nonlinear remainder: the evolution law that selects an order.

    (1 - nu ∂xx) u_T = Λ u + B g(A u) - epsilon u_xxxx

for the radius deviation ``u(x, T)`` (m) over the angle (rad) and the normed life time ``T``.
``Λ``, ``A`` and ``B`` are Fourier multipliers (diagonal in the polygon order ``n``):

- ``Λ`` multiplies harmonic ``n`` by ``λ_n`` (complex, per unit ``T``): its growth rate and
  phase, e.g. the Fourier technique's ``λ_n`` (``railwear.longterm.fourier``). Unlike a local
  law ``h(u_xx)``, whose linear rate ``-h'(0) n²`` is monotone in ``n``, a multiplier can let one
  band of orders grow and the rest decay. It is taken exactly in ETDRK4's linear part.
- ``A`` maps ``u`` to the local variable ``w = A u``: the curvature ``u_xx`` (``A_n = -n²``, the
  default, paper eq. 4) or another linear functional of ``u`` such as the dynamic normal force
  (N) of a linear wheel-track model.
- ``g(w)`` is point-wise (a :class:`~railwear.pde.forms.BuiltinRate`, m per unit ``T``): the
  nonlinearity of the contact (saturation, contact loss) that the multiplier leaves out. It must
  not hold a part linear in ``w``, or the linear rate is counted twice: :class:`Remainder` takes a
  local law and removes its value and slope at ``w = 0``.
- ``B`` spreads the point-wise rate (e.g. the contact filter of the patch); 1 by default.

In the spectrum ``v = rfft(u)``: ``v_T = L v + N(v)`` with
``L = (λ_n - epsilon n⁴) / (1 + nu n²)`` and ``N(v) = B_n mask rfft(g(irfft(A_n v))) / (1 + nu n²)``,
the form :mod:`railwear.pde.etdrk4` compiles (``m_in = A``, ``m_out = B mask / (1 + nu n²)``).
With ``g`` constant (the mean wear rate) every order evolves as ``e^{λ_n T}`` exactly.
"""

import warnings
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from railwear.errors import ResolutionWarning, ScenarioError, start_past_limit
from railwear.pde.equation import EvolutionEquation
from railwear.pde.evolution import to_dataset
from railwear.pde.forms import BuiltinRate, Cubic, Pointwise
from railwear.pde.solver import ETDRK4Solver, EvolutionRun, _outside_pde, _tail


@dataclass(frozen=True, eq=False)
class Fixed(BuiltinRate):
    """A point-wise ``g(w)`` (m per unit ``T``) that does not depend on the speed."""

    g: Pointwise
    name = "fixed"

    def at_speed(self, speed):
        return self.g


@dataclass(frozen=True, eq=False)
class Remainder(BuiltinRate):
    """The nonlinear part of a local law: ``h(w) - h(0) - h'(0) w + constant`` (m per unit ``T``),
    ``h`` a built-in form at each speed. ``constant`` (m per unit ``T``) is the mean wear rate the
    multiplier's order 0 does not carry."""

    h: BuiltinRate
    constant: float = 0.0
    name = "remainder"

    def at_speed(self, speed):
        p = self.h.at_speed(speed)
        poly = np.zeros(max(p.poly.size, 2))
        poly[: p.poly.size] = p.poly
        poly[0] += self.constant - float(p(np.zeros(1))[0])
        poly[1] -= _slope_at_zero(p)
        return replace(p, poly=poly)


def _slope_at_zero(p):
    """``g'(0)`` of a :class:`Pointwise`, the Hermite table's derivative taken exactly (its
    :meth:`~Pointwise.slope` differences, which loses digits to round-off)."""
    slope = p.poly[1] if p.poly.size > 1 else 0.0
    if not p.table_value.size:
        return float(slope)
    t, top = -p.table_lo / p.table_ds, p.table_value.size - 1
    if t <= 0.0 or t >= top:
        return float(slope + p.table_slope[0 if t <= 0.0 else top])
    j = min(int(t), top - 1)
    x = t - j
    y0, y1 = p.table_value[j], p.table_value[j + 1]
    d0, d1 = p.table_ds * p.table_slope[j], p.table_ds * p.table_slope[j + 1]
    c2, c3 = 3.0 * (y1 - y0) - 2.0 * d0 - d1, 2.0 * (y0 - y1) + d0 + d1
    return float(slope + (d0 + x * (2.0 * c2 + 3.0 * x * c3)) / p.table_ds)


def _rows(name, value, rows, nk, dtype):
    """``value`` broadcast to ``(rows, nk)``: one multiplier for every row or one per row."""
    value = np.asarray(value, dtype=dtype)
    if value.ndim not in (1, 2) or value.shape[-1] != nk or (value.ndim == 2 and value.shape[0] not in (1, rows)):
        raise ScenarioError(f"{name} must have {nk} values per row (orders 0..n/2), one row or {rows}")
    if not np.all(np.isfinite(value)):
        raise ScenarioError(f"{name} must be finite")
    return np.broadcast_to(np.atleast_2d(value), (rows, nk)).copy()


@dataclass(frozen=True, eq=False)
class MultiplierEquation(EvolutionEquation):
    """:class:`~railwear.pde.equation.EvolutionEquation` with the multipliers of the module
    docstring per row, orders ``0..n/2``: ``rate`` ``λ_n`` (complex, per unit ``T``), ``local_input``
    ``A_n`` (units of ``w`` per m; ``None``: the curvature) and ``local_output`` ``B_n`` (``None``: 1).
    ``h`` is the point-wise ``g``. Build it with :meth:`from_multiplier`."""

    rate: np.ndarray = None
    local_input: np.ndarray | None = None
    local_output: np.ndarray | None = None

    @classmethod
    def from_multiplier(cls, u0, rate, local=None, speed=0.0, epsilon=0.0, nu=0.0, *, local_input=None,
                        local_output=None, dealias=True):
        """Check and broadcast like :meth:`EvolutionEquation.from_input`; ``local`` the point-wise
        ``g`` (a built-in form; ``None``: 0)."""
        base = EvolutionEquation.from_input(u0, Cubic() if local is None else local, speed, epsilon, nu,
                                            dealias=dealias)
        rows, nk = len(base.speeds), base.k.size
        inputs = None if local_input is None else _rows("local_input", local_input, rows, nk, complex)
        outputs = None if local_output is None else _rows("local_output", local_output, rows, nk, complex)
        fields = {f: getattr(base, f) for f in ("u0", "speeds", "h", "epsilon", "nu", "drift", "dispersion",
                                               "dealias", "batch")}
        if not base.compiled:
            raise ScenarioError("local must be a built-in form (the multiplier law runs compiled only)")
        return cls(**fields, rate=_rows("rate", rate, rows, nk, complex), local_input=inputs,
                   local_output=outputs)

    @cached_property
    def m_in(self):
        """Spectrum of ``u`` to spectrum of ``w``: ``A_n`` per row."""
        return super().m_in if self.local_input is None else self.local_input.copy()

    @cached_property
    def m_out(self):
        """Spectrum of ``g`` to its part of ``v_T``: ``B_n mask / (1 + nu n²)`` per row."""
        out = super().m_out
        return out if self.local_output is None else out * self.local_output

    def linear(self, S):
        """``L`` of the module docstring, less ``S n² / (1 + nu n²)`` (``S`` 0 unless ``w = u_xx``)."""
        return super().linear(S) + self.rate / (1 + self.nu * self.k**2)

    def fields(self, v):
        """``w``, ``u``, ``u_x`` on the grid from the spectra ``v``."""
        s, u, ux = super().fields(v)
        return (s if self.local_input is None else np.fft.irfft(self.m_in * v, self.n, axis=-1)), u, ux

    def max_slope(self, v):
        """The split's ``S``: the largest ``g'`` where ``w = u_xx``, else 0 (``S w`` would not cancel)."""
        return super().max_slope(v) if self.local_input is None else np.zeros(len(self.speeds))

    def growth_bound(self, v):
        """Largest ``Re L`` over the kept orders plus the largest rate ``g`` adds (for the first step)."""
        kept = slice(0, self.kept + 1)
        bound = np.max(self.linear(np.zeros(len(self.speeds))).real[:, kept], axis=1)
        if self.local_input is None:
            return bound + np.maximum(super().growth_bound(v), 0.0)
        w = self.fields(v)[0]
        slope = np.array([np.max(np.abs(self.pointwise[b].slope(w[b]))) for b in range(len(self.speeds))])
        return bound + slope * np.max(np.abs(self.m_in * self.m_out)[:, kept], axis=1)

    def ill_posed(self, v):
        """The multiplier is bounded on the grid; only ``g`` decreasing in ``u_xx`` without ``epsilon`` or
        ``nu`` is ill-posed."""
        return (self.local_input is None and self.epsilon == 0 and self.nu == 0
                and bool(np.any(EvolutionEquation.growth_bound(self, v) > 0)))

    def fingerprint_bytes(self):
        parts = [self.rate] + [m for m in (self.local_input, self.local_output) if m is not None]
        return b"".join(np.ascontiguousarray(m).tobytes() for m in parts)


def solve_multiplier(u0, t_end, rate, local=None, speed=0.0, epsilon=0.0, nu=0.0, *, local_input=None,
                     local_output=None, dealias=True, peak_to_peak_limit=None, progress=None, checkpoint=None,
                     resume=None, **options):
    """Solve the multiplier law from ``u0`` (m) over normed time ``[0, t_end]``: ``rate`` ``λ_n``,
    ``local`` ``g``, ``local_input`` ``A_n`` and ``local_output`` ``B_n`` as in
    :class:`MultiplierEquation`; ``options`` those of
    :class:`~railwear.pde.solver.ETDRK4Solver`. With ``peak_to_peak_limit`` (m; one row only) the
    run stops where the wheel is first that far out of round (:func:`_stop_at_peak_to_peak`).
    Returns the Dataset of :func:`~railwear.pde.evolution.solve_evolution`."""
    equation = MultiplierEquation.from_multiplier(u0, rate, local, speed, epsilon, nu, local_input=local_input,
                                                  local_output=local_output, dealias=dealias)
    solver = ETDRK4Solver(**options)
    if peak_to_peak_limit is None:
        run = solver.solve(equation, t_end, progress=progress, checkpoint=checkpoint, resume=resume)
    else:
        run = _stop_at_peak_to_peak(equation, solver, t_end, float(peak_to_peak_limit), progress, checkpoint, resume)
    return to_dataset(equation, solver, run)


CROSSING_BRACKET = 1e-9  # the peak-to-peak crossing is bracketed to this fraction of one ETDRK4 step


class _Crossed(Exception):
    """Raised from the solver's checkpoint call: the interval just taken passed the limit."""

    def __init__(self, state):
        super().__init__("peak-to-peak limit passed")
        self.state = state


def _peak_to_peak(v, n):
    return float(np.ptp(np.fft.irfft(v, n, axis=-1)))


def _stop_at_peak_to_peak(equation, solver, t_end, limit, progress, checkpoint, resume):
    """:meth:`ETDRK4Solver.solve` stopped where ``max u - min u`` first reaches ``limit`` (m).

    After each output interval the solver's checkpoint call looks at the peak to peak. The output
    interval in which it passed the limit is taken again from its start with a fixed step of half
    the solver's last (so at least as fine as the step that passed it), saving every step; in the
    first step that reaches the limit the crossing is bracketed by bisection on single ETDRK4 steps
    of a fraction of it, to :data:`CROSSING_BRACKET` of the step. The stop is the end of the
    bracket at or past the limit, as the Fourier technique's bisection takes it: where the
    multiplier law is the Fourier solution (no local part, taken exactly) the two stops agree to
    round-off; otherwise the stop is as accurate as the solution's own ``rtol``.
    """
    if len(equation.speeds) != 1:
        raise ScenarioError("peak_to_peak_limit: the stop at a peak-to-peak limit takes one row")
    n = equation.n
    if np.ptp(equation.u0[0]) >= limit:
        raise start_past_limit("peak_to_peak_limit", np.ptp(equation.u0[0]), limit)

    def watch(state):
        if _peak_to_peak(state.spectra[0], n) >= limit:
            raise _Crossed(state)
        if checkpoint is not None:
            checkpoint(state)

    try:
        run = solver.solve(equation, t_end, progress=progress, checkpoint=watch, resume=resume)
    except _Crossed as crossed:
        state = crossed.state
        times, saved, stabilisation, tail = state.times, state.saved, state.stabilisation, state.tail_peak
        steps = int(state.steps[0])
        finished = False
    else:  # the last interval (the end, or a depth stop inside it) is not checkpointed: look at it here
        if _peak_to_peak(run.saved[-1, 0], n) < limit:
            return run
        times, saved, stabilisation, tail = run.times, run.saved, run.stabilisation, run.spectral_tail
        steps = max(int(round(t_end / (solver.n_save - 1) / run.time_step[0])), 1)
        finished = True
    interval = t_end / (solver.n_save - 1)
    t_stop, v_stop = _locate(equation, solver, float(stabilisation[0]), times[-2], times[-1], saved[-2],
                             saved[-1], 2 * steps * (times[-1] - times[-2]) / interval, limit)
    if not finished:
        _resolution_warning(equation, solver, tail)
        if progress is not None:
            progress(1.0)
    return EvolutionRun(np.append(times[:-1], t_stop), np.concatenate([saved[:-1], v_stop[None, None]]),
                        np.array([t_stop]), np.array([interval / steps]), np.asarray(stabilisation), np.asarray(tail))


def _restart(equation, v):
    """``equation`` from the spectra ``v`` (rows, n // 2 + 1) as its start."""
    return replace(equation, u0=np.ascontiguousarray(np.fft.irfft(v, equation.n, axis=-1)))


def _step_solver(solver, stabilisation, dt, n_save):
    return ETDRK4Solver(dt=dt, n_save=n_save, stabilisation=stabilisation, rtol=None,
                        tail_tolerance=solver.tail_tolerance, max_halvings=solver.max_halvings,
                        resolution_tolerance=solver.resolution_tolerance)


def _locate(equation, solver, stabilisation, t_a, t_b, v_a, v_b, steps, limit):
    """``(T, v)`` where the peak to peak first reaches ``limit`` between ``t_a`` (under it, spectra
    ``v_a``) and ``t_b`` (at or over it, ``v_b``), in ``steps`` (rounded up) fixed ETDRK4 steps."""
    n, span = equation.n, t_b - t_a
    m = max(int(np.ceil(steps - 1e-9)), 1)
    fine = _step_solver(solver, stabilisation, span / m, m + 1).solve(_restart(equation, v_a), span)
    ptp = np.ptp(np.fft.irfft(fine.saved[:, 0], n, axis=-1), axis=-1)
    over = np.flatnonzero(ptp >= limit)
    if over.size == 0:  # the finer steps keep it just under the limit up to t_b: the coarse crossing stands
        return t_b, v_b[0]
    j = int(over[0])
    start, dt = _restart(equation, fine.saved[j - 1]), fine.times[j] - fine.times[j - 1]
    lo, hi, v_hi = 0.0, 1.0, fine.saved[j, 0]
    while hi - lo > CROSSING_BRACKET:
        mid = 0.5 * (lo + hi)
        v_mid = _step_solver(solver, stabilisation, mid * dt, 2).solve(start, mid * dt).saved[-1, 0]
        if _peak_to_peak(v_mid, n) >= limit:
            hi, v_hi = mid, v_mid
        else:
            lo = mid
    return t_a + fine.times[j - 1] + hi * dt, v_hi


def _resolution_warning(equation, solver, tail_peak):
    """The solver's warning when the top of the kept spectrum grew (its end was not reached)."""
    tail_start, amp_start = _tail(equation, np.fft.rfft(equation.u0, axis=-1))
    start_ratio = tail_start / np.maximum(amp_start, 1e-300)
    coarse = (tail_peak > solver.resolution_tolerance) & (tail_peak > 10 * start_ratio)
    if np.any(coarse):
        warnings.warn(
            f"the top quarter of the kept orders reached {np.max(tail_peak):.2g} of the largest "
            f"amplitude: {equation.n} points may not resolve this run; compare with {2 * equation.n}",
            ResolutionWarning, stacklevel=_outside_pde())
