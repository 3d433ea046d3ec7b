"""Long-term wear of the wheelset on real profiles: the worn lateral profile and the angular pattern.

The wheelset is :class:`railwear.dynamics.TableWheelsetModel` on a contact table of the wheel
profile (S1002) on the rail (UIC60), :func:`railwear.geometry.contact_table`. Each wheel has a
wear surface (:class:`railwear.geometry.wear_surface.WearSurface`) over angle × lateral position
``s`` on the wheel profile (m, the profile coordinate, positive towards the field side). Between
two output times of the dynamics the frictional energy ``E = ∫ P dt`` of a wheel (trapezoidal) is
removed as the volume ``β E`` (energy law, ``railwear.wear.EnergyLaw.beta``, m³/J; another
:class:`~railwear.wear.WearLaw` gives its trapezoidal volume over the interval) under the Hertz
ellipse of the contact table (semi-axes ``a`` along rolling, ``b`` across, interpolated at the
wheelset's shift), centred at the contact position the table gives and swept along the
circumference over the angle the wheel turned in that interval (at the axle's quasi-static spin
``2 V / (r_L + r_R)``). The removed volume equals ``β ∫ P dt`` to round-off.

``contact_model`` (``"hertz"``, ``"multi-hertz"``, ``"semi-hertzian"``, :func:`contact_table`)
chooses the tables. On ``"hertz"`` (one rigid point per wheel) the wear goes under the table's
ellipse at the dynamics' contact position as above. On the other two a wheel has several contacts
sharing its load and the dynamics evaluate each on its own (its creepages, Kalker coefficients and
saturation, ``TableWheelsetModel.point_outputs``); each contact's own frictional power at each
output is shared between the table's two shifts around the wheelset's (linear-interpolation
weights, over the shifts where that contact carries load) and put down at its own
``point_wheel_y`` under its own ellipse (``point_a``, ``point_b``, multi-hertz), so the wear lands
on the contacts, each by its own power, not on the resultant's position between them. A
semi-hertzian table carries each patch's strips (``point_strip_wheel_y``, ``point_strip_width``,
``point_strip_half_length``): there each contact's volume is put down across its strips, each
strip at its own position on the wheel profile (width ``point_strip_width cos(angle)`` there),
along its own length, with its share of the contact's power: under ``creep_law="strip-fastsim"``
the strip's own FASTSIM dissipation (``point_strip_frictional_power`` of ``point_outputs``), under
the cubic law :func:`strip_weights` (the strip's full-slip dissipation with the contact's
creepages and spin, semi-elliptic pressure; without spin its share of the load, which the strips
of a Hertz ellipse turn into the ellipse's footprint).

Feedback ("the contact geometry sees u"): after each long-term step the wheel profile is worn by
the angle-averaged depth over ``s``, averaged over the two wheels (the contact table is built for
a symmetric wheelset; under hunting and random starts the two wheels wear alike), the contact
table is recomputed from the worn profile and the dynamics continue on it. The angle-dependent
part of the depth is an output only: the table model has no angle round the wheel.

:class:`Wheelset` is the body the strategies wear:

- :class:`~railwear.longterm.stepwise.Stepwise` (strategy 3): frozen profile; ``samples`` runs
  from random initial lateral offsets and phases, each ``transient`` seconds thrown away and
  ``seconds`` gathered; the mean depth rate is extrapolated over a long-term step in which the fed
  lateral profile changes by at most ``step_limit`` (m); repeat.
- :class:`~railwear.longterm.direct.Direct` (strategy 1): one run, the wear coefficient
  multiplied by ``acceleration``; the surface takes the wear of every interval, the profile and
  the table are updated every ``update_seconds`` of simulated time.

Normed time: ``life_distance`` metres of running are one unit. The result keeps the long-term
contract (``u`` = minus the removed depth over (time, wheel, angle, lateral), ``distance`` in km)
and adds ``worn_depth(time, wheel, lateral)`` (m, angle-averaged), ``surface_depth(wheel, angle,
lateral)`` at the end, the removed and the law's volume, the contact positions and the largest
lateral displacement seen per step, the tables' rolling-radius difference per step, the flange
parameters Sh, Sd, qR of each worn wheel (m, :mod:`railwear.geometry.flange`), and the cost
(simulated seconds, right-hand sides, tables); stepwise adds the Monte Carlo standard error of the
final worn depth. Checkpoints and resumes are the driver's, bit for bit.
"""

from dataclasses import astuple, dataclass, field, fields, replace

import numpy as np

from railwear.errors import ScenarioError
from railwear.geometry import contact_table, worn_profile
from railwear.geometry.contact_models import CONTACT_MODELS
from railwear.geometry.flange import flange_parameters
from railwear.geometry.wear_surface import WearSurface, deposit_rectangles, ellipse_footprint
from railwear.longterm.base import Body, time_coordinates
from railwear.wear import ContactSample, WearLaw

WHEELS = ("left", "right")
# The flange parameters (EN 15313) of each wheel's worn profile at every save, in FlangeParameters' order.
FLANGE_VARIABLES = (("flange_height", "flange height Sh"), ("flange_thickness", "flange thickness Sd"),
                    ("flange_gradient", "flange gradient qR"))


def _default_shifts():
    return tuple(np.round(np.linspace(-0.010, 0.010, 201), 12))


def _default_edges():
    return tuple(np.round(np.linspace(-0.050, 0.040, 181), 12))


def band_width(depth, lateral, fraction=0.9):
    """Width (m) of the central lateral band holding ``fraction`` of the removed volume: the
    distance between the ``(1 - fraction)/2`` and ``(1 + fraction)/2`` quantiles of ``depth``
    (m, on cell centres ``lateral``, equally spaced), the depth constant on each cell."""
    depth = np.clip(np.asarray(depth, float), 0.0, None)
    lateral = np.asarray(lateral, float)
    ds = lateral[1] - lateral[0]
    edges = np.concatenate([lateral - ds / 2, [lateral[-1] + ds / 2]])
    cumulative = np.concatenate([[0.0], np.cumsum(depth)])
    if not cumulative[-1] > 0:
        return 0.0
    cumulative /= cumulative[-1]
    lo, hi = np.interp([(1 - fraction) / 2, (1 + fraction) / 2], cumulative, edges)
    return float(hi - lo)


def sweep_deposit(surface, volume, angle0, angle1, lateral, a, b, footprint="hertz", n=8):
    """Remove ``volume`` (m³, one per interval) under the patch ellipse (semi-axes ``a``, ``b``, m)
    centred at ``lateral`` (m) and swept from ``angle0`` to ``angle1`` (rad): each piece of the
    footprint (:func:`~railwear.geometry.wear_surface.ellipse_footprint`) is stretched along the
    circumference by the distance turned. Returns the volume added (m³)."""
    volume, angle0, angle1, lateral, a, b = (np.asarray(v, float) for v in
                                             np.broadcast_arrays(volume, angle0, angle1, lateral, a, b))
    x_lo, x_hi, s_lo, s_hi, share = ellipse_footprint(1.0, 1.0, n, footprint)
    col = (slice(None), None)
    return _swept(surface, volume, angle0, angle1, a, x_lo, x_hi, (s_lo * b[col] + lateral[col]).ravel(),
                  (s_hi * b[col] + lateral[col]).ravel(), share)


def _swept(surface, volume, angle0, angle1, reach, x_lo, x_hi, s_lo, s_hi, share):
    """Deposit ``share`` of each interval's ``volume`` on the pieces ``[x_lo, x_hi] reach`` along
    rolling (stretched by the distance turned from ``angle0`` to ``angle1``) by ``[s_lo, s_hi]``
    across (m, one row per interval and piece)."""
    if np.any(volume < 0) or not np.all(np.isfinite(volume)):
        raise ScenarioError("wear volumes must be finite and >= 0")
    start = np.mod(angle0, 2 * np.pi) * surface.radius
    travel = (angle1 - angle0) * surface.radius
    if np.any(travel < 0) or np.any(travel + 2 * reach >= 0.5 * surface.circumference):
        raise ScenarioError("the wheel must turn forwards by less than half a revolution per interval")
    col = (slice(None), None)
    return deposit_rectangles(
        surface.depth, surface.circumference, surface.lateral_edges[0],
        surface.lateral_edges[1] - surface.lateral_edges[0],
        (x_lo * reach[col] + start[col]).ravel(), (x_hi * reach[col] + (start + travel)[col]).ravel(),
        s_lo, s_hi, (share * volume[col]).ravel())


def strip_deposit(surface, volume, angle0, angle1, lateral, width, half_length, footprint="hertz", n=8):
    """Remove ``volume`` (m³, one per strip and interval) under a strip of a patch: ``width`` (m)
    across centred at ``lateral`` (m, on the wheel profile), ``2 half_length`` (m) along rolling,
    swept from ``angle0`` to ``angle1`` (rad). The strip is cut into ``n`` equal pieces along its
    length, weighted by the semi-elliptic pressure ``sqrt(1 - x²/L²)`` at their centres times their
    length (``footprint`` "hertz": the strips of an ellipse then give ``ellipse_footprint``'s
    pieces) or by their length ("uniform"); each piece is stretched along the circumference by the
    distance turned. Returns the volume added (m³)."""
    volume, angle0, angle1, lateral, width, half = (np.asarray(v, float) for v in np.broadcast_arrays(
        volume, angle0, angle1, lateral, width, half_length))
    t = np.linspace(-1.0, 1.0, n + 1)
    lo, hi = t[:-1], t[1:]
    weight = (hi - lo) * (np.sqrt(1.0 - (0.5 * (lo + hi)) ** 2) if footprint == "hertz" else 1.0)
    return _swept(surface, volume, angle0, angle1, half, lo, hi, np.repeat(lateral - 0.5 * width, n),
                  np.repeat(lateral + 0.5 * width, n), weight / weight.sum())


_NODES = 5  # quadrature nodes along a strip for the cubic law's strip weights


def strip_weights(half_length, y, xi, eta, phi, footprint="hertz"):
    """The cubic law's share of a contact's frictional power per strip (normalised over the last
    axis): the full-slip dissipation ``mu ∫ p |s| dx`` of the strip with the rigid slip of
    Kalker's kinematics ``s = (xi - phi y, eta + phi x)`` (``y`` the strip's lateral position about
    the contact's centroid in its plane, ``x`` along it), the pressure ``p`` semi-elliptic along
    the strip (``footprint`` "hertz": the patch's normal solution) or uniform. Without spin it is
    the strip's share of the load (of the area, uniform), which is also the share of the linear
    (no-slip) power, ``xi Fx + eta Fy``, strip by strip. Where every slip is zero the load share."""
    L = np.asarray(half_length, float)
    i = np.arange(1, _NODES + 1)
    if footprint == "hertz":  # Gauss-Chebyshev of the second kind: exact for sqrt(1 - t^2) times a quintic
        t = np.cos(i * np.pi / (_NODES + 1))
        q = np.pi / (_NODES + 1) * np.sin(i * np.pi / (_NODES + 1)) ** 2
        scale = L ** 2
    else:
        t, q = np.polynomial.legendre.leggauss(_NODES)
        scale = L
    sx = (np.asarray(xi, float) - np.asarray(phi, float) * np.asarray(y, float))[..., None]
    sy = np.asarray(eta, float)[..., None] + (np.asarray(phi, float) * L)[..., None] * t
    weight = scale * np.sum(q * np.hypot(sx, sy), -1)
    load = np.broadcast_to(scale, weight.shape)
    total = weight.sum(-1, keepdims=True)
    fallback = load.sum(-1, keepdims=True)
    return np.where(total > 0, weight / np.where(total > 0, total, 1.0),
                    np.divide(load, fallback, out=np.zeros_like(load), where=fallback > 0))


@dataclass(frozen=True)
class WheelsetWear:
    """What both wheelset strategies wear.

    ``model`` a :class:`~railwear.dynamics.TableWheelsetModel` (its speed, suspension and friction
    are used; its table, start and phase are replaced), ``wheel`` and ``rail`` the
    :class:`~railwear.geometry.Profile` s, ``law`` the :class:`~railwear.wear.WearLaw`, ``beta`` (m³/J) its volume per frictional
    energy, ``life_distance`` (m) one unit of normed time, ``shifts`` (m) the lateral shifts of the
    contact tables, ``lateral_edges`` (m) the lateral cells of the wear surface on the wheel
    profile, ``n_angle`` its cells round the wheel, ``transient`` (s) run before wear is gathered,
    ``offsets`` (m) the range of the magnitude of the random initial lateral displacement (its
    sign random too), ``output_rate`` (1/s) output times of the dynamics per simulated second.
    """

    model: object
    wheel: object
    rail: object
    law: WearLaw
    life_distance: float
    shifts: tuple = field(default_factory=_default_shifts)
    lateral_edges: tuple = field(default_factory=_default_edges)
    n_angle: int = 64
    transient: float = 3.0
    offsets: tuple = (1e-3, 3e-3)
    output_rate: float = 2000.0
    footprint: str = "hertz"
    contact_model: str = "hertz"

    def __post_init__(self):
        if not isinstance(self.law, WearLaw):
            raise ScenarioError(f"law must be a railwear.wear.WearLaw, not {type(self.law).__name__}")
        for name in ("life_distance", "output_rate"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ScenarioError(f"{name} must be finite and > 0, got {value}")
        if not (np.isfinite(self.transient) and self.transient >= 0):
            raise ScenarioError(f"transient must be finite and >= 0 (s), got {self.transient}")
        lo, hi = (float(v) for v in self.offsets)
        if not 0 <= lo <= hi:
            raise ScenarioError(f"offsets must be (low, high) with 0 <= low <= high (m), got {self.offsets}")
        if self.footprint not in ("hertz", "uniform"):
            raise ScenarioError(f"footprint must be 'hertz' or 'uniform', not {self.footprint!r}")
        if self.contact_model not in CONTACT_MODELS:
            raise ScenarioError(f"contact_model must be one of {', '.join(CONTACT_MODELS)}, not {self.contact_model!r}")
        object.__setattr__(self, "shifts", tuple(float(v) for v in self.shifts))
        object.__setattr__(self, "lateral_edges", tuple(float(v) for v in self.lateral_edges))
        self.new_surface()  # validates the grid

    @property
    def lateral(self):
        """Lateral cell centres (m)."""
        edges = np.asarray(self.lateral_edges)
        return 0.5 * (edges[1:] + edges[:-1])

    def new_surface(self):
        """An unworn :class:`WearSurface` of one wheel at the model's nominal radius."""
        return WearSurface(self.radius, self.n_angle, self.lateral_edges)

    @property
    def radius(self):
        """Nominal rolling radius (m) the surface is laid on: the model's contact table's."""
        return float(self.model.table.attrs["nominal_rolling_radius"])

    def profile(self, depth):
        """The wheel profile worn by ``depth`` (m, removed, on the lateral cell centres; zero
        outside the grid)."""
        removed = np.interp(self.wheel.y, self.lateral, np.asarray(depth, float), left=0.0, right=0.0)
        return worn_profile(self.wheel, -removed)

    def table(self, depth):
        """Contact table of the wheel worn by the lateral ``depth`` (m) on the rail, over ``shifts``,
        with the track, load and elastic constants of the model's own (new-profile) table."""
        a = self.model.table.attrs
        return contact_table(self.profile(depth), self.rail, gauge=a["gauge"], cant=a["cant"],
                             back_to_back=a["back_to_back"], axle_load=a["axle_load"],
                             y=np.asarray(self.shifts), rolling_radius=a["nominal_rolling_radius"],
                             taping_line_offset=a["taping_line_offset"], youngs_modulus=a["youngs_modulus"],
                             poisson=a["poisson"], contact_model=self.contact_model)

    def start(self, rng):
        """Random initial lateral displacement (m) and phase (rad)."""
        lo, hi = self.offsets
        offset = rng.uniform(lo, hi) * rng.choice((-1.0, 1.0))
        return float(offset), float(rng.uniform(0.0, 2 * np.pi))

    def run(self, table, seconds, state=None, offset=0.0, cost=None):
        """Run the wheelset on ``table`` for ``seconds`` (s) from ``state`` (or at rest displaced by
        ``offset``, m): ``(dataset, final state)``; the seconds and right-hand sides are added to
        ``cost``."""
        from railwear.dynamics import simulate

        model = replace(self.model, table=table, initial_lateral_displacement=offset, initial_yaw_angle=0.0,
                        initial_lateral_velocity=0.0, initial_yaw_rate=0.0)
        ds = simulate(model, seconds, n_output=max(int(np.ceil(seconds * self.output_rate)), 2) + 1,
                      initial_state=state)
        if model.contacts:  # several contacts per wheel: each one's own power for point_volumes
            ds = ds.merge(model.point_outputs(ds))
        end = np.array([ds[v].values[-1] for v in ("lateral_displacement", "yaw_angle", "lateral_velocity",
                                                    "yaw_rate")])
        if cost is not None:
            cost["seconds"] += seconds
            cost["rhs_evaluations"] += ds.attrs["rhs_evaluations"]
        return ds, end

    @property
    def beta(self):
        """The energy law's volume per frictional energy (m³/J), ``None`` for another law."""
        return self.law.beta

    def contact(self, ds, table, wheel):
        """The :class:`~railwear.wear.ContactSample` of ``wheel`` at the outputs of the run ``ds``:
        sliding speed ``V √(ξ² + η²)``, patch area ``π a b`` of the table at the shift."""
        shift = -ds.lateral_displacement.values
        a, b = (np.interp(shift, table.y.values, table[v].sel(side=wheel).values) for v in ("a", "b"))
        v = self.model.speed
        slip = np.hypot(ds.longitudinal_creepage.sel(wheel=wheel).values, ds.lateral_creepage.sel(wheel=wheel).values)
        force = ds.normal_force.sel(wheel=wheel).values
        return ContactSample(ds.frictional_power.sel(wheel=wheel).values, force, v * slip, np.full(shift.size, v),
                             np.where(force > 0, np.pi * a * b, 0.0))

    def settle(self, table, offset, cost):
        """State (or ``None``) after the transient from rest at ``offset`` (m)."""
        return self.run(table, self.transient, offset=offset, cost=cost)[1] if self.transient > 0 else None

    def deposit(self, surfaces, ds, table, phase, factor=1.0):
        """Wear the two ``surfaces`` (left, right) by ``factor`` times the law's volume over the run
        ``ds`` on ``table`` (energy law: ``β ∫ P dt``; another law: the trapezoidal integral of its
        rate at the outputs, the patch area ``π a b`` from the table), the wheel angle starting at
        ``phase`` (rad) and turning at ``2 V / (r_L + r_R)`` (the axle's quasi-static spin, radii
        from the table). A table of one contact per wheel (``"hertz"``) puts it under the resultant's
        footprint at the contact position of the dynamics; a table of several
        (:meth:`point_volumes`) under each point's own. Returns the volume added (m³), the law's
        volume (m³) and the end angle (rad)."""
        t = ds.time.values
        shift = -0.5 * (ds.lateral_displacement.values[1:] + ds.lateral_displacement.values[:-1])  # table y: right
        at = {(wheel, v): np.interp(shift, table.y.values, table[v].sel(side=wheel).values)
              for wheel in WHEELS for v in ("a", "b", "rolling_radius")}
        turned = 2 * self.model.speed * np.diff(t) / (at["left", "rolling_radius"] + at["right", "rolling_radius"])
        angle = phase + np.concatenate([[0.0], np.cumsum(turned)])
        added = law = 0.0
        for surface, wheel in zip(surfaces, WHEELS):
            if "point_strip_half_length" in table:  # semi-hertzian: each contact's power across its strips
                interval, volume, position, width, half = self.point_volumes(ds, table, wheel, factor, strips=True)
                added += strip_deposit(surface, volume, angle[interval], angle[interval + 1], position, width, half,
                                       self.footprint)
                law += float(volume.sum())
                continue
            if "point_creep_share" in table:
                interval, volume, position, a, b = self.point_volumes(ds, table, wheel, factor)
                added += sweep_deposit(surface, volume, angle[interval], angle[interval + 1], position, a, b,
                                       self.footprint)
                law += float(volume.sum())
                continue
            power = ds.frictional_power.sel(wheel=wheel).values
            if self.beta is not None:
                volume = factor * self.beta * 0.5 * (power[1:] + power[:-1]) * np.diff(t)
            else:
                rate = self.law.volume_rate_of(self.contact(ds, table, wheel))
                volume = factor * 0.5 * (rate[1:] + rate[:-1]) * np.diff(t)
            position = ds.contact_lateral_position.sel(wheel=wheel).values
            a, b = at[wheel, "a"], at[wheel, "b"]
            added += sweep_deposit(surface, volume, angle[:-1], angle[1:], 0.5 * (position[1:] + position[:-1]),
                                   a, b, self.footprint)
            law += float(volume.sum())
        return added, law, float(angle[-1])

    def point_volumes(self, ds, table, wheel, factor=1.0, strips=False):
        """The wear of ``wheel`` over the run ``ds`` on a table of several contacts per wheel, per
        contact point: at every output each contact's own frictional power
        (``point_frictional_power`` of :meth:`run`, the contacts as
        :func:`~railwear.dynamics.table_wheelset.point_tracks` follows them) is shared between the
        table's two shifts around the wheelset's by their linear-interpolation weights, over the
        shifts where that contact carries load (energy law: ``β P_i``; another law: its rate of
        the point's ``P_i``, ``point_normal_force`` and patch ``π point_a point_b``, the wheel's
        sliding speed), and integrated over each output interval (trapezoidal). Returns, one per
        loaded point and interval end, the interval's index, the volume (m³, times ``factor``),
        the point's ``point_wheel_y`` and its ``point_a``, ``point_b`` (m), which :meth:`deposit`
        puts down; their volumes sum to the law's of the summed point powers over the run.

        ``strips=True`` (semi-hertzian tables, which carry each patch's strips): each point's
        volume is shared over the strips of its patch at the table's shift, by each strip's own
        frictional power where the run has it (``point_strip_frictional_power``, strip-wise
        FASTSIM), else by :func:`strip_weights` of the point's creepages; returned per strip:
        interval, volume, the strip's ``point_strip_wheel_y``, its width on the wheel profile
        (``point_strip_width cos(point_contact_angle)``) and ``point_strip_half_length`` (m)."""
        from railwear.dynamics.table_wheelset import point_tracks

        if "point_frictional_power" not in ds:
            raise ScenarioError("the run lacks each contact's frictional power (point_frictional_power): "
                                "run the wheelset through WheelsetWear.run")
        node, weight = _brackets(table.y.values, -ds.lateral_displacement.values)  # (time, 2)
        index = point_tracks(table)[wheel][node]  # (time, 2, contact): the table's point, -1 unloaded
        loaded = index >= 0
        if index.shape[-1] != ds.sizes["point"]:
            raise ScenarioError("the run's contacts are not those of the contact table")
        rows = np.broadcast_to(node[..., None], index.shape)
        y, a, b, force = (np.where(loaded, table[f"point_{v}"].sel(side=wheel).values[rows, np.maximum(index, 0)],
                                   np.nan if v == "wheel_y" else 0.0)
                          for v in ("wheel_y", "a", "b", "normal_force"))
        held = weight[:, :, None] * loaded
        total = held.sum(1, keepdims=True)
        share = np.divide(held, total, out=np.zeros_like(held), where=total > 0)
        power = np.broadcast_to(ds.point_frictional_power.sel(wheel=wheel).values[:, None, :], share.shape)
        if self.beta is not None:
            rate = self.beta * power
        else:
            slip = np.hypot(ds.longitudinal_creepage.sel(wheel=wheel).values,
                            ds.lateral_creepage.sel(wheel=wheel).values)
            v = self.model.speed
            rate = self.law.volume_rate_of(ContactSample(
                power, force, np.broadcast_to(v * slip[:, None, None], power.shape), np.full(power.shape, v),
                np.where(force > 0, np.pi * a * b, 0.0)))
        rate = rate * share
        if strips:
            return self._strip_volumes(ds, table, wheel, factor, node, index, loaded, rows, rate)
        half = factor * 0.5 * np.diff(ds.time.values)[:, None, None]
        volume = np.stack([half * rate[:-1], half * rate[1:]], 1)  # (interval, end, 2, point)
        same = (node[1:, 0] == node[:-1, 0])[:, None, None]  # both ends between the same shifts: one deposit
        volume = np.stack([volume[:, 0] + np.where(same, volume[:, 1], 0.0), np.where(same, 0.0, volume[:, 1])], 1)
        interval = np.broadcast_to(np.arange(half.size)[:, None, None, None], volume.shape)
        y, a, b = (np.stack([v[:-1], v[1:]], 1) for v in (y, a, b))
        keep = volume != 0  # a negative or NaN volume reaches sweep_deposit, which refuses it
        if not np.all(np.isfinite(y[keep])):
            raise ScenarioError(f"the contact table has wear on a point without a position ({wheel} wheel)")
        return interval[keep], volume[keep], y[keep], a[keep], b[keep]


    def _strip_volumes(self, ds, table, wheel, factor, node, index, loaded, rows, rate):
        """:meth:`point_volumes` across the strips (``rate`` its ``(time, node, point)`` volume rates)."""
        side = table.sel(side=wheel)
        at = np.maximum(index, 0)
        half_length, lateral = (np.where(loaded[..., None], side[f"point_strip_{v}"].values[rows, at], 0.0)
                                for v in ("half_length", "wheel_y"))
        angle, centre, width = (np.where(loaded, side[f"point_{v}"].values[rows, at], 0.0)
                                for v in ("contact_angle", "wheel_y", "strip_width"))
        if "point_strip_frictional_power" in ds:  # each strip's own FASTSIM dissipation
            # (time, 1, point, strip); a round-off below zero (1e-5 W beside 30 W seen) counts as none
            power = np.maximum(ds.point_strip_frictional_power.sel(wheel=wheel).values[:, None], 0.0)
            total = power.sum(-1, keepdims=True)
            share = np.divide(power, total, out=np.zeros_like(power), where=total > 0)
            share = np.broadcast_to(share, half_length.shape)
        else:
            sign = 1.0 if wheel == "left" else -1.0
            y = sign * (lateral - centre[..., None]) / np.cos(angle)[..., None]
            creep = [ds[f"point_{v}_creepage"].sel(wheel=wheel).values[:, None, :, None]
                     for v in ("longitudinal", "lateral", "spin")]
            share = strip_weights(half_length, y, *creep, footprint=self.footprint)
        rate = rate[..., None] * share * loaded[..., None]
        half = factor * 0.5 * np.diff(ds.time.values)[:, None, None, None]
        volume = np.stack([half * rate[:-1], half * rate[1:]], 1)  # (interval, end, node, point, strip)
        same = (node[1:, 0] == node[:-1, 0])[:, None, None, None]
        volume = np.stack([volume[:, 0] + np.where(same, volume[:, 1], 0.0), np.where(same, 0.0, volume[:, 1])], 1)
        interval = np.broadcast_to(np.arange(half.shape[0])[:, None, None, None, None], volume.shape)
        lateral, half_length = (np.stack([v[:-1], v[1:]], 1) for v in (lateral, half_length))
        across = (width * np.cos(angle))[..., None]
        across = np.broadcast_to(np.stack([across[:-1], across[1:]], 1), volume.shape)
        keep = volume != 0
        if not np.all(np.isfinite(lateral[keep])):
            raise ScenarioError(f"the contact table has wear on a strip without a position ({wheel} wheel)")
        return interval[keep], volume[keep], lateral[keep], across[keep], half_length[keep]


@dataclass(frozen=True)
class Wheelset(Body, name="wheelset"):
    """The wheelset of ``problem`` as a long-term body. Frozen geometry: ``samples`` runs from
    random starts, each ``seconds`` (s) after the transient; coupled: the profile and the table
    follow the surface every ``update_seconds`` (s) of simulated time. The wear variable ``u`` is
    the removed depth (m) over (wheel, angle, lateral); the depth limit and the step limit look at
    the fed lateral profile (round the wheel and over both wheels)."""

    problem: WheelsetWear
    seconds: float = 2.0
    samples: int = 4
    update_seconds: float = 0.5
    _table: dict = field(default_factory=dict, compare=False, repr=False)

    label = "wheelset"

    def __post_init__(self):
        for name in ("seconds", "update_seconds"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ScenarioError(f"{name} must be finite and > 0 (s), got {value}")
        if int(self.samples) != self.samples or self.samples < 2:
            raise ScenarioError(f"samples must be a whole number >= 2 (for a variance), got {self.samples}")

    @property
    def table(self):
        """The contact table of the current fed profile."""
        return self._table["table"]

    def statistics(self, table, rng, cost=None):
        """Depth rate (m per unit normed time) per draw over (wheel, angle, lateral), the law's
        volume rate (m³ per unit normed time) per draw, the contact range and largest |y| (m)
        seen, and the cost (added to ``cost`` when given)."""
        p = self.problem
        rates, law, seen = [], [], (np.inf, -np.inf, 0.0)
        cost = {"seconds": 0.0, "rhs_evaluations": 0} if cost is None else cost
        for _ in range(self.samples):
            offset, phase = p.start(rng)
            ds, _ = p.run(table, self.seconds, state=p.settle(table, offset, cost), offset=offset, cost=cost)
            surfaces = (p.new_surface(), p.new_surface())
            _, volume, _ = p.deposit(surfaces, ds, table, phase)
            per_life = p.life_distance / (p.model.speed * self.seconds)
            rates.append(np.stack([s.depth for s in surfaces]) * per_life)
            law.append(volume * per_life)
            lo, hi, amplitude = _seen(ds, table)
            seen = (min(seen[0], lo), max(seen[1], hi), max(seen[2], amplitude))
        return np.array(rates), np.array(law), seen, cost

    # the body protocol
    def start(self, u0):
        p = self.problem
        depth = np.zeros((2, p.n_angle, p.lateral.size))
        if u0 is not None:
            u0 = np.asarray(u0, float)
            if u0.shape != p.lateral.shape or not np.all(np.isfinite(u0)):
                raise ScenarioError(f"u0 must be {p.lateral.size} finite lateral depths (m)")
            depth += u0[None, None, :]
        return depth

    @staticmethod
    def fed(depth):
        """Lateral depth (m) the profile is worn by: round the wheel and over both wheels."""
        return depth.mean(1).mean(0)

    def removed(self, u, u_start):
        return self.fed(u) - self.fed(u_start)

    def removal(self, increment):
        return self.fed(increment)

    def apply(self, u, increment):
        return u + increment

    def limited(self, rate, on="u"):
        fed = self.fed(rate)
        return fed if on == "u" else fed - fed.mean()

    def update(self, u, cost):
        self._table["table"] = self.problem.table(self.fed(u))
        if cost is not None:
            cost["tables"] += 1

    def error_shape(self, u):
        return (2, u.shape[2])

    def new_cost(self):
        return {"seconds": 0.0, "rhs_evaluations": 0, "tables": 0}

    def rates(self, u, rng, cost):
        rates, laws, seen, _ = self.statistics(self.table, rng, cost)
        error = rates.mean(2).std(0, ddof=1) / np.sqrt(self.samples)
        return rates.mean(0), error, laws.mean(), seen

    def couple(self, u, rng, acceleration, cost):
        offset, phase = self.problem.start(rng)
        state = self.problem.settle(self.table, offset, cost)
        return {"state": np.zeros(0) if state is None else state, "offset": offset, "phase": phase}

    def segment(self, u, carry, acceleration, remaining, cost):
        p = self.problem
        per_second = acceleration * p.model.speed / p.life_distance  # normed time per simulated second
        last = remaining / per_second <= self.update_seconds
        seconds = remaining / per_second if last else self.update_seconds
        state = carry["state"] if np.size(carry["state"]) else None
        ds, state = p.run(self.table, seconds, state=state, offset=carry["offset"], cost=cost)
        segment = (p.new_surface(), p.new_surface())
        _, volume, phase = p.deposit(segment, ds, self.table, carry["phase"], acceleration)
        carry = {"state": state, "offset": carry["offset"], "phase": phase}
        return np.stack([s.depth for s in segment]), seconds * per_second, last, volume, _seen(ds, self.table), carry

    def record(self, u, seen, law_volume):
        p = self.problem
        seen = (np.nan,) * 3 if seen is None else seen
        cell = p.new_surface().cell_area
        return {"u": -u, "depth": u.mean(1), "volume": sum(float(w.sum() * cell) for w in u), "law": law_volume,
                "cmin": seen[0], "cmax": seen[1], "amplitude": seen[2],
                "rrd": self.table.rolling_radius_difference.values.copy()}

    def result(self, records, times, cost, error, attrs):
        import xarray as xr

        p = self.problem
        depth = np.array(records["depth"])
        per_time = {
            "worn_depth": (("wheel", "lateral"), depth, "m", "depth removed, mean round the wheel"),
            "removed_volume": ((), records["volume"], "m3", "volume removed from both wheels"),
            "law_volume": ((), records["law"], "m3", "volume of the wear law over the run"),
            "contact_min": ((), records["cmin"], "m", "smallest contact lateral position seen in the step"),
            "contact_max": ((), records["cmax"], "m", "largest contact lateral position seen in the step"),
            "lateral_amplitude": ((), records["amplitude"], "m",
                                  "largest lateral displacement after the transient in the step"),
            "rolling_radius_difference": (("shift",), records["rrd"], "m",
                                          "rolling radius difference right - left of the table"),
        }
        data = {k: (("time",) + dims, np.array(v), {"units": unit, "long_name": name})
                for k, (dims, v, unit, name) in per_time.items()}
        data.update({
            "u": (("time", "wheel", "angle", "lateral"), np.array(records["u"]),
                  {"units": "m", "long_name": "radius deviation (minus the depth removed)"}),
            "surface_depth": (("wheel", "angle", "lateral"), -np.array(records["u"][-1]),
                              {"units": "m", "long_name": "depth removed at the end over angle and lateral position"}),
        })
        flange = np.array([[astuple(flange_parameters(p.profile(d))) for d in at] for at in depth])
        for k, (name, long_name) in enumerate(FLANGE_VARIABLES):
            data[name] = (("time", "wheel"), flange[..., k], {"units": "m", "long_name": long_name})
        if error is not None:
            data["worn_depth_final_standard_error"] = (
                ("wheel", "lateral"), np.asarray(error[-1]),
                {"units": "m", "long_name": "Monte Carlo standard error of the final worn depth"})
        coords = time_coordinates(times, p.life_distance, p.model.speed)
        coords.update({
            "wheel": ("wheel", list(WHEELS), {"long_name": "wheel of the wheelset"}),
            "lateral": ("lateral", p.lateral, {"units": "m", "long_name": "lateral position on the wheel profile"}),
            "angle": ("angle", p.new_surface().angle, {"units": "rad", "long_name": "angle round the wheel"}),
            "shift": ("shift", np.asarray(p.shifts), {"units": "m", "long_name": "lateral shift of the wheelset"}),
        })
        attrs = dict(attrs, wear_law=p.law.name, life_distance=p.life_distance, samples=self.samples,
                     seconds_per_sample=self.seconds, update_seconds=self.update_seconds)
        return xr.Dataset(data, coords=coords, attrs=attrs)

    def fingerprint_parts(self):
        p = self.problem
        model = {f.name: getattr(p.model, f.name) for f in fields(p.model) if f.name != "table"}
        return (self.seconds, self.samples, self.update_seconds, repr(model), p.wheel.y, p.wheel.z, p.rail.y,
                p.rail.z, (p.wheel.cant, p.rail.cant), repr(p.law), p.life_distance, np.asarray(p.shifts),
                np.asarray(p.lateral_edges), p.n_angle, p.transient, p.offsets, p.output_rate, p.footprint, p.radius) + (
            () if p.contact_model == "hertz" else (p.contact_model,)) + (  # hertz checkpoints of before stay valid
            ("strips",) if p.contact_model == "semi-hertzian" else ())  # semi-hertzian wear goes across the strips


def _brackets(y, shift):
    """The table nodes around each ``shift`` (m, clipped to the table, as ``np.interp``) and their
    linear-interpolation weights: indices and weights of shape ``shift.shape + (2,)``."""
    if y.size == 1:
        return np.zeros(shift.shape + (2,), int), np.stack([np.ones_like(shift), np.zeros_like(shift)], -1)
    x = np.clip(shift, y[0], y[-1])
    lo = np.clip(np.searchsorted(y, x, side="right") - 1, 0, y.size - 2)
    w = (x - y[lo]) / (y[lo + 1] - y[lo])
    return np.stack([lo, lo + 1], -1), np.stack([1 - w, w], -1)


def _seen(ds, table=None):
    """Smallest and largest contact lateral position and largest |y| (m) of a run: of the dynamics'
    contact, or on a table of several contacts per wheel, of every loaded point at the table's
    shifts around the run's."""
    amplitude = float(np.abs(ds.lateral_displacement.values).max())
    if table is None or "point_creep_share" not in table:
        position = ds.contact_lateral_position.values
        return float(position.min()), float(position.max()), amplitude
    node, weight = _brackets(table.y.values, -ds.lateral_displacement.values)
    used = np.unique(node[weight > 0])
    share, y = (table[v].values[used] for v in ("point_creep_share", "point_wheel_y"))
    position = y[share > 0]
    return float(position.min()), float(position.max()), amplitude
