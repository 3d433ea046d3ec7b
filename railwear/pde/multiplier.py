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

from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from railwear.errors import ScenarioError
from railwear.pde.equation import EvolutionEquation
from railwear.pde.evolution import to_dataset
from railwear.pde.forms import BuiltinRate, Cubic, Pointwise
from railwear.pde.solver import ETDRK4Solver


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
                     local_output=None, dealias=True, progress=None, checkpoint=None, resume=None, **options):
    """Solve the multiplier law from ``u0`` (m) over normed time ``[0, t_end]``: ``rate`` ``λ_n``,
    ``local`` ``g``, ``local_input`` ``A_n`` and ``local_output`` ``B_n`` as in
    :class:`MultiplierEquation`; ``options`` those of
    :class:`~railwear.pde.solver.ETDRK4Solver`. Returns the Dataset of
    :func:`~railwear.pde.evolution.solve_evolution`."""
    equation = MultiplierEquation.from_multiplier(u0, rate, local, speed, epsilon, nu, local_input=local_input,
                                                  local_output=local_output, dealias=dealias)
    solver = ETDRK4Solver(**options)
    run = solver.solve(equation, t_end, progress=progress, checkpoint=checkpoint, resume=resume)
    return to_dataset(equation, solver, run)
