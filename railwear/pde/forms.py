"""Wear-rate forms ``h(u_xx; u, u_x, v)`` of the evolution equation (paper eq. 4), and their registry.

``h`` returns the rate of change of the radius deviation in metres per unit of normed life time
(negative where material is removed). The curvature ``s = u_xx`` is in metres per rad², the speed
in m/s. Built-in forms depend on ``s`` and the speed only; each reduces, for one speed, to a
:class:`Pointwise` function that the compiled solver evaluates. Any vectorised callable
``h(s, u, ux, speed)`` may be used instead (see :func:`as_wear_rate`).

A new built-in form is one :class:`BuiltinRate` subclass with a ``name`` and ``at_speed``,
decorated with :func:`register_rate`; :func:`wear_rate` and :func:`as_wear_rate` then select it
by that name (``"cubic"``, ``"table"``, ``"disk_contact"``, ...).
"""

from abc import ABC, abstractmethod
from dataclasses import MISSING, dataclass, field, fields, is_dataclass
from functools import cached_property

import numpy as np

from railwear.errors import ScenarioError
from railwear.pde.etdrk4 import pointwise

TABLE_POINTS = 2049  # resolution of the Hermite tables the compiled solver evaluates


@dataclass(frozen=True)
class Pointwise:
    """``g(s) = sum_j poly[j] s^j + T(s)`` with ``T`` cubic Hermite on a uniform grid.

    ``table_lo`` (m/rad²) and ``table_ds`` give the grid; ``table_value`` and ``table_slope`` the
    values and derivatives on it (empty arrays for no table).
    """

    poly: np.ndarray
    table_lo: float = 0.0
    table_ds: float = 1.0
    table_value: np.ndarray = field(default_factory=lambda: np.zeros(0))
    table_slope: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __call__(self, s):
        s = np.asarray(s, dtype=float)
        flat = np.ascontiguousarray(s.reshape(1, -1))
        out = pointwise(
            flat, self.poly.reshape(1, -1), np.array([self.table_lo]), np.array([self.table_ds]),
            self.table_value.reshape(1, -1), self.table_slope.reshape(1, -1),
        )
        return out.reshape(s.shape)

    def slope(self, s):
        """``dg/ds``; the Hermite table's slope is taken from the interpolant itself."""
        s = np.asarray(s, dtype=float)
        dp = np.polynomial.polynomial.polyder(self.poly) if self.poly.size > 1 else np.zeros(1)
        out = np.polynomial.polynomial.polyval(s, dp)
        if self.table_value.size:
            h = 1e-6 * self.table_ds
            table_only = Pointwise(np.zeros(1), self.table_lo, self.table_ds, self.table_value,
                                   self.table_slope)
            out = out + (table_only(s + h) - table_only(s - h)) / (2 * h)
        return out

    @classmethod
    def from_samples(cls, s_lo, s_hi, value, slope):
        """Table from samples of ``g`` and ``dg/ds`` on ``TABLE_POINTS`` points in ``[s_lo, s_hi]``."""
        s = np.linspace(s_lo, s_hi, TABLE_POINTS)
        return cls(np.zeros(1), float(s_lo), float(s[1] - s[0]), np.asarray(value(s), float),
                   np.asarray(slope(s), float))


class BuiltinRate(ABC):
    """A wear-rate form that depends on the curvature and the speed only."""

    name = "builtin"

    @abstractmethod
    def at_speed(self, speed) -> Pointwise:
        """The form at one speed (m/s) as a compiled point-wise function of the curvature."""

    def __call__(self, s, u=None, ux=None, speed=0.0):
        s, speed = np.broadcast_arrays(np.asarray(s, float), np.asarray(speed, float))
        return self._by_speed(s, speed, lambda g, x: g(x))

    def slope(self, s, speed=0.0):
        """``∂h/∂u_xx`` (rad² per unit normed time)."""
        s, speed = np.broadcast_arrays(np.asarray(s, float), np.asarray(speed, float))
        return self._by_speed(s, speed, lambda g, x: g.slope(x))

    def _by_speed(self, s, speed, f):
        out = np.empty(s.shape)
        for v in np.unique(speed):
            mask = speed == v
            out[mask] = f(self.at_speed(float(v)), s[mask])
        return out


_RATES = {}  # name -> BuiltinRate subclass


def register_rate(cls):
    """Class decorator: make the built-in form ``cls`` selectable by its ``name``."""
    if not (isinstance(cls, type) and issubclass(cls, BuiltinRate)):
        raise TypeError(f"register_rate takes a BuiltinRate subclass, not {cls!r}")
    known = _RATES.setdefault(cls.name, cls)
    if known is not cls:
        raise ValueError(f"the wear-rate name {cls.name!r} is taken by {known.__qualname__}")
    return cls


def rate_names():
    """The names of the registered built-in forms, sorted."""
    return tuple(sorted(_RATES))


def wear_rate(name, **parameters):
    """The registered built-in form ``name`` with its parameters (SI units, see each form)."""
    cls = _RATES.get(name)
    if cls is None:
        known = ", ".join(repr(n) for n in rate_names())
        raise ScenarioError(f"unknown h {name!r}: use one of {known}, a form, or a callable")
    if is_dataclass(cls):
        names = {f.name for f in fields(cls)}
        unknown = sorted(set(parameters) - names)
        missing = [f.name for f in fields(cls) if f.name not in parameters
                   and f.default is MISSING and f.default_factory is MISSING]
        if unknown or missing:
            raise ScenarioError(
                f"h {name!r}: " + "; ".join(
                    ([f"unknown parameters {', '.join(unknown)}"] if unknown else [])
                    + ([f"needs {', '.join(missing)}"] if missing else [])))
    return cls(**parameters)


@register_rate
@dataclass(frozen=True)
class Cubic(BuiltinRate):
    """``h = c0 + c1 s + c3 s³`` (m, rad², 1/m² per unit normed time), the same at every speed."""

    c0: float = 0.0
    c1: float = 0.0
    c3: float = 0.0
    name = "cubic"

    def __post_init__(self):
        for f in ("c0", "c1", "c3"):
            if not np.isfinite(getattr(self, f)):
                raise ScenarioError(f"cubic.{f} must be finite")

    def at_speed(self, speed):
        return Pointwise(np.array([self.c0, self.c1, 0.0, self.c3]))


@register_rate
@dataclass(frozen=True, eq=False)
class Table(BuiltinRate):
    """``h`` tabulated over the curvature (m/rad²) and, optionally, the speed (m/s).

    ``rate`` (m per unit normed time) has shape ``(curvature,)`` or ``(curvature, speed)``. It is
    interpolated by cubic splines (scipy ``RectBivariateSpline``, linear in speed for two speeds)
    and continued linearly with the end slope beyond the curvature range; speeds outside the
    table are an error.
    """

    curvature: np.ndarray
    rate: np.ndarray
    speed: np.ndarray | None = None
    name = "table"

    def __post_init__(self):
        s = np.asarray(self.curvature, float)
        r = np.asarray(self.rate, float)
        object.__setattr__(self, "curvature", s)
        object.__setattr__(self, "rate", r)
        if s.ndim != 1 or s.size < 4:
            raise ScenarioError("table.curvature must list at least 4 values")
        if not np.all(np.isfinite(s)) or np.any(np.diff(s) <= 0):
            raise ScenarioError("table.curvature must be finite and strictly increasing")
        if not np.all(np.isfinite(r)):
            raise ScenarioError("table.rate has non-finite values")
        if self.speed is None:
            if r.shape != s.shape:
                raise ScenarioError("table.rate must have one value per curvature")
        else:
            v = np.atleast_1d(np.asarray(self.speed, float))
            object.__setattr__(self, "speed", v)
            if not np.all(np.isfinite(v)) or np.any(np.diff(v) <= 0):
                raise ScenarioError("table.speed must be finite and strictly increasing")
            if r.shape != (s.size, v.size):
                raise ScenarioError(
                    f"table.rate must have shape (curvature, speed) = ({s.size}, {v.size})")

    @cached_property
    def _spline(self):
        from scipy.interpolate import CubicSpline, RectBivariateSpline

        if self.speed is None or self.speed.size == 1:
            return CubicSpline(self.curvature, self.rate.reshape(self.curvature.size, -1)[:, 0])
        ky = min(3, self.speed.size - 1)
        return RectBivariateSpline(self.curvature, self.speed, self.rate, kx=3, ky=ky, s=0)

    def at_speed(self, speed):
        spline = self._spline
        if self.speed is not None and self.speed.size > 1:
            lo, hi = self.speed[0], self.speed[-1]
            if not lo - 1e-9 * abs(lo) <= speed <= hi + 1e-9 * abs(hi):
                raise ScenarioError(
                    f"speed {speed:g} m/s is outside the h table's speeds [{lo:g}, {hi:g}] m/s")
            value = lambda s: spline(s, speed, grid=False)  # noqa: E731
            slope = lambda s: spline(s, speed, dx=1, grid=False)  # noqa: E731
        else:
            value, slope = spline, lambda s: spline(s, 1)  # noqa: E731
        return Pointwise.from_samples(self.curvature[0], self.curvature[-1], value, slope)


class CallableRate:
    """A user-supplied vectorised ``h(s, u, ux, speed)``; solved on the Python path."""

    name = "callable"

    def __init__(self, func):
        self.func = func

    def __call__(self, s, u, ux, speed):
        return self.func(s, u, ux, speed)

    def slope(self, s, speed=0.0, u=0.0, ux=0.0):
        """``∂h/∂u_xx`` by central differences."""
        s = np.asarray(s, float)
        h = 1e-6 * max(float(np.max(np.abs(s), initial=0.0)), 1e-9)
        return (self.func(s + h, u, ux, speed) - self.func(s - h, u, ux, speed)) / (2 * h)


def as_wear_rate(h):
    """Accept a built-in form, a registered name (the form with its defaults), a vectorised
    callable ``h(s, u, ux, speed)``, or a list of built-in forms (one per batch row)."""
    if isinstance(h, (list, tuple)):
        forms = [as_wear_rate(f) for f in h]
        if not forms or not all(isinstance(f, BuiltinRate) for f in forms):
            raise ScenarioError("a list of h forms must hold built-in forms only")
        return forms
    if isinstance(h, (BuiltinRate, CallableRate)):
        return h
    if isinstance(h, str):
        return wear_rate(h)
    if callable(h):
        return CallableRate(h)
    raise ScenarioError(f"h must be a wear-rate form or a callable, not {type(h).__name__}")
