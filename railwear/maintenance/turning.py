"""Re-profiling as an action and a wheel's life under a policy, on the Fourier technique (layer 4).

Between turnings the radius deviation ``u(x, s)`` (m, about the nominal radius ``R = D/2`` of
the segment) evolves exactly, order by order, over the distance ``s`` run at the speed ``V``:

    û_n(s) = û_n(0) exp(g λ_n s / V),   ū(s) = ū(0) + ṙ s / V

with ``λ_n`` the Fourier technique's rates (1/s) at the diameter ``D`` and ``ṙ`` its mean rate
(m/s, negative: the wheel wears); ``g`` is the growth multiplier (no field growth rate of a
polygon is published, so a plan runs a band of them). The mean diameter is ``D + 2 ū(s)``.

A turning cuts the radius by ``c`` (:class:`CutRule`) from the mean: the diameter falls from
``D_b = D + 2 ū`` to ``D_a = D_b - 2 c``, and the wheel restarts at ``R = D_a / 2`` with the
residual out-of-roundness of :class:`Residual` (plus, if asked, the scenario's ``[initial]``
roughness). The technique is rebuilt at ``D_a``, so the order the wheel selects moves with the
diameter (``n ∝ D`` at a fixed frequency). A wheel is scrapped at its last-turning diameter
``D_s``: when wear takes its mean diameter there, or when a trigger asks for a turning that would
take it below.

Where the scenario simulates the lateral profile (:mod:`railwear.maintenance.lateral`), the flange
parameters are further triggers, and the turning restores the design profile: its depth relative
to the tape circle adds to the polygon's in the cut (:meth:`CutRule.depth`).
"""

from dataclasses import dataclass, replace

import numpy as np

from railwear.errors import NumericalInstabilityError, ScenarioError
from railwear.geometry import bands, roundness
from railwear.geometry.roundness import ROUGHNESS_REFERENCE
from railwear.longterm.fourier import Harmonics
from railwear.units import KM, MM

ROUNDING = 1e-9  # of a lathe step: a depth this close above a whole number of steps is that number
BISECTIONS = 48  # halvings of a scan step to locate a trigger: 500 km / 2^48 is 2 µm
CHUNK = 256  # scan points evolved together


@dataclass(frozen=True, eq=False)
class RateTable(Harmonics):
    """The rates ``g λ_n`` (1/s, complex) of orders ``1 .. len(table)`` and the mean rate
    ``mean_rate`` (m/s) of a Fourier technique at ``speed`` (m/s) on a wheel of ``radius`` (m),
    evaluated once (:meth:`of`) so that evolving the wheel costs no transfer function."""

    table: np.ndarray
    mean_rate: float
    speed: float
    radius: float

    @classmethod
    def of(cls, technique, highest, multiplier=1.0):
        """The table of ``technique`` (a :class:`~railwear.longterm.fourier.Harmonics`) for orders
        1 .. ``highest``, its rates times ``multiplier`` (the mean rate is not scaled)."""
        table = np.asarray(technique.rates(np.arange(1, highest + 1)), complex)
        return cls(table if multiplier == 1.0 else multiplier * table, float(technique.mean_rate),
                   float(technique.speed), float(technique.radius))

    def scaled(self, multiplier):
        """The same wheel with its rates times ``multiplier``."""
        return RateTable(multiplier * self.table, self.mean_rate, self.speed, self.radius)

    def rates(self, orders):
        return self.table[np.asarray(orders, int) - 1]

    def selected_order(self):
        """The fastest-growing order (below the grid's alternating order)."""
        return int(np.argmax(self.table.real[:-1])) + 1


@dataclass(frozen=True, eq=False)
class WheelState:
    """A wheel: ``u`` (m) about the nominal radius ``diameter / 2`` (m) on equal angles,
    ``distance`` (m) run since new, ``since`` (m) since the last turning, ``turnings`` done."""

    u: np.ndarray
    diameter: float
    distance: float = 0.0
    since: float = 0.0
    turnings: int = 0

    def __post_init__(self):
        u = np.array(self.u, float)
        u.flags.writeable = False
        object.__setattr__(self, "u", u)

    @property
    def mean_diameter(self):
        """``D + 2 ū`` (m)."""
        return self.diameter + 2 * float(np.mean(self.u))


@dataclass(frozen=True)
class CutRule:
    """The cut depth on the radius (m): ``c = max(c_min, Δ ⌈(ū - min u + p + m) / Δ⌉)``, the deepest
    point below the mean plus the depth ``p`` that restores the design profile below the tape
    circle (0 without a lateral profile) plus the ``margin`` m, rounded up to the lathe's ``step``
    Δ, at least ``minimum`` c_min."""

    margin: float
    step: float
    minimum: float

    def depth(self, u, profile=0.0):
        steps = np.ceil((float(np.mean(u) - np.min(u)) + profile + self.margin) / self.step - ROUNDING)
        return max(self.minimum, float(steps) * self.step)


@dataclass(frozen=True)
class Residual:
    """The out-of-roundness a turning leaves (m, mean zero), by ``kind``:

    - ``"round"``: none;
    - ``"spectrum"``: ``Σ A_n cos(n x + φ_n)`` over ``orders``, ``amplitudes`` (m), ``phases`` (rad);
    - ``"inherit"``: ``f_n`` times each harmonic of the old polygon, ``fractions`` per order of
      ``orders`` (no orders: the one fraction for every order);
    - ``"band"``: the level ``level`` (dB re 1 µm) in the one-third-octave band of nominal
      ``wavelength`` (m): equal amplitudes ``A`` on the orders whose lines reach the band, their
      shares ``w_n`` of it (EN 15610 Annex C) giving ``Σ w_n A²/2 = (1 µm)² 10^(L/10)``; phases
      drawn from ``seed`` and the turning's number.
    """

    kind: str
    orders: tuple = ()
    amplitudes: tuple = ()
    phases: tuple = ()
    fractions: tuple = ()
    wavelength: float = float("nan")
    level: float = float("nan")
    seed: int = 0

    def check(self, points):
        """Refuse orders the grid of ``points`` angles does not hold (``residual.orders``)."""
        top = points // 2 - 1
        if self.orders and max(self.orders) > top:
            raise ScenarioError(f"residual.orders: order {max(self.orders)} is above the grid's highest order {top} "
                                "(raise solver.points)")

    def band_orders(self, diameter, points):
        """``(orders, shares)`` of the lines of a wheel of ``diameter`` (m) in the band."""
        k = int(bands.band_index(self.wavelength))
        orders = np.arange(1, points // 2)
        share = bands.line_shares(orders, np.pi * diameter, np.array([k]))[:, 0]
        keep = share > 0
        if not keep.any():
            raise ScenarioError(f"residual.wavelength_mm: no order of a {diameter / MM:.1f} mm wheel on {points} points "
                                f"lies in the {self.wavelength / MM:g} mm band")
        return orders[keep], share[keep]

    def shape(self, old, diameter, turning):
        """The residual (m) on the grid of ``old`` (the polygon before the cut, m) for a wheel
        turned to ``diameter`` (m) at its turning number ``turning``."""
        points = old.size
        if self.kind == "round":
            return np.zeros(points)
        if self.kind == "spectrum":
            return roundness.harmonics(points, self.orders, self.amplitudes, self.phases)
        if self.kind == "inherit":
            spectrum = np.fft.rfft(old)
            factor = np.zeros(spectrum.size)
            if self.orders:
                factor[list(self.orders)] = self.fractions
            else:
                factor[1:] = self.fractions[0]
            return np.fft.irfft(spectrum * factor, points)
        orders, share = self.band_orders(diameter, points)
        amplitude = np.sqrt(2 * ROUGHNESS_REFERENCE**2 * 10 ** (self.level / 10) / np.sum(share))
        phases = np.random.default_rng([self.seed, turning]).uniform(0, 2 * np.pi, orders.size)
        return roundness.harmonics(points, orders, np.full(orders.size, amplitude), phases)


@dataclass(frozen=True)
class TurnRecord:
    """One turning: at ``distance`` (m) by ``trigger``, the polygon's ``peak_to_peak`` (m) and
    ``dominant_order`` before the cut, the ``cut`` (m), the mean diameters ``before`` and
    ``after`` (m); ``selected_order`` is the fastest-growing order at the new diameter (filled
    by the life); with a lateral profile the ``flange`` parameters before the cut (Sh, Sd, qR in m;
    empty without, NaN where worn past measuring) and the share of the cut that restores the design
    profile ``profile_cut`` (m)."""

    distance: float
    trigger: str
    peak_to_peak: float
    dominant_order: int
    cut: float
    before: float
    after: float
    selected_order: int = 0
    flange: tuple = ()
    profile_cut: float = 0.0


@dataclass(frozen=True, eq=False)
class Turning:
    """The action: ``cut`` (a :class:`CutRule`), ``residual`` (a :class:`Residual`) and ``base``
    (m on the grid, or None), the roughness of a re-profiled wheel added to the residual."""

    cut: CutRule
    residual: Residual
    base: np.ndarray | None = None

    def apply(self, state, trigger="", lateral=None):
        """``(state after, record)``: ``state`` (a :class:`WheelState`) turned, ``D_a = D_b - 2c``
        with ``D_b`` its mean diameter; the new state is the residual about ``R = D_a / 2``. With
        ``lateral`` (a :class:`~railwear.maintenance.lateral.ProfileWear`, worn for
        ``state.since``) the cut also restores the design profile."""
        u = state.u
        flange, profile = (), 0.0
        if lateral is not None:
            profile = max(lateral.cut(state.since), 0.0)
            try:
                p = lateral.flange(state.since)
                flange = (p.height, p.thickness, p.gradient)
            except ScenarioError:  # worn past measuring: reported as NaN
                flange = (float("nan"),) * 3
        c = self.cut.depth(u, profile)
        before = state.mean_diameter
        after = before - 2 * c
        old = u - np.mean(u)
        new = self.residual.shape(old, after, state.turnings + 1)
        if self.base is not None:
            new = new + (self.base - np.mean(self.base))
        record = TurnRecord(state.distance, trigger, float(np.ptp(u)), int(roundness.polygon_spectrum(u)["dominant_order"]),
                            c, before, after, 0, flange, profile)
        return WheelState(new, after, state.distance, 0.0, state.turnings + 1), record


@dataclass(frozen=True)
class Triggers:
    """When to turn: ``limits`` (:class:`~railwear.forecast.Limit`: peak to peak, level per order,
    band levels), reached when the largest excess over them reaches 0 dB, ``interval`` (m run
    since the last turning, or None), and ``peak_force`` (N, or None): the peak vertical
    wheel–rail force a wheel-impact-load detector would read at any of ``force_speeds`` (m/s;
    empty: the scenario's speed), found by the life's ``force`` search; ``flange``
    (:class:`~railwear.maintenance.lateral.FlangeLimit`), read on the lateral profile."""

    limits: tuple = ()
    interval: float | None = None
    peak_force: float | None = None
    force_speeds: tuple = ()
    flange: tuple = ()

    def excess(self, u, diameter):
        """``(excess, which)`` along the rows of ``u`` (m): the largest level above a limit (dB)
        and the index of that limit."""
        if not self.limits:
            return np.full(u.shape[:-1], -np.inf), np.zeros(u.shape[:-1], int)
        over = np.stack([limit.excess(u, diameter)[0] for limit in self.limits], axis=-1)
        over = np.where(np.isnan(over), -np.inf, over)
        return np.max(over, axis=-1), np.argmax(over, axis=-1)

    def names(self):
        return [limit.name for limit in self.limits] + (
            [f"interval {self.interval / KM:,.0f} km"] if self.interval is not None else [])

    @property
    def force_name(self):
        return f"peak wheel-rail force {self.peak_force / 1e3:g} kN"


WORN = "worn to the last-turning diameter"
BELOW = "the cut would take it below the last-turning diameter"
HORIZON = "the horizon"


@dataclass(frozen=True)
class Segment:
    """A run between turnings: the ``state`` where it ends, why (``reason``: a trigger's name,
    :data:`WORN` or :data:`HORIZON`), and its ``history``: distances (m), peak to peak (m) and
    mean diameters (m) along it."""

    state: WheelState
    reason: str
    history: tuple


@dataclass(frozen=True, eq=False)
class Life:
    """A wheel's life: its ``turnings`` (:class:`TurnRecord`), the ``starts`` after each of them
    (:class:`WheelState`; a life resumed from one is the rest of this one bit for bit), the
    ``end`` state, why it ended (``reason``: :data:`WORN`, :data:`BELOW` or :data:`HORIZON`), the
    order the wheel it started from selects (``selected_order``), the ``history`` (distance m,
    peak to peak m, mean diameter m) and, ended :data:`BELOW`, the trigger that ``asked`` for the
    cut ("" otherwise)."""

    turnings: tuple
    starts: tuple
    end: WheelState
    reason: str
    selected_order: int
    history: tuple
    asked: str = ""

    @property
    def scrapped(self):
        return self.reason != HORIZON


@dataclass(frozen=True, eq=False)
class Policy:
    """A maintenance policy in SI: ``triggers`` (:class:`Triggers`), the ``turning``
    (:class:`Turning`), the ``last_diameter`` D_s (m) at which the wheel is scrapped."""

    name: str
    triggers: Triggers
    turning: Turning
    last_diameter: float
    source: str = ""
    description: str = ""

    def advance(self, state, technique, horizon, resolution, force=None, lateral=None):
        """The :class:`Segment` from ``state`` on ``technique`` (a :class:`RateTable` at
        ``state.diameter``) to the first of: a limit reached (located by bisection between scan
        points ``resolution`` m apart), the interval, the peak force (``force(state, technique,
        within)``: the distance in m at which the grown wheel's peak force passes the trigger,
        ``inf`` if not within ``within`` m), a flange trigger on ``lateral`` (a
        :class:`~railwear.maintenance.lateral.ProfileWear` worn for ``state.since``), the mean
        diameter worn to ``D_s``, the ``horizon`` (m since new). A state that is not finite before any of them raises
        :class:`NumericalInstabilityError`."""
        speed, u0, d = technique.speed, state.u, state.diameter
        ends = {HORIZON: max(horizon - state.distance, 0.0)}
        if self.triggers.interval is not None:
            ends[self.triggers.names()[-1]] = max(self.triggers.interval - state.since, 0.0)
        wear = -technique.mean_rate / speed  # m of radius per m run
        if wear > 0:
            ends[WORN] = max((state.mean_diameter - self.last_diameter) / (2 * wear), 0.0)
        if self.triggers.peak_force is not None:
            if force is None:
                raise ScenarioError(f"policy {self.name}: trigger.peak_force_kN needs the time-domain track (plan)")
            ends[self.triggers.force_name] = float(force(state, technique, min(ends.values())))
        if self.triggers.flange:
            if lateral is None:
                raise ScenarioError(f"policy {self.name}: a flange trigger needs the lateral profile (plan)")
            within = min(ends.values())
            at = lateral.distance(self.triggers.flange, state.since, within)
            if at <= within:
                ends[lateral.which(self.triggers.flange, state.since + at)] = at
        reason = min(ends, key=lambda k: (ends[k], k != WORN))
        end = ends[reason]
        names = self.triggers.names()
        s, hit, which = self._scan(u0, d, speed, technique, end, resolution)
        if hit is not None:
            end, reason = hit, names[which]
        s = np.append(s[s < end], end)
        u = technique.evolve(u0, s / speed)
        history = (state.distance + s, np.ptp(u, axis=1), d + 2 * np.mean(u, axis=1))
        done = WheelState(u[-1], d, state.distance + end, state.since + end, state.turnings)
        return Segment(done, reason, history)

    def _scan(self, u0, diameter, speed, technique, end, resolution):
        """``(s, hit, which)``: the scan distances (m) to the first limit reached within ``end``
        (m), that distance (None if none) and the limit's index."""
        if not self.triggers.limits:
            return np.linspace(0.0, end, max(int(np.ceil(end / resolution)), 1) + 1), None, 0
        steps = max(int(np.ceil(end / resolution)), 1)
        grid = np.linspace(0.0, end, steps + 1)
        for first in range(0, grid.size, CHUNK):
            s = grid[first:first + CHUNK + 1]
            u = technique.evolve(u0, s / speed)
            finite = np.all(np.isfinite(u), axis=1)
            excess, which = self.triggers.excess(np.where(finite[:, None], u, 0.0), diameter)
            reached = np.flatnonzero((excess >= 0) | ~finite)
            if reached.size == 0:
                continue
            k = reached[0]
            if not finite[k]:
                raise NumericalInstabilityError(
                    f"policy {self.name}: the polygon overflowed {s[k] / KM:,.0f} km after the last turning without "
                    f"reaching a trigger", last_good=u[max(k - 1, 0)], last_time=float(s[max(k - 1, 0)] / speed))
            if k == 0 and first == 0:
                return grid[:1], 0.0, int(which[0])
            lo, hi = s[k - 1], s[k]
            for _ in range(BISECTIONS):
                mid = 0.5 * (lo + hi)
                over, _ = self.triggers.excess(technique.evolve(u0, mid / speed), diameter)
                lo, hi = (lo, mid) if over[0] >= 0 else (mid, hi)
            _, which = self.triggers.excess(technique.evolve(u0, hi / speed), diameter)
            return grid[grid < hi], float(hi), int(which[0])
        return grid, None, 0

    def life(self, start, technique_at, horizon, resolution=500 * KM, force=None, lateral=None):
        """The :class:`Life` from ``start`` (a :class:`WheelState`): segments on
        ``technique_at(diameter)`` (a :class:`RateTable`), turning at each trigger (``force``:
        the peak-force search of :meth:`advance`; ``lateral``: the lateral profile of the flange
        triggers, restored by each turning), until the wheel is scrapped or the ``horizon`` (m
        since new) is reached."""
        state, records, starts, history = start, [], [], []
        selected = None
        while True:
            technique = technique_at(state.diameter)
            if selected is None:
                selected = technique.selected_order()
            else:
                records[-1] = replace(records[-1], selected_order=technique.selected_order())
            segment = self.advance(state, technique, horizon, resolution, force, lateral)
            history.append(segment.history)
            reason = asked = segment.reason
            if reason not in (WORN, HORIZON):
                turned, record = self.turning.apply(segment.state, reason, lateral)
                if record.after >= self.last_diameter:
                    records.append(record)
                    starts.append(turned)
                    state = turned
                    continue
                reason = BELOW
            joined = tuple(np.concatenate([h[i] for h in history]) for i in range(3))
            return Life(tuple(records), tuple(starts), segment.state, reason, selected, joined,
                        asked if reason == BELOW else "")


def evolve_batch(spectra, rates, slope, points, s):
    """:meth:`~railwear.longterm.fourier.Harmonics.evolve` of many wheels at once: ``u`` (m) of
    shape ``s.shape + (points,)`` at the distances ``s`` (m, one row per wheel) from the
    ``spectra`` (``rfft`` of each wheel's ``u0``) under ``rates`` (``λ_n / V``, 1/m, orders 1 ..
    ``points / 2``, a row per wheel) and the mean ``slope`` (``ṙ / V``, m per m run)."""
    out = np.empty(s.shape + (spectra.shape[-1],), complex)
    out[..., 0] = spectra[:, None, 0] + points * slope[:, None] * s
    with np.errstate(over="ignore", invalid="ignore"):  # an overflowed polygon has passed every limit
        out[..., 1:] = spectra[:, None, 1:] * np.exp(s[..., None] * rates[:, None, :])
        return np.fft.irfft(out, points, axis=-1)
