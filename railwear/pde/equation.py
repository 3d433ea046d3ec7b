"""The regularised evolution equation of the wheel radius (paper eq. 4), discretised in Fourier space.

    (1 - nu ∂xx) u_T = h(u_xx; u, u_x, v) + drift u_x + dispersion u_xxx - epsilon u_xxxx

for the radius deviation ``u(x, T)`` (m) on the periodic angle ``x`` (rad) over the normed life
time ``T``, one row per batch member. With the stabilising split ``h = S u_xx + (h - S u_xx)``
(``S`` in rad² per unit ``T``, chosen by the solver) the spectrum ``v = rfft(u)`` obeys
``v_T = L v + N(v)`` with the diagonal linear part

    L = (-(epsilon k⁴ + S k²) + i (drift k - dispersion k³)) / (1 + nu k²)

and the nonlinear part ``N(v) = mask rfft(h - S u_xx) / (1 + nu k²)`` (``mask`` the kept orders).
"""

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from railwear.errors import ScenarioError
from railwear.pde.forms import BuiltinRate, as_wear_rate
from railwear.pde.linear import dispersion as growth_rate


def wavenumbers(n_points):
    """Non-negative integer wavenumbers (polygon orders) of a real FFT over ``n_points``."""
    return np.arange(n_points // 2 + 1, dtype=float)


def _check_input(u0, speed, epsilon, nu):
    u0 = np.asarray(u0, dtype=float)
    if u0.ndim not in (1, 2) or u0.shape[-1] < 8 or u0.shape[-1] % 2:
        raise ScenarioError("u0 must be 1-D or 2-D (batch, angle) with an even number >= 8 of points")
    if not np.all(np.isfinite(u0)):
        raise ScenarioError("u0 has non-finite values")
    for name, value in (("epsilon", epsilon), ("nu", nu)):
        if not np.isfinite(value) or value < 0:
            raise ScenarioError(f"{name} must be finite and >= 0, got {value}")
    speed = np.asarray(speed, dtype=float)
    if speed.ndim > 1 or not np.all(np.isfinite(speed)) or np.any(speed < 0):
        raise ScenarioError("speed must be a finite value or 1-D array >= 0 (m/s)")
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


@dataclass(frozen=True, eq=False)
class EvolutionEquation:
    """The problem: initial rows ``u0`` (batch, n) in m, ``speeds`` (batch,) in m/s, the form ``h``
    (one, or a list of built-in forms with one per row), ``epsilon`` (rad⁴ per unit ``T``), ``nu``
    (rad²), ``drift`` (rad) and ``dispersion`` (rad³ per unit ``T``) per row, 2/3-rule ``dealias``
    of ``h``, and ``batch``, the name of the rows' dimension in results (``None`` for one row).

    Build it from user input with :meth:`from_input`.
    """

    u0: np.ndarray
    speeds: np.ndarray
    h: object
    epsilon: float
    nu: float
    drift: np.ndarray
    dispersion: np.ndarray
    dealias: bool = True
    batch: str | None = None

    @classmethod
    def from_input(cls, u0, h, speed=0.0, epsilon=0.0, nu=0.0, *, drift=0.0, dispersion=0.0, dealias=True):
        """Check and broadcast: ``u0`` (angle,) or (batch, angle), ``speed`` a value or one per row;
        ``h`` as :func:`~railwear.pde.forms.as_wear_rate` takes it; drift and dispersion one value
        or one per row."""
        u0, speed = _check_input(u0, speed, epsilon, nu)
        form = as_wear_rate(h)
        u_start, speeds, batch = _batch(u0, speed, len(form) if isinstance(form, list) else 1)
        if isinstance(form, list) and len(form) != len(speeds):
            raise ScenarioError(f"h lists {len(form)} forms for a batch of {len(speeds)} rows")
        rows = len(speeds)
        return cls(u_start, speeds, form, epsilon, nu, _per_row("drift", drift, rows, "rad"),
                   _per_row("dispersion", dispersion, rows, "rad³"), dealias, batch)

    @property
    def n(self):
        """Number of points round the wheel."""
        return self.u0.shape[-1]

    @cached_property
    def forms(self):
        """The form of each row."""
        return self.h if isinstance(self.h, list) else [self.h] * len(self.speeds)

    @cached_property
    def compiled(self):
        """Whether every row is a built-in form, which the compiled loop evaluates."""
        return all(isinstance(f, BuiltinRate) for f in self.forms)

    @cached_property
    def k(self):
        return wavenumbers(self.n)

    @property
    def kept(self):
        """Highest order kept in ``h`` (2/3 rule with ``dealias``)."""
        return self.n // 3 if self.dealias else self.n // 2 - 1

    @cached_property
    def m_in(self):
        """Spectrum of ``u`` to spectrum of ``u_xx``: ``-k²`` per row."""
        return np.broadcast_to(-(self.k**2) + 0j, (len(self.speeds), self.k.size)).copy()

    @cached_property
    def m_out(self):
        """Spectrum of ``h`` to its part of ``v_T``: ``mask / (1 + nu k²)`` per row."""
        mask = (self.k <= self.kept).astype(float)
        return np.broadcast_to(mask / (1 + self.nu * self.k**2) + 0j, self.m_in.shape).copy()

    @cached_property
    def pointwise(self):
        """Each row's built-in form at its speed (compiled path only)."""
        return [f.at_speed(float(v)) for f, v in zip(self.forms, self.speeds)]

    def linear(self, S):
        """The diagonal linear part ``L`` (batch, n // 2 + 1) for the stabilisations ``S`` per row."""
        k2 = self.k**2
        L = -(self.epsilon * k2**2 + S[:, None] * k2) / (1 + self.nu * k2)
        if np.any(self.drift) or np.any(self.dispersion):
            odd = self.drift[:, None] * self.k - self.dispersion[:, None] * self.k**3
            L = L + 1j * odd / (1 + self.nu * k2)
        return L

    def fields(self, v):
        """``u_xx``, ``u``, ``u_x`` on the grid (m/rad², m, m/rad) from the spectra ``v``."""
        return (np.fft.irfft(-(self.k**2) * v, axis=-1), np.fft.irfft(v, self.n, axis=-1),
                np.fft.irfft(1j * self.k * v, self.n, axis=-1))

    def nonlinear(self, v, S):
        """``N(v)`` evaluated in Python (the path of a callable ``h``; it takes ``forms[0]``)."""
        s, u, ux = self.fields(v)
        g = self.forms[0](s, u, ux, self.speeds[:, None]) - S[:, None] * s
        return np.fft.rfft(g, axis=-1) * self.m_out

    def compiled_terms(self, S):
        """``g = h - S u_xx`` per row for the compiled loop: ``(poly, tab_lo, tab_ds, tab_val, tab_der)``."""
        tables = self.pointwise
        width = max(max(t.poly.size for t in tables), 2)
        poly = np.zeros((len(self.speeds), width))
        for b, t in enumerate(tables):
            poly[b, : t.poly.size] = t.poly
        poly[:, 1] -= S
        n_tab = max(t.table_value.size for t in tables)
        if n_tab and any(t.table_value.size != n_tab for t in tables):
            raise ScenarioError("h tables of one batch must have the same number of points")
        return (poly, np.array([t.table_lo for t in tables]), np.array([t.table_ds for t in tables]),
                np.array([t.table_value for t in tables]).reshape(len(tables), n_tab),
                np.array([t.table_slope for t in tables]).reshape(len(tables), n_tab))

    def _slope(self, b, s, u=0.0, ux=0.0):
        """``∂h/∂u_xx`` of row ``b`` at the curvatures ``s`` (rad² per unit ``T``)."""
        if self.compiled:
            return self.pointwise[b].slope(s)
        return self.forms[b].slope(s, self.speeds[b], u, ux)

    def max_slope(self, v):
        """Largest ``∂h/∂u_xx`` per row over the present curvatures and a band four times as wide."""
        s, u, ux = self.fields(v)
        out = np.empty(len(self.speeds))
        for b in range(len(self.speeds)):
            reach = 4 * max(float(np.max(np.abs(s[b]))), 1e-12)
            grid = np.linspace(-reach, reach, 201)
            out[b] = np.max(np.concatenate([self._slope(b, s[b], u[b], ux[b]), self._slope(b, grid)]))
        return out

    def ill_posed(self, v):
        """Whether ``h`` decreases with ``u_xx`` at ``v`` and neither ``epsilon`` nor ``nu`` regularises it."""
        return self.epsilon == 0 and self.nu == 0 and bool(np.any(self.growth_bound(v) > 0))

    def fingerprint_bytes(self):
        """What a subclass adds to the problem's fingerprint (nothing here)."""
        return b""

    def growth_bound(self, v):
        """Largest linear growth rate per row over the kept orders, slopes frozen at the present curvatures."""
        s, u, ux = self.fields(v)
        low = np.array([np.min(self._slope(b, s[b], u[b], ux[b])) for b in range(len(self.speeds))])
        k = self.k[: self.kept + 1]
        return np.max(growth_rate(-np.minimum(low, 0.0)[:, None], k[None, :], self.epsilon, self.nu), axis=1)
